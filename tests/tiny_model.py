"""A third model defined only in the tests: walkers in a walled room rest after a random time.

It exists to show that a model is only its own code: registered through the entry-point group
(see ``conftest.py``), it gets every verb without a line of ``abm/`` or ``analysis/`` changed.
"""

from dataclasses import dataclass

import numpy as np

from abm.arena import Arena
from abm.coverage import CoverageRaster
from abm.model import SwarmModel
from abm.params import SwarmParams, param
from abm.physics import FlightParams
from abm.published import MacroSpec
from abm.robot import Robot


@dataclass(frozen=True)
class TinyParams(SwarmParams):
    """A random walk in a square room.

    Attributes:
        walkers: robots launched from the room's centre.
        launch_period: time between two launches (s).
        rest_rate: rate at which a walker stops for good (1/s).
        speed: walking speed (m/s).
        room: side of the square room (m).
        sensor_range: radius a resting robot covers (m).
        time_limit: longest run (s).

    """

    walkers: int = param(6, low=1, high=200, integer=True)
    launch_period: float = param(5.0, low=0.0, low_open=True)
    rest_rate: float = param(0.05, low=0.0, low_open=True)
    speed: float = param(0.5, low=0.0, high=0.55, low_open=True)
    room: float = param(12.0, low=4.0, high=200.0)
    sensor_range: float = param(1.5, low=0.0, low_open=True)
    time_limit: float = param(200.0, low=0.0, low_open=True)


class Walker(Robot):
    """A walker: leaves the centre at full speed in random directions, rests after a random
    time (rate ``rest_rate``) and covers what its sensor sees from where it rests.
    """

    def walk(self):
        """The walker's behaviour: walk, then rest for good."""
        model = self.model
        model.physics.fly(self.unique_id, model.centre)
        yield model.env.timeout(model.rng.exponential(1.0 / model.params.rest_rate))
        model.physics.finish([self.unique_id])
        self.set_state("resting")
        self.set_mode("rest")
        model.comms.add(self.unique_id, self.position.copy())
        model.coverage.stamp(self.position[None], model.env.now)
        if model.recorder.counts["resting"] == model.params.walkers:
            model.finish("all resting")


class TinyModel(SwarmModel):
    """Walkers leave the centre one per launch period, walk at random and rest."""

    Params = TinyParams
    STATES = ("walking", "resting")
    MACRO = MacroSpec("walking", "resting", step=1.0, arrival_period="launch_period",
                      supply="walkers")  # fmt: skip

    def __init__(self, *, seed: int | None = None, **params: object) -> None:
        p = self.make_params(**params)
        n = int(p.room)
        free = np.zeros((n + 2, n + 2), dtype=bool)
        free[1:-1, 1:-1] = True
        super().__init__(p, Arena(free, 1.0, name="room"), seed=seed, comm_range=2.0,
                         powers={"walk": 10.0, "rest": 1.0},
                         flight=FlightParams(max_speed=p.speed, body_noise=0.01))  # fmt: skip
        self.coverage = CoverageRaster(self.arena, p.sensor_range, pixel=0.5)
        self.physics.controller = self
        self.centre = np.array([self.arena.width, self.arena.height]) / 2
        self.env.process(self._launcher())

    def control(self, physics):
        """Every tick each walker heads in a random direction at full speed."""
        angle = self.rng.uniform(0, 2 * np.pi, physics.n_flying)
        heading = np.stack([np.cos(angle), np.sin(angle)], axis=1) * self.params.speed
        return heading, np.zeros(physics.n_flying, dtype=bool)

    def _launcher(self):
        for _ in range(self.params.walkers):
            yield self.env.timeout(self.params.launch_period)
            walker = Walker(self, self.centre, "walking", "walk")
            walker.start(walker.walk())

    def metrics(self) -> dict:
        """Robots resting at the end (MACRO reads its parameters from the run's own)."""
        return {"resting": self.recorder.counts["resting"]}
