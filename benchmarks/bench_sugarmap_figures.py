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
from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor, as_completed
from pathlib import Path

from abm.pools import process_pool
from analysis.report import write_report
from analysis.sweep.execute import execute
from analysis.sweep.spec import load_sweep

ROOT = Path(__file__).resolve().parents[1]


def _load() -> str:
    one, five, fifteen = os.getloadavg()
    return f"load average {one:.2f} {five:.2f} {fifteen:.2f} on {os.cpu_count()} cores"


def _timed(sweep, folder: Path, pool: ProcessPoolExecutor) -> tuple:
    """Run one sweep on the shared pool: its runs and the seconds until it finished."""
    t0 = time.perf_counter()
    runs = execute(sweep, folder, executor=pool, progress=False)
    return runs, time.perf_counter() - t0


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
    print(_load())
    sweeps = [load_sweep(path, args.replications) for path in files]
    folders = [args.out / sweep.name for sweep in sweeps]
    start = time.perf_counter()
    # One pool for all the sweeps, fed by all of them at once: no pool start-up per sweep and
    # no idle cores while one sweep waits for its last run.
    with process_pool(args.workers or os.cpu_count()) as pool:
        with ThreadPoolExecutor(len(sweeps)) as feeders:
            jobs = {
                feeders.submit(_timed, sweep, folder, pool): sweep.name
                for sweep, folder in zip(sweeps, folders, strict=True)
            }
            total_runs = 0
            for job in as_completed(jobs):
                runs, seconds = job.result()
                ok = int((runs["status"] == "ok").sum())
                total_runs += len(runs)
                print(
                    f"{jobs[job]:24s} {ok:4d}/{len(runs):<4d} runs ok, done after {seconds:6.1f} s"
                )
    total = time.perf_counter() - start
    print(f"{'all sweeps':24s} {total_runs:9d} runs     {total:7.1f} s ({total / 60:.1f} min)")
    print(_load())
    t0 = time.perf_counter()
    report = write_report(folders, args.out / "report.html")
    print(f"report in {time.perf_counter() - t0:.1f} s")
    print(f"wrote {report}")


if __name__ == "__main__":
    main()
