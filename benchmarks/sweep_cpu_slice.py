"""CPU time of a sweep's runs, measured on an evenly spaced slice of its plan run in this process.

On a shared machine a sweep's wall time says more about the other users than about the sweep.
The CPU time of its runs does not: run one run in ``every`` of the plan (the same specs, seeds
and code path as ``abm sweep``'s workers, in one worker of the same process pool), serially, and
add up ``time.process_time`` per run.
A quiet machine with W cores then needs about ``runs x mean CPU per run / W`` for the runs (the
workers share no work; process start-up and the report come on top).

    python benchmarks/sweep_cpu_slice.py experiments/morris_beacon_explorer.toml --every 12
"""

import argparse
import os
import time
from itertools import islice

from machine import machine

from abm.pools import process_pool
from analysis.runner import RunSpec, run_one
from analysis.sweep import load_sweep
from analysis.sweep.seeding import iter_plan


def time_runs(specs: list[RunSpec]) -> tuple[list[float], list[float], int]:
    """In a pool worker: run ``specs`` one after another as the worker would; their CPU and
    wall seconds and how many failed. The first run is run once more beforehand, outside the
    measurement, to compile (numba) and import.
    """
    run_one(specs[0])
    cpu, wall, failed = [], [], 0
    for spec in specs:
        c0, w0 = time.process_time(), time.perf_counter()
        failed += run_one(spec)["row"]["status"] != "ok"
        cpu.append(time.process_time() - c0)
        wall.append(time.perf_counter() - w0)
    return cpu, wall, failed


def main() -> None:
    """Run the slice and print CPU and wall per run, and the quiet-machine estimate."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("file", help="sweep file")
    parser.add_argument("--every", type=int, default=10, help="run one run in this many")
    parser.add_argument("--cores", type=int, default=2, help="cores of the quiet estimate")
    args = parser.parse_args()
    sweep = load_sweep(args.file)
    specs = list(islice(iter_plan(sweep), 0, None, args.every))
    with process_pool(1) as pool:
        cpu, wall, failed = pool.submit(time_runs, specs).result()
    mean_cpu = sum(cpu) / len(cpu)
    print(f"machine: {machine()}; load average {os.getloadavg()[0]:.2f} (1 min) at the end")
    print(
        f"{sweep.name}: {len(specs)} of {sweep.n_runs} runs (one in {args.every}), "
        f"{failed} failed; CPU per run mean {mean_cpu:.3f} s, max {max(cpu):.2f} s; "
        f"wall per run mean {sum(wall) / len(wall):.3f} s"
    )
    print(
        f"quiet estimate for all {sweep.n_runs} runs on {args.cores} cores: "
        f"{sweep.n_runs * mean_cpu / args.cores / 60:.1f} min (runs only)"
    )


if __name__ == "__main__":
    main()
