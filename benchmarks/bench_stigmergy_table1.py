"""Table 1 of Arnaldo et al. (2018) reproduced and timed: 4 maps x 4 radii x 30 runs.

Usage:
    python benchmarks/bench_stigmergy_table1.py                 # the full reproduction
    python benchmarks/bench_stigmergy_table1.py --runs 3        # a quick look
    python benchmarks/bench_stigmergy_table1.py --maps hall100 --radii 20 30 40 --runs 10

Runs go through :func:`analysis.sweep.run_sweep` on all cores: a progress bar, each finished
run written at once to ``<out>/runs`` and ``<out>/series`` (Parquet), and a restarted
benchmark skips the runs already there (so the wall time printed is that of this session's
runs only; use a fresh ``--out`` to time the whole reproduction). Runs are keyed by their
parameters, which name a map but do not pin its walls: stored runs whose ``map_digest`` is not
the current map's (or that have none) are deleted first and run again. Prints the machine's load
before and after (the machine may be shared), our Table 1 beside the paper's, the mean RMSDs
beside the paper's Table 2, and writes ``<out>/table1.csv`` and the HTML fit report.
"""

import argparse
import os
import time
from pathlib import Path

import pandas as pd

from analysis.fit_report import analyse, sweep_grid, write_report
from models.stigmergy.params import PAPER_TABLE1, PAPER_TABLE2

#: Our reconstructions of the paper's Table 1 maps, by the paper's map id.
PAPER_MAPS = {"hall100": 1, "hall100x200": 2, "divided": 3, "complex": 4}


def _load() -> str:
    one, five, fifteen = os.getloadavg()
    return f"load average {one:.2f} {five:.2f} {fifteen:.2f} on {os.cpu_count()} cores"


def _drop_stale(out: Path, maps: list[str]) -> int:
    """Delete stored runs of ``maps`` made on other walls than today's; returns how many."""
    from abm.worlds import builtin_map, map_digest
    from analysis.sweep import load_results

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


def _table(result: dict) -> pd.DataFrame:
    """Our Table 1 rows with the paper's numbers beside them (``p_`` columns)."""
    t1 = result["table1"]
    rows = []
    for r in t1.itertuples():
        row = {
            "map": r.map,
            "id": PAPER_MAPS.get(r.map),
            "C_rb": r.radius,
            "runs": r.runs,
            "w": r.w,
            "b": r.b,
            "w_hat": getattr(r, "w_hat", float("nan")),
            "b_hat": getattr(r, "b_hat", float("nan")),
            "t": r.t,
            "ca": r.ca,
            "cb": r.cb,
            "rmsd_w": getattr(r, "rmsd_w", float("nan")),
            "rmsd_b": getattr(r, "rmsd_b", float("nan")),
            "rmsd_w_reg": getattr(r, "rmsd_w_reg", float("nan")),
            "rmsd_b_reg": getattr(r, "rmsd_b_reg", float("nan")),
            "rmsd_w_fit": r.rmsd_w_fit,
            "rmsd_b_fit": r.rmsd_b_fit,
        }
        paper = PAPER_TABLE1.get((row["id"], int(r.radius)))
        if paper is not None:
            names = ("w", "b", "w_hat", "b_hat", "t", "ca", "cb", "rmsd_w", "rmsd_b")
            row.update({f"p_{n}": v for n, v in zip(names, paper, strict=True)})
        rows.append(row)
    return pd.DataFrame(rows)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--maps", nargs="+", default=list(PAPER_MAPS))
    parser.add_argument("--radii", nargs="+", type=float, default=[10.0, 20.0, 30.0, 40.0])
    parser.add_argument("--runs", type=int, default=30, help="runs per map and radius")
    parser.add_argument("--seed", type=int, default=2018, help="root seed of the sweep")
    parser.add_argument("--workers", type=int, default=None, help="processes (default: all)")
    parser.add_argument("--out", type=Path, default=Path("out/stigmergy_table1"))
    args = parser.parse_args()

    stale = _drop_stale(args.out, args.maps)
    if stale:
        print(f"deleted {stale} stored runs made on other map walls; they run again")
    print(f"before: {_load()}", flush=True)
    start = time.perf_counter()
    summaries, counts = sweep_grid(
        args.maps, args.radii, args.runs, args.out, seed=args.seed, workers=args.workers
    )
    elapsed = time.perf_counter() - start
    print(f"after:  {_load()}")
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

    result = analyse(summaries, counts)
    table = _table(result)
    order = {m: i for i, m in enumerate(PAPER_MAPS)}
    table = table.sort_values(["map", "C_rb"], key=lambda c: c.map(order) if c.name == "map" else c)
    table.to_csv(args.out / "table1.csv", index=False)
    show = ["id", "C_rb", "w", "p_w", "b", "p_b", "w_hat", "p_w_hat", "b_hat", "p_b_hat"]
    show += ["t", "p_t", "ca", "p_ca", "cb", "p_cb", "rmsd_w", "p_rmsd_w", "rmsd_b", "p_rmsd_b"]
    show = [c for c in show if c in table]
    print("\nTable 1 (ours beside the paper's p_ columns; w_hat, b_hat, rmsd from our lambdas):")
    print(table[show].to_string(index=False, float_format=lambda v: f"{v:.4g}"))
    print("\nMean RMSD over these maps and radii (paper's Table 2: 10 maps):")
    for label, w, b in (
        ("lambda model (joint fit)", "rmsd_w", "rmsd_b"),
        ("lambda model (regressions)", "rmsd_w_reg", "rmsd_b_reg"),
        ("a0, alpha6 per curve", "rmsd_w_fit", "rmsd_b_fit"),
    ):
        print(f"  {label:27s} w {table[w].mean():.4g}  b {table[b].mean():.4g}")
    paper_w = [
        PAPER_TABLE1[(PAPER_MAPS[m], int(r))][7]
        for m, r in zip(table["map"], table["C_rb"], strict=True)
        if (PAPER_MAPS.get(m), int(r)) in PAPER_TABLE1
    ]
    paper_b = [
        PAPER_TABLE1[(PAPER_MAPS[m], int(r))][8]
        for m, r in zip(table["map"], table["C_rb"], strict=True)
        if (PAPER_MAPS.get(m), int(r)) in PAPER_TABLE1
    ]
    if paper_w:
        print(
            f"  {'paper, these Table 1 rows':27s} w {sum(paper_w) / len(paper_w):.4g}  "
            f"b {sum(paper_b) / len(paper_b):.4g}"
        )
    print(
        f"  {'paper, Table 2 (10 maps)':27s} w {PAPER_TABLE2['rmsd_w'][0]:.4g}  "
        f"b {PAPER_TABLE2['rmsd_b'][0]:.4g}"
    )
    if result.get("lambdas") is not None:
        lam, _ = result["lambdas"]
        print("lambdas: " + ", ".join(f"{k}={v:.4g}" for k, v in lam.items()))
    meta = f"benchmark: {len(summaries)} runs, {elapsed:.0f} s wall this session; {_load()}"
    print(f"wrote {args.out / 'table1.csv'}")
    print(f"wrote {write_report(result, summaries, args.out, meta)}")


if __name__ == "__main__":
    main()
