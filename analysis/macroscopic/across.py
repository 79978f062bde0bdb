"""Rate equations across parameters: one hazard per transition whose log-rate moves with the
swept parameters, fitted on some conditions of a grid and predicting the others.

A fit of one condition (:func:`analysis.macroscopic.fit_rates`) says nothing about a condition
it has not seen. Here every transition's hazard gets, beside its family's terms, one
log-linear *effect* per swept parameter (:mod:`analysis.macroscopic.hazards`), fitted to the
exposure tables of all fitted conditions at once (one Poisson GLM), the way the stigmergy paper
regresses its recurrence's rates on the pheromone radius and the map's entropy:

    log lambda_ij(condition) = (family's terms) + sum_p g_p x_p

A numeric parameter whose fitted values are all positive enters as its logarithm, so the
rate is a power law of it (``lambda ~ value ** g``: a rate proportional to a speed or inverse
to a period is exactly of this form, and no positive parameter can drive it negative); one
that takes zero or negative values enters as it is. Either is then standardised over the
fitted conditions (``x = (v - mean) / sd``). A categorical parameter enters as 0/1 columns of
its levels beside the first. Families are chosen as
for one condition, by held-out likelihood over runs split in two, among those whose terms do
not change with the condition: constant, counts of another state, time. A recorded covariate
(coverage, ...) and the piecewise family are left out: their path or pieces belong to one
condition's runs, not to the parameters.

At a condition (:meth:`AcrossModel.at`) the effects fold into the intercepts, and the launch
schedule is a known source taken from that condition's runs (the parameters set it: a launch
period, a swarm size); every transition rate is predicted.
"""

import dataclasses
import numbers
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd

from abm.errors import ConfigError
from analysis.macroscopic.design import exposure_table
from analysis.macroscopic.hazards import Hazard, candidate_families, fit_hazard
from analysis.macroscopic.logs import LAUNCH, RunLog, transitions
from analysis.macroscopic.rates import RateModel, select_family, sources_of

__all__ = ["AcrossModel", "fit_across", "numeric_values"]

#: The hazard families whose terms mean the same in every condition.
FAMILIES_ACROSS = ("constant", "counts", "time")


@dataclass(frozen=True)
class AcrossModel:
    """Hazards fitted across conditions, with the effects of the swept parameters.

    Attributes:
        states: the model's states.
        hazards: one hazard per transition, its last coefficients the parameters' effects.
        numeric: per numeric parameter: whether it enters as its log, then the mean and sd of
            what enters, over the fitted conditions.
        levels: per categorical parameter, its levels (the first is the baseline).
        conditions: the fitted conditions, one dict of parameter values each.
        horizon: the longest fitted run (s).
        bin_width: the exposure tables' grid (s).

    """

    states: tuple[str, ...]
    hazards: tuple[Hazard, ...]
    numeric: dict[str, tuple[bool, float, float]]
    levels: dict[str, tuple[object, ...]]
    conditions: tuple[dict, ...]
    horizon: float
    bin_width: float

    def effect_values(self, condition: Mapping[str, object]) -> dict[str, float]:
        """The effect columns' values at ``condition``.

        Raises:
            ConfigError: a categorical level the fit never saw (it has no effect to use).

        """
        values = {}
        for name, (log, mean, sd) in self.numeric.items():
            value = float(condition[name])
            if log and value <= 0:
                raise ConfigError(
                    f"{name}={value:g}: the fit took the log of {name} (all its fitted values "
                    "were positive) and cannot predict at a value <= 0"
                )
            values[f"x:{name}"] = ((np.log(value) if log else value) - mean) / sd
        for name, levels in self.levels.items():
            if condition[name] not in levels:
                raise ConfigError(
                    f"{name}={condition[name]!r} was not among the fitted conditions' levels "
                    f"({', '.join(map(repr, levels))}): its effect cannot be predicted"
                )
            for level in levels[1:]:
                values[f"x:{name}={level}"] = float(condition[name] == level)
        return values

    def at(self, condition: Mapping[str, object], logs: Sequence[RunLog]) -> RateModel:
        """The rate model predicted at ``condition``, its launches the known sources of
        ``logs`` (that condition's runs).
        """
        values = self.effect_values(condition)
        sources = sources_of(logs)
        horizon = max(log.end for log in logs)
        return RateModel(
            states=self.states,
            hazards=tuple(h.at(values) for h in self.hazards),
            schedules=sources.schedules,
            launches="observed",
            streams=sources.streams,
            horizon=horizon,
            swarm_size=max(log.swarm_size for log in logs),
            covariate_times=np.array([0.0]),
            covariate_paths={},
            bin_width=self.bin_width,
        )

    def table(self) -> pd.DataFrame:
        """Every coefficient, parameter effects included, with standard errors and 95 %
        intervals (``rates_across.csv``).
        """
        return pd.concat(
            [h.table().assign(score=h.score, events=h.events) for h in self.hazards],
            ignore_index=True,
        )


