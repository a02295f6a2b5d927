"""What the ddmr-hil plot scripts share: matplotlib set up for deterministic
output (fixed SVG ids, no dates), saving a figure as PNG and SVG, reading the
CSV files, and the plots every report has in common: an X-Y figure, time
series of the plant's columns (truth.csv and sim.csv share them), currents and
battery voltage as PWM-window means, markers for a scenario's steps, and
report.md's sections (a caption under every plot)."""
import csv
import json
import math
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


def save_tight(fig, out_dir, name):
    """Lays the figure out tightly, saves it (save()) and returns name."""
    fig.tight_layout()
    save(fig, out_dir, name)
    return name


def read_csv(path):
    """{column: [floats]} of a CSV file with a header; {} when it has no rows."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return {k: [float(r[k]) for r in rows] for k in (rows[0].keys() if rows else [])}


def read_csv_if_present(path):
    """read_csv(path), or None when the file does not exist."""
    return read_csv(path) if os.path.exists(path) else None


def write_markdown(out_dir, lines):
    """Writes out_dir/report.md (atomically) and returns its path."""
    path = os.path.join(out_dir, "report.md")
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write("\n".join(lines))
    os.replace(tmp, path)
    return path


# The Uno's 490 Hz phase-correct PWM: 1 / 490.2 s. Currents and the battery
# voltage follow each PWM pulse; sampled at 1 kHz (truth.csv) they alias into
# solid blocks. Plotted instead: the mean over windows of whole PWM periods,
# and the envelope (min and max) of each window. The window is 25 periods
# (51.0 ms): 1 kHz against 490.196 Hz beats at |1000 - 2 x 490.196| = 19.61 Hz,
# one beat every 51.0 ms, so a window's 51 samples fall at evenly spread
# phases of the PWM cycle and their mean is the cycle's mean.
PWM_PERIOD_S = 510.0 * 64 / 16e6  # Timer1/2 phase-correct 8-bit (TOP 255: 510 counts), prescaler 64
WINDOW_PERIODS = 25
WINDOW_S = WINDOW_PERIODS * PWM_PERIOD_S


def window_stats(t, y, window_s):
    """Consecutive windows of window_s [s] from t[0]: (centre time, mean, min,
    max) of the samples in each; a last partial window is dropped."""
    out = []
    if not t:
        return out
    start, i, n = t[0], 0, len(t)
    while True:
        end = start + window_s
        j = i
        while j < n and t[j] < end:
            j += 1
        if j >= n:  # partial window at the end
            break
        if j > i:
            chunk = y[i:j]
            out.append((start + window_s / 2, sum(chunk) / len(chunk), min(chunk), max(chunk)))
        i, start = j, end
    return out


def varies(values):
    """True if the finite values are not all the same: a column a plant
    without motors (the kinematic one) holds constant (currents 0, battery
    6.1 V) has nothing to plot."""
    finite = [v for v in values if math.isfinite(v)]
    return bool(finite) and min(finite) != max(finite)


def distance(xs, ys, gxs, gys):
    """|G - P| per sample: the tracking error [m] of (xs, ys) against the goal (gxs, gys)."""
    return [math.hypot(gx - x, gy - y) for x, y, gx, gy in zip(xs, ys, gxs, gys)]


# --- Markers for a scenario's steps on a time axis -------------------------

def step_marks(steps):
    """The steps of a scenario's result.json grouped by the AVR time they ended
    at: [(t_s, label, passed)], label the steps' YAML lines ("L7" or "L9-12"),
    passed False if any step at that time failed. In time order."""
    groups = {}
    for st in steps:
        g = groups.setdefault(round(st["t_s"], 6), [])
        g.append(st)
    marks = []
    for t in sorted(groups):
        lines = sorted(st["line"] for st in groups[t])
        label = f"L{lines[0]}" if len(lines) == 1 else f"L{lines[0]}-{lines[-1]}"
        marks.append((t, label, all(st["passed"] for st in groups[t])))
    return marks


def draw_marks(ax, marks):
    """A dotted vertical line per step time (red where a step failed), its
    YAML lines written at the top."""
    for t, label, passed in marks:
        colour = "0.55" if passed else "red"
        ax.axvline(t, color=colour, lw=0.8, ls=":")
        ax.text(t, 1.0, label, transform=ax.get_xaxis_transform(), rotation=90, va="top", ha="right",
                fontsize=6, color=colour)


# --- Plots ------------------------------------------------------------------

def xy_axes(folder=None):
    """An X-Y figure; with `folder`, the world of its world.json drawn first
    (the run's tape lines and walls, under the robot's path)."""
    fig, ax = plt.subplots(figsize=(6.5, 7.3))
    if folder is not None:
        draw_world(ax, folder)
    return fig, ax


def draw_world(ax, folder):
    """The tape lines (their centrelines, grey) and walls (brown) of
    folder/world.json, which `run` and `scenario` write when the robot drove
    in a world (docs/world.md); nothing without it."""
    path = os.path.join(folder, "world.json")
    if not os.path.exists(path):
        return
    with open(path) as f:
        world = json.load(f)
    for i, line in enumerate(world.get("lines", [])):
        xs = [p[0] for p in line["points_m"]]
        ys = [p[1] for p in line["points_m"]]
        ax.plot(xs, ys, color="0.55", lw=5, alpha=0.5, solid_capstyle="round", zorder=0,
                label=f"tape line ({line['width_m'] * 1000:.0f} mm)" if i == 0 else None)
    for i, wall in enumerate(world.get("walls", [])):
        (x0, y0), (x1, y1) = wall["from_m"], wall["to_m"]
        ax.plot([x0, x1], [y0, y1], color="saddlebrown", lw=3, zorder=0, label="wall" if i == 0 else None)


def finish_xy(fig, ax, title, out_dir, name="xy"):
    """Equal aspect, axes labelled, legend below; saved as out_dir/name.*."""
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(title)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.09), ncol=3, fontsize=8)
    return save_tight(fig, out_dir, name)


def goal_circle(ax, radius, period):
    a = [2 * math.pi * k / 360 for k in range(361)]
    ax.plot([radius * math.cos(x) for x in a], [radius * math.sin(x) for x in a], "k--", lw=1,
            label=f"goal circle ({radius} m, {period:g} s)")


def finish_time_plot(fig, ax, xlabel, ylabel, out_dir, name, marks=(), legend_fontsize=8):
    """The steps marked, axes labelled, grid, legend; saved as out_dir/name.*."""
    draw_marks(ax, marks)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=legend_fontsize)
    return save_tight(fig, out_dir, name)


def time_series(out_dir, name, t, curves, xlabel, ylabel, marks=()):
    """curves: [(values, label)] against t; returns name."""
    fig, ax = plt.subplots(figsize=(8, 3.5))
    for values, label in curves:
        ax.plot(t, values, lw=1, label=label)
    return finish_time_plot(fig, ax, xlabel, ylabel, out_dir, name, marks)


def pwm_means(out_dir, name, t, curves, xlabel, ylabel, marks=()):
    """curves: [(values, label)], each as its mean per window of WINDOW_PERIODS
    PWM periods, with the window's range shaded; returns name."""
    fig, ax = plt.subplots(figsize=(8, 3.5))
    for n, (values, label) in enumerate(curves):
        st = window_stats(t, values, WINDOW_S)
        tc = [w[0] for w in st]
        colour = f"C{n}"
        ax.fill_between(tc, [w[2] for w in st], [w[3] for w in st], color=colour, alpha=0.15, lw=0,
                        label=f"{label}: min-max per window")
        ax.plot(tc, [w[1] for w in st], color=colour, lw=1.6, ls="-" if n == 0 else "--",
                label=f"{label}: mean over {WINDOW_PERIODS} PWM periods ({WINDOW_S * 1e3:.1f} ms)")
    return finish_time_plot(fig, ax, xlabel, ylabel, out_dir, name, marks, legend_fontsize=7)


