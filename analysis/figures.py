"""Seaborn figures of a sweep's results, of the kinds the papers draw, for any model.

What is drawn comes from the model's :class:`abm.published.ReportLayout` (or, for a model
without one, from the swept parameters):

* :func:`metric_panels`: mean +- standard error of each metric against the swept parameter
  ``x``, one line per value of ``hue`` (Stirling et al. Figs. 6, 8, 10a; Arnaldo et al.
  Table 1 as curves); a metric the end of some runs censors (the model's ``CENSORED``) is
  drawn as its Kaplan-Meier median per condition instead, with the conditions whose median
  is not reached marked at their bound, since a mean of lower bounds is no estimate;
* :func:`stacked_bars`: components (e.g. energy per mode) stacked per ``x`` value, one panel per
  ``hue`` value, with the standard error of the total (Stirling et al. Figs. 7, 9, 10b);
* :func:`compare_bars`: one metric for each value of a compared parameter (hover vs attach);
* :func:`curve_panels`: the model's time series (e.g. coverage against time), mean and spread
  over the runs of each condition (Purohit et al. Figs. 5-9, 11, 15).
"""

from collections.abc import Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
import seaborn as sns  # noqa: E402

from abm.published import Censored, ReportLayout  # noqa: E402
from analysis.censoring import censored_mask, survival  # noqa: E402
from analysis.stats import ok_runs  # noqa: E402

__all__ = [
    "compare_bars",
    "curve_panels",
    "label",
    "metric_panels",
    "save_curves",
    "save_figures",
    "stacked_bars",
]

_BAR_COLOURS = ("#d1495b", "#00798c", "#edae49", "#66a182", "#2e4057", "#8d96a3")


#: The most x values that each get a tick of their own (e.g. 30 robot totals would overlap).
MAX_TICKS = 12


def label(layout: ReportLayout, column: str) -> str:
    """The axis label of ``column`` (the layout's, else the column's name)."""
    return layout.labels.get(column, column.replace("_", " "))


def _values(df: pd.DataFrame, layout: ReportLayout, column: str) -> pd.Series:
    """The column's values, in kJ when its label says so."""
    values = df[column].astype(float)
    return values / 1000.0 if "(kJ)" in label(layout, column) else values


def _hue_levels(df: pd.DataFrame, layout: ReportLayout) -> list:
    if layout.hue is None or layout.hue not in df:
        return []
    present = list(dict.fromkeys(df[layout.hue]))
    ordered = [h for h in layout.hue_order if h in present]
    return ordered + [h for h in present if h not in ordered]


def metric_panels(
    df: pd.DataFrame, layout: ReportLayout, censored: Sequence[Censored] = ()
) -> plt.Figure:
    """Each of ``layout.metrics`` against ``layout.x`` (mean +- standard error), side by side;
    a metric some of these runs censor (``censored``) as its Kaplan-Meier medians.
    """
    runs, names = _positions(ok_runs(df), layout.x)
    metrics = [m for m in layout.metrics if m in runs]
    hues = _hue_levels(runs, layout)
    cut = {c.metric: c for c in censored if c.metric in metrics and censored_mask(runs, c).any()}
    fig, axes = plt.subplots(1, len(metrics), figsize=(4.8 * len(metrics), 4.2), squeeze=False)
    for ax, metric in zip(axes[0], metrics, strict=True):
        if metric in cut:
            _km_medians(ax, runs, layout, cut[metric], hues)
        else:
            data = runs.assign(_y=_values(runs, layout, metric))
            sns.lineplot(
                data=data,
                x=layout.x,
                y="_y",
                hue=layout.hue if len(hues) > 1 else None,
                hue_order=hues if len(hues) > 1 else None,
                errorbar="se",
                err_style="bars",
                marker="o",
                err_kws={"capsize": 3},
                ax=ax,
                color=None if len(hues) > 1 else "#00798c",
                linestyle="" if names else "-",  # names in alphabetical order: no line between
            )
        xs = sorted(runs[layout.x].unique())
        if len(xs) <= MAX_TICKS:  # a tick per condition; beyond that matplotlib's own ticks
            ticks = [names[int(x)] if names else f"{x:g}" for x in xs]
            ax.set_xticks(xs)
            # long labels (small rates such as 0.0005) would run into each other: slant them
            crowded = sum(len(t) for t in ticks) > 24
            ax.set_xticklabels(
                ticks, rotation=40 if crowded else 0, ha="right" if crowded else "center"
            )
        ax.set_xlabel(label(layout, layout.x))
        ax.set_ylabel(label(layout, metric))
        ax.set_ylim(bottom=0)
        ax.grid(alpha=0.3)
        if ax.get_legend() is not None:
            if ax is axes[0][-1]:
                ax.legend(title=label(layout, layout.hue), frameon=False)
            else:
                ax.get_legend().remove()
    groups = [layout.x, *([layout.hue] if len(hues) > 1 else [])]
    n = runs.groupby(groups).size()
    runs_text = f"{n.min()}" if n.min() == n.max() else f"{n.min()}–{n.max()}"
    km = "Kaplan-Meier median (△: fewer than half reached it; the median is at least this)"
    if len(cut) == len(metrics):
        title = f"{km}, over {runs_text} runs per condition"
    else:
        title = f"Mean ± standard error over {runs_text} runs per condition"
        title += f"; censored metrics: {km}" if cut else ""
    fig.suptitle(title, fontsize=11)
    fig.tight_layout()
    return fig


