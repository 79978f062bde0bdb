"""The stigmergy swarm's robot: a UAV that wanders, then lands as a beacon.

Arnaldo et al. (2018), "Proposed microscopic behaviour and virtual stigmergy sensor for
multi-robot deployment" and Fig 1: every UAV has a numeric identifier that grows with each
launch; it flies (wander state) until its communication with the swarm weakens to a threshold
(at most l_i metres from the nearest beacon), then lands and becomes a beacon, which relays
for the swarm and leaves a pheromone footprint of radius C_rb and intensity C_db once.
"""

from collections.abc import Generator
from typing import TYPE_CHECKING

import numpy as np

from abm.robot import Robot

if TYPE_CHECKING:
    from models.stigmergy.model import StigmergyModel

__all__ = ["UAV"]


class UAV(Robot):
    """One UAV of the swarm: state "wander" (flying, power mode "flight") or "beacon" (landed,
    relaying, power mode "beacon").

    Args:
        model: the stigmergy model.
        position: where it starts (m): p0, the launch site.
        state: "wander" for a launched UAV, "beacon" for the one already landed at p0.
        mode: its power mode, "flight" or "beacon".
        launch_index: its identifier in launch order (0 for p0's beacon, then 1, 2, ...);
            the footprint's intensity C_db = (swarmsize - launch_index) / swarmsize.

    Attributes:
        launch_index: as above.
        beacon_row: its row in ``model.beacon_positions`` while it is a live beacon (the
            model renumbers the rows when a beacon fails), else None.

    """

    model: "StigmergyModel"

    def __init__(
        self,
        model: "StigmergyModel",
        position: np.ndarray,
        state: str,
        mode: str,
        *,
        launch_index: int,
    ) -> None:
        super().__init__(model, position, state, mode)
        self.launch_index = launch_index
        self.beacon_row: int | None = None

    def wander(self) -> Generator:
        """Take off from p0 and explore until the link to the swarm weakens to l_i, then land.

        The flight itself (heading f = a1 f1 + a2 f2 + a3 f3, the wander's pheromone deposits,
        the link check every 0.5 s model step) is worked out for every flying UAV at once by
        the model's :class:`~models.stigmergy.wander.WanderController`, which ends this
        UAV's flight when the nearest beacon is l_i or farther away.
        """
        model = self.model
        landed = model.physics.fly(self.unique_id, model.start)
        model.controller.launched()  # its first heading
        yield landed
        self.land()

    def land(self) -> None:
        """Become a beacon where it is: leave the footprint (radius C_rb, intensity C_db), then
        relay for the swarm (a new row of the model's beacons) and see its surroundings.
        """
        model = self.model
        if self.state != "beacon":
            self.set_state("beacon")
            self.set_mode("beacon")
        position = self.position.copy()
        model.recorder.log("land", self.unique_id, x=position[0], y=position[1])
        p = model.params
        model.pheromone.deposit(
            position,
            p.pheromone_radius,
            max(0.0, (p.swarmsize - self.launch_index) / p.swarmsize),
            time=model.env.now,
            line_of_sight=p.deposit_line_of_sight,
        )
        self.beacon_row = model.add_beacon(position)
