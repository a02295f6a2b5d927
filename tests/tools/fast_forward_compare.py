#!/usr/bin/python3
"""Compares two result folders of the same runs, one with fast-forward and one
with --no-fast-forward (docs/fast-forward.md): every artifact must be byte
for byte the same, apart from what describes the skipping itself (the
"fast_forward" section of result.json / summary.json) and wall-clock times.

    fast_forward_compare.py ON_DIR OFF_DIR
    fast_forward_compare.py --run DDMR_HIL ARG...   (runs `DDMR_HIL run ARG...`
        both ways, with a VCD, in a temporary folder, and compares them)

Exit 0 if they agree; 1 naming the first difference of each file otherwise.
"""
import json
import subprocess
import sys
import tempfile
from pathlib import Path

# Fields that differ between any two runs (wall clock) or that describe the skip.
VOLATILE = {"fast_forward", "wall_seconds", "mcycles_per_s"}


def normalized(path: Path) -> bytes:
    if path.name in ("result.json", "summary.json"):
        data = json.loads(path.read_text())
        if isinstance(data, dict):
            for key in VOLATILE:
                data.pop(key, None)
        return json.dumps(data, indent=2, sort_keys=True).encode()
    return path.read_bytes()


def first_difference(a: bytes, b: bytes) -> str:
    for i, (x, y) in enumerate(zip(a, b)):
        if x != y:
            line = a[:i].count(b"\n") + 1
            return f"first differs at byte {i} (line {line})"
    return f"lengths {len(a)} and {len(b)}"


def compare(on: Path, off: Path) -> list:
    problems = []
    # Suite summaries (times, JUnit) are not compared: each scenario's files are.
    suite = {Path("junit.xml"), Path("results.json")}
    on_files = {p.relative_to(on) for p in on.rglob("*") if p.is_file()} - suite
    off_files = {p.relative_to(off) for p in off.rglob("*") if p.is_file()} - suite
    for rel in sorted(on_files ^ off_files):
        problems.append(f"{rel}: only in {'the fast-forward run' if rel in on_files else 'the --no-fast-forward run'}")
    for rel in sorted(on_files & off_files):
        a, b = normalized(on / rel), normalized(off / rel)
        if a != b:
            problems.append(f"{rel}: differs with fast-forward, {first_difference(a, b)}")
    return problems


def run_both(cli: str, args: list, work: Path) -> tuple:
    dirs = []
    for name, extra in (("on", []), ("off", ["--no-fast-forward"])):
        out = work / name
        out.mkdir()
        cmd = [cli, "run", *args, "-q", "--out", str(out / "run"), "--vcd", str(out / "run.vcd"), *extra]
        done = subprocess.run(cmd, capture_output=True, text=True)
        if done.returncode != 0:
            raise SystemExit(f"fast_forward_compare: {' '.join(cmd)} exited {done.returncode}: {done.stderr.strip()}")
        # summary.json names its VCD's path, which differs by folder only.
        summary = out / "run" / "summary.json"
        data = json.loads(summary.read_text())
        data["vcd"] = "run.vcd"
        summary.write_text(json.dumps(data, indent=2, sort_keys=True))
        dirs.append(out)
    return dirs[0], dirs[1]


def main() -> int:
    if len(sys.argv) >= 3 and sys.argv[1] == "--run":
        with tempfile.TemporaryDirectory() as work:
            on, off = run_both(sys.argv[2], sys.argv[3:], Path(work))
            problems = compare(on, off)
            for p in problems:
                print(p)
            if not problems:
                print(f"run {' '.join(sys.argv[3:])}: identical with and without fast-forward")
            return 1 if problems else 0
    if len(sys.argv) != 3:
        print(__doc__.strip(), file=sys.stderr)
        return 2
    on, off = Path(sys.argv[1]), Path(sys.argv[2])
    for d in (on, off):
        if not d.is_dir():
            print(f"fast_forward_compare: {d} is not a folder", file=sys.stderr)
            return 2
    problems = compare(on, off)
    for p in problems:
        print(p)
    if not problems:
        count = sum(1 for p in on.rglob("*") if p.is_file())
        print(f"{count} files: identical with and without fast-forward")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
