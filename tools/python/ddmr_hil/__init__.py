"""ddmr-hil from Python: the unmodified AVR firmware in simavr, the robot's
plant around it, driven step by step (docs/python.md).

    from ddmr_hil import Session
    s = Session(firmware="build/firmware/ddmr_tracking.elf")
    s.run_until_serial("0.6m", timeout_s=8)    # AVR time; raises ddmr_hil.Timeout
    s.serial.write(b"1"); s.run_for(12.0)
    print(s.truth.pose(), s.var("Count1", "uint32").value)

The engine is the same Session the command line drives (`ddmr-hil run`):
the same checks, the same one-line errors, the same artifacts.
"""

from __future__ import annotations

import os
from collections import namedtuple

TYPE_CHECKING = False  # typing's own idiom, without importing typing

from ._ddmr_hil import (  # noqa: F401  (re-exported)
    ConfigError,
    DdmrHilError,
    RunEnded,
    Timeout,
    UsageError,
    _Session,
)

__all__ = [
    "Session",
    "Snapshot",
    "Pose",
    "DdmrHilError",
    "ConfigError",
    "Timeout",
    "RunEnded",
    "UsageError",
    "sweep",
    "grid",
    "to_csv",
]

if TYPE_CHECKING:  # annotations only: `typing` costs the import time of a short test
    from typing import Callable, Optional, Union

    PathLike = Union[str, "os.PathLike[str]"]


class Pose(namedtuple("Pose", ["x_m", "y_m", "theta_rad"])):
    """The robot's true pose: x_m, y_m [m] and theta_rad [rad, not wrapped]."""

    __slots__ = ()


class Serial:
    """The host's side of the firmware's serial port (Serial, or the
    board's host port)."""

    def __init__(self, core: _Session):
        self._core = core

    def write(self, data: Union[bytes, str]) -> None:
        """Types `data` into the firmware's RX now (at the line's baud rate)."""
        if isinstance(data, str):
            data = data.encode()
        self._core.serial_write(bytes(data))

    def read(self) -> bytes:
        """The bytes the host received since the last read()."""
        return self._core.serial_read_new()

    @property
    def text(self) -> bytes:
        """Every byte the host has received."""
        return self._core.serial_text()


class Pin:
    """A board pin: `level` is what the chip drives (an output, PWM
    included) or reads (an input's PINx bit)."""

    def __init__(self, core: _Session, name: str):
        self._core = core
        self.name = name
        self.number = core.pin_number(name)

    @property
    def level(self) -> int:
        return 1 if self._core.pin_level(self.number) else 0

    @property
    def duty(self) -> float:
        """The output's mean level over its PWM period (0 or 1 when static)."""
        return self._core.pwm_duty(self.number)

    def drive(self, level: int) -> None:
        """Drives this input pin to `level` (0 or 1) from now on, as a switch
        or a signal generator wired to it would: PINx reads it, and an INTn or
        pin-change interrupt enabled on it fires at this cycle. A pin the
        board wires (a part, a motor driver, an encoder) or the host's serial
        port is refused: set a part's reading with sensor(NAME).set()."""
        if level not in (0, 1, True, False):
            raise ConfigError(f"pin {self.name}: drive(level) takes 0 or 1, not {level!r}")
        self._core.pin_drive(self.number, bool(level))


class Var:
    """A firmware global, read by its ELF name as `type` (int8 .. uint32,
    float; default: by its size)."""

    def __init__(self, core: _Session, name: str, type: str = ""):
        self._core = core
        self.name = name
        self.type = type
        self.value  # checks the name and the type now

    @property
    def value(self) -> float:
        return self._core.var_read(self.name, self.type)

    def write(self, value: float) -> None:
        """Writes the global now, as a debugger does (no code runs); a value
        the type cannot hold (a fraction into an int, 300 into a uint8) is
        refused."""
        self._core.var_write(self.name, self.type, float(value))

    def __float__(self) -> float:
        return float(self.value)

    def __int__(self) -> int:
        return int(self.value)

    def __repr__(self) -> str:
        return f"Var({self.name!r}, {self.type or 'by size'!r}) = {self.value!r}"


