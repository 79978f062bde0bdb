"""One self-contained HTML reproduction report per sweep (figures embedded, tables inline).

The report shows the sweep's figures, the two-way ANOVA tables, percent-change tables, the
optimal launch period, and every published number of SPEC A (Stirling et al. 2010) beside the
sweep's value for the same condition, with a column saying whether the direction agrees.
"""

import base64
import datetime
import html
import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from analysis import stats
from analysis.figures import LABELS, save_figures
from analysis.sweep import load_results

__all__ = ["Published", "PUBLISHED", "compare_published", "write_report"]

NOT_IN_SWEEP = "not in this sweep"


@dataclass(frozen=True)
class Published:
    """One published number and how to compute ours.

    Attributes:
        section: the paper's experiment ("corridor", "open space", ...).
        quantity: what is measured, with unit.
        condition: the runs it is computed on: world, complexity, periods, hover.
        value: the published value (or a short text such as "0.32 -> 0.02").
        kind: "level" (mean of ``metric``), "change" (percent change ``a`` -> ``b``),
            "pair" (two means a -> b), "r" (Pearson r), "ratio" (hover / attached),
            "convex" (minimum of the mean inside the period range).
        metric: summary column.
        check: the rule deciding "direction agrees".

    """

    section: str
    quantity: str
    condition: dict
    value: float | str
    kind: str
    metric: str
    check: str
    a: float | None = None
    b: float | None = None


def _corridor_levels() -> list[Published]:
    rows = []
    series = [
        ("coverage area (%), mean over periods", "coverage_area", (79.4, 90.1, 94.0)),
        ("complete coverage (% of trials)", "complete", (38.5, 64.2, 74.3)),
        ("corridor branches per world (mean)", "branches", (3.56, 5.82, 9.5)),
    ]
    for quantity, metric, values in series:
        for i, (level, value) in enumerate(zip(("low", "medium", "high"), values, strict=True)):
            check = "reference level" if i == 0 else "rises from the previous complexity"
            rows.append(
                Published(
                    "corridor",
                    quantity,
                    {"world": "corridor", "complexity": level},
                    value,
                    "level",
                    metric,
                    check,
                )
            )
    return rows


def _changes(section, world, complexity, a, b, items) -> list[Published]:
    return [
        Published(
            section,
            f"{LABELS.get(metric, metric).split(' (')[0].lower()}: change {b:g} s vs {a:g} s (%)",
            {"world": world, "complexity": complexity},
            value,
            "change",
            metric,
            "same sign",
            a,
            b,
        )
        for metric, value in items
    ]


#: Every published number of SPEC A, in the paper's order.
PUBLISHED: list[Published] = [
    *_corridor_levels(),
    *_changes(
        "corridor",
        "corridor",
        "high",
        6.0,
        24.0,
        [
            ("flight_time", -41.5),
            ("collisions", -93.9),
            ("coverage_time", 90.5),
            ("energy_total", -30.8),
        ],
    ),
    Published(
        "corridor",
        "Pearson r, mean flight time vs mean energy across conditions",
        {"world": "corridor"},
        0.974,
        "r",
        "flight_time",
        "same sign",
    ),
    Published(
        "open space",
        "coverage area (%), mean over all conditions",
        {"world": "open"},
        99.7,
        "level",
        "coverage_area",
        "near complete (>= 95 %)",
    ),
    *_changes(
        "open space",
        "open",
        "high",
        3.0,
        12.0,
        [("flight_time", -29.9), ("energy_total", -16.4), ("coverage_time", 149.7)],
    ),
    Published(
        "open space",
        "collisions per run, 3 s -> 12 s",
        {"world": "open", "complexity": "high"},
        "0.32 -> 0.02",
        "pair",
        "collisions",
        "decreases",
        3.0,
        12.0,
    ),
    *_changes(
        "open space",
        "open",
        "high",
        3.0,
        6.0,
        [("flight_time", -15.0), ("coverage_time", 44.9)],
    ),
    Published(
        "open space",
        "total energy vs period (medium density)",
        {"world": "open", "complexity": "medium"},
        "convex (optimum inside)",
        "convex",
        "energy_total",
        "minimum inside the period range",
    ),
    *_changes(
        "mixed",
        "mixed",
        "medium",
        6.0,
        24.0,
        [
            ("flight_time", -34.0),
            ("collisions", -86.4),
            ("coverage_time", 70.5),
            ("energy_total", -25.3),
        ],
    ),
    Published(
        "hover vs attach",
        "total energy, hovering / attached beacons (x)",
        {"world": "mixed", "complexity": "medium", "launch_period": 6.0},
        3.6,
        "ratio",
        "energy_total",
        "ratio > 1",
    ),
]


