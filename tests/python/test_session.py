"""ddmr_hil.Session: the engine driven from Python, checked against what the
command line does with the same firmware, and against facts of the
reference sketch (firmware/ddmr_tracking: setup() ends with delay(5000),
then it waits for the case byte; case 1 drives a 0.6 m circle)."""

import subprocess

import numpy as np
import pytest

import ddmr_hil
from ddmr_hil import Session

# Files `ddmr-hil run` writes whose bytes depend only on the simulation
# (summary.json also holds wall-clock times and paths).
DETERMINISTIC = ["uart.txt", "truth.csv", "eeprom.bin", "firmware.csv", "eeprom_log.csv", "isr.json", "isr.md"]


def test_run_contract_gives_the_cli_runs_artifacts(tmp_path, build_dir, reference_elf):
    api = tmp_path / "api"
    s = Session(firmware=reference_elf)
    assert s.run_contract(case=1) == "report_complete"
    assert s.save_artifacts(api) == "report_complete"
    cli = tmp_path / "cli"
    subprocess.run([str(build_dir / "ddmr-hil"), "run", "--case", "1", "--quiet", "--out", str(cli)], check=True,
                   stdout=subprocess.DEVNULL)
    for name in DETERMINISTIC:
        assert (api / name).read_bytes() == (cli / name).read_bytes(), name
    # The session's truth is truth.csv's, value for value.
    csv = np.genfromtxt(cli / "truth.csv", delimiter=",", names=True)
    hist = s.truth.history()
    assert list(hist.dtype.names) == list(csv.dtype.names)
    assert len(hist) == len(csv)
    np.testing.assert_allclose(hist["x_m"], csv["x_m"], rtol=0, atol=1e-8)
    with pytest.raises(ddmr_hil.RunEnded):
        s.run_for(0.1)


def test_a_free_run_boots_takes_the_case_byte_and_drives(reference_elf):
    s = Session(firmware=reference_elf, instruments=False)
    s.run_for(4.0)  # inside setup()'s delay(5000): nothing moves
    assert s.time_s == pytest.approx(4.0, abs=1e-4)
    assert s.truth.pose() == (0.0, 0.0, 0.0)
    assert s.var("t").value == 0.0
    s.run_for(1.1)
    s.serial.write(b"1")
    s.run_until(lambda s: s.truth.pose().x_m > 0.05, timeout_s=3.0)
    assert s.var("t").value > 0.0  # the control loop runs
    assert 0.0 < s.pwm("D10").duty <= 1.0  # the right motor's enable is modulated
    hist = s.truth.history()
    assert hist["t_s"][-1] == pytest.approx(s.time_s, abs=2e-3)
    assert hist["x_m"][-1] > 0.05


def test_a_wait_that_times_out_raises_timeout_and_the_session_goes_on(reference_elf):
    s = Session(firmware=reference_elf, instruments=False)
    with pytest.raises(ddmr_hil.Timeout, match="'never' did not come within 0.5 s of AVR time"):
        s.run_until_serial("never", timeout_s=0.5)
    assert s.time_s == pytest.approx(0.5, abs=1e-3)
    s.run_for(0.1)
    assert s.time_s == pytest.approx(0.6, abs=1e-3)
    with pytest.raises(ddmr_hil.Timeout, match="did not come within 0.1 s"):
        s.run_until_serial(b"\xb0", timeout_s=0.1)  # bytes go to the wire as they are


def test_plant_overrides_and_seed_change_the_plant(tmp_path, reference_elf):
    def end_x(**kw):
        s = Session(firmware=reference_elf, instruments=False, **kw)
        s.run_for(5.1)
        s.serial.write(b"1")
        s.run_for(1.0)
        return s.truth.pose().x_m

    base = end_x()
    assert end_x() == base  # deterministic
    # A motor with twice the armature resistance gives less torque: the robot lags.
    assert end_x(plant={"motor1": {"resistance_ohm": 2 * 5.32}}) != base


def test_bad_input_is_a_one_line_error(tmp_path, reference_elf):
    with pytest.raises(ddmr_hil.ConfigError, match="no_such.elf"):
        Session(firmware=tmp_path / "no_such.elf")
    with pytest.raises(ValueError):  # a ConfigError is a ValueError too
        Session(firmware=reference_elf, plant={"motor1": {"resistance_ohm": -1}})
    s = Session(firmware=reference_elf, instruments=False)
    with pytest.raises(ddmr_hil.ConfigError, match="pin 'D99'"):
        s.pin("D99")
    with pytest.raises(ddmr_hil.ConfigError, match="no_such_global"):
        s.var("no_such_global")
    with pytest.raises(ddmr_hil.ConfigError):
        s.run_for(-1)
    s.run_for(0.01)
    with pytest.raises(ddmr_hil.UsageError, match="fresh Session"):
        s.run_contract(case=1)


