"""Model-vs-simulation: the wander/beacon recurrence fitted to any model's two counted states.

A model declares which two of its states the recurrence counts (``MACRO``, an
:class:`abm.published.MacroSpec`: explorer/beacon for the beacon/explorer swarm, wander/beacon
for stigmergy). :func:`fit_runs` runs the model over a grid as a resumable sweep that keeps
each run's counts; :func:`read_runs` reads such a sweep folder; :func:`analyse` fits a0 and
alpha6 per condition (lmfit) and, when the spec names the paper's covariates, regresses the
lambdas across conditions, predicts with them (the paper's Table 1 / Table 2) and checks them
on held-out conditions; :func:`write_fit_report` writes one HTML page.
"""

import dataclasses
import json
import re
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np
import pandas as pd

from abm.errors import ConfigError
from abm.published import MacroSpec
from abm.registry import model_class
from analysis.html import figure_data, render_page, table
from analysis.macro import (
    a0_from_lambdas,
    alpha6_from_lambdas,
    fit_lambdas,
    fit_recurrence,
    predict_from_lambdas,
    recurrence,
    refine_lambdas,
    rmsd,
)
from analysis.macroscopic import RunLog, expected_counts, fit_rates
from analysis.sweep import load_results, run_sweep, swept_keys

__all__ = [
    "METHODS",
    "RUN_COLUMNS",
    "analyse",
    "fit_runs",
    "is_parameter",
    "macro_spec",
    "methods",
    "methods_note",
    "rate_legend",
    "read_runs",
    "set_keys",
    "speak",
    "spoken",
    "with_parameters",
    "write_fit_report",
]

#: The ways of getting a0 and alpha6 per condition that :func:`methods` compares, as
#: (RMSD column suffix, description with the rates' names as ``{a0}``, ``{alpha6}``); "" is
#: the joint refinement, the headline figure.
METHODS = (
    ("_reg", "the paper's method: {a0}, {alpha6} fitted per curve, then the two regressions "
             "({alpha6} on the radius, {a0} on entropy and size)"),
    ("", "joint refinement: the six lambdas fitted to all curves at once, minimising the "
         "mean RMSD"),
    ("_fit", "{a0}, {alpha6} fitted per curve (no lambda model)"),
    ("_reg_alpha6", "diagnosis: {alpha6} from the regression, {a0} per curve"),
    ("_reg_a0", "diagnosis: {a0} from the regression, {alpha6} per curve"),
    ("_rates", "rate equations from the event log: per-robot hazards fitted per condition "
               "(analysis.macroscopic), no recurrence"),
)  # fmt: skip

#: The recurrence's symbols as they appear in column names (``rmsd_w_fit``, ``a0_se``).
_SYMBOL = re.compile(r"(?<![A-Za-z0-9])(w|b|a0|alpha6|alpha5)(?![A-Za-z0-9])")


def spoken(text: str, spec: MacroSpec) -> str:
    """``text`` (a column name or a sentence) with the recurrence's symbols replaced by the
    model's names: w and b by its two counted states, a0, alpha6 and alpha5 by the rate names
    it declares (:meth:`abm.published.MacroSpec.names`); ``rmsd_w_fit`` of the beacon/explorer
    swarm reads ``rmsd_explorer_fit``.
    """
    names = spec.names()
    return _SYMBOL.sub(lambda m: names[m.group(1)], text)


def speak(frame: pd.DataFrame, spec: MacroSpec) -> pd.DataFrame:
    """``frame`` with its columns named in the model's words (:func:`spoken`)."""
    return frame.rename(columns=lambda c: spoken(str(c), spec))


def rate_legend(spec: MacroSpec) -> list[str]:
    """One line per fitted rate: its name in the model's words and what it is."""
    n = spec.names()
    return [
        f"{n['a0']}: share of the {n['w']} robots that turn {n['b']} in the first step",
        f"{n['alpha6']}: factor that share changes by at each step ({spec.step:g} s)",
        f"{n['alpha5']}: {n['w']} robots arriving per step",
    ]