# ---------------------------------------------------------------------------------- comparison
def _select(df: pd.DataFrame, condition: dict, hover: bool | None = False) -> pd.DataFrame:
    runs = stats.ok_runs(df)
    for key, value in condition.items():
        if key not in runs:
            return runs.iloc[0:0]
        if isinstance(value, float):
            runs = runs[np.isclose(runs[key].astype(float), value)]
        else:
            runs = runs[runs[key] == value]
    if hover is not None and "hover_beacons" in runs:
        runs = runs[runs["hover_beacons"] == hover]
    return runs


def _mean(runs: pd.DataFrame, metric: str) -> float:
    values = runs[metric].astype(float)
    return float(values.mean() * (100.0 if metric == "complete" else 1.0))


def _at(runs: pd.DataFrame, period: float) -> pd.DataFrame:
    return runs[np.isclose(runs["launch_period"].astype(float), period)]


def _fmt(x: float, digits: int = 1) -> str:
    return "nan" if x != x else f"{x:+.{digits}f}" if digits < 0 else f"{x:.{digits}f}"


def _yes(flag: bool) -> str:
    return "yes" if flag else "no"


def _ours(item: Published, df: pd.DataFrame, previous: dict) -> tuple[str, str, str]:
    """(ours, n runs, agrees) for one published number."""
    runs = _select(df, item.condition)
    if item.kind == "level":
        if runs.empty or item.metric not in runs:
            return NOT_IN_SWEEP, "0", NOT_IN_SWEEP
        value = _mean(runs, item.metric)
        key = (item.section, item.quantity)
        before = previous.get(key)
        previous[key] = value
        if item.check.startswith("near complete"):
            agrees = _yes(value >= 95.0)
        elif before is None:
            agrees = "(reference)"
        else:
            agrees = _yes(value > before)
        return (
            f"{value:.2f}" if item.metric == "branches" else f"{value:.1f}",
            str(len(runs)),
            agrees,
        )
    if item.kind in ("change", "pair", "convex") and "launch_period" not in runs:
        return NOT_IN_SWEEP, "0", NOT_IN_SWEEP
    if item.kind in ("change", "pair"):
        before, after = _at(runs, item.a), _at(runs, item.b)
        if before.empty or after.empty:
            return NOT_IN_SWEEP, "0", NOT_IN_SWEEP
        m0, m1 = _mean(before, item.metric), _mean(after, item.metric)
        n = f"{len(before)} + {len(after)}"
        if item.kind == "pair":
            return f"{m0:.2f} -> {m1:.2f}", n, _yes(m1 < m0)
        if m0 == 0:
            return "undefined (0 at baseline)", n, "no"
        change = 100.0 * (m1 - m0) / m0
        return f"{change:+.1f}", n, _yes(np.sign(change) == np.sign(item.value))
    if item.kind == "convex":
        if runs["launch_period"].nunique() < 3:
            return NOT_IN_SWEEP, "0", NOT_IN_SWEEP
        means = runs.groupby("launch_period")[item.metric].mean()
        best = float(means.idxmin())
        inside = means.index.min() < best < means.index.max()
        return f"minimum at {best:g} s", str(len(runs)), _yes(inside)
    if item.kind == "r":
        if runs.empty or "complexity" not in runs:
            return NOT_IN_SWEEP, "0", NOT_IN_SWEEP
        result = stats.pearson(runs)
        if result["n"] < 3:
            return NOT_IN_SWEEP, str(len(runs)), NOT_IN_SWEEP
        shown = f"{result['r']:.3f} ({result['n']} conditions, p = {result['p']:.2g})"
        return shown, str(len(runs)), _yes(result["r"] > 0)
    if item.kind == "ratio":
        attached = _select(df, item.condition, hover=False)
        hovering = _select(df, item.condition, hover=True)
        if attached.empty or hovering.empty:
            return NOT_IN_SWEEP, "0", NOT_IN_SWEEP
        ratio = _mean(hovering, item.metric) / _mean(attached, item.metric)
        return f"{ratio:.2f}", f"{len(attached)} + {len(hovering)}", _yes(ratio > 1)
    raise ValueError(f"unknown kind {item.kind!r}")


def _condition_text(item: Published) -> str:
    parts = [f"{k.replace('_', ' ')} {v:g} s" if k == "launch_period" else str(v)
             for k, v in item.condition.items()]  # fmt: skip
    if item.kind in ("change", "pair"):
        parts.append(f"{item.a:g} s -> {item.b:g} s")
    return ", ".join(parts)


