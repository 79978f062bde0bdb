"""The flock's robot: a bird whose position and unit velocity are rows of the flock's arrays."""

from typing import TYPE_CHECKING

import numpy as np

from abm.robot import Robot

if TYPE_CHECKING:
    from models.flocking.model import FlockingModel

__all__ = ["Bird"]


class Bird(Robot):
    """One bird of the flock: a robot in its one state, ``flying``.

    A bird has no SimPy process of its own and draws no power (no mode): every update step the
    flock's compiled sequential update (:func:`models.flocking.kernel.flock_step`) moves all
    birds at once, one by one in a fresh random order, on the Mesa space's position array and
    the flock's velocity array, where the bird's rows are.

    Args:
        model: the flocking model (which places all birds at once and puts them in their
            state, ``flying``, together: :meth:`~abm.robot.Robot.enter_all`).
        row: its row in the space's position array and the flock's velocity array.

    """

    def __init__(self, model: "FlockingModel", row: int) -> None:
        super().__init__(model, None, None)
        self.row = row

    @property
    def velocity(self) -> np.ndarray:
        """The bird's unit velocity (a view: the flock's update writes it)."""
        return self.model.velocity[self.row]
