"""Seaborn figures of the kinds in Stirling et al. (2010), from tidy sweep results.

* :func:`metric_vs_period`: mean +- standard error of a metric against the inter-launch period,
  one line per complexity (Figs. 6, 8, 10a);
* :func:`period_panels`: coverage time, flight time and collisions side by side (Fig. 6);
* :func:`energy_components`: stacked mean flight, beacon and ground energy per period, one
  panel per complexity, with the standard error of the total (Figs. 7, 9, 10b);
* :func:`hover_energy`: energy of attached vs hovering beacons (end of Sect. 4).
"""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
import seaborn as sns  # noqa: E402

from analysis.stats import ok_runs  # noqa: E402

__all__ = [
    "LABELS",
    "metric_vs_period",
    "period_panels",
    "energy_components",
    "hover_energy",
    "save_figures",
]

#: Axis labels (with units) of the summary metrics.
LABELS = {
    "coverage_time": "Coverage time (s)",
    "coverage_area": "Coverage area (% of free area)",
    "flight_time": "Total swarm flight time (s)",
    "collisions": "Collisions per run",
    "energy_total": "Total swarm energy (kJ)",
    "energy_flight": "Flight energy (kJ)",
    "energy_beacon": "Beacon energy (kJ)",
    "energy_ground": "Ground energy (kJ)",
    "launch_period": "Inter-launch period (s)",
}
_ORDER = ("low", "medium", "high")
_ENERGY = ("energy_flight", "energy_beacon", "energy_ground")
_COLOURS = {"energy_flight": "#d1495b", "energy_beacon": "#00798c", "energy_ground": "#edae49"}


def _complexities(df: pd.DataFrame) -> list[str]:
    present = list(dict.fromkeys(df["complexity"])) if "complexity" in df else []
    return [c for c in _ORDER if c in present] + [c for c in present if c not in _ORDER]


def _legend_title(df: pd.DataFrame) -> str:
    worlds = set(df["world"]) if "world" in df else set()
    if worlds == {"open"}:
        return "Obstacle density"
    return "Corridor complexity" if worlds == {"corridor"} else "Complexity"


def _scaled(df: pd.DataFrame, metric: str) -> pd.Series:
    values = df[metric].astype(float)
    return values / 1000.0 if metric.startswith("energy") else values


def metric_vs_period(df: pd.DataFrame, metric: str, ax=None) -> plt.Axes:
    """Mean +- standard error of ``metric`` against the launch period, one line per complexity."""
    runs = ok_runs(df).copy()
    runs["_y"] = _scaled(runs, metric)
    if ax is None:
        _fig, ax = plt.subplots(figsize=(5, 4))
    hue_order = _complexities(runs)
    sns.lineplot(
        data=runs,
        x="launch_period",
        y="_y",
        hue="complexity" if len(hue_order) > 1 else None,
        hue_order=hue_order if len(hue_order) > 1 else None,
        errorbar="se",
        err_style="bars",
        marker="o",
        err_kws={"capsize": 3},
        ax=ax,
        color=None if len(hue_order) > 1 else "#00798c",
    )
    periods = sorted(runs["launch_period"].unique())
    ax.set_xticks(periods)
    ax.set_xticklabels([f"{p:g}" for p in periods])
    ax.set_xlabel(LABELS["launch_period"])
    ax.set_ylabel(LABELS.get(metric, metric))
    ax.set_ylim(bottom=0)
    if ax.get_legend() is not None:
        ax.legend(title=_legend_title(runs), frameon=False)
    ax.grid(alpha=0.3)
    return ax


