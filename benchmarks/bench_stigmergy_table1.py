"""Table 1 reproduction benchmark: maps x radii x runs of StigmergyModel, timed.

Usage: python benchmarks/bench_stigmergy_table1.py [--maps ...] [--radii ...] [--runs 30]
       [--workers 2] [--out out/bench_table1]
Prints the wall time and the Table 1 summary; writes runs/counts Parquet and report.html.
"""

import argparse
import time
from pathlib import Path

from analysis.fit_report import analyse, run_grid, write_report

parser = argparse.ArgumentParser()
parser.add_argument("--maps", nargs="+", default=["hall100", "hall100x200", "divided", "complex"])
parser.add_argument("--radii", nargs="+", type=float, default=[10.0, 20.0, 30.0, 40.0])
parser.add_argument("--runs", type=int, default=30)
parser.add_argument("--workers", type=int, default=2)
parser.add_argument("--out", type=Path, default=Path("out/bench_table1"))
args = parser.parse_args()

start = time.perf_counter()
summaries, counts = run_grid(args.maps, args.radii, args.runs, workers=args.workers)
elapsed = time.perf_counter() - start
args.out.mkdir(parents=True, exist_ok=True)
summaries.to_parquet(args.out / "runs.parquet")
counts.to_parquet(args.out / "counts.parquet")
print(
    f"{len(summaries)} runs in {elapsed:.0f} s wall with {args.workers} workers "
    f"({summaries['wall_time'].sum():.0f} s of run time)"
)
table = summaries.groupby(["map", "pheromone_radius"])[
    ["wander", "beacon", "time", "ca", "cb", "wall_time"]
].mean()
print(table.round(2).to_string())
if summaries["pheromone_radius"].nunique() >= 1:
    result = analyse(summaries, counts)
    print(f"wrote {write_report(result, summaries, args.out, f'benchmark: {elapsed:.0f} s')}")