# The plant's columns (truth.csv, sim.csv): (plot, how it is drawn, columns, labels, y label).
PLANT_PLOTS = (
    ("wheel_speeds", time_series, ("wheel1_rad_s", "wheel2_rad_s"), ("wheel 1 (right)", "wheel 2 (left)"),
     "wheel speed [rad/s]"),
    ("drive", time_series, ("duty1", "duty2", "dir1", "dir2"),
     ("duty 1 (right)", "duty 2 (left)", "direction 1 (right)", "direction 2 (left)"),
     "duty [0-1], direction [1 = forward]"),
    ("currents", pwm_means, ("ia1_A", "ia2_A"), ("motor 1 (right)", "motor 2 (left)"), "armature current [A]"),
    ("battery", pwm_means, ("vbatt_V",), ("battery terminal voltage",), "voltage [V]"),
)


def plant_plots(out_dir, table, rows, t, xlabel, source, constant_reason, marks=()):
    """The wheel speeds, drive, currents and battery plots of a truth.csv or
    sim.csv table (its rows `rows`, at times t). A plot whose columns are
    missing or constant (constant_reason says why they may be) is left out.
    Returns (plotted names, [what was not available and why])."""
    plotted, missing = [], []
    for name, draw, keys, labels, ylabel in PLANT_PLOTS:
        if not all(k in table for k in keys):
            missing.append(f"{TITLES[name]}: {source} has no {', '.join(k for k in keys if k not in table)}")
            continue
        columns = [[table[k][i] for i in rows] for k in keys]
        if not any(varies(c) for c in columns):
            verb = "never changes" if len(keys) == 1 else "never change"
            missing.append(f"{TITLES[name]}: {', '.join(keys)} in {source} {verb} ({constant_reason})")
            continue
        plotted.append(draw(out_dir, name, t, list(zip(columns, labels)), xlabel, ylabel, marks))
    return plotted, missing


