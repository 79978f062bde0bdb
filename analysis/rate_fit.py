"""``abm fit`` for any model with two or more states: rate equations from its own event log.

The runs of one condition are split by seed: the first ``runs`` fit the per-robot hazards
(:func:`analysis.macroscopic.fit_rates`), the next ``held`` check the mean-field model and its
90 % band on runs it has not seen (:func:`analysis.macroscopic.check_heldout`), and the
well-mixed diagnostic looks at the fitted runs. Everything is written beside a figure:
``rates.csv`` (each transition's hazard family and coefficients with standard errors and 95 %
intervals), ``fit.csv`` (per state: held-out RMSD as a share of the swarm, the RMSD a perfect
model would still show with so few runs, band coverage), ``mixing.csv`` when the runs kept
positions, and one HTML page with the state graph drawn. Rates across swept parameters, fitted
on some grid points and predicting the others, are :mod:`analysis.rate_across`.
"""

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from abm.errors import ConfigError  # noqa: E402
from abm.pools import process_pool  # noqa: E402
from analysis.html import figure_data, image_data, render_page, table  # noqa: E402
from analysis.macroscopic import (  # noqa: E402
    Checks,
    Mixing,
    RateModel,
    RunLog,
    check_heldout,
    check_states,
    collect_runs,
    fit_rates,
    state_graph,
    well_mixed,
)

__all__ = [
    "RateFit",
    "fit_logs",
    "fit_rate_equations",
    "plot_curves",
    "run_logs",
    "summary_lines",
    "write_rate_fit",
]


@dataclass(frozen=True)
class RateFit:
    """A rate-equation fit of one condition and its held-out checks."""

    model: RateModel
    checks: Checks
    mixing: Mixing
    fitted_seeds: tuple[int, ...]
    held_seeds: tuple[int, ...]
    graph: object


def _one_run(model: str, seed: int, params: Mapping[str, object]) -> RunLog:
    return collect_runs(model, [seed], params)[0]


def run_logs(
    target: str, seeds: Sequence[int], params: Mapping[str, object], workers: int = 1
) -> list[RunLog]:
    """The run logs of ``target`` ("module:Class") at ``params``, one per seed, on ``workers``
    local processes.
    """
    if workers > 1:
        with process_pool(workers) as pool:
            n = len(seeds)
            return list(pool.map(_one_run, [target] * n, seeds, [dict(params)] * n))
    return collect_runs(target, seeds, params)


def fit_rate_equations(
    cls: type,
    params: Mapping[str, object],
    seed: int,
    runs: int,
    held: int,
    workers: int = 1,
) -> RateFit:
    """Run ``runs + held`` seeds from ``seed`` on with ``params``, fit the rate equations on
    the first ``runs`` and check them on the rest.

    Raises:
        ConfigError: fewer than two states, fewer than 2 fitted runs or 1 held-out run
            (checked before any run).

    """
    check_states(cls.STATES, cls.__name__)
    if runs < 2:
        raise ConfigError(f"--runs must be at least 2 to fit rates, got {runs}")
    if held < 1:
        raise ConfigError(f"--held must be at least 1, got {held}")
    cls(seed=seed, **dict(params))  # bad parameters stop here, before any run
    seeds = list(range(seed, seed + runs + held))
    logs = run_logs(f"{cls.__module__}:{cls.__qualname__}", seeds, params, workers)
    return fit_logs(logs[:runs], logs[runs:], seeds[:runs], seeds[runs:], seed)


def fit_logs(
    fitted: Sequence[RunLog],
    heldout: Sequence[RunLog],
    fitted_seeds: Sequence[int],
    held_seeds: Sequence[int],
    seed: int,
) -> RateFit:
    """Fit the rate equations on ``fitted`` runs and check them on ``heldout`` ones (the band's
    replicates drawn from ``seed``).
    """
    model = fit_rates(fitted)
    checks = check_heldout(model, heldout, np.random.default_rng(seed))
    return RateFit(model, checks, well_mixed(fitted), tuple(fitted_seeds), tuple(held_seeds),
                   state_graph(fitted))  # fmt: skip