def _km_medians(
    ax: plt.Axes, runs: pd.DataFrame, layout: ReportLayout, spec: Censored, hues: list
) -> None:
    """The Kaplan-Meier median of a censored metric per ``x`` value, one line per hue; where
    fewer than half the runs reached the target the median is unknown, and an open triangle
    marks the largest censored bound (the median is at least that).
    """
    scale = 1 / 1000.0 if "(kJ)" in label(layout, spec.metric) else 1.0
    palette = sns.color_palette(n_colors=max(1, len(hues)))
    for i, hue in enumerate(hues if len(hues) > 1 else [None]):
        part = runs if hue is None else runs[runs[layout.hue] == hue]
        colour = palette[i] if hue is not None else "#00798c"
        reached, unknown = [], []
        for x, group in part.groupby(layout.x):
            km = survival(group, spec)
            if km.median is not None:
                reached.append((x, km.median * scale))
            elif km.bound is not None:
                unknown.append((x, km.bound * scale))
        if reached:
            xs, ys = zip(*reached, strict=True)
            ax.plot(xs, ys, marker="o", color=colour, label=None if hue is None else str(hue))
        if unknown:
            xs, ys = zip(*unknown, strict=True)
            ax.scatter(xs, ys, marker="^", facecolors="none", edgecolors=colour, s=60, zorder=3)
    ax.set_title(f"{label(layout, spec.metric)}: Kaplan-Meier median", fontsize=9)
    if len(hues) > 1:
        ax.legend(title=label(layout, layout.hue), frameon=False)


def _positions(runs: pd.DataFrame, x: str) -> tuple[pd.DataFrame, list[str]]:
    """``runs`` with a non-numeric ``x`` (names, e.g. arenas) as positions 0, 1, ... and the
    names in that order; a numeric ``x`` unchanged, with no names.
    """
    column = runs[x]
    if pd.api.types.is_numeric_dtype(column) and column.dtype != bool:
        return runs, []
    names = sorted(column.astype(str).unique())
    return runs.assign(**{x: column.astype(str).map(names.index)}), names


