"""Tangible PSO, timed and reproduced: one Table-1 run against the paper's ~28 s in MATLAB,
then Table 1 (1,200 runs) as a sweep, printed beside the paper's numbers with the directions
judged and the sensitivity of the collision and deadlock readings, and the HTML report.

Usage:
    python benchmarks/bench_tangible_pso.py                      # timing + Table 1 + report
    python benchmarks/bench_tangible_pso.py --replications 20    # a quick look
    python benchmarks/bench_tangible_pso.py --fig9 --sensitivity # also Fig. 9 and the readings
    python benchmarks/bench_tangible_pso.py --fig10 --controller # Figs. 10-11, the follower
    python benchmarks/bench_tangible_pso.py --timing-only

The sweeps go through the common sweep runner (resumable: runs already stored are skipped, so
use a fresh ``--out`` to time them). The same report comes from
``abm report <out>/tangible_pso_table1 [<out>/tangible_pso_fig9]``.
"""

import argparse
import os
import statistics
import time
from pathlib import Path

import pandas as pd
from machine import load_average  # benchmarks/machine.py, beside this script

from abm.pools import process_pool
from analysis.report import write_report
from analysis.sweep.execute import execute
from analysis.sweep.spec import load_sweep
from models.tangible_pso import TangiblePSOModel
from models.tangible_pso.published import SECONDS_PER_RUN, SWAP_RESOLVED_PCT, TABLE1

ROOT = Path(__file__).resolve().parents[1]


def time_runs(repeats: int) -> None:
    """Wall and CPU time of single Table-1 runs (40 particles x 70 iterations, 3 MAVs), one
    process; the CPU time is what the run costs when the machine is shared.
    """
    TangiblePSOModel(seed=0, iterations=2).run()  # compile (numba caches to disk)
    print(f"one Table-1 run (40 particles, 70 iterations, 3 MAVs), median of {repeats}:")
    for mp in (False, True):
        for k in (0, 1, 2):
            wall, cpu = [], []
            for seed in range(repeats):
                t0, c0 = time.perf_counter(), time.process_time()
                TangiblePSOModel(seed=1000 + seed, neighbours=k, motion_planning=mp).run()
                wall.append(time.perf_counter() - t0)
                cpu.append(time.process_time() - c0)
            med = statistics.median(wall)
            print(
                f"  k={k} {'with' if mp else 'without':7s} MP: wall {med:.3f} s, CPU "
                f"{statistics.median(cpu):.3f} s ({SECONDS_PER_RUN['table1'] / med:.0f}x faster "
                "than the paper's 28 s in wall time)"
            )


def _pct(x: pd.Series) -> str:
    return f"{100 * x.mean():5.1f} %"


def print_table1(runs: pd.DataFrame) -> None:
    """Table 1 beside the paper's, the directions, and how the readings move the numbers."""
    runs = runs[runs["status"] == "ok"]
    g = runs.groupby(["neighbours", "motion_planning"])
    print("\nTable 1 (ours | paper); cost: ours in 1 m cells with A_max = 1 (start 64)")
    print("  k  MP    runs  collisions         deadlocks          best cost (ratio to start)")
    for (k, mp), rows in g:
        col, dead, cost = TABLE1[(int(k), bool(mp))]
        print(
            f"  {k}  {'yes' if mp else 'no ':3s} {len(rows):5d}  {_pct(rows['collision'])} | "
            f"{100 * col:5.1f} %  {_pct(rows['deadlock'])} | {100 * dead:4.0f} %  "
            f"{rows['best_cost'].mean():6.2f} ({rows['best_cost_ratio'].mean():.3f}) | {cost:.1e}"
        )
    means = g[["collision", "deadlock", "best_cost"]].mean()
    print("\ndirections:")
    for col in ("collision", "deadlock", "best_cost"):
        lower = all(means.loc[(k, True), col] <= means.loc[(k, False), col] for k in (0, 1, 2))
        strictly = all(means.loc[(k, True), col] < means.loc[(k, False), col] for k in (0, 1, 2))
        verdict = "yes" if strictly else "ties" if lower else "NO"
        print(f"  {col:10s} lower with MP at every k: {verdict}")
        for mp in (False, True):
            v = [means.loc[(k, mp), col] for k in (0, 1, 2)]
            rising = "yes" if v[0] < v[1] < v[2] else "flat at 0" if max(v) == 0 else "NO"
            print(f"  {col:10s} rises with k {'with' if mp else 'without'} MP: {rising} "
                  f"({', '.join(f'{x:.3g}' for x in v)})")  # fmt: skip
    print("\nreadings (share of runs, k = 0 / 1 / 2, without MP | with MP):")
    readings = {
        "collision: an MAV stopped at the zone (ours)": runs["collision"],
        "collision: a proposal inside the zone": runs["collision_proposal"],
        "deadlock: >= 25 % of particles at the zone, last 10 it.": runs["zone_pressed_min"] >= 0.25,
        "deadlock: >= 50 % (ours)": runs["zone_pressed_min"] >= 0.5,
        "deadlock: >= 75 %": runs["zone_pressed_min"] >= 0.75,
        "deadlock: best particle at the zone, last 10 it.": runs["deadlock_best"],
        "deadlock: no particle moved > 1 cm, last 10 it. (spec)": runs["deadlock_frozen"],
    }
    for label, flag in readings.items():
        share = flag.groupby([runs["motion_planning"], runs["neighbours"]]).mean()
        cells = [
            " / ".join(f"{100 * share.loc[(mp, k)]:3.0f}" for k in (0, 1, 2))
            for mp in (False, True)
        ]
        print(f"  {label:58s} {cells[0]} | {cells[1]}")
    mp = runs[runs["motion_planning"]]
    conflicts = mp["swap_conflicts"].sum()
    resolved = mp["swap_resolved"].sum()
    print(
        f"\ngoal swapping: {resolved} of {conflicts} mutual path collisions resolved "
        f"({100 * resolved / max(conflicts, 1):.1f} %; paper {SWAP_RESOLVED_PCT} %)"
    )


