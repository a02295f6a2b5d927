"""What the `make bench` scripts of this folder share: their options, timing a
command from outside (its start-up included) and writing a result file."""

import argparse
import json
import subprocess
import time
from pathlib import Path


def timed(cmd):
    """Wall seconds of one run of `cmd` (a list), its output discarded; raises if it fails."""
    start = time.monotonic()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.monotonic() - start


def write_result(path, result):
    """`result` as indented JSON in the file `path`."""
    Path(path).write_text(json.dumps(result, indent=2) + "\n", encoding="utf-8")


def parse_bench_args(with_source=False):
    """The options every bench script takes: --build, --rounds, --out (and the source tree)."""
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default="build", help="the CMake build folder")
    if with_source:
        ap.add_argument("--source", default=str(Path(__file__).resolve().parents[3]), help="the source tree")
    ap.add_argument("--rounds", type=int, default=5, help="interleaved rounds per comparison")
    ap.add_argument("--out", required=True, help="the JSON file to write")
    return ap.parse_args()
