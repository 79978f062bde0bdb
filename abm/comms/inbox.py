"""A member's inbox: the messages a SimPy process takes one at a time, in arrival order.

:class:`Inbox` is ``simpy.Store`` (unbounded) for a process that only ever ``yield``s
``inbox.get()`` and never waits on a ``put``: it schedules the very same events in the same
order (so a model's event sequence, and every seeded result, is unchanged), without the
Store's generic machinery (bound event classes, put and get queues re-scanned on every call).
A message-driven model hands over tens of thousands of messages a run, each one put and one
get.

What it keeps of ``simpy.Store``, event for event:

- ``put(item)`` files the item at once and takes one place among the events (a plain call,
  where the Store schedules its put event); at that place the oldest waiting ``get`` (if any)
  takes the oldest item.
- ``get()`` returns an event; it is triggered at once if it is the only waiting ``get`` and
  an item is filed, else it waits in line.
- A ``get`` whose process was interrupted stays in line and takes an item, as in SimPy.
"""

from collections import deque
from typing import Any

import simpy
from simpy.events import Event

from abm.clock import scheduler


class Inbox:
    """An unbounded FIFO of items for SimPy processes, ordered exactly as ``simpy.Store``.

    Args:
        env: the SimPy environment.

    Attributes:
        items: the items filed and not yet taken, oldest first.

    """

    def __init__(self, env: simpy.Environment) -> None:
        self.env = env
        self.items: list[Any] = []
        self._waiting: deque[Event] = deque()
        self._call_later = scheduler(env)

    def put(self, item: Any) -> None:
        """File ``item`` now. The put's turn among the events (where ``Store.put`` schedules
        its put event) serves the oldest waiting get; nothing waits on a put of an unbounded
        inbox, so the turn is a plain call on the clock (:func:`~abm.clock.call_later`), not
        an event of its own.
        """
        self.items.append(item)
        self._call_later(0, self._serve)

    def get(self) -> Event:
        """An event whose value is the oldest item, triggered once it is this one's turn."""
        get = Event(self.env)
        self._waiting.append(get)
        self._serve(None)
        return get

    def _serve(self, _event: Event | None) -> None:
        """Hand the oldest item to the oldest waiting get, if both exist (SimPy serves at most
        one get per call: ``Store._do_get`` returns None, which stops its loop).
        """
        if self._waiting and self.items:
            self._waiting.popleft().succeed(self.items.pop(0))