def print_fig9(runs: pd.DataFrame) -> None:
    runs = runs[runs["status"] == "ok"]
    print("\nFig. 9 (6 MAVs, k = 2, 40 x 20), per reading of the initial velocities:")
    for reading, rows in runs.groupby("initial_velocity"):
        print(
            f"  {reading:9s} {len(rows)} runs: split into 2+ groups in "
            f"{100 * (rows['groups'] >= 2).mean():.0f} %; best found at iteration "
            f"{rows['best_iteration'].median():.0f} (median; paper 17); cost ratio "
            f"{rows['best_cost_ratio'].mean():.2f}"
        )


def print_fig10(runs: pd.DataFrame) -> None:
    """Figs. 10-11: each method's solution flown (claims C6, C6b), means per method."""
    runs = runs[runs["status"] == "ok"]
    print("\nFigs. 10-11 (3 MAVs, k = 1, 40 x 70), each solution flown by the same planner:")
    for method, rows in runs.groupby("method"):
        reached = rows["reach_time"].dropna()
        time_text = (
            f"{reached.median():.0f} s (median of {len(reached)})" if len(reached) else "never"
        )
        print(
            f"  {method:11s} {len(rows)} runs: planned cost {rows['best_cost_ratio'].mean():.3f} "
            f"of nothing seen; unchecked plan loses a neighbour {_pct(rows['plan_unlocalised'])} "
            f"({rows['plan_unlocalised_time'].mean():.1f} s), MAVs within d_min "
            f"{_pct(rows['plan_collision'])}; checked deployment stops short "
            f"{_pct(rows['deploy_deadlock'])}, ends at {rows['deployed_cost_ratio'].mean():.3f}; "
            f"reaches the formation in {time_text}"
        )


def print_controller(runs: pd.DataFrame) -> None:
    """Table 1 with motion planning under the second-order follower, per omega and noise."""
    runs = runs[runs["status"] == "ok"]
    print("\nTable 1 with motion planning, second-order follower (zeta 0.5):")
    keys = ["ctrl_omega", "ctrl_noise", "neighbours"]
    for (omega, noise, k), rows in runs.groupby(keys):
        paper = 100 * TABLE1[int(k), True][0]
        print(
            f"  omega {omega:g} rad/s, noise {noise:g}, k = {k}: collisions "
            f"{_pct(rows['collision'])} (paper {paper:.1f} %), deadlocks "
            f"{_pct(rows['deadlock'])}, cost {rows['best_cost_ratio'].mean():.3f} of the start's, "
            f"largest tracking error {rows['tracking_error_max'].max():.2f} m"
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=Path("out/tangible_pso"))
    parser.add_argument("--replications", type=int, default=None, help="override the files'")
    parser.add_argument("--workers", type=int, default=None, help="default: all cores")
    parser.add_argument("--repeats", type=int, default=10, help="timed single runs per row")
    parser.add_argument("--timing-only", action="store_true")
    parser.add_argument("--fig9", action="store_true", help="also Fig. 9's sweep")
    parser.add_argument("--sensitivity", action="store_true", help="also the readings' sweep")
    parser.add_argument("--fig10", action="store_true", help="also Figs. 10-11's sweep")
    parser.add_argument("--controller", action="store_true", help="also the follower's sweep")
    args = parser.parse_args()
    print(load_average())
    time_runs(args.repeats)
    if args.timing_only:
        return
    names = ["tangible_pso_table1"]
    names += ["tangible_pso_fig9"] if args.fig9 else []
    names += ["sensitivity_tangible_pso_table1"] if args.sensitivity else []
    names += ["tangible_pso_fig10"] if args.fig10 else []
    names += ["sensitivity_tangible_pso_controller"] if args.controller else []
    folders = {}
    with process_pool(args.workers or os.cpu_count()) as pool:
        for name in names:
            sweep = load_sweep(ROOT / "experiments" / f"{name}.toml", args.replications)
            folders[name] = args.out / name
            t0 = time.perf_counter()
            runs = execute(sweep, folders[name], executor=pool, progress=True)
            ok = int((runs["status"] == "ok").sum())
            print(f"{name}: {ok}/{len(runs)} runs ok in {time.perf_counter() - t0:.1f} s wall")
            if name == "tangible_pso_table1":
                print_table1(runs)
            elif name == "tangible_pso_fig9":
                print_fig9(runs)
            elif name == "tangible_pso_fig10":
                print_fig10(runs)
            elif name == "sensitivity_tangible_pso_controller":
                print_controller(runs)
            else:
                for point, rows in runs.groupby(["initial_velocity", "initial_speed", "stop_rule"],
                                                dropna=False):  # fmt: skip
                    print(f"\nreading {point}:")
                    print_table1(rows)
    print(load_average())
    table = [n for n in names if n in ("tangible_pso_table1", "tangible_pso_fig9")]
    report = write_report([folders[n] for n in table], args.out / "report.html")
    print(f"wrote {report}")
    if args.fig10:  # the two methods apart from Table 1's runs
        report = write_report([folders["tangible_pso_fig10"]], args.out / "report_fig10.html")
        print(f"wrote {report}")


if __name__ == "__main__":
    main()
