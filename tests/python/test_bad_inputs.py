"""The reliability suite's bad inputs (tests/reliability/bad_input_test.cpp)
fed through the Python API, and the API's own: each raises the documented
exception with one line, none crashes the interpreter, and a hundred
rounds of them leave memory flat. `make test` runs this file twice: here,
and in the sanitizer tree under AddressSanitizer and UBSan
(ctest -R python_bad_inputs_asan), where a memory error on any error path
aborts the interpreter."""

import os
import random

import pytest

import ddmr_hil
from ddmr_hil import Session

BOARD_HEAD = "board: uno\nwheels:\n  right: {motor: {driver: dir-pwm, PWM: 10, DIR: 12}, encoder: {type: single, OUT: 2}}\n"


def corrupt_elfs(elf: bytes):
    """The reliability suite's firmware files: name, bytes, a word of the message."""
    cases = [
        ("empty.elf", b"", "empty"),
        ("head.elf", elf[:40], "head.elf"),
        ("cut.elf", elf[:600], "cut.elf"),
        ("half.elf", elf[: len(elf) // 2], "half.elf"),
        ("notes.elf", b"this is not a firmware\n", "not an ELF"),
        ("bad.hex", b":10000000FFFFFFFFFFFFFFFFFFFFFFFFFFFFFFFF00\n:00000001FF\n", "bad.hex"),
    ]
    rng = random.Random(7)  # the same bytes every run
    for k in range(3):
        cases.append((f"random{k}.elf", b"\x7fELF" + bytes(rng.randrange(256) for _ in range(2000)), f"random{k}.elf"))
    return cases


BAD_FILES = [
    # (argument, file name, text, a word of the message)
    ("plant", "p.yaml", "motor1: [1,\n", "malformed YAML"),
    ("plant", "p.yaml", "motor1:\n  resistanse_ohm: 5\n", "resistanse_ohm"),
    ("plant", "p.yaml", "motor3:\n  resistance_ohm: 5\n", "motor3"),
    ("plant", "p.yaml", "motor1:\n  resistance_ohm: abc\n", "resistance_ohm"),
    ("plant", "p.yaml", "battery:\n  open_circuit_V: .nan\n", "open_circuit_V"),
    ("plant", "p.yaml", "motor2:\n  inductance_H: .inf\n", "inductance_H"),
    ("plant", "p.yaml", "kinematics:\n  wheel_radius_right_m: 0\n", "wheel_radius_right_m"),
    ("board", "b.yaml", BOARD_HEAD + "  left: {motor: {driver: dir-pwm, PWM: 11, DIR: 20}, encoder: {type: single, OUT: 3}}\n", "20"),
    ("board", "b.yaml", BOARD_HEAD + "  left: {motor: {driver: dir-pwm, PWM: 4, DIR: 13}, encoder: {type: single, OUT: 3}}\n", "PWM"),
    ("board", "b.yaml", BOARD_HEAD + "  left: {motor: {driver: dir-pwm, PWM: 11, DIR: 13}, encoder: {type: single, OUT: 12}}\n", "already used"),
    ("board", "b.yaml", BOARD_HEAD + "  left: {motor: {driver: l297, EN: 5}, encoder: {type: single, OUT: 3}}\n", "l297"),
    ("world", "w.yaml", "lines:\n  - {points_m: [[0, 0], [1, 0]], width_m: 0}\n", "width_m"),
    ("world", "w.yaml", "walls:\n  - {from_m: [1, 1], to_m: [1, 1]}\n", "zero length"),
    ("world", "w.yaml", "walls:\n  - {polygon_m: [[0, 0], [1, 0]]}\n", "polygon_m"),
    ("world", "w.yaml", "walls: [\n", "malformed YAML"),
    ("contract", "c.yaml", "start: {text: [\n", "c.yaml"),
]


def one_line_error(exc_type, match, call):
    with pytest.raises(exc_type, match=match) as e:
        call()
    text = str(e.value)
    assert text and "\n" not in text, repr(text)


def feed_everything(tmp_path, elf_path):
    elf = elf_path.read_bytes()
    for name, data, word in corrupt_elfs(elf):
        (tmp_path / name).write_bytes(data)
        one_line_error(ddmr_hil.ConfigError, None, lambda: Session(firmware=tmp_path / name))
    one_line_error(ddmr_hil.ConfigError, "missing.elf", lambda: Session(firmware=tmp_path / "missing.elf"))
    for arg, name, text, word in BAD_FILES:
        (tmp_path / name).write_text(text)
        one_line_error(ddmr_hil.ConfigError, None, lambda: Session(firmware=elf_path, **{arg: tmp_path / name}))
        one_line_error(ddmr_hil.ConfigError, None, lambda: Session(firmware=elf_path, **{arg: tmp_path / "gone.yaml"}))
    one_line_error(ddmr_hil.ConfigError, "resistance_ohm", lambda: Session(firmware=elf_path, plant={"motor1": {"resistance_ohm": "x"}}))
    one_line_error(ddmr_hil.ConfigError, None, lambda: Session(firmware=elf_path, plant={"motor9": {}}))

    s = Session(firmware=elf_path, instruments=False)
    s.run_for(0.001)
    one_line_error(ddmr_hil.ConfigError, "pin 'D99'", lambda: s.pin("D99"))
    one_line_error(ddmr_hil.ConfigError, "no_such", lambda: s.var("no_such"))
    one_line_error(ddmr_hil.ConfigError, None, lambda: s.var("Count1", "int64"))
    one_line_error(ddmr_hil.ConfigError, None, lambda: s.var("Count1", "uint8"))
    one_line_error(ddmr_hil.ConfigError, None, lambda: s.var("Count1", "int32").write(2.0**40))
    one_line_error(ddmr_hil.ConfigError, None, lambda: s.run_for(float("nan")))
    one_line_error(ddmr_hil.ConfigError, None, lambda: s.run_until_serial("", timeout_s=1))
    one_line_error(ddmr_hil.ConfigError, None, lambda: s.run_until_serial("x", timeout_s=-1))
    one_line_error(ddmr_hil.ConfigError, "not a fault", lambda: s.fault("explode"))
    one_line_error(ddmr_hil.ConfigError, None, lambda: s.fault("stall", motor="middle", for_s=1))
    one_line_error(ddmr_hil.ConfigError, None, lambda: s.fault("push", dx_m=float("inf")))
    one_line_error(ddmr_hil.ConfigError, None, lambda: s.move_obstacle("nothing", dx_m=0.1))
    one_line_error(ddmr_hil.ConfigError, "the board wires it", lambda: s.pin("D10").drive(1))
    one_line_error(ddmr_hil.ConfigError, "no such part", lambda: s.sensor("sonar").set(distance_m=1.0))
    one_line_error(ddmr_hil.UsageError, "profile=True", lambda: s.loop_profile())
    one_line_error(ddmr_hil.UsageError, "instruments=False", lambda: s.isr_stats())
    one_line_error(ddmr_hil.UsageError, "fresh Session", lambda: s.run_contract(case=1))
    s.serial.write(b"\xff\x00garbage\n")
    s.run_for(0.001)
    s.save_artifacts(tmp_path / "saved")
    one_line_error(ddmr_hil.RunEnded, None, lambda: s.run_for(0.001))
    one_line_error(ddmr_hil.RunEnded, None, lambda: s.snapshot())
    c = Session(firmware=elf_path, instruments=False)
    one_line_error(ddmr_hil.ConfigError, None, lambda: c.run_contract(case=9))


def test_every_bad_input_raises_its_exception_with_one_line(tmp_path, reference_elf):
    feed_everything(tmp_path, reference_elf)


@pytest.mark.skipif("ASAN_OPTIONS" in os.environ, reason="RSS under AddressSanitizer's allocator says nothing")
def test_a_hundred_rounds_of_bad_inputs_leave_memory_flat(tmp_path, reference_elf):
    import ctypes
    import gc

    libc = ctypes.CDLL("libc.so.6")

    def rss():
        # Freed memory handed back first: without it, RSS measures glibc's
        # arenas (+8 MB over the first 50 rounds, then creeping with
        # fragmentation), not what is still held.
        gc.collect()
        libc.malloc_trim(0)
        with open("/proc/self/statm") as f:
            return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")

    for _ in range(20):  # warm up: caches, the module's statics
        feed_everything(tmp_path, reference_elf)
    base = rss()
    for _ in range(100):
        feed_everything(tmp_path, reference_elf)
    grown = rss() - base
    # Measured: 0.2 MB after 300 rounds. A session's leak (a core, its SRAM,
    # a plant: over 100 KB) would show 100 times over.
    assert grown < 2 * 1024 * 1024, f"{grown / 1e6:.1f} MB more after 100 more rounds"
