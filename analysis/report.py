"""One self-contained HTML report of one or several sweeps of a model (``abm report``).

The report reads the sweeps' datasets and the model's declared ``PUBLISHED`` records,
``CLAIMS``, ``CENSORED`` metrics and ``REPORT`` layout (its ``published.py``): every published
number beside ours on the runs of the paper's condition, and every claim with ours, each with
its rule and verdict (:mod:`analysis.compare`; the same rows go to ``comparison.csv`` beside
the HTML); then
per sweep the paper's figure types, the time-series curves (mean and spread over runs), two-way
ANOVA over the swept factors, percent changes, the optimal value of the swept parameter,
Pearson's r, the condition means and the runs that failed. A model without a layout gets one
from its swept parameters.
"""

import contextlib
import datetime
import warnings
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
import pandas as pd

from abm.errors import ABMError, ConfigError
from abm.published import Claim, Published, ReportLayout
from abm.registry import model_class
from abm.units import unit_of
from analysis import stats
from analysis.anova import RESAMPLES, Anova
from analysis.censoring import censored_mask, censoring_causes
from analysis.compare import (
    BY_CONSTRUCTION,
    NOT_IN_SWEEP,
    compare_published,
    comparison_csv,
    fault_free,
    judge_claims,
    parameter_defaults,
)
from analysis.figures import label, save_curves, save_figures
from analysis.html import image_data, render_page, table
from analysis.sensitivity_report import design_block
from analysis.sensitivity_report import write_csv as write_sensitivity
from analysis.statistics_table import anova_items, pearson_rows, statistics_frame, tests_on_page
from analysis.statistics_table import write_csv as write_statistics
from analysis.sweep import load_results, read_manifest, swept_keys
from analysis.sweep.folder import refuse_while_running

__all__ = ["layout_for", "write_report"]

#: Summary keys every model has (or has when it covers / has energy), used by default layouts.
COMMON_METRICS = ("time", "coverage_area", "energy_total", "collisions")

_CAPTIONS = {
    "metrics": "Mean ± standard error against {x}; a metric the time limit censors in some "
    "runs: its Kaplan-Meier median per condition (△: not reached, at least the bound).",
    "stacked": "Mean components per run, stacked; error bars: standard error of the total; "
    "'k/n cut': runs the time limit ended, whose sums are lower bounds.",
    "compare": "Mean {metric} for each value of {compare}.",
}


def _numeric(runs: pd.DataFrame, column: str) -> bool:
    return pd.api.types.is_numeric_dtype(runs[column]) and runs[column].dtype != bool


def _derived(runs: pd.DataFrame, column: str | None) -> bool:
    """A numeric summary column that varies over the runs (e.g. a total derived from two swept
    parameters), usable as a layout's ``x`` or ``hue``.
    """
    return (
        column is not None
        and column in runs
        and _numeric(runs, column)
        and (runs[column].nunique() > 1)
    )


def layout_for(declared: ReportLayout | None, manifest: dict, runs: pd.DataFrame) -> ReportLayout:
    """The layout for these runs: the model's (or the first of its ``alternatives`` whose
    ``x`` the sweep varies), with ``x`` and ``hue`` kept only where they vary (a swept
    parameter, or a numeric summary column derived from them); otherwise the first numeric
    swept parameter as ``x`` and another as ``hue``.
    """
    swept = swept_keys(manifest, runs)
    numeric = [k for k in swept if _numeric(runs, k)]
    if declared is not None:
        declared = next(
            (
                layout
                for layout in (declared, *declared.alternatives)
                if layout.x in swept or _derived(runs, layout.x)
            ),
            declared,
        )
    layout = declared or ReportLayout(metrics=tuple(m for m in COMMON_METRICS if m in runs))
    varies = set(swept) | {c for c in (layout.x, layout.hue) if _derived(runs, c)}
    x = layout.x if layout.x in varies else (numeric[0] if numeric else None)
    hue = layout.hue if layout.hue in varies and layout.hue != x else None
    if hue is None and declared is None:
        hue = next((k for k in swept if k != x), None)
    compare = layout.compare if layout.compare in swept else None
    return replace(layout, x=x, hue=hue, compare=compare)


