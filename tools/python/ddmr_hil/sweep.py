"""python3 -m ddmr_hil.sweep: HIL sessions over plant variations from a shell
(docs/python.md, "Sweeps"). In Python, ddmr_hil.sweep(...) is the function
(ddmr_hil/_sweep.py); this module is callable as that function too, so that
`import ddmr_hil.sweep` does not take it away."""

from __future__ import annotations

import argparse
import os
import sys
import types
from typing import Any, Dict, List, Optional

from . import ConfigError, DdmrHilError
from ._sweep import flatten, grid, nested, sweep, to_csv  # noqa: F401  (re-exported)


def _parse_grid(specs: List[str]) -> Dict[str, List[float]]:
    axes: Dict[str, List[float]] = {}
    for s in specs:
        key, sep, values = s.partition("=")
        if not sep or not key or not values:
            raise ConfigError(f"--grid '{s}': expected KEY=V1,V2,... (motor1.resistance_ohm=5,5.5,6)")
        try:
            axes[key] = [float(v) for v in values.split(",")]
        except ValueError:
            raise ConfigError(f"--grid '{s}': the values must be numbers") from None
    return axes


def _read_plants(path: str) -> List[Dict[str, Any]]:
    import yaml

    try:
        with open(path, encoding="utf-8") as f:
            data = yaml.safe_load(f)
    except OSError as e:
        raise ConfigError(f"--plants {path}: {e.strerror}") from None
    except yaml.YAMLError as e:
        raise ConfigError(f"--plants {path}: not YAML: {e}") from None
    if not isinstance(data, list) or not all(isinstance(p, dict) for p in data):
        raise ConfigError(f"--plants {path}: expected a list of plant overrides ({{motor1: {{resistance_ohm: 6}}}})")
    return data


def main(argv: Optional[List[str]] = None) -> int:
    ap = argparse.ArgumentParser(prog="python3 -m ddmr_hil.sweep",
                                 description="HIL sessions over plant variations, on local cores or a Dask cluster "
                                             "(docs/python.md).")
    ap.add_argument("--firmware", required=True, help="the ELF")
    ap.add_argument("--board", help="board file (docs/boards.md)")
    ap.add_argument("--world", help="world file (docs/world.md)")
    ap.add_argument("--contract", help="sketch contract (default: the reference ELF's own)")
    how = ap.add_mutually_exclusive_group()
    how.add_argument("--case", type=int, help="run the contract with this case (default: its first)")
    how.add_argument("--seconds", type=float, help="run this much AVR time instead of the contract")
    what = ap.add_mutually_exclusive_group(required=True)
    what.add_argument("--plants", help="YAML or JSON file: a list of plant overrides")
    what.add_argument("--grid", action="append", metavar="KEY=V1,V2", help="an axis of a grid (repeatable)")
    where = ap.add_mutually_exclusive_group()
    where.add_argument("--scheduler", help="a running Dask scheduler's address (tcp://host:8786)")
    where.add_argument("--workers", type=int, help="local worker processes (default: the cores)")
    where.add_argument("--serial", action="store_true", help="run in this process, one after the other")
    ap.add_argument("--seed", type=int, default=1, help="task k's encoder seeds are seed + 2k, seed + 2k + 1")
    ap.add_argument("--out", required=True, help="the results CSV (written whole or not at all)")
    ap.add_argument("--quiet", action="store_true", help="no progress lines")
    a = ap.parse_args(argv)
    try:
        plants = _read_plants(a.plants) if a.plants else grid(_parse_grid(a.grid))
        client: Any = "serial" if a.serial else None
        if a.scheduler:
            from dask.distributed import Client

            client = Client(a.scheduler)
        table = sweep(plants, a.firmware, board=a.board, world=a.world, contract=a.contract, case=a.case,
                      seconds=a.seconds, seed=a.seed, client=client, workers=a.workers, progress=not a.quiet)
        text = to_csv(table)
        tmp = a.out + ".partial"
        with open(tmp, "w", encoding="utf-8") as f:
            f.write(text)
        os.replace(tmp, a.out)
    except DdmrHilError as e:
        print(f"ddmr_hil.sweep: {e}", file=sys.stderr)
        return 2
    except OSError as e:
        where = f"{e.filename}: " if e.filename else ""
        print(f"ddmr_hil.sweep: {where}{e.strerror or e}", file=sys.stderr)
        return 2
    print(f"ddmr_hil.sweep: {len(plants)} plants -> {a.out}", file=sys.stderr)
    return 0


class _CallableModule(types.ModuleType):
    def __call__(self, *args, **kwargs):
        return sweep(*args, **kwargs)


sys.modules[__name__].__class__ = _CallableModule

if __name__ == "__main__":
    sys.exit(main())
