"""Robot: a Mesa continuous-space agent with a state, a power mode and a SimPy behaviour."""

import inspect
from collections.abc import Generator
from typing import TYPE_CHECKING

import numpy as np
import simpy
from mesa.experimental.continuous_space import ContinuousSpaceAgent

from abm.errors import ABMError, HookError

if TYPE_CHECKING:
    from abm.faults import Failure
    from abm.model import SwarmModel

__all__ = ["Robot", "RobotFailedError"]


class RobotFailedError(ABMError, RuntimeError):
    """A model tried to change the state or power mode of a robot that has failed."""


class Robot(ContinuousSpaceAgent):
    """A robot of the swarm.

    The robot's behaviour is a SimPy generator (``behaviour``) that a model writes to read like
    the source's flowchart; the robot only keeps the bookkeeping every model needs: its state
    (counted by the recorder), its power mode (integrated by the energy ledger) and its place
    in the Mesa space.

    A robot that failed (:meth:`abm.faults.FaultInjector.fail`) keeps its place and its
    ``failure`` record; it refuses any further change of state or mode
    (:class:`RobotFailedError`), so a model that forgot one of its robots failed learns it.

    Args:
        model: the swarm model.
        position: where the robot starts (m).
        state: its first state (one of ``model.STATES``).
        mode: its first power mode.

    """

    def __init__(self, model: "SwarmModel", position: np.ndarray, state: str, mode: str) -> None:
        super().__init__(model.space, model)
        model.joined_space(self.unique_id)
        self.position = np.asarray(position, dtype=float)
        self.state: str | None = None
        self.process: simpy.Process | None = None
        self.failure: Failure | None = None
        self._removed = False
        self.set_state(state)
        self.set_mode(mode)

    @property
    def env(self) -> simpy.Environment:
        """The model's SimPy environment."""
        return self.model.env

    def set_state(self, state: str) -> None:
        """Enter a new state; logged and counted (the fault injector learns it too: a
        robot's hazard may apply in some states only).
        """
        if state not in self.model.STATES:
            raise ValueError(f"unknown state {state!r}; states are {self.model.STATES}")
        self._refuse_if_failed(f"enter state {state!r}")
        old, self.state = self.state, state
        self.model.recorder.move(old, state)
        self.model.recorder.log("state", self.unique_id, state=state)
        self.model.faults.state_changed(self, old, state)

    def set_mode(self, mode: str) -> None:
        """Switch power mode (the ledger integrates power piecewise)."""
        self._refuse_if_failed(f"switch to power mode {mode!r}")
        self.model.ledger.set_mode(self.unique_id, mode)

    @property
    def failed(self) -> bool:
        """True once the robot has failed (see ``failure`` for when, why and in what state)."""
        return self.failure is not None

    def _refuse_if_failed(self, what: str) -> None:
        if self.failure is not None:
            raise RobotFailedError(
                f"robot {self.unique_id} failed at t={self.failure.time:g} s "
                f"({self.failure.cause}); it cannot {what} (handle on_robot_failed)"
            )

    @property
    def mode(self) -> str | None:
        """Current power mode (None once the robot failed: its ledger is closed)."""
        if self.failure is not None:
            return None
        return self.model.ledger.mode(self.unique_id)

    def start(self, behaviour: Generator) -> simpy.Process:
        """Run ``behaviour`` as this robot's SimPy process.

        When the robot fails or is removed its process is interrupted; a behaviour that does
        not catch the interrupt simply ends there.

        Raises:
            HookError: ``behaviour`` is not a generator (e.g. the generator function itself,
                not called), naming the model and what it got.

        """
        if not inspect.isgenerator(behaviour):
            raise HookError(
                f"{type(self.model).__qualname__}: robot.start() got {_called(behaviour)}; "
                "expected a generator, the behaviour called: robot.start(self.walk(robot))"
            )
        self.process = self.env.process(self._ends_on_interrupt(behaviour))
        return self.process

    def _ends_on_interrupt(self, behaviour: Generator) -> Generator:
        try:
            return (yield from behaviour)
        except simpy.Interrupt:
            if self.failure is None and not self._removed:
                raise
            return None

    def remove(self) -> None:
        """Take the robot out of the model: out of the air, out of the counts, the energy
        ledger and the space (the other robots' rows in the space move up).

        The model's own structures (e.g. a beacon network) are the model's to update first.
        """
        model = self.model
        self._removed = True
        if model.physics is not None and self.unique_id in model.physics.ids:
            model.physics.stop(self.unique_id)
        if self.process is not None and self.process.is_alive:
            self.process.interrupt("removed")
        model.faults.robot_removed(self)
        model.recorder.move(self.state, None)
        model.recorder.log("removed", self.unique_id)
        model.ledger.retire(self.unique_id)
        super().remove()
        model.left_space()


def _called(behaviour: object) -> str:
    """What a robot was given to run, for the message (a function: its name, not called)."""
    if behaviour is None:
        return "None (a behaviour without any yield runs at once when called)"
    if callable(behaviour):
        return f"the function {getattr(behaviour, '__qualname__', behaviour)!s} (not called)"
    return f"a {type(behaviour).__qualname__}"