def test_faults_act_as_the_scenario_steps_do(reference_elf):
    s = Session(firmware=reference_elf, instruments=False)
    s.run_for(1.0)  # in setup(): the robot stands still
    s.push(dx_m=0.05, dtheta_rad=0.1)
    assert s.truth.pose().x_m == pytest.approx(0.05, abs=1e-9)
    assert s.truth.pose().theta_rad == pytest.approx(0.1, abs=1e-9)
    s.place(x_m=0.2, y_m=-0.1, heading_deg=90)
    assert s.truth.pose() == pytest.approx((0.2, -0.1, 1.5707963267948966), abs=1e-9)
    s.run_for(4.1)
    s.serial.write(b"1")
    s.run_for(0.5)
    s.fault("stall", motor="left", for_s=0.3)  # the left wheel is motor 2
    s.run_for(0.2)
    assert s.truth.history()["wheel2_rad_s"][-1] == 0.0
    assert s.truth.history()["wheel1_rad_s"][-1] != 0.0
    s.run_for(0.3)  # the stall is over
    assert s.truth.history()["wheel2_rad_s"][-1] != 0.0
    with pytest.raises(ddmr_hil.ConfigError, match=r"fault\(\):1: key 'stall.motor'"):
        s.fault("stall", motor=3, for_s=0.1)
    with pytest.raises(ddmr_hil.ConfigError, match="duration '-1.0s'"):
        s.fault("stall", motor=1, for_s=-1)
    with pytest.raises(ddmr_hil.ConfigError, match="not a fault"):
        s.fault("dance")
    with pytest.raises(ddmr_hil.ConfigError, match="not a fault"):
        s.fault("reset")  # a scenario step the fault parser also reads, not a fault
    with pytest.raises(ddmr_hil.ConfigError, match="no obstacle named 'box'"):
        s.move_obstacle("box", dx_m=0.1)


def test_plant_overrides_merge_as_layers_with_the_encoder_resolution_rule(reference_elf):
    # One layer's edges_per_wheel_rev replaces the other's edges_per_motor_rev
    # (tools/common/plant_yaml.cpp, as a scenario's overrides); both in one
    # mapping is a contradiction and is refused.
    s = Session(firmware=reference_elf, instruments=False, plant={"encoder1": {"edges_per_motor_rev": 12}},
                plant_overrides={"encoder1": {"edges_per_wheel_rev": 600}})
    s.run_for(0.01)
    with pytest.raises(ddmr_hil.ConfigError, match="edges_per"):
        Session(firmware=reference_elf, plant={"encoder1": {"edges_per_motor_rev": 12, "edges_per_wheel_rev": 600}})


def interrupt_after(seconds):
    """Ctrl-C from a timer thread: SIGINT to this process after `seconds` of wall time."""
    import os
    import signal
    import threading

    t = threading.Timer(seconds, lambda: os.kill(os.getpid(), signal.SIGINT))
    t.start()
    return t


def test_ctrl_c_stops_a_long_run_and_the_session_stays_where_it_stopped(reference_elf):
    s = Session(firmware=reference_elf, instruments=False, fast_forward=False)
    interrupt_after(0.3)
    with pytest.raises(KeyboardInterrupt):
        s.run_for(600.0)
    stopped = s.time_s
    assert 0.0 < stopped < 600.0
    s.run_for(0.01)
    assert s.time_s == pytest.approx(stopped + 0.01, abs=1e-3)


def test_ctrl_c_stops_run_contract_which_then_cannot_run_on(reference_elf):
    # Executing every pass, case 1 takes about 1.5 s of wall time (about
    # 0.5 s with fast-forward: too close to call).
    s = Session(firmware=reference_elf, instruments=False, fast_forward=False)
    interrupt_after(0.4)
    with pytest.raises(KeyboardInterrupt):
        s.run_contract(case=1)
    with pytest.raises(ddmr_hil.RunEnded, match=r"run_contract\(\) was stopped before the contract's end"):
        s.run_for(0.1)


def test_fast_forward_off_gives_the_same_run(tmp_path, reference_elf):
    """docs/fast-forward.md: a session skipping busy-wait passes and one
    executing them stop on the same condition at the same cycle, with the
    same bytes and the same ground truth."""
    runs = []
    for ff in (True, False):
        s = Session(firmware=reference_elf, fast_forward=ff)
        s.run_for(5.2)
        s.serial.write(b"2")
        s.run_until(lambda s: s.var("Count1", "int32").value >= 500, timeout_s=5.0)
        s.save_artifacts(tmp_path / str(ff))
        runs.append((s.time_s, s.serial.text, s.truth.history()))
    assert runs[0][0] == runs[1][0]
    assert runs[0][1] == runs[1][1]
    np.testing.assert_array_equal(runs[0][2], runs[1][2])
    for name in ("uart.txt", "truth.csv", "eeprom.bin", "isr.json"):
        assert (tmp_path / "True" / name).read_bytes() == (tmp_path / "False" / name).read_bytes(), name
