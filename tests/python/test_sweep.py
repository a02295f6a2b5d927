"""ddmr_hil.sweep: HIL sessions over plant variations, serially and on a
Dask LocalCluster of 2 workers on 127.0.0.1: the same bytes either way."""

import subprocess
import sys

import pytest

import ddmr_hil
from ddmr_hil import grid, sweep
from ddmr_hil.sweep import flatten, nested, to_csv


def test_grid_is_every_combination_last_axis_fastest():
    g = grid({"motor1.resistance_ohm": [5.0, 6.0], "battery.voltage_v": [7.0, 8.0, 9.0]})
    assert len(g) == 6
    assert g[0] == {"motor1": {"resistance_ohm": 5.0}, "battery": {"voltage_v": 7.0}}
    assert g[1] == {"motor1": {"resistance_ohm": 5.0}, "battery": {"voltage_v": 8.0}}
    assert g[5] == {"motor1": {"resistance_ohm": 6.0}, "battery": {"voltage_v": 9.0}}
    assert flatten(nested({"a.b.c": 1, "a.d": 2})) == {"a.b.c": 1, "a.d": 2}
    with pytest.raises(ddmr_hil.ConfigError, match="axis 'x' has no values"):
        grid({"x": []})
    # The module of `python3 -m ddmr_hil.sweep` is imported here: ddmr_hil.sweep still sweeps.
    assert callable(ddmr_hil.sweep)


def test_a_dask_sweep_gives_the_serial_sweeps_bytes(reference_elf):
    plants = grid({"motor1.resistance_ohm": [5.0, 6.5], "motor2.resistance_ohm": [5.0, 6.5]})
    serial = to_csv(sweep(plants, firmware=reference_elf, case=2, client="serial"))
    local = to_csv(sweep(plants, firmware=reference_elf, case=2, workers=2))
    assert local == serial
    lines = serial.splitlines()
    assert lines[0] == "index,motor1.resistance_ohm,motor2.resistance_ohm,exit_reason,sim_s,x_m,y_m,theta_rad"
    assert len(lines) == 5
    assert all(",report_complete," in line for line in lines[1:])
    # Case 2 drives toward (0.4 m, 0): every plant gets most of the way, and
    # a plant with a weaker right motor (higher R: less torque) ends elsewhere.
    xs = [float(line.split(",")[5]) for line in lines[1:]]
    assert all(0.3 < x < 0.5 for x in xs)
    assert xs[0] != xs[2]


def test_the_command_line_writes_the_csv_or_one_line_and_nothing(tmp_path, reference_elf):
    out = tmp_path / "r.csv"
    cmd = [sys.executable, "-m", "ddmr_hil.sweep", "--firmware", str(reference_elf), "--seconds", "0.2",
           "--serial", "--quiet", "--out", str(out)]
    r = subprocess.run(cmd + ["--grid", "motor1.resistance_ohm=5,6"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert out.read_text().splitlines()[1].startswith("0,5.0,stopped,0.2")
    bad = tmp_path / "bad.csv"
    r = subprocess.run(cmd[:-1] + [str(bad), "--grid", "motor1.resistance_ohm=five"], capture_output=True, text=True)
    assert r.returncode == 2
    assert r.stderr.strip().splitlines() == ["ddmr_hil.sweep: --grid 'motor1.resistance_ohm=five': the values must "
                                             "be numbers"]
    assert not bad.exists()
    r = subprocess.run(cmd[:-1] + [str(bad), "--grid", "motor1.resistance_ohm=-5"], capture_output=True, text=True)
    assert r.returncode == 2
    assert "plant" in r.stderr and "resistance_ohm" in r.stderr
    assert not bad.exists()
