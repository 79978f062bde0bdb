"""Checks of a fitted macroscopic model on runs it has not seen.

- RMSD per state: the root mean square, over an even time grid, of the difference between
  the held-out runs' mean count and the mean-field prediction, divided by the swarm size N
  (the most robots any held-out run had): a share of the swarm.
- Band coverage per state: the share of (held-out run, grid time) points whose count lies
  inside the stochastic model's 90 % band (pointwise; a calibrated band gives ~0.9).
- Speed ratio: the held-out agent runs' wall time over the macroscopic prediction's (the
  mean-field solve from the fitted model, after the compiled integrator's one-time load, the
  fastest of ``ODE_REPEATS``; the stochastic band's ratio apart), both measured in this
  process.

A held-out run that ended before the grid's last time keeps its final counts (the run is
over; its robots stay where they are), as the sweeps' count tables do. That is exact for a
run that ended because nothing could change any more, and an assumption for one its model
stopped by a rule of its own.
"""

import time
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd

from analysis.macroscopic.design import counts_at
from analysis.macroscopic.logs import RunLog
from analysis.macroscopic.meanfield import Band, expected_counts, simulate_counts
from analysis.macroscopic.rates import RateModel

__all__ = ["GRID_POINTS", "ODE_REPEATS", "Checks", "check_heldout", "observed_counts"]

#: Points of the even time grid the checks compare on (ours).
GRID_POINTS = 201
#: Mean-field solves timed; the fastest counts (on a shared machine a job of a millisecond is
#: often preempted for longer than it runs).
ODE_REPEATS = 5


@dataclass(frozen=True)
class Checks:
    """The held-out checks of one fitted model.

    Attributes:
        table: one row per state: ``occupied`` (a held-out run or the ODE ever puts a robot
            in it; the other columns are NaN when not: checks of zeros), ``rmsd`` (share of
            the swarm), ``rmsd_robots``, ``noise`` (share of the swarm: the root mean square
            standard error of the held-out mean itself, the RMSD a perfect model would still
            show with this few runs; NaN from one held-out run), ``band_coverage`` (share of
            points inside the 90 % band).
        rmsd_max: the worst state's ``rmsd``.
        band_coverage: share of all (run, time, state) points inside the band, over the
            states that ever hold a robot (held out or predicted): a state no robot enters
            lies inside any band and would only pad the share.
        swarm_size: N.
        agent_seconds: wall time of the held-out agent runs (s).
        ode_seconds: wall time of the mean-field prediction (s).
        band_seconds: wall time of the stochastic band (s).
        expected: the mean-field prediction (time plus one column per state).
        band: the stochastic band.
        observed: the held-out runs' counts on the grid (run, time, state).

    """

    table: pd.DataFrame
    rmsd_max: float
    band_coverage: float
    swarm_size: int
    agent_seconds: float
    ode_seconds: float
    band_seconds: float
    expected: pd.DataFrame
    band: Band
    observed: np.ndarray

    @property
    def speed_ratio(self) -> float:
        """Agent runs' wall time / mean-field prediction time."""
        return self.agent_seconds / self.ode_seconds

    @property
    def band_speed_ratio(self) -> float:
        """Agent runs' wall time / stochastic band time."""
        return self.agent_seconds / self.band_seconds


def observed_counts(logs: Sequence[RunLog], grid: np.ndarray) -> np.ndarray:
    """Counts of each run on ``grid``: shape (run, time, state)."""
    return np.stack([counts_at(log, grid) for log in logs])


def check_heldout(
    model: RateModel,
    logs: Sequence[RunLog],
    rng: np.random.Generator,
    replicates: int = 200,
) -> Checks:
    """Check ``model`` on held-out ``logs`` (see the module's docstring)."""
    horizon = max(log.end for log in logs)
    grid = np.linspace(0.0, horizon, GRID_POINTS)
    observed = observed_counts(logs, grid)
    expected_counts(model, grid[:2])  # the compiled integrator's one-time load, not timed
    ode_seconds = np.inf
    for _ in range(ODE_REPEATS):  # a millisecond's work: the fastest of a few, as timeit does
        start = time.perf_counter()
        expected = expected_counts(model, grid)
        ode_seconds = min(ode_seconds, time.perf_counter() - start)
    start = time.perf_counter()
    band = simulate_counts(model, grid, replicates, rng)
    band_seconds = time.perf_counter() - start
    size = max(log.swarm_size for log in logs)
    states = list(model.states)
    error = observed.mean(axis=0) - expected[states].to_numpy()
    rmsd = np.sqrt((error**2).mean(axis=0))
    noise = (
        np.sqrt((observed.var(axis=0, ddof=1) / len(logs)).mean(axis=0))
        if len(logs) > 1
        else np.full(len(states), np.nan)
    )
    low, high = band.low[states].to_numpy(), band.high[states].to_numpy()
    inside = (observed >= low - 1e-9) & (observed <= high + 1e-9)
    # a state no held-out run and not the ODE ever occupies fits "perfectly" whatever the
    # rates: its checks would be statistics of zeros, so they are left empty
    visited = (observed.max(axis=(0, 1)) > 0) | (expected[states].to_numpy().max(axis=0) > 0)
    table = pd.DataFrame(
        {
            "state": states,
            "occupied": visited,
            "rmsd": np.where(visited, rmsd / size, np.nan),
            "rmsd_robots": np.where(visited, rmsd, np.nan),
            "noise": np.where(visited, noise / size, np.nan),
            "band_coverage": np.where(visited, inside.mean(axis=(0, 1)), np.nan),
        }
    )
    return Checks(
        table=table,
        rmsd_max=float(table["rmsd"].max()),
        band_coverage=float(inside[:, :, visited].mean()),
        swarm_size=size,
        agent_seconds=float(sum(log.wall_time for log in logs)),
        ode_seconds=ode_seconds,
        band_seconds=band_seconds,
        expected=expected,
        band=band,
        observed=observed,
    )
