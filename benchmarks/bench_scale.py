"""Cost growth with swarm size: wall time per simulated second per robot, 50 to 10,000 robots.

Each model runs at four sizes in a world that grows with the swarm, so the density of robots
stays about the same and a linear-cost framework shows the same wall time per simulated second
per robot at every size:

- beacon/explorer: an open hall of 3 m cells with a few obstacle cells (one every 7 cells in
  both directions), about 1.1 cells per robot, launch period 3 s, simulated until every robot
  has launched plus 60 s (``n * 3 + 60`` s);
- stigmergy: an open square map of 1 m pixels with the same obstacle pattern scaled, about
  60 m^2 per robot, launch rate 0.1 (one robot per 5 s, ten times the paper's), simulated until
  every robot has launched (``n * 5`` s).

A run that would take longer than ``--budget`` wall seconds stops early (checked every
simulated ``--chunk`` seconds) and its row reports the simulated time it reached: its cost is
then measured over the early, cheaper part of the deployment only (fewer robots aloft), so a
truncated row *under*states that size's cost. The growth exponent b is the least-squares slope
of log(wall per simulated second) against log(robots): b = 1 is linear cost.

Every run is a process of its own (after a 20-robot warm-up run there that loads the compiled
kernels), so each row also reports that process's peak memory (``ru_maxrss``, MB; the warm-up
and the imports included), and its per-robot cost as a multiple of the smallest size's.
"x real time (CPU)" is simulated time over the run's CPU time: what one idle core would give,
on a machine shared with other work the steadier figure.

The worlds are built from plain cell lists and arrays (not the generators' size options) so
the same script times older revisions of the framework.

With ``--compare DIR`` every case also runs on the code checked out in DIR (e.g. a worktree
of main: ``git worktree add /tmp/before main``), both revisions side by side at the same time
in two processes, so both see the same machine load; the table then shows both and their
ratio, of wall times and of CPU times (on a machine shared with other work the two processes
need not get the same share of the cores: the CPU-time ratio is the steadier one, valid when
both runs reached the same simulated time).

Usage: python benchmarks/bench_scale.py [--quick] [--models beacon-explorer stigmergy]
    [--sizes 50 200 1000 2000 10000] [--budget 600] [--seed 1] [--profile out/scale.prof]
    [--compare DIR]
"""

import argparse
import cProfile
import json
import math
import os
import resource
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from abm.registry import model_class
from models.environments.world import world_from_cells

#: Sizes of the full and the quick run (robots).
SIZES = (50, 200, 1000, 2000, 10000)
QUICK_SIZES = (50, 100, 200, 400)
#: Explorer launch period (s) of the beacon/explorer runs.
LAUNCH_PERIOD = 3.0
#: Stigmergy launch rate (robots per 0.5 s model step): one per 5 s, ten times the paper's.
STIGMERGY_RATE = 0.1
#: Obstacle spacing in both directions (cells or 1/7 of the map).
OBSTACLE_EVERY = 7


def beacon_explorer_case(n: int) -> tuple[dict, float]:
    """Parameters and simulated duration of an ``n``-robot beacon/explorer run."""
    side = math.ceil(math.sqrt(1.1 * n))
    cells = [
        (ix, iy)
        for iy in range(side)
        for ix in range(side)
        if not (ix % OBSTACLE_EVERY == 3 and iy % OBSTACLE_EVERY == 3)
    ]
    world = world_from_cells(cells, (0, 0), "open", "low", None, 3.0)
    duration = n * LAUNCH_PERIOD + 60.0
    params = {
        "world": world,
        "n_robots": n,
        "launch_period": LAUNCH_PERIOD,
        "time_limit": duration,
        "stall_time": None,
    }
    return params, duration


def stigmergy_case(n: int) -> tuple[dict, float]:
    """Parameters and simulated duration of an ``n``-robot stigmergy run."""
    side = max(60, math.ceil(math.sqrt(600.0 * n)))
    free = np.ones((side, side), dtype=bool)
    free[[0, -1], :] = free[:, [0, -1]] = False
    step = side // OBSTACLE_EVERY
    for k in range(1, OBSTACLE_EVERY):
        for m in range(1, OBSTACLE_EVERY):
            free[k * step : k * step + 3, m * step : m * step + 3] = False
    duration = n * 0.5 / STIGMERGY_RATE
    params = {
        "map": free,
        "start": (5.0, 5.0),
        "launch_rate": STIGMERGY_RATE,
        "swarm_size": n,
        "time_limit": duration,
        "coverage_target": 1.0,
    }
    return params, duration