class Sensor:
    """A part of the board's `parts:` list whose readings a test may hold in
    place of the world's (docs/python.md, "Holding a sensor's reading"):
    ultrasonic distance_m, reflectance reflectance, bumper pressed,
    ir-obstacle detected, imu gyro_z_dps."""

    def __init__(self, core: _Session, name: str):
        self._core = core
        self.name = name

    def set(self, **readings) -> None:
        """Holds each reading from the next plant step on (62.5 us); None
        gives it back to the world: set(distance_m=0.2), set(distance_m=None)."""
        if not readings:
            raise ConfigError(f"sensor '{self.name}': set() needs a reading, as set(distance_m=0.2)")
        for key, value in readings.items():
            self._core.sensor_set(self.name, key, None if value is None else float(value))


class Snapshot:
    """A session's state at an AVR cycle (Session.snapshot()); restore() comes
    back to it by building the session again and replaying what was done."""

    def __init__(self, core_snapshot):
        self._snap = core_snapshot

    @property
    def cycle(self) -> int:
        return self._snap.cycle

    def __repr__(self) -> str:
        return f"Snapshot(cycle={self._snap.cycle}, acts={self._snap.acts})"


class Truth:
    """The plant's ground truth: truth.csv's columns, sampled every
    millisecond of AVR time."""

    def __init__(self, core: _Session):
        self._core = core

    def pose(self) -> Pose:
        return Pose(*self._core.pose())

    @property
    def columns(self) -> list:
        return list(self._core.truth_columns())

    def history(self):
        """Every sample so far as a numpy structured array, one field per
        truth.csv column (t_s, x_m, ..., then the world's and the parts')."""
        import numpy as np

        rows = self._core.truth_history()
        dtype = np.dtype([(c, np.float64) for c in self._core.truth_columns()])
        return np.ascontiguousarray(rows).view(dtype).reshape(-1)


