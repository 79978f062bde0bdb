"""Right-censored summary metrics: which runs a run's end cut short, and the Kaplan-Meier
median of what they say.

A model declares the metrics its runs' ends can censor (``CENSORED``, a sequence of
:class:`abm.published.Censored`); a time to reach a target from a run cut by the time limit
is only a lower bound, and the mean of such values is not the mean time. Reports show the
share of censored runs and the Kaplan-Meier median (or ">= the largest bound" when fewer than
half the runs reached the target), and judge no claim from censored values.
"""

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd

from abm.published import Censored

__all__ = ["Survival", "censored_mask", "censoring_causes", "ended_by", "km_median", "survival"]


def ended_by(runs: pd.DataFrame, ends: Sequence[str]) -> pd.Series:
    """True for the runs whose ``end_reason`` starts with one of ``ends`` (all False without
    an ``end_reason`` column or without ends).
    """
    if not ends or "end_reason" not in runs:
        return pd.Series(False, index=runs.index)
    return runs["end_reason"].fillna("").astype(str).str.startswith(tuple(ends))


def censored_mask(runs: pd.DataFrame, spec: Censored) -> pd.Series:
    """True for the runs whose ``spec.metric`` is censored: ended by one of ``spec.ends``,
    or (with ``spec.bound``) missing the metric.
    """
    mask = ended_by(runs, spec.ends)
    if spec.bound is not None and spec.metric in runs:
        mask |= runs[spec.metric].isna()
    return mask


def censoring_causes(runs: pd.DataFrame, spec: Censored) -> str:
    """Why ``runs``' censored values of ``spec.metric`` are censored, in words: "2 ended by
    time limit; 3 never reached it" (a run that reached its own end without the target is
    censored by its end, not by a time limit).
    """
    by_end = ended_by(runs, spec.ends)
    unreached = pd.Series(False, index=runs.index)
    if spec.bound is not None and spec.metric in runs:
        unreached = runs[spec.metric].isna() & ~by_end
    parts = []
    if by_end.any():
        parts.append(f"{int(by_end.sum())} ended by {' or '.join(spec.ends)}")
    if unreached.any():
        parts.append(f"{int(unreached.sum())} never reached it before their end")
    return "; ".join(parts)


def _values(runs: pd.DataFrame, spec: Censored) -> np.ndarray:
    """Each run's value of the metric, or its lower bound where the metric is missing."""
    if spec.metric in runs:
        values = runs[spec.metric].astype(float)
    else:
        values = pd.Series(np.nan, index=runs.index)
    if spec.bound is not None and spec.bound in runs:
        bound = runs[spec.bound].astype(float)
        if spec.since is not None and spec.since in runs:
            bound = bound - runs[spec.since].astype(float)
        values = values.fillna(bound)
    return np.asarray(values, dtype=float)


def km_median(values: Sequence[float], observed: Sequence[bool]) -> float | None:
    """The Kaplan-Meier median of right-censored ``values`` (``observed`` False: censored):
    the smallest value at which the estimated survival falls to 0.5 or below; None when it
    never does (fewer than half the runs reached the target before their bound).
    """
    t = np.asarray(values, dtype=float)
    d = np.asarray(observed, dtype=bool)
    keep = ~np.isnan(t)
    t, d = t[keep], d[keep]
    survival = 1.0
    for time in np.unique(t[d]):
        at_risk = np.sum(t >= time)
        events = np.sum((t == time) & d)
        survival *= 1.0 - events / at_risk
        if survival <= 0.5 + 1e-12:
            return float(time)
    return None


@dataclass(frozen=True)
class Survival:
    """A censored metric over some runs.

    Attributes:
        runs: the runs with a value or a bound.
        censored: how many of them are censored.
        median: the Kaplan-Meier median, or None when it is not reached.
        bound: the largest censored bound (the median is at least this when not reached).

    """

    runs: int
    censored: int
    median: float | None
    bound: float | None

    @property
    def share(self) -> float:
        """The share of censored runs (0-1)."""
        return self.censored / self.runs if self.runs else 0.0

    def text(self) -> str:
        """E.g. "KM median 512 (3 of 10 runs censored)" or "KM median >= 600 (...)"."""
        median = f"{self.median:.4g}" if self.median is not None else f">= {self.bound:.4g}"
        return f"KM median {median} ({self.censored} of {self.runs} runs censored)"


def survival(runs: pd.DataFrame, spec: Censored) -> Survival:
    """The censoring of ``spec.metric`` over ``runs`` and its Kaplan-Meier median."""
    values = _values(runs, spec)
    censored = np.asarray(censored_mask(runs, spec), dtype=bool)
    keep = ~np.isnan(values)
    values, censored = values[keep], censored[keep]
    bound = float(values[censored].max()) if censored.any() else None
    return Survival(len(values), int(censored.sum()), km_median(values, ~censored), bound)
