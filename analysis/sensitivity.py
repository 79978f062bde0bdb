"""Sensitivity indices of a sweep with a design: which parameters move which output metric.

The design's sample is drawn again from its manifest (:class:`~analysis.sweep.design.Design`,
checked against the points the sweep ran), each sample row is given the mean of its runs'
metric (over replications), and SALib's estimators give, per parameter and output metric:

- Morris (``morris``): mu* (mean absolute elementary effect, in the metric's unit per
  normalised step of the parameter's range) with its bootstrap interval, and sigma (their
  standard deviation: interactions or non-linearity) -- Campolongo et al. (2007);
- Sobol' (``sobol``): first-order S1 and total ST indices with bootstrap intervals --
  Saltelli et al. (2010), Jansen's estimator for ST;
- Latin hypercube (``lhs``): first-order S1 by RBD-FAST (Tarantola et al. 2006, M = 10
  harmonics) with a bootstrap interval.

Convergence: the same indices on nested leading subsets of the sample, each a valid design of
its kind: the first ``m`` base points of a Sobol' sample (Saltelli blocks; the scrambled Sobol'
sequence is balanced at every power of two), the first ``m`` Morris trajectories (drawn
independently), the first ``m`` Latin-hypercube rows (a random sample, no longer stratified,
which RBD-FAST accepts). Intervals are the half-width SALib reports at 95 %, shown as
``value +- half``.
"""

import json
import math
import warnings
from collections.abc import Sequence
from pathlib import Path

import numpy as np
import pandas as pd

from analysis.sweep.design import MIN_N, MORRIS_LEVELS, Design

__all__ = [
    "BOOKKEEPING",
    "CONF_LEVEL",
    "HEADLINE",
    "RESAMPLES",
    "DesignData",
    "design_data",
    "indices",
    "ranking",
    "save_figures",
    "unranked",
]

#: Confidence level of every interval, and bootstrap resamples behind it.
CONF_LEVEL = 0.95
RESAMPLES = 1000
#: Columns of a sweep's rows that are never output metrics.
BOOKKEEPING = (
    "run_id",
    "rep",
    "seed",
    "spawn_key",
    "status",
    "error",
    "traceback",
    "wall_time",
    "worker",
    "sweep",
)
#: The headline index of each kind (what the ranking sorts by).
HEADLINE = {"morris": "mu_star", "sobol": "ST", "lhs": "S1"}
_RBD_HARMONICS = 10


class DesignData:
    """A design's sample matrix and, per output metric, one value per sample row.

    Attributes:
        design: the design, as recorded in ``sweep.json``.
        matrix: SALib's sample (rows x parameters, before rounding).
        outputs: metric -> array of one value per sample row (mean over replications).
        notes: why a metric (or the whole design) has no indices.
        censored: metric -> share of runs whose value is only a lower bound.
        set_by: metric -> the parameter that alone sets it in these runs (:func:`_echoed`):
            its indices would restate that, so it is left out of the ranking.

    """

    def __init__(self, design: Design, matrix: np.ndarray) -> None:
        self.design = design
        self.matrix = matrix
        self.outputs: dict[str, np.ndarray] = {}
        self.notes: list[str] = []
        self.censored: dict[str, float] = {}
        self.set_by: dict[str, str] = {}