TITLES = {"xy": "X-Y trajectories", "tracking_error": "Tracking error", "wheel_speeds": "Wheel speeds",
          "drive": "Drive (duty and direction)", "currents": "Motor currents", "battery": "Battery voltage"}

CAPTIONS = {
    "wheel_speeds": "The wheels' speeds from the plant: the outer (right) wheel turns faster on the circle.",
    "drive": "What the motor driver is told, per coupling step: duty (mean enable level) and direction "
             "(on the reference robot pins 10 and 11, 12 and 13; a board file says which).",
    "currents": f"The motor currents, averaged over {WINDOW_PERIODS} PWM periods "
                f"({WINDOW_S * 1e3:.1f} ms), with their range in each window shaded: the "
                "current rises and falls with every 490 Hz pulse, so 1 kHz samples of it alias into blocks. "
                "Look at the means for the load, at the band for the ripple.",
    "battery": "The battery's terminal voltage, averaged the same way: it dips with each pulse's current "
               "(internal resistance) and sags slowly with the charge drawn.",
}


def plot_sections(plots, captions, titles=TITLES):
    """report.md's sections: per plot a heading, the PNG and its caption in italics."""
    lines = []
    for p in plots:
        lines += [f"## {titles[p]}", "", f"![{titles[p]}]({p}.png)", "", f"*{captions[p]}*", ""]
    return lines


def not_available_section(missing):
    """report.md's list of what the folder could not plot (nothing if empty)."""
    if not missing:
        return []
    return ["## Not available", ""] + [f"- {m}" for m in missing] + [""]


def isr_section(out_dir):
    """isr.md (ISR timing and races) included, when the folder has one."""
    path = os.path.join(out_dir, "isr.md")
    if not os.path.exists(path):
        return []
    with open(path) as f:
        return ["## ISR timing", "", f.read(), ""]
