"""Plain callbacks on the SimPy clock, at a fraction of a timeout's cost, and a clock that
knows which event it scheduled last.

A large beacon network schedules millions of events that nothing yields on or inspects: a
broadcast arriving, a beacon's next control step. ``env.timeout(delay).callbacks.append(f)``
builds a full :class:`simpy.Timeout` for each; :func:`call_later` puts a two-slot event in
SimPy's queue instead. It takes its place in the queue exactly as the timeout would (same time
``now + delay``, same priority, the next number of the same counter), so events run in the same
order whichever of the two scheduled them.

Events due at the same instant run in the order they were scheduled. So when an event is the
last one a :class:`Clock` scheduled, work added to it now runs exactly when it would have run
as an event of its own scheduled now, after it: the comm network gathers a flood's broadcasts
that way (one event per instant instead of one per broadcast).
"""

from collections.abc import Callable
from heapq import heappush

import simpy
from simpy.events import NORMAL

__all__ = ["Clock", "call_again_now", "call_later", "urgent_now"]


class _Call:
    """An already triggered event with callbacks (what :meth:`simpy.Environment.step` reads)."""

    __slots__ = ("callbacks", "value", "eid")
    _ok = True  # it never fails

    def __init__(self, callback: Callable[["_Call"], None], value: object, eid: int) -> None:
        self.callbacks: list[Callable[[_Call], None]] | None = [callback]
        self.value = value
        self.eid = eid  # its place among events due at the same instant


class Clock(simpy.Environment):
    """A SimPy environment that records the event it scheduled last (``last_scheduled``),
    whether through SimPy (timeouts, processes, ``succeed``) or :func:`call_later`.
    """

    def __init__(self, initial_time: float = 0) -> None:
        super().__init__(initial_time)
        self.last_scheduled: object = None

    def schedule(self, event: simpy.Event, priority: int = NORMAL, delay: float = 0) -> None:
        """Schedule ``event`` as SimPy does, and remember it as the last one scheduled."""
        self.last_scheduled = event
        heappush(self._queue, (self._now + delay, priority, next(self._eid), event))


def call_later(
    env: simpy.Environment, delay: float, callback: Callable[[_Call], None], value: object = None
) -> _Call:
    """Run ``callback(event)`` ``delay`` seconds from now (``event.value`` is ``value``), in
    the same order as ``env.timeout(delay, value).callbacks.append(callback)`` would.

    Returns the scheduled event, also recorded as ``env.last_scheduled`` (meaningful on a
    :class:`Clock`, which records every event it schedules).

    Raises:
        ValueError: ``delay`` is negative.

    """
    if delay < 0:
        raise ValueError(f"negative delay {delay}")
    call = _Call(callback, value, next(env._eid))
    heappush(env._queue, (env._now + delay, NORMAL, call.eid, call))
    env.last_scheduled = call
    return call


def urgent_now(env: simpy.Environment) -> bool:
    """True if an event more urgent than a normal one (a process starting or interrupted) is
    due at this instant: it runs before any normal event still due now.
    """
    queue = env._queue
    return bool(queue) and queue[0][1] < NORMAL and queue[0][0] == env._now


def call_again_now(
    env: simpy.Environment, call: _Call, callback: Callable[[_Call], None], value: object
) -> None:
    """Run ``callback`` on ``call`` (the event running now, with ``value`` as its value) again
    at this instant in the place the event had: after the urgent events due now, before every
    normal event scheduled after it (the rest of a group of work that an urgent event
    interrupts).
    """
    call.callbacks = [callback]
    call.value = value
    heappush(env._queue, (env._now, NORMAL, call.eid, call))
