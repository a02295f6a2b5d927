"""`cmake --install` puts the package, its module and its pytest entry point
under <prefix>/lib/python3/dist-packages, importable from there alone."""

import subprocess
import sys


def test_the_installed_package_imports_and_registers_its_pytest_plugin(tmp_path, build_dir):
    subprocess.run(["cmake", "--install", str(build_dir), "--prefix", str(tmp_path)], check=True,
                   stdout=subprocess.DEVNULL)
    site = tmp_path / "lib" / "python3" / "dist-packages"
    probe = (
        "import importlib.metadata as m, ddmr_hil, ddmr_hil.sweep, ddmr_hil.pytest_plugin;"
        "print(ddmr_hil.__file__);"
        "print([e.value for e in m.entry_points(group='pytest11') if e.name.startswith('ddmr_hil')])"
    )
    r = subprocess.run([sys.executable, "-c", probe], env={"PYTHONPATH": str(site)}, capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert r.stdout.splitlines() == [str(site / "ddmr_hil" / "__init__.py"), "['ddmr_hil.pytest_plugin']"]
