"""ANOVA that refuses what its design cannot support, with bootstrap intervals of its effects.

A two-way ANOVA (Stirling et al. 2010, Sect. 5) means something only when each factor varies,
the design matrix has full rank (no factor fixed by the others, e.g. the hierarchy's robot
total N = 1 + W + W S beside W and S), the response varies, and it varies within conditions
(else F is a ratio to zero). :func:`anova` checks each of these first and returns the one
condition that failed instead of a table; a warning numpy or statsmodels still raises is kept
as a note of the result, never printed.

Beside each p-value the effect size eta_sq (the share of the sum of squares) comes with a
95 % percentile bootstrap interval: runs resampled with replacement within each condition,
the type-II sums of squares recomputed by least squares (the same sums statsmodels gives);
none from conditions of fewer than :data:`MIN_BOOTSTRAP_RUNS` runs, whose resamples collapse.
"""

import warnings
from dataclasses import dataclass, field
from itertools import combinations

import numpy as np
import pandas as pd

from abm.errors import ConfigError

__all__ = ["Anova", "anova", "type2_sums"]

#: Bootstrap resamples of the effect sizes' intervals.
RESAMPLES = 1000
#: The fewest runs of a condition from which the bootstrap draws an interval: from two runs a
#: resample repeats one run in half the draws, leaving no spread within the condition, and the
#: interval collapses onto [eta_sq, 1].
MIN_BOOTSTRAP_RUNS = 5

#: A sum of squares this small beside the total is rounding, not variation.
_RELATIVE_ZERO = 1e-10


@dataclass(frozen=True)
class Anova:
    """One metric's ANOVA, or why it was not computed.

    Attributes:
        metric: the response column.
        factors: the factors in the model (those with more than one level).
        table: one row per source (each factor, their interaction, ``Residual``): ``sum_sq``,
            ``df``, ``F``, ``PR(>F)``, ``eta_sq`` and its bootstrap interval ``eta_sq_low``,
            ``eta_sq_high``; None when refused.
        reason: why it was not computed (None when it was).
        notes: what the reader must know (a factor left out, a warning numpy or statsmodels
            raised).

    """

    metric: str
    factors: tuple[str, ...]
    table: pd.DataFrame | None
    reason: str | None = None
    notes: tuple[str, ...] = field(default=())