class Session:
    """One simulated robot: the firmware in simavr, the board's wiring, the
    plant, the world.

    firmware   the ELF (built for the board's MCU)
    sketch     instead of firmware: an Arduino sketch (x/x.ino or its folder),
               built for the board with arduino-builder (cached; docs/firmware.md)
    libraries  the sketch's library folders (folders *of* libraries), after its src/
    board      a board file (docs/boards.md); None: the thesis robot's wiring
    plant      a plant file (docs/plant.md), or a dict of overrides on the
               defaults ({"motor1": {"resistance_ohm": 6.0}}); None: defaults
    plant_overrides  a dict merged into `plant` when that is a file
    world      a world file (docs/world.md); None: the plain floor
    contract   the sketch contract (docs/contracts.md); None: the reference
               firmware's own, for other firmware none
    seed       the encoders' noise seeds (encoder1 = seed, encoder2 = seed+1)
    max_sim_s  the session's AVR-time limit [s] (RunEnded when reached)
    baud       the host's serial adapter (8N1); None: bytes as sent
    instruments  the ISR monitor, stack guard and race detector (default on)
    profile    the loop profiler, for loop_profile() (exact; single-steps: slower)
    fast_forward  skip whole passes of busy-wait loops exactly (default on;
               docs/fast-forward.md); False executes every instruction
    loop_mark  the function each control-loop iteration calls once; None: as
               `ddmr-hil run --profile` picks it (the contract's, else delay)
    """

    def __init__(
        self,
        firmware: Optional[PathLike] = None,
        board: Optional[PathLike] = None,
        world: Optional[PathLike] = None,
        plant: Union[None, PathLike, dict] = None,
        plant_overrides: Optional[dict] = None,
        contract: Optional[PathLike] = None,
        seed: Optional[int] = None,
        max_sim_s: float = 3600.0,
        baud: Optional[int] = None,
        instruments: bool = True,
        profile: bool = False,
        loop_mark: Optional[str] = None,
        sketch: Optional[PathLike] = None,
        libraries: Optional[list] = None,
        fast_forward: bool = True,
    ):
        overrides = {}
        plant_file = None
        if isinstance(plant, dict):
            overrides = plant
        elif plant is not None:
            plant_file = os.fspath(plant)
        layers = [layer for layer in (overrides, plant_overrides) if layer]  # merged in C++, in order
        kw = {
            "firmware": _path(firmware),
            "sketch": _path(sketch),
            "libraries": [os.fspath(d) for d in libraries or []],
            "board": _path(board),
            "world": _path(world),
            "plant_file": plant_file,
            "plant_overrides": [_json().dumps(layer) for layer in layers],
            "contract": _path(contract),
            "seed": seed,
            "max_sim_s": float(max_sim_s),
            "baud": baud,
            "instruments": bool(instruments),
            "profile": bool(profile),
            "loop_mark": loop_mark,
            "fast_forward": bool(fast_forward),
        }
        self._core = _Session(kw)
        self.serial = Serial(self._core)
        self.truth = Truth(self._core)

    # --- time ---------------------------------------------------------------
    @property
    def time_s(self) -> float:
        """The AVR's time [s] (its cycle count at the board's clock)."""
        return self._core.time_s

    @property
    def cycle(self) -> int:
        return self._core.cycle

    def run_for(self, seconds: float) -> "Session":
        """Runs `seconds` more of AVR time."""
        self._core.run_for(float(seconds))
        return self

    def run_until_serial(self, text: Union[str, bytes], timeout_s: float) -> "Session":
        """Runs until the host receives `text` (after what it had received),
        stopping right after its last byte; Timeout after `timeout_s` of AVR time."""
        self._core.run_until_serial(text.encode() if isinstance(text, str) else bytes(text), float(timeout_s))
        return self

    def run_until(self, condition: Callable[["Session"], bool], timeout_s: float) -> "Session":
        """Runs until condition(session) is true (checked every millisecond of
        AVR time); Timeout after `timeout_s`."""
        self._core.run_until(lambda: bool(condition(self)), float(timeout_s))
        return self

    def run_contract(self, case: Optional[int] = None) -> str:
        """The sketch contract's run as `ddmr-hil run --case N` does it, on a
        fresh session; returns the exit reason (report_complete when it
        completed). The session cannot run on afterwards; save_artifacts()
        writes the same files as `run`."""
        return self._core.run_contract(case)

    # --- faults -------------------------------------------------------------
    def fault(self, kind: str, **params) -> "Session":
        """A scenario fault step, with the scenario's keys (docs/scenarios.md,
        "Faults"): inject, stall, battery, slip, place, push, move-obstacle.
        Durations as for_s= / over_s= in seconds (or the scenario's for= / over=
        strings, "300ms"). It acts now; a timed one goes on over AVR time.

            s.fault("stall", motor="left", for_s=0.5)
            s.fault("inject", encoder=1, drop=0.05)"""
        self._core.fault(kind.replace("_", "-"), _json().dumps(_step_value(params)))
        return self

    def push(self, dx_m: float = 0.0, dy_m: float = 0.0, dtheta_rad: float = 0.0, over_s: float = 0.0) -> "Session":
        """Displaces the robot (in the world frame), at once or evenly over over_s."""
        return self.fault("push", dx_m=dx_m, dy_m=dy_m, dtheta_rad=dtheta_rad, over_s=over_s)

    def place(self, x_m: float, y_m: float, heading_deg: float) -> "Session":
        """Sets the robot down at this pose (odometry does not see it)."""
        return self.fault("place", x_m=x_m, y_m=y_m, heading_deg=heading_deg)

    def move_obstacle(self, name: str, dx_m: float = 0.0, dy_m: float = 0.0, over_s: float = 0.0) -> "Session":
        """Slides the world's obstacle `name` (docs/world.md), at once or over over_s."""
        return self.fault("move-obstacle", name=name, dx_m=dx_m, dy_m=dy_m, over_s=over_s)

    # --- the robot ----------------------------------------------------------
    def pin(self, name: Union[str, int]) -> Pin:
        return Pin(self._core, str(name))

    def pwm(self, name: Union[str, int]) -> Pin:
        return Pin(self._core, str(name))

    def var(self, name: str, type: str = "") -> Var:
        return Var(self._core, name, type)

    def sensor(self, name: str) -> Sensor:
        """The board's part `name` (its `parts:` entry), to hold its readings."""
        return Sensor(self._core, name)

    # --- instruments --------------------------------------------------------
    def isr_stats(self) -> dict:
        """isr.json's content so far: per-vector counts, latency and duration
        in cycles, and the race detector's findings (docs/isr.md)."""
        return _json().loads(self._core.isr_stats_json())

    def start_loop_profile(self) -> "Session":
        """Starts the loop profile at the next return of the loop mark
        (Session(profile=True)); run_contract() starts it as `run` does,
        when it sends the contract's start text."""
        self._core.loop_profile_start()
        return self

    def loop_profile(self):
        """The control loop's iterations so far, as a numpy structured array:
        start, mark_entry, end, compute, wait, period [cycles], eeprom_write."""
        import numpy as np

        rows = self._core.loop_profile()
        names = ["start", "mark_entry", "end", "compute", "wait", "period", "eeprom_write"]
        dtype = np.dtype([(n, np.uint64) for n in names])
        return np.ascontiguousarray(rows).view(dtype).reshape(-1)

    # --- snapshots ----------------------------------------------------------
    def snapshot(self) -> Snapshot:
        """The state now, to restore() later (boot once, try many inputs)."""
        return Snapshot(self._core.snapshot())

    def restore(self, snap: Snapshot) -> "Session":
        """Back to `snap`, exactly: the session is built again from reset and
        what was done before the snapshot (serial bytes, faults, drives,
        writes) is replayed at the same cycles. It costs the snapshot's AVR
        time again. Ctrl-C during it leaves the session as it was."""
        self._core.restore(snap._snap)
        return self

    def eeprom(self) -> bytes:
        """The MCU's whole EEPROM now."""
        return self._core.eeprom()

    def warnings(self) -> list:
        """The run's warnings so far (the wiring's, the parts')."""
        return list(self._core.warnings())

    # --- the end ------------------------------------------------------------
    def save_artifacts(self, folder: PathLike) -> str:
        """Ends the run (the session cannot run on) and writes the artifacts
        `ddmr-hil run` writes (uart.txt, truth.csv, summary.json, ...) into
        `folder`; returns the exit reason."""
        self._core.save_artifacts(os.fspath(folder))
        return self._core.exit_reason

    @property
    def exit_reason(self) -> str:
        """summary.json's exit_reason once the run has ended, else ''."""
        return self._core.exit_reason


def _step_value(params: dict) -> dict:
    """Python keywords -> a scenario step's keys: for_s=0.5 -> for: "0.5s"."""
    out = {}
    for key, value in params.items():
        if key in ("for_s", "over_s"):
            if key == "over_s" and value == 0:
                continue
            out[key[:-2]] = f"{float(value)!r}s"
        elif key in ("for_", "over_"):
            out[key[:-1]] = value
        else:
            out[key] = value
    return out


def _json():
    import json  # on first use: a plain session does not pay for it

    return json


def _path(p: Optional[PathLike]) -> Optional[str]:
    return None if p is None else os.fspath(p)


def __getattr__(name: str):
    """sweep, grid and to_csv load with their module on first use (PEP 562):
    a session that never sweeps does not pay for its imports."""
    if name in ("sweep", "grid", "to_csv"):
        from . import _sweep

        return getattr(_sweep, name)
    raise AttributeError(f"module 'ddmr_hil' has no attribute {name!r}")
