"""What the ddmr-hil plot scripts share: matplotlib set up for deterministic
output (fixed SVG ids, no dates), and saving a figure as PNG and SVG."""
import os
import sys

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:  # pragma: no cover - depends on the machine
    sys.stderr.write(f"{os.path.basename(sys.argv[0])}: error: matplotlib is missing: apt-get install "
                     "python3-matplotlib and run with /usr/bin/python3\n")
    sys.exit(2)

matplotlib.rcParams["svg.hashsalt"] = "ddmr-hil"
matplotlib.rcParams["figure.dpi"] = 100


def save(fig, out_dir, name):
    """Writes out_dir/name.png and .svg, then closes the figure."""
    fig.savefig(os.path.join(out_dir, name + ".png"), metadata={"Software": None})
    fig.savefig(os.path.join(out_dir, name + ".svg"), metadata={"Date": None, "Creator": None})
    plt.close(fig)
