"""Statistics of sweep results (tidy DataFrames, one row per run), for any model.

The analyses of Stirling et al. (2010), with the factors and metrics named by the caller (the
report takes them from the model's layout): two-way ANOVA over swept factors (refusing what
the design cannot support, :mod:`analysis.anova`), Pearson's r of condition means with a
bootstrap interval, percent-change tables between two values of a factor, and the optimal value of
a factor (Sect. 5: cubic interpolations of the condition means of some metrics, each
normalised to [0, 1], summed with weights; the value at the minimum).
"""

from collections.abc import Mapping, Sequence

import numpy as np
import pandas as pd

from abm.errors import ConfigError
from analysis.anova import RESAMPLES, Anova, anova

__all__ = [
    "Anova",
    "ok_runs",
    "condition_means",
    "anova",
    "pearson",
    "percent_change",
    "percent_change_table",
    "optimal_period",
]


def ok_runs(df: pd.DataFrame) -> pd.DataFrame:
    """Only the runs that finished (drops rows whose ``status`` is "failed")."""
    if "status" in df:
        return df[df["status"] == "ok"]
    return df


def _check_columns(df: pd.DataFrame, columns: Sequence[str]) -> None:
    missing = [c for c in columns if c not in df.columns]
    if missing:
        raise ConfigError(f"column {missing[0]!r} is not in the results; have {list(df.columns)}")


def condition_means(df: pd.DataFrame, metrics: Sequence[str], by: Sequence[str]) -> pd.DataFrame:
    """Mean, standard error and count of each metric per condition (tidy: one row each)."""
    by = [b for b in by if b in df.columns]
    _check_columns(df, list(metrics))
    runs = ok_runs(df)
    long = runs.melt(id_vars=by, value_vars=list(metrics), var_name="metric")
    long["value"] = long["value"].astype(float)
    grouped = long.groupby([*by, "metric"], observed=True)["value"]
    return grouped.agg(mean="mean", sem="sem", n="count").reset_index()


def pearson(
    df: pd.DataFrame,
    x: str,
    y: str,
    by: Sequence[str],
    *,
    seed: int | None = 0,
    resamples: int = RESAMPLES,
) -> dict:
    """Pearson's r between the condition means of ``x`` and ``y`` (conditions: values of ``by``).

    Returns:
        ``{"r", "p", "df", "n", "r_low", "r_high", "reason"}``: ``r_low``/``r_high`` the 95 %
        percentile bootstrap interval of r (runs resampled within their conditions, the means
        and r recomputed; seeded by ``seed``); ``reason`` says why r was not computed (fewer
        than 3 conditions, or a constant mean), else None.

    """
    from scipy.stats import pearsonr

    runs = ok_runs(df)
    by = [b for b in by if b in runs.columns and runs[b].nunique() > 0]
    _check_columns(runs, [x, y])
    runs = runs.dropna(subset=[x, y])
    means = (
        runs.groupby(by, observed=True)[[x, y]].mean() if by else runs[[x, y]].mean().to_frame().T
    )
    n = len(means)
    out = {"r": float("nan"), "p": float("nan"), "df": max(n - 2, 0), "n": n,
           "r_low": float("nan"), "r_high": float("nan"), "reason": None}  # fmt: skip
    if n < 3:
        return {**out, "reason": f"{n} conditions: r needs at least 3"}
    for column in (x, y):
        if means[column].nunique() < 2:
            return {**out, "reason": f"the mean of {column} is the same in every condition"}
    r, p = pearsonr(means[x].astype(float), means[y].astype(float))
    low, high = _pearson_interval(runs, x, y, by, seed, resamples)
    return {**out, "r": float(r), "p": float(p), "r_low": low, "r_high": high}


def _pearson_interval(runs, x, y, by, seed, resamples) -> tuple[float, float]:
    """95 % percentile bootstrap interval of the r of condition means."""
    if resamples <= 0 or not by:
        return float("nan"), float("nan")
    rng = np.random.default_rng(seed)
    groups = [part[[x, y]].to_numpy(float) for _, part in runs.groupby(by, observed=True)]
    draws = np.empty(resamples)
    for k in range(resamples):
        means = np.array([g[rng.integers(0, len(g), len(g))].mean(axis=0) for g in groups])
        with np.errstate(all="ignore"):
            draws[k] = np.corrcoef(means[:, 0], means[:, 1])[0, 1]
    if np.isnan(draws).all():
        return float("nan"), float("nan")
    return float(np.nanpercentile(draws, 2.5)), float(np.nanpercentile(draws, 97.5))


