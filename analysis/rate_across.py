"""``abm fit MODEL --grid ...`` with rate equations: fitted on some grid points, predicting the
others.

Every grid point gets ``runs + held`` seeded runs (point k's seeds follow point k-1's). The
held-out points (:func:`held_out_points`: evenly spread among the grid's interior points, so
the prediction interpolates) are fitted on nothing; the others fit the hazards across
parameters (:func:`analysis.macroscopic.across.fit_across`) on their first ``runs`` runs. The
prediction is then checked at every point on runs the fit has not seen: the ``held`` runs of a
fitted point, every run of a held-out one (RMSD per state as a share of the swarm, band
coverage; :func:`analysis.macroscopic.check_heldout`). Written beside one HTML page:
``rates_across.csv`` (coefficients and parameter effects with standard errors),
``conditions.csv`` (per grid point: its role, seeds and checks) and ``curves.png`` (the
held-out points' runs against the prediction).
"""

import itertools
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from abm.errors import ConfigError
from analysis.html import image_data, render_page, table
from analysis.macroscopic import Checks, RunLog, check_heldout, check_states
from analysis.macroscopic.across import AcrossModel, fit_across, numeric_values
from analysis.rate_fit import plot_curves, run_logs

__all__ = [
    "AcrossFit",
    "fit_grid",
    "fit_rates_across",
    "held_out_points",
    "summary_lines",
    "write_across",
]


@dataclass(frozen=True)
class AcrossFit:
    """Rates fitted across a grid and their checks at every grid point.

    Attributes:
        model: the fitted hazards with their parameter effects.
        points: the grid points (dicts of parameter values), in grid order.
        held_out: for each point, True when it was held out of the fit.
        seeds: each point's seeds.
        checks: each point's checks on runs the fit has not seen.
        runs: fitted runs per fitted point; held: their held-out runs.

    """

    model: AcrossModel
    points: tuple[dict, ...]
    held_out: tuple[bool, ...]
    seeds: tuple[tuple[int, ...], ...]
    checks: tuple[Checks, ...]
    runs: int
    held: int

    def table(self) -> pd.DataFrame:
        """One row per grid point and state (``conditions.csv``)."""
        rows = []
        for point, out, seeds, checks in zip(
            self.points, self.held_out, self.seeds, self.checks, strict=True
        ):
            role = "held-out condition" if out else "fitted condition, held-out seeds"
            checked = seeds if out else seeds[self.runs :]
            for row in checks.table.itertuples(index=False):
                rows.append(
                    {
                        **point,
                        "role": role,
                        "checked_seeds": f"{checked[0]}-{checked[-1]}",
                        "state": row.state,
                        "rmsd": row.rmsd,
                        "noise": row.noise,
                        "band_coverage": row.band_coverage,
                        "swarm_size": checks.swarm_size,
                    }
                )
        return pd.DataFrame(rows)


