"""From a run's event log to its state changes: the data every macroscopic model is built on.

A robot's life in the log is a sequence of ``state`` events (``Robot.set_state`` logs one per
change, the first when the robot appears) and, when it leaves the model, one ``removed`` event.
:func:`collect_runs` runs a model and keeps, per run, exactly what the rate equations need;
:func:`transitions` turns a run into one row per change of state.
"""

import time as _time
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from functools import cached_property

import numpy as np
import pandas as pd

from abm.errors import ConfigError
from abm.registry import model_class
from analysis.runner import LIFECYCLE_EVENTS, lifecycle_events

__all__ = [
    "LAUNCH",
    "LIFECYCLE_EVENTS",
    "REMOVED",
    "RunLog",
    "check_states",
    "collect_runs",
    "lifecycle_events",
    "log_from_events",
    "run_log",
    "stays",
    "transitions",
]

#: Pseudo-state a robot comes from when it appears in the model (a source of the state graph).
LAUNCH = "(launch)"
#: Pseudo-state a robot goes to when it is removed from the model (a sink of the state graph).
REMOVED = "(removed)"


@dataclass(frozen=True)
class RunLog:
    """What one run leaves for the macroscopic model.

    Attributes:
        run: the run's label (its seed unless given).
        states: the model's ``STATES`` in this run (``failed`` included when robots can fail).
        changes: the state changes: ``time`` (s), ``robot``, ``state`` (the state entered; the
            first row of a robot is its appearance) and ``launch`` (True when the model logged
            a ``launch`` event for that robot at that time, i.e. the change is a scheduled
            launch and not a hazard), plus removals as rows whose ``state`` is :data:`REMOVED`.
        end: the run's end time (s).
        samples: the model's own time series (``time`` plus metrics), or None.
        positions: sampled positions (time, robot, x, y, state), or None when the run kept
            none (``trace_interval=None``).
        wall_time: wall-clock seconds the run took.

    """

    run: object
    states: tuple[str, ...]
    changes: pd.DataFrame
    end: float
    samples: pd.DataFrame | None = None
    positions: pd.DataFrame | None = None
    wall_time: float = float("nan")

    @cached_property
    def moves(self) -> pd.DataFrame:
        """The run's transitions (see :func:`transitions`), computed once."""
        return _transitions(self.changes)

    @property
    def swarm_size(self) -> int:
        """Robots that ever appeared in the run."""
        return int(self.changes["robot"].nunique())


def check_states(states: Iterable[str], model: str = "this model") -> tuple[str, ...]:
    """The model's states, or a ConfigError when it has fewer than two (nothing changes state).

    A one-state model (flocking: every robot is ``flying``) has no transition to fit; what
    such a model can still be described by are counts it defines itself, e.g. robots per
    cluster or with a neighbour in range, recorded with ``recorder.sample``.
    """
    states = tuple(states)
    if len(states) < 2:
        raise ConfigError(
            f"{model} has {len(states)} state ({', '.join(states) or 'none'}): a macroscopic "
            "model needs robots that change state; count something that changes instead "
            "(e.g. robots per cluster or with a neighbour in range) as states of your own"
        )
    return states


def log_from_events(
    events: pd.DataFrame,
    states: Iterable[str],
    end: float,
    run: object,
    samples: pd.DataFrame | None = None,
    positions: pd.DataFrame | None = None,
    wall_time: float = float("nan"),
) -> RunLog:
    """The :class:`RunLog` of a run from its lifecycle events (:func:`lifecycle_events`: from a
    finished model, or read back from a sweep's ``changes/``).
    """
    kept = events[events["event"].isin(["state", "removed"])]
    changes = pd.DataFrame(
        {
            "time": kept["time"].to_numpy(dtype=float),
            "robot": kept["robot"].to_numpy(dtype=np.int64),
            "state": np.where(kept["event"] == "removed", REMOVED, kept["state"]),
        }
    )
    launches = events[events["event"] == "launch"]
    marks = set(
        zip(launches["time"].astype(float), launches["robot"].astype(np.int64), strict=True)
    )
    changes["launch"] = [
        (t, r) in marks for t, r in zip(changes["time"], changes["robot"], strict=True)
    ]
    return RunLog(
        run=run,
        states=tuple(states),
        changes=changes,
        end=float(end),
        samples=samples,
        positions=positions,
        wall_time=wall_time,
    )


