"""What a test does to a running robot through ddmr_hil.Session: drive an
input pin, write a global, hold a sensor's reading, read the ISR statistics
and the loop profile, and come back to a snapshot. Each checked against a
fact of the fixture firmware (tests/firmware/*.c) or of the reference
sketch (firmware/ddmr_tracking)."""

import json

import pytest

import ddmr_hil
from ddmr_hil import Session

DETERMINISTIC = ["uart.txt", "truth.csv", "eeprom.bin", "firmware.csv", "eeprom_log.csv", "isr.json", "isr.md"]
WALL_FIELDS = {"wall_seconds", "mcycles_per_s", "out_dir"}


def summary_without_wall_time(path):
    s = json.loads(path.read_text())
    return {k: v for k, v in s.items() if k not in WALL_FIELDS}


def started(elf, seed=1):
    """The reference sketch takes its case byte during setup()'s delay(5000)."""
    s = Session(firmware=elf, seed=seed)
    s.run_for(0.1)
    return s


def test_a_restored_snapshot_runs_on_as_a_run_that_never_stopped(tmp_path, reference_elf):
    never = started(reference_elf)
    never.serial.write(b"1")
    never.run_until_serial("0.6m", timeout_s=8).run_for(1.0)
    never.save_artifacts(tmp_path / "never")

    s = started(reference_elf)
    booted = s.snapshot()
    s.serial.write(b"2")  # another case, then back: nothing of it may remain
    s.run_for(0.5)
    s.fault("stall", motor="left", for_s=0.2)
    s.restore(booted)
    assert s.cycle == booted.cycle
    s.serial.write(b"1")
    s.run_until_serial("0.6m", timeout_s=8)
    moving = s.snapshot()
    s.push(dy_m=0.05).run_for(0.3)
    s.restore(moving)
    s.run_for(1.0)
    s.save_artifacts(tmp_path / "restored")

    for name in DETERMINISTIC:
        assert (tmp_path / "restored" / name).read_bytes() == (tmp_path / "never" / name).read_bytes(), name
    assert summary_without_wall_time(tmp_path / "restored" / "summary.json") == summary_without_wall_time(
        tmp_path / "never" / "summary.json"
    )


def test_a_snapshot_belongs_to_its_session_and_not_to_an_ended_run(reference_elf):
    a = Session(firmware=reference_elf, instruments=False)
    b = Session(firmware=reference_elf, instruments=False)
    snap = a.run_for(0.01).snapshot()
    with pytest.raises(ddmr_hil.UsageError, match="taken by another Session"):
        b.restore(snap)
    a.save_artifacts  # noqa: B018  (the attribute exists)
    ended = Session(firmware=reference_elf, instruments=False)
    assert ended.run_contract(case=2) == "report_complete"
    with pytest.raises(ddmr_hil.RunEnded):
        ended.snapshot()


def test_a_driven_pin_raises_its_pin_change_interrupt(build_dir):
    # edge_fixture: A0 (PCINT8) is enabled in PCMSK1, its ISR counts pcint1_count.
    s = Session(firmware=build_dir / "tests" / "firmware" / "edge_fixture.elf", instruments=False)
    s.run_for(0.001)
    count = s.var("pcint1_count", "uint16")
    assert count.value == 0
    s.pin("A0").drive(1)
    s.run_for(0.001)
    assert count.value == 1 and s.pin("A0").level == 1
    s.pin("A0").drive(0)
    s.run_for(0.001)
    assert count.value == 2 and s.pin("A0").level == 0
    # D2 is the default board's right encoder: a second source would fight it.
    with pytest.raises(ddmr_hil.ConfigError, match=r"pin 2: the board wires it \(wheels\.right\.encoder\.OUT\)"):
        s.pin("D2").drive(1)
    with pytest.raises(ddmr_hil.ConfigError, match="pin 0 carries Serial"):
        s.pin("D0").drive(1)
    with pytest.raises(ddmr_hil.ConfigError, match="takes 0 or 1"):
        s.pin("A1").drive(5)


def test_a_written_global_is_what_the_firmware_reads(build_dir):
    s = Session(firmware=build_dir / "tests" / "firmware" / "edge_fixture.elf", instruments=False)
    s.run_for(0.001)
    count = s.var("int0_count", "uint16")
    count.write(40000)
    assert count.value == 40000
    assert s.eeprom() == s.eeprom()  # reads have no side effects
    with pytest.raises(ddmr_hil.ConfigError, match=r"var 'int0_count': 70000 is not a uint16 \(an integer in \[0, 65535\]\)"):
        count.write(70000)
    with pytest.raises(ddmr_hil.ConfigError, match="is not a uint16"):
        count.write(1.5)
    assert count.value == 40000  # a refused write changes nothing


