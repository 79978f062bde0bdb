"""CPU per run of a sweep's slice under two checkouts, run by run, side by side.

``sweep_cpu_slice.py`` times a slice under one checkout; two of its runs one after the other
differ by 15 % on a shared machine whose load moves within minutes. Here each checkout keeps
one warm worker process (its own code on its ``PYTHONPATH``, numba's kernels loaded), and
every run of the slice is run under both, one right after the other, the order swapped from
run to run, so the two times of a pair share the machine's state. Prints the ratio of the
summed CPU times (new / base) and the median and quartiles of the per-run ratios.

    python benchmarks/sweep_cpu_paired.py experiments/corridor.toml --every 90 \\
        --base ../old-checkout --new .
"""

import argparse
import os
import statistics
import subprocess
import sys
import time
from itertools import islice
from pathlib import Path

from machine import machine


def serve(file: str, every: int) -> None:
    """The worker: load the slice, run its first run once (imports, numba), then run the run
    whose index each line of stdin names and answer with its CPU seconds and status.
    """
    from analysis.runner import run_one
    from analysis.sweep import load_sweep
    from analysis.sweep.seeding import iter_plan

    specs = list(islice(iter_plan(load_sweep(file)), 0, None, every))
    run_one(specs[0])
    print(len(specs), flush=True)
    for line in sys.stdin:
        start = time.process_time()
        status = run_one(specs[int(line)])["row"]["status"]
        print(f"{time.process_time() - start:.6f} {status}", flush=True)


class Worker:
    """A :func:`serve` process running the code of one checkout."""

    def __init__(self, checkout: Path, file: str, every: int) -> None:
        env = dict(os.environ, PYTHONPATH=f"{checkout}{os.pathsep}{checkout / 'benchmarks'}")
        self.process = subprocess.Popen(
            [sys.executable, str(Path(__file__).resolve()), file, "--every", str(every), "--serve"],
            cwd=checkout,
            env=env,
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            text=True,
        )
        self.runs = int(self.process.stdout.readline())

    def cpu(self, index: int) -> float:
        """CPU seconds of run ``index`` of the slice; RuntimeError if it failed."""
        self.process.stdin.write(f"{index}\n")
        self.process.stdin.flush()
        seconds, status = self.process.stdout.readline().split()
        if status != "ok":
            raise RuntimeError(f"run {index} of the slice ended {status}")
        return float(seconds)

    def close(self) -> None:
        self.process.stdin.close()
        self.process.wait()


def main() -> None:
    """Run the slice pairwise under both checkouts and print the ratios."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("file", help="sweep file (a path inside each checkout)")
    parser.add_argument("--every", type=int, default=10, help="run one run in this many")
    parser.add_argument("--base", type=Path, help="the checkout to compare against")
    parser.add_argument("--new", type=Path, default=Path("."), help="the checkout measured")
    parser.add_argument("--rounds", type=int, default=1, help="times through the slice")
    parser.add_argument("--serve", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.every < 1 or args.rounds < 1:
        parser.error("--every and --rounds must be at least 1")
    if args.serve:
        serve(args.file, args.every)
        return
    if args.base is None:
        parser.error("--base CHECKOUT is required")
    for checkout in (args.base, args.new):
        if not (checkout / args.file).is_file():
            parser.error(f"no sweep file {args.file!r} in checkout {str(checkout)!r}")
    workers = {
        "base": Worker(args.base.resolve(), args.file, args.every),
        "new": Worker(args.new.resolve(), args.file, args.every),
    }
    runs = workers["base"].runs
    ratios, total = [], {"base": 0.0, "new": 0.0}
    for round_ in range(args.rounds):
        for index in range(runs):
            order = ("base", "new") if (index + round_) % 2 == 0 else ("new", "base")
            cpu = {name: workers[name].cpu(index) for name in order}
            ratios.append(cpu["new"] / cpu["base"])
            for name in cpu:
                total[name] += cpu[name]
    for worker in workers.values():
        worker.close()
    low, _, high = statistics.quantiles(ratios, n=4) if len(ratios) > 1 else (ratios[0],) * 3
    print(f"machine: {machine()}; load average {os.getloadavg()[0]:.2f} (1 min) at the end")
    print(
        f"{args.file}, one run in {args.every}: {runs} runs x {args.rounds} rounds; CPU base "
        f"{total['base']:.1f} s, new {total['new']:.1f} s: new / base "
        f"{total['new'] / total['base']:.3f} ({total['base'] / total['new']:.2f}x less CPU); "
        f"per run median "
        f"{statistics.median(ratios):.3f} (quartiles {low:.3f}-{high:.3f})"
    )


if __name__ == "__main__":
    main()
