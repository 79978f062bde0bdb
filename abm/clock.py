"""Plain callbacks on the SimPy clock, at a fraction of a timeout's cost.

A large beacon network schedules millions of events that nothing yields on or inspects: a
broadcast arriving, a beacon's next control step. ``env.timeout(delay).callbacks.append(f)``
builds a full :class:`simpy.Timeout` for each; :func:`call_later` puts a two-slot event in
SimPy's queue instead. It takes its place in the queue exactly as the timeout would (same time
``now + delay``, same priority, the next number of the same counter), so events run in the same
order whichever of the two scheduled them.
"""

from collections.abc import Callable
from heapq import heappush

import simpy
from simpy.events import NORMAL

__all__ = ["call_later"]


class _Call:
    """An already triggered event with callbacks (what :meth:`simpy.Environment.step` reads)."""

    __slots__ = ("callbacks", "value")
    _ok = True  # it never fails

    def __init__(self, callback: Callable[["_Call"], None], value: object) -> None:
        self.callbacks: list[Callable[[_Call], None]] | None = [callback]
        self.value = value


def call_later(
    env: simpy.Environment, delay: float, callback: Callable[[_Call], None], value: object = None
) -> None:
    """Run ``callback(event)`` ``delay`` seconds from now (``event.value`` is ``value``), in
    the same order as ``env.timeout(delay, value).callbacks.append(callback)`` would.

    Raises:
        ValueError: ``delay`` is negative.

    """
    if delay < 0:
        raise ValueError(f"negative delay {delay}")
    heappush(env._queue, (env._now + delay, NORMAL, next(env._eid), _Call(callback, value)))