def macro_spec(model: str | type) -> MacroSpec:
    """The model's MacroSpec, or a ConfigError saying the model declares none."""
    cls = model_class(model)
    if cls.MACRO is None:
        raise ConfigError(
            f"{cls.__name__} declares no MACRO (the two states the recurrence counts); "
            "abm fit needs one, see docs/adding-a-model.md"
        )
    return cls.MACRO


def fit_runs(
    model: str | type,
    grid: Mapping[str, Sequence],
    runs: int,
    out: str | Path,
    seed: int = 0,
    workers: int | None = None,
    progress: bool = True,
) -> tuple[pd.DataFrame, pd.DataFrame, list[str]]:
    """Run ``model`` over ``grid`` x ``runs`` as a resumable sweep in ``out`` keeping counts.

    Returns what :func:`read_runs` returns, for the runs of this grid.
    """
    rows = run_sweep(
        model, grid, runs, seed, out, workers=workers, time_series=True, progress=progress
    )
    failed = rows[rows["status"] != "ok"]
    if len(failed):
        raise ConfigError(f"{len(failed)} runs failed, first: {failed['error'].iloc[0]}")
    return read_runs(out, grid=grid, runs=runs)


def read_runs(
    folder: str | Path, grid: Mapping[str, Sequence] | None = None, runs: int | None = None
) -> tuple[pd.DataFrame, pd.DataFrame, list[str]]:
    """A sweep folder's run summaries, their counts over time, and the condition columns.

    Args:
        folder: a sweep folder whose runs kept their time series (``abm sweep`` with
            ``time_series = true``, or :func:`fit_runs`).
        grid: keep only the runs of this grid (default: all).
        runs: keep only the first ``runs`` replications of each grid point.

    Returns:
        ``(summaries, counts, conditions)``: one row per run; the counts with ``run_id`` and
        the condition columns; the swept parameters that tell conditions apart.

    """
    folder = Path(folder)
    summaries = load_results(folder, failed=False)
    if summaries.empty:
        raise ConfigError(f"{folder} holds no finished runs")
    keep = pd.Series(True, index=summaries.index)
    for key, values in (grid or {}).items():
        keep &= summaries[key].isin(list(values))
    if runs is not None:
        keep &= summaries["rep"] < runs
    summaries = summaries[keep].reset_index(drop=True)
    series = load_results(folder, series=True)
    if series.empty:
        raise ConfigError(
            f"{folder} kept no time series: run the sweep with time_series = true (abm fit does)"
        )
    manifest = json.loads((folder / "sweep.json").read_text())
    conditions = swept_keys(manifest, summaries)
    summaries = with_parameters(summaries, model_class(manifest["target"]), set_keys(manifest))
    info = summaries[["run_id", *conditions]]
    counts = series[series["run_id"].isin(summaries["run_id"])].merge(info, on="run_id")
    return summaries, counts.sort_values(["run_id", "time"], kind="stable"), conditions


def set_keys(manifest: Mapping) -> list[str]:
    """The parameters a sweep sets (its ``grid`` and ``points`` keys), in the file's order."""
    keys = [*manifest.get("grid", {}), *(k for p in manifest.get("points", []) for k in p)]
    return list(dict.fromkeys(keys))


def is_parameter(params_cls: type, name: str) -> bool:
    """True when ``name`` is a field or a property of the params dataclass."""
    fields = {f.name for f in dataclasses.fields(params_cls)}
    return name in fields or isinstance(getattr(params_cls, name, None), property)


