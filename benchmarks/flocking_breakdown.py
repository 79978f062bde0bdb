"""Where a flocking run's CPU time goes: construction, the compiled update, the rest of a step.

For each of the comparison's cases, medians over ``--runs`` seeded runs (CPU time of this
process) of: the run with data collection off (construction plus 100 steps), its construction,
Mesa's own creation of as many plain ``ContinuousSpaceAgent``s in a bare Mesa model and space
(what any Mesa model pays for its agents: the floor of our construction), the compiled update's
100 calls (``kernel.flock_step``, timed call by call) and what is left of the steps (the
activation order drawn, the call, the sample, SimPy's tick); and the run with the model's
defaults (position trace on).

Run: ``.venv/bin/python benchmarks/flocking_breakdown.py [--runs 20]``.
"""

import argparse
import time

import mesa
import numpy as np
from mesa.experimental.continuous_space import ContinuousSpace, ContinuousSpaceAgent

import models.flocking.model as flocking_model
from models.flocking import LARGE, SMALL, FlockingModel
from models.flocking.kernel import flock_step


class _PlainAgent(ContinuousSpaceAgent):
    """A Mesa agent in a continuous space and nothing else."""


def _mesa_agents(seed: int, case: dict) -> float:
    """CPU time (s) Mesa takes to make ``case["birds"]`` plain continuous-space agents."""
    model = mesa.Model(rng=seed)
    side = case["extent"]
    space = ContinuousSpace([[0, side], [0, side]], torus=True, random=model.random)
    c0 = time.process_time()
    for _ in range(case["birds"]):
        _PlainAgent(space, model)
    return time.process_time() - c0


def breakdown(seed: int, case: dict) -> tuple[float, ...]:
    """(total, construction, Mesa's agents, kernel, rest of the steps, total with defaults), s."""
    spent = [0.0]

    def timed(*args):
        c0 = time.process_time()
        out = flock_step(*args)
        spent[0] += time.process_time() - c0
        return out

    mesa_agents = _mesa_agents(seed, case)
    c0 = time.process_time()
    model = FlockingModel(seed=seed, trace_interval=None, **case)
    c1 = time.process_time()
    flocking_model.flock_step = timed
    try:
        model.run()
    finally:
        flocking_model.flock_step = flock_step
    c2 = time.process_time()
    FlockingModel(seed=seed, **case).run()
    c3 = time.process_time()
    return c2 - c0, c1 - c0, mesa_agents, spent[0], c2 - c1 - spent[0], c3 - c2


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--runs", type=int, default=20, help="seeded runs per case")
    args = parser.parse_args()
    FlockingModel(seed=1, birds=20, extent=30.0).run()  # compile
    for name, case in (("small", SMALL), ("large", LARGE)):
        rows = [breakdown(seed, case) for seed in range(args.runs)]
        r = np.median(np.array(rows), axis=0) * 1e3
        print(
            f"{name}: DC off {r[0]:.2f} ms = construction {r[1]:.2f} (Mesa's own creation of "
            f"{case['birds']} plain agents: {r[2]:.2f}) + compiled update {r[3]:.2f} + rest of "
            f"the steps {r[4]:.2f}; defaults {r[5]:.2f} ms"
        )


if __name__ == "__main__":
    main()
