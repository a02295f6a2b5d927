"""The pytest suite of the Python API (docs/python.md). CTest runs it with
Debian's /usr/bin/python3 and PYTHONPATH=<build>/python; DDMR_BUILD_DIR names
the build tree (the reference ELF, the ddmr-hil executable, the fixtures)."""

import os
import pathlib

import pytest


@pytest.fixture(scope="session")
def build_dir() -> pathlib.Path:
    d = os.environ.get("DDMR_BUILD_DIR")
    if not d:
        pytest.fail("DDMR_BUILD_DIR is not set: run the suite through ctest (make test)")
    return pathlib.Path(d)


@pytest.fixture(scope="session")
def source_dir() -> pathlib.Path:
    return pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def reference_elf(build_dir) -> pathlib.Path:
    return build_dir / "firmware" / "ddmr_tracking.elf"
