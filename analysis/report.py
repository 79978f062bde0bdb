"""One self-contained HTML report per sweep, for any model (``abm report``).

The report reads the sweep's dataset and the model's declared ``PUBLISHED`` records and
``REPORT`` layout (its ``published.py``): every published number beside ours for the same
condition with whether the direction agrees, the paper's figure types, two-way ANOVA over the
swept factors, percent changes, the optimal value of the swept parameter, Pearson's r, the
condition means, how the runs ended and the runs that failed. A model without a layout gets one
from its swept parameters.
"""

import datetime
import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pandas as pd

from abm.errors import ABMError
from abm.published import Published, ReportLayout
from abm.registry import model_class
from analysis import stats
from analysis.compare import NOT_IN_SWEEP, compare_published
from analysis.figures import label, save_figures
from analysis.html import image_data, render_page, table
from analysis.sweep import load_results

__all__ = ["layout_for", "write_report"]

#: Summary keys every model has (or has when it covers / has energy), used by default layouts.
COMMON_METRICS = ("time", "coverage_area", "energy_total", "collisions")

_CAPTIONS = {
    "metrics": "Mean ± standard error against {x}.",
    "stacked": "Mean components per run, stacked; error bars: standard error of the total.",
    "compare": "Mean {metric} for each value of {compare}.",
}


def _swept(manifest: dict, runs: pd.DataFrame) -> list[str]:
    """Grid parameters that take more than one value in the runs."""
    return [k for k in manifest.get("grid", {}) if k in runs and runs[k].nunique() > 1]


def _numeric(runs: pd.DataFrame, column: str) -> bool:
    return pd.api.types.is_numeric_dtype(runs[column]) and runs[column].dtype != bool


def layout_for(declared: ReportLayout | None, manifest: dict, runs: pd.DataFrame) -> ReportLayout:
    """The layout for these runs: the model's, with ``x`` and ``hue`` kept only where they
    vary; otherwise the first numeric swept parameter as ``x`` and another as ``hue``.
    """
    swept = _swept(manifest, runs)
    numeric = [k for k in swept if _numeric(runs, k)]
    layout = declared or ReportLayout(metrics=tuple(m for m in COMMON_METRICS if m in runs))
    x = layout.x if layout.x in swept else (numeric[0] if numeric else None)
    hue = layout.hue if layout.hue in swept and layout.hue != x else None
    if hue is None and declared is None:
        hue = next((k for k in swept if k != x), None)
    compare = layout.compare if layout.compare in swept else None
    return replace(layout, x=x, hue=hue, compare=compare)


def write_report(sweep_dir: str | Path, out: str | Path | None = None) -> Path:
    """Write ``report.html`` (and the figure PNGs in ``figures/``) for a sweep folder.

    Args:
        sweep_dir: a folder written by :func:`analysis.sweep.execute` (``abm sweep``).
        out: the HTML file (default ``<sweep_dir>/report.html``).

    Returns:
        The path of the HTML file.

    """
    sweep_dir = Path(sweep_dir)
    manifest_path = sweep_dir / "sweep.json"
    if not manifest_path.is_file():
        raise ABMError(f"{sweep_dir} is not a sweep folder (no sweep.json); run `abm sweep` first")
    manifest = json.loads(manifest_path.read_text())
    df = load_results(sweep_dir)
    out = Path(out) if out is not None else sweep_dir / "report.html"
    cls, problem = _model(manifest)
    runs = stats.ok_runs(df)
    failed = df[df["status"] == "failed"] if "status" in df else df.iloc[0:0]
    layout = layout_for(None if cls is None else cls.REPORT, manifest, runs)
    figures = save_figures(runs, layout, sweep_dir / "figures") if len(runs) else {}
    published = list(cls.PUBLISHED) if cls is not None else []
    name = manifest.get("name", sweep_dir.name)
    return render_page(
        "sweep_report.html.j2",
        out,
        title=f"{'Reproduction' if published else 'Sweep'} report: {name}",
        subtitle=manifest.get("description", ""),
        meta=_meta(manifest, df, failed, sweep_dir),
        problem=problem,
        comparison=_comparison(df, published),
        not_in_sweep=NOT_IN_SWEEP,
        figures=[
            {
                "src": image_data(path),
                "caption": _CAPTIONS[key].format(
                    x=label(layout, layout.x or ""),
                    metric=label(layout, layout.compare_metric or ""),
                    compare=label(layout, layout.compare or ""),
                ),
            }
            for key, path in figures.items()
        ],
        anova=_anova(runs, layout) if len(runs) else [],
        sections=_factor_sections(runs, layout, published) if len(runs) else [],
        failed=table(failed.drop(columns=["traceback"], errors="ignore").head(20))
        if len(failed)
        else None,
        n_failed=len(failed),
    )


def _model(manifest: dict) -> tuple[type | None, str | None]:
    """The sweep's model class, or None and why (a model no longer importable here)."""
    try:
        return model_class(manifest.get("target") or manifest["model"]), None
    except (ABMError, KeyError) as exc:
        return None, f"the model of this sweep cannot be loaded here ({exc}); no published numbers"


