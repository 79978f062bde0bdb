"""The deployment: the real swarm flies the best particle's realised transitions, and what the
survivors do when an MAV fails on the way (our reading; Saska et al. 2016 plan the deployment,
Sect. 5, and hand it to the MAVs' controllers, Sect. 6, but say nothing of a failure during it
beyond "the operator can still obtain data ... in a case of a single MAV failure", Sect. 1).

A leg is one transition flown by the MAVs still alive: their paths, and how far each follows its
path before the feasibility check stops it. As in the optimisation (:func:`follow`), the MAVs of
a leg move together: every MAV covers the same share of its planned path per tick, so after
``elapsed`` seconds an MAV is ``elapsed * speed * total_i / longest`` along its path (the longest
path flown at ``speed``), never beyond where the check stopped it.

When an MAV fails, the survivors stop where they are, then fly on to their own planned ends of
the current transition and of every later one: each leg is planned again from where they are
(visibility-graph paths with goal swapping, or straight lines) and checked with the survivors
alone, so a survivor whose localisation depended on the lost MAV is stopped by the same rule
that stops it during the optimisation.
"""

from dataclasses import dataclass

import numpy as np

from abm.visibility_graph import VisibilityPlanner
from models.tangible_pso.feasibility import follow
from models.tangible_pso.transition import plan_paths

__all__ = ["Leg", "checked_leg", "replanned_leg"]


@dataclass(frozen=True)
class Leg:
    """One transition flown by the MAVs alive.

    Attributes:
        start: ``(m, 3)`` where they start (m).
        points: ``(m, w, 3)`` each one's path waypoints (m).
        count: ``(m,)`` waypoints in use.
        travelled: ``(m,)`` how far each follows its path (m).
        end: ``(m, 3)`` where they end (m).
        speed: the speed of the longest path (m/s).

    """

    start: np.ndarray
    points: np.ndarray
    count: np.ndarray
    travelled: np.ndarray
    end: np.ndarray
    speed: float

    @property
    def duration(self) -> float:
        """How long the leg takes (s): the longest realised path at ``speed``."""
        return float(self.travelled.max(initial=0.0)) / self.speed

    def positions(self, elapsed: float) -> np.ndarray:
        """Where every MAV is ``elapsed`` seconds into the leg, ``(m, 3)`` (m)."""
        out = np.empty_like(self.start)
        totals = [_length(self.points[i, : max(int(c), 1)]) for i, c in enumerate(self.count)]
        longest = max(totals, default=0.0)
        for i, total in enumerate(totals):  # the few MAVs of one swarm
            if total <= 0.0:
                out[i] = self.start[i]
                continue
            arc = min(elapsed * self.speed * total / longest, float(self.travelled[i]))
            out[i] = _point_at(self.points[i, : int(self.count[i])], arc)
        return out


def replanned_leg(
    start: np.ndarray,
    goal: np.ndarray,
    planner: VisibilityPlanner | None,
    zones: tuple[np.ndarray, np.ndarray],
    k: int,
    d_min: float,
    loc_range: float,
    speed: float,
    dt: float,
    swarm_rule: bool,
) -> Leg:
    """The survivors' leg from ``start`` to ``goal`` (``(m, 3)``): paths planned as in the
    optimisation and followed under the feasibility check with ``k`` required neighbours.
    """
    plans = plan_paths(planner, start[None], goal[None], d_min)
    return checked_leg(
        start, plans.points[0], plans.count[0], zones, k, d_min, loc_range, speed, dt, swarm_rule
    )


def checked_leg(
    start: np.ndarray,
    points: np.ndarray,
    count: np.ndarray,
    zones: tuple[np.ndarray, np.ndarray],
    k: int,
    d_min: float,
    loc_range: float,
    speed: float,
    dt: float,
    swarm_rule: bool,
) -> Leg:
    """The leg along planned paths ``points`` (``(m, w, 3)``, ``count`` waypoints each) from
    ``start`` (``(m, 3)``), followed under the feasibility check with ``k`` required
    neighbours: each MAV stops where a constraint would break.
    """
    end, _outcome, travelled = follow(
        start[None], points[None], count[None], zones[0], zones[1], k, d_min, loc_range,
        speed * dt, swarm_rule,
    )  # fmt: skip
    return Leg(start, points, count, travelled[0], end[0], speed)


def _length(points: np.ndarray) -> float:
    return float(np.linalg.norm(np.diff(points, axis=0), axis=-1).sum()) if len(points) > 1 else 0.0


def _point_at(points: np.ndarray, arc: float) -> np.ndarray:
    """The point at arc length ``arc`` along a polyline (clamped to its end)."""
    seg = np.linalg.norm(np.diff(points, axis=0), axis=-1)
    cum = np.concatenate([[0.0], np.cumsum(seg)])
    return np.array([np.interp(arc, cum, points[:, d]) for d in range(points.shape[1])])
