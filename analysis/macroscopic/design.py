"""Binned exposure tables: the data a Poisson regression of transition counts is fitted to.

A run's time is cut into bins: a regular grid of ``bin_width`` seconds refined at every change
of any state count, so that within a bin every count is constant. For each bin and each state
i held by at least one robot the table holds the robot-time spent in i (the exposure
``n_i * width``), the counts of every state, the model's recorded covariates at the bin's
middle, and the number of hazard transitions i -> j that ended a stay in i during the bin.
With a per-robot hazard lambda_ij that is constant within a bin, those numbers are Poisson
with mean ``exposure * lambda_ij``: the likelihood of the continuous-time chain, exactly.
"""

from collections.abc import Sequence

import numpy as np
import pandas as pd

from analysis.macroscopic.logs import LAUNCH, REMOVED, RunLog, transitions

__all__ = ["count_columns", "counts_at", "covariate_names", "exposure_table"]


def count_columns(states: Sequence[str]) -> list[str]:
    """Column holding the count of each state in an exposure table."""
    return [f"n:{s}" for s in states]


def covariate_names(logs: Sequence[RunLog]) -> list[str]:
    """Numeric sample columns every run recorded (candidates for a covariate hazard)."""
    names = None
    for log in logs:
        if log.samples is None:
            return []
        numeric = [
            c
            for c in log.samples.columns
            if c != "time" and pd.api.types.is_numeric_dtype(log.samples[c])
        ]
        names = numeric if names is None else [c for c in names if c in numeric]
    return names or []


def _count_steps(log: RunLog) -> tuple[np.ndarray, np.ndarray, pd.DataFrame]:
    """Times at which counts change and the counts after each (rows), plus the transitions."""
    moves = transitions(log)
    index = {s: k for k, s in enumerate(log.states)}
    times = np.unique(moves["time"].to_numpy(dtype=float))
    delta = np.zeros((len(times), len(log.states)))
    row = np.searchsorted(times, moves["time"].to_numpy(dtype=float))
    for state, sign in (("source", -1.0), ("target", 1.0)):
        cols = moves[state].map(index)
        known = cols.notna().to_numpy()
        np.add.at(delta, (row[known], cols[known].to_numpy(dtype=int)), sign)
    return times, np.cumsum(delta, axis=0), moves


def counts_at(log: RunLog, grid: np.ndarray) -> np.ndarray:
    """Robots per state at each time of ``grid`` (after the changes at that time), shape
    ``(len(grid), len(states))``.
    """
    times, counts, _ = _count_steps(log)
    where = np.searchsorted(times, grid, side="right") - 1
    out = np.zeros((len(grid), len(log.states)))
    out[where >= 0] = counts[where[where >= 0]]
    return out


def _sampled(samples: pd.DataFrame, names: Sequence[str], at: np.ndarray) -> np.ndarray:
    """The last recorded value of each covariate at or before ``at`` (the first one before)."""
    samples = samples.sort_values("time", kind="stable")
    where = np.searchsorted(samples["time"].to_numpy(dtype=float), at, side="right") - 1
    values = samples[list(names)].to_numpy(dtype=float)
    return values[np.clip(where, 0, len(values) - 1)]


def exposure_table(log: RunLog, bin_width: float, covariates: Sequence[str] = ()) -> pd.DataFrame:
    """The run's bins, one row per (bin, state held): see the module's docstring.

    Columns: ``run``, ``start``, ``stop``, ``time`` (bin middle, s), ``state`` (the source i),
    ``exposure`` (robot-s in i), ``n:<k>`` (robots in each state k), the covariates by name,
    and ``to:<j>`` (hazard transitions i -> j ending in the bin, for every state j and
    :data:`REMOVED`). Scheduled launches are not hazards and are left out of ``to:<j>``.
    """
    times, counts, moves = _count_steps(log)
    grid = np.arange(0.0, log.end, bin_width)
    edges = np.unique(np.concatenate([[0.0], grid, times, [log.end]]))
    edges = edges[(edges >= 0) & (edges <= log.end)]
    start, stop = edges[:-1], edges[1:]
    where = np.searchsorted(times, start, side="right") - 1
    held = np.zeros((len(start), len(log.states)))
    held[where >= 0] = counts[where[where >= 0]]
    middle = (start + stop) / 2
    hazards = moves[(moves["source"] != LAUNCH) & ~moves["launch"].astype(bool)]
    # A transition at time t ends the bin whose stop is t.
    ending = np.searchsorted(stop, hazards["time"].to_numpy(dtype=float), side="left")
    targets = [*log.states, REMOVED]
    frames = []
    for k, state in enumerate(log.states):
        keep = held[:, k] > 0
        frame = pd.DataFrame(
            {
                "run": log.run,
                "start": start[keep],
                "stop": stop[keep],
                "time": middle[keep],
                "state": state,
                "exposure": held[keep, k] * (stop[keep] - start[keep]),
            }
        )
        for col, values in zip(count_columns(log.states), held[keep].T, strict=True):
            frame[col] = values
        if covariates:
            frame[list(covariates)] = _sampled(log.samples, covariates, middle[keep])
        mine = (hazards["source"] == state).to_numpy()
        for target in targets:
            if target == state:
                continue
            hits = np.bincount(
                ending[mine & (hazards["target"] == target).to_numpy()], minlength=len(start)
            )
            frame[f"to:{target}"] = hits[keep]
        frames.append(frame)
    return pd.concat(frames, ignore_index=True)
