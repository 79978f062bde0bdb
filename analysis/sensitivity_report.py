"""The report's part for a sweep with a design: the sensitivity ranking, its figures, its table,
and ``sensitivity.csv`` beside the HTML (:mod:`analysis.sensitivity` computes the indices).

A design sweep has no grid to draw or test factor by factor (its parameters take hundreds of
values, one per sample row), so its block in the report is this one instead of the grid's
figures, ANOVAs and condition means.
"""

from pathlib import Path

import pandas as pd

from abm.params import param_fields
from analysis.html import image_data, table
from analysis.sensitivity import CONF_LEVEL, HEADLINE, RESAMPLES, design_data, indices, ranking
from analysis.sensitivity import save_figures as save_sensitivity_figures
from analysis.sweep.design import MORRIS_LEVELS

__all__ = ["design_block", "share_text", "write_csv"]

_CAPTIONS = {
    "ranking": "Ranking: each parameter's {what} on the whole sample, per output metric (right) "
    "and averaged over the metrics (left); most influential first.",
    "convergence": "Convergence: {index} of the most influential parameters on nested leading "
    "subsets of the sample, with {conf:.0%} bootstrap intervals; settled indices stay flat.",
}
_WHAT = {
    "morris": "Morris mu* (scaled to the metric's largest)",
    "sobol": "Sobol' total index ST",
    "lhs": "first-order index S1 (RBD-FAST)",
}
_METHOD = {
    "morris": "Morris elementary effects (SALib, {levels} levels): an effect is the change of "
    "the metric over a step of 2/3 of the parameter's range divided by that step (the metric's "
    "unit per whole range); mu* is their mean absolute value, sigma their standard deviation "
    "(interactions, non-linearity)",
    "sobol": "Sobol' indices (SALib, Saltelli sampling, Jansen's ST estimator)",
    "lhs": "RBD-FAST first-order indices (SALib, M = 10 harmonics) on a Latin hypercube",
}


def design_block(
    name: str, manifest: dict, runs: pd.DataFrame, cls: type | None, folder: Path, title: str
) -> dict:
    """The report block of one design sweep (the keys the page template reads).

    Args:
        name: the sweep's name.
        manifest: its ``sweep.json``.
        runs: every row (finished and failed).
        cls: the model class (its censored metrics, and the metrics its report layout draws
            first, with its total); None when it cannot be imported.
        folder: where its figures go.
        title: the block's heading ("" for a single sweep).

    """
    censored = () if cls is None else cls.CENSORED
    first: tuple = ()
    if cls is not None and cls.REPORT is not None:  # the paper's metrics, its total energy too
        first = (*cls.REPORT.metrics, *((cls.REPORT.total,) if cls.REPORT.total else ()))
    design = manifest["design"]
    kind = design["kind"]
    names = () if cls is None else [f.name for f in param_fields(cls.Params)]
    data = design_data(manifest, runs, censored, names)
    frame = indices(data) if data.outputs else pd.DataFrame()
    failed = runs[runs["status"] == "failed"] if "status" in runs else runs[:0]
    figures = []
    if len(frame):
        paths = save_sensitivity_figures(frame, kind, folder, first=first)
        for key, path in paths.items():
            figures.append(
                {
                    "src": image_data(path),
                    "caption": _CAPTIONS[key].format(
                        what=_WHAT[kind], index=HEADLINE[kind], conf=CONF_LEVEL
                    ),
                }
            )
    params = ", ".join(
        f"{k} in {v['range']}" if "range" in v else f"{k} in {v['choices']}"
        for k, v in design["parameters"].items()
    )
    fixed = "; ".join(f"{k} = {v[0]}" for k, v in manifest.get("grid", {}).items())
    notes = list(data.notes)
    if data.censored:
        notes += [
            f"{m}: {share_text(share)} of runs report a lower bound (the run's end cut it "
            "short); its indices describe the reported value"
            for m, share in data.censored.items()
            if share > 0
        ]
    return {
        "title": title,
        "setup": f"{kind} design, n = {design['n']}, design seed {design['seed']}: {params}"
        + (f"; fixed: {fixed}" if fixed else "")
        + f"; {manifest.get('replications', 1)} run(s) per point, sweep seed "
        + f"{manifest.get('seed', '?')}",
        "figures": figures,
        "name": name,
        "labels": {},
        "anova": [],
        "correlation": None,
        "warnings": [],
        "sections": [],
        "macro": None,
        "failed": table(failed.drop(columns=["traceback"], errors="ignore").head(20))
        if len(failed)
        else None,
        "n_failed": len(failed),
        "sensitivity": {
            "method": _METHOD[kind].replace("{levels}", str(MORRIS_LEVELS))
            + f"; intervals: {CONF_LEVEL:.0%} bootstrap ({RESAMPLES} resamples).",
            "notes": notes,
            "table": _table(frame, kind, first) if len(frame) else None,
            "frame": frame.assign(sweep=name, kind=kind) if len(frame) else frame,
        },
    }


def share_text(share: float) -> str:
    """A share of runs as a percentage that is never "0%" for a share above 0 (2 of 764
    censored runs read "0%" beside the note that they cut the metric short).
    """
    return f"{share:.0%}" if share >= 0.01 or share == 0 else f"{share:.1%}"


def _table(frame: pd.DataFrame, kind: str, first: tuple = ()) -> str:
    """Parameters by rank, each metric's headline index ``value +- half`` (Morris: and sigma),
    the metrics of ``first`` (the model's report metrics) in the first columns.
    """
    order = ranking(frame, kind, first)
    full = frame[frame["full"]].set_index(["parameter", "metric", "index"])
    rows = []
    for rank, parameter in enumerate(order.index, start=1):
        row = {"rank": rank, "parameter": parameter}
        for metric in order.columns:
            value = full.loc[(parameter, metric, HEADLINE[kind])]
            cell = f"{value['value']:.3g} ± {value['half']:.2g}"
            if kind == "morris":
                cell += f" (σ {full.loc[(parameter, metric, 'sigma')]['value']:.3g})"
            elif kind == "sobol":
                s1 = full.loc[(parameter, metric, "S1")]
                cell += f"; S1 {s1['value']:.3g} ± {s1['half']:.2g}"
            row[metric] = cell
        rows.append(row)
    return table(pd.DataFrame(rows), text_columns=("parameter", *order.columns))


def write_csv(blocks: list[dict], path: Path) -> Path | None:
    """Every design block's indices as one CSV (``sensitivity.csv``); None without any."""
    frames = [b["sensitivity"].pop("frame") for b in blocks if b.get("sensitivity")]
    frames = [f for f in frames if len(f)]
    if not frames:
        return None
    columns = ["sweep", "kind", "metric", "parameter", "index", "value", "half", "n", "full",
               "censored_share", "set_by"]  # fmt: skip
    pd.concat(frames, ignore_index=True)[columns].to_csv(path, index=False)
    return path
