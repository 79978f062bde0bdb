"""Robot: a Mesa continuous-space agent with a state, a power mode and a SimPy behaviour."""

from collections.abc import Generator
from typing import TYPE_CHECKING

import numpy as np
import simpy
from mesa.experimental.continuous_space import ContinuousSpaceAgent

if TYPE_CHECKING:
    from abm.model import SwarmModel

__all__ = ["Robot"]


class Robot(ContinuousSpaceAgent):
    """A robot of the swarm.

    The robot's behaviour is a SimPy generator (``behaviour``) that a model writes to read like
    the paper's flowchart; the robot only keeps the bookkeeping every model needs: its state
    (counted by the recorder), its power mode (integrated by the energy ledger) and its place
    in the Mesa space.

    Args:
        model: the swarm model.
        position: where the robot starts (m).
        state: its first state (one of ``model.STATES``).
        mode: its first power mode.

    """

    def __init__(self, model: "SwarmModel", position: np.ndarray, state: str, mode: str) -> None:
        super().__init__(model.space, model)
        model._robot_added(self.unique_id)
        self.position = np.asarray(position, dtype=float)
        self.state: str | None = None
        self.process: simpy.Process | None = None
        self.set_state(state)
        self.set_mode(mode)

    @property
    def env(self) -> simpy.Environment:
        """The model's SimPy environment."""
        return self.model.env

    def set_state(self, state: str) -> None:
        """Enter a new state; logged and counted."""
        if state not in self.model.STATES:
            raise ValueError(f"unknown state {state!r}; states are {self.model.STATES}")
        old, self.state = self.state, state
        self.model.recorder.move(old, state)
        self.model.recorder.log("state", self.unique_id, state=state)

    def set_mode(self, mode: str) -> None:
        """Switch power mode (the ledger integrates power piecewise)."""
        self.model.ledger.set_mode(self.unique_id, mode)

    @property
    def mode(self) -> str:
        """Current power mode."""
        return self.model.ledger.mode(self.unique_id)

    def start(self, behaviour: Generator) -> simpy.Process:
        """Run ``behaviour`` as this robot's SimPy process."""
        self.process = self.env.process(behaviour)
        return self.process

    def remove(self) -> None:
        """Take the robot out of the model: out of the air, out of the counts, the energy
        ledger and the space (the other robots' rows in the space move up).

        The model's own structures (e.g. a beacon network) are the model's to update first.
        """
        model = self.model
        if model.physics is not None and self.unique_id in model.physics.ids:
            model.physics.stop(self.unique_id)
        if self.process is not None and self.process.is_alive:
            self.process.interrupt("removed")
        model.recorder.move(self.state, None)
        model.recorder.log("removed", self.unique_id)
        model.ledger.retire(self.unique_id)
        super().remove()
        model._robots_reindexed()