def run_log(model: object, run: object = None, wall_time: float = float("nan")) -> RunLog:
    """The :class:`RunLog` of a finished model instance (any SwarmModel)."""
    states = check_states(model.STATES, type(model).__name__)
    samples = model.samples()
    positions = model.positions()
    return log_from_events(
        lifecycle_events(model.events()),
        states,
        model.time,
        model.seed if run is None else run,
        samples=None if samples.empty else samples,
        positions=None if positions.empty else positions[["time", "robot", "x", "y", "state"]],
        wall_time=wall_time,
    )


def collect_runs(
    model: str | type, seeds: Iterable[int], params: Mapping[str, object] | None = None
) -> list[RunLog]:
    """Run ``model`` once per seed with ``params`` and keep each run's :class:`RunLog`.

    Raises:
        ConfigError: the model has fewer than two states (checked before any run).

    """
    cls = model_class(model)
    check_states(cls.STATES, cls.__name__)
    logs = []
    for seed in seeds:
        start = _time.perf_counter()
        instance = cls(seed=seed, **dict(params or {}))
        instance.run()
        logs.append(run_log(instance, seed, _time.perf_counter() - start))
    return logs


def transitions(log: RunLog) -> pd.DataFrame:
    """One row per change of state of one run: ``robot``, ``time`` (s), ``source``, ``target``,
    ``dwell`` (s spent in ``source``) and ``launch``.

    A robot's appearance is a change from :data:`LAUNCH`; its removal a change to
    :data:`REMOVED`. Changes a robot makes at one instant (zero dwell) are merged into one,
    from the state it held before that instant to the one it holds after: a zero dwell is a
    relabelling by the model's code, not an event any hazard could produce.
    """
    return log.moves.copy()


def _transitions(changes: pd.DataFrame) -> pd.DataFrame:
    ordered = changes.sort_values(["robot", "time"], kind="stable")
    launched = ordered.groupby(["robot", "time"], sort=False)["launch"].transform("any")
    last = ordered.assign(launch=launched.astype(bool)).drop_duplicates(
        ["robot", "time"], keep="last"
    )
    by_robot = last.groupby("robot", sort=False)
    moves = pd.DataFrame(
        {
            "robot": last["robot"].to_numpy(),
            "time": last["time"].to_numpy(dtype=float),
            "source": by_robot["state"].shift().fillna(LAUNCH).to_numpy(),
            "target": last["state"].to_numpy(),
            "dwell": (last["time"] - by_robot["time"].shift()).to_numpy(dtype=float),
            "launch": last["launch"].to_numpy(dtype=bool),
        }
    )
    moves = moves[moves["source"] != moves["target"]]
    return moves.sort_values(["time", "robot"], kind="stable").reset_index(drop=True)


def stays(log: RunLog) -> pd.DataFrame:
    """One row per stay of a robot in a state of one run: ``robot``, ``state``, ``start`` and
    ``stop`` (s; the run's end for the stay a robot is in when the run ends).
    """
    moves = transitions(log)
    moves = moves[moves["target"] != REMOVED].sort_values(["robot", "time"], kind="stable")
    following = moves.groupby("robot")["time"].shift(-1)
    left = transitions(log)
    left = left[left["target"] == REMOVED].set_index("robot")["time"]
    stop = following.fillna(moves["robot"].map(left)).fillna(log.end)
    return pd.DataFrame(
        {
            "robot": moves["robot"].to_numpy(),
            "state": moves["target"].to_numpy(),
            "start": moves["time"].to_numpy(),
            "stop": stop.to_numpy(dtype=float),
        }
    )
