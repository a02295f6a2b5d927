"""The data the reports plot (tools/report/), worked out by hand: the
PWM-window statistics that replace aliased 1 kHz samples, the tracking error,
a scenario's step markers and expect-pose targets, which plant columns are
worth a plot, which folder is which, and a suite's index."""
import json
import math
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "tools", "report"))

import make_report  # noqa: E402
import plot_common  # noqa: E402
import scenario_report  # noqa: E402


def test_the_pwm_period_is_the_unos_490_hz():
    # Timer1/2 phase-correct 8-bit, prescaler 64: 16 MHz / (64 x 510) = 490.196 Hz.
    assert math.isclose(1.0 / plot_common.PWM_PERIOD_S, 490.196, rel_tol=1e-5)


def test_a_pwm_square_wave_sampled_at_1khz_averages_to_its_duty():
    # A 490 Hz wave at duty 0.3 between 0 and 2 A, sampled at 1 kHz for 2 s:
    # each sample alone is 0 or 2 (the solid blocks). A window of 25 PWM
    # periods (51 ms) holds 51 or 52 samples at evenly spread phases of the
    # cycle, 15 to 17 of them high: its mean is the wave's (0.6 A) within
    # 0.06 (2 A x 3/104: a sample more or less at each end). The envelope
    # spans 0..2 A.
    p = plot_common.PWM_PERIOD_S
    t = [k * 1e-3 for k in range(2000)]
    y = [2.0 if (tk / p) % 1.0 < 0.3 else 0.0 for tk in t]
    window = plot_common.WINDOW_S
    assert window == plot_common.WINDOW_PERIODS * p
    stats = plot_common.window_stats(t, y, window)
    assert len(stats) == int(t[-1] / window)  # whole windows only: 39
    for centre, mean, lo, hi in stats:
        assert abs(mean - 0.6) <= 0.06, (centre, mean)
        assert (lo, hi) == (0.0, 2.0)
    # A window of 10 periods (20.4 ms) sees 2/5 of a beat: its mean is off by up to 0.5 A.
    short = plot_common.window_stats(t, y, 10 * p)
    assert max(abs(s[1] - 0.6) for s in short) > 0.3


def test_a_constant_stays_constant_and_windows_are_centred():
    t = [k * 1e-3 for k in range(100)]
    stats = plot_common.window_stats(t, [5.0] * 100, 0.02)
    assert [s[1:] for s in stats] == [(5.0, 5.0, 5.0)] * 4  # 0-20, ..., 60-80 ms; 80-100 ms is partial
    assert [round(s[0], 6) for s in stats] == [0.01, 0.03, 0.05, 0.07]
    assert plot_common.window_stats([], [], 0.02) == []


def test_the_tracking_error_is_the_distance_to_the_goal_at_each_sample():
    # The robot at (0, 0), then (0.3, 0.4); the goal at (0.6, 0), then (0.3, 0):
    # 0.6 m, then 0.4 m (a 3-4-5 triangle has nothing to do with the second: x agrees).
    assert plot_common.distance([0.0, 0.3], [0.0, 0.4], [0.6, 0.3], [0.0, 0.0]) == [0.6, 0.4]


def test_a_constant_or_nan_column_is_not_worth_a_plot():
    assert not plot_common.varies([0.0] * 5)  # the kinematic plant's currents
    assert not plot_common.varies([6.1] * 5)  # its battery
    assert not plot_common.varies([float("nan")] * 3)  # the Lyapunov function with K_y = 0
    assert not plot_common.varies([])
    assert plot_common.varies([6.1, float("nan"), 6.0])


def test_the_plant_plots_skip_what_a_kinematic_plant_holds_constant(tmp_path):
    n = 200
    t = [k * 1e-3 for k in range(n)]
    table = {"wheel1_rad_s": [k * 0.01 for k in range(n)], "wheel2_rad_s": [k * 0.02 for k in range(n)],
             "duty1": [0.5] * n, "duty2": [0.4] * n, "dir1": [1.0] * n, "dir2": [1.0] * n,
             "ia1_A": [0.0] * n, "ia2_A": [0.0] * n}  # no vbatt_V column at all
    plotted, missing = plot_common.plant_plots(str(tmp_path), table, range(n), t, "t [s]", "sim.csv",
                                                   "no motors")
    assert plotted == ["wheel_speeds"]
    assert missing == [
        "Drive (duty and direction): duty1, duty2, dir1, dir2 in sim.csv never change (no motors)",
        "Motor currents: ia1_A, ia2_A in sim.csv never change (no motors)",
        "Battery voltage: sim.csv has no vbatt_V",
    ]
    assert sorted(os.listdir(tmp_path)) == ["wheel_speeds.png", "wheel_speeds.svg"]


