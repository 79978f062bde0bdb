"""Model-vs-simulation fitting of the stigmergy swarm: agent runs, fits, one HTML report.

``run_grid`` runs :class:`StigmergyModel` over maps x radii x seeds in worker processes (a
picklable top-level run function; per-run seeds from ``SeedSequence.spawn``). ``analyse`` fits
the recurrence per (map, radius), regresses the lambdas, predicts with them (Table 1 / Table 2
equivalents) and checks the lambdas on held-out maps. ``write_report`` writes one
self-contained HTML page (figures embedded as PNG).
"""

import base64
import io
import time
from concurrent.futures import Executor
from pathlib import Path

import numpy as np
import pandas as pd

from analysis.macro import (
    fit_lambdas,
    fit_recurrence,
    predict_from_lambdas,
    refine_lambdas,
    rmsd,
)
from analysis.pools import process_pool

__all__ = ["analyse", "run_grid", "run_stigmergy", "sweep_grid", "write_report"]


def run_stigmergy(task: dict) -> tuple[dict, pd.DataFrame]:
    """One agent run (picklable): ``task`` holds ``map``, ``radius``, ``seed`` and model kwargs.

    Returns the run's summary and its state counts (with ``map``, ``radius``, ``seed``
    columns and a last row at the run's end time).
    """
    from models.stigmergy import StigmergyModel

    kwargs = dict(task)
    map_name, radius, seed = kwargs.pop("map"), kwargs.pop("radius"), kwargs.pop("seed")
    start = time.perf_counter()
    model = StigmergyModel(map_name, radius, seed=seed, **kwargs).run()
    summary = model.summary()
    summary["wall_time"] = time.perf_counter() - start
    counts = model.state_counts()
    end = counts.iloc[[-1]].copy()
    end["time"] = model.env.now
    counts = pd.concat([counts, end], ignore_index=True)
    counts["map"], counts["radius"], counts["seed"] = map_name, float(radius), seed
    return summary, counts


def run_grid(
    maps: list[str],
    radii: list[float],
    runs: int,
    seed: int = 0,
    workers: int = 2,
    executor: Executor | None = None,
    progress: bool = True,
    **model_kwargs,
) -> tuple[pd.DataFrame, pd.DataFrame]:
    """All runs of maps x radii x ``runs`` seeds; returns (summaries, counts) DataFrames."""
    seeds = np.random.SeedSequence(seed).spawn(len(maps) * len(radii) * runs)
    tasks = []
    for i, (m, r, k) in enumerate((m, r, k) for m in maps for r in radii for k in range(runs)):
        s = int(seeds[i].generate_state(1)[0])
        tasks.append({"map": m, "radius": float(r), "seed": s, **model_kwargs, "_run": k})
    for t in tasks:
        t.pop("_run")
    own = executor is None
    executor = executor or process_pool(workers)
    try:
        results = executor.map(run_stigmergy, tasks)
        if progress:
            from tqdm import tqdm

            results = tqdm(results, total=len(tasks), desc="agent runs", unit="run")
        results = list(results)
    finally:
        if own:
            executor.shutdown()
    summaries = pd.DataFrame([s for s, _ in results])
    counts = pd.concat([c for _, c in results], ignore_index=True)
    return summaries, counts


def sweep_grid(
    maps: list[str],
    radii: list[float],
    runs: int,
    out: str | Path,
    seed: int = 0,
    workers: int | None = None,
    progress: bool = True,
    **model_kwargs,
) -> tuple[pd.DataFrame, pd.DataFrame]:
    """:func:`run_grid` as a resumable sweep (:func:`analysis.sweep.run_sweep`).

    Each finished run is written to ``out`` at once (``runs/``, ``series/``); runs already
    there are skipped, so an interrupted reproduction picks up where it stopped. Returns the
    same ``(summaries, counts)`` as :func:`run_grid`, for the runs of this grid.
    """
    from analysis.sweep import load_results, run_sweep
    from models.stigmergy import StigmergyModel

    grid = {"map": list(maps), "pheromone_radius": [float(r) for r in radii]}
    grid.update({k: [v] for k, v in model_kwargs.items()})
    rows = run_sweep(
        StigmergyModel,
        grid,
        replications=runs,
        seed=seed,
        out=out,
        workers=workers,
        time_series=True,
        progress=progress,
    )
    failed = rows[rows["status"] != "ok"]
    if len(failed):
        raise RuntimeError(f"{len(failed)} runs failed, first: {failed['error'].iloc[0]}")
    keep = rows["map"].isin(maps) & rows["pheromone_radius"].isin(grid["pheromone_radius"])
    keep &= rows["rep"] < runs
    for key, value in model_kwargs.items():
        keep &= rows[key] == value
    summaries = rows[keep].reset_index(drop=True)
    series = load_results(out, series=True)
    series = series[series["run_id"].isin(summaries["run_id"])]
    ends = summaries[["run_id", "time"]].rename(columns={"time": "end"})
    series = series.merge(ends, on="run_id")
    last = series.sort_values("time", kind="stable").groupby("run_id").tail(1).copy()
    last["time"] = last["end"]  # the counts hold until the run ends
    counts = pd.concat([series, last], ignore_index=True).drop(columns="end")
    info = summaries[["run_id", "map", "pheromone_radius", "seed"]].rename(
        columns={"pheromone_radius": "radius"}
    )
    counts = counts.merge(info, on="run_id").sort_values(["run_id", "time"], kind="stable")
    return summaries, counts.reset_index(drop=True)