def with_parameters(summaries: pd.DataFrame, model: type, keys: Sequence[str]) -> pd.DataFrame:
    """``summaries`` with a column for every parameter the model's ``MACRO`` reads, holding
    each run's own value: its params built from what the sweep set (``keys``; a points-only
    key a run leaves unset takes the default) and read back, so a default or a property of
    the params (a launch period derived from a launch rate) is the value the run had.

    Args:
        summaries: one row per run, with the columns of ``keys``.
        model: the model class of the runs.
        keys: the parameters the sweep set.

    """
    spec = model.MACRO
    names = [n for n in (spec.inputs if spec else ()) if is_parameter(model.Params, n)]
    if not names or summaries.empty:
        return summaries
    given = [k for k in keys if k in summaries]
    values, built = [], {}  # runs of one grid point share their params: built once
    for row in summaries[given].to_dict("records"):
        set_here = {k: v for k, v in row.items() if not _unset(v)}
        key = repr(sorted(set_here.items()))
        if key not in built:
            params = model.make_params(**set_here)
            built[key] = [getattr(params, n) for n in names]
        values.append(built[key])
    columns = pd.DataFrame(values, columns=names, index=summaries.index)
    return summaries.drop(columns=names, errors="ignore").join(columns)


def _unset(value: object) -> bool:
    """A points-only parameter a run does not set reads back as missing."""
    return value is None or (pd.api.types.is_scalar(value) and pd.isna(value))


def _label(row: Mapping, conditions: Sequence[str]) -> str:
    return ", ".join(f"{k}={_shown(row[k])}" for k in conditions) or "all runs"


def _shown(value: object) -> str:
    return f"{value:g}" if isinstance(value, float) else str(value)


