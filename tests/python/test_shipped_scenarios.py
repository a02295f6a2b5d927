"""tests/scenarios/ rewritten with the Python API: the same steps, the same
pinned numbers (each scenario file says where they come from). A scenario
without `seed:` runs with seed 1, as the scenario runner does."""

import csv
import json
import math
import subprocess

import pytest

from ddmr_hil import Session


def started(elf, case: bytes, seed=1) -> Session:
    """The sketch takes its case byte during setup()'s delay(5000)."""
    s = Session(firmware=elf, seed=seed)
    s.run_for(0.1)
    s.serial.write(case)
    return s


def firmware_pose(s):
    return s.var("Ex", "float").value, s.var("Ey", "float").value


def near(pose, x, y, tol):
    return math.hypot(pose[0] - x, pose[1] - y) <= tol


def no_x_line(s):
    """fail-serial "^X$": the sketch's answer to an unknown case byte never comes."""
    return b"X" not in s.serial.text.replace(b"\r", b"").split(b"\n")


@pytest.mark.parametrize(
    "case, title, count1, truth, firmware",
    [
        (b"1", "0.6m", 7000, (0.5350, -0.0443), (0.5347, -0.0218)),  # case1_converges.yaml
        (b"2", "0.4m", 3000, (0.3777, -0.0509), (0.3774, -0.0341)),  # case2_converges.yaml
    ],
)
def test_case_converges(reference_elf, case, title, count1, truth, firmware):
    s = started(reference_elf, case)
    s.run_until_serial(title, timeout_s=6)
    assert s.pin(12).level == 1 and s.pin(13).level == 1  # both motors forward
    s.run_until_serial("END", timeout_s=20)
    assert s.var("Count1", "int32").value >= count1
    if case == b"1":
        assert s.var("Count2", "int32").value >= 5000
    assert near(s.truth.pose(), *truth, 0.01)
    assert near(firmware_pose(s), *firmware, 0.01)
    assert no_x_line(s)


def test_push_recovery(reference_elf):
    s = started(reference_elf, b"1")
    s.run_until_serial("0.6m", timeout_s=6)
    s.run_for(6.0)
    s.push(dy_m=0.05)
    s.run_until_serial("END", timeout_s=20)
    assert near(firmware_pose(s), 0.5347, -0.0218, 0.01)  # the firmware does not see the push
    assert near(s.truth.pose(), 0.5350, 0.0057, 0.01)  # case 1's end + the push


def test_encoder_drop(reference_elf):
    s = started(reference_elf, b"1", seed=7)
    s.fault("inject", encoder=1, drop=0.05)
    s.run_until_serial("END", timeout_s=25)
    assert s.var("Count1", "int32").value > 7600
    assert near(s.truth.pose(), 0.1445, 0.4802, 0.02)
    assert near(firmware_pose(s), 0.5673, -0.0332, 0.01)  # it believes it is near the circle's end


@pytest.mark.parametrize("r_scale", [0.9, 1.0, 1.1])
def test_case1_completes_over_a_small_plant_matrix(reference_elf, r_scale):
    """Both motors' armature resistance within +-10 %: the firmware still
    completes its report, and the robot ends within 10 cm of the nominal end."""
    s = Session(firmware=reference_elf, instruments=False,
                plant={"motor1": {"resistance_ohm": 5.32 * r_scale}, "motor2": {"resistance_ohm": 5.41 * r_scale}})
    assert s.run_contract(case=1) == "report_complete"
    assert near(s.truth.pose(), 0.5350, -0.0443, 0.10)


def test_isr_latency_and_loop_timing(reference_elf):
    """isr_latency.yaml and loop_timing.yaml in one run: the loop profile
    starts with the case byte, as the scenario runner starts it."""
    s = Session(firmware=reference_elf, seed=1, profile=True)
    s.run_for(0.1)
    s.start_loop_profile()
    s.serial.write(b"1")
    s.run_until_serial("END", timeout_s=25)
    isr = s.isr_stats()
    v = {x["name"]: x for x in isr["vectors"]}
    for name, count in (("INT0", 7000), ("INT1", 5000)):
        assert v[name]["count"] >= count
        assert v[name]["latency"]["max_cycles"] <= 150
        assert v[name]["duration"]["max_cycles"] <= 120
    assert v["TIMER0_OVF"]["count"] >= 10000 and v["TIMER0_OVF"]["duration"]["max_cycles"] <= 120
    assert isr["races"]["torn_observed"] == 0
    loop = s.loop_profile()
    us = 1e6 / 16e6  # the Uno's 16 MHz
    quiet = loop[loop["eeprom_write"] == 0]
    assert 950 <= quiet["compute"].max() * us <= 1300
    assert 9900 <= quiet["period"].mean() * us <= 10300
    assert 3500 <= loop["compute"].max() * us <= 5000
    assert 12500 <= loop["period"].max() * us <= 14500
    assert (loop["period"] == loop["compute"] + loop["wait"]).all()
    assert (loop["start"][1:] == loop["end"][:-1]).all()


def test_eeprom_vs_sim(tmp_path, build_dir, source_dir, reference_elf):
    """eeprom_vs_sim.yaml: the EEPROM log against the host simulation
    (`ddmr-hil compare`) and against today's log, one count (4 mm) per axis."""
    s = started(reference_elf, b"1")
    s.run_until_serial("END", timeout_s=25)
    s.save_artifacts(tmp_path)
    subprocess.run([str(build_dir / "ddmr-hil"), "compare", str(tmp_path)], check=True, stdout=subprocess.DEVNULL)
    log_vs_sim = json.loads((tmp_path / "compare.json").read_text())["pairs"]["log_vs_sim"]
    assert log_vs_sim["rms_m"] <= 0.03 and log_vs_sim["endpoint_m"] <= 0.05
    with open(tmp_path / "eeprom_log.csv") as now, open(source_dir / "tests/scenarios/golden/case1_eeprom_log.csv") as gold:
        rows, golden = list(csv.DictReader(now)), list(csv.DictReader(gold))
    assert len(rows) == len(golden)
    for a, b in zip(rows, golden):
        assert abs(float(a["x_m"]) - float(b["x_m"])) <= 0.0057 and abs(float(a["y_m"]) - float(b["y_m"])) <= 0.0057
