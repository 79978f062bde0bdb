"""Speed of the framework, measured as ratios within one run (the machine is shared and noisy).

1. Real-time factor (simulated s / wall s) of a 20-robot high-complexity corridor run of the
   beacon/explorer model: median over several seeds.
2. Flying-robot steps per second at 100 and 1000 robots in an open 100 m x 100 m arena with
   internal walls: our single vectorised physics process (control from four cardinal distance
   sensors, drag, noise, wall contacts, robot-robot contacts from a cell-list Verlet list)
   beside Mesa's own per-agent idiom on its classic ContinuousSpace (``move_agent`` +
   ``get_neighbors`` per agent), which does less work (no walls, no sensors, no dynamics).

Usage: python benchmarks/bench_beacon_explorer.py [--seeds 5] [--ticks 200]
"""

import argparse
import statistics
import time
import warnings

import mesa
import numpy as np
import simpy

from abm.arena import CARDINALS, Arena
from abm.physics import FlightParams, Physics
from analysis.runner import run_model


def real_time_factor(seeds: int) -> list[float]:
    """RTF of the default 20-robot high-complexity corridor run, one per seed.

    One unmeasured warm-up run first loads (or, on a fresh checkout, compiles) the numba kernels.
    """
    params = {"world": "corridor", "complexity": "high"}
    run_model("beacon-explorer", params, seed=0)
    factors = []
    for seed in range(1, seeds + 1):
        result = run_model("beacon-explorer", params, seed)
        factors.append(result.summary["time"] / result.wall_time)
    return factors


def walled_arena() -> Arena:
    free = np.ones((100, 100), dtype=bool)
    free[[0, -1], :] = free[:, [0, -1]] = False
    free[20:80:15, 10:90] = False  # internal walls with gaps at both ends
    return Arena(free, 1.0)


class WallAvoidingWanderer:
    """Vectorised controller: wander, pushed away from walls seen by the cardinal sensors."""

    def __init__(self, arena: Arena, rng: np.random.Generator) -> None:
        self.arena = arena
        self.rng = rng

    def control(self, physics: Physics):
        reading = self.arena.cardinal_distances(physics.pos, 3.5)
        push = np.maximum(0.0, 1.0 / np.maximum(reading, 0.05) - 1.0 / 3.5)
        heading = physics.vel + self.rng.normal(0.0, 0.3, physics.vel.shape) - push @ CARDINALS
        return heading, np.zeros(physics.n_flying, dtype=bool)


def ours_steps_per_second(n: int, ticks: int) -> float:
    rng = np.random.default_rng(1)
    arena = walled_arena()
    env = simpy.Environment()
    physics = Physics(
        env, arena, rng, WallAvoidingWanderer(arena, rng), params=FlightParams(body_noise=0.025)
    )
    starts = arena.free_cell_centres()
    for i, p in enumerate(starts[rng.choice(len(starts), n, replace=False)]):
        physics.fly(i, p)
    start = time.perf_counter()
    env.run(until=ticks * physics.dt - 1e-9)
    return physics.flyer_steps / (time.perf_counter() - start)


class MesaWalker(mesa.Agent):
    """Mesa's idiom: each agent moves itself and asks the space for its neighbours."""

    def __init__(self, model, velocity):
        super().__init__(model)
        self.velocity = velocity

    def step(self):
        x, y = self.pos
        new = (
            min(max(x + 0.1 * self.velocity[0], 0.5), 99.5),
            min(max(y + 0.1 * self.velocity[1], 0.5), 99.5),
        )
        self.model.space.move_agent(self, new)
        self.model.space.get_neighbors(new, radius=0.4, include_center=False)


class MesaModel(mesa.Model):
    def __init__(self, n: int):
        super().__init__(rng=1)
        self.space = mesa.space.ContinuousSpace(100, 100, torus=False)
        for _ in range(n):
            agent = MesaWalker(self, self.rng.normal(0, 1, 2))
            self.space.place_agent(agent, tuple(self.rng.uniform(1, 99, 2)))

    def step(self):
        self.agents.do("step")


def mesa_steps_per_second(n: int, ticks: int) -> float:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = MesaModel(n)
        start = time.perf_counter()
        for _ in range(ticks):
            model.step()
    return n * ticks / (time.perf_counter() - start)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--seeds", type=int, default=5)
    parser.add_argument("--ticks", type=int, default=200)
    args = parser.parse_args()
    factors = real_time_factor(args.seeds)
    print(f"1. real-time factor, 20-robot high-complexity corridor, {args.seeds} seeds:")
    runs = ", ".join(f"{f:.0f}" for f in factors)
    print(f"   median {statistics.median(factors):.0f}x  (runs: {runs})")
    print("2. flying-robot steps per second (open 100 m arena with walls):")
    for n in (100, 1000):
        ticks = args.ticks if n == 100 else max(20, args.ticks // 4)
        ours = statistics.median(ours_steps_per_second(n, ticks) for _ in range(3))
        theirs = statistics.median(mesa_steps_per_second(n, ticks) for _ in range(3))
        print(
            f"   {n:>5} robots: ours {ours:>10,.0f}/s   Mesa per-agent {theirs:>10,.0f}/s   "
            f"ratio {ours / theirs:5.1f}x"
        )


if __name__ == "__main__":
    main()
