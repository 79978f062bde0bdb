"""Why corridor searches do not complete: bounds and failure classes over a corridor sweep.

For every run of the beacon/explorer model on a generated corridor world, records whether the
world was completable (``models.beacon_explorer.diagnose``: the path bound and the perfect
depth-first search under the paper's rules) and, for completable worlds the run did not
complete, the failure class. Prints, per complexity: complete-coverage rate, both bounds, and
the counts per cause.

Seeds start at 500000 by default, away from every seed the tests use.

Usage: python benchmarks/diagnose_corridor.py [--seeds 30] [--periods 6 24]
       [--first-seed 500000] [--set key=value ...]
"""

import argparse
import collections
import time

import pandas as pd
from tqdm import tqdm

from abm.pools import process_pool
from models.beacon_explorer.diagnose import CAUSES, diagnose
from models.beacon_explorer.model import BeaconExplorerModel

LEVELS = ("low", "medium", "high")


def one_run(job: tuple[str, float, int, dict]) -> dict:
    level, period, seed, extra = job
    model = BeaconExplorerModel(
        world="corridor",
        complexity=level,
        launch_period=period,
        seed=seed,
        trace_interval=None,
        **extra,
    )
    model.run()
    row = diagnose(model)
    row.update(level=level, period=period, seed=seed, coverage=model.coverage.fraction)
    return row


def _value(text: str) -> object:
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return {"true": True, "false": False, "none": None}.get(text.lower(), text)


def table(rows: list[dict]) -> str:
    """The classification table: one line per complexity, counts per cause."""
    short = [c.split(":")[-1].strip() for c in CAUSES]
    head = f"{'level':>6} {'runs':>4} {'complete':>8} {'path':>6} {'DFS':>6} {'gap':>6} | "
    lines = [head + " ".join(f"{s[:10]:>10}" for s in short)]
    for level in LEVELS:
        rs = [r for r in rows if r["level"] == level]
        if not rs:
            continue
        n = len(rs)
        causes = collections.Counter(r["cause"] for r in rs if r["cause"])
        complete = 100 * sum(r["complete"] for r in rs) / n
        dfs = 100 * sum(r["completable"] for r in rs) / n
        path = 100 * sum(r["path_bound"] for r in rs) / n
        lines.append(
            f"{level:>6} {n:>4} {complete:7.1f}% {path:5.1f}% {dfs:5.1f}% {complete - dfs:+6.1f} | "
            + " ".join(f"{causes.get(c, 0):>10}" for c in CAUSES)
        )
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=30, help="runs per complexity and period")
    parser.add_argument("--periods", type=float, nargs="+", default=[6.0, 24.0])
    parser.add_argument("--first-seed", type=int, default=500_000)
    parser.add_argument("--set", nargs="*", default=[], help="model keywords, key=value")
    parser.add_argument("--csv", help="also write one row per run to this CSV file")
    args = parser.parse_args()
    extra = {k: _value(v) for k, v in (s.split("=", 1) for s in args.set)}
    jobs = [
        (level, period, args.first_seed + i, extra)
        for level in LEVELS
        for period in args.periods
        for i in range(args.seeds)
    ]
    start = time.perf_counter()
    with process_pool() as pool:
        rows = list(tqdm(pool.map(one_run, jobs), total=len(jobs), desc="corridor runs"))
    if args.csv:
        pd.DataFrame(rows).to_csv(args.csv, index=False)
    print(f"{len(rows)} runs, {time.perf_counter() - start:.0f} s wall, model keywords {extra}")
    print(table(rows))
    for period in args.periods:
        print(f"\nlaunch period {period:g} s")
        print(table([r for r in rows if r["period"] == period]))
    uncompleted = [r for r in rows if r["completable"] and not r["complete"]]
    print(
        f"\ncompletable but not complete: {len(uncompleted)}; beacons stranded "
        f"{sum(r['stranded'] for r in uncompleted)}, extra in side branches "
        f"{sum(r['extra_in_side'] for r in uncompleted)}, sharing a cell "
        f"{sum(r['shared_cells'] for r in uncompleted)}"
    )


if __name__ == "__main__":
    main()
