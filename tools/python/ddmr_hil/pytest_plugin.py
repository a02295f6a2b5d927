"""The pytest plugin of ddmr_hil (docs/python.md, "pytest").

Loaded by pytest itself where the package is installed with its entry
point (cmake --install), or from a conftest.py:

    pytest_plugins = ["ddmr_hil.pytest_plugin"]

It gives a `hil` fixture, a fresh ddmr_hil.Session per test, configured by

    --hil-firmware ELF   --hil-board FILE   --hil-plant FILE   --hil-world FILE
    --hil-contract FILE  --hil-seed N

and per test by a marker, whose keywords are Session's and win over the
options:

    @pytest.mark.hil(plant={"motor1": {"resistance_ohm": 6.0}}, seed=3)
    def test_slow_motor(hil):
        hil.run_for(5.1); hil.serial.write(b"1"); ...

When a test that used `hil` fails, its artifacts (the files `ddmr-hil run`
writes) are saved under pytest's tmp path, the failure report names the
folder, and --junitxml records it as the test's property `hil_artifacts`.
Each test has its own Session, so pytest-xdist (`-n auto`) runs them in
parallel with the same results.
"""

from __future__ import annotations

import pytest

from . import Session

_OPTIONS = {
    "firmware": "the firmware ELF of the `hil` fixture's sessions",
    "sketch": "instead of --hil-firmware: an Arduino sketch (x/x.ino or its folder), built for the board (cached)",
    "board": "board file (docs/boards.md)",
    "plant": "plant file (docs/plant.md)",
    "world": "world file (docs/world.md)",
    "contract": "sketch contract (docs/contracts.md)",
    "seed": "the encoders' noise seed",
}

def pytest_addoption(parser):
    group = parser.getgroup("ddmr-hil", "ddmr-hil hardware-in-the-loop sessions")
    for name, help_text in _OPTIONS.items():
        group.addoption(f"--hil-{name}", dest=f"hil_{name}", default=None,
                        type=int if name == "seed" else str, help=help_text)


def pytest_configure(config):
    config.addinivalue_line("markers", "hil(**kwargs): ddmr_hil.Session keywords for this test's `hil` fixture")


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    outcome = yield
    report = outcome.get_result()
    session = getattr(item, "_ddmr_hil_session", None)
    if session is None or not report.failed or report.when == "teardown":
        return
    name = "hil-" + "".join(ch if ch.isalnum() or ch in "-_." else "_" for ch in item.name)[:60]
    try:
        folder = item.config._tmp_path_factory.mktemp(name, numbered=True)
        reason = session.save_artifacts(folder)
    except Exception as e:  # the report must not fail: say why there is nothing
        report.sections.append(("ddmr-hil artifacts", f"not saved: {e}"))
        return
    report.sections.append(("ddmr-hil artifacts", f"{folder} (exit reason: {reason})"))
    item.user_properties.append(("hil_artifacts", str(folder)))


def _session_kwargs(request) -> dict:
    opt = request.config.getoption
    kw = {
        "firmware": opt("hil_firmware"),
        "sketch": opt("hil_sketch"),
        "board": opt("hil_board"),
        "plant": opt("hil_plant"),
        "world": opt("hil_world"),
        "contract": opt("hil_contract"),
        "seed": opt("hil_seed"),
    }
    for marker in reversed(list(request.node.iter_markers("hil"))):  # the closest marker wins
        if marker.args:
            raise pytest.UsageError("@pytest.mark.hil takes keywords only (Session's: firmware=, plant=, ...)")
        kw.update(marker.kwargs)
    if not kw.get("firmware") and not kw.get("sketch"):
        raise pytest.UsageError("the hil fixture needs a firmware: --hil-firmware ELF, --hil-sketch INO or "
                                "@pytest.mark.hil(firmware=...)")
    return {k: v for k, v in kw.items() if v is not None}


@pytest.fixture
def hil(request):
    """A fresh ddmr_hil.Session for the test (--hil-* options, @pytest.mark.hil)."""
    session = Session(**_session_kwargs(request))
    request.node._ddmr_hil_session = session
    yield session
    request.node._ddmr_hil_session = None
