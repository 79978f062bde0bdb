"""Every statistical test of one report page as one tidy table: shown in the HTML, written
beside it as ``statistics.csv``.

One row per ANOVA source (or one row per refused ANOVA, saying why) and per Pearson
correlation, each with its effect size and bootstrap 95 % interval. When the page makes more
than one test, the p-values are adjusted for the number of tests on the page by Holm's
step-down method (``p_holm``), which keeps the chance of any false positive on the page at
5 % without assuming the tests independent.
"""

from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pandas as pd

from analysis.anova import Anova
from analysis.html import table

__all__ = [
    "COLUMNS",
    "anova_items",
    "holm",
    "pearson_rows",
    "statistics_frame",
    "tests_on_page",
    "write_csv",
]

#: The columns of statistics.csv, in order.
COLUMNS = (
    "sweep", "metric", "test", "factors", "source", "df", "sum_sq", "F", "r", "p", "p_holm",
    "effect", "effect_value", "ci_low", "ci_high", "computed", "reason", "notes",
)  # fmt: skip


def holm(p: Sequence[float]) -> np.ndarray:
    """Holm's step-down adjusted p-values (NaN stays NaN and is not counted as a test)."""
    p = np.asarray(p, dtype=float)
    out = np.full_like(p, np.nan)
    tested = np.flatnonzero(~np.isnan(p))
    m = len(tested)
    order = tested[np.argsort(p[tested], kind="stable")]
    running = 0.0
    for rank, i in enumerate(order):
        running = max(running, min(1.0, (m - rank) * p[i]))
        out[i] = running
    return out


def _anova_rows(sweep: str, result: Anova) -> list[dict]:
    notes = " ".join(result.notes)
    factors = " x ".join(result.factors)
    if result.table is None:
        return [{"sweep": sweep, "metric": result.metric, "test": "ANOVA", "factors": factors,
                 "computed": False, "reason": result.reason, "notes": notes}]  # fmt: skip
    rows = []
    for source, row in result.table.iterrows():
        residual = source == "Residual"
        rows.append(
            {
                "sweep": sweep,
                "metric": result.metric,
                "test": "ANOVA",
                "factors": factors,
                "source": source,
                "df": row["df"],
                "sum_sq": row["sum_sq"],
                "F": None if residual else row["F"],
                "p": None if residual else row["PR(>F)"],
                "effect": "eta_sq",
                "effect_value": row["eta_sq"],
                "ci_low": row.get("eta_sq_low"),
                "ci_high": row.get("eta_sq_high"),
                "computed": True,
                "notes": notes,
            }
        )
    return rows


def pearson_rows(sweep: str, x: str, y: str, result: dict) -> list[dict]:
    """The row of one Pearson correlation (:func:`analysis.stats.pearson`), or why it was not
    computed.
    """
    metric = f"{x} ~ {y}"
    if result.get("reason"):
        return [{"sweep": sweep, "metric": metric, "test": "Pearson r", "computed": False,
                 "reason": result["reason"]}]  # fmt: skip
    return [
        {
            "sweep": sweep,
            "metric": metric,
            "test": "Pearson r",
            "source": f"{result['n']} condition means",
            "df": result["df"],
            "r": result["r"],
            "p": result["p"],
            "effect": "r",
            "effect_value": result["r"],
            "ci_low": result.get("r_low"),
            "ci_high": result.get("r_high"),
            "computed": True,
        }
    ]


def statistics_frame(
    anovas: Sequence[tuple[str, Anova]], extra_rows: Sequence[dict] = ()
) -> pd.DataFrame:
    """All the page's tests, one row each (``COLUMNS``), with Holm-adjusted p-values."""
    rows = [row for sweep, result in anovas for row in _anova_rows(sweep, result)]
    frame = pd.DataFrame([*rows, *extra_rows], columns=list(COLUMNS))
    frame["computed"] = frame["computed"].astype(bool)
    frame["p"] = frame["p"].astype(float)
    frame["p_holm"] = holm(frame["p"].to_numpy())
    return frame


def tests_on_page(frame: pd.DataFrame) -> int:
    """How many p-values the page shows (the Holm adjustment's m)."""
    return int(frame["p"].notna().sum())


def anova_items(frame: pd.DataFrame, sweep: str, labels: dict[str, str]) -> list[dict]:
    """One sweep's ANOVA tables for the page (title, table or the refusal, notes); titles name
    the factors when the sweep is tested over more than one set of them.
    """
    part = frame[(frame["sweep"] == sweep) & (frame["test"] == "ANOVA")]
    several = part["factors"].fillna("").nunique() > 1
    items = []
    for (factors, metric), rows in part.groupby(["factors", "metric"], sort=False, dropna=False):
        first = rows.iloc[0]
        title = labels.get(metric, metric)
        if several and isinstance(factors, str) and factors:
            title = f"{title}, over {factors}"
        item = {"title": title, "table": None, "reason": None, "notes": first["notes"] or ""}
        if not first["computed"]:
            item["reason"] = f"not computed: {first['reason']}"
        else:
            shown = rows[["source", "df", "sum_sq", "F", "p", "p_holm", "effect_value",
                          "ci_low", "ci_high"]].rename(columns={
                "p": "PR(>F)", "p_holm": "p (Holm)", "effect_value": "eta_sq",
                "ci_low": "eta_sq 2.5 %", "ci_high": "eta_sq 97.5 %"})  # fmt: skip
            item["table"] = table(shown.replace({np.nan: None}), text_columns=("source",))
        items.append(item)
    return items


def write_csv(frame: pd.DataFrame, path: str | Path) -> Path:
    """Write the page's tests as CSV (full precision); returns the path."""
    path = Path(path)
    frame.to_csv(path, index=False)
    return path
