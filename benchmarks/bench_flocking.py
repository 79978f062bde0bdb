"""The ABMFrameworksComparison flocking benchmark: our model beside Mesa 3.5, small and large.

The Mesa side is written the way Mesa's own ``boid_flockers`` example writes boids (a
``ContinuousSpaceAgent`` per bird on a periodic ``ContinuousSpace``, ``get_neighbors_in_radius``
and numpy per agent, ``agents.shuffle_do("step")`` per step), with the example's update
replaced by the comparison's declared rule (means over all neighbours, vel = unit((vel +
cohere + separate + match) / 2)). Ours is ``models.flocking.FlockingModel`` (Mesa agents, the
SimPy clock, the compiled sequential update) with position tracing off, as the comparison
records nothing.

What is timed, as the comparison's current harnesses do (``Flocking/Agents/
benchmark_flocking.jl`` and ``Flocking/Mesa/benchmark_flocking.py``): one run is the model's
construction plus exactly 100 steps, from a seed drawn for the run; the median over the runs
is reported. Both wall time (what the comparison reports) and CPU time of this process (what
is fair on a machine shared with other work) are measured, and the 100 steps alone as well.
The two frameworks' runs are interleaved, so both see the same machine load.

Run: ``.venv/bin/python benchmarks/bench_flocking.py`` (``--mesa-runs``, ``--our-runs``).
"""

import argparse
import time

import mesa
import numpy as np
from mesa.experimental.continuous_space import ContinuousSpace, ContinuousSpaceAgent
from tqdm import tqdm

from models.flocking import LARGE, SMALL, FlockingModel
from models.flocking.published import SLOWER_THAN_AGENTS_JL

STEPS = 100  # the declaration: exactly 100 steps
CASES = {"small": SMALL, "large": LARGE}
SEED = 42  # seeds of the runs are drawn from this one, as the comparison draws them


class MesaBoid(ContinuousSpaceAgent):
    """Mesa's boid_flockers ``Boid`` with the comparison's declared update."""

    def __init__(self, model, space, position, direction, speed, vision, separation,
                 cohere, separate, match):  # fmt: skip
        super().__init__(space, model)
        self.position = position
        self.direction = direction
        self.speed = speed
        self.vision = vision
        self.separation = separation
        self.cohere_factor = cohere
        self.separate_factor = separate
        self.match_factor = match

    def step(self):
        neighbors, distances = self.get_neighbors_in_radius(radius=self.vision)
        if not neighbors:  # unit((vel + 0) / 2) is vel: keep the heading
            self.position += self.direction * self.speed
            return
        n = len(neighbors)
        delta = self.space.calculate_difference_vector(self.position, agents=neighbors)
        cohere = delta.sum(axis=0) / n * self.cohere_factor
        separate = -delta[distances < self.separation].sum(axis=0) / n * self.separate_factor
        match = np.asarray([b.direction for b in neighbors]).sum(axis=0) / n * self.match_factor
        self.direction = (self.direction + cohere + separate + match) / 2
        self.direction /= np.linalg.norm(self.direction)
        self.position += self.direction * self.speed


class MesaFlock(mesa.Model):
    """Mesa's BoidFlockers model (periodic ContinuousSpace, random activation each step)."""

    def __init__(self, seed, birds, extent, visual_distance, speed=1.0, separation=1.0,
                 cohere=0.03, separate=0.015, match=0.05):  # fmt: skip
        super().__init__(rng=seed)
        self.space = ContinuousSpace(
            [[0, extent], [0, extent]], torus=True, random=self.random, n_agents=birds
        )
        positions = self.rng.random(size=(birds, 2)) * self.space.size
        directions = self.rng.uniform(-1, 1, size=(birds, 2))
        directions /= np.linalg.norm(directions, axis=1)[:, None]  # declared: a unit vector
        MesaBoid.create_agents(
            self, birds, self.space, position=positions, direction=directions, speed=speed,
            vision=visual_distance, separation=separation, cohere=cohere, separate=separate,
            match=match,
        )  # fmt: skip

    def step(self):
        self.agents.shuffle_do("step")

    def polarisation(self) -> float:
        return float(np.linalg.norm(np.mean([b.direction for b in self.agents], axis=0)))


