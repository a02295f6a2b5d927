"""HIL sessions over many plants, on this machine's cores or a Dask cluster
(docs/python.md, "Sweeps"). The implementation of ddmr_hil.sweep (the
command line is ddmr_hil/sweep.py).

    from ddmr_hil import sweep, grid, to_csv
    table = sweep(grid({"motor1.resistance_ohm": [5.0, 5.5, 6.0]}),
                  firmware="build/firmware/ddmr_tracking.elf", case=1)

Each plant is one task: a Session with that plant, run as its sketch
contract says (`case`) or for `seconds` of AVR time, then measured. Task k
is seeded from k alone (encoder seeds seed + 2k and seed + 2k + 1), and the
rows come back in task order, so the table does not depend on how many
workers ran it or in which order they finished: the same bytes serially
(`client="serial"`), on a LocalCluster, or on a cluster.

From a shell: python3 -m ddmr_hil.sweep --help
"""

from __future__ import annotations

import itertools
import json
import math
import os
import sys
import warnings
from dataclasses import dataclass
from typing import Any, Callable, Dict, Iterable, List, Optional, Sequence

from . import ConfigError, DdmrHilError, Session

# The columns every row has after the plant's keys.
RESULT_COLUMNS = ["exit_reason", "sim_s", "x_m", "y_m", "theta_rad"]


@dataclass(frozen=True)
class SweepSpec:
    """What every task of a sweep shares (picklable: it travels to workers)."""

    firmware: str
    board: Optional[str] = None
    world: Optional[str] = None
    contract: Optional[str] = None
    case: Optional[int] = None
    seconds: Optional[float] = None
    seed: int = 1
    instruments: bool = False
    measure: Optional[Callable[[Session], Dict[str, Any]]] = None


def nested(dotted: Dict[str, Any]) -> Dict[str, Any]:
    """{"motor1.resistance_ohm": 6} -> {"motor1": {"resistance_ohm": 6}}."""
    out: Dict[str, Any] = {}
    for key, value in dotted.items():
        node = out
        parts = key.split(".")
        for p in parts[:-1]:
            node = node.setdefault(p, {})
        node[parts[-1]] = value
    return out


def flatten(plant: Dict[str, Any], prefix: str = "") -> Dict[str, Any]:
    """{"motor1": {"resistance_ohm": 6}} -> {"motor1.resistance_ohm": 6}."""
    out: Dict[str, Any] = {}
    for key, value in plant.items():
        name = f"{prefix}{key}"
        if isinstance(value, dict):
            out.update(flatten(value, name + "."))
        else:
            out[name] = value
    return out


def grid(axes: Dict[str, Sequence[Any]]) -> List[Dict[str, Any]]:
    """Every combination of the axes' values (the last axis varies fastest),
    each as a plant overrides dict."""
    if not axes:
        raise ConfigError("grid: no axes")
    for key, values in axes.items():
        if len(values) == 0:
            raise ConfigError(f"grid: axis '{key}' has no values")
    keys = list(axes)
    return [nested(dict(zip(keys, combo))) for combo in itertools.product(*(axes[k] for k in keys))]


def run_task(spec: SweepSpec, index: int, plant: Dict[str, Any]) -> Dict[str, Any]:
    """One plant: a Session, its run, its row. Runs on a worker."""
    try:
        s = Session(
            firmware=spec.firmware,
            board=spec.board,
            world=spec.world,
            contract=spec.contract,
            plant=plant or None,
            seed=spec.seed + 2 * index,
            instruments=spec.instruments,
        )
    except DdmrHilError as e:
        raise ConfigError(f"plant {index} {json.dumps(plant, sort_keys=True)}: {e}") from None
    if spec.seconds is None:
        exit_reason = s.run_contract(spec.case)
    else:
        try:
            s.run_for(spec.seconds)
            exit_reason = "stopped"
        except DdmrHilError as e:  # the run ended early: that is this plant's result
            exit_reason = f"ended: {e}"
    pose = s.truth.pose()
    row: Dict[str, Any] = {"index": index}
    row.update(flatten(plant))
    row.update({"exit_reason": exit_reason, "sim_s": s.time_s, "x_m": pose.x_m, "y_m": pose.y_m,
                "theta_rad": pose.theta_rad})
    if spec.measure is not None:
        row.update(spec.measure(s))
    return row


def _columns(rows: List[Dict[str, Any]]) -> List[str]:
    cols: List[str] = []
    for r in rows:
        for k in r:
            if k not in cols:
                cols.append(k)
    return cols


def _table(rows: List[Dict[str, Any]]):
    """pandas.DataFrame when pandas is installed, else a numpy structured array."""
    cols = _columns(rows)
    try:
        import pandas as pd  # optional

        return pd.DataFrame([[r.get(c) for c in cols] for r in rows], columns=cols)
    except ImportError:
        import numpy as np

        def kind(c: str):
            values = [r.get(c) for r in rows]
            if all(isinstance(v, int) and not isinstance(v, bool) for v in values):
                return np.int64
            if all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in values):
                return np.float64
            return object

        dtype = np.dtype([(c, kind(c)) for c in cols])
        return np.array([tuple(r.get(c) for c in cols) for r in rows], dtype=dtype)


