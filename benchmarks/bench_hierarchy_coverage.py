"""CPU time of one bubble-coverage call (the report's Fig. 24) as the hierarchy model makes them.

Runs the hierarchy model on the 20 m x 20 m room for a few (workers, scouts per worker)
configurations, records every coverage call the directors make, and re-times a sample of them
offline: each sampled call is repeated ``--repeat`` times on a copy of its input and its
smallest process CPU time is kept (the machine is shared and noisy; the minimum is the
reproducible cost). Calls are split by level: the queen's map is the whole room (200 x 200
cells of 0.10 m); a worker's map is its bubble (plus the routing box around it).

Usage: python benchmarks/bench_hierarchy_coverage.py [--configs 2x2 4x4 7x8] [--seeds 1 2]
       [--sample 10] [--repeat 5]
"""

import argparse
import copy
import time
from unittest import mock

import numpy as np
from tqdm import tqdm

import models.hierarchy.agents as agents
from models.hierarchy.coverage import coverage
from models.hierarchy.model import HierarchyModel
from models.hierarchy.probmap import Rect


def record_calls(workers: int, scouts: int, seed: int, every: int) -> tuple[list, int, float]:
    """Run one model; return the input of every queen call and of every ``every``-th worker call,
    the number of calls, and the run's CPU time (recording included)."""
    sample: list[tuple] = []
    count = 0

    def recording(pmap, children, rng, **kwargs):
        nonlocal count
        queen = isinstance(pmap.region, Rect)
        if queen or count % every == 0:
            state = copy.deepcopy((pmap, list(children), kwargs))
            sample.append((*state, rng.bit_generator.state))
        count += 1
        return coverage(pmap, children, rng, **kwargs)

    model = HierarchyModel(workers=workers, scouts_per_worker=scouts, seed=seed)
    start = time.process_time()
    with mock.patch.object(agents, "coverage", recording):
        model.run()
    return sample, count, time.process_time() - start


def cpu_time(call: tuple, repeat: int) -> float:
    """Smallest CPU time (s) of ``repeat`` runs of one recorded call."""
    pmap, children, kwargs, rng_state = call
    best = np.inf
    for _ in range(repeat):
        rng = np.random.default_rng()
        rng.bit_generator.state = rng_state
        start = time.process_time()
        coverage(pmap, children, rng, **kwargs)
        best = min(best, time.process_time() - start)
    return best


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--configs", nargs="+", default=["2x2", "4x4", "7x8"])
    parser.add_argument("--seeds", nargs="+", type=int, default=[1, 2])
    parser.add_argument("--sample", type=int, default=10, help="re-time every n-th worker call")
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    cpu_time(record_calls(2, 2, 0, 50)[0][0], 1)  # warm-up: load the compiled kernels
    print(f"{'config':>7} {'level':>6} {'calls':>6} {'median ms':>10} {'mean ms':>8} "
          f"{'p90 ms':>7} {'max ms':>7} {'run CPU s':>10}")  # fmt: skip
    for config in args.configs:
        workers, scouts = (int(v) for v in config.split("x"))
        times: dict[str, list[float]] = {"queen": [], "worker": []}
        calls = run_cpu = 0.0
        for seed in tqdm(args.seeds, desc=config, leave=False):
            sample, count, run_s = record_calls(workers, scouts, seed, args.sample)
            run_cpu += run_s / len(args.seeds)
            calls += count / len(args.seeds)
            for call in sample:
                level = "queen" if isinstance(call[0].region, Rect) else "worker"
                times[level].append(cpu_time(call, args.repeat))
        for level, values in times.items():
            ms = 1e3 * np.asarray(values)
            print(f"{config:>7} {level:>6} {len(ms):>6} {np.median(ms):>10.2f} {ms.mean():>8.2f} "
                  f"{np.percentile(ms, 90):>7.2f} {ms.max():>7.1f} {run_cpu:>10.2f}")  # fmt: skip
        print(f"{config:>7}   ({calls:.0f} coverage calls per run; every queen call and every "
              f"{args.sample}th worker call re-timed, min of {args.repeat} repeats)")  # fmt: skip


if __name__ == "__main__":
    main()