def analyse(
    summaries: pd.DataFrame,
    counts: pd.DataFrame,
    spec: MacroSpec,
    conditions: Sequence[str],
    heldout: bool = True,
    logs: Mapping[tuple, Sequence[RunLog]] | None = None,
) -> dict:
    """Fit the recurrence per condition; regress and check the lambdas where the spec says.

    With a regression, every condition is predicted two ways (see :data:`METHODS`): from the
    lambdas of the paper's method (per-curve fits, then the two regressions in parameter
    space; columns ``*_reg``) and from the joint refinement of the same six lambdas against
    all curves (the columns without suffix); ``*_reg_alpha6`` and ``*_reg_a0`` replace only
    one of the two per-curve parameters by its regressed value, to show which regression
    costs the RMSD.

    Args:
        summaries: one row per run.
        counts: the runs' counts over time with ``run_id`` and the condition columns.
        spec: the model's MACRO.
        conditions: the columns that tell conditions apart.
        heldout: also refit the lambdas with each value of the other condition left out.
        logs: the runs' logs per condition (keyed by the condition's values, in the order of
            ``conditions``): the rate equations are fitted to the same runs and their RMSDs
            (``rmsd_w_rates``, ``rmsd_b_rates``) computed the same way, on the same curves.

    Returns:
        A dict: ``fits`` (per condition: a0, alpha6 +- stderr, RMSDs of the direct fit, the
        final mean counts and time), ``table`` (``fits`` plus, with a regression, the
        predictions w_hat, b_hat, the a0 and alpha6 of each method and their RMSDs),
        ``curves`` (observed mean +- se and predictions over time), ``lambdas`` (or None),
        ``lambdas_regressed``, ``heldout`` (or None) and ``notes``.

    """
    notes: list[str] = []
    conditions = list(conditions)
    for column in spec.inputs:
        if column not in summaries:
            raise ConfigError(
                f"the model's MACRO names {column!r}, which is neither a parameter of the "
                f"model nor a key of its runs' summaries; their columns: "
                f"{', '.join(summaries.columns)}"
            )
    groups = [((), counts)] if not conditions else counts.groupby(conditions, sort=True)
    rows, curves = [], []
    for key, part in groups:
        key = key if isinstance(key, tuple) else (key,)
        where = dict(zip(conditions, key, strict=True))
        runs = summaries
        for k, v in where.items():
            runs = runs[runs[k] == v]
        alpha5 = supply = None
        if spec.arrival_period is not None:
            alpha5 = spec.step / float(runs[spec.arrival_period].mean())
        if spec.supply is not None:
            supply = float(runs[spec.supply].mean())
        final = part.groupby("run_id", sort=False).tail(1)
        fit = fit_recurrence(
            part.rename(columns={"run_id": "run"}),
            wander=spec.moving,
            beacon=spec.settled,
            step=spec.step,
            alpha5=alpha5,
            supply=supply,
        )
        row = {
            **where,
            "condition": _label(where, conditions),
            "runs": len(runs),
            "a0": fit.params["a0"],
            "a0_se": fit.stderr["a0"],
            "alpha6": fit.params["alpha6"],
            "alpha6_se": fit.stderr["alpha6"],
            "alpha5": fit.params["alpha5"],
            "rmsd_w_fit": fit.rmsd_w,
            "rmsd_b_fit": fit.rmsd_b,
            "w": final[spec.moving].mean(),
            "b": final[spec.settled].mean(),
            "t": runs["time"].mean(),
            "steps": int(round(fit.observed["time"].iloc[-1] / spec.step)),
        }
        for covariate, column in (spec.regression or {}).items():
            if covariate != "radius":
                row[covariate] = float(runs[column].iloc[0])
        rows.append(row)
        obs = fit.observed.assign(condition=row["condition"], **where)
        obs["wander_fit"] = fit.predicted["wander"].to_numpy()
        obs["beacon_fit"] = fit.predicted["beacon"].to_numpy()
        if logs is not None and len(logs.get(key, ())) >= 2:
            expected = expected_counts(fit_rates(logs[key]), obs["time"].to_numpy())
            for col, state in (("wander", spec.moving), ("beacon", spec.settled)):
                obs[f"{col}_rates"] = expected[state].to_numpy()
                row[f"rmsd_{col[0]}_rates"] = rmsd(obs[f"{col}_rates"], obs[col])
        curves.append(obs)
    fits = pd.DataFrame(rows)
    curves = pd.concat(curves, ignore_index=True)
    out = {"fits": fits, "table": fits, "curves": curves, "notes": notes,
           "lambdas": None, "heldout": None}  # fmt: skip
    radius = (spec.regression or {}).get("radius")
    if spec.regression is None:
        return out
    if radius not in fits or fits[radius].nunique() < 3:
        notes.append(f"lambda regression skipped: it needs at least 3 values of {radius}")
        return out
    alpha5 = float(fits["alpha5"].iloc[0])
    reg = fits.rename(columns={radius: "radius"})
    regressed, _ = fit_lambdas(reg)
    lambdas, lambdas_se = refine_lambdas(regressed, _curves(reg, curves), alpha5, spec.step)
    out["lambdas"] = (lambdas, lambdas_se)
    out["lambdas_regressed"] = regressed
    notes.append(
        "lambdas: the paper's regressions (alpha6 on C_rb, a0 on entropy and size) give the "
        "start values, then the six lambdas are fitted jointly to all count curves, "
        "minimising the mean RMSD of w and b over them (the Table 2 figure; "
        "analysis.macro.refine_lambdas); rmsd_*_reg are the RMSDs that the regressed start "
        "values give, before the joint fit"
    )
    curves["wander_lambda"] = np.nan
    curves["beacon_lambda"] = np.nan
    rows = []
    for row in reg.to_dict("records"):
        sel = curves["condition"] == row["condition"]
        obs = curves[sel]
        idx = np.round(obs["time"].to_numpy() / spec.step).astype(int)
        got = {}
        for name, lam in (("_lam", lambdas), ("_reg", regressed)):
            got[f"a0{name}"] = _clip(a0_from_lambdas(lam, row["entropy"], row["envsize"]))
            got[f"alpha6{name}"] = _clip(alpha6_from_lambdas(lam, row["radius"]))
        for name, a0, alpha6 in (
            ("", got["a0_lam"], got["alpha6_lam"]),
            ("_reg", got["a0_reg"], got["alpha6_reg"]),
            ("_reg_alpha6", row["a0"], got["alpha6_reg"]),
            ("_reg_a0", got["a0_reg"], row["alpha6"]),
        ):
            pred = recurrence(a0, alpha6, alpha5, row["steps"], 0.0, 1.0, spec.step)
            pw, pb = pred["wander"].to_numpy()[idx], pred["beacon"].to_numpy()[idx]
            got[f"rmsd_w{name}"] = rmsd(pw, obs["wander"])
            got[f"rmsd_b{name}"] = rmsd(pb, obs["beacon"])
            if not name:
                curves.loc[sel, "wander_lambda"] = pw
                curves.loc[sel, "beacon_lambda"] = pb
                got.update(w_hat=pw[-1], b_hat=pb[-1])
        rows.append({**row, **got})
    out["table"] = pd.DataFrame(rows).rename(columns={"radius": radius})
    if heldout:
        out["heldout"] = _heldout(reg, curves, conditions, radius, alpha5, spec, notes)
    return out