def analyse(summaries: pd.DataFrame, counts: pd.DataFrame, step: float = 0.5) -> dict:
    """Fit per (map, radius), regress lambdas, predict with them, held-out check.

    Returns a dict of DataFrames: ``fits`` (per map and radius: a0, alpha6 +- stderr, RMSDs of
    the direct fit), ``table1`` (final w, b simulated vs predicted, t, ca, cb, RMSDs of the
    lambda model), ``curves`` (observed mean +- se and predictions over time), ``lambdas``,
    ``heldout`` (leave-one-map-out RMSDs) and ``notes`` (list of str).
    """
    notes: list[str] = []
    rows, curves = [], []
    for (m, r), c in counts.groupby(["map", "radius"], sort=True):
        fit = fit_recurrence(c, step=step, alpha5=step / 50.0 * 1.0)
        s = summaries[(summaries["map"] == m) & (summaries["pheromone_radius"] == r)]
        rows.append(
            {
                "map": m,
                "radius": r,
                "runs": len(s),
                "entropy": float(s["entropy"].iloc[0]),
                "envsize": float(s["envsize"].iloc[0]),
                "a0": fit.params["a0"],
                "a0_se": fit.stderr["a0"],
                "alpha6": fit.params["alpha6"],
                "alpha6_se": fit.stderr["alpha6"],
                "rmsd_w_fit": fit.rmsd_w,
                "rmsd_b_fit": fit.rmsd_b,
                "w": s["wander"].mean(),
                "b": s["beacon"].mean(),
                "t": s["time"].mean(),
                "ca": s["ca"].mean(),
                "cb": s["cb"].mean(),
                "steps": int(round(fit.observed["time"].iloc[-1] / step)),
            }
        )
        obs = fit.observed.assign(map=m, radius=r)
        obs["wander_fit"] = fit.predicted["wander"].to_numpy()
        obs["beacon_fit"] = fit.predicted["beacon"].to_numpy()
        curves.append(obs)
    fits = pd.DataFrame(rows)
    curves = pd.concat(curves, ignore_index=True)
    out = {"fits": fits, "curves": curves, "notes": notes}
    if fits["radius"].nunique() < 3:
        notes.append("lambda regression skipped: it needs at least 3 radii (quadratic in C_rb)")
        out["lambdas"] = None
        out["table1"] = fits
        out["heldout"] = None
        return out
    regressed, _ = fit_lambdas(fits)
    lambdas, lambdas_se = refine_lambdas(regressed, _lambda_curves(fits, curves), step / 50, step)
    out["lambdas"] = (lambdas, lambdas_se)
    out["lambdas_regressed"] = regressed
    notes.append(
        "lambdas: the paper's regressions (alpha6 on C_rb, a0 on entropy and size) give the "
        "start values, then the six lambdas are fitted jointly to all count curves, "
        "minimising the mean RMSD of w and b over them (the Table 2 figure; "
        "analysis.macro.refine_lambdas); rmsd_*_reg are the RMSDs of the regressed start"
    )
    curves["wander_lambda"] = np.nan
    curves["beacon_lambda"] = np.nan
    t1 = []
    for row in fits.itertuples():
        sel = (curves["map"] == row.map) & (curves["radius"] == row.radius)
        obs = curves[sel]
        idx = np.round(obs["time"].to_numpy() / step).astype(int)
        got = {}
        for name, lam in (("", lambdas), ("_reg", regressed)):
            pred = predict_from_lambdas(
                lam, row.radius, row.entropy, row.envsize, row.steps, step / 50.0, step
            )
            pw, pb = pred["wander"].to_numpy()[idx], pred["beacon"].to_numpy()[idx]
            got[f"rmsd_w{name}"] = rmsd(pw, obs["wander"])
            got[f"rmsd_b{name}"] = rmsd(pb, obs["beacon"])
            if not name:
                curves.loc[sel, "wander_lambda"] = pw
                curves.loc[sel, "beacon_lambda"] = pb
                got.update(w_hat=pw[-1], b_hat=pb[-1])
        t1.append({**row._asdict(), **got})
    out["table1"] = pd.DataFrame(t1).drop(columns=["Index"])
    held = []
    maps = sorted(fits["map"].unique())
    if len(maps) >= 2:
        for m in maps:
            train = fits[fits["map"] != m]
            if train["radius"].nunique() < 3:
                continue
            lam, _ = fit_lambdas(train)
            lam, _ = refine_lambdas(lam, _lambda_curves(train, curves), step / 50, step)
            for row in fits[fits["map"] == m].itertuples():
                obs = curves[(curves["map"] == m) & (curves["radius"] == row.radius)]
                pred = predict_from_lambdas(
                    lam, row.radius, row.entropy, row.envsize, row.steps, step / 50.0, step
                )
                idx = np.round(obs["time"].to_numpy() / step).astype(int)
                held.append(
                    {
                        "held_out_map": m,
                        "radius": row.radius,
                        "rmsd_w": rmsd(pred["wander"].to_numpy()[idx], obs["wander"]),
                        "rmsd_b": rmsd(pred["beacon"].to_numpy()[idx], obs["beacon"]),
                    }
                )
    else:
        notes.append("held-out check skipped: it needs at least 2 maps")
    out["heldout"] = pd.DataFrame(held) if held else None
    return out