def _check_units(sweeps: list) -> None:
    """Refuse to pool sweeps whose runs are in different units: a sweep records the unit of
    each summary key in its ``sweep.json``; one made before units were recorded cannot be
    checked, so it is reported only alone.
    """
    if len(sweeps) < 2:
        return
    unrecorded = [s.name for s in sweeps if "units" not in s.manifest]
    if unrecorded:
        raise ABMError(
            f"{', '.join(unrecorded)}: made by code that recorded no units, so its numbers "
            "cannot be checked against the other sweeps'; report it alone or run it again"
        )
    first = sweeps[0]
    for other in sweeps[1:]:
        a, b = first.manifest["units"], other.manifest["units"]
        differ = sorted(k for k in set(a) & set(b) if a[k] != b[k])
        if differ:
            shown = ", ".join(f"{k} ({a[k]} vs {b[k]})" for k in differ)
            raise ABMError(
                f"{first.name} and {other.name} record different units for {shown}: "
                "their runs cannot be pooled; run the older sweep again"
            )


@dataclass
class _Sweep:
    """One sweep folder, loaded."""

    folder: Path
    manifest: dict
    runs: pd.DataFrame  # every row (finished and failed), with a ``sweep`` column
    samples: pd.DataFrame  # the model's time series of its runs (may be empty)

    @property
    def name(self) -> str:
        return self.manifest.get("name", self.folder.name)


def _load(folder: str | Path) -> _Sweep:
    folder = Path(folder)
    manifest = read_manifest(folder)  # one line for a missing, damaged or non-UTF-8 sweep.json
    refuse_while_running(folder, "a report")
    name = manifest.get("name", folder.name)
    runs = load_results(folder).assign(sweep=name)
    samples = load_results(folder, samples=True)
    return _Sweep(folder, manifest, runs, samples)


def write_report(
    sweep_dirs: str | Path | Sequence[str | Path], out: str | Path | None = None
) -> Path:
    """Write one HTML report (and its figure PNGs) for one or several sweep folders.

    Several folders must hold sweeps of the same model (e.g. one per figure of its paper):
    the published numbers and the claims are checked on all their runs together; figures,
    curves and statistics are drawn per sweep.

    Args:
        sweep_dirs: folders written by :func:`analysis.sweep.execute` (``abm sweep``).
        out: the HTML file (default ``<first folder>/report.html``).

    Returns:
        The path of the HTML file.

    """
    if isinstance(sweep_dirs, str | Path):
        sweep_dirs = [sweep_dirs]
    sweeps = [_load(folder) for folder in sweep_dirs]
    if not sweeps:
        raise ABMError("give at least one sweep folder")
    targets = {s.manifest.get("target") or s.manifest.get("model") for s in sweeps}
    if len(targets) > 1:
        raise ABMError(f"the sweeps are of different models ({', '.join(sorted(targets))})")
    _check_units(sweeps)
    out = Path(out) if out is not None else sweeps[0].folder / "report.html"
    out.parent.mkdir(parents=True, exist_ok=True)
    cls, problem = _model(sweeps[0].manifest)
    every = pd.concat([s.runs for s in sweeps], ignore_index=True)
    published = list(cls.PUBLISHED) if cls is not None else []
    claims = list(cls.CLAIMS) if cls is not None else []
    defaults = parameter_defaults(cls)
    varied = sorted(
        {name for s in sweeps for name in s.manifest.get("design", {}).get("parameters", {})}
    )
    comparison = (
        compare_published(every, published, defaults, cls.CENSORED, varied, cls.CUT_ENDS)
        if published
        else None
    )
    judged = _claims(sweeps, claims, defaults, varied, () if cls is None else cls.CUT_ENDS)
    names = ", ".join(s.name for s in sweeps)
    blocks = [_block(s, cls, published, len(sweeps) > 1) for s in sweeps]
    statistics = _statistics(blocks, out)
    path = render_page(
        "sweep_report.html.j2",
        out,
        title=f"{'Reproduction' if published or claims else 'Sweep'} report: {names}",
        subtitle=" ".join(s.manifest.get("description", "") for s in sweeps if len(sweeps) == 1),
        meta=_meta(sweeps, every),
        problem=problem,
        comparison=_shown_rows(comparison.to_dict("records")) if comparison is not None else None,
        claims=_shown_rows(judged) if judged else None,
        tally=_tally(comparison, judged),
        not_in_sweep=NOT_IN_SWEEP,
        blocks=blocks,
        statistics=statistics,
    )
    comparison_csv(comparison, judged).to_csv(path.with_name("comparison.csv"), index=False)
    write_sensitivity(blocks, path.with_name("sensitivity.csv"))
    return path