def _meta(manifest: dict, df: pd.DataFrame, failed: pd.DataFrame, folder: Path) -> list:
    grid = manifest.get("grid", {})
    rows = [
        ("model", manifest.get("model", "?")),
        ("grid", "; ".join(f"{k} = {v}" for k, v in grid.items())),
        ("replications", manifest.get("replications", "?")),
        ("sweep seed", manifest.get("seed", "?")),
        ("runs finished / failed", f"{len(df) - len(failed)} / {len(failed)}"),
    ]
    if "end_reason" in df:
        kinds = df["end_reason"].dropna().astype(str).str.split(":").str[0].value_counts()
        # runs that hit the time limit are outliers in every mean: the reader must see them
        rows.append(("runs ended by", ", ".join(f"{k} {n}" for k, n in kinds.items())))
    rows += [
        ("data", str(folder.resolve())),
        ("generated", datetime.datetime.now().isoformat(timespec="seconds")),
    ]
    return rows


def _comparison(df: pd.DataFrame, published: list[Published]) -> list[dict] | None:
    if not published:
        return None
    rows = compare_published(df, published)
    return rows.to_dict("records")


def _factors(runs: pd.DataFrame, layout: ReportLayout) -> list[str]:
    return [f for f in (layout.x, layout.hue) if f is not None and f in runs]


def _metrics(runs: pd.DataFrame, layout: ReportLayout) -> list[str]:
    wanted = [*layout.metrics, *([layout.total] if layout.total else [])]
    return [m for m in dict.fromkeys(wanted) if m in runs and _numeric(runs, m)]


def _anova(runs: pd.DataFrame, layout: ReportLayout) -> list[dict]:
    factors = _factors(runs, layout)
    if not factors:
        return []
    out = []
    for metric in _metrics(runs, layout):
        result = stats.anova(runs, metric, factors)
        if not result.empty:
            shown = result.reset_index(names="source")
            out.append({"title": label(layout, metric).replace("(kJ)", "(J)"),
                        "table": table(shown, text_columns=("source",))})  # fmt: skip
    return out


def _factor_sections(
    runs: pd.DataFrame, layout: ReportLayout, published: list[Published]
) -> list[dict]:
    """Percent changes, optimum, Pearson's r and condition means (titles, notes, tables)."""
    sections = []
    x, hue = layout.x, layout.hue
    metrics = _metrics(runs, layout)
    if x is not None and _numeric(runs, x) and metrics:
        values = sorted(runs[x].unique())
        pairs = [(values[0], values[-1])]
        pairs += [
            (p.a, p.b)
            for p in published
            if p.kind == "change" and p.factor == x and p.a in values and p.b in values
        ]
        pairs = list(dict.fromkeys(pairs))
        changes = stats.percent_change_table(runs, pairs, metrics, factor=x, by=hue)
        if not changes.empty:
            changes = changes.rename(columns={"change": "change (%)"})
            sections.append({"title": f"Percent changes between values of {x}", "note": "",
                             "table": table(changes)})  # fmt: skip
        optimum = [m for m in layout.optimum if m in runs]
        if optimum:
            best = stats.optimal_period(runs, dict.fromkeys(optimum, 1.0), factor=x, by=hue)
            if not best.empty:
                note = (
                    f"Cubic interpolation of the means of {', '.join(optimum)} over {x}, each "
                    "normalised to [0, 1], summed with equal weights; the optimum is the minimum "
                    "(Stirling et al. Sect. 5). analysis.stats.optimal_period takes other weights."
                )
                sections.append({"title": f"Optimal {x}", "note": note, "table": table(best)})
    if layout.correlate and all(c in runs for c in layout.correlate):
        r = stats.pearson(runs, *layout.correlate, by=_factors(runs, layout))
        if r["n"] >= 3:
            note = (
                f"Pearson r of the condition means of {layout.correlate[0]} and "
                f"{layout.correlate[1]} across {r['n']} conditions: r = {r['r']:.3f} "
                f"(df = {r['df']}, p = {r['p']:.2g})."
            )
            sections.append({"title": "Correlation", "note": note, "table": None})
    factors = _factors(runs, layout)
    extra = [m for m in ("coverage_area", "energy_total", *layout.stacked) if m in runs]
    shown = [m for m in dict.fromkeys([*metrics, *extra]) if _numeric(runs, m)]
    if shown:
        means = stats.condition_means(runs, metrics=shown, by=factors)
        wide = (
            means.pivot_table(index=factors, columns="metric", values="mean")
            .rename_axis(columns=None)
            .reset_index()
            if factors
            else means[["metric", "mean", "sem", "n"]]
        )
        note = "Times in s, energies in J, coverage in % of the free area."
        sections.append({"title": "Condition means", "note": note,
                         "table": table(wide.replace({np.nan: None}), digits=4)})  # fmt: skip
    return sections