def held_out_points(points: Sequence[Mapping[str, object]], count: int) -> list[int]:
    """Indices of ``count`` of ``points`` (conditions: parameter -> value) to hold out: evenly
    spread among the interior ones, where every numeric parameter taking three or more values
    over ``points`` lies strictly between its lowest and highest (so predictions interpolate).

    Raises:
        ConfigError: fewer interior points than ``count``, or fewer than two points left to fit.

    """
    if count < 1:
        raise ConfigError(f"--held-points must be at least 1, got {count}")
    keys = list(points[0]) if points else []
    spans = {k: _span([p[k] for p in points]) for k in keys}
    interior = [
        k
        for k, point in enumerate(points)
        if any(spans.values())
        and all(s is None or s[0] < point[key] < s[1] for key, s in spans.items())
    ]
    if len(interior) < count:
        raise ConfigError(
            f"--held-points {count}: the grid has {len(interior)} interior point(s); give a "
            "numeric parameter at least 3 values (points with a parameter at its lowest or "
            "highest value are never held out: that would be extrapolation)"
        )
    if len(points) - count < 2:
        raise ConfigError(f"--held-points {count} leaves fewer than 2 of {len(points)} to fit")
    n = len(interior)  # the middle of each of ``count`` equal shares: distinct, evenly spread
    return [interior[(2 * i + 1) * n // (2 * count)] for i in range(count)]


def _span(values: Sequence[object]) -> tuple[float, float] | None:
    """(lowest, highest) of a numeric parameter swept over 3 or more values, else None."""
    if not numeric_values(values) or len(set(values)) < 3:
        return None
    return float(min(values)), float(max(values))


def fit_rates_across(
    cls: type,
    grid: Mapping[str, Sequence[object]],
    fixed: Mapping[str, object],
    seed: int,
    runs: int,
    held: int,
    held_points: int,
    workers: int = 1,
    progress=print,
) -> AcrossFit:
    """Run every grid point, fit on the fitted points' first ``runs`` runs, check everywhere.

    Raises:
        ConfigError: fewer than two states, too few runs, a grid that cannot hold points out
            (all checked before any run).

    """
    check_states(cls.STATES, cls.__name__)
    if runs < 2:
        raise ConfigError(f"--runs must be at least 2 to fit rates, got {runs}")
    if held < 1:
        raise ConfigError(f"--held must be at least 1, got {held}")
    points = [dict(zip(grid, values, strict=True)) for values in itertools.product(*grid.values())]
    out = held_out_points(points, held_points)
    for point in points:
        cls(seed=seed, **{**fixed, **point})  # bad parameters stop here, before any run
    target = f"{cls.__module__}:{cls.__qualname__}"
    per_point = runs + held
    logs: list[list[RunLog]] = []
    seeds: list[tuple[int, ...]] = []
    for k, point in enumerate(points):
        these = tuple(range(seed + k * per_point, seed + (k + 1) * per_point))
        progress(f"grid point {k + 1}/{len(points)} {_label(point)}: seeds {these[0]}-{these[-1]}")
        logs.append(run_logs(target, these, {**fixed, **point}, workers))
        seeds.append(these)
    return fit_grid(points, logs, seeds, list(grid), out, runs, seed)


def fit_grid(
    points: Sequence[dict],
    logs: Sequence[Sequence[RunLog]],
    seeds: Sequence[tuple[int, ...]],
    swept: Sequence[str],
    held_out: Sequence[int],
    runs: int,
    seed: int,
) -> AcrossFit:
    """Fit across the points not in ``held_out`` (indices) on their first ``runs`` runs, and
    check every point on the runs the fit has not seen.

    Raises:
        ConfigError: a fitted point with ``runs`` runs or fewer (none left to check it on).

    """
    short = [
        _label(points[k]) for k in range(len(points)) if k not in held_out and len(logs[k]) <= runs
    ]
    if short:
        raise ConfigError(
            f"fitted points need more than --runs {runs} runs (the rest check them); "
            f"{', '.join(short)} {'has' if len(short) == 1 else 'have'} too few"
        )
    fitted = [(points[k], logs[k][:runs]) for k in range(len(points)) if k not in held_out]
    model = fit_across(fitted, swept)
    rng = np.random.default_rng(seed)
    checks = []
    for k, point in enumerate(points):
        checked = logs[k] if k in held_out else logs[k][runs:]
        checks.append(check_heldout(model.at(point, checked), checked, rng))
    held = max(len(logs[k]) - runs for k in range(len(points)) if k not in held_out)
    return AcrossFit(
        model,
        tuple(points),
        tuple(k in held_out for k in range(len(points))),
        tuple(seeds),
        tuple(checks),
        runs,
        held,
    )


def _label(point: Mapping[str, object]) -> str:
    return ", ".join(f"{k}={v}" for k, v in point.items())


def summary_lines(result: AcrossFit) -> list[str]:
    """What ``abm fit`` prints: the effects, then the checks per grid point."""
    rates = result.model.table()
    shown = ["source", "target", "family", "coefficient", "estimate", "se"]
    lines = [rates[shown].to_string(index=False, float_format=lambda v: f"{v:.4g}"), ""]
    for point, out, checks in zip(result.points, result.held_out, result.checks, strict=True):
        role = "HELD OUT" if out else "fitted  "
        lines.append(
            f"{role} {_label(point)}: worst RMSD {100 * checks.rmsd_max:.1f} % of N = "
            f"{checks.swarm_size}, band coverage {100 * checks.band_coverage:.1f} %"
        )
    return lines


def write_across(result: AcrossFit, out: Path, title: str) -> list[Path]:
    """Write rates_across.csv, conditions.csv, curves.png and rates_across.html into ``out``."""
    out.mkdir(parents=True, exist_ok=True)
    paths = [out / "rates_across.csv", out / "conditions.csv", out / "curves.png"]
    result.model.table().to_csv(paths[0], index=False)
    result.table().to_csv(paths[1], index=False)
    held = [k for k, o in enumerate(result.held_out) if o]
    plot_curves(
        [result.checks[k] for k in held],
        [f"held out: {_label(result.points[k])}" for k in held],
        result.model.states,
        paths[2],
        title,
    )
    numeric = ", ".join(
        f"{name} ({'log, ' if log else ''}mean {mean:.3g}, sd {sd:.3g})"
        for name, (log, mean, sd) in result.model.numeric.items()
    )
    levels = ", ".join(
        f"{name} (levels {', '.join(map(str, lv))}; baseline {lv[0]})"
        for name, lv in result.model.levels.items()
    )
    worst = max(result.checks[k].rmsd_max for k in held)
    paths.append(
        render_page(
            "rates_across.html.j2",
            out / "rates_across.html",
            title=title,
            subtitle="",
            meta=[
                ("fitted points", str(len(result.points) - len(held))),
                ("held-out points", str(len(held))),
                ("runs per fitted point", f"{result.runs} fitted + {result.held} held out"),
            ],
            effects="; ".join(x for x in (numeric, levels) if x),
            rates=table(result.model.table(), 4, ("source", "target", "family", "coefficient")),
            conditions=table(result.table(), 3, ("role", "checked_seeds", "state")),
            curves=image_data(paths[2]),
            verdict=(
                f"Worst state at a held-out condition: RMSD {100 * worst:.1f} % of the swarm."
            ),
        )
    )
    return paths
