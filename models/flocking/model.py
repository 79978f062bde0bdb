"""The flocking model of the ABMFrameworksComparison suite on the framework.

Birds (:class:`models.flocking.agents.Bird`, robots of the framework) are the Mesa agents of a
periodic Mesa space; the flock's clock is SimPy: one process ticks once per update step, draws
a new random activation order from ``model.rng`` and runs the compiled sequential update
(:func:`models.flocking.kernel.flock_step`) on the space's own position array, so every
agent's ``position`` is current after each step.
"""

import numpy as np

from abm.arena import Arena
from abm.model import SwarmModel
from abm.styles import StateStyle
from models.flocking.agents import Bird
from models.flocking.kernel import CellList, flock_step, order_parameters, squared_limit
from models.flocking.params import FlockingParams
from models.flocking.published import PUBLISHED, REPORT
from models.flocking.units import SUMMARY_UNITS

__all__ = ["FlockingModel"]


class FlockingModel(SwarmModel):
    """Boids on a periodic square, updated one by one in a new random order each step.

    Each step every bird, in turn, finds its neighbours within the visual distance, steers by
    cohesion, separation and alignment, normalises its velocity and moves ``speed * dt``
    (the ABMFrameworksComparison Flocking declaration; ``models/flocking/README.md``).
    """

    Params = FlockingParams
    STATES = ("flying",)
    STATE_STYLES = {"flying": StateStyle("#0072B2", marker="o", size=18.0, label="bird")}
    ARROWS_LABEL = "heading (half the visual distance long)"
    PUBLISHED = PUBLISHED
    # boids pass through one another and the square has no walls: no collision to count
    CONTACTS = False
    REPORT = REPORT
    APP = "models.flocking.app"

    SUMMARY_UNITS = SUMMARY_UNITS

    def __init__(self, *, seed: int | None = None, **params: object) -> None:
        p = self.make_params(**params)
        super().__init__(
            p,
            Arena(np.ones((1, 1), dtype=bool), p.extent, name="periodic square"),
            seed=seed,
            physics=False,
            torus=True,
        )
        positions = self.rng.random((p.birds, 2)) * p.extent
        heading = self.rng.uniform(-1.0, 1.0, (p.birds, 2))
        #: Unit velocity of every bird, one row per bird (the rows of the Mesa space).
        self.velocity = heading / np.linalg.norm(heading, axis=1)[:, None]
        birds = [Bird(self, row) for row in range(p.birds)]
        Bird.enter_all(birds, "flying")
        self.place(np.array([bird.unique_id for bird in birds]), positions)
        self.cells = cells = CellList(self.space.agent_positions, p.extent, p.visual_distance)
        #: Neighbours each bird saw at its last update.
        self.seen = np.zeros(p.birds, dtype=np.int64)
        # the kernel's arguments after positions, velocities and order, all fixed for the run
        # (its arrays are updated in place), gathered once: a step's Python work is the draw
        # of the order and one call
        self._kernel_args = (
            p.extent,
            squared_limit(p.visual_distance),
            squared_limit(p.separation, strict=True),
            np.array([p.cohere_factor, p.separate_factor, p.match_factor]),
            p.speed * p.dt,
            cells.cells,
            cells.side,
            cells.around,
            cells.head,
            cells.after,
            cells.before,
            cells.cell,
            self.seen,
        )
        self._rows = np.arange(p.birds)
        self._order = np.empty(p.birds, dtype=np.int64)  # each step's activation order
        self.updates = 0
        self.env.process(self._flock())

    def _flock(self):
        """The flock's clock: one update step per tick of ``dt`` seconds, ``steps`` of them."""
        for _ in range(self.params.steps):
            yield self.env.timeout(self.params.dt)
            self.update()
        self.finish(f"{self.params.steps} steps")

    def update(self) -> None:
        """One update step: every bird in a new random order, each seeing those moved before."""
        # rng.permutation(birds) is this: the same draws, without making the arrays anew
        order = self._order
        order[:] = self._rows
        self.rng.shuffle(order)
        polarisation, mean_neighbours = flock_step(
            self.space.agent_positions, self.velocity, order, *self._kernel_args
        )
        self.updates += 1
        self.recorder.sample(polarisation=polarisation, mean_neighbours=mean_neighbours)

    def _order_parameters(self) -> dict:
        polarisation, mean_neighbours = order_parameters(self.velocity, self.seen)
        return {"polarisation": polarisation, "mean_neighbours": mean_neighbours}

    def arrows(self) -> tuple[np.ndarray, np.ndarray]:
        """Each bird's heading: its position and unit velocity x half the visual distance (m),
        long enough to see at the scale of the whole square.
        """
        return self.space.agent_positions.copy(), self.velocity * (self.params.visual_distance / 2)

    def reporters(self) -> dict:
        """The state count and the flock's polarisation (the page plots it live)."""
        return {
            **super().reporters(),
            "polarisation": lambda m: m._order_parameters()["polarisation"],
        }

    def metrics(self) -> dict:
        """Update steps run, the flock's polarisation |mean unit velocity| (0: headings at
        random, 1: all birds aligned) and the mean neighbour count at the last step.
        """
        return {"updates": self.updates, **self._order_parameters()}