def _lambda_curves(fits: pd.DataFrame, curves: pd.DataFrame) -> list:
    """``(observed, radius, entropy, envsize)`` per row of ``fits`` for :func:`refine_lambdas`."""
    out = []
    for row in fits.itertuples():
        obs = curves[(curves["map"] == row.map) & (curves["radius"] == row.radius)]
        out.append((obs, row.radius, row.entropy, row.envsize))
    return out


# ---------------------------------------------------------------------- report
def _figure_png(fig) -> str:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=90, bbox_inches="tight")
    return base64.b64encode(buf.getvalue()).decode()


def _curve_figure(obs: pd.DataFrame, title: str):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import seaborn as sns

    sns.set_theme(style="whitegrid", context="notebook")
    fig, ax = plt.subplots(figsize=(7, 3.6))
    t = obs["time"].to_numpy()
    for col, colour, label in (
        ("wander", "tab:orange", "w (wander)"),
        ("beacon", "tab:blue", "b (beacon)"),
    ):
        mean, se = obs[col].to_numpy(), obs[f"{col}_se"].fillna(0).to_numpy()
        ax.fill_between(t, mean - se, mean + se, color=colour, alpha=0.25, lw=0)
        ax.plot(t, mean, color=colour, lw=1.5, label=f"{label}: simulated mean \u00b1 s.e.")
        ax.plot(
            t,
            obs[f"{col}_fit"],
            color=colour,
            ls="--",
            lw=1.2,
            label=f"{label}: recurrence, fitted a0, \u03b16",
        )
        if f"{col}_lambda" in obs and obs[f"{col}_lambda"].notna().any():
            ax.plot(
                t,
                obs[f"{col}_lambda"],
                color=colour,
                ls=":",
                lw=1.5,
                label=f"{label}: recurrence from fitted \u03bb",
            )
    ax.set_xlabel("time (s)")
    ax.set_ylabel("robots")
    ax.set_title(title)
    ax.legend(fontsize=7, loc="upper left", ncol=1)
    fig.tight_layout()
    png = _figure_png(fig)
    plt.close(fig)
    return png


def _html_table(df: pd.DataFrame, digits: int = 4) -> str:
    return df.to_html(
        index=False,
        float_format=lambda v: f"{v:.{digits}g}",
        border=0,
        classes="t",
        na_rep="\u2013",
    )


