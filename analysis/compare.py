"""Published numbers beside ours: each :class:`abm.published.Published` record computed on a
sweep's runs, with whether the direction agrees.
"""

from collections.abc import Sequence

import numpy as np
import pandas as pd

from abm.published import Published
from analysis import stats

__all__ = ["NOT_IN_SWEEP", "compare_published", "fault_free"]

NOT_IN_SWEEP = "not in this sweep"
_TEXT = {
    "reference": "reference level",
    "rises": "rises from the previous",
    "falls": "falls from the previous",
    "at least": "at least {threshold:g}",
    "same sign": "same sign",
    "decreases": "decreases",
    "increases": "increases",
    "above 1": "ratio > 1",
    "below 1": "ratio < 1",
    "positive": "r > 0",
    "negative": "r < 0",
    "minimum inside": "minimum inside the range",
}


def compare_published(df: pd.DataFrame, records: Sequence[Published]) -> pd.DataFrame:
    """Every published record beside ours for the same condition.

    Returns:
        Columns section, quantity, condition, published, ours, runs, check, direction agrees
        ("yes", "no", "(reference)" or "not in this sweep"), source.

    """
    previous: dict = {}
    rows = []
    for item in records:
        ours, n, agrees = _ours(item, df, previous)
        if isinstance(item.value, str):
            published = item.value
        elif item.kind == "change":
            published = f"{item.value:+.1f}"
        else:
            published = f"{item.value:g}"
        rows.append(
            {
                "section": item.section,
                "quantity": item.quantity,
                "condition": _condition_text(item),
                "published": published,
                "ours": ours,
                "runs": n,
                "check": _TEXT[item.check].format(threshold=item.threshold or 0.0),
                "direction agrees": agrees,
                "source": item.source,
            }
        )
    return pd.DataFrame(rows)


#: The keywords whose non-default values inject faults (the papers' numbers have none).
_FAULT_SWITCHES = ("fault_rate", "fault_times", "link_outage_rate", "loss_burst_rate",
                   "sensor_fault_rate")  # fmt: skip


def _select(df: pd.DataFrame, condition: dict) -> pd.DataFrame:
    """The finished runs of ``condition``; runs with faults injected only if the condition
    itself names a fault keyword (a paper's number is compared with fault-free runs).
    """
    runs = fault_free(stats.ok_runs(df), keep=condition)
    for key, value in condition.items():
        if key not in runs:
            return runs.iloc[0:0]
        runs = runs[_equal(runs[key], value)]
    return runs


def fault_free(runs: pd.DataFrame, keep: Sequence[str] = ()) -> pd.DataFrame:
    """The runs without injected faults (:mod:`abm.faults`), judged on every fault keyword
    except those in ``keep`` (e.g. a condition that names one itself).
    """
    for key in _FAULT_SWITCHES:
        if key in runs and key not in keep:
            runs = runs[~runs[key].map(_injects)]
    return runs


def _injects(value: object) -> bool:
    """True for a fault keyword's value that injects faults (a rate > 0, some times)."""
    if value is None or (isinstance(value, float) and np.isnan(value)):
        return False
    if isinstance(value, int | float | np.number):
        return value > 0
    return len(value) > 0


def _equal(column: pd.Series, value) -> pd.Series:
    if isinstance(value, bool) or not isinstance(value, int | float):
        return column == value
    return pd.Series(np.isclose(column.astype(float), value), index=column.index)


def _mean(runs: pd.DataFrame, metric: str) -> float:
    values = runs[metric].astype(float)
    return float(values.mean() * (100.0 if runs[metric].dtype == bool else 1.0))


def _yes(flag: bool) -> str:
    return "yes" if flag else "no"


def _ours(item: Published, df: pd.DataFrame, previous: dict) -> tuple[str, str, str]:
    """(ours, n runs, agrees) for one published record."""
    runs = _select(df, dict(item.condition))
    missing = (NOT_IN_SWEEP, "0", NOT_IN_SWEEP)
    if runs.empty or item.metric not in runs:
        return missing
    if item.kind == "level":
        value = _mean(runs, item.metric)
        key = (item.section, item.quantity)
        before = previous.get(key)
        previous[key] = value
        if item.check == "at least":
            agrees = _yes(value >= item.threshold)
        elif item.check == "reference" or before is None:
            agrees = "(reference)"
        else:
            agrees = _yes(value > before if item.check == "rises" else value < before)
        return f"{value:.3g}" if abs(value) < 100 else f"{value:.1f}", str(len(runs)), agrees
    if item.kind in ("change", "pair", "ratio"):
        if item.factor not in runs:
            return missing
        before = runs[_equal(runs[item.factor], item.a)]
        after = runs[_equal(runs[item.factor], item.b)]
        if before.empty or after.empty:
            return missing
        m0, m1 = _mean(before, item.metric), _mean(after, item.metric)
        n = f"{len(before)} + {len(after)}"
        if item.kind == "pair":
            return (
                f"{m0:.3g} -> {m1:.3g}",
                n,
                _yes(m1 < m0 if item.check == "decreases" else m1 > m0),
            )
        if m0 == 0:
            return "undefined (0 at baseline)", n, "no"
        if item.kind == "ratio":
            ratio = m1 / m0
            return f"{ratio:.2f}", n, _yes(ratio > 1 if item.check == "above 1" else ratio < 1)
        change = 100.0 * (m1 - m0) / m0
        return f"{change:+.1f}", n, _yes(np.sign(change) == np.sign(item.value))
    if item.kind == "convex":
        if item.factor not in runs or runs[item.factor].nunique() < 3:
            return missing
        means = runs.groupby(item.factor)[item.metric].mean()
        best = float(means.idxmin())
        inside = means.index.min() < best < means.index.max()
        return f"minimum at {best:g}", str(len(runs)), _yes(inside)
    # "r": Pearson r of condition means
    by = [b for b in item.by if b in runs]
    if item.other not in runs or not by:
        return missing
    result = stats.pearson(runs, item.metric, item.other, by)
    if result["n"] < 3:
        return NOT_IN_SWEEP, str(len(runs)), NOT_IN_SWEEP
    shown = f"{result['r']:.3f} ({result['n']} conditions, p = {result['p']:.2g})"
    positive = result["r"] > 0
    return shown, str(len(runs)), _yes(positive if item.check == "positive" else not positive)


def _shown(value: object) -> str:
    return f"{value:g}" if isinstance(value, float) else str(value)


def _condition_text(item: Published) -> str:
    parts = [f"{k.replace('_', ' ')} {_shown(v)}" for k, v in item.condition.items()]
    if item.kind in ("change", "pair", "ratio"):
        parts.append(f"{item.factor.replace('_', ' ')} {_shown(item.a)} -> {_shown(item.b)}")
    return ", ".join(parts)