def write_rate_fit(result: RateFit, out: Path, title: str) -> list[Path]:
    """Write rates.csv, fit.csv, mixing.csv (when computable), curves.png and
    rates_report.html into ``out``.
    """
    out.mkdir(parents=True, exist_ok=True)
    checks = result.checks
    paths = [out / "rates.csv", out / "fit.csv"]
    result.model.table().to_csv(paths[0], index=False)
    checks.table.assign(
        swarm_size=checks.swarm_size,
        fitted_runs=len(result.fitted_seeds),
        held_out_runs=len(result.held_seeds),
        speed_ratio_ode=checks.speed_ratio,
        speed_ratio_band=checks.band_speed_ratio,
    ).to_csv(paths[1], index=False)
    if result.mixing.computable:
        paths.append(out / "mixing.csv")
        result.mixing.table.to_csv(paths[-1], index=False)
    paths.append(plot_curves([checks], [""], list(result.model.states), out / "curves.png", title))
    paths.append(_page(result, out / "rates_report.html", title, paths[-1]))
    return paths


def _page(result: RateFit, path: Path, title: str, curves: Path) -> Path:
    """The HTML page: state graph, rates, held-out curves and checks, the mixing diagnostic."""
    checks, mixing = result.checks, result.mixing
    if mixing.computable:
        mixing_text = ("no: a rate follows the local density more than the count the model "
                       "uses" if mixing.flagged else "yes: no rate follows the local density "
                       "more than the count")  # fmt: skip
        mixing_text += f" (neighbourhood radius {mixing.radius:.2f} m)"
    else:
        mixing_text = f"cannot be computed: {mixing.reason}"
    return render_page(
        "rates_report.html.j2",
        path,
        title=title,
        subtitle="",
        meta=[
            ("fitted on seeds", f"{result.fitted_seeds[0]}-{result.fitted_seeds[-1]}"),
            ("checked on seeds", f"{result.held_seeds[0]}-{result.held_seeds[-1]}"),
        ],
        fitted=len(result.fitted_seeds),
        held=len(result.held_seeds),
        graph=_graph_figure(result.graph),
        rates=table(result.model.table(), 4, ("source", "target", "family", "coefficient")),
        curves=image_data(curves),
        swarm=checks.swarm_size,
        checks=table(checks.table, 3, ("state",)),
        verdict=(
            f"Worst state: RMSD {100 * checks.rmsd_max:.1f} % of N; band coverage "
            f"{100 * checks.band_coverage:.1f} %; the ODE ran {_faster(checks.speed_ratio)} and "
            f"the band {_faster(checks.band_speed_ratio)} than the held-out agent runs."
        ),
        mixing_text=mixing_text,
        mixing=table(mixing.table, 3, ("source", "target", "k")) if mixing.computable else "",
    )


def _graph_figure(graph: object) -> str:
    """The state graph drawn as a circle of states, each edge labelled with its count and
    crude rate (1/s).
    """
    import networkx as nx

    fig, ax = plt.subplots(figsize=(7.5, 5.0))
    layout = nx.circular_layout(graph)
    nx.draw_networkx_nodes(graph, layout, ax=ax, node_color="#cfe8ec", node_size=2200)
    nx.draw_networkx_labels(graph, layout, ax=ax, font_size=9)
    nx.draw_networkx_edges(graph, layout, ax=ax, arrows=True, arrowsize=16, node_size=2200,
                           connectionstyle="arc3,rad=0.12")  # fmt: skip
    labels = {}
    for a, b, data in graph.edges(data=True):
        rate = data.get("rate", float("nan"))
        labels[a, b] = f"{data.get('count', 0)}" + (f"\n{rate:.3g}/s" if rate == rate else "")
    nx.draw_networkx_edge_labels(graph, layout, edge_labels=labels, ax=ax, font_size=7,
                                 connectionstyle="arc3,rad=0.12")  # fmt: skip
    ax.set_axis_off()
    data = figure_data(fig)
    plt.close(fig)
    return data