def stacked_bars(df: pd.DataFrame, layout: ReportLayout) -> plt.Figure:
    """``layout.stacked`` stacked per ``x`` value; one panel per ``hue`` value."""
    runs = ok_runs(df)
    parts = [c for c in layout.stacked if c in runs]
    hues = _hue_levels(runs, layout) or [None]
    fig, axes = plt.subplots(1, len(hues), figsize=(4.6 * len(hues), 4.2), sharey=True,
                             squeeze=False)  # fmt: skip
    for ax, level in zip(axes[0], hues, strict=True):
        part = runs if level is None else runs[runs[layout.hue] == level]
        scaled = part.assign(**{c: _values(part, layout, c) for c in parts})
        means = scaled.groupby(layout.x)[parts].mean()
        total = scaled[parts].sum(axis=1).groupby(scaled[layout.x]).sem().fillna(0.0)
        x = np.arange(len(means))
        bottom = np.zeros(len(means))
        for colour, name in zip(_BAR_COLOURS, parts, strict=False):
            text = label(layout, name).replace(" (kJ)", "")
            ax.bar(x, means[name], bottom=bottom, color=colour, label=text, width=0.7)
            bottom += means[name].to_numpy()
        ax.errorbar(x, bottom, yerr=total.to_numpy(), fmt="none", ecolor="black", capsize=3)
        if "end_reason" in part:  # a run cut by the time limit accumulated only a lower bound
            reasons = part["end_reason"].fillna("").astype(str)
            cut = reasons.str.startswith("time limit").groupby(part[layout.x]).agg(["sum", "size"])
            for i, (_, row) in enumerate(cut.loc[means.index].iterrows()):
                if row["sum"]:
                    ax.annotate(f"{row['sum']}/{row['size']} cut", (x[i], bottom[i]),
                                xytext=(0, 10), textcoords="offset points", ha="center",
                                fontsize=7, color="#d1495b")  # fmt: skip
            ax.margins(y=0.12)  # room for the note above the tallest bar
        ax.set_xticks(x)
        ax.set_xticklabels([f"{p:g}" if isinstance(p, int | float) else str(p)
                            for p in means.index])  # fmt: skip
        ax.set_xlabel(label(layout, layout.x))
        if level is not None:
            ax.set_title(f"{label(layout, layout.hue)}: {level}")
        ax.grid(axis="y", alpha=0.3)
    unit = "kJ" if "(kJ)" in label(layout, parts[0]) else ""
    axes[0][0].set_ylabel(f"Mean per run {f'({unit})' if unit else ''}".strip())
    handles, labels = axes[0][0].get_legend_handles_labels()
    if any(ax.texts for ax in axes[0]):  # before the layout, which leaves room for it
        fig.suptitle("k/n cut: k of n runs ended by the time limit (sums are lower bounds)",
                     fontsize=8, color="#d1495b")  # fmt: skip
    _legend_below(fig, handles, labels, "Component (error bar: standard error of the total)")
    return fig


def _legend_below(fig: plt.Figure, handles: list, labels: list[str], title: str) -> None:
    """A legend under the panels in as many columns as fit the figure's width (one panel is
    narrower than three labels side by side), the panels laid out above it.
    """
    for ncol in range(len(labels), 0, -1):
        legend = fig.legend(handles, labels, loc="lower center", ncol=ncol, frameon=False,
                            title=title)  # fmt: skip
        fig.canvas.draw()
        box = legend.get_window_extent()
        if box.width <= 0.98 * fig.bbox.width or ncol == 1:
            break
        legend.remove()
    fig.tight_layout(rect=(0, min(0.6, box.height / fig.bbox.height + 0.02), 1, 1))


def compare_bars(df: pd.DataFrame, layout: ReportLayout) -> plt.Figure:
    """Mean of ``layout.compare_metric`` (stacked into ``layout.stacked`` when present) for
    each value of ``layout.compare``.
    """
    runs = ok_runs(df)
    parts = [c for c in layout.stacked if c in runs] or [layout.compare_metric]
    scaled = runs.assign(**{c: _values(runs, layout, c) for c in parts})
    means = scaled.groupby(layout.compare)[parts].mean()
    fig, ax = plt.subplots(figsize=(5, 4))
    bottom = np.zeros(len(means))
    x = np.arange(len(means))
    for colour, name in zip(_BAR_COLOURS, parts, strict=False):
        ax.bar(x, means[name], bottom=bottom, color=colour, width=0.6,
               label=label(layout, name).replace(" (kJ)", ""))  # fmt: skip
        bottom += means[name].to_numpy()
    ax.set_xticks(x)
    ax.set_xticklabels([str(v) for v in means.index])
    ax.set_xlabel(label(layout, layout.compare))
    ax.set_ylabel(f"Mean {label(layout, layout.compare_metric)}")
    if len(parts) > 1:
        ax.legend(frameon=False)
    ax.grid(axis="y", alpha=0.3)
    fig.tight_layout()
    return fig