def _shown_rows(rows: list[dict]) -> list[dict]:
    """The rows without their CSV-only numbers (keys that start with "_")."""
    return [{k: v for k, v in row.items() if not k.startswith("_")} for row in rows]


def _tally(comparison: pd.DataFrame | None, claims: list[dict] | None) -> list[str]:
    """One line per table: how many verdicts of each kind; what holds by construction is
    counted apart and never as reproduced.
    """
    lines = []
    for name, verdicts in (
        ("published numbers", [] if comparison is None else list(comparison["verdict"])),
        ("claims", [row["verdict"] for row in claims or []]),
    ):
        if not verdicts:
            continue
        counts = pd.Series(verdicts).value_counts()
        tested = sum(counts.get(v, 0) for v in ("holds", "does not hold", "undecided"))
        held = counts.get("holds", 0)
        parts = [f"{held} of {tested} judged here hold" if tested else "none judged here"]
        parts += [_counted(n, v) for v, n in counts.items() if v != "holds"]
        lines.append(f"{name.capitalize()}: {'; '.join(parts)}.")
    return lines


def _counted(n: int, verdict: str) -> str:
    """``n`` rows of one verdict, as the tally says it ("4 do not hold", "1 by construction
    (not a test), not counted as reproduced").
    """
    if verdict == "does not hold" and n != 1:
        return f"{n} do not hold"
    if verdict == BY_CONSTRUCTION:
        return f"{n} {verdict}, not counted as reproduced"
    return f"{n} {verdict}"


def _block(sweep: _Sweep, cls: type | None, published: list, titled: bool) -> dict:
    """One sweep's figures, curves, statistics and failures (a design sweep: its sensitivity)."""
    if sweep.manifest.get("design"):
        title = f"{sweep.name}: {sweep.manifest.get('description', '')}" if titled else ""
        return design_block(sweep.name, sweep.manifest, sweep.runs, cls,
                            sweep.folder / "figures", title)  # fmt: skip
    runs = stats.ok_runs(sweep.runs)
    failed = sweep.runs[sweep.runs["status"] == "failed"] if "status" in sweep.runs else runs[:0]
    layout = layout_for(None if cls is None else cls.REPORT, sweep.manifest, runs)
    layout = _for_this_grid(layout, runs, swept_keys(sweep.manifest, runs), cls)
    folder = sweep.folder / "figures"
    with _noted() as warned:
        censored = () if cls is None else cls.CENSORED
        figures = save_figures(runs, layout, folder, censored=censored) if len(runs) else {}
    shown = [
        {
            "src": image_data(path),
            "caption": _CAPTIONS[key].format(
                x=label(layout, layout.x or ""),
                metric=label(layout, layout.compare_metric or ""),
                compare=label(layout, layout.compare or ""),
            ),
        }
        for key, path in figures.items()
    ]
    conditions = swept_keys(sweep.manifest, runs)
    cut = _censored_here(runs, cls)
    curves = [m for m in layout.curves if m in sweep.samples]
    if curves and len(runs):
        path = save_curves(sweep.samples, runs, layout, curves, conditions, folder)
        shown.append({"src": image_data(path), "caption": _curve_caption(layout, conditions)})
    grid = sweep.manifest.get("grid", {})
    points = [", ".join(f"{k}={v}" for k, v in p.items()) for p in sweep.manifest.get("points", [])]
    return {
        "title": f"{sweep.name}: {sweep.manifest.get('description', '')}" if titled else "",
        "setup": "; ".join([*(f"{k} = {v}" for k, v in grid.items()), *(f"({p})" for p in points)])
        + f"; {sweep.manifest.get('replications', '?')} runs each, sweep seed "
        + f"{sweep.manifest.get('seed', '?')}",
        "figures": shown,
        "name": sweep.name,
        "labels": {m: label(layout, m).replace("(kJ)", "(J)") for m in runs.columns},
        **_tests(runs, layout, _seed(sweep), conditions, warned, cut),
        "sections": _factor_sections(runs, layout, published, conditions, cut) if len(runs) else [],
        "macro": _macro(sweep, cls) if len(runs) else None,
        "failed": table(failed.drop(columns=["traceback"], errors="ignore").head(20))
        if len(failed)
        else None,
        "n_failed": len(failed),
    }