def compare_published(df: pd.DataFrame) -> pd.DataFrame:
    """Every published number of SPEC A beside ours for the same condition.

    Returns:
        Columns section, quantity, condition, published, ours, runs, check, direction agrees.
        Conditions the sweep lacks read "not in this sweep".

    """
    previous: dict = {}
    rows = []
    for item in PUBLISHED:
        ours, n, agrees = _ours(item, df, previous)
        published = item.value if isinstance(item.value, str) else f"{item.value:g}"
        if item.kind == "change":
            published = f"{item.value:+.1f}"
        rows.append(
            {
                "section": item.section,
                "quantity": item.quantity,
                "condition": _condition_text(item),
                "published": published,
                "ours": ours,
                "runs": n,
                "check": item.check,
                "direction agrees": agrees,
            }
        )
    return pd.DataFrame(rows)


# ---------------------------------------------------------------------------------- HTML
_CSS = """
body { font-family: system-ui, sans-serif; margin: 2em auto; max-width: 1150px; color: #222; }
h1 { font-size: 1.6em; }
h2 { border-bottom: 1px solid #ccc; padding-bottom: .2em; margin-top: 2em; }
table { border-collapse: collapse; margin: .8em 0; font-size: .9em; }
th, td { border: 1px solid #ddd; padding: .3em .6em; text-align: right; }
th { background: #f3f3f3; } td.text, th.text { text-align: left; }
tr.yes td.agree { background: #e3f4e1; } tr.no td.agree { background: #fbe0e0; }
tr.missing td { color: #999; }
img { max-width: 100%; border: 1px solid #eee; }
.meta td { text-align: left; } .note { color: #555; font-size: .9em; }
"""


def _table(df: pd.DataFrame, float_format: str = "{:,.3g}") -> str:
    return df.to_html(
        index=False, border=0, na_rep="", float_format=lambda x: float_format.format(x)
    )


def _comparison_html(table: pd.DataFrame) -> str:
    heads = "".join(
        f'<th class="{"text" if c in ("section", "quantity", "condition", "check") else ""}">'
        f"{html.escape(c)}</th>"
        for c in table.columns
    )
    body = []
    for _, row in table.iterrows():
        agrees = row["direction agrees"]
        cls = (
            "yes"
            if agrees == "yes"
            else "no"
            if agrees == "no"
            else "missing"
            if agrees == NOT_IN_SWEEP
            else ""
        )
        cells = []
        for col in table.columns:
            kind = "text" if col in ("section", "quantity", "condition", "check") else ""
            kind = "agree" if col == "direction agrees" else kind
            cells.append(f'<td class="{kind}">{html.escape(str(row[col]))}</td>')
        body.append(f'<tr class="{cls}">{"".join(cells)}</tr>')
    return f"<table><tr>{heads}</tr>{''.join(body)}</table>"


def _img(path: Path, alt: str) -> str:
    data = base64.b64encode(path.read_bytes()).decode()
    return f'<p><img alt="{html.escape(alt)}" src="data:image/png;base64,{data}"></p>'


def _anova_html(runs: pd.DataFrame) -> str:
    parts = []
    for metric, table in stats.anova_tables(runs).items():
        if table.empty:
            continue
        shown = table.reset_index(names="source")
        label = LABELS.get(metric, metric).replace("(kJ)", "(J)")
        parts.append(f"<h3>{html.escape(label)}</h3>{_table(shown)}")
    if not parts:
        return '<p class="note">Not enough conditions or runs for an ANOVA.</p>'
    note = (
        '<p class="note">OLS with categorical factors, type-II sums of squares (statsmodels); '
        "eta_sq = share of the total sum of squares. Factors with one level are left out.</p>"
    )
    return note + "".join(parts)