def _clip(value: float) -> float:
    """a0 and alpha6 are fractions: the lambda model's value clipped to [0, 1]."""
    return min(1.0, max(0.0, float(value)))


def methods(table: pd.DataFrame, spec: MacroSpec) -> pd.DataFrame:
    """Mean (std) RMSD of w and b over the conditions for each fitting method, and the paper's.

    Args:
        table: ``analyse(...)["table"]``.
        spec: the model's MACRO (the paper's per-condition RMSDs and overall figures).

    Returns:
        One row per method present in ``table`` (see :data:`METHODS`), then the paper's mean
        over the same conditions (where it publishes per-condition RMSDs) and its overall
        figures: ``method``, ``conditions``, ``rmsd_w``, ``rmsd_b`` (means), ``rmsd_w_std``,
        ``rmsd_b_std``.

    """
    rows = []
    names = spec.names()
    for suffix, text in METHODS:
        w, b = f"rmsd_w{suffix}", f"rmsd_b{suffix}"
        if w in table and b in table and table[w].notna().any():
            rows.append(_method_row(text.format(**names), table[w], table[b]))
    matched = _published_columns(table, spec)
    if {"paper rmsd_w", "paper rmsd_b"} <= set(matched):
        keep = matched["paper rmsd_w"].notna() & matched["paper rmsd_b"].notna()
        if keep.any():
            where = f" ({spec.published_label})" if spec.published_label else ""
            rows.append(
                _method_row(
                    f"paper{where}, the same conditions",
                    matched.loc[keep, "paper rmsd_w"],
                    matched.loc[keep, "paper rmsd_b"],
                )
            )
    if {"rmsd_w", "rmsd_b"} <= set(spec.published_summary):
        (w, w_sd), (b, b_sd) = spec.published_summary["rmsd_w"], spec.published_summary["rmsd_b"]
        where = f" ({spec.summary_label})" if spec.summary_label else ""
        rows.append(
            {"method": f"paper{where}", "conditions": np.nan, "rmsd_w": w, "rmsd_b": b,
             "rmsd_w_std": w_sd, "rmsd_b_std": b_sd}
        )  # fmt: skip
    return pd.DataFrame(rows)


def _method_row(text: str, w: pd.Series, b: pd.Series) -> dict:
    return {"method": text, "conditions": len(w), "rmsd_w": w.mean(), "rmsd_b": b.mean(),
            "rmsd_w_std": w.std(), "rmsd_b_std": b.std()}  # fmt: skip


def _curves(reg: pd.DataFrame, curves: pd.DataFrame) -> list:
    """``(observed, radius, entropy, envsize)`` per condition, for :func:`refine_lambdas`."""
    return [
        (curves[curves["condition"] == row["condition"]], row["radius"], row["entropy"],
         row["envsize"])
        for row in reg.to_dict("records")
    ]  # fmt: skip