def design_data(
    manifest: dict, runs: pd.DataFrame, censored: Sequence = (), parameters: Sequence[str] = ()
) -> DesignData | None:
    """The sample and outputs of the sweep ``manifest`` from its ``runs``; None without design.

    Args:
        manifest: the sweep's ``sweep.json``.
        runs: its rows (:func:`analysis.sweep.load_results`; failed rows are left out).
        censored: the model's censored metrics (:class:`abm.published.Censored`).
        parameters: the model's parameters, never output metrics (a summary may echo them).

    """
    if not manifest.get("design"):
        return None
    design = Design.from_manifest(manifest["design"])
    matrix = design.matrix()
    rows = design.rows(matrix)
    data = DesignData(design, matrix)
    planned = {_key(p, design.names) for p in manifest.get("points", [])}
    if {_key(r, design.names) for r in rows} != planned:
        data.notes.append(
            "the design's sample drawn again differs from the points the sweep ran (another "
            "SALib version?): no indices"
        )
        return data
    ok = runs[runs["status"] == "ok"] if "status" in runs else runs
    columns = zip(*(ok[name].tolist() for name in design.names), strict=True)  # dtypes kept
    keys = pd.Series([json.dumps(list(values)) for values in columns], index=ok.index, dtype=object)
    wanted = [_key(r, design.names) for r in rows]
    missing = len(set(wanted) - set(keys))
    if missing:
        data.notes.append(
            f"{missing} of {len(set(wanted))} design points have no finished run (failed or "
            "not run yet): no indices; run the sweep again to complete it"
        )
        return data
    constant = []
    groups = _repeated_values(rows, design.names)
    for metric in _metrics(ok, manifest, parameters):
        values = pd.to_numeric(ok[metric], errors="coerce").astype(float)
        if values.isna().any():
            data.notes.append(
                f"metric {metric!r} left out: missing in {int(values.isna().sum())} of "
                f"{len(values)} runs"
            )
            continue
        means = values.groupby(keys.values).mean()
        y = means.reindex(wanted).to_numpy(dtype=float)
        if np.ptp(y) == 0:
            constant.append(metric)
            continue
        data.outputs[metric] = y
        source = _echoed(y, groups)
        if source is not None:
            data.set_by[metric] = source
    if constant:
        data.notes.append(f"left out, the same in every run: {', '.join(constant)}")
    if data.set_by:
        echoes = ", ".join(f"{m} ({p})" for m, p in data.set_by.items())
        data.notes.append(
            "left out of the ranking, set by one parameter alone in these runs (the same "
            "value wherever that parameter had the same value, which fewer than 1 % of "
            "shuffles of the values give: their indices would restate it; more rows may show "
            f"other parameters acting): {echoes}; their indices are in sensitivity.csv"
        )
    for spec in censored:
        if spec.metric in data.outputs:
            from analysis.censoring import censored_mask

            data.censored[spec.metric] = float(censored_mask(ok, spec).mean())
    return data


def _repeated_values(rows: Sequence[dict], names: Sequence[str]) -> dict[str, np.ndarray]:
    """Per parameter whose values repeat over at least half the design rows, each row's value
    as a group code (for :func:`_echoed`). A Sobol' sample repeats each value across its
    matrices, a Morris trajectory along its steps; where a parameter's values are all
    distinct (a Latin hypercube of a real parameter) nothing could be told, so it is not here.
    """
    groups = {}
    for name in names:
        codes, uniques = pd.factorize(pd.Series([json.dumps(r[name]) for r in rows]))
        if len(uniques) <= len(rows) / 2:
            groups[name] = codes
    return groups


def _echoed(y: np.ndarray, groups: dict[str, np.ndarray]) -> str | None:
    """The parameter that alone sets ``y`` (one value per design row), or None.

    An output that takes one value wherever a parameter takes one value (a count of robots
    that echoes ``n_robots``, an energy fixed per robot) has ST = 1 for that parameter and 0
    for the others whatever the model does: counted in the ranking's mean over metrics, it
    would pull that parameter up (on the beacon/explorer Sobol' design two such outputs put
    n_robots first; without them body_radius is first).

    An output with few distinct values on a small design (a beacon count of 13 or 14 over 9
    Morris rows) can be constant within one parameter's groups by chance: it is named only
    when fewer than 1 % of :data:`ECHO_SHUFFLES` seeded shuffles of its values over the rows
    are also constant within those groups.
    """
    for name, codes in groups.items():
        if _constant_within(y, codes) and _chance_of_echo(y, codes) < 0.01:
            return name
    return None


#: Shuffles of an output's values by which :func:`_echoed` tells an echo from chance.
ECHO_SHUFFLES = 999


def _constant_within(y: np.ndarray, codes: np.ndarray) -> bool:
    """Whether ``y`` takes one value within each group of ``codes``."""
    by_value = pd.Series(y).groupby(codes)
    return bool(((by_value.max() - by_value.min()) == 0).all())


def _chance_of_echo(y: np.ndarray, codes: np.ndarray) -> float:
    """The share of seeded shuffles of ``y`` over the rows that are constant within ``codes``'
    groups (0 when its values are too varied for any shuffle to be).
    """
    rng = np.random.default_rng(len(y))
    hits = sum(_constant_within(rng.permutation(y), codes) for _ in range(ECHO_SHUFFLES))
    return hits / ECHO_SHUFFLES


def _key(params: dict, names: Sequence[str]) -> str:
    values = [params[n].item() if isinstance(params[n], np.generic) else params[n] for n in names]
    return json.dumps(values)


def _metrics(runs: pd.DataFrame, manifest: dict, parameters: Sequence[str]) -> list[str]:
    """Numeric columns that are neither parameters nor bookkeeping."""
    skip = set(BOOKKEEPING) | set(manifest.get("grid", {})) | set(manifest["design"]["parameters"])
    skip |= set(parameters)
    return [
        c
        for c in runs.columns
        if c not in skip
        and (pd.api.types.is_numeric_dtype(runs[c]) or pd.api.types.is_bool_dtype(runs[c]))
    ]


