"""Rate equations fitted to runs: one hazard per transition, its family chosen by held-out
likelihood, plus the launch schedule as a known source.

:func:`fit_rates` builds every run's exposure table (:mod:`analysis.macroscopic.design`),
then for each transition i -> j seen in the runs fits every candidate family
(:mod:`analysis.macroscopic.hazards`) on half of the runs and scores it on the other half
and the other way round (split by runs, never by bins of one run), keeps the family with the
highest held-out Poisson log-likelihood and refits it on all the runs given.
"""

import dataclasses
import math
from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np
import pandas as pd

from abm.errors import ConfigError
from analysis.macroscopic.design import covariate_names, exposure_table
from analysis.macroscopic.hazards import Hazard, candidate_families, fit_hazard, heldout_loglik
from analysis.macroscopic.logs import LAUNCH, RunLog, transitions

if TYPE_CHECKING:
    from analysis.macroscopic.compiled import CompiledRates

__all__ = ["LAUNCH_MODES", "RateModel", "Sources", "fit_rates", "select_family", "sources_of"]

#: How launches enter the macroscopic model: the launch times observed in the fitted runs, or
#: a constant rate per launch stream fitted between its first and last launch.
LAUNCH_MODES = ("observed", "rate")


@dataclass(frozen=True)
class RateModel:
    """A fitted macroscopic model: hazards, known sources and the covariates' mean paths.

    Attributes:
        states: the model's states, in its order.
        hazards: one fitted :class:`Hazard` per transition that is not a launch.
        schedules: per fitted run, its sources: ``time``, ``source`` (:data:`LAUNCH` for a
            robot that appears, else the state a scheduled launch takes it from), ``target``.
        launches: "observed" or "rate" (see :data:`LAUNCH_MODES`).
        streams: per (source, target) launch stream: ``rate`` (robots/s), ``first``, ``last``
            (s; the mean over runs), ``total`` (robots per run): the "rate" mode's sources.
        horizon: the longest fitted run (s).
        swarm_size: the most robots any fitted run had.
        covariate_times: grid (s) of ``covariate_paths``.
        covariate_paths: each covariate's mean over the fitted runs on that grid.
        bin_width: the exposure tables' grid (s).

    """

    states: tuple[str, ...]
    hazards: tuple[Hazard, ...]
    schedules: tuple[pd.DataFrame, ...]
    launches: str
    streams: pd.DataFrame
    horizon: float
    swarm_size: int
    covariate_times: np.ndarray
    covariate_paths: dict
    bin_width: float

    @cached_property
    def compiled(self) -> "CompiledRates":
        """The hazards and sources as arrays for the compiled mean-field ODE
        (:func:`analysis.macroscopic.compiled.compile_rates`), made once.
        """
        from analysis.macroscopic.compiled import compile_rates  # it imports this module

        return compile_rates(self)

    def covariates_at(self, t: float | np.ndarray) -> dict:
        """The covariates' mean values at time(s) ``t`` (the last grid value at or before)."""
        where = np.searchsorted(self.covariate_times, t, side="right") - 1
        where = np.clip(where, 0, max(len(self.covariate_times) - 1, 0))
        return {name: path[where] for name, path in self.covariate_paths.items()}

    def table(self) -> pd.DataFrame:
        """All fitted coefficients with standard errors and 95 % intervals (rates.csv)."""
        if not self.hazards:
            return pd.DataFrame()
        return pd.concat(
            [h.table().assign(score=h.score, events=h.events) for h in self.hazards],
            ignore_index=True,
        )


@dataclass(frozen=True)
class Sources:
    """The known sources of some runs: each run's launch schedule and the launch streams."""

    schedules: tuple[pd.DataFrame, ...]
    streams: pd.DataFrame


def sources_of(logs: Sequence[RunLog]) -> Sources:
    """The launch schedules of ``logs`` (robots that appear, scheduled moves) and their
    streams: the sources a rate model takes as known.
    """
    schedules = tuple(_schedule(log) for log in logs)
    return Sources(schedules, _streams(schedules))


def _schedule(log: RunLog) -> pd.DataFrame:
    moves = transitions(log)
    known = moves[(moves["source"] == LAUNCH) | moves["launch"].astype(bool)]
    return known[["time", "source", "target"]].reset_index(drop=True)