def write_report(result: dict, summaries: pd.DataFrame, out: Path, meta: str = "") -> Path:
    """Write ``out/report.html`` (and ``out/figures/*.png``); returns the HTML's path."""
    from abm.worlds.bitmap import MAPS
    from models.stigmergy.params import PAPER_LAMBDAS, PAPER_TABLE1, PAPER_TABLE2

    out = Path(out)
    figdir = out / "figures"
    figdir.mkdir(parents=True, exist_ok=True)
    parts = [
        "<html><head><meta charset='utf-8'><title>Stigmergy swarm: model vs simulation</title>",
        "<style>body{font-family:sans-serif;max-width:1100px;margin:auto}"
        "table.t{border-collapse:collapse;font-size:12px}table.t td,table.t th{padding:2px 6px;"
        "border-bottom:1px solid #ddd;text-align:right}.fig{display:inline-block;margin:4px}"
        ".note{color:#a33}</style></head><body>",
        "<h1>Wander/beacon swarm: macroscopic model vs agent simulation</h1>",
        f"<p>Arnaldo et al. (2018), PLOS ONE 13(1): e0190692. {meta}</p>",
    ]
    for note in result["notes"]:
        parts.append(f"<p class='note'>{note}</p>")
    # Table 1.
    t1 = result["table1"].copy()
    paper = []
    for row in t1.itertuples():
        pid = MAPS[row.map].paper_id if row.map in MAPS else None
        p = PAPER_TABLE1.get((pid, int(row.radius))) if pid else None
        paper.append(p if p else (np.nan,) * 9)
    paper = np.array(paper, dtype=float)
    cols = ["map", "radius", "runs", "w", "b"]
    cols += [c for c in ("w_hat", "b_hat") if c in t1]
    cols += ["t", "ca", "cb"]
    cols += [c for c in ("rmsd_w", "rmsd_b", "rmsd_w_reg", "rmsd_b_reg") if c in t1]
    cols += ["rmsd_w_fit", "rmsd_b_fit"]
    table = t1[cols].copy()
    for j, name in enumerate(["w", "b", "w_hat", "b_hat", "t", "ca", "cb", "rmsd_w", "rmsd_b"]):
        table[f"paper {name}"] = paper[:, j]
    parts.append(
        "<h2>Table 1 equivalent</h2><p>Ours: mean over runs of final w, b, end time t "
        "(s), ca and cb (%); w_hat, b_hat and rmsd_w, rmsd_b: the recurrence with a0 and "
        "alpha6 from our fitted lambdas (as the paper); rmsd_*_reg: the same with the "
        "lambdas of the regressions alone, before the joint fit; rmsd_*_fit: the recurrence "
        "with a0, alpha6 fitted to this map and radius alone. 'paper *': the published Table "
        "1 row of the map this one reconstructs (blank for our extra maps).</p>"
    )
    parts.append(_html_table(table))
    # Table 2.
    mean_cols = ["rmsd_w", "rmsd_b", "rmsd_w_reg", "rmsd_b_reg", "rmsd_w_fit", "rmsd_b_fit"]
    mean_cols = [c for c in mean_cols if c in t1]
    t2 = pd.DataFrame(
        {
            "metric": mean_cols,
            "mean": [t1[c].mean() for c in mean_cols],
            "std": [t1[c].std() for c in mean_cols],
            "paper mean": [PAPER_TABLE2.get(c, (np.nan,))[0] for c in mean_cols],
            "paper std": [PAPER_TABLE2.get(c, (np.nan, np.nan))[1] for c in mean_cols],
        }
    )
    parts.append(
        f"<h2>Table 2 equivalent (over {t1['map'].nunique()} maps x "
        f"{t1['radius'].nunique()} radii)</h2>"
    )
    parts.append(_html_table(t2))
    # Lambdas.
    if result["lambdas"] is not None:
        lam, se = result["lambdas"]
        lt = pd.DataFrame(
            {
                "lambda": list(lam),
                "ours": list(lam.values()),
                "stderr": [se[k] for k in lam],
                "regressions alone": [result["lambdas_regressed"][k] for k in lam],
                "paper (signs of l1, l2 restored)": [PAPER_LAMBDAS[k] for k in lam],
            }
        )
        parts.append("<h2>Fitted lambdas</h2>")
        parts.append(_html_table(lt))
        parts.append(
            "<p>alpha6 = l0 + l1 C_rb + l2 C_rb^2; a0 = l3 + l4 sum P log2 P + l5 "
            "envsize (m^2). The per-map, per-radius fits they are regressed on:</p>"
        )
        parts.append(
            _html_table(
                result["fits"][
                    ["map", "radius", "entropy", "envsize", "a0", "a0_se", "alpha6", "alpha6_se"]
                ]
            )
        )
    if result["heldout"] is not None:
        h = result["heldout"]
        parts.append("<h2>Held-out maps (lambdas fitted on the other maps)</h2>")
        parts.append(
            f"<p>Mean held-out RMSD: w {h['rmsd_w'].mean():.3g}, b "
            f"{h['rmsd_b'].mean():.3g} (in-sample: w {t1['rmsd_w'].mean():.3g}, b "
            f"{t1['rmsd_b'].mean():.3g}).</p>"
        )
        parts.append(_html_table(h))
    # Figures.
    parts.append("<h2>w and b over time (cf. the paper's Figs. 4-5)</h2>")
    curves = result["curves"]
    for (m, r), obs in curves.groupby(["map", "radius"], sort=True):
        png = _curve_figure(obs, f"map {m}, C_rb = {r:g} m ({int(obs['runs'].max())} runs)")
        (figdir / f"{m}_r{r:g}.png").write_bytes(base64.b64decode(png))
        parts.append(f"<div class='fig'><img src='data:image/png;base64,{png}'></div>")
    parts.append("<h2>Runs</h2>")
    parts.append(_html_table(summaries))
    parts.append("</body></html>")
    path = out / "report.html"
    path.write_text("\n".join(parts))
    return path