def _macro(sweep: _Sweep, cls: type | None) -> dict | None:
    """The paper's macroscopic-model fit of a sweep that kept its counts over time, when the
    model declares the lambda regressions (``MACRO.regression``): the fitting methods side by
    side with the paper's figures, and the per-condition fits. None otherwise.
    """
    from analysis.fit import analyse, methods, read_runs

    spec = None if cls is None else cls.MACRO
    if spec is None or spec.regression is None or not (sweep.folder / "series").is_dir():
        return None
    try:
        summaries, counts, conditions = read_runs(sweep.folder)
        result = analyse(summaries, counts, spec, conditions, heldout=False)
    except ConfigError as err:
        return {"note": f"not fitted: {err}", "methods": None, "fits": None}
    shown = [c for c in ("condition", "runs", "w", "b", "a0", "alpha6", "a0_reg", "alpha6_reg",
                         "rmsd_w_reg", "rmsd_b_reg", "rmsd_w", "rmsd_b", "rmsd_w_fit",
                         "rmsd_b_fit") if c in result["table"]]  # fmt: skip
    return {
        "note": " ".join(result["notes"]),
        "methods": table(methods(result["table"], spec), digits=3, text_columns=("method",)),
        "fits": table(result["table"][shown], digits=4, text_columns=("condition",)),
    }


def _curve_caption(layout: ReportLayout, conditions: list[str]) -> str:
    spread = "standard deviation" if layout.curve_spread == "sd" else "standard error"
    by = ", ".join(conditions) or "all runs"
    return f"Mean ± {spread} over the runs of each condition ({by}) against {layout.curve_x}."


def _claims(
    sweeps: list[_Sweep],
    claims: list[Claim],
    defaults: dict,
    varied: Sequence[str] = (),
    cut_ends: Sequence[str] = (),
) -> list[dict] | None:
    """Every claim with ours and its verdict on all the sweeps' fault-free runs (at the
    defaults of the parameters a design varies, ``varied``; none judged on runs cut short,
    ``cut_ends``).
    """
    if not claims:
        return None
    # the papers' claims are about swarms without injected faults
    runs = fault_free(stats.ok_runs(pd.concat([s.runs for s in sweeps], ignore_index=True)))
    frames = [s.samples for s in sweeps if not s.samples.empty]
    samples = None
    if frames:
        samples = pd.concat(frames, ignore_index=True)
        params = runs.drop(columns=[c for c in samples.columns if c != "run_id" and c in runs])
        samples = samples.merge(params, on="run_id")
    return judge_claims(runs, samples, claims, defaults, varied, cut_ends)


def _model(manifest: dict) -> tuple[type | None, str | None]:
    """The sweep's model class, or None and why (a model no longer importable here)."""
    try:
        return model_class(manifest.get("target") or manifest["model"]), None
    except (ABMError, KeyError) as exc:
        return None, f"the model of this sweep cannot be loaded here ({exc}); no published numbers"


def _meta(sweeps: list[_Sweep], every: pd.DataFrame) -> list:
    failed = int((every["status"] == "failed").sum()) if "status" in every else 0
    rows = [
        ("model", sweeps[0].manifest.get("model", "?")),
        ("sweeps", ", ".join(f"{s.name} ({len(s.runs)} runs)" for s in sweeps)),
        ("runs finished / failed", f"{len(every) - failed} / {failed}"),
    ]
    if len(sweeps) == 1:
        manifest = sweeps[0].manifest
        rows += [
            ("grid", "; ".join(f"{k} = {v}" for k, v in manifest.get("grid", {}).items())),
            ("replications", manifest.get("replications", "?")),
            ("sweep seed", manifest.get("seed", "?")),
        ]
    if "end_reason" in every:
        kinds = every["end_reason"].dropna().astype(str).str.split(":").str[0].value_counts()
        # runs that hit the time limit are outliers in every mean: the reader must see them
        rows.append(("runs ended by", ", ".join(f"{k} {n}" for k, n in kinds.items())))
    rows += [
        ("data", ", ".join(str(s.folder.resolve()) for s in sweeps)),
        ("generated", datetime.datetime.now().isoformat(timespec="seconds")),
    ]
    return rows


