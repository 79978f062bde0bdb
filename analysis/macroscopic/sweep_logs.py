"""The run logs of a sweep folder: rate equations fitted to runs a sweep already made.

A sweep that keeps time series (``time_series = true``, or ``abm fit``'s own) keeps, per run,
its state counts (``series/``), its lifecycle events (``changes/``: state changes, removals,
launches) and the model's samples: exactly what :class:`~analysis.macroscopic.RunLog` holds
except positions (so the well-mixed diagnostic cannot be computed from a sweep).
"""

import json
from dataclasses import dataclass
from pathlib import Path

import pandas as pd

from abm.errors import ConfigError
from analysis.macroscopic.logs import RunLog, check_states, log_from_events
from analysis.sweep.storage import load_results, swept_keys

__all__ = ["SweepLogs", "sweep_logs"]

_NO_EVENTS = pd.DataFrame({"time": [], "event": [], "robot": [], "state": []})


@dataclass(frozen=True)
class SweepLogs:
    """A sweep's runs by condition.

    Attributes:
        target: the model ("module:Class").
        grid: each swept parameter and its values, in the sweep file's order.
        points: each condition's parameter values, in the order the sweep planned them.
        logs: each condition's run logs, by replication.
        seeds: each condition's seeds, by replication.
        run_ids: each condition's run ids, by replication.

    """

    target: str
    grid: dict[str, list]
    points: list[dict]
    logs: list[list[RunLog]]
    seeds: list[tuple[int, ...]]
    run_ids: list[tuple[str, ...]]


def sweep_logs(folder: str | Path) -> SweepLogs:
    """Read the finished runs of ``folder`` as run logs, grouped by condition.

    Raises:
        ConfigError: no finished run, or runs that kept no lifecycle events (a sweep without
            time series, or one made before sweeps kept them).

    """
    folder = Path(folder)
    summaries = load_results(folder, failed=False)
    if summaries.empty:
        raise ConfigError(f"{folder} holds no finished runs")
    changes = load_results(folder, changes=True)
    kept = set(changes["run_id"]) if not changes.empty else set()
    missing = sorted(set(summaries["run_id"]) - kept)
    if missing:
        raise ConfigError(
            f"{folder}: {len(missing)} of {len(summaries)} runs kept no state changes (a sweep "
            "without time_series = true, or made before sweeps kept them); run the sweep "
            "again into a new folder with time_series = true"
        )
    series = load_results(folder, series=True)
    samples = load_results(folder, samples=True)
    manifest = json.loads((folder / "sweep.json").read_text())
    conditions = swept_keys(manifest, summaries)
    grid = {k: list(dict.fromkeys(summaries[k].tolist())) for k in conditions}
    order = {k: {repr(v): i for i, v in enumerate(values)} for k, values in grid.items()}
    ranked = summaries.assign(
        _order=[tuple(order[k][repr(r[k])] for k in conditions) for _, r in summaries.iterrows()]
    ).sort_values(["_order", "rep"], kind="stable")
    # each run's rows, split once (not filtered out of the whole sweep once per run)
    by_run = {
        kind: dict(tuple(frame.groupby("run_id", sort=False))) if not frame.empty else {}
        for kind, frame in (("changes", changes), ("series", series), ("samples", samples))
    }
    points, logs, seeds, run_ids = [], [], [], []
    for _, group in ranked.groupby("_order", sort=True):
        first = group.iloc[0]
        points.append({k: first[k] for k in conditions})
        logs.append([_log(row, by_run) for _, row in group.iterrows()])
        seeds.append(tuple(int(s) for s in group["seed"]))
        run_ids.append(tuple(group["run_id"]))
    return SweepLogs(manifest["target"], grid, points, logs, seeds, run_ids)


def _log(row: pd.Series, by_run: dict[str, dict[str, pd.DataFrame]]) -> RunLog:
    rid = row["run_id"]
    counts = by_run["series"][rid].dropna(axis=1, how="all")
    states = check_states([c for c in counts.columns if c not in ("time", "run_id")])
    own = by_run["samples"].get(rid)
    if own is not None:
        own = own.drop(columns="run_id").dropna(axis=1, how="all")
        own = own if not own.empty else None
    events = by_run["changes"].get(rid, _NO_EVENTS)  # a run whose robots never changed state
    return log_from_events(
        events, states, row["time"], int(row["seed"]), samples=own, wall_time=row["wall_time"]
    )
