"""Table 1 of Arnaldo et al. (2018) reproduced and timed: 4 maps x 4 radii x 30 runs.

Usage:
    python benchmarks/bench_stigmergy_table1.py                 # the full reproduction
    python benchmarks/bench_stigmergy_table1.py --runs 3        # a quick look
    python benchmarks/bench_stigmergy_table1.py --maps hall100 --radii 20 30 40 --runs 10

Runs go through :func:`analysis.fit.fit_runs` (a resumable sweep on all cores): a progress
bar, each finished run written at once to ``<out>/runs`` and ``<out>/series`` (Parquet), and a
restarted benchmark skips the runs already there (so the wall time printed is that of this
session's runs only; use a fresh ``--out`` to time the whole reproduction). Runs are keyed by
their parameters, which name a map but do not pin its walls: stored runs whose ``map_digest``
is not the current map's (or that have none) are deleted first and run again. Prints the
machine's load before and after, our Table 1 beside the paper's, the mean RMSDs of both
fitting methods (the paper's: per-curve fits then the two regressions; ours: the joint
refinement) beside the paper's Tables 1 and 2, a diagnosis per map and radius (which
regression costs the paper's method its RMSD), and a check of the paper's own numbers (its
published lambdas against its Table 1 predictions); writes ``<out>/table1.csv``,
``<out>/fit_table.csv`` (every column of the fit) and the HTML fit report. The same tables
come from ``abm fit stigmergy --read <out>``.
"""

import argparse
import os
import time
from pathlib import Path

import pandas as pd
from machine import load_average  # benchmarks/machine.py, beside this script

from analysis.fit import analyse, fit_runs, methods, write_fit_report
from analysis.macro import predict_from_lambdas
from models.environments import MAPS, builtin_map
from models.stigmergy.published import LAMBDAS, MACRO, MAP_OF_ID, TABLE1, TABLE1_COLUMNS

#: Our reconstructions of the paper's Table 1 maps, in the paper's order.
PAPER_MAPS = [MAP_OF_ID[i] for i in sorted(MAP_OF_ID)]
ID_OF_MAP = {name: i for i, name in MAP_OF_ID.items()}


def _drop_stale(out: Path, maps: list[str]) -> int:
    """Delete stored runs of ``maps`` made on other walls than today's; returns how many."""
    from analysis.sweep import load_results
    from models.environments import builtin_map, map_digest

    if not (out / "runs").is_dir():
        return 0
    rows = load_results(out, failed=False)
    if rows.empty:
        return 0
    digest = rows["map_digest"] if "map_digest" in rows else pd.Series(None, index=rows.index)
    current = {m: map_digest(builtin_map(m)) for m in maps}
    stale = rows["map"].isin(maps) & (digest != rows["map"].map(current))
    for run_id in rows.loc[stale, "run_id"]:
        for sub in ("runs", "series"):
            (out / sub / f"{run_id}.parquet").unlink(missing_ok=True)
    return int(stale.sum())


def _table(result: dict, summaries: pd.DataFrame) -> pd.DataFrame:
    """Our Table 1 rows (with ca, cb) and the paper's numbers beside them (``p_`` columns)."""
    t1 = result["table"]
    rows = []
    for r in t1.to_dict("records"):
        runs = summaries[
            (summaries["map"] == r["map"])
            & (summaries["pheromone_radius"] == r["pheromone_radius"])
        ]
        row = {
            "map": r["map"],
            "id": ID_OF_MAP.get(r["map"]),
            "C_rb": r["pheromone_radius"],
            "runs": r["runs"],
            **{k: r.get(k, float("nan")) for k in ("w", "b", "w_hat", "b_hat", "t")},
            "ca": runs["ca"].mean(),
            "cb": runs["cb"].mean(),
            **{
                k: r.get(k, float("nan"))
                for k in (
                    "rmsd_w",
                    "rmsd_b",
                    "rmsd_w_reg",
                    "rmsd_b_reg",
                    "rmsd_w_fit",
                    "rmsd_b_fit",
                )
            },  # fmt: skip
        }
        paper = TABLE1.get((row["id"], int(r["pheromone_radius"])))
        if paper is not None:
            row.update({f"p_{n}": v for n, v in zip(TABLE1_COLUMNS, paper, strict=True)})
        rows.append(row)
    return pd.DataFrame(rows)


