"""The report's scaling experiment, timed: 42 configurations (W = 2-7 workers x S = 2-8 scouts
per worker) x 10 runs on the empty 20 m room (``experiments/hierarchy_scaling.toml``), then the
reproduction report with the claims table. Target: under 10 minutes on 2 cores.

Usage:
    python benchmarks/bench_hierarchy.py                        # the 420 runs, all cores
    python benchmarks/bench_hierarchy.py --replications 1       # a quick look (42 runs)
    python benchmarks/bench_hierarchy.py --with-controls        # + equal-scout and no-wave sweeps

The sweep goes through the common runner (resumable: runs already stored are skipped, so use a
fresh ``--out`` to time the whole experiment). Prints the machine's load before and after (the
cores may be shared), the runs and the wall time of each sweep, the mean CPU seconds of one run
by configuration size, and where the report went.
"""

import argparse
import os
import time
from pathlib import Path

import pandas as pd
from machine import load_average  # benchmarks/machine.py, beside this script

from abm.pools import process_pool
from analysis.report import write_report
from analysis.sweep.execute import execute
from analysis.sweep.spec import load_sweep

ROOT = Path(__file__).resolve().parents[1]
CONTROLS = ("hierarchy_equal_scouts", "hierarchy_no_waves")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=Path("out/hierarchy_bench"))
    parser.add_argument("--replications", type=int, default=None, help="override the file's")
    parser.add_argument("--workers", type=int, default=None, help="default: all cores")
    parser.add_argument("--with-controls", action="store_true", help="also run the controls")
    args = parser.parse_args()
    names = ["hierarchy_scaling", *(CONTROLS if args.with_controls else ())]
    print(load_average())
    folders = []
    with process_pool(args.workers or os.cpu_count()) as pool:
        for name in names:
            sweep = load_sweep(ROOT / "experiments" / f"{name}.toml", args.replications)
            folder = args.out / sweep.name
            folders.append(folder)
            t0 = time.perf_counter()
            runs = execute(sweep, folder, executor=pool, progress=True)
            seconds = time.perf_counter() - t0
            ok = runs[runs["status"] == "ok"]
            print(f"{name:24s} {len(ok):4d}/{len(runs):<4d} runs ok in {seconds:7.1f} s "
                  f"({seconds / 60:.1f} min)")  # fmt: skip
            if "wall_time" in ok and "N" in ok:
                per = ok.groupby(pd.cut(ok["N"], [0, 20, 40, 70]), observed=True)["wall_time"]
                print("  mean seconds per run by N:", per.mean().round(2).to_dict())
    print(load_average())
    t0 = time.perf_counter()
    report = write_report(folders, args.out / "report.html")
    print(f"report in {time.perf_counter() - t0:.1f} s")
    print(f"wrote {report}")


if __name__ == "__main__":
    main()
