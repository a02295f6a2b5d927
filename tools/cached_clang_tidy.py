#!/usr/bin/python3
"""clang-tidy on one source file, skipped when the same input already passed.

    cached_clang_tidy.py CLANG_TIDY_ARGS... FILE

runs `clang-tidy CLANG_TIDY_ARGS... FILE` (the clang-tidy first on PATH) as
`make lint` does, e.g. `-p build --quiet --warnings-as-errors='*' plant/x.cpp`,
unless a cache entry says that the same input passed before. The key is the
sha256 of everything clang-tidy's result depends on:
  - FILE's preprocessed text: each of its compile commands in
    BUILD/compile_commands.json (BUILD from -p) run with -E instead of -c/-o,
    the same compiler and flags, line markers kept; so a change to FILE, to any
    header it includes (the project's or the system's), to a macro or to the
    file's path changes the key;
  - the compile commands themselves (flags that do not show in -E's output,
    e.g. warnings, still change what clang-tidy reports);
  - every .clang-tidy from FILE's folder up to / (clang-tidy uses the nearest,
    and its parents with InheritParentConfig), path and contents;
  - `clang-tidy --version`, the path, size and mtime of the clang-tidy binary,
    and the GCC installations clang may take its C++ library from
    (/usr/lib/gcc/*/*, /usr/include/c++/*);
  - the exact clang-tidy arguments.
An entry is written only when clang-tidy exits 0 and prints no warning or
error: a file with findings is checked again on every run and prints them.
Entries are files named by key under ${XDG_CACHE_HOME:-$HOME/.cache}/ddmr-hil/
clang-tidy/, written to a temporary file and renamed (atomic: parallel runs
and an interrupted run never leave a partial entry). A file whose key cannot
be computed (no compile command, the preprocessor fails) is checked by
clang-tidy as usual and not cached. The output and exit status are
clang-tidy's; a cache hit prints nothing and exits 0.
`make lint LINT_CACHE=0` calls clang-tidy directly instead.

    --source-root=DIR (first argument; not passed to clang-tidy)

makes the key independent of where the checkout is: DIR (the project's root)
is replaced by a placeholder in all of the above, so a fresh clone in another
folder reuses the entries of the same sources checked elsewhere. clang-tidy's
verdict does not depend on that folder, except through a HeaderFilterRegex
that the folder's own path matches: the placeholder keeps whether DIR
matches the project's filter (/plant/, /hil/ or /tools/ in it), so such a
folder gets keys of its own.
"""
import glob
import hashlib
import json
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
import time

FINDING = re.compile(rb": (warning|error): ")


def cache_dir():
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return os.path.join(base, "ddmr-hil", "clang-tidy")


def build_dir(args):
    """The -p folder, as clang-tidy takes it (-p DIR, -p=DIR); None without."""
    for i, arg in enumerate(args):
        if arg == "-p" and i + 1 < len(args):
            return args[i + 1]
        if arg.startswith("-p="):
            return arg[3:]
    return None


def compile_commands(build, source):
    """The entries of BUILD/compile_commands.json for SOURCE, as argument lists
    with their folder; [] when there are none."""
    path = os.path.join(build, "compile_commands.json")
    with open(path, encoding="utf-8") as f:
        entries = json.load(f)
    want = {os.path.abspath(source), os.path.realpath(source)}
    found = []
    for entry in entries:
        directory = entry["directory"]
        file = os.path.normpath(os.path.join(directory, entry["file"]))
        if file in want or os.path.realpath(file) in want:
            argv = entry["arguments"] if "arguments" in entry else shlex.split(entry["command"])
            found.append((directory, argv))
    return found


def preprocess_argv(argv):
    """ARGV with -E instead of -c, no output file and no dependency files."""
    out = [argv[0], "-E"]
    skip = False
    for arg in argv[1:]:
        if skip:
            skip = False
        elif arg in ("-o", "-MF", "-MT", "-MQ"):
            skip = True
        elif arg in ("-c", "-MD", "-MMD") or arg.startswith(("-o", "-MF", "-MT", "-MQ")):
            pass
        else:
            out.append(arg)
    return out