def _streams(schedules: Sequence[pd.DataFrame]) -> pd.DataFrame:
    rows = []
    both = pd.concat([s.assign(run=i) for i, s in enumerate(schedules)])
    for (source, target), group in both.groupby(["source", "target"], sort=True):
        per_run = group.groupby("run")["time"]
        first, last = float(per_run.min().mean()), float(per_run.max().mean())
        total = len(group) / len(schedules)
        rate = total / (last - first) if last > first else math.inf
        rows.append((source, target, rate, first, last, total))
    return pd.DataFrame(rows, columns=["source", "target", "rate", "first", "last", "total"])


def _covariate_paths(
    logs: Sequence[RunLog], names: Sequence[str], grid: np.ndarray
) -> dict[str, np.ndarray]:
    paths = {}
    for name in names:
        values = []
        for log in logs:
            samples = log.samples.sort_values("time", kind="stable")
            where = np.searchsorted(samples["time"].to_numpy(dtype=float), grid, side="right")
            column = samples[name].to_numpy(dtype=float)
            values.append(column[np.clip(where - 1, 0, len(column) - 1)])
        paths[name] = np.mean(values, axis=0)
    return paths


def select_family(
    tables: Sequence[pd.DataFrame],
    source: str,
    target: str,
    families: Sequence[str],
    horizon: float,
    effects: Sequence[str] = (),
) -> tuple[str, float]:
    """The family with the best two-fold held-out log-likelihood (per held-out run), runs
    split into even and odd (``tables``: one exposure table per run); ``effects`` as in
    :func:`~analysis.macroscopic.hazards.fit_hazard`.
    """
    folds = [
        (pd.concat(tables[0::2]), pd.concat(tables[1::2])),
        (pd.concat(tables[1::2]), pd.concat(tables[0::2])),
    ]
    best, best_score = "constant", -math.inf
    for family in families:
        score, scored = 0.0, 0
        for train, test in folds:
            rows_train = train[train["state"] == source]
            rows_test = test[test["state"] == source]
            if rows_train.empty or rows_test.empty:
                continue
            hazard = fit_hazard(rows_train, source, target, family, horizon, effects)
            if hazard is None:
                score = -math.inf
                break
            score += heldout_loglik(hazard, rows_test)
            scored += 1
        if scored and score > best_score:
            best, best_score = family, score
    return best, best_score / len(tables) if np.isfinite(best_score) else best_score


def fit_rates(
    logs: Sequence[RunLog], bin_width: float | None = None, launches: str = "observed"
) -> RateModel:
    """Fit the macroscopic rate model of ``logs`` (runs of one model and one condition).

    Args:
        logs: at least two runs (the families are chosen on runs held out from their fit).
        bin_width: the exposure grid (s); default the longest run / 200.
        launches: see :data:`LAUNCH_MODES`.

    Raises:
        ConfigError: fewer than two runs, an unknown launch mode or a bad bin width.

    """
    if len(logs) < 2:
        raise ConfigError(
            f"fit_rates needs at least 2 runs (families are chosen on held-out runs), got "
            f"{len(logs)}"
        )
    if launches not in LAUNCH_MODES:
        raise ConfigError(f"launches must be one of {LAUNCH_MODES}, got {launches!r}")
    horizon = max(log.end for log in logs)
    if bin_width is None:
        bin_width = horizon / 200
    if not (isinstance(bin_width, int | float) and 0 < bin_width <= horizon):
        raise ConfigError(f"bin_width must be in (0, {horizon:g}] s, got {bin_width!r}")
    states = logs[0].states
    names = covariate_names(logs)
    tables = [exposure_table(log, bin_width, names) for log in logs]
    every = pd.concat(tables, ignore_index=True)
    moves = pd.concat([transitions(log) for log in logs])
    hazard_moves = moves[(moves["source"] != LAUNCH) & ~moves["launch"].astype(bool)]
    hazards = []
    for (source, target), _ in hazard_moves.groupby(["source", "target"], sort=True):
        families = candidate_families(states, source, names)
        family, score = select_family(tables, source, target, families, horizon)
        rows = every[every["state"] == source]
        fitted = fit_hazard(rows, source, target, family, horizon)
        if fitted is None:  # the chosen family cannot be fitted to all runs together
            fitted = fit_hazard(rows, source, target, "constant", horizon)
        hazards.append(dataclasses.replace(fitted, score=score))
    sources = sources_of(logs)
    grid = np.arange(0.0, horizon + bin_width, bin_width)
    return RateModel(
        states=states,
        hazards=tuple(hazards),
        schedules=sources.schedules,
        launches=launches,
        streams=sources.streams,
        horizon=horizon,
        swarm_size=max(log.swarm_size for log in logs),
        covariate_times=grid,
        covariate_paths=_covariate_paths(logs, names, grid),
        bin_width=float(bin_width),
    )
