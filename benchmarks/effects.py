"""Published effects of the inter-launch period (Stirling et al. 2010, Sect. 4), measured.

Runs N seeds of the high-complexity corridor world at 6 s and 24 s (and, with --hover, the
mixed world at 6 s with attached vs hovering beacons) and prints our percent changes beside the
paper's. Usage: python benchmarks/effects.py --seeds 30 [--hover] [--coverage]
"""

import argparse
import time

import pandas as pd

from abm.pools import process_pool
from analysis.runner import run_model
from models.beacon_explorer.published import CORRIDOR_24_VS_6 as PAPER_24_VS_6
from models.beacon_explorer.published import COVERAGE as PAPER_COVERAGE
from models.beacon_explorer.published import HOVER_RATIO as PAPER_HOVER_RATIO


def one_run(kwargs: dict) -> dict:
    params = {"trace_interval": None, **kwargs}
    seed = params.pop("seed")
    return run_model("beacon-explorer", params, seed).summary


def run_all(jobs: list[dict], workers: int) -> pd.DataFrame:
    with process_pool(workers) as pool:
        return pd.DataFrame(list(pool.map(one_run, jobs, chunksize=2)))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--seeds", type=int, default=30)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--hover", action="store_true", help="also hovering vs attached beacons")
    parser.add_argument("--coverage", action="store_true", help="also coverage per complexity")
    args = parser.parse_args()
    seeds = range(1, args.seeds + 1)
    t0 = time.perf_counter()
    jobs = [
        {"world": "corridor", "complexity": "high", "launch_period": p, "seed": s}
        for p in (6.0, 24.0)
        for s in seeds
    ]
    df = run_all(jobs, args.workers)
    means = df.groupby("launch_period")[list(PAPER_24_VS_6)].mean()
    print(f"high-complexity corridor, {args.seeds} seeds per period (means):")
    print(means.round(1).to_string())
    print(f"\n{'metric':<15} {'ours 24 vs 6 s':>15} {'paper':>8}  direction")
    for metric, paper in PAPER_24_VS_6.items():
        ours = 100.0 * (means.loc[24.0, metric] / means.loc[6.0, metric] - 1.0)
        agree = "agrees" if (ours > 0) == (paper > 0) else "DISAGREES"
        print(f"{metric:<15} {ours:>+14.1f}% {paper:>+7.1f}%  {agree}")
    if args.coverage:
        jobs = [
            {"world": "corridor", "complexity": c, "launch_period": p, "seed": s}
            for c in PAPER_COVERAGE
            for p in (6.0, 24.0)
            for s in seeds
        ]
        cov = (
            run_all(jobs, args.workers).groupby("complexity")[["coverage_area", "complete"]].mean()
        )
        print("\ncorridor coverage area (%) per complexity (periods 6 and 24 s pooled):")
        for c, paper in PAPER_COVERAGE.items():
            row = cov.loc[c]
            print(
                f"  {c:<7} ours {row.coverage_area:5.1f} %  paper {paper:5.1f} %   "
                f"complete {100 * row.complete:5.1f} % of runs"
            )
    if args.hover:
        jobs = [
            {"world": "mixed", "launch_period": 6.0, "seed": s, "hover_beacons": h}
            for h in (False, True)
            for s in seeds
        ]
        hov = run_all(jobs, args.workers).groupby("hover_beacons")["energy_total"].mean()
        print(
            f"\nmixed, 6 s: hovering / attached energy = {hov[True] / hov[False]:.2f}x "
            f"(paper {PAPER_HOVER_RATIO}x)"
        )
    print(f"\nwall time {time.perf_counter() - t0:.0f} s")


if __name__ == "__main__":
    main()