def _g(v: float) -> str:
    return f"{v:.4g}" if abs(v) >= 1e-3 or v == 0 else f"{v:.2e}"


def _paper_check() -> None:
    """The paper's published lambdas against its own Table 1 predictions w_hat, b_hat.

    The recurrence from the published lambdas (l1, l2 < 0, see published.py), run with the
    paper's time base (0.5 s steps, alpha5 = 0.01, w0 = 0, b0 = 1) for t / 0.5 steps, against
    the w_hat, b_hat printed in Table 1 (whose sum is 1 + t / 50 in every row: the same time
    base).
    """
    print("\nThe paper's own numbers: its published lambdas vs its Table 1 predictions at t")
    rows = []
    for (map_id, radius), values in sorted(TABLE1.items()):
        row = dict(zip(TABLE1_COLUMNS, values, strict=True))
        name = MAP_OF_ID[map_id]
        arena = builtin_map(name)  # the paper's size: 100 x 100 m, map 2 100 x 200 m
        pred = predict_from_lambdas(
            LAMBDAS,
            radius,
            MAPS[name].paper_entropy,
            arena.width * arena.height,
            int(row["t"] / 0.5),
        )
        rows.append(
            {
                "id": map_id,
                "C_rb": radius,
                "t": row["t"],
                "w_hat (lambdas)": pred["wander"].iloc[-1],
                "w_hat (Table 1)": row["w_hat"],
                "b_hat (lambdas)": pred["beacon"].iloc[-1],
                "b_hat (Table 1)": row["b_hat"],
                "w_hat + b_hat (Table 1)": row["w_hat"] + row["b_hat"],
                "1 + t/50": 1 + row["t"] / 50,
            }
        )
    print(pd.DataFrame(rows).to_string(index=False, float_format=lambda v: f"{v:.4g}"))
    _best_form_for_table1()


