"""Robot: a Mesa continuous-space agent with a state, a power mode and a SimPy behaviour."""

import inspect
from collections.abc import Generator, Sequence
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

    A model's robots are subclasses of this class in the model's ``agents.py``, one per role,
    and a robot's behaviour is a SimPy generator method of its class that reads like the
    source's flowchart, run with ``robot.start(robot.behaviour())``. This class keeps the
    bookkeeping every model needs: its state (counted by the recorder), its power mode
    (integrated by the energy ledger) and its place in the Mesa space. A robot joins the model
    when it is made and the model's ``agents`` is the index of its robots; changes of state,
    failures and removals are published on ``model.lifecycle`` (:mod:`abm.lifecycle`) to the
    parts that keep something per robot.

    A robot that failed (:meth:`abm.faults.FaultInjector.fail`) keeps its place and its
    ``failure`` record; it refuses any further change of state or mode
    (:class:`RobotFailedError`), so a model that forgot one of its robots failed learns it.

    Args:
        model: the swarm model.
        position: where the robot starts (m); None when the model places its robots itself,
            all at once (:meth:`~abm.model.SwarmModel.place`), before they move.
        state: its first state (one of ``model.STATES``); None for a robot that a model makes
            among many at once and puts in its first state with the others, in one call of
            :meth:`enter_all`, before anything else happens to it.
        mode: its first power mode; None for a robot whose energy is not modelled (it then
            has no mode, and draws nothing).

    """

    def __init__(
        self,
        model: "SwarmModel",
        position: np.ndarray | None,
        state: str | None,
        mode: str | None = None,
    ) -> None:
        super().__init__(model.space, model)
        model.joined_space(self.unique_id)
        if position is not None:
            self.position = np.asarray(position, dtype=float)
        self.state: str | None = None
        self.process: simpy.Process | None = None
        self.failure: Failure | None = None
        self._removed = False
        if state is not None:
            self.set_state(state)
        if mode is not None:
            self.set_mode(mode)

    @property
    def env(self) -> simpy.Environment:
        """The model's SimPy environment."""
        return self.model.env

    def set_state(self, state: str) -> None:
        """Enter a new state; logged, counted and published (``"state"``: a robot's fault
        hazard may apply in some states only).
        """
        if state not in self.model.STATES:
            raise ValueError(f"unknown state {state!r}; states are {self.model.STATES}")
        self._refuse_if_failed(f"enter state {state!r}")
        old, self.state = self.state, state
        self.model.recorder.move(old, state)
        self.model.recorder.log("state", self.unique_id, state=state)
        self.model.lifecycle.publish("state", self, old, state)

    @staticmethod
    def enter_all(robots: Sequence["Robot"], state: str) -> None:
        """Put robots of one model, just made without a state, into their first ``state``
        together: the event rows, counts and lifecycle events of ``set_state`` on each in
        turn, in one pass (a flock of hundreds of birds is made at once).

        Raises:
            ValueError: ``state`` is not one of the model's states, or a robot already has a
                state or belongs to another model.

        """
        if not robots:
            return
        model = robots[0].model
        if state not in model.STATES:
            raise ValueError(f"unknown state {state!r}; states are {model.STATES}")
        for robot in robots:
            if robot.state is not None or robot.model is not model:
                raise ValueError(
                    f"robot {robot.unique_id} already has a state or another model; enter_all "
                    "takes robots of one model made with state=None"
                )
        model.recorder.entered(state, [robot.unique_id for robot in robots])
        told = model.lifecycle.subscribers("state")
        for robot in robots:
            robot.state = state
            for callback in told:
                callback(robot, None, state)

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
        """Current power mode (None once the robot failed, or for a robot without one)."""
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
                "expected a generator, the behaviour called: robot.start(robot.walk())"
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
        """Take the robot out of the model: the one place a robot leaves without failing.

        It is published (``"removed"``: it leaves the air, the comm network and the energy
        ledger, and faults no longer touch it), its process is interrupted, it leaves the
        counts (logged as ``removed``), Mesa's agents and the space (the other robots' rows in
        the space move up).

        The model's own structures (e.g. a beacon network) are the model's to update first.
        """
        model = self.model
        self._removed = True
        model.lifecycle.publish("removed", self)
        if self.process is not None and self.process.is_alive:
            self.process.interrupt("removed")
        model.recorder.move(self.state, None)
        model.recorder.log("removed", self.unique_id)
        super().remove()
        model.left_space()


def _called(behaviour: object) -> str:
    """What a robot was given to run, for the message (a function: its name, not called)."""
    if behaviour is None:
        return "None (a behaviour without any yield runs at once when called)"
    if callable(behaviour):
        return f"the function {getattr(behaviour, '__qualname__', behaviour)!s} (not called)"
    return f"a {type(behaviour).__qualname__}"
