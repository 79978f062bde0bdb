"""A deployment plan flown to its end with nothing to stop it: what Fig. 10 of Saska et al.
(2016) shows for the state-space search's solution ("the solution does not guarantee that the
direct visibility is kept during the movement (it is violated in b, c, d)", Sect. 7.1).

The MAVs of one transition move together as in the feasibility check
(:func:`~models.tangible_pso.feasibility.follow`): the longest path advances ``step`` per tick
and every MAV covers the same share of its own path, up to its planned reach. At every tick the
swarm is checked, but nobody stops: the result is which constraints the plan itself breaks on
the way. Tangible PSO's plan is the best particle's realised transitions, each state already
checked, so it breaks none; the state-space search's plan is one leg from the depot to its
solution, planned by the same visibility graph with goal swapping and never checked.
"""

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from abm.polygons import inside_any

__all__ = ["OpenLoop", "fly_open_loop"]


@dataclass(frozen=True)
class OpenLoop:
    """What a plan broke on the way, counted in ticks of the flight.

    Attributes:
        ticks: the flight's ticks (its states, the start of each transition included).
        unlocalised: ticks at which some MAV localised fewer than k neighbours (a neighbour
            at a distance in [d_min, loc_range]).
        collided: ticks at which two MAVs were closer than d_min or one was inside a (grown)
            no-fly zone.
        unlocalised_time: flight time with the localisation broken (s): the unlocalised
            ticks times the duration of a tick of their transition (at most dt).

    """

    ticks: int
    unlocalised: int
    collided: int
    unlocalised_time: float


def _states(
    start: np.ndarray, points: np.ndarray, count: np.ndarray, reach: np.ndarray | None, step: float
):
    """Every MAV's position at every tick of one transition, ``(S, m, 3)``, and the length
    the longest path moves per tick (m; at most ``step``, 0 when nothing moves). An MAV
    whose path has no length stays at its start, as in the feasibility check (a path
    with no planar length holds the goal's altitude only).
    """
    m = len(points)
    cum = np.zeros((m, points.shape[1]))
    for i in range(m):  # the few MAVs of one swarm
        c = max(int(count[i]), 1)
        seg = np.linalg.norm(np.diff(points[i, :c], axis=0), axis=-1)
        cum[i, 1:c] = np.cumsum(seg)
        cum[i, c:] = cum[i, c - 1]
    total = cum[np.arange(m), np.maximum(count, 1) - 1]
    longest = float(total.max(initial=0.0))
    steps = int(np.ceil(longest / step)) if longest > 0.0 else 0
    frac = np.arange(steps + 1) / max(steps, 1)
    limit = total if reach is None else np.minimum(reach, total)
    arc = np.minimum(frac[:, None] * total[None, :], limit[None, :])  # (S, m)
    out = np.empty((len(frac), m, 3))
    for i in range(m):
        c = max(int(count[i]), 1)
        for d in range(3):
            if total[i] <= 0.0:
                out[:, i, d] = start[i, d]
            else:
                out[:, i, d] = np.interp(arc[:, i], cum[i, :c], points[i, :c, d])
    return out, (longest / steps if steps else 0.0)


def fly_open_loop(
    legs: Sequence[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray | None]],
    zones: Sequence[np.ndarray],
    k: int,
    d_min: float,
    loc_range: float,
    speed: float,
    dt: float,
) -> OpenLoop:
    """Fly every transition of a plan to its end and count the ticks that break a constraint.

    Args:
        legs: per transition, where each MAV starts ``(m, 3)`` (m), its path waypoints
            ``(m, w, 3)`` (m), the waypoints in use ``(m,)`` and how far it flies along its
            path ``(m,)`` (m; None: to its end).
        zones: the no-fly zones grown by the MAV radius.
        k: required localised neighbours.
        d_min: minimum distance between MAVs (m).
        loc_range: maximal localisation distance (m).
        speed: flight speed of the longest path (m/s).
        dt: the tick (s): the longest path moves ``speed * dt`` per tick.

    """
    ticks = unlocalised = collided = 0
    unlocalised_time = 0.0
    for start, points, count, reach in legs:
        states, per_tick = _states(start, points, count, reach, speed * dt)
        n = states.shape[1]
        d = np.linalg.norm(states[:, :, None] - states[:, None], axis=-1)
        off = ~np.eye(n, dtype=bool)
        near = ((d >= d_min) & (d <= loc_range) & off).sum(axis=-1)
        lost = (near < k).any(axis=-1)
        hit = ((d < d_min) & off).any(axis=(-1, -2))
        if len(zones):
            hit |= inside_any(states[..., :2], list(zones)).any(axis=-1)
        ticks += len(states)
        unlocalised += int(lost.sum())
        collided += int(hit.sum())
        unlocalised_time += float(lost.sum()) * per_tick / speed
    return OpenLoop(ticks, unlocalised, collided, unlocalised_time)
