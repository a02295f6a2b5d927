"""`make lint`'s clang-tidy cache (tools/cached_clang_tidy.py) on a tiny
project made here: its own compile_commands.json, .clang-tidy (bugprone-*),
a clean file including a header and a file with a finding. A stand-in
clang-tidy first on PATH logs each call and runs the real one, so whether
clang-tidy ran is counted, not timed. The cache is in a temporary
XDG_CACHE_HOME."""
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

SCRIPT = Path(__file__).resolve().parents[2] / "tools" / "cached_clang_tidy.py"
REAL_CLANG_TIDY = shutil.which("clang-tidy")
ARGS = ["-p", "build", "--quiet", "--warnings-as-errors=*"]

pytestmark = pytest.mark.skipif(REAL_CLANG_TIDY is None, reason="clang-tidy not installed (make deps)")


@pytest.fixture
def project(tmp_path):
    src = tmp_path / "src"
    (src / "build").mkdir(parents=True)
    (src / ".clang-tidy").write_text("Checks: '-*,bugprone-*'\n")
    (src / "util.hpp").write_text("inline int twice(int n) { return 2 * n; }\n")
    (src / "clean.cpp").write_text('#include "util.hpp"\nint four() { return twice(2); }\n')
    (src / "finding.cpp").write_text(
        "int scaled(int n) { return static_cast<int>(sizeof(sizeof(n))) * n; }\n")
    (src / "build" / "compile_commands.json").write_text(json.dumps([
        {"directory": str(src / "build"),
         "command": f"/usr/bin/c++ -I{src} -std=c++17 -o {name}.o -c {src / (name + '.cpp')}",
         "file": str(src / (name + ".cpp"))}
        for name in ("clean", "finding")]))
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    log = tmp_path / "calls.log"
    fake = bin_dir / "clang-tidy"
    fake.write_text(f'#!/bin/sh\necho "$*" >> "{log}"\nexec "{REAL_CLANG_TIDY}" "$@"\n')
    fake.chmod(0o755)
    env = dict(os.environ, PATH=f"{bin_dir}:{os.environ['PATH']}", XDG_CACHE_HOME=str(tmp_path / "cache"))
    return src, env, log, tmp_path / "cache" / "ddmr-hil" / "clang-tidy"


def lint(project, name):
    src, env, _, _ = project
    return subprocess.run([sys.executable, str(SCRIPT), *ARGS, name], cwd=src, env=env,
                          capture_output=True, text=True)


def runs(project):
    """How many times clang-tidy checked a file (not --version)."""
    log = project[2]
    calls = log.read_text().splitlines() if log.exists() else []
    return len([c for c in calls if c != "--version"])


def entries(project):
    cache = project[3]
    return sorted(p.name for p in cache.iterdir()) if cache.exists() else []


def test_a_clean_file_is_checked_once_then_served_from_the_cache(project):
    first = lint(project, "clean.cpp")
    assert first.returncode == 0, first.stdout + first.stderr
    assert runs(project) == 1
    assert len(entries(project)) == 1
    assert json.loads((project[3] / entries(project)[0]).read_text())["result"] == "clean"
    second = lint(project, "clean.cpp")
    assert second.returncode == 0
    assert second.stdout == ""
    assert runs(project) == 1  # clang-tidy did not run again
    assert len(entries(project)) == 1


def test_changing_an_included_header_invalidates_the_entry(project):
    assert lint(project, "clean.cpp").returncode == 0
    old = entries(project)
    header = project[0] / "util.hpp"
    header.write_text("inline int twice(int n) { return n + n; }\n")
    assert lint(project, "clean.cpp").returncode == 0
    assert runs(project) == 2
    assert len(entries(project)) == 2 and set(old) < set(entries(project))
    header.write_text("inline int twice(int n) { return 2 * n; }\n")  # back: the first entry again
    assert lint(project, "clean.cpp").returncode == 0
    assert runs(project) == 2


def test_changing_the_config_or_the_arguments_invalidates_the_entry(project):
    assert lint(project, "clean.cpp").returncode == 0
    (project[0] / ".clang-tidy").write_text("Checks: '-*,bugprone-*,performance-*'\n")
    assert lint(project, "clean.cpp").returncode == 0
    assert runs(project) == 2
    src, env, _, _ = project
    more = subprocess.run([sys.executable, str(SCRIPT), *ARGS, "--header-filter=.*", "clean.cpp"],
                          cwd=src, env=env, capture_output=True, text=True)
    assert more.returncode == 0, more.stdout + more.stderr
    assert runs(project) == 3
    assert len(entries(project)) == 3


def test_a_file_with_a_finding_fails_every_time_and_is_never_cached(project):
    for attempt in (1, 2, 3):
        done = lint(project, "finding.cpp")
        assert done.returncode != 0
        assert "bugprone-sizeof-expression" in done.stdout
        assert runs(project) == attempt
        assert entries(project) == []


def test_a_file_without_a_compile_command_is_checked_and_not_cached(project):
    (project[0] / "other.cpp").write_text("int one() { return 1; }\n")
    for attempt in (1, 2):
        lint(project, "other.cpp")  # clang-tidy's own verdict (it guesses the flags)
        assert runs(project) == attempt
    assert entries(project) == []


def test_the_same_sources_in_another_folder_share_the_entry(tmp_path):
    """--source-root: a fresh clone elsewhere reuses the entries of the same sources."""
    cache = tmp_path / "cache"
    env = dict(os.environ, XDG_CACHE_HOME=str(cache))
    results = []
    for copy in ("first", "second"):
        root = tmp_path / copy
        (root / "build").mkdir(parents=True)
        (root / ".clang-tidy").write_text("Checks: '-*,bugprone-*'\n")
        (root / "util.hpp").write_text("inline int twice(int n) { return 2 * n; }\n")
        (root / "clean.cpp").write_text('#include "util.hpp"\nint four() { return twice(2); }\n')
        (root / "build" / "compile_commands.json").write_text(json.dumps([
            {"directory": str(root / "build"),
             "command": f"/usr/bin/c++ -I{root} -std=c++17 -o clean.o -c {root / 'clean.cpp'}",
             "file": str(root / "clean.cpp")}]))
        done = subprocess.run([sys.executable, str(SCRIPT), f"--source-root={root}", *ARGS, "clean.cpp"], cwd=root,
                              env=env, capture_output=True, text=True)
        assert done.returncode == 0, done.stdout + done.stderr
        results.append(sorted(p.name for p in (cache / "ddmr-hil" / "clang-tidy").iterdir()))
    assert len(results[0]) == 1
    assert results[1] == results[0]  # the second copy hit the first's entry
    # Without --source-root the folder is part of the key.
    root = tmp_path / "second"
    done = subprocess.run([sys.executable, str(SCRIPT), *ARGS, "clean.cpp"], cwd=root, env=env,
                          capture_output=True, text=True)
    assert done.returncode == 0
    assert len(list((cache / "ddmr-hil" / "clang-tidy").iterdir())) == 2