CASES = {"beacon-explorer": beacon_explorer_case, "stigmergy": stigmergy_case}
#: Wall seconds between a long run's progress lines (on stderr).
PROGRESS_EVERY = 60.0
#: The checkout this script belongs to.
HERE = str(Path(__file__).resolve().parent.parent)


def time_run(
    name: str, n: int, seed: int, budget: float, chunk: float, profile: str | None = None
) -> dict:
    """Run one case; wall time, simulated time reached and how the run ended."""
    params, duration = CASES[name](n)
    cls = model_class(name)
    profiler = cProfile.Profile() if profile else None
    start, cpu_start = time.perf_counter(), time.process_time()
    if profiler:
        profiler.enable()
    model = cls(seed=seed, **params)
    # (simulated s, wall s, CPU s) after each chunk
    progress = [(0.0, time.perf_counter() - start, time.process_time() - cpu_start)]
    shown = 0.0
    while model.running and model.env.now < duration:
        model.run(until=min(duration, model.env.now + chunk))
        progress.append(
            (float(model.env.now), time.perf_counter() - start, time.process_time() - cpu_start)
        )
        if progress[-1][1] > budget:
            break
        if progress[-1][1] - shown >= PROGRESS_EVERY:  # a long run says how far it is
            shown = progress[-1][1]
            sim, wall, cpu = progress[-1]
            print(f"{name} {n}: t {sim:.0f}/{duration:.0f} s after {wall:.0f} s wall, "
                  f"{cpu:.0f} s CPU", file=sys.stderr, flush=True)  # fmt: skip
    if profiler:
        profiler.disable()
        profiler.dump_stats(profile)
    wall = time.perf_counter() - start
    cpu = time.process_time() - cpu_start
    simulated = float(model.env.now)
    return {
        "model": name,
        "robots": n,
        "simulated": simulated,
        "wall": wall,
        "cpu": cpu,
        "per_robot_us": 1e6 * wall / simulated / n,
        "rtf": simulated / wall,
        "rtf_cpu": simulated / cpu,
        "truncated": simulated < duration and model.running,
        "events": len(model.events()),
        "end": model.end_reason or "",
        "progress": progress,
    }


def wall_at(row: dict, simulated: float, column: int = 1) -> float:
    """Wall time (s; CPU time with ``column=2``) a run took to reach ``simulated`` seconds
    (linear between chunks).
    """
    sims, times = [p[0] for p in row["progress"]], [p[column] for p in row["progress"]]
    return float(np.interp(simulated, sims, times))


def start_child(
    root: str, name: str, n: int, seed: int, budget: float, chunk: float, profile: str | None
) -> subprocess.Popen:
    """Start a process timing one case on the code checked out in directory ``root``."""
    env = {**os.environ, "PYTHONPATH": root}
    argv = [sys.executable, str(Path(__file__).resolve()), "--one", name, str(n)]
    argv += ["--seed", str(seed), "--budget", str(budget), "--chunk", str(chunk)]
    if profile:
        argv += ["--profile", profile]
    return subprocess.Popen(argv, env=env, stdout=subprocess.PIPE, text=True, cwd=root)


def child_row(run: subprocess.Popen) -> dict:
    """The row a process started by :func:`start_child` printed last."""
    return json.loads(run.communicate()[0].strip().splitlines()[-1])


def side_by_side(
    name: str, n: int, seed: int, budget: float, chunk: float, other: str
) -> tuple[dict, dict]:
    """Run a case on this code and on the code in directory ``other`` at the same time."""
    runs = [start_child(root, name, n, seed, budget, chunk, None) for root in (HERE, other)]
    return tuple(child_row(run) for run in runs)


def speedup(after: dict, before: dict, column: int = 1) -> float:
    """Ratio of the wall (``column=2``: CPU) times both revisions took to reach the simulated
    time both reached (a run stopped at the budget is compared over the part both ran).
    """
    common = min(after["simulated"], before["simulated"])
    return wall_at(before, common, column) / wall_at(after, common, column)