def _heldout(reg, curves, conditions, radius, alpha5, spec, notes) -> pd.DataFrame | None:
    """Leave out each value of the other condition (e.g. each map) in turn: lambdas fitted on
    the rest, RMSDs on the one left out.
    """
    others = [c for c in conditions if c != radius]
    if not others or reg[others[0]].nunique() < 2:
        notes.append("held-out check skipped: it needs at least 2 values of another condition")
        return None
    key = others[0]
    held = []
    for value in sorted(reg[key].unique()):
        train = reg[reg[key] != value]
        if train["radius"].nunique() < 3:
            continue
        lam, _ = fit_lambdas(train)
        lam, _ = refine_lambdas(lam, _curves(train, curves), alpha5, spec.step)
        for row in reg[reg[key] == value].to_dict("records"):
            obs = curves[curves["condition"] == row["condition"]]
            pred = predict_from_lambdas(
                lam, row["radius"], row["entropy"], row["envsize"], row["steps"], alpha5, spec.step
            )
            idx = np.round(obs["time"].to_numpy() / spec.step).astype(int)
            held.append(
                {
                    f"held-out {key}": value,
                    radius: row["radius"],
                    "rmsd_w": rmsd(pred["wander"].to_numpy()[idx], obs["wander"]),
                    "rmsd_b": rmsd(pred["beacon"].to_numpy()[idx], obs["beacon"]),
                }
            )
    return pd.DataFrame(held) if held else None


# ---------------------------------------------------------------------- report
def _curve_figure(obs: pd.DataFrame, spec: MacroSpec, title: str) -> str:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import seaborn as sns

    # styles as context managers: set_theme would restyle every later figure of the process
    with sns.axes_style("whitegrid"), sns.plotting_context("notebook"):
        fig, ax = plt.subplots(figsize=(7, 3.6))
        _draw_curves(ax, obs, spec, title)
        data = figure_data(fig)
    plt.close(fig)
    return data


def _draw_curves(ax, obs: pd.DataFrame, spec: MacroSpec, title: str) -> None:
    t = obs["time"].to_numpy()
    names = spec.names()
    for col, colour, name in (
        ("wander", "tab:orange", spec.moving),
        ("beacon", "tab:blue", spec.settled),
    ):
        mean, se = obs[col].to_numpy(), obs[f"{col}_se"].fillna(0).to_numpy()
        ax.fill_between(t, mean - se, mean + se, color=colour, alpha=0.25, lw=0)
        ax.plot(t, mean, color=colour, lw=1.5, label=f"{name}: simulated mean \u00b1 s.e.")
        ax.plot(t, obs[f"{col}_fit"], color=colour, ls="--", lw=1.2,
                label=f"{name}: recurrence, fitted {names['a0']}, {names['alpha6']}")  # fmt: skip
        if f"{col}_lambda" in obs and obs[f"{col}_lambda"].notna().any():
            ax.plot(t, obs[f"{col}_lambda"], color=colour, ls=":", lw=1.5,
                    label=f"{name}: recurrence from fitted \u03bb")  # fmt: skip
        if f"{col}_rates" in obs and obs[f"{col}_rates"].notna().any():
            ax.plot(t, obs[f"{col}_rates"], color=colour, ls="-.", lw=1.2,
                    label=f"{name}: rate equations from the event log")  # fmt: skip
    ax.set_xlabel("time (s)")
    ax.set_ylabel("robots")
    ax.set_title(title)
    ax.legend(fontsize=7, loc="upper left", ncol=1)
    ax.figure.tight_layout()


def _published_columns(table: pd.DataFrame, spec: MacroSpec) -> pd.DataFrame:
    """The fit table with the paper's numbers of the same condition beside ours."""
    t = table.copy()
    keys = spec.condition_keys
    names = sorted({n for values in spec.published.values() for n in values})
    for name in names:
        t[f"paper {name}"] = [
            spec.published.get(tuple(row.get(k) for k in keys), {}).get(name, np.nan)
            if all(k in row for k in keys)
            else np.nan
            for row in t.to_dict("records")
        ]
    return t


#: Columns of a run the fit report's runs table shows (all of them go to runs.csv).
RUN_COLUMNS = ("run_id", "rep", "time", "end_reason", "status")