def period_panels(
    df: pd.DataFrame, metrics=("coverage_time", "flight_time", "collisions")
) -> plt.Figure:
    """Several metrics against the launch period, side by side (mean +- standard error)."""
    fig, axes = plt.subplots(1, len(metrics), figsize=(4.8 * len(metrics), 4.2), squeeze=False)
    for ax, metric in zip(axes[0], metrics, strict=True):
        metric_vs_period(df, metric, ax=ax)
        if ax is not axes[0][-1] and ax.get_legend() is not None:
            ax.get_legend().remove()
    n = ok_runs(df).groupby(["launch_period", "complexity"]).size()
    runs_text = f"{n.min()}" if n.min() == n.max() else f"{n.min()}–{n.max()}"
    fig.suptitle(f"Mean ± standard error over {runs_text} runs per condition", fontsize=11)
    fig.tight_layout()
    return fig


def energy_components(df: pd.DataFrame) -> plt.Figure:
    """Stacked mean flight, beacon and ground energy (kJ) per period; one panel per complexity."""
    runs = ok_runs(df)
    levels = _complexities(runs)
    fig, axes = plt.subplots(
        1, len(levels), figsize=(4.6 * len(levels), 4.2), sharey=True, squeeze=False
    )
    for ax, level in zip(axes[0], levels, strict=True):
        part = runs[runs["complexity"] == level]
        means = part.groupby("launch_period")[list(_ENERGY)].mean() / 1000.0
        sem = part.groupby("launch_period")["energy_total"].sem().fillna(0.0) / 1000.0
        x = np.arange(len(means))
        bottom = np.zeros(len(means))
        for name in _ENERGY:
            label = LABELS[name].replace(" (kJ)", "")
            ax.bar(x, means[name], bottom=bottom, color=_COLOURS[name], label=label, width=0.7)
            bottom += means[name].to_numpy()
        ax.errorbar(x, bottom, yerr=sem.to_numpy(), fmt="none", ecolor="black", capsize=3)
        ax.set_xticks(x)
        ax.set_xticklabels([f"{p:g}" for p in means.index])
        ax.set_xlabel(LABELS["launch_period"])
        ax.set_title(f"{_legend_title(part)}: {level}")
        ax.grid(axis="y", alpha=0.3)
    axes[0][0].set_ylabel("Mean swarm energy (kJ)")
    handles, labels = axes[0][0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", ncol=3, frameon=False,
               title="Energy component (error bar: standard error of the total)")  # fmt: skip
    fig.tight_layout(rect=(0, 0.12, 1, 1))
    return fig


def hover_energy(df: pd.DataFrame) -> plt.Figure:
    """Mean energy components (kJ) with beacons attached to the ceiling vs hovering."""
    runs = ok_runs(df)
    means = runs.groupby("hover_beacons")[list(_ENERGY)].mean() / 1000.0
    fig, ax = plt.subplots(figsize=(5, 4))
    bottom = np.zeros(len(means))
    x = np.arange(len(means))
    for name in _ENERGY:
        ax.bar(x, means[name], bottom=bottom, color=_COLOURS[name], width=0.6,
               label=LABELS[name].replace(" (kJ)", ""))  # fmt: skip
        bottom += means[name].to_numpy()
    ax.set_xticks(x)
    ax.set_xticklabels(["hovering" if h else "attached" for h in means.index])
    ax.set_xlabel("Beacons")
    ax.set_ylabel("Mean swarm energy (kJ)")
    ax.legend(frameon=False)
    ax.grid(axis="y", alpha=0.3)
    fig.tight_layout()
    return fig


def save_figures(df: pd.DataFrame, folder: str | Path, dpi: int = 110) -> dict[str, Path]:
    """Draw every figure the results support and save them as PNG in ``folder``."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    runs = ok_runs(df)
    figures = {}
    if len(runs) and runs["launch_period"].nunique() > 1:
        figures["periods"] = period_panels(runs)
        figures["energy"] = energy_components(runs)
    if "hover_beacons" in runs and runs["hover_beacons"].nunique() > 1:
        figures["hover"] = hover_energy(runs)
    paths = {}
    for name, fig in figures.items():
        path = folder / f"{name}.png"
        fig.savefig(path, dpi=dpi)
        plt.close(fig)
        paths[name] = path
    return paths
