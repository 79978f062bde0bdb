"""A robot's lifecycle as events the interested parts of a model subscribe to.

A robot joins the swarm when it is made (:class:`~abm.robot.Robot`), changes state, and leaves
it by failing (:meth:`abm.faults.FaultInjector.fail`) or by being removed
(:meth:`abm.robot.Robot.remove`). Each of these happens in one place, which publishes it here;
the parts that keep something per robot -- the flight physics, the comm network, the energy
ledger, the fault injector -- subscribe to what concerns them (the model wires them in
:class:`~abm.model.SwarmModel`), so no lifecycle step reaches into them, and a part a model does
not use is simply not told.

Events and the arguments a subscriber gets:

- ``"state"``: ``(robot, old, new)`` after the robot entered state ``new`` (``old`` is None
  when it has just joined);
- ``"failed"``: ``(robot,)`` when a robot fails, after the fault is logged and before its
  state becomes ``failed``: it leaves the air, the comm network and the ledger;
- ``"removed"``: ``(robot,)`` when a robot is taken out of the model, before it leaves Mesa's
  space: likewise, and the fault injector forgets it.

Subscribers run in the order they subscribed.
"""

from collections.abc import Callable
from typing import Any

from abm.errors import ConfigError

__all__ = ["EVENTS", "Lifecycle"]

#: The lifecycle events, in the order a robot meets them.
EVENTS = ("state", "failed", "removed")


class Lifecycle:
    """Subscribers per lifecycle event, told in the order they subscribed."""

    def __init__(self) -> None:
        self._subscribers: dict[str, list[Callable[..., None]]] = {e: [] for e in EVENTS}

    def subscribe(self, event: str, callback: Callable[..., None]) -> None:
        """Call ``callback`` with the event's arguments (module docstring) each time it happens.

        Raises:
            ConfigError: ``event`` is not one of :data:`EVENTS`.

        """
        if event not in self._subscribers:
            raise ConfigError(f"unknown lifecycle event {event!r}; events are {EVENTS}")
        self._subscribers[event].append(callback)

    def subscribers(self, event: str) -> tuple[Callable[..., None], ...]:
        """Who hears ``event``, in the order they are told."""
        return tuple(self._subscribers[event])

    def publish(self, event: str, *args: Any) -> None:
        """Tell the subscribers of ``event``."""
        for callback in self._subscribers[event]:
            callback(*args)
