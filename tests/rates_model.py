"""A test model whose robots change state at known rates (for ``analysis.macroscopic``).

Robots stand still at random places in a square room, all present from the start (state A),
or one per ``launch_period``. Each robot in A turns B at the constant hazard ``rate_ab``;
each robot in B turns C at a hazard set by the robots in A:

- ``mixing="global"`` (well mixed): ``contact * n_A``, mass action on the global count;
- ``mixing="local"`` (not well mixed by construction): ``contact * m_A * area / (pi r^2)``
  with m_A the robots in A within ``radius`` of it: the same mean hazard in a uniform swarm,
  but what matters is who stands nearby.

The chain is simulated exactly (Gillespie) as one SimPy process; every change goes through
``Robot.set_state``, so the event log is what any model's log is.
"""

from dataclasses import dataclass

import numpy as np

from abm.arena import Arena
from abm.model import SwarmModel
from abm.params import SwarmParams, param
from abm.robot import Robot


@dataclass(frozen=True)
class RatesParams(SwarmParams):
    """Known rates.

    Attributes:
        robots: swarm size N.
        rate_ab: hazard of A -> B (1/s).
        contact: per-partner hazard of B -> C (1/(s robot)).
        mixing: "global" or "local" (see the module's docstring).
        radius: neighbourhood radius of the "local" mixing (m).
        room: side of the square room (m).
        launch_period: time between two robots' appearances (s; 0: all at t = 0).
        time_limit: longest run (s).

    """

    robots: int = param(30, low=1, high=500, integer=True)
    rate_ab: float = param(0.05, low=0.0)
    contact: float = param(0.002, low=0.0)
    mixing: str = param("global", choices=("global", "local"))
    radius: float = param(3.0, low=0.0, low_open=True)
    room: float = param(20.0, low=2.0, high=200.0)
    launch_period: float = param(0.0, low=0.0)
    time_limit: float = param(150.0, low=0.0, low_open=True)


class RatesModel(SwarmModel):
    """Robots in A turn B at a constant rate; robots in B turn C by meeting robots in A."""

    Params = RatesParams
    STATES = ("A", "B", "C")

    def __init__(self, *, seed: int | None = None, **params: object) -> None:
        p = self.make_params(**params)
        n = int(np.ceil(p.room))
        super().__init__(p, Arena(np.ones((n, n), dtype=bool), 1.0, name="room"), seed=seed,
                         physics=False)  # fmt: skip
        self.robots: list[Robot] = []
        self.env.process(self._launcher())
        self.env.process(self._chain())
        self._changed = self.env.event()

    def _launcher(self):
        for _ in range(self.params.robots):
            if self.params.launch_period > 0:
                yield self.env.timeout(self.params.launch_period)
            place = self.rng.uniform(0.0, self.params.room, 2)
            self.robots.append(Robot(self, place, "A", "idle"))
            self._poke()

    def _poke(self) -> None:
        """Wake the chain: the population changed outside it."""
        if not self._changed.triggered:
            self._changed.succeed()

    def _hazards(self) -> np.ndarray:
        p = self.params
        states = np.array([r.state for r in self.robots])
        hazard = np.where(states == "A", p.rate_ab, 0.0)
        b = states == "B"
        if b.any():
            if p.mixing == "global":
                hazard[b] = p.contact * np.count_nonzero(states == "A")
            else:
                xy = np.array([r.position for r in self.robots])
                a_xy = xy[states == "A"]
                near = np.linalg.norm(xy[b][:, None, :] - a_xy[None, :, :], axis=2) <= p.radius
                scale = p.room**2 / (np.pi * p.radius**2)
                hazard[b] = p.contact * near.sum(axis=1) * scale
        return hazard

    def _chain(self):
        while True:
            hazard = self._hazards() if self.robots else np.zeros(0)
            total = hazard.sum()
            if total <= 0:
                if len(self.robots) == self.params.robots:
                    self.finish("no transition left")
                    return
                self._changed = self.env.event()
                yield self._changed
                continue
            self._changed = self.env.event()
            wait = self.env.timeout(self.rng.exponential(1.0 / total))
            yield wait | self._changed
            if not wait.processed and not wait.triggered:
                continue  # a robot appeared: the hazards changed (memoryless: draw again)
            robot = self.robots[int(self.rng.choice(len(hazard), p=hazard / total))]
            robot.set_state("B" if robot.state == "A" else "C")