def _mesa_run(seed: int, case: dict) -> tuple[float, float, float, float, float]:
    """(wall, cpu, wall of the steps, cpu of the steps, polarisation) of one Mesa run (s)."""
    w0, c0 = time.perf_counter(), time.process_time()
    model = MesaFlock(seed, **case)
    w1, c1 = time.perf_counter(), time.process_time()
    for _ in range(STEPS):
        model.step()
    w2, c2 = time.perf_counter(), time.process_time()
    return w2 - w0, c2 - c0, w2 - w1, c2 - c1, model.polarisation()


def _our_run(seed: int, case: dict) -> tuple[float, float, float, float, float]:
    """The same for our model."""
    w0, c0 = time.perf_counter(), time.process_time()
    model = FlockingModel(seed=seed, trace_interval=None, steps=STEPS, **case)
    w1, c1 = time.perf_counter(), time.process_time()
    model.run()
    w2, c2 = time.perf_counter(), time.process_time()
    return w2 - w0, c2 - c0, w2 - w1, c2 - c1, model.summary()["polarisation"]


def _bench(case: dict, mesa_runs: int, our_runs: int, bar: tqdm) -> dict:
    seeds = np.random.default_rng(SEED).integers(1, 10_001, size=max(mesa_runs, our_runs))
    ours_per_mesa = -(-our_runs // mesa_runs)
    mesa_rows, our_rows = [], []
    for r in range(mesa_runs):  # interleaved: every Mesa run, then a few of ours
        mesa_rows.append(_mesa_run(int(seeds[r]), case))
        bar.update(1)
        for k in range(r * ours_per_mesa, min((r + 1) * ours_per_mesa, our_runs)):
            our_rows.append(_our_run(int(seeds[k]), case))
    mesa_med = np.median(np.array(mesa_rows), axis=0)
    our_med = np.median(np.array(our_rows), axis=0)
    return {"mesa": mesa_med, "ours": our_med, "ratio": mesa_med[:4] / our_med[:4]}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--mesa-runs", type=int, default=15, help="seeded Mesa runs per case")
    parser.add_argument("--our-runs", type=int, default=100, help="seeded runs of ours per case")
    args = parser.parse_args()
    if args.mesa_runs < 1 or args.our_runs < 1:
        parser.error("--mesa-runs and --our-runs must be at least 1")
    _our_run(1, {"birds": 20, "extent": 30.0, "visual_distance": 5.0})  # compile the kernel
    results = {}
    with tqdm(total=2 * args.mesa_runs, desc="Mesa runs (ours interleaved)") as bar:
        for name, case in CASES.items():
            results[name] = _bench(case, args.mesa_runs, args.our_runs, bar)
    print(f"\nFlocking, construction + {STEPS} steps, median of {args.mesa_runs} Mesa "
          f"{mesa.__version__} runs and {args.our_runs} of ours (seeds from {SEED})")  # fmt: skip
    header = (
        f"{'case':6} {'Mesa wall':>10} {'ours wall':>10} {'ratio':>7}   {'Mesa CPU':>10} "
        f"{'ours CPU':>10} {'ratio':>7}   {'target':>7}"
    )
    print(header)
    agents_jl = SLOWER_THAN_AGENTS_JL["Mesa 3.2"]
    for i, (name, res) in enumerate(results.items()):
        m, o, ratio = res["mesa"], res["ours"], res["ratio"]
        print(
            f"{name:6} {m[0] * 1e3:8.1f}ms {o[0] * 1e3:8.2f}ms {ratio[0]:6.0f}x   "
            f"{m[1] * 1e3:8.1f}ms {o[1] * 1e3:8.2f}ms {ratio[1]:6.0f}x   >={agents_jl[i]:5.1f}x"
        )
    print(f"\nThe {STEPS} steps alone (construction excluded)")
    for name, res in results.items():
        m, o, ratio = res["mesa"], res["ours"], res["ratio"]
        print(
            f"{name:6} {m[2] * 1e3:8.1f}ms {o[2] * 1e3:8.2f}ms {ratio[2]:6.0f}x   "
            f"{m[3] * 1e3:8.1f}ms {o[3] * 1e3:8.2f}ms {ratio[3]:6.0f}x"
        )
    print(f"\nSame rules, same order: median polarisation after {STEPS} steps")
    for name, res in results.items():
        print(f"{name:6} Mesa {res['mesa'][4]:.2f}   ours {res['ours'][4]:.2f}")
    print("\nPublished (ABMFrameworksComparison): times slower than Agents.jl, small / large")
    for framework, (small, large) in SLOWER_THAN_AGENTS_JL.items():
        print(f"  {framework:9} {small:6.2f} / {large:5.2f}")


if __name__ == "__main__":
    main()