def _factors(runs: pd.DataFrame, layout: ReportLayout) -> list[str]:
    return [f for f in (layout.x, layout.hue) if f is not None and f in runs]


def _for_this_grid(
    layout: ReportLayout, runs: pd.DataFrame, swept: list[str], cls: type | None
) -> ReportLayout:
    """The layout made to show what this grid swept and measured: its metrics those the runs
    measured (:func:`_metrics`); against the first swept key that varies when the layout's
    ``x`` does not (a custom grid of names, e.g. arenas); every column labelled with its unit.
    """
    x = layout.x
    if x is None:
        x = next((k for k in swept if k in runs and runs[k].nunique() > 1), None)
    units = {} if cls is None else cls.SUMMARY_UNITS
    labels = {
        column: f"{column.replace('_', ' ')} ({unit})"
        for column in runs.columns
        if (unit := unit_of(column, units)) and unit not in ("text", "id", "flag")
    }
    layout = replace(layout, x=x, labels={**labels, **layout.labels})
    return replace(layout, metrics=tuple(_metrics(runs, layout)))


def _censored_here(runs: pd.DataFrame, cls: type | None) -> dict[str, str]:
    """The model's censored metrics (``CENSORED``) that the end of some of these runs cut
    short, each with why ("4 of 8 runs ended by time limit"): their values are lower bounds,
    so the statistics below refuse them, as the comparison does.
    """
    cut = {}
    for spec in () if cls is None else cls.CENSORED:
        if spec.metric in runs:
            hit = int(censored_mask(runs, spec).sum())
            if hit:
                cut[spec.metric] = (
                    f"{hit} of {len(runs)} runs censored ({censoring_causes(runs, spec)}): "
                    f"their {spec.metric} is only a lower bound"
                )
    return cut


def _metrics(runs: pd.DataFrame, layout: ReportLayout) -> list[str]:
    """The layout's numeric metrics these runs measured (not NaN in every run); when they
    measured none of them (a custom grid the paper never ran, runs cut before the model's own
    metrics exist), the common summary keys they did measure, so that every sweep shows its
    metrics against its swept keys.
    """

    def measured(columns) -> list[str]:
        return [m for m in dict.fromkeys(columns) if m in runs and _numeric(runs, m)
                and runs[m].notna().any()]  # fmt: skip

    declared = measured([*layout.metrics, *([layout.total] if layout.total else [])])
    return declared or measured(COMMON_METRICS)


@contextlib.contextmanager
def _noted(notes: list[str] | None = None) -> Iterator[list[str]]:
    """Record the warnings numpy, statsmodels, pandas or matplotlib raise inside, as notes for
    the page (each once), instead of letting them reach the terminal.
    """
    notes = [] if notes is None else notes
    with warnings.catch_warnings(record=True) as caught, np.errstate(all="warn"):
        warnings.simplefilter("always")
        yield notes
    for w in caught:
        text = f"{w.category.__name__}: {w.message}"
        if text not in notes:
            notes.append(text)


def _tests(
    runs: pd.DataFrame,
    layout: ReportLayout,
    seed: int,
    conditions: list[str],
    notes: list[str],
    cut: dict[str, str],
) -> dict:
    """The block's ANOVAs and correlation, and every warning raised while drawing and testing;
    a metric some runs censor (``cut``) is refused, not tested on its lower bounds.
    """
    if not len(runs):
        return {"anova": [], "correlation": None, "warnings": notes}
    with _noted(notes):
        return {"anova": _anova(runs, layout, seed, conditions, cut), "warnings": notes,
                "correlation": _correlation(runs, layout, seed, cut)}  # fmt: skip