def indices(data: DesignData, convergence: bool = True) -> pd.DataFrame:
    """Tidy indices: one row per metric, parameter, index and subset size ``n``.

    Columns: ``metric``, ``parameter``, ``index`` (``mu_star``, ``sigma``, ``S1``, ``ST``),
    ``value``, ``half`` (half-width of the 95 % bootstrap interval; NaN for sigma), ``n``
    (base points, trajectories or rows used), ``full`` (True for the whole sample),
    ``censored_share``, ``set_by`` (the parameter that alone sets the metric, else empty).
    """
    rows = []
    design = data.design
    sizes = _subset_sizes(design) if convergence else [design.n]
    for metric, y in data.outputs.items():
        for m in sizes:
            for name, index, value, half in _analyse(design, data.matrix, y, m):
                rows.append(
                    {
                        "metric": metric,
                        "parameter": name,
                        "index": index,
                        "value": value,
                        "half": half,
                        "n": m,
                        "full": m == design.n,
                        "censored_share": data.censored.get(metric, 0.0),
                        "set_by": data.set_by.get(metric, ""),
                    }
                )
    columns = [
        "metric", "parameter", "index", "value", "half", "n", "full", "censored_share", "set_by",
    ]  # fmt: skip
    return pd.DataFrame(rows, columns=columns)


def _subset_sizes(design: Design) -> list[int]:
    """Nested leading subsets for convergence (see the module's text), the whole last."""
    n = design.n
    if design.kind == "sobol":
        sizes = [2**k for k in range(3, int(math.log2(n)) + 1)]
    elif design.kind == "morris":
        sizes = sorted({int(round(v)) for v in np.geomspace(2, n, min(n - 1, 6))})
    else:
        sizes = sorted({int(round(v)) for v in np.geomspace(MIN_N["lhs"], n, 6)})
    return sorted(set(sizes) | {n})


def _analyse(design: Design, matrix: np.ndarray, y: np.ndarray, m: int) -> list[tuple]:
    """(parameter, index, value, half-width) on the first ``m`` units of the design."""
    from SALib.analyze import morris, rbd_fast, sobol

    problem = design.problem()
    d = len(design.parameters)
    out = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        if design.kind == "sobol":
            rows = m * (d + 2)
            s = sobol.analyze(
                problem,
                y[:rows],
                calc_second_order=False,
                num_resamples=RESAMPLES,
                conf_level=CONF_LEVEL,
                seed=design.seed,
            )
            for j, name in enumerate(design.names):
                out.append((name, "S1", s["S1"][j], s["S1_conf"][j]))
                out.append((name, "ST", s["ST"][j], s["ST_conf"][j]))
        elif design.kind == "morris":
            rows = m * (d + 1)
            s = morris.analyze(
                problem,
                matrix[:rows],
                y[:rows],
                num_resamples=RESAMPLES,
                conf_level=CONF_LEVEL,
                num_levels=MORRIS_LEVELS,
                seed=design.seed,
            )
            for j, name in enumerate(design.names):
                out.append((name, "mu_star", s["mu_star"][j], s["mu_star_conf"][j]))
                out.append((name, "sigma", s["sigma"][j], math.nan))
        else:
            s = rbd_fast.analyze(
                problem,
                matrix[:m],
                y[:m],
                M=_RBD_HARMONICS,
                num_resamples=RESAMPLES,
                conf_level=CONF_LEVEL,
                seed=design.seed,
            )
            for j, name in enumerate(design.names):
                out.append((name, "S1", s["S1"][j], s["S1_conf"][j]))
    return [(name, index, float(v), float(h)) for name, index, v, h in out]


def ranking(frame: pd.DataFrame, kind: str, first: Sequence[str] = ()) -> pd.DataFrame:
    """Parameters (rows) x metrics (columns): the headline index on the whole sample, each
    metric's column scaled to its largest (Morris mu*; Sobol' ST and RBD-FAST S1 are shares of
    variance already), parameters sorted by their mean over metrics, most influential first;
    the metrics of ``first`` that have indices (e.g. the model's report metrics) in the first
    columns. Metrics set by one parameter alone (``set_by``) are not ranked, unless no other
    metric is left.
    """
    index = HEADLINE[kind]
    full = frame[frame["full"] & (frame["index"] == index)]
    full = full[~full["metric"].isin(unranked(frame))]
    table = full.pivot_table(index="parameter", columns="metric", values="value", sort=False)
    if kind == "morris":
        table = table / table.max().replace(0, np.nan)
    table = table.clip(lower=0)
    shown = [m for m in first if m in table.columns]
    table = table[shown + [m for m in table.columns if m not in shown]]
    return table.loc[table.mean(axis=1).sort_values(ascending=False).index]