def anova(
    df: pd.DataFrame,
    metric: str,
    factors: tuple[str, ...] | list[str],
    *,
    seed: int | None = 0,
    resamples: int = RESAMPLES,
) -> Anova:
    """Two-way (or one-way) ANOVA of ``metric`` over categorical ``factors``, type-II sums of
    squares (statsmodels OLS), or the reason it cannot be computed.

    Args:
        df: one row per run (failed runs and runs without ``metric`` are left out).
        metric: the response column.
        factors: the factor columns; those with one level are left out (with a note).
        seed: seed of the bootstrap of the effect sizes' intervals.
        resamples: bootstrap resamples (0: no intervals).

    Returns:
        An :class:`Anova`: the table, or ``reason`` naming the condition that failed.

    """
    from statsmodels.formula.api import ols
    from statsmodels.stats.anova import anova_lm

    runs = df[df["status"] == "ok"] if "status" in df else df
    missing = [c for c in (metric, *factors) if c not in runs.columns]
    if missing:
        raise ConfigError(f"column {missing[0]!r} is not in the results; have {list(df.columns)}")
    runs = runs.dropna(subset=[metric])
    notes = []
    flat = [f for f in factors if runs[f].nunique() <= 1]
    used = tuple(f for f in factors if f not in flat)
    if flat:
        notes.append(f"{', '.join(flat)} has one level in these runs: left out")
    y = runs[metric].astype(float).to_numpy()

    def refuse(reason: str) -> Anova:
        return Anova(metric, used, None, reason, tuple(notes))

    if not used:
        return refuse(f"no factor varies ({', '.join(factors)} each have one level)")
    if y.max() - y.min() <= _RELATIVE_ZERO * max(1.0, float(np.abs(y).max())):
        return refuse(f"{metric} is constant ({y[0]:g} in every run)")
    codes = [pd.factorize(runs[f], sort=True)[0] for f in used]
    terms = _terms(used)
    if not _full_rank(codes, terms):
        return refuse(_collinear(runs, used))
    cells = len(set(zip(*codes, strict=True)))
    columns = 1 + sum(_term_columns(codes, t).shape[1] for t in terms)
    if len(y) <= columns:
        return refuse(
            f"no residual degrees of freedom ({len(y)} runs for {columns} model terms): "
            "each condition needs a second run"
        )
    sums = type2_sums(y, codes, terms)
    total = float(((y - y.mean()) ** 2).sum())
    if sums["Residual"] <= _RELATIVE_ZERO * total:
        return refuse(
            f"{metric} does not vary within any condition ({cells} conditions, residual sum "
            "of squares 0): F would be a ratio to zero"
        )
    data = pd.DataFrame({"y": y, **{f"f{i}": c for i, c in enumerate(codes)}})
    formula = " + ".join(":".join(f"C(f{i})" for i in term) for term in terms)
    with warnings.catch_warnings(record=True) as caught, np.errstate(all="warn"):
        warnings.simplefilter("always")
        table = anova_lm(ols(f"y ~ {formula}", data=data).fit(), typ=2)
    for message in dict.fromkeys(f"{w.category.__name__}: {w.message}" for w in caught):
        notes.append(f"statsmodels warned: {message}")
    table.index = [_source(i, used) for i in table.index]
    table["eta_sq"] = table["sum_sq"] / table["sum_sq"].sum()
    fewest = int(pd.Series(list(zip(*codes, strict=True))).value_counts().min())
    if resamples > 0 and fewest < MIN_BOOTSTRAP_RUNS:
        notes.append(
            f"no bootstrap interval of eta_sq: a condition has {fewest} run(s), at least "
            f"{MIN_BOOTSTRAP_RUNS} needed (resamples of fewer collapse onto [eta_sq, 1])"
        )
        resamples = 0
    low, high = _bootstrap(y, codes, terms, used, seed, resamples)
    table["eta_sq_low"] = table.index.map(low)
    table["eta_sq_high"] = table.index.map(high)
    return Anova(metric, used, table, None, tuple(notes))


def _terms(used: tuple[str, ...]) -> list[tuple[int, ...]]:
    """Every main effect and interaction of the factors (by position)."""
    idx = range(len(used))
    return [t for k in range(1, len(used) + 1) for t in combinations(idx, k)]


def _source(name: str, used: tuple[str, ...]) -> str:
    """The source ``C(f0):C(f1)`` of statsmodels as ``launch_period:complexity``."""
    for i, factor in enumerate(used):
        name = name.replace(f"C(f{i})", factor)
    return name


def _term_columns(codes: list[np.ndarray], term: tuple[int, ...]) -> np.ndarray:
    """Treatment-coded columns of one term: products of its factors' dummy columns."""
    out = np.ones((len(codes[0]), 1))
    for i in term:
        levels = codes[i].max() + 1
        dummies = (codes[i][:, None] == np.arange(1, levels)[None, :]).astype(float)
        out = (out[:, :, None] * dummies[:, None, :]).reshape(len(out), -1)
    return out


def _design(codes: list[np.ndarray], terms: list[tuple[int, ...]]) -> np.ndarray:
    return np.hstack([np.ones((len(codes[0]), 1)), *(_term_columns(codes, t) for t in terms)])


def _full_rank(codes: list[np.ndarray], terms: list[tuple[int, ...]]) -> bool:
    """Whether the design matrix of the terms (main effects and interactions) has full rank."""
    x = _design(codes, terms)
    return int(np.linalg.matrix_rank(x)) == x.shape[1]


