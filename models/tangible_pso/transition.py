"""Steps 2-3 of a tangible transition (Saska et al. 2016, Sect. 5, Figs. 5-6), for every
virtual swarm at once: shift the proposed positions out of trouble, then plan each MAV's path
(a visibility-graph path around the no-fly zones, with goal swapping on mutual collisions, or
the straight line of the variant without motion planning).
"""

from dataclasses import dataclass

import numpy as np

from abm.polygons import push_outside
from abm.visibility_graph import VisibilityPlanner
from models.tangible_pso.feasibility import path_conflicts

__all__ = ["Plans", "plan_paths", "shift_proposals"]

#: Common fractions of the transition at which two paths are compared for a mutual collision.
SWAP_SAMPLES = 41


def shift_proposals(
    proposal: np.ndarray,
    zones: list[np.ndarray],
    low: np.ndarray,
    high: np.ndarray,
    d_min: float,
    rounds: int = 3,
) -> tuple[np.ndarray, np.ndarray]:
    """Step 2 (Fig. 5a): proposed positions outside the operational area are clipped into it,
    positions in a (grown) no-fly zone moved to its nearest border, and MAVs of one swarm
    closer than ``d_min`` pushed apart along the line between them.

    Args:
        proposal: ``(P, n, 3)`` proposed positions p_j(t) (m).
        zones: the grown no-fly zones.
        low: the area's lower corner (x, y, z) (m).
        high: the area's upper corner (m).
        d_min: minimum distance between MAVs (m).
        rounds: passes of the push-apart (each may create a new close pair).

    Returns:
        The shifted positions p'_j(t) and ``(P, n)``: which proposals lay in a zone.

    """
    p = np.clip(proposal, low, high)
    xy, in_zone = push_outside(p[..., :2], zones)
    p[..., :2] = xy
    n = p.shape[1]
    if n > 1:
        a, b = np.triu_indices(n, 1)
        for _ in range(rounds):
            gap = p[:, b] - p[:, a]
            dist = np.linalg.norm(gap, axis=-1)
            close = dist < d_min
            if not close.any():
                break
            unit = np.where(
                dist[..., None] > 1e-9, gap / np.maximum(dist, 1e-9)[..., None], [1, 0, 0]
            )
            push = np.where(close, (d_min * (1 + 1e-6) - dist) / 2, 0.0)[..., None] * unit
            np.add.at(p, (slice(None), a), -push)
            np.add.at(p, (slice(None), b), push)
            p = np.clip(p, low, high)
            xy, moved = push_outside(p[..., :2], zones)
            p[..., :2] = xy
            in_zone |= moved
    return p, in_zone


@dataclass(frozen=True)
class Plans:
    """Every MAV's path of one transition.

    Attributes:
        points: ``(P, n, w, 3)`` waypoints (m), from the start to the (possibly swapped) goal.
        count: ``(P, n)`` waypoints in use (1: no path, the MAV stays).
        conflicts: mutual path collisions found before swapping.
        resolved: of those, the ones goal swapping removed.

    """

    points: np.ndarray
    count: np.ndarray
    conflicts: int
    resolved: int


def _paths_3d(planner: VisibilityPlanner | None, start: np.ndarray, goal: np.ndarray):
    """Paths ``(q, w, 3)`` from ``start`` to ``goal`` (``(q, 3)``): planar routes around the
    zones with the altitude changing linearly along them; straight lines without a planner.
    """
    if planner is None:
        return np.stack([start, goal], axis=1), np.full(len(start), 2, dtype=np.int64)
    paths = planner.plan(start[:, :2], goal[:, :2])
    pts = paths.points
    seg = np.linalg.norm(np.diff(pts, axis=1), axis=-1)
    cum = np.concatenate([np.zeros((len(pts), 1)), np.cumsum(seg, axis=1)], axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        frac = np.where(cum[:, -1:] > 0, cum / cum[:, -1:], 1.0)
    z = start[:, 2:3] + frac * (goal[:, 2:3] - start[:, 2:3])
    stay = paths.count == 1
    z[stay] = start[stay, 2:3]
    return np.concatenate([pts, z[..., None]], axis=-1), paths.count


def _conflicts(points: np.ndarray, count: np.ndarray, d_min: float) -> np.ndarray:
    """``(P, pairs)``: which pairs of a swarm's synchronised paths come closer than d_min."""
    return path_conflicts(
        np.ascontiguousarray(points), np.ascontiguousarray(count), SWAP_SAMPLES, d_min
    )


def plan_paths(
    planner: VisibilityPlanner | None, start: np.ndarray, goal: np.ndarray, d_min: float
) -> Plans:
    """Step 3 (Fig. 5b): every MAV's path from ``start`` to ``goal`` (``(P, n, 3)``).

    With a planner, pairs whose paths collide swap their goals (the MAVs are interchangeable),
    each MAV at most once per transition, and are planned again; collisions left after the swap
    are left to the feasibility check, which stops the MAVs before them (the paper shifts the
    target "to a sufficient distance before" the collision, Sect. 5). Without a planner the
    paths are straight lines and nothing is swapped.
    """
    n_p, n, _ = start.shape
    flat_s, flat_g = start.reshape(-1, 3), goal.reshape(-1, 3)
    pts, cnt = _paths_3d(planner, flat_s, flat_g)
    points, count = pts.reshape(n_p, n, *pts.shape[1:]), cnt.reshape(n_p, n)
    if planner is None or n < 2:
        return Plans(points, count, 0, 0)
    clash = _conflicts(points, count, d_min)
    conflicts = int(clash.sum())
    if not conflicts:
        return Plans(points, count, 0, 0)
    a, b = np.triu_indices(n, 1)
    goal = goal.copy()
    swapped = np.zeros((n_p, n), dtype=bool)
    for pair in range(len(a)):
        rows = np.nonzero(clash[:, pair] & ~swapped[:, a[pair]] & ~swapped[:, b[pair]])[0]
        goal[rows, a[pair]], goal[rows, b[pair]] = goal[rows, b[pair]], goal[rows, a[pair]].copy()
        swapped[rows, a[pair]] = swapped[rows, b[pair]] = True
    redo = np.nonzero(swapped.reshape(-1))[0]
    pts2, cnt2 = _paths_3d(planner, flat_s[redo], goal.reshape(-1, 3)[redo])
    width = max(points.shape[2], pts2.shape[1])
    flat_p = _pad(points.reshape(n_p * n, *points.shape[2:]), width)
    flat_p[redo] = _pad(pts2, width)
    flat_c = count.reshape(-1).copy()
    flat_c[redo] = cnt2
    points, count = flat_p.reshape(n_p, n, width, 3), flat_c.reshape(n_p, n)
    left = _conflicts(points, count, d_min) & clash
    return Plans(points, count, conflicts, conflicts - int(left.sum()))


def _pad(points: np.ndarray, width: int) -> np.ndarray:
    """Paths padded to ``width`` waypoints by repeating the last."""
    if points.shape[1] >= width:
        return points.copy()
    extra = np.repeat(points[:, -1:], width - points.shape[1], axis=1)
    return np.concatenate([points, extra], axis=1)
