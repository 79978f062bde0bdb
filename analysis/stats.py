"""Statistics of sweep results (tidy DataFrames, one row per run), for any model.

The analyses of Stirling et al. (2010), with the factors and metrics named by the caller (the
report takes them from the model's layout): two-way ANOVA over swept factors, Pearson's r of
condition means, percent-change tables between two values of a factor, and the optimal value of
a factor (Sect. 5: cubic interpolations of the condition means of some metrics, each
normalised to [0, 1], summed with weights; the value at the minimum).
"""

from collections.abc import Mapping, Sequence

import numpy as np
import pandas as pd

from abm.errors import ConfigError

__all__ = [
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


def anova(df: pd.DataFrame, metric: str, factors: Sequence[str], typ: int = 2) -> pd.DataFrame:
    """Two-way ANOVA (statsmodels OLS, type ``typ`` sums of squares) of ``metric``.

    Factors with a single level in ``df`` are left out (a one-way ANOVA remains).

    Returns:
        One row per source (each factor, their interaction, Residual): ``sum_sq``, ``df``,
        ``F``, ``PR(>F)`` and ``eta_sq`` (share of the total sum of squares).

    """
    from statsmodels.formula.api import ols
    from statsmodels.stats.anova import anova_lm

    runs = ok_runs(df)
    _check_columns(runs, [metric, *factors])
    used = [f for f in factors if runs[f].nunique() > 1]
    if not used or len(runs) <= runs.groupby(used).ngroups:
        return pd.DataFrame(columns=["sum_sq", "df", "F", "PR(>F)", "eta_sq"])
    data = runs[[metric, *used]].astype({metric: float}).rename(columns={metric: "y"})
    terms = " * ".join(f"C({f})" for f in used)
    fit = ols(f"y ~ {terms}", data=data).fit()
    table = anova_lm(fit, typ=typ)
    table["eta_sq"] = table["sum_sq"] / table["sum_sq"].sum()
    table.index = [i.replace("C(", "").replace(")", "") for i in table.index]
    return table


def pearson(df: pd.DataFrame, x: str, y: str, by: Sequence[str]) -> dict:
    """Pearson's r between the condition means of ``x`` and ``y`` (conditions: values of ``by``).

    Returns:
        ``{"r", "p", "df", "n"}``; r and p are NaN with fewer than 3 conditions.

    """
    from scipy.stats import pearsonr

    runs = ok_runs(df)
    by = [b for b in by if b in runs.columns and runs[b].nunique() > 0]
    _check_columns(runs, [x, y])
    means = (
        runs.groupby(by, observed=True)[[x, y]].mean() if by else runs[[x, y]].mean().to_frame().T
    )
    n = len(means)
    if n < 3 or means[x].nunique() < 2 or means[y].nunique() < 2:
        return {"r": float("nan"), "p": float("nan"), "df": max(n - 2, 0), "n": n}
    r, p = pearsonr(means[x].astype(float), means[y].astype(float))
    return {"r": float(r), "p": float(p), "df": n - 2, "n": n}


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