def _best_form_for_table1() -> None:
    """Can any lambdas of the paper's form give its Table 1 predictions? The form makes a0 a
    function of the map and alpha6 of the radius; fitting one a0 per map and one alpha6 per
    radius (8 free values, more freedom than the 6 lambdas) to the 16 rows' w_hat and b_hat
    bounds from below how closely any lambdas can.
    """
    import numpy as np
    from scipy.optimize import least_squares

    from analysis.macro import final_counts

    keys = sorted(TABLE1)
    maps = sorted({m for m, _ in keys})
    radii = sorted({r for _, r in keys})
    rows = [dict(zip(TABLE1_COLUMNS, TABLE1[k], strict=True)) for k in keys]

    def residual(x: np.ndarray) -> np.ndarray:
        out = []
        for (m, r), row in zip(keys, rows, strict=True):
            a0, alpha6 = x[maps.index(m)], 1.0 - x[len(maps) + radii.index(r)] ** 2
            w, b = final_counts(a0, alpha6, 0.01, int(row["t"] / 0.5))
            out += [w - row["w_hat"], b - row["b_hat"]]
        return np.array(out)

    rng = np.random.default_rng(0)
    best = min(
        (
            least_squares(
                residual,
                np.r_[rng.uniform(0.01, 0.5, len(maps)), rng.uniform(0.005, 0.1, len(radii))],
                bounds=(0.0, 1.0),
            )
            for _ in range(12)
        ),
        key=lambda sol: sol.cost,
    )
    err = residual(best.x)[::2]
    print(
        "best a0 per map and alpha6 per radius for Table 1's w_hat, b_hat (12 starts): "
        f"w_hat off by {np.sqrt(np.mean(err**2)):.2f} robots rms, at most {np.abs(err).max():.2f} "
        f"(map {keys[int(np.abs(err).argmax())][0]}, C_rb {keys[int(np.abs(err).argmax())][1]})"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--maps", nargs="+", default=PAPER_MAPS)
    parser.add_argument("--radii", nargs="+", type=float, default=[10.0, 20.0, 30.0, 40.0])
    parser.add_argument("--runs", type=int, default=30, help="runs per map and radius")
    parser.add_argument("--seed", type=int, default=2018, help="root seed of the sweep")
    parser.add_argument("--workers", type=int, default=None, help="processes (default: all)")
    parser.add_argument("--out", type=Path, default=Path("out/stigmergy_table1"))
    args = parser.parse_args()

    stale = _drop_stale(args.out, args.maps)
    if stale:
        print(f"deleted {stale} stored runs made on other map walls; they run again")
    print(f"before: {load_average()}", flush=True)
    start = time.perf_counter()
    grid = {"map": args.maps, "pheromone_radius": args.radii}
    summaries, counts, conditions = fit_runs(
        "stigmergy", grid, args.runs, args.out, seed=args.seed, workers=args.workers
    )
    elapsed = time.perf_counter() - start
    print(f"after:  {load_average()}")
    print(
        f"{len(summaries)} runs on disk in {args.out}; this session took {elapsed:.0f} s wall "
        f"({elapsed / 60:.1f} min) with {args.workers or os.cpu_count()} workers; the runs "
        f"together took {summaries['wall_time'].sum():.0f} s of run time"
    )
    ended = summaries.groupby(["map", "pheromone_radius"])["end_reason"].agg(
        lambda s: (s == "coverage").mean()
    )
    if (ended < 1).any():
        print("runs ending before ca reached the target (share ended by coverage):")
        print(ended[ended < 1].round(2).to_string())

    result = analyse(summaries, counts, MACRO, conditions)
    table = _table(result, summaries)
    order = {m: i for i, m in enumerate(PAPER_MAPS)}
    table = table.sort_values(["map", "C_rb"], key=lambda c: c.map(order) if c.name == "map" else c)
    table.to_csv(args.out / "table1.csv", index=False)
    show = ["id", "C_rb", "w", "p_w", "b", "p_b", "w_hat", "p_w_hat", "b_hat", "p_b_hat"]
    show += ["t", "p_t", "ca", "p_ca", "cb", "p_cb", "rmsd_w", "p_rmsd_w", "rmsd_b", "p_rmsd_b"]
    show = [c for c in show if c in table]
    print("\nTable 1 (ours beside the paper's p_ columns; w_hat, b_hat, rmsd from our lambdas):")
    print(table[show].to_string(index=False, float_format=lambda v: f"{v:.4g}"))
    print("\nMean (std) RMSD over these maps and radii, by fitting method:")
    print(methods(result["table"], MACRO).to_string(index=False, float_format=lambda v: f"{v:.3g}"))
    full = result["table"].sort_values(
        ["map", "pheromone_radius"], key=lambda c: c.map(order) if c.name == "map" else c
    )
    full.to_csv(args.out / "fit_table.csv", index=False)
    print("\nDiagnosis per map and radius (a0, alpha6 per curve +- s.e., and as regressed):")
    diag = ["map", "pheromone_radius", "steps", "a0", "a0_se", "a0_reg", "alpha6", "alpha6_se"]
    diag += ["alpha6_reg", "rmsd_w_reg", "rmsd_b_reg", "rmsd_w_reg_alpha6", "rmsd_w_reg_a0"]
    diag += ["rmsd_w", "rmsd_w_fit"]
    print(full[[c for c in diag if c in full]].to_string(index=False, float_format=_g))
    _paper_check()
    if result.get("lambdas") is not None:
        lam, _ = result["lambdas"]
        print("lambdas: " + ", ".join(f"{k}={v:.4g}" for k, v in lam.items()))
    meta = [
        ("model", "stigmergy"),
        ("runs", f"{len(summaries)} in {args.out}"),
        ("wall time", f"{elapsed:.0f} s this session; {load_average()}"),
    ]
    print(f"wrote {args.out / 'table1.csv'}")
    print(f"wrote {write_fit_report(result, summaries, MACRO, args.out, meta)}")


if __name__ == "__main__":
    main()