def to_csv(table) -> str:
    """The table as CSV text, numbers in repr form (shortest round trip):
    equal tables give equal bytes."""
    if hasattr(table, "to_dict"):  # pandas
        cols = list(table.columns)
        rows = table.to_dict("records")
    else:
        cols = list(table.dtype.names)
        rows = [dict(zip(cols, r)) for r in table.tolist()]

    def cell(v: Any) -> str:
        if v is None or (isinstance(v, float) and math.isnan(v)):
            return ""
        if isinstance(v, float):
            return repr(v)
        text = str(v)
        return '"' + text.replace('"', '""') + '"' if any(ch in text for ch in ',"\n') else text

    lines = [",".join(cols)] + [",".join(cell(r.get(c)) for c in cols) for r in rows]
    return "\n".join(lines) + "\n"


def _package_parent() -> str:
    return os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def sweep(
    plants: Iterable[Dict[str, Any]],
    firmware: str,
    board: Optional[str] = None,
    world: Optional[str] = None,
    contract: Optional[str] = None,
    case: Optional[int] = None,
    seconds: Optional[float] = None,
    seed: int = 1,
    instruments: bool = False,
    measure: Optional[Callable[[Session], Dict[str, Any]]] = None,
    client: Any = None,
    workers: Optional[int] = None,
    progress: bool = False,
):
    """Runs one HIL session per plant (a dict of plant overrides, as
    Session(plant=...) takes) and returns their rows as a table, in the
    plants' order: index, the plant's keys (dotted), exit_reason, sim_s and the
    end pose (x_m, y_m, theta_rad), then what `measure(session)` returns
    (a module-level function, so that it can travel to workers).

    client=None: a dask.distributed LocalCluster with `workers` processes
    (default: this machine's cores); a dask.distributed.Client: its cluster
    (every worker must import ddmr_hil and read the same firmware and files
    at the same paths); "serial": this process, one after the other."""
    plant_list = [dict(p) for p in plants]
    if not plant_list:
        raise ConfigError("sweep: no plants")
    if seconds is not None and not (seconds > 0 and math.isfinite(seconds)):
        raise ConfigError(f"sweep: seconds {seconds} must be a positive number")
    # Absolute paths: a worker's working folder may be another.
    spec = SweepSpec(os.path.abspath(firmware), _opt(board), _opt(world), _opt(contract), case, seconds, int(seed),
                     bool(instruments), measure)
    # Checked here, before any work is sent: the firmware, the files, every plant.
    for i, p in enumerate(plant_list):
        try:
            Session(firmware=spec.firmware, board=spec.board, world=spec.world, contract=spec.contract,
                    plant=p or None, instruments=False)
        except DdmrHilError as e:
            raise ConfigError(f"plant {i} {json.dumps(p, sort_keys=True, default=str)}: {e}") from None
    if client == "serial":
        rows = []
        for i, p in enumerate(plant_list):
            rows.append(run_task(spec, i, p))
            if progress:
                print(f"ddmr_hil.sweep: {i + 1}/{len(plant_list)} done", file=sys.stderr)
    elif client is None:
        rows = _on_local_cluster(spec, plant_list, workers, progress)
    else:
        rows = _on_client(client, spec, plant_list, progress)
    rows.sort(key=lambda r: r["index"])
    return _table(rows)


def _on_client(client, spec: SweepSpec, plants: List[Dict[str, Any]], progress: bool) -> List[Dict[str, Any]]:
    from dask.distributed import as_completed

    futures = client.map(run_task, [spec] * len(plants), range(len(plants)), plants, pure=False)
    rows = []
    for done, future in enumerate(as_completed(futures), start=1):
        rows.append(future.result())
        if progress:
            print(f"ddmr_hil.sweep: {done}/{len(plants)} done", file=sys.stderr)
    return rows


def _on_local_cluster(spec, plants, workers: Optional[int], progress: bool) -> List[Dict[str, Any]]:
    from dask.distributed import Client, LocalCluster

    n = workers or os.cpu_count() or 1
    # The workers are new processes: they find the package through PYTHONPATH
    # (set while they start, then as it was).
    saved = os.environ.get("PYTHONPATH")
    if _package_parent() not in (saved or "").split(os.pathsep):
        os.environ["PYTHONPATH"] = os.pathsep.join(p for p in [_package_parent(), saved] if p)
    try:
        with warnings.catch_warnings():
            # Debian 12's tornado 6.2 under Python 3.11, inside dask's LocalCluster:
            # "make_current is deprecated" is theirs, not the sweep's.
            warnings.filterwarnings("ignore", message="make_current is deprecated", category=DeprecationWarning)
            with LocalCluster(n_workers=n, threads_per_worker=1, processes=True, host="127.0.0.1",
                              dashboard_address=None) as cluster, Client(cluster) as client:
                return _on_client(client, spec, plants, progress)
    finally:
        if saved is None:
            os.environ.pop("PYTHONPATH", None)
        else:
            os.environ["PYTHONPATH"] = saved


def _opt(p) -> Optional[str]:
    return None if p is None else os.path.abspath(p)