def percent_change(
    df: pd.DataFrame,
    metric: str,
    baseline: float,
    compare: float,
    factor: str,
    by: str | None = None,
) -> pd.DataFrame:
    """Change of the mean of ``metric`` from ``factor == baseline`` to ``factor == compare``.

    Returns:
        One row per level of ``by``: ``baseline_mean``, ``compare_mean``, ``change`` (%, i.e.
        100 (compare - baseline) / baseline), ``n_baseline``, ``n_compare``. Empty when either
        level is missing.

    """
    runs = ok_runs(df)
    _check_columns(runs, [metric, factor])
    groups = runs.groupby(by, observed=True) if by and by in runs else [(None, runs)]
    rows = []
    for level, part in groups:
        a = part.loc[np.isclose(part[factor].astype(float), baseline), metric].astype(float)
        b = part.loc[np.isclose(part[factor].astype(float), compare), metric].astype(float)
        if a.empty or b.empty:
            continue
        change = 100.0 * (b.mean() - a.mean()) / a.mean() if a.mean() != 0 else float("nan")
        rows.append(
            {
                **({by: level} if by else {}),
                "metric": metric,
                factor: f"{baseline:g} -> {compare:g}",
                "baseline_mean": a.mean(),
                "compare_mean": b.mean(),
                "change": change,
                "n_baseline": len(a),
                "n_compare": len(b),
            }
        )
    return pd.DataFrame(rows)


def percent_change_table(
    df: pd.DataFrame,
    pairs: Sequence[tuple[float, float]],
    metrics: Sequence[str],
    factor: str,
    by: str | None = None,
) -> pd.DataFrame:
    """:func:`percent_change` for every (baseline, compare) pair and metric, stacked."""
    frames = [percent_change(df, m, a, b, factor, by) for a, b in pairs for m in metrics if m in df]
    frames = [f for f in frames if not f.empty]
    return pd.concat(frames, ignore_index=True) if frames else pd.DataFrame()


def optimal_period(
    df: pd.DataFrame,
    weights: Mapping[str, float],
    factor: str,
    by: str | None = None,
    resolution: float = 0.05,
) -> pd.DataFrame:
    """The paper's optimal inter-launch period per ``by`` level (Sect. 5).

    Each metric's condition means are interpolated over ``factor`` with a cubic spline (lower
    order with fewer than 4 periods), normalised to [0, 1] over the sampled range, weighted
    and summed; the optimum is the period at the minimum of the sum.

    Args:
        df: sweep results.
        weights: metric -> relative weight (the paper: coverage time, collisions and total
            energy, equally). Weights must be >= 0 and not all zero.
        factor: the swept period column.
        by: one optimum per level of this column (None: one for all runs).
        resolution: spacing of the interpolation grid (s).

    Returns:
        One row per level: ``optimal_period`` (s), ``score`` (the weighted sum there) and the
        weights used.

    """
    from scipy.interpolate import make_interp_spline

    weights = dict(weights)
    for name, w in weights.items():
        if isinstance(w, bool) or not isinstance(w, int | float) or w < 0:
            raise ConfigError(f"weight of {name!r} must be a number >= 0, got {w!r}")
    if sum(weights.values()) <= 0:
        raise ConfigError(f"weights must not all be zero, got {weights!r}")
    runs = ok_runs(df)
    _check_columns(runs, [factor, *weights])
    groups = runs.groupby(by, observed=True) if by and by in runs else [(None, runs)]
    rows = []
    for level, part in groups:
        means = part.groupby(factor)[list(weights)].mean().sort_index()
        periods = means.index.to_numpy(dtype=float)
        if len(periods) < 2:
            continue
        grid = np.arange(periods[0], periods[-1] + resolution / 2, resolution)
        total = np.zeros_like(grid)
        for name, w in weights.items():
            k = min(3, len(periods) - 1)
            curve = make_interp_spline(periods, means[name].to_numpy(float), k=k)(grid)
            span = curve.max() - curve.min()
            flat = span <= 1e-9 * max(1.0, np.abs(curve).max())  # constant up to rounding
            total += w * (np.zeros_like(curve) if flat else (curve - curve.min()) / span)
        best = int(np.argmin(total))
        rows.append(
            {
                **({by: level} if by else {}),
                "optimal_period": float(grid[best]),
                "score": float(total[best] / sum(weights.values())),
                "weights": ", ".join(f"{k}={v:g}" for k, v in weights.items()),
            }
        )
    return pd.DataFrame(rows)
