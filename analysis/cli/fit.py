"""``abm fit``: stigmergy agent runs -> macroscopic-model fits -> one HTML report."""

import argparse
import os
import time
from pathlib import Path

import pandas as pd

VERB = "fit"
HELP = "run the stigmergy swarm over maps x radii, fit the wander/beacon recurrence, report"
EXAMPLE = "abm fit --maps hall100 divided --radii 20 30 40 --runs 4 --out out/fit"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Options of ``abm fit``."""
    parser.add_argument(
        "--maps",
        nargs="+",
        default=["hall100"],
        help="built-in map names (see abm.worlds.MAPS) or map files",
    )
    parser.add_argument(
        "--radii",
        nargs="+",
        type=float,
        default=[20.0, 30.0, 40.0],
        help="pheromone radii C_rb (m)",
    )
    parser.add_argument("--runs", type=int, default=5, help="runs per map and radius")
    parser.add_argument("--seed", type=int, default=0, help="root seed of the runs")
    parser.add_argument("--workers", type=int, default=min(2, os.cpu_count() or 1))
    parser.add_argument("--time-limit", type=float, default=15000.0, help="(s)")
    parser.add_argument(
        "--read",
        type=Path,
        default=None,
        help="read runs.parquet/counts.parquet from this folder instead of running",
    )
    parser.add_argument("--out", type=Path, default=Path("out/fit"), help="output folder")


def main(args: argparse.Namespace) -> int:
    """Run (or read), fit, write the report."""
    from abm.errors import ConfigError
    from analysis.fit_report import analyse, run_grid, write_report

    if args.runs < 1:
        raise ConfigError(f"--runs must be at least 1, got {args.runs}")
    args.out.mkdir(parents=True, exist_ok=True)
    start = time.perf_counter()
    if args.read is not None:
        summaries = pd.read_parquet(args.read / "runs.parquet")
        counts = pd.read_parquet(args.read / "counts.parquet")
    else:
        summaries, counts = run_grid(
            [str(m) for m in args.maps],
            args.radii,
            args.runs,
            seed=args.seed,
            workers=args.workers,
            time_limit=args.time_limit,
        )
        summaries.to_parquet(args.out / "runs.parquet")
        counts.to_parquet(args.out / "counts.parquet")
    elapsed = time.perf_counter() - start
    result = analyse(summaries, counts)
    meta = (
        f"{len(summaries)} agent runs ({summaries['map'].nunique()} maps, radii "
        f"{sorted(summaries['pheromone_radius'].unique().tolist())}); simulation wall time "
        f"{elapsed:.0f} s with {args.workers} workers."
    )
    report = write_report(result, summaries, args.out, meta)
    t1 = result["table1"]
    show = [
        c
        for c in (
            "map",
            "radius",
            "w",
            "b",
            "t",
            "ca",
            "cb",
            "rmsd_w",
            "rmsd_b",
            "rmsd_w_fit",
            "rmsd_b_fit",
        )
        if c in t1
    ]
    print(t1[show].to_string(index=False, float_format=lambda v: f"{v:.3g}"))
    print(
        f"\nwrote {args.out / 'runs.parquet'}\nwrote {args.out / 'counts.parquet'}\nwrote {report}"
    )
    return 0