def _seed(sweep: _Sweep) -> int:
    """The seed of the report's bootstrap intervals: the sweep's own seed (0 when unknown)."""
    seed = sweep.manifest.get("seed")
    return seed if isinstance(seed, int) and seed >= 0 else 0


def _anova(
    runs: pd.DataFrame,
    layout: ReportLayout,
    seed: int,
    conditions: Sequence[str] = (),
    cut: dict[str, str] | None = None,
) -> list[stats.Anova]:
    """The ANOVA of each metric over the layout's factors (x, hue), or why it was refused;
    then, when the grid swept other keys (at most two, e.g. the hierarchy's W and S beside
    its drawn N = 1 + W + W S), over those; only over those when they split the runs into the
    same conditions (a star arm against the hierarchy: N follows the topology), one test.
    """
    factors = _factors(runs, layout)
    swept = [k for k in conditions if k in runs and _groupable(runs, [k])[k].nunique() > 1]
    sets = [factors] if factors else []
    if swept and len(swept) <= 2 and set(swept) != set(factors):
        if factors and _same_partition(runs, factors, swept):  # one test, named by the sweep
            sets = [swept]
        else:
            sets.append(swept)
    grouped = _groupable(runs, swept)
    cut = cut or {}
    return [
        Anova(metric, tuple(chosen), None, cut[metric])
        if metric in cut
        else stats.anova(grouped, metric, chosen, seed=seed)
        for chosen in sets
        for metric in _metrics(runs, layout)
    ]


def _same_partition(runs: pd.DataFrame, first: list[str], second: list[str]) -> bool:
    """Whether two sets of factors split the runs into the same conditions (a star arm's N
    against its topology): an ANOVA over each would be one test counted twice by Holm.
    """
    grouped = _groupable(runs, list(dict.fromkeys([*first, *second])))
    a = grouped.groupby(first, dropna=False).ngroup()
    b = grouped.groupby(second, dropna=False).ngroup()
    pairs = pd.DataFrame({"a": a, "b": b}).drop_duplicates()
    return len(pairs) == a.nunique() == b.nunique()


def _correlation(
    runs: pd.DataFrame, layout: ReportLayout, seed: int, cut: dict[str, str] | None = None
) -> dict | None:
    """Pearson's r of the layout's two correlated columns over the condition means (None when
    a column is missing or censored in some run).
    """
    if not (layout.correlate and all(c in runs for c in layout.correlate)):
        return None
    if any(c in (cut or {}) for c in layout.correlate):
        return None
    x, y = layout.correlate
    return {"x": x, "y": y, **stats.pearson(runs, x, y, by=_factors(runs, layout), seed=seed)}


def _statistics(blocks: list[dict], out: Path) -> dict:
    """Every test of the page in one table (Holm over all of them), written as
    ``statistics.csv`` beside the HTML; each block gets its ANOVA items and correlation line.
    """
    anovas = [(block["name"], result) for block in blocks for result in block["anova"]]
    extra = [
        row
        for block in blocks
        if block["correlation"] is not None
        for row in pearson_rows(block["name"], block["correlation"]["x"],
                                block["correlation"]["y"], block["correlation"])
    ]  # fmt: skip
    frame = statistics_frame(anovas, extra)
    path = write_statistics(frame, out.parent / "statistics.csv")
    for block in blocks:
        block["anova"] = anova_items(frame, block["name"], block["labels"])
        block["correlation"] = _correlation_note(frame, block["name"])
    return {"tests": tests_on_page(frame), "csv": path.name, "resamples": RESAMPLES}


def _correlation_note(frame: pd.DataFrame, sweep: str) -> str | None:
    rows = frame[(frame["sweep"] == sweep) & (frame["test"] == "Pearson r")]
    if rows.empty:
        return None
    row = rows.iloc[0]
    x, y = row["metric"].split(" ~ ")
    if not row["computed"]:
        return f"Pearson r of the condition means of {x} and {y}: not computed: {row['reason']}."
    return (
        f"Pearson r of the condition means of {x} and {y} across {row['source']}: "
        f"r = {row['r']:.3f} (95 % bootstrap interval {row['ci_low']:.3f} to "
        f"{row['ci_high']:.3f}; df = {row['df']:.0f}, p = {row['p']:.2g}, "
        f"Holm-adjusted p = {row['p_holm']:.2g})."
    )