SONAR_BOARD = """board: uno
wheels:
  right: {motor: {driver: dir-pwm, PWM: 10, DIR: 12}, encoder: {type: single, OUT: 2}}
  left:  {motor: {driver: dir-pwm, PWM: 11, DIR: 13}, encoder: {type: single, OUT: 3}}
parts:
  - {name: sonar, type: ultrasonic, TRIG: 7, ECHO: 8, x_mm: 0, y_mm: 0}
"""
SONAR_WORLD = """walls:
  - {from_m: [1.0, -1.0], to_m: [1.0, 1.0], height_m: 0.3}
"""


def ping(s, n):
    """sonar_fixture pings (12 us on TRIG, D7) when `request` changes."""
    s.var("request", "uint8").write(n)
    s.run_for(0.03)
    h = s.truth.history()
    return h["sonar.distance_m"][-1], h["sonar.echo_us"][-1], h["sonar.pings"][-1]


def test_a_held_sonar_reading_replaces_the_world_until_released(tmp_path, build_dir):
    (tmp_path / "board.yaml").write_text(SONAR_BOARD)
    (tmp_path / "world.yaml").write_text(SONAR_WORLD)
    s = Session(firmware=build_dir / "tests" / "firmware" / "sonar_fixture.elf", board=tmp_path / "board.yaml",
                world=tmp_path / "world.yaml", instruments=False)
    s.run_for(0.001)
    d, echo, pings = ping(s, 1)
    assert (d, pings) == (pytest.approx(1.0, abs=1e-9), 1)  # the wall, 1 m ahead of the axle
    s.sensor("sonar").set(distance_m=0.2)
    d, echo, pings = ping(s, 2)
    # 2 d / c at 20 C: c = 331.5 + 0.6 x 20 = 343.5 m/s (SENSORS.md) -> 1164.49 us
    assert (d, pings) == (pytest.approx(0.2), 2)
    assert echo == pytest.approx(2 * 0.2 / 343.5 * 1e6, abs=1e-6)
    s.sensor("sonar").set(distance_m=None)
    assert ping(s, 3)[0] == pytest.approx(1.0, abs=1e-9)
    with pytest.raises(ddmr_hil.ConfigError, match=r"sensor 'sonar' \(ultrasonic\) has no reading 'range'; it has: distance_m"):
        s.sensor("sonar").set(range=1.0)
    with pytest.raises(ddmr_hil.ConfigError, match=r"sensor 'front': the board has no such part; .*: sonar \(ultrasonic\)"):
        s.sensor("front").set(distance_m=1.0)
    with pytest.raises(ddmr_hil.ConfigError, match=r"distance_m = -1 is outside \[0, 100\]"):
        s.sensor("sonar").set(distance_m=-1)


def test_the_loop_profile_needs_the_profiler(reference_elf):
    s = Session(firmware=reference_elf, instruments=False)
    with pytest.raises(ddmr_hil.UsageError, match=r"Session\(profile=True\)"):
        s.loop_profile()
    with pytest.raises(ddmr_hil.UsageError, match=r"Session\(instruments=False\)"):
        s.isr_stats()


def test_a_sketch_is_built_for_the_board_and_a_held_sonar_reading_stops_the_avoider(source_dir):
    """firmware/examples/obstacle_avoider_servo from its sketch: it stops and
    prints "stop CM" when its sonar reads under 30 cm. The world's wall is
    1.2 m ahead; held at 0.2 m it stops at once: 2 x 0.2 / 343.5 s = 1164 us,
    / 58 us a cm = 20 cm (pulseIn may count a little short: 19)."""
    import re

    example = source_dir / "firmware" / "examples" / "obstacle_avoider_servo"
    s = Session(sketch=example, board=example / "board.yaml", world=example / "world.yaml", instruments=False)
    s.run_until_serial("obstacle_avoider_servo ready", timeout_s=3)
    s.run_for(0.3)
    assert b"stop" not in s.serial.text  # the wall is 1.2 m away
    s.sensor("sonar").set(distance_m=0.2)
    s.run_until_serial("stop ", timeout_s=0.5)
    s.run_until_serial("\n", timeout_s=0.1)
    assert re.search(rb"stop (19|20)\r?\n", s.serial.text), s.serial.text


def test_firmware_or_sketch_one_of_them(tmp_path, reference_elf):
    with pytest.raises(ddmr_hil.ConfigError, match="give firmware .* or sketch"):
        Session()
    with pytest.raises(ddmr_hil.ConfigError, match="not both"):
        Session(firmware=reference_elf, sketch=tmp_path)
    with pytest.raises(ddmr_hil.ConfigError, match=r"a folder without .*\.ino"):
        Session(sketch=tmp_path)