def unranked(frame: pd.DataFrame) -> list[str]:
    """The metrics :func:`ranking` leaves out: those set by one parameter alone (``set_by``),
    unless every metric is.
    """
    if "set_by" not in frame:
        return []
    echoes = set(frame.loc[frame["set_by"].fillna("") != "", "metric"])
    return [] if echoes == set(frame["metric"]) else sorted(echoes)


def save_figures(
    frame: pd.DataFrame, kind: str, folder: Path, first: Sequence[str] = ()
) -> dict[str, Path]:
    """The ranking (a bar of each parameter's mean and a heat map per metric, the metrics of
    ``first`` that have indices first, e.g. the model's report layout, then the others) and the
    convergence figure (headline index against n, top parameters of the first four metrics);
    PNGs in ``folder``.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    folder.mkdir(parents=True, exist_ok=True)
    table = ranking(frame, kind, first)
    what = {
        "morris": "mu* / largest mu* of the metric",
        "sobol": "total index ST",
        "lhs": "first-order index S1 (RBD-FAST)",
    }[kind]
    n_p, n_m = table.shape
    fig, (bar, heat) = plt.subplots(
        1,
        2,
        figsize=(4 + 0.45 * n_m + 3, 2.6 + 0.28 * n_p),  # room for titles and metric names
        gridspec_kw={"width_ratios": [3, max(n_m * 0.45, 1.5)]},
        sharey=True,
    )
    means = table.mean(axis=1)
    y = np.arange(n_p)
    bar.barh(y, means.to_numpy(), color="#3b6ea8")
    bar.set_yticks(y, table.index)
    bar.invert_yaxis()
    bar.set_xlabel(f"mean over {n_m} metric{'s' * (n_m != 1)}")
    bar.set_title("ranking")
    image = heat.imshow(
        table.to_numpy(),
        aspect="auto",
        cmap="viridis",
        vmin=0,
        vmax=max(1.0, float(np.nanmax(table.to_numpy()))),
    )
    heat.set_xticks(np.arange(n_m), table.columns, rotation=60, ha="right")
    heat.set_title("per metric")
    fig.colorbar(image, ax=heat, label=what, fraction=0.08)
    fig.suptitle(f"{kind.capitalize()} sensitivity: {what}, most influential first")
    fig.tight_layout(rect=(0, 0, 1, 1 - 0.5 / fig.get_figheight()))
    paths = {"ranking": folder / "sensitivity_ranking.png"}
    fig.savefig(paths["ranking"], dpi=110)
    plt.close(fig)
    if frame["n"].nunique() > 1:
        paths["convergence"] = _convergence(frame, kind, table.iloc[:, :4], folder, plt)
    return paths


def _convergence(frame, kind, table, folder, plt) -> Path:
    """Headline index (with its interval) against n for the top parameters of each metric of
    ``table``.
    """
    index = HEADLINE[kind]
    metrics = list(table.columns)
    fig, axes = plt.subplots(1, len(metrics), figsize=(4.2 * len(metrics), 3.4), squeeze=False)
    for ax, metric in zip(axes[0], metrics, strict=False):
        top = table[metric].sort_values(ascending=False).index[:5]
        for name in top:
            rows = frame[
                (frame["metric"] == metric)
                & (frame["parameter"] == name)
                & (frame["index"] == index)
            ].sort_values("n")
            ax.errorbar(
                rows["n"], rows["value"], yerr=rows["half"], marker="o", capsize=2, label=name
            )
        ax.set_xscale("log", base=2)
        if kind == "morris":  # the smallest subsets' intervals would hide the rest
            final = frame[frame["full"] & (frame["metric"] == metric) & (frame["index"] == index)]
            ax.set_ylim(0, 1.5 * float((final["value"] + final["half"]).max()) or 1.0)
        else:
            ax.set_ylim(-0.2, 1.2)
        ax.set_xlabel({"sobol": "base points", "morris": "trajectories", "lhs": "rows"}[kind])
        ax.set_ylabel(index)
        ax.set_title(metric)
        ax.legend(fontsize=7)
    fig.suptitle("Convergence: indices on leading subsets of the sample (95 % intervals)")
    fig.tight_layout(rect=(0, 0, 1, 0.92))
    path = folder / "sensitivity_convergence.png"
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