def _groupable(runs: pd.DataFrame, factors: list[str]) -> pd.DataFrame:
    """``runs`` with every factor column made a valid group key: a points-only key missing (NaN)
    in the other points' runs reads "(default)" (the runs are kept), and a list-valued key
    (e.g. ``fault_states``, read back from Parquet as arrays) reads as its text.
    """

    def key(value: object) -> object:
        if isinstance(value, np.ndarray | list | tuple):
            return str(list(value))
        return "(default)" if pd.isna(value) else value

    return runs.assign(**{f: runs[f].astype(object).map(key) for f in factors if f in runs})


def _factor_sections(
    runs: pd.DataFrame,
    layout: ReportLayout,
    published: list[Published],
    conditions: list[str] | None = None,
    cut: dict[str, str] | None = None,
) -> list[dict]:
    """Percent changes, optimum, Pearson's r and condition means (titles, notes, tables); the
    means are per condition of every swept parameter (``conditions``), so no factor is
    averaged over. Metrics some runs censor (``cut``) get no percent change and no optimum;
    their condition means are marked as lower bounds.
    """
    sections = []
    x, hue = layout.x, layout.hue
    cut = cut or {}
    metrics = _metrics(runs, layout)
    changed = [m for m in metrics if m not in cut]
    if x is not None and _numeric(runs, x) and metrics:
        values = sorted(runs[x].unique())
        pairs = [(values[0], values[-1])]
        pairs += [
            (p.a, p.b)
            for p in published
            if p.measure == "change" and p.factor == x and p.a in values and p.b in values
        ]
        pairs = list(dict.fromkeys(pairs))
        refused = "; ".join(f"not computed for {m}: {cut[m]}" for m in metrics if m in cut)
        changes = (
            stats.percent_change_table(runs, pairs, changed, factor=x, by=hue)
            if changed
            else pd.DataFrame()
        )
        if not changes.empty or refused:
            changes = changes.rename(columns={"change": "change (%)"})
            sections.append({"title": f"Percent changes between values of {x}", "note": refused,
                             "table": table(changes) if not changes.empty else None})  # fmt: skip
        optimum = [m for m in layout.optimum if m in runs]
        if any(m in cut for m in optimum):
            why = "; ".join(cut[m] for m in optimum if m in cut)
            sections.append({"title": f"Optimal {x}", "note": f"not computed: {why}",
                             "table": None})  # fmt: skip
        elif optimum:
            best = stats.optimal_period(runs, dict.fromkeys(optimum, 1.0), factor=x, by=hue)
            if not best.empty:
                note = (
                    f"Cubic interpolation of the means of {', '.join(optimum)} over {x}, each "
                    "normalised to [0, 1], summed with equal weights; the optimum is the minimum "
                    "(Stirling et al. Sect. 5). analysis.stats.optimal_period takes other weights."
                )
                sections.append({"title": f"Optimal {x}", "note": note, "table": table(best)})
    factors = list(dict.fromkeys([*_factors(runs, layout), *(conditions or [])]))
    extra = [m for m in ("coverage_area", "energy_total", *layout.stacked) if m in runs]
    shown = [m for m in dict.fromkeys([*metrics, *extra]) if _numeric(runs, m)]
    if shown:
        means = stats.condition_means(_groupable(runs, factors), metrics=shown, by=factors)
        wide = (
            means.pivot_table(index=factors, columns="metric", values="mean")
            .rename_axis(columns=None)
            .reset_index()
            if factors
            else means[["metric", "mean", "sem", "n"]]
        )
        # the means are of the runs' own values: energies in J even where a figure draws kJ
        units = {m: label(layout, m).replace("(kJ)", "(J)") for m in shown}
        note = "; ".join(f"{m}: {text}" for m, text in units.items() if text != m)
        bounds = [m for m in shown if m in cut]
        if bounds:
            note += f". Lower bounds only (runs cut short): {', '.join(bounds)}"
        sections.append({"title": "Condition means", "note": note,
                         "table": table(wide.replace({np.nan: None}), digits=4)})  # fmt: skip
    return sections