def step(line, t_s, passed=True, kind="delay", text="{delay: 100ms}"):
    return {"line": line, "kind": kind, "step": text, "passed": passed, "t_s": t_s, "message": ""}


def test_steps_that_end_together_share_one_marker_red_if_one_failed():
    # write-serial and the expect-* steps after a wait take no AVR time: they
    # end when the step before them did.
    steps = [step(5, 0.1), step(6, 0.1), step(7, 1.1), step(8, 1.1, passed=False), step(9, 1.1000004)]
    assert plot_common.step_marks(steps) == [(0.1, "L5-6", True), (1.1, "L7-9", False)]
    assert plot_common.step_marks([]) == []


def test_expect_pose_targets_are_read_from_the_step_text():
    steps = [
        step(4, 0.1),
        step(7, 1.1, kind="expect-pose", text="{expect-pose: {source: truth, x_m: 0.3777, y_m: -0.0509, tol_m: 0.01}}"),
        step(8, 1.1, False, "expect-pose", "{expect-pose: {source: firmware, x_m: 5, y_m: 0, tol_m: 0.2}}"),
        step(9, 1.1, kind="expect-pose", text="{expect-pose: {x_m: 1e-1, y_m: -2}}"),  # defaults
    ]
    assert scenario_report.pose_targets(steps) == [
        ("truth", 0.3777, -0.0509, 0.01, True), ("firmware", 5.0, 0.0, 0.2, False), ("truth", 0.1, -2.0, 0.0, True)]


def test_each_output_folder_is_told_apart_by_its_files(tmp_path):
    def folder(name, files):
        d = tmp_path / name
        d.mkdir()
        for f, content in files.items():
            (d / f).write_text(json.dumps(content))
        return str(d)

    assert make_report.folder_kind(folder("run", {"summary.json": {"clock_hz": 16000000}})) == "run"
    assert make_report.folder_kind(folder("sim", {"summary.json": {"model": "ideal", "fidelity": []}})) == "sim"
    assert make_report.folder_kind(folder("suite", {"results.json": {}})) == "scenario"
    assert make_report.folder_kind(folder("one", {"result.json": {}})) == "scenario_result"
    assert make_report.folder_kind(folder("calib", {"calibration.json": {}})) == "other"
    assert make_report.folder_kind(folder("odd", {"summary.json": {"x": 1}})) == "other"
    assert make_report.main(["make_report.py", str(tmp_path / "calib")]) == 2


def test_the_suite_index_links_each_report_and_says_why_one_is_missing():
    results = {"passed": 1, "failed": 0, "errors": 1, "total": 2, "scenarios": [
        {"name": "a", "verdict": "pass", "message": "", "sim_seconds": 1.5},
        {"name": "b", "verdict": "firmware", "message": "crash | at 0x12", "sim_seconds": 0.25}]}
    lines = scenario_report.suite_lines(results, {"a": "/x/a/report.md"})
    assert lines[0] == "# ddmr-hil scenarios: 1 of 2 passed"
    assert "| a | PASS | 1.500 |  | [a/report.md](a/report.md) |" in lines
    assert "| b | ERROR | 0.250 | crash &#124; at 0x12 | no result.json in its folder |" in lines


def test_a_scenario_that_stopped_before_the_plant_ran_gets_a_report_without_plots(tmp_path):
    # A firmware crash at reset: truth.csv has its header only, uart.txt is empty.
    result = {"name": "crash", "file": "crash.yaml", "firmware": "crash.elf", "board": None, "verdict": "firmware",
              "exit_code": 3, "message": "crash.yaml:4: wait-serial failed at t=0.000010 s: invalid opcode",
              "sim_seconds": 1e-5, "cycles": 160, "clock_hz": 16000000, "seed": 1, "baud": 9600, "uart_bytes": 0,
              "framing_errors": 0, "steps_total": 2, "wiring_warnings": [],
              "steps": [step(4, 1e-5, False, "wait-serial", "{wait-serial: END}")]}
    (tmp_path / "result.json").write_text(json.dumps(result))
    (tmp_path / "truth.csv").write_text("t_s,x_m,y_m\n")
    (tmp_path / "uart.txt").write_text("")
    assert scenario_report.scenario_report(str(tmp_path)) == [str(tmp_path / "report.md")]
    md = (tmp_path / "report.md").read_text()
    assert md.startswith("# ddmr-hil scenario: crash (ERROR)\n")
    assert "| 4 | `{wait-serial: END}` | 0.000010 | **FAILED** |  |" in md
    assert "| | 1 more step(s) not run | | | |" in md
    assert "The firmware sent nothing (uart.txt is empty)." in md
    assert "## Not available\n\n- every plot: truth.csv is missing or has no rows" in md
    assert sorted(os.listdir(tmp_path)) == ["report.md", "result.json", "truth.csv", "uart.txt"]