def write_report(sweep_dir: str | Path, out: str | Path | None = None) -> Path:
    """Write ``report.html`` (and the figure PNGs in ``figures/``) for a sweep folder.

    Args:
        sweep_dir: a folder written by :func:`analysis.sweep.execute` (``abm sweep``).
        out: the HTML file (default ``<sweep_dir>/report.html``).

    Returns:
        The path of the HTML file.

    """
    sweep_dir = Path(sweep_dir)
    df = load_results(sweep_dir)
    out = Path(out) if out is not None else sweep_dir / "report.html"
    manifest_path = sweep_dir / "sweep.json"
    manifest = json.loads(manifest_path.read_text()) if manifest_path.is_file() else {}
    runs = stats.ok_runs(df)
    failed = df[df["status"] == "failed"] if "status" in df else df.iloc[0:0]
    figures = save_figures(runs, sweep_dir / "figures") if len(runs) else {}
    name = manifest.get("name", sweep_dir.name)

    sections = [
        f"<h1>Reproduction report: {html.escape(name)}</h1>",
        f"<p>{html.escape(manifest.get('description', ''))}</p>",
        _meta_html(manifest, df, failed, sweep_dir),
        "<h2>Published numbers (Stirling et al. 2010, SPEC A) beside ours</h2>",
        '<p class="note">Same condition as the paper. "Direction agrees" applies the rule in '
        "the <i>check</i> column: for percent changes the sign, for levels across complexities "
        "whether ours rises like the paper's. Conditions the sweep lacks read "
        f'"{NOT_IN_SWEEP}".</p>',
        _comparison_html(compare_published(df)),
    ]
    if figures:
        sections.append("<h2>Figures</h2>")
        captions = {
            "periods": "Mean ± standard error against the inter-launch period (cf. Figs. 6, 8, "
            "10a).",
            "energy": "Mean energy components per run, stacked; error bars: standard error of "
            "the total (cf. Figs. 7, 9, 10b).",
            "hover": "Mean energy with beacons attached to the ceiling vs hovering.",
        }
        for key, path in figures.items():
            sections.append(f"<p class='note'>{captions.get(key, '')}</p>{_img(path, key)}")
    if len(runs):
        sections += ["<h2>Two-way ANOVA: period x complexity</h2>", _anova_html(runs)]
        sections += _period_tables(runs)
    if len(failed):
        shown = failed[[c for c in failed.columns if c not in ("traceback",)]].head(20)
        sections += [f"<h2>Failed runs ({len(failed)})</h2>", _table(shown)]
    page = (
        "<!DOCTYPE html><html><head><meta charset='utf-8'>"
        f"<title>{html.escape(name)}: reproduction report</title><style>{_CSS}</style></head>"
        f"<body>{''.join(sections)}</body></html>"
    )
    out.write_text(page)
    return out


def _end_reasons(df: pd.DataFrame) -> list[tuple[str, str]]:
    """How the runs ended ("stuck: ..." counted as "stuck"); runs that hit the time limit are
    outliers in every mean, so the reader must see how many there are.
    """
    if "end_reason" not in df:
        return []
    kinds = df["end_reason"].dropna().str.split(":").str[0].value_counts()
    return [("runs ended by", ", ".join(f"{k} {n}" for k, n in kinds.items()))]


def _meta_html(manifest: dict, df: pd.DataFrame, failed: pd.DataFrame, folder: Path) -> str:
    grid = manifest.get("grid", {})
    rows = [
        ("model", manifest.get("model", "?")),
        ("grid", "; ".join(f"{k} = {v}" for k, v in grid.items())),
        ("replications", manifest.get("replications", "?")),
        ("sweep seed", manifest.get("seed", "?")),
        ("runs finished / failed", f"{len(df) - len(failed)} / {len(failed)}"),
        *_end_reasons(df),
        ("data", str(folder.resolve())),
        ("generated", datetime.datetime.now().isoformat(timespec="seconds")),
    ]
    cells = "".join(
        f"<tr><th class='text'>{html.escape(k)}</th><td>{html.escape(str(v))}</td></tr>"
        for k, v in rows
    )
    return f"<table class='meta'>{cells}</table>"


def _period_tables(runs: pd.DataFrame) -> list[str]:
    periods = sorted(runs["launch_period"].unique()) if "launch_period" in runs else []
    if len(periods) < 2:
        return []
    out = []
    pairs = [(periods[0], periods[-1])]
    if 3.0 in periods and 6.0 in periods and periods[-1] != 6.0:
        pairs.append((3.0, 6.0))
    changes = stats.percent_change_table(runs, pairs=pairs)
    if not changes.empty:
        changes = changes.rename(columns={"change": "change (%)"})
        out += ["<h2>Percent changes between periods</h2>", _table(changes)]
    optimum = stats.optimal_period(runs)
    if not optimum.empty:
        out += [
            "<h2>Optimal inter-launch period</h2>",
            '<p class="note">Cubic interpolation of the mean coverage time, collisions and total '
            "energy over the period, each normalised to [0, 1], weighted sum (equal weights), "
            "minimum (Sect. 5). Use <code>analysis.stats.optimal_period(df, weights=...)</code> "
            "for other weights.</p>",
            _table(optimum),
        ]
    r = stats.pearson(runs)
    if r["n"] >= 3:
        out += [
            "<h2>Flight time predicts energy</h2>",
            f"<p>Pearson r of mean flight time vs mean total energy across {r['n']} conditions: "
            f"<b>{r['r']:.3f}</b> (df = {r['df']}, p = {r['p']:.2g}); paper: 0.974 (df = 16).</p>",
        ]
    means = stats.condition_means(runs, metrics=[*stats.METRICS, "coverage_area"])
    wide = (
        means.pivot_table(
            index=[c for c in ("complexity", "launch_period") if c in means],
            columns="metric",
            values="mean",
        )
        .rename_axis(columns=None)
        .reset_index()
    )
    out += [
        "<h2>Condition means</h2>",
        '<p class="note">Times in s, energies in J, coverage area in % of the free area.</p>',
        _table(wide, "{:,.1f}"),
    ]
    return out
