"""The pytest plugin (ddmr_hil.pytest_plugin): the `hil` fixture from
--hil-* options and markers, artifacts kept for failed tests, and the same
artifacts serially and under pytest-xdist (-n 2)."""

import filecmp
import pathlib

pytest_plugins = ["pytester"]

CONFTEST = 'pytest_plugins = ["ddmr_hil.pytest_plugin"]\n'


def test_the_fixture_the_marker_and_a_failed_tests_artifacts(pytester, reference_elf):
    pytester.makeconftest(CONFTEST)
    pytester.makepyfile(
        """
        import pytest

        def test_boots(hil):
            hil.run_for(0.1)
            assert hil.time_s > 0.099

        @pytest.mark.hil(plant={"motor1": {"resistance_ohm": 6.0}}, seed=7)
        def test_fails_on_purpose(hil):
            hil.run_for(0.05)
            assert hil.time_s > 1.0, "on purpose"
        """
    )
    r = pytester.runpytest(f"--hil-firmware={reference_elf}", "--junitxml=junit.xml")
    r.assert_outcomes(passed=1, failed=1)
    r.stdout.fnmatch_lines(["*ddmr-hil artifacts*", "*hil-test_fails_on_purpose*(exit reason: stopped)*"])
    junit = (pytester.path / "junit.xml").read_text()
    assert 'name="hil_artifacts"' in junit
    folder = pathlib.Path(junit.split('name="hil_artifacts" value="')[1].split('"')[0])
    assert (folder / "uart.txt").exists() and (folder / "summary.json").exists()
    assert '"plant_file": "(embedded defaults) + overrides"' in (folder / "summary.json").read_text()


def test_the_entry_point_loads_the_plugin_without_a_conftest(pytester, reference_elf):
    pytester.makepyfile("def test_x(hil):\n    hil.run_for(0.01)\n")
    r = pytester.runpytest_subprocess(f"--hil-firmware={reference_elf}")
    r.assert_outcomes(passed=1)


def test_without_a_firmware_the_fixture_says_how_to_give_one(pytester):
    pytester.makeconftest(CONFTEST)
    pytester.makepyfile("def test_x(hil):\n    pass\n")
    r = pytester.runpytest()
    assert r.ret != 0
    r.stdout.fnmatch_lines(["*--hil-firmware ELF, --hil-sketch INO or @pytest.mark.hil(firmware=...)*"])


def test_xdist_gives_the_serial_runs_files(pytester, reference_elf, monkeypatch):
    pytester.makeconftest(CONFTEST)
    # Each test saves its artifacts under OUT/<r>: compare the two runs' files.
    pytester.makepyfile(
        test_save="""
        import os
        import pytest

        def plant(r):
            return pytest.param(r, marks=pytest.mark.hil(plant={"motor1": {"resistance_ohm": r}}))

        @pytest.mark.parametrize("r", [plant(5.0), plant(6.0), plant(7.0), plant(8.0)])
        def test_save(hil, r):
            hil.run_for(5.1)
            hil.serial.write(b"1")
            hil.run_for(0.3)
            hil.save_artifacts(os.path.join(os.environ["OUT"], str(r)))
        """
    )
    monkeypatch.setenv("OUT", str(pytester.path / "serial"))
    serial = pytester.runpytest_subprocess(f"--hil-firmware={reference_elf}", "test_save.py")
    serial.assert_outcomes(passed=4)
    monkeypatch.setenv("OUT", str(pytester.path / "xdist"))
    xdist = pytester.runpytest_subprocess(f"--hil-firmware={reference_elf}", "-n", "2", "test_save.py")
    xdist.assert_outcomes(passed=4)
    for r in ["5.0", "6.0", "7.0", "8.0"]:
        a, b = pytester.path / "serial" / r, pytester.path / "xdist" / r
        for name in ["uart.txt", "truth.csv", "eeprom.bin", "isr.json"]:
            assert filecmp.cmp(a / name, b / name, shallow=False), f"{r}/{name}"