def config_files(source):
    """(path, contents) of every .clang-tidy from SOURCE's folder up to /."""
    found = []
    folder = os.path.dirname(os.path.abspath(source))
    while True:
        path = os.path.join(folder, ".clang-tidy")
        if os.path.isfile(path):
            with open(path, "rb") as f:
                found.append((path, f.read()))
        parent = os.path.dirname(folder)
        if parent == folder:
            return found
        folder = parent


def tool_identity(clang_tidy):
    """What identifies the clang-tidy that runs and the C++ library it sees."""
    version = subprocess.run([clang_tidy, "--version"], capture_output=True, check=True).stdout
    real = os.path.realpath(clang_tidy)
    st = os.stat(real)
    toolchains = sorted(glob.glob("/usr/lib/gcc/*/*") + glob.glob("/usr/include/c++/*"))
    return [version, f"{real} {st.st_size} {st.st_mtime_ns}".encode(), "\n".join(toolchains).encode()]


def rooted(data, root):
    """`data` (bytes) with the checkout's folder `root` replaced by a placeholder."""
    if not root:
        return data
    marker = b"<root:" + (b"filtered" if re.search(r"/(plant|hil|tools)/", root + "/") else b"plain") + b">"
    return data.replace(root.encode(), marker)


def cache_key(clang_tidy, args, source, root=None):
    """The key, or None when it cannot be computed (then no caching)."""
    build = build_dir(args)
    if build is None:
        return None
    try:
        commands = compile_commands(build, source)
    except (OSError, ValueError, KeyError):
        return None
    if not commands:
        return None
    parts = [b"ddmr-hil cached_clang_tidy 2"]
    for directory, argv in commands:
        done = subprocess.run(preprocess_argv(argv), cwd=directory, capture_output=True)
        if done.returncode != 0:
            return None
        parts += [rooted(json.dumps([directory, argv]).encode(), root), rooted(done.stdout, root)]
    for path, contents in config_files(source):
        parts += [rooted(path.encode(), root), contents]
    parts += tool_identity(clang_tidy)
    parts.append(json.dumps(args).encode())
    digest = hashlib.sha256()
    for part in parts:  # length-prefixed: no two lists of parts hash alike
        digest.update(len(part).to_bytes(8, "big"))
        digest.update(part)
    return digest.hexdigest()


def record_clean(key, source):
    folder = cache_dir()
    os.makedirs(folder, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=folder, prefix=".tmp-")
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            json.dump({"result": "clean", "file": os.path.abspath(source), "time": time.time()}, f)
        os.replace(tmp, os.path.join(folder, key))
    except BaseException:
        os.unlink(tmp)
        raise


def is_clean(key):
    try:
        with open(os.path.join(cache_dir(), key), encoding="utf-8") as f:
            return json.load(f).get("result") == "clean"
    except (OSError, ValueError, AttributeError):
        return False


def main(argv):
    if len(argv) < 1:
        print("usage: cached_clang_tidy.py CLANG_TIDY_ARGS... FILE", file=sys.stderr)
        return 2
    root = None
    if argv and argv[0].startswith("--source-root="):
        root = os.path.realpath(argv[0].split("=", 1)[1])
        argv = argv[1:]
    if len(argv) < 1:
        print("usage: cached_clang_tidy.py [--source-root=DIR] CLANG_TIDY_ARGS... FILE", file=sys.stderr)
        return 2
    args, source = argv[:-1], argv[-1]
    clang_tidy = shutil.which("clang-tidy")
    if clang_tidy is None:
        print("cached_clang_tidy: clang-tidy not found on PATH", file=sys.stderr)
        return 127
    key = cache_key(clang_tidy, args, source, root)
    if key is not None and is_clean(key):
        return 0
    done = subprocess.run([clang_tidy, *args, source], capture_output=True)
    sys.stdout.buffer.write(done.stdout)
    sys.stdout.flush()
    sys.stderr.buffer.write(done.stderr)
    sys.stderr.flush()
    if key is not None and done.returncode == 0 and not FINDING.search(done.stdout + done.stderr):
        record_clean(key, source)
    return done.returncode if done.returncode >= 0 else 128 - done.returncode  # killed: 128+signal, as sh says


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