def plot_curves(
    checks: Sequence[Checks], labels: Sequence[str], states: Sequence[str], path: Path, title: str
) -> Path:
    """One row of panels per checked condition, one panel per state: the held-out runs, their
    mean, the mean-field ODE and the 90 % band.
    """
    rows, cols = len(checks), len(states)
    fig, axes = plt.subplots(rows, cols, figsize=(4.2 * cols, 3.6 * rows), squeeze=False)
    for r, (check, label) in enumerate(zip(checks, labels, strict=True)):
        grid = check.expected["time"].to_numpy()
        for i, (ax, state) in enumerate(zip(axes[r], states, strict=True)):
            for run in check.observed[:, :, i]:
                ax.plot(grid, run, color="0.75", lw=0.7)
            ax.fill_between(grid, check.band.low[state], check.band.high[state],
                            color="#00798c", alpha=0.25, lw=0, label="90 % band")  # fmt: skip
            ax.plot(grid, check.observed[:, :, i].mean(axis=0), color="black", lw=1.4,
                    label="held-out runs, mean")  # fmt: skip
            ax.plot(grid, check.expected[state], color="#d1495b", lw=1.4, ls="--",
                    label="mean-field ODE")  # fmt: skip
            rmsd = float(check.table.loc[check.table["state"] == state, "rmsd"].iloc[0])
            head = f"{label}\n" if label else ""
            said = "never occupied" if np.isnan(rmsd) else f"RMSD {100 * rmsd:.1f} % of N"
            ax.set_title(f"{head}{state} ({said})", fontsize=9)
            ax.set_xlabel("time (s)")
            ax.grid(alpha=0.3)
        axes[r][0].set_ylabel("robots")
    axes[0][-1].legend(frameon=False, fontsize=8)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def summary_lines(result: RateFit) -> list[str]:
    """What ``abm fit`` prints: the rates, the held-out checks, mixing and speed."""
    checks, mixing = result.checks, result.mixing
    rates = result.model.table()
    shown = [c for c in ("source", "target", "family", "coefficient", "estimate", "se")
             if c in rates]  # fmt: skip
    lines = [rates[shown].to_string(index=False, float_format=lambda v: f"{v:.4g}"), ""]
    lines.append(checks.table.to_string(index=False, float_format=lambda v: f"{v:.3f}", na_rep="-"))
    empty = checks.table.loc[~checks.table["occupied"], "state"].tolist()
    if empty:
        lines.append(f"never occupied, held out or predicted (not checked): {', '.join(empty)}")
    lines.append(
        f"held-out seeds {result.held_seeds[0]}-{result.held_seeds[-1]}: worst RMSD "
        f"{100 * checks.rmsd_max:.1f} % of N = {checks.swarm_size}; band coverage "
        f"{100 * checks.band_coverage:.1f} %"
    )
    if mixing.computable:
        flagged = mixing.table[mixing.table["flagged"]]
        pairs = ", ".join(f"{r.source}->{r.target} vs {r.k}" for r in flagged.itertuples())
        lines.append(f"well mixed: {'no (' + pairs + ')' if mixing.flagged else 'yes'}")
    else:
        lines.append(f"well mixed: cannot be computed ({mixing.reason})")
    lines.append(
        f"speed: the ODE {_faster(checks.speed_ratio)}, the band "
        f"{_faster(checks.band_speed_ratio)} than the held-out agent runs"
    )
    return lines


def _faster(ratio: float) -> str:
    """A speed ratio in words: "46x faster", or "1.7x slower" below 1 (not "0.6x faster")."""
    if ratio >= 1:
        return f"{ratio:.0f}x faster" if ratio >= 10 else f"{ratio:.1f}x faster"
    return f"{1 / ratio:.1f}x slower"
