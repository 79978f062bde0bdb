"""The bare physics at scale: flyer-steps per second at 10,000 and 100,000 flyers.

One :class:`abm.physics.Physics` process moves every flyer per tick (dt = 0.1 s): flight
dynamics, body noise, wall contacts, robot-robot contacts. The flyers start at random free
cells of a square walled arena of 1 m pixels with about 10 m^2 per flyer and internal walls
(every tenth row, with gaps), so density and wall share do not change with the swarm size.
Three controllers:

- ``cruise``: each flyer keeps the desired velocity it was given at take-off (1 m/s in a
  random direction): the physics alone, no controller work per tick;
- ``hold``: each flyer keeps its velocity plus a small random turn (two normal draws per flyer
  per tick from the model's generator);
- ``sensing``: wander pushed away from walls by the four cardinal distance sensors
  (``bench_beacon_explorer.py``'s ``WallAvoidingWanderer``), a controller's typical per-tick
  work.

Real time at dt = 0.1 s means 10 ticks per simulated second: 100,000 flyers at 10x real time
is 1e7 flyer-steps per second.

With ``--compare DIR`` every timed run also runs on the code checked out in DIR (e.g. ``git
worktree add /tmp/before <commit>``): each run in its own process, the two revisions
alternating, so both see the same machine load; the table shows both and their ratio.

Usage: python benchmarks/bench_physics.py [--sizes 10000 100000] [--ticks 50] [--repeats 3]
    [--compare DIR]
"""

import argparse
import math
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import simpy
from bench_beacon_explorer import WallAvoidingWanderer  # the "sensing" controller

from abm.arena import Arena
from abm.physics import FlightParams, Physics


def arena_for(n: int) -> Arena:
    """A walled square with about 10 m^2 of free space per flyer and internal walls."""
    side = max(40, math.ceil(math.sqrt(11.0 * n)))
    free = np.ones((side, side), dtype=bool)
    free[[0, -1], :] = free[:, [0, -1]] = False
    free[10:-10:10, 5:-5] = False
    free[10:-10:10, 5:-5:40] = True  # gaps every 40 m
    return Arena(free, 1.0)


class Cruise:
    """Keep the desired velocity given at take-off: 1 m/s in a random direction."""

    def __init__(self, rng: np.random.Generator, n: int) -> None:
        heading = rng.uniform(0.0, 2 * math.pi, n)
        self.desired = np.column_stack([np.cos(heading), np.sin(heading)])

    def control(self, physics: Physics):
        return self.desired, np.zeros(physics.n_flying, dtype=bool)


class Hold:
    """Keep flying: the current velocity plus a small random turn."""

    def __init__(self, rng: np.random.Generator) -> None:
        self.rng = rng

    def control(self, physics: Physics):
        desired = physics.vel + self.rng.normal(0.0, 0.1, physics.vel.shape)
        return desired, np.zeros(physics.n_flying, dtype=bool)


def launch(physics: Physics, positions: np.ndarray) -> None:
    """Put every flyer in the air at once.

    Revisions before ``Physics.fly_many`` grew the arrays one flyer at a time (quadratic set-up
    at 100,000 flyers), so for timing those the arrays are filled directly; only the ticks are
    timed either way.
    """
    ids = np.arange(len(positions))
    if "fly_many" in type(physics).__dict__:
        physics.fly_many(ids, positions)
        return
    physics.fly(0, positions[0])
    physics.ids = ids
    physics.pos = np.array(positions, dtype=float)
    physics.vel = np.zeros_like(physics.pos)
    physics._wall_contact = np.zeros(len(ids), dtype=bool)
    physics._arrivals = [physics.env.event() for _ in ids]


def steps_per_second(n: int, ticks: int, controller: str, seed: int) -> float:
    """Flyer-steps per wall second over ``ticks`` ticks of ``n`` flyers."""
    rng = np.random.default_rng(seed)
    arena = arena_for(n)
    env = simpy.Environment()
    control = {
        "cruise": lambda: Cruise(rng, n),
        "hold": lambda: Hold(rng),
        "sensing": lambda: WallAvoidingWanderer(arena, rng),
    }[controller]()
    physics = Physics(env, arena, rng, control, params=FlightParams(body_noise=0.025))
    cells = arena.free_cell_centres()
    launch(physics, cells[rng.choice(len(cells), n, replace=False)])
    env.run(until=2 * physics.dt - 1e-9)  # first ticks: compile/load, settle
    before = physics.flyer_steps
    start = time.perf_counter()
    env.run(until=(2 + ticks) * physics.dt - 1e-9)
    return (physics.flyer_steps - before) / (time.perf_counter() - start)


CONTROLLERS = ("cruise", "hold", "sensing")


def in_checkout(root: str, n: int, ticks: int, controller: str, seed: int) -> float:
    """One timed run on the code checked out in ``root``, in a process of its own."""
    argv = [sys.executable, str(Path(__file__).resolve()), "--one", str(n), controller]
    argv += ["--ticks", str(ticks), "--seed", str(seed)]
    run = subprocess.run(
        argv, env={**os.environ, "PYTHONPATH": root}, cwd=root, capture_output=True, text=True
    )
    if run.returncode:
        raise RuntimeError(f"timing in {root} failed:\n{run.stderr}")
    return float(run.stdout.split()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[10_000, 100_000])
    parser.add_argument("--ticks", type=int, default=50)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--controllers", nargs="+", default=CONTROLLERS, choices=CONTROLLERS)
    parser.add_argument("--compare", default=None, help="also time the code in this checkout")
    parser.add_argument("--one", nargs=2, default=None, help=argparse.SUPPRESS)
    parser.add_argument("--seed", type=int, default=1, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.one:  # a worker of --compare: warm up, time one run, print the rate
        n, controller = int(args.one[0]), args.one[1]
        steps_per_second(1000, 3, controller, 0)
        print(steps_per_second(n, args.ticks, controller, args.seed))
        return
    print(
        f"flyer-steps per second, dt = 0.1 s, median of {args.repeats} runs of {args.ticks} ticks"
    )
    head = f"  {'flyers':>8} {'controller':>10} {'steps/s':>12} {'x real time':>11}"
    if args.compare:
        head += f"   {'before: steps/s':>15} {'x real time':>11}  speed-up   ({args.compare})"
    print(head)
    here = str(Path(__file__).resolve().parent.parent)
    for n in args.sizes:
        for controller in args.controllers:
            seeds = range(1, args.repeats + 1)
            if not args.compare:
                rates = [steps_per_second(n, args.ticks, controller, seed) for seed in seeds]
                rate = statistics.median(rates)
                print(f"  {n:>8} {controller:>10} {rate:>12,.0f} {rate / n / 10:>11.1f}")
                continue
            rates, before = [], []
            for seed in seeds:  # alternate, so both revisions see the same load
                rates.append(in_checkout(here, n, args.ticks, controller, seed))
                before.append(in_checkout(args.compare, n, args.ticks, controller, seed))
            rate, old = statistics.median(rates), statistics.median(before)
            print(
                f"  {n:>8} {controller:>10} {rate:>12,.0f} {rate / n / 10:>11.1f}   "
                f"{old:>15,.0f} {old / n / 10:>11.1f}  {rate / old:>7.2f}x",
                flush=True,
            )


if __name__ == "__main__":
    main()
