"""Run one model: the single helper behind sweeps, fits, benchmarks, examples and tests.

:func:`run_model` builds any registered model (or class) from plain parameters and a seed,
runs it to the end and returns its summary and, when asked, its robot counts over time and its
lifecycle events (what a macroscopic model is fitted to). It is
a top-level, picklable function so executors can run it in worker processes; :func:`run_one`
wraps it for sweeps (a failing run becomes a recorded failure, not a lost sweep).
"""

import os
import socket
import time
import traceback
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
import pandas as pd

from abm.pools import settle_worker_heap
from abm.registry import model_class

__all__ = ["LIFECYCLE_EVENTS", "RunResult", "RunSpec", "lifecycle_events", "run_model", "run_one"]

#: The events of a run's log a macroscopic model reads: the state changes, removals and
#: launches (what a sweep keeps in ``changes/`` when it keeps time series).
LIFECYCLE_EVENTS = ("state", "removed", "launch")


def lifecycle_events(events: pd.DataFrame) -> pd.DataFrame:
    """The rows of an event log a macroscopic model needs: ``time``, ``event``, ``robot``,
    ``state`` for every state change, removal and launch.
    """
    if events.empty:
        return pd.DataFrame(
            {"time": pd.Series(dtype=float), "event": pd.Series(dtype=str),
             "robot": pd.Series(dtype=np.int64), "state": pd.Series(dtype=object)}
        )  # fmt: skip
    kept = events[events["event"].isin(LIFECYCLE_EVENTS)]
    return pd.DataFrame(
        {
            "time": kept["time"].to_numpy(dtype=float),
            "event": kept["event"].to_numpy(dtype=object),
            "robot": kept["robot"].to_numpy(dtype=np.int64),
            "state": kept["state"].to_numpy(dtype=object) if "state" in kept else None,
        }
    )


@dataclass(frozen=True)
class RunResult:
    """What one run gives.

    Attributes:
        summary: the model's summary (flat dict).
        counts: robots per state after every change plus a last row at the run's end time
            (so a run's counts say how long it lasted), with a ``time`` column; None unless
            asked for.
        wall_time: seconds of wall time the run took.
        samples: the model's own time series (``SwarmModel.samples``) when asked for the
            counts and the model records one; else None.
        changes: the run's lifecycle events (:func:`lifecycle_events`) when asked for the
            counts; else None.

    """

    summary: dict
    counts: pd.DataFrame | None
    wall_time: float
    samples: pd.DataFrame | None = None
    changes: pd.DataFrame | None = None


def run_model(
    model: str | type,
    params: Mapping[str, object] | None = None,
    seed: int | None = None,
    *,
    counts: bool = False,
) -> RunResult:
    """Build ``model`` with ``params`` and ``seed``, run it to the end.

    Args:
        model: a registered model name, ``"module:Class"`` or a model class.
        params: constructor keywords (fields of the model's params).
        seed: the model's seed.
        counts: also return the state counts (and the model's samples) over time, and the
            lifecycle events.

    """
    start = time.perf_counter()
    instance = model_class(model)(seed=seed, **dict(params or {}))
    instance.run()
    summary = instance.summary()
    table = samples = changes = None
    if counts:
        changes = lifecycle_events(instance.events())
        table = instance.state_counts()
        end = table.iloc[[-1]].copy()
        end["time"] = float(instance.time)
        table = pd.concat([table, end], ignore_index=True)
        samples = instance.samples()
        samples = None if samples.empty else samples
    return RunResult(summary, table, time.perf_counter() - start, samples, changes)


@dataclass(frozen=True)
class RunSpec:
    """One run of a sweep: everything :func:`run_one` needs, picklable.

    Attributes:
        target: ``"module:Class"`` of the model.
        params: constructor keywords.
        rep: replication index within its grid point.
        seed: the model's seed.
        spawn_key: the ``SeedSequence`` spawn key the seed came from.
        run_id: the run's identity (a hash of its parameters and replication).
        time_series: also keep the run's state counts, samples and lifecycle events.

    """

    target: str
    params: dict
    rep: int
    seed: int
    spawn_key: tuple[int, int]
    run_id: str
    time_series: bool = False


def run_one(spec: RunSpec) -> dict:
    """Run one sweep run; never raises for the model's own errors.

    Returns:
        ``{"row": dict, "series": ..., "samples": ..., "changes": DataFrame | None}``. The row
        holds ``run_id``, ``rep``, ``seed``, ``spawn_key``, the parameters, the model's
        summary, ``status`` ("ok" or "failed"), ``error`` and ``traceback`` (failures only),
        ``wall_time`` (s) and ``worker`` (host:pid).

    """
    row = {
        "run_id": spec.run_id,
        "rep": spec.rep,
        "seed": spec.seed,
        "spawn_key": f"{spec.spawn_key[0]},{spec.spawn_key[1]}",
        **spec.params,
    }
    series = samples = changes = None
    settle_worker_heap()
    start = time.perf_counter()
    try:
        result = run_model(spec.target, _untraced(spec.params), spec.seed, counts=spec.time_series)
        summary = dict(result.summary)
        summary.pop("seed", None)
        row.update({k: _cell(v) for k, v in summary.items() if k not in spec.params})
        row.update(status="ok", error=None, traceback=None)
        if result.counts is not None:
            series = result.counts.assign(run_id=spec.run_id)
        if result.samples is not None:
            samples = result.samples.assign(run_id=spec.run_id)
        if result.changes is not None:
            changes = result.changes.assign(run_id=spec.run_id)
    except Exception as exc:  # a failing run is a result, not the end of the sweep
        if _interrupted(exc):
            raise KeyboardInterrupt from exc
        row.update(
            status="failed",
            error=f"{type(exc).__name__}: {exc}",
            traceback=traceback.format_exc(),
        )
    row["wall_time"] = time.perf_counter() - start
    row["worker"] = f"{socket.gethostname()}:{os.getpid()}"
    return {"row": row, "series": series, "samples": samples, "changes": changes}


def _untraced(params: Mapping[str, object]) -> dict:
    """A sweep run's constructor keywords: ``params`` with the position trace off unless they
    set ``trace_interval`` themselves.

    A sweep keeps each run's row, counts, samples and lifecycle events, never its positions
    (the trace is what ``abm render`` draws); sampling them made a beacon/explorer corridor
    run take 1.15x the CPU. No model's summary, events or counts read them
    (``tests/test_contract.py`` runs every model both ways).
    """
    return dict(params) if "trace_interval" in params else {**params, "trace_interval": None}


def _interrupted(exc: BaseException) -> bool:
    """True when a Ctrl-C caused ``exc``: a KeyboardInterrupt that surfaced as another error
    (numba reports one raised in its callbacks as a SystemError; SimPy re-raises copies).
    """
    seen = set()
    while exc is not None and id(exc) not in seen:
        if isinstance(exc, KeyboardInterrupt):
            return True
        seen.add(id(exc))
        exc = exc.__cause__ or exc.__context__
    return False


def _cell(value: object) -> object:
    """A summary value as a Parquet-friendly cell (numpy scalars unwrapped)."""
    return value.item() if isinstance(value, np.generic) else value