def growth_exponent(rows: list[dict]) -> float:
    """Slope b of log(wall per simulated second) against log(robots)."""
    robots = np.log([r["robots"] for r in rows])
    cost = np.log([r["wall"] / r["simulated"] for r in rows])
    return float(np.polyfit(robots, cost, 1)[0])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true", help=f"sizes {QUICK_SIZES}")
    parser.add_argument("--sizes", type=int, nargs="+", default=None)
    parser.add_argument("--models", nargs="+", default=list(CASES), choices=list(CASES))
    parser.add_argument("--budget", type=float, default=600.0, help="wall s per run at most")
    parser.add_argument("--chunk", type=float, default=30.0, help="simulated s between checks")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--profile", default=None, help="cProfile file of the largest run")
    parser.add_argument("--compare", default=None, help="also time the code in this checkout")
    parser.add_argument("--one", nargs=2, default=None, help=argparse.SUPPRESS)
    args = parser.parse_args()
    sizes = args.sizes or (QUICK_SIZES if args.quick else SIZES)
    if args.one:  # one timed run in a process of its own: warm up, time, print it as JSON
        name, n = args.one[0], int(args.one[1])
        model_class(name)(seed=0, **CASES[name](20)[0]).run(until=30.0)
        row = time_run(name, n, args.seed, args.budget, args.chunk, args.profile)
        row["peak_mb"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
        print(json.dumps(row))
        return
    rows = []
    for name in args.models:
        rows += print_compared(name, sizes, args) if args.compare else print_rows(name, sizes, args)
    if any(row["truncated"] for row in rows):
        print("  (* stopped at the wall budget: cost measured over the cheaper early part)")


def cut(row: dict) -> str:
    """A mark for a row stopped at the wall budget."""
    return "*" if row["truncated"] else " "


def print_rows(name: str, sizes: list[int], args: argparse.Namespace) -> list[dict]:
    """Time each size of one model, one process after the other, print the table and return
    its rows.
    """
    print(f"{name} (seed {args.seed}):")
    print(
        f"  {'robots':>7} {'sim s':>8} {'wall s':>8} {'CPU s':>8} {'us/robot/sim-s':>15} "
        f"{'vs smallest':>11} {'x real time':>11} {'(CPU)':>7} {'peak MB':>8} {'events':>8}  end"
    )
    rows = []
    for n in sizes:
        profile = args.profile if n == max(sizes) else None
        row = child_row(start_child(HERE, name, n, args.seed, args.budget, args.chunk, profile))
        rows.append(row)
        print(
            f"  {n:>7} {row['simulated']:>7.0f}{cut(row)} {row['wall']:>8.1f} {row['cpu']:>8.1f} "
            f"{row['per_robot_us']:>15.1f} {row['per_robot_us'] / rows[0]['per_robot_us']:>10.2f}x "
            f"{row['rtf']:>11.1f} {row['rtf_cpu']:>7.1f} {row['peak_mb']:>8.0f} "
            f"{row['events']:>8}  {row['end']}",
            flush=True,
        )
    if len(rows) > 1:
        print(f"  growth exponent b = {growth_exponent(rows):.2f} (wall per sim-s ~ robots^b)")
    return rows


def print_compared(name: str, sizes: list[int], args: argparse.Namespace) -> list[dict]:
    """Time each size of one model on this code and on ``args.compare`` side by side, print
    the table and return every row of both.
    """
    print(f"{name} (seed {args.seed}), this code vs {args.compare}, run side by side:")
    print(
        f"  {'robots':>7} {'sim s':>8} {'us/robot/sim-s':>15} {'vs smallest':>11} "
        f"{'x real time':>11} {'(CPU)':>7} {'peak MB':>8}   {'before: sim s':>13} "
        f"{'us/robot/sim-s':>15} {'x real time':>11} {'(CPU)':>7} {'peak MB':>8}  "
        f"speed-up to the same sim time (wall; CPU)"
    )
    pairs = []
    for n in sizes:
        after, before = side_by_side(name, n, args.seed, args.budget, args.chunk, args.compare)
        pairs.append((after, before))
        print(
            f"  {n:>7} {after['simulated']:>7.0f}{cut(after)} {after['per_robot_us']:>15.1f} "
            f"{after['per_robot_us'] / pairs[0][0]['per_robot_us']:>10.2f}x "
            f"{after['rtf']:>11.1f} {after['rtf_cpu']:>7.1f} {after['peak_mb']:>8.0f}   "
            f"{before['simulated']:>12.0f}{cut(before)} {before['per_robot_us']:>15.1f} "
            f"{before['rtf']:>11.1f} {before['rtf_cpu']:>7.1f} {before['peak_mb']:>8.0f}  "
            f"{speedup(after, before):>6.2f}x; {speedup(after, before, 2):.2f}x",
            flush=True,
        )
    for label, rows in (("this code", [a for a, _ in pairs]), ("before", [b for _, b in pairs])):
        if len(rows) > 1:
            ratio = rows[-1]["per_robot_us"] / rows[0]["per_robot_us"]
            print(
                f"  {label}: per-robot cost {rows[-1]['robots']} vs {rows[0]['robots']} "
                f"robots {ratio:.2f}x, growth exponent b = {growth_exponent(rows):.2f}"
            )
    return [row for pair in pairs for row in pair]


if __name__ == "__main__":
    main()
