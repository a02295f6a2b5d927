"""A thousand sessions, each built, run a little, refused or errored, and
dropped, leave the process's memory flat: nothing is kept per session (the
staging folders are removed too)."""

import glob
import os
import tempfile

import pytest

import ddmr_hil
from ddmr_hil import Session

PAGE = os.sysconf("SC_PAGE_SIZE")


def rss_bytes() -> int:
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * PAGE


def one_round(elf, tmp):
    s = Session(firmware=elf, instruments=False)
    s.run_for(0.002)
    s.serial.write(b"x")
    with pytest.raises(ddmr_hil.Timeout):
        s.run_until_serial("never", timeout_s=0.001)
    with pytest.raises(ddmr_hil.ConfigError):
        s.var("no_such_global")
    with pytest.raises(ddmr_hil.ConfigError):
        Session(firmware=os.path.join(tmp, "missing.elf"))
    with pytest.raises(ddmr_hil.ConfigError):
        Session(firmware=elf, plant={"motor1": {"resistance_ohm": "x"}})


def test_a_thousand_sessions_leave_memory_flat(reference_elf, tmp_path):
    staging = lambda: set(glob.glob(os.path.join(tempfile.gettempdir(), "ddmr-hil-session-*")))  # noqa: E731
    before = staging()
    for _ in range(100):  # warm up: allocators, caches, the module's statics
        one_round(reference_elf, str(tmp_path))
    base = rss_bytes()
    for _ in range(900):
        one_round(reference_elf, str(tmp_path))
    grown = rss_bytes() - base
    assert grown < 8 * 1024 * 1024, f"{grown / 1e6:.1f} MB more after 900 more sessions"
    assert staging() == before  # every session's staging folder is gone