def methods_note(overall: pd.DataFrame, spec: MacroSpec) -> str:
    """What the methods table holds, in as many words as it has rows."""
    ours = [m for m in overall["method"] if not str(m).startswith("paper")]
    ways = "one way" if len(ours) == 1 else f"{len(ours)} ways"
    n = spec.names()
    text = f"The same runs, {n['a0']} and {n['alpha6']} per condition got {ways} (one row each)"
    if any(str(m).startswith("the paper's method") for m in ours):
        text += (
            f". In the paper's method errors small in parameter space, such as 1e-4 in "
            f"{n['alpha6']}, "
            "compound over thousands of steps; the joint refinement fits the same six lambdas "
            "to all count curves at once, minimising the mean RMSD it is judged on"
        )
    elif len(ours) == 1:
        text += ": the lambda regression did not run (see the note above)"
    if len(ours) < len(overall):
        text += ". Then the paper's own figures"
    return text + "."


def write_fit_report(
    result: dict,
    summaries: pd.DataFrame,
    spec: MacroSpec,
    out: str | Path,
    meta: list,
    conditions: Sequence[str] = (),
) -> Path:
    """Write ``out/fit_report.html`` and every run's summary as ``out/runs.csv``; returns the
    HTML's path.

    Args:
        result: :func:`analyse`'s result.
        summaries: one row per run.
        spec: the model's MACRO.
        out: the output folder.
        meta: (name, value) rows of the page's header.
        conditions: the columns that tell conditions apart (shown in the runs table).

    """
    out = Path(out)
    t = _published_columns(result["table"], spec)
    overall = methods(result["table"], spec)
    lambdas = None
    if result["lambdas"] is not None:
        lam, se = result["lambdas"]
        lambdas = pd.DataFrame(
            {
                "lambda": list(lam),
                "joint refinement": list(lam.values()),
                "stderr": [se[k] for k in lam],
                "paper's method (regressions)": [result["lambdas_regressed"][k] for k in lam],
                "paper": [(spec.lambdas or {}).get(k, np.nan) for k in lam],
            }
        )
    heldout = result["heldout"]
    held_text = None
    if heldout is not None:
        held_text = spoken(
            f"Mean held-out RMSD: w {heldout['rmsd_w'].mean():.3g}, b "
            f"{heldout['rmsd_b'].mean():.3g} (in-sample: w {t['rmsd_w'].mean():.3g}, b "
            f"{t['rmsd_b'].mean():.3g}).",
            spec,
        )
    # panels in the fits' order: the condition values' own (6, 12, 24), not their text's
    curves = result["curves"].groupby("condition", sort=False)
    titles = {c: f"{c} ({int(o['runs'].max())} runs)" for c, o in curves}
    figures = [
        {"title": titles[c], "src": _curve_figure(curves.get_group(c), spec, titles[c])}
        for c in result["fits"]["condition"]
    ]
    runs = summaries.drop(columns=["traceback", "error"], errors="ignore")
    out.mkdir(parents=True, exist_ok=True)
    runs.to_csv(out / "runs.csv", index=False)
    shown = [c for c in dict.fromkeys([RUN_COLUMNS[0], *conditions, *RUN_COLUMNS[1:]]) if c in runs]
    return render_page(
        "fit_report.html.j2",
        out / "fit_report.html",
        title=f"Macroscopic model vs simulation: {spec.moving} and {spec.settled}",
        subtitle=spec.source,
        summary_label=spec.summary_label,
        published_label=spec.published_label,
        meta=meta,
        notes=result["notes"],
        names=spec.names(),
        legend=rate_legend(spec),
        methods_note=methods_note(overall, spec),
        fits=table(speak(t, spec), digits=4),
        overall=table(speak(overall, spec), digits=4, text_columns=("method",)),
        lambdas=None if lambdas is None else table(lambdas, digits=4),
        heldout=None if heldout is None else table(speak(heldout, spec), digits=4),
        held_text=held_text,
        figures=figures,
        runs=table(
            runs[shown].sort_values([c for c in (*conditions, "rep") if c in shown], kind="stable"),
            digits=4,
            text_columns=("run_id", "end_reason", "status"),
        ),
        runs_csv="runs.csv",
    )