def _collinear(runs: pd.DataFrame, used: tuple[str, ...]) -> str:
    """Why the design matrix lacks full rank, in words: a factor fixed by another, or
    combinations of the factors that were never run.
    """
    for a, b in combinations(used, 2):
        for one, other in ((a, b), (b, a)):
            if (runs.groupby(one, observed=True)[other].nunique() <= 1).all():
                return (
                    f"{other} is fixed by {one} (each value of {one} comes with one value of "
                    f"{other}): the design matrix does not have full rank"
                )
    cells = len(runs.groupby(list(used), observed=True))
    every = int(np.prod([runs[f].nunique() for f in used]))
    return (
        f"only {cells} of the {every} combinations of {' x '.join(used)} were run: the design "
        "matrix does not have full rank"
    )


def type2_sums(y: np.ndarray, codes: list[np.ndarray], terms: list[tuple[int, ...]]) -> dict:
    """Type-II sums of squares by least squares: each term's against the model of every term
    that does not contain it; keys are the terms (tuples of factor positions) and
    ``"Residual"``.
    """
    cell, counts, projections = _cells(codes, terms)
    sums = np.bincount(cell, weights=y, minlength=len(counts))[None, :]
    out = _sums_of_squares(sums, float(y @ y), projections)
    return {k: float(v[0]) for k, v in out.items()}


def _cells(codes, terms):
    """Each run's condition, the runs per condition, and per model the projection that gives
    its fitted sum of squares from the conditions' sums (every model here is constant within a
    condition, so these few numbers are all least squares needs).
    """
    keys, cell = np.unique(np.column_stack(codes), axis=0, return_inverse=True)
    cell = cell.ravel()
    counts = np.bincount(cell).astype(float)
    per_cell = [keys[:, i] for i in range(keys.shape[1])]
    needed = [tuple(terms)]
    for term in terms:
        without = tuple(t for t in terms if not set(term) <= set(t))
        needed += [without, (*without, term)]
    models = {}
    for chosen in dict.fromkeys(needed):
        x = _design(per_cell, list(chosen))
        models[chosen] = x @ np.linalg.pinv(x.T @ (counts[:, None] * x)) @ x.T
    projections = {"terms": terms, "models": models}
    return cell, counts, projections


def _sums_of_squares(sums: np.ndarray, squares, projections) -> dict:
    """Type-II sums of squares for each row of condition sums (``sums``: resamples x
    conditions; ``squares``: sum of y^2 per resample).
    """
    terms, models = projections["terms"], projections["models"]

    def rss(chosen):
        return squares - np.einsum("rc,cd,rd->r", sums, models[tuple(chosen)], sums)

    out = {}
    for term in terms:
        without = tuple(t for t in terms if not set(term) <= set(t))
        out[term] = rss(without) - rss((*without, term))
    out["Residual"] = rss(terms)
    return out


def _bootstrap(y, codes, terms, used, seed, resamples) -> tuple[dict, dict]:
    """95 % percentile intervals of each source's eta_sq: runs resampled within conditions."""
    if resamples <= 0:
        return {}, {}
    rng = np.random.default_rng(seed)
    cell, counts, projections = _cells(codes, terms)
    groups = [np.flatnonzero(cell == c) for c in range(len(counts))]
    picks = np.concatenate(
        [g[rng.integers(0, len(g), size=(resamples, len(g)))] for g in groups], axis=1
    )
    values = y[picks]
    sums = np.stack([values[:, cell[picks[0]] == c].sum(axis=1) for c in range(len(counts))], 1)
    out = _sums_of_squares(sums, (values**2).sum(axis=1), projections)
    total = sum(out.values())
    names = [":".join(used[i] for i in t) for t in terms]
    with np.errstate(all="ignore"):
        draws = np.column_stack([out[t] / total for t in terms])
    low = dict(zip(names, np.nanpercentile(draws, 2.5, axis=0), strict=True))
    high = dict(zip(names, np.nanpercentile(draws, 97.5, axis=0), strict=True))
    return low, high
