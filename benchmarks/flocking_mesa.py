"""The Mesa side of the flocking benchmark, importable by any Mesa 3.2+ on its own.

Mesa's own ``boid_flockers`` example (a ``ContinuousSpaceAgent`` per bird on a periodic
``ContinuousSpace``, ``get_neighbors_in_radius`` and numpy per agent,
``agents.shuffle_do("step")`` per step) with the example's update replaced by the
ABMFrameworksComparison's declared rule (means over all neighbours, vel = unit((vel + cohere +
separate + match) / 2)). It imports nothing of this project, so a venv that holds only another
Mesa (``bench_flocking.py`` makes one for Mesa 3.2.0, the version of the comparison's published
table) runs it as a worker:

    python flocking_mesa.py --worker

prints one JSON line naming its Mesa, numpy and Python, then answers each request line
``{"seed": 7, "birds": 200, "extent": 100.0, "visual_distance": 5.0, "steps": 100}`` with one
line ``{"wall": .., "cpu": .., "wall_steps": .., "cpu_steps": .., "polarisation": ..}``
(seconds: construction plus the steps, and the steps alone; CPU time of the worker process).
"""

import json
import platform
import sys
import time

import mesa
import numpy as np
from mesa.experimental.continuous_space import ContinuousSpace, ContinuousSpaceAgent

__all__ = ["MesaBoid", "MesaFlock", "mesa_run", "serve"]


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
        """Find the neighbours, steer by the declared rule, move ``speed`` along the heading."""
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
        """Every boid once, in a new random order."""
        self.agents.shuffle_do("step")

    def polarisation(self) -> float:
        """|mean unit heading| of the flock."""
        return float(np.linalg.norm(np.mean([b.direction for b in self.agents], axis=0)))


def mesa_run(seed: int, birds: int, extent: float, visual_distance: float, steps: int) -> dict:
    """One timed run: construction plus ``steps`` steps (s, wall and CPU), the steps alone, and
    the flock's polarisation at the end.
    """
    w0, c0 = time.perf_counter(), time.process_time()
    model = MesaFlock(seed, birds, extent, visual_distance)
    w1, c1 = time.perf_counter(), time.process_time()
    for _ in range(steps):
        model.step()
    w2, c2 = time.perf_counter(), time.process_time()
    return {
        "wall": w2 - w0,
        "cpu": c2 - c0,
        "wall_steps": w2 - w1,
        "cpu_steps": c2 - c1,
        "polarisation": model.polarisation(),
    }


def serve(requests, reply) -> None:
    """Answer run requests (JSON lines from ``requests``) with ``reply(line)``, after a first
    line naming the versions this worker runs.
    """
    reply(
        json.dumps(
            {"mesa": mesa.__version__, "numpy": np.__version__, "python": platform.python_version()}
        )
    )
    for line in requests:
        if line.strip():
            reply(json.dumps(mesa_run(**json.loads(line))))


if __name__ == "__main__":
    if sys.argv[1:] != ["--worker"]:
        sys.exit(__doc__)
    serve(sys.stdin, lambda line: print(line, flush=True))
