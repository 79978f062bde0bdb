"""The whole SugarMap figure set, timed: every ``experiments/sugarmap_*.toml`` sweep, then the
one reproduction report with the claims table.

Usage:
    python benchmarks/bench_sugarmap_figures.py                       # all sweeps, all cores
    python benchmarks/bench_sugarmap_figures.py --replications 2      # a quick look
    python benchmarks/bench_sugarmap_figures.py --only fig5 fig15     # some figures

Each sweep goes through the common sweep runner (resumable: runs already stored are skipped, so
use a fresh ``--out`` to time the whole set); all of them share one process pool. Prints the
machine's load before and after, each sweep's runs and when it finished, the total, and where
the report went. The same report comes from ``abm report <out>/sugarmap_*``.
"""

import argparse
import os
import time
from pathlib import Path

from bench_reproductions import run_together
from machine import load_average

from analysis.report import write_report
from analysis.sweep.spec import load_sweep

ROOT = Path(__file__).resolve().parents[1]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=Path("out/sugarmap_figures"))
    parser.add_argument("--replications", type=int, default=None, help="override the files'")
    parser.add_argument("--workers", type=int, default=None, help="default: all cores")
    parser.add_argument("--only", nargs="*", default=None, help="e.g. fig5 fig15 noise")
    args = parser.parse_args()
    files = sorted((ROOT / "experiments").glob("sugarmap_*.toml"))
    if args.only:
        files = [f for f in files if f.stem.removeprefix("sugarmap_") in args.only]
    print(load_average())
    sweeps = [load_sweep(path, args.replications) for path in files]
    folders = [args.out / sweep.name for sweep in sweeps]
    start = time.perf_counter()
    total_runs, _ = run_together(sweeps, folders, args.workers or os.cpu_count())
    total = time.perf_counter() - start
    print(f"{'all sweeps':24s} {total_runs:9d} runs     {total:7.1f} s ({total / 60:.1f} min)")
    print(load_average())
    t0 = time.perf_counter()
    report = write_report(folders, args.out / "report.html")
    print(f"report in {time.perf_counter() - t0:.1f} s")
    print(f"wrote {report}")


if __name__ == "__main__":
    main()
