"""Plain callbacks on the SimPy clock, gathered into one event per instant where that changes
nothing.

A large beacon network schedules millions of events that nothing yields on or inspects: a
broadcast arriving, a beacon's next control step. ``env.timeout(delay).callbacks.append(f)``
builds a full :class:`simpy.Timeout` for each. :func:`call_later` schedules a plain call
instead, in exactly the place such a timeout would take in SimPy's queue (same time
``now + delay``, same priority, the next number of the same counter), so events run in the same
order whichever of the two scheduled them.

On a :class:`Clock` it does more. Events due at the same instant and priority run in the order
they were scheduled, so a call due at the same time as the event the clock scheduled last would
run right after that event's calls: the clock appends it to them (one event, not one per call).
If a call schedules an urgent event for the same instant (a process starting or interrupted),
which as events of their own would run before the calls after it, the remaining calls go back
to the queue in the group's place. The run is the same event for event; a flood's thousands of
broadcasts per instant cost one event.
"""

from collections.abc import Callable
from heapq import heappush

import simpy
from simpy.core import BoundClass
from simpy.events import NORMAL

__all__ = ["Clock", "call_later", "scheduler"]

Call = Callable[[object], None]


class _Calls:
    """A triggered event that runs plain calls ``callback(value)`` in order (what
    :meth:`simpy.Environment.step` reads: ``callbacks`` and ``_ok``).
    """

    __slots__ = ("callbacks", "calls", "at", "eid")
    _ok = True  # it never fails

    def __init__(self, run: Callable[["_Calls"], None], calls: list, at: float, eid: int) -> None:
        self.callbacks: list[Callable[[_Calls], None]] | None = [run]
        self.calls = calls  # [(callback, value), ...]
        self.at = at
        self.eid = eid  # its place among the events due at the same instant


def _run_alone(event: _Calls) -> None:
    """Run the calls of an event scheduled on a plain SimPy environment."""
    for callback, value in event.calls:
        callback(value)


class Clock(simpy.Environment):
    """A SimPy environment that gathers :func:`call_later` calls due together (see the module).

    It records the event it scheduled last, whether through SimPy (timeouts, processes,
    ``succeed``) or :meth:`call_later`: only calls that would follow that event directly join
    it.
    """

    def __init__(self, initial_time: float = 0) -> None:
        super().__init__(initial_time)
        self._last: object = None
        # SimPy binds its event classes (``timeout``, ``event``, ``process``, ...) to an
        # environment once, but only those of the environment's own class (``bind_early``
        # reads ``type(env).__dict__``), so on this subclass every ``env.timeout`` made a new
        # bound method: bind them here as a plain Environment has them.
        for name, attribute in vars(simpy.Environment).items():
            if type(attribute) is BoundClass:
                setattr(self, name, getattr(self, name))

    def schedule(self, event: simpy.Event, priority: int = NORMAL, delay: float = 0) -> None:
        """Schedule ``event`` as SimPy does, and remember it as the last one scheduled."""
        self._last = event
        heappush(self._queue, (self._now + delay, priority, next(self._eid), event))

    def call_later(self, delay: float, callback: Call, value: object = None) -> None:
        """Run ``callback(value)`` ``delay`` seconds from now (see :func:`call_later`)."""
        if delay < 0:
            raise ValueError(f"negative delay {delay}")
        at = self._now + delay
        last = self._last
        if last.__class__ is _Calls and last.at == at and last.callbacks is not None:
            last.calls.append((callback, value))  # it would run next: run it with them
            return
        event = self._last = _Calls(self._run, [(callback, value)], at, next(self._eid))
        heappush(self._queue, (at, NORMAL, event.eid, event))

    def _run(self, event: _Calls) -> None:
        """Run a group of calls in order; after a call that scheduled an urgent event for now,
        put the rest back in the group's place (as events of their own they would run after it).
        """
        calls = event.calls
        queue = self._queue
        last = len(calls) - 1
        for k, (callback, value) in enumerate(calls):
            callback(value)
            if k < last and queue and queue[0][1] < NORMAL and queue[0][0] == self._now:
                event.calls = calls[k + 1 :]
                event.callbacks = [self._run]
                heappush(queue, (self._now, NORMAL, event.eid, event))
                return


def call_later(env: simpy.Environment, delay: float, callback: Call, value: object = None) -> None:
    """Run ``callback(value)`` ``delay`` seconds from now, in the place in the order of events
    that ``env.timeout(delay).callbacks.append(lambda _event: callback(value))`` would take.

    Raises:
        ValueError: ``delay`` is negative.

    """
    if isinstance(env, Clock):
        env.call_later(delay, callback, value)
        return
    if delay < 0:
        raise ValueError(f"negative delay {delay}")
    at = env._now + delay
    event = _Calls(_run_alone, [(callback, value)], at, next(env._eid))
    heappush(env._queue, (at, NORMAL, event.eid, event))


def scheduler(env: simpy.Environment) -> Callable[[float, Call, object], None]:
    """:func:`call_later` bound to ``env``: ``scheduler(env)(delay, callback, value)`` (on a
    :class:`Clock` its own method, without the dispatch; for code that schedules millions).
    """
    if isinstance(env, Clock):
        return env.call_later
    return lambda delay, callback, value=None: call_later(env, delay, callback, value)