def save_figures(
    df: pd.DataFrame,
    layout: ReportLayout,
    folder: str | Path,
    dpi: int = 110,
    censored: Sequence[Censored] = (),
) -> dict[str, Path]:
    """Draw every figure the results and the layout support; save them as PNG in ``folder``
    (``censored``: the model's censored metrics, drawn as Kaplan-Meier medians).
    """
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    runs = ok_runs(df)
    figures = {}
    x_varies = layout.x is not None and layout.x in runs and runs[layout.x].nunique() > 1
    if len(runs) and x_varies and any(m in runs for m in layout.metrics):
        figures["metrics"] = metric_panels(runs, layout, censored)
    if len(runs) and x_varies and any(c in runs for c in layout.stacked):
        figures["stacked"] = stacked_bars(runs, layout)
    compare = layout.compare
    if compare and compare in runs and runs[compare].nunique() > 1:
        figures["compare"] = compare_bars(runs, layout)
    paths = {}
    for name, fig in figures.items():
        path = folder / f"{name}.png"
        fig.savefig(path, dpi=dpi)
        plt.close(fig)
        paths[name] = path
    return paths


def condition_labels(data: pd.DataFrame, conditions: list[str]) -> np.ndarray | str:
    """Each row's condition as text, its ``conditions``' values joined by ", " ("3, 0.5"),
    or "all runs" when there are none.

    Built a column at a time: a sweep's samples run to hundreds of thousands of rows, and
    joining them row by row (``agg(", ".join, axis=1)``) took most of a report's time.
    """
    if not conditions:
        return "all runs"
    text = data[conditions[0]].astype(str)
    for column in conditions[1:]:
        text = text + ", " + data[column].astype(str)
    return text.to_numpy()


def curve_panels(
    samples: pd.DataFrame,
    runs: pd.DataFrame,
    layout: ReportLayout,
    metrics: list[str],
    conditions: list[str],
) -> plt.Figure:
    """Each sampled metric against ``layout.curve_x``: one line per condition (the values of
    ``conditions`` a run had), the mean over its runs with a band of one standard deviation
    (``curve_spread="sd"``) or standard error.
    """
    keep = ["run_id", *conditions]
    data = samples.merge(runs[keep], on="run_id") if conditions else samples
    data = data.assign(_condition=condition_labels(data, conditions))
    # lines in the order of the condition values (2, 3, 10 rather than "10", "2", "3")
    ordered = data.drop_duplicates("_condition").sort_values([*conditions, "_condition"])
    order = {c: i for i, c in enumerate(ordered["_condition"])}
    fig, axes = plt.subplots(1, len(metrics), figsize=(5.2 * len(metrics), 4.2), squeeze=False)
    x = layout.curve_x
    for ax, metric in zip(axes[0], metrics, strict=True):
        grouped = data.groupby(["_condition", x], sort=True)[metric]
        table = grouped.agg(["mean", "std", "count"]).reset_index()
        parts = sorted(table.groupby("_condition", sort=False), key=lambda kv: order[kv[0]])
        for condition, part in parts:
            spread = part["std"].fillna(0.0)
            if layout.curve_spread == "se":
                spread = spread / np.sqrt(part["count"])
            (line,) = ax.plot(part[x], part["mean"], lw=1.6, label=condition)
            ax.fill_between(part[x], part["mean"] - spread, part["mean"] + spread,
                            color=line.get_color(), alpha=0.2, lw=0)  # fmt: skip
        ax.set_xlabel(label(layout, x))
        ax.set_ylabel(label(layout, metric))
        ax.grid(alpha=0.3)
    axes[0][-1].legend(title=", ".join(conditions) or None, frameon=False, fontsize=8)
    fig.tight_layout()
    return fig


def save_curves(
    samples: pd.DataFrame,
    runs: pd.DataFrame,
    layout: ReportLayout,
    metrics: list[str],
    conditions: list[str],
    folder: str | Path,
    dpi: int = 110,
) -> Path:
    """Draw :func:`curve_panels` of the runs in ``runs`` and save it as ``curves.png``."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    fig = curve_panels(samples[samples["run_id"].isin(runs["run_id"])], runs, layout, metrics,
                       conditions)  # fmt: skip
    path = folder / "curves.png"
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
    return path