def numeric_values(values: Sequence[object]) -> bool:
    """True when every value is a real number (numpy's included), not a truth value."""
    return all(isinstance(v, numbers.Real) and not isinstance(v, bool | np.bool_) for v in values)


def _effect_columns(
    conditions: Sequence[Mapping[str, object]], names: Sequence[str]
) -> tuple[dict[str, tuple[bool, float, float]], dict[str, tuple[object, ...]]]:
    """Numeric parameters (log or not, mean, sd) and categorical levels among ``names`` that
    vary over the fitted conditions; a parameter held at one value has no effect to fit.
    """
    numeric, levels = {}, {}
    for name in names:
        values = [c[name] for c in conditions]
        if len({repr(v) for v in values}) < 2:
            continue
        if numeric_values(values):
            array = np.asarray(values, dtype=float)
            log = bool((array > 0).all())
            array = np.log(array) if log else array
            numeric[name] = (log, float(array.mean()), float(array.std()))
        else:
            levels[name] = tuple(dict.fromkeys(values))
    return numeric, levels


def fit_across(
    runs: Sequence[tuple[Mapping[str, object], Sequence[RunLog]]],
    swept: Sequence[str],
    bin_width: float | None = None,
) -> AcrossModel:
    """Fit hazards with the effects of the ``swept`` parameters to the runs of several
    conditions.

    Args:
        runs: per fitted condition, its parameter values and its runs (at least two runs in
            all; the families are chosen on runs held out from their fit).
        swept: the parameters whose effects are fitted.
        bin_width: the exposure grid (s); default the longest run / 200.

    Raises:
        ConfigError: fewer than two fitted conditions, or no swept parameter that varies
            among them.

    """
    if len(runs) < 2:
        raise ConfigError(
            f"rates across parameters need at least 2 fitted conditions, got {len(runs)}"
        )
    conditions = tuple(dict(c) for c, _ in runs)
    numeric, levels = _effect_columns(conditions, swept)
    if not numeric and not levels:
        raise ConfigError(
            f"none of the swept parameters ({', '.join(swept)}) varies over the fitted "
            "conditions: nothing to fit across"
        )
    logs = [log for _, group in runs for log in group]
    horizon = max(log.end for log in logs)
    bin_width = horizon / 200 if bin_width is None else bin_width
    model = AcrossModel(logs[0].states, (), numeric, levels, conditions, horizon, float(bin_width))
    tables = []
    for condition, group in runs:
        values = model.effect_values(condition)
        for log in group:
            tables.append(exposure_table(log, bin_width).assign(**values))
    # a state no robot of a run ever entered has no count or transition column there: 0
    counted = sorted({c for t in tables for c in t.columns if c.startswith(("to:", "n:"))})
    tables = [t.assign(**{c: 0.0 for c in counted if c not in t}) for t in tables]
    every = pd.concat(tables, ignore_index=True)
    effects = sorted(c for c in every.columns if c.startswith("x:"))
    moves = pd.concat([transitions(log) for log in logs])
    hazard_moves = moves[(moves["source"] != LAUNCH) & ~moves["launch"].astype(bool)]
    hazards = []
    for (source, target), _ in hazard_moves.groupby(["source", "target"], sort=True):
        families = [
            f
            for f in candidate_families(model.states, source, covariates=())
            if f.split(":")[0] in FAMILIES_ACROSS
        ]
        family, score = select_family(tables, source, target, families, horizon, effects)
        rows = every[every["state"] == source]
        fitted = fit_hazard(rows, source, target, family, horizon, effects)
        if fitted is None:
            fitted = fit_hazard(rows, source, target, "constant", horizon, effects)
        if fitted is None:
            raise ConfigError(
                f"the transition {source} -> {target} cannot be fitted across the conditions "
                "(too few transitions, or parameters that move together)"
            )
        hazards.append(dataclasses.replace(fitted, score=score))
    return AcrossModel(
        model.states, tuple(hazards), numeric, levels, conditions, horizon, float(bin_width)
    )
