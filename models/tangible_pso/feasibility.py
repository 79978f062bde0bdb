"""The feasibility check of a transition p_j(t-1) -> p_j(t) (Saska et al. 2016, Sect. 5, step 4),
compiled: every virtual swarm follows its MAVs' paths in small steps and stops where a
constraint would break.

The constraints at every step: no MAV inside a (grown) no-fly zone; no two MAVs closer than
``d_min``; every MAV keeps at least ``k`` neighbours it can localise (an omnidirectional sensor:
a neighbour at a distance in [d_min, loc_range], Sect. 7.1). The MAVs of a swarm move together:
each covers the same fraction of its path per step (our reading of the paper's controller,
which we do not model: a point mass that tracks its path exactly).

Where a step would break a constraint, the reading ``stop_rule`` decides:

- "mav" (default, ours): the MAVs that would break it stop where they are, and so do the
  moving neighbours a stopped MAV would lose; the others go on. If the swarm still breaks a
  constraint, the whole swarm stops at the last feasible step: "the paths are shortened to
  such a position where all constraints are still satisfied" (Sect. 5), per MAV.
- "swarm": the whole swarm stops at the first step that breaks a constraint.

Every realised state is feasible when the start was: a step is only taken once it is checked.
"""

import numba
import numpy as np

from abm.polygons import edge_distance2, inside_padded

__all__ = ["OUTCOMES", "follow", "localised", "path_conflicts"]

#: What the check did to each MAV's path: reached its end, stopped by a swarm constraint,
#: stopped at a no-fly zone.
OUTCOMES = ("free", "stopped", "blocked")


@numba.njit(cache=True, inline="always")
def _dist(a, b):
    """Euclidean distance of two 3-vectors (no temporaries)."""
    x, y, z = a[0] - b[0], a[1] - b[1], a[2] - b[2]
    return np.sqrt(x * x + y * y + z * z)


@numba.njit(cache=True, inline="always")
def _copy(src, dst):
    for c in range(3):
        dst[c] = src[c]


@numba.njit(cache=True)
def _point_at(points, count, cum, dist, out):
    """The point at arc length ``dist`` along a polyline (clamped to its ends)."""
    if count == 1 or dist <= 0.0:
        for c in range(3):
            out[c] = points[0, c]
        return
    for w in range(1, count):
        if dist <= cum[w] or w == count - 1:
            seg = cum[w] - cum[w - 1]
            f = 1.0 if seg <= 0.0 else min(1.0, (dist - cum[w - 1]) / seg)
            for c in range(3):
                out[c] = points[w - 1, c] + f * (points[w, c] - points[w - 1, c])
            return


@numba.njit(cache=True)
def _lengths(points, count, cum):
    cum[0] = 0.0
    for w in range(1, count):
        cum[w] = cum[w - 1] + _dist(points[w], points[w - 1])
    return cum[count - 1] if count > 1 else 0.0


@numba.njit(cache=True)
def path_conflicts(points, count, samples, d_min):
    """``(P, pairs)``: which pairs of MAVs of a swarm (``np.triu_indices`` order) come closer
    than ``d_min`` when they follow their paths together, compared at ``samples`` common
    fractions of the transition.
    """
    n_p, n, w = points.shape[0], points.shape[1], points.shape[2]
    out = np.zeros((n_p, n * (n - 1) // 2), dtype=np.bool_)
    cum = np.empty((n, w))
    total = np.empty(n)
    at = np.empty((n, samples, 3))
    for j in range(n_p):
        for i in range(n):
            total[i] = _lengths(points[j, i], count[j, i], cum[i])
            for s in range(samples):
                _point_at(points[j, i], count[j, i], cum[i], s / (samples - 1) * total[i], at[i, s])
        pair = 0
        for i in range(n):
            for m in range(i + 1, n):
                for s in range(samples):
                    if _dist(at[i, s], at[m, s]) < d_min:
                        out[j, pair] = True
                        break
                pair += 1
    return out


@numba.njit(cache=True)
def _linked(a, b, d_min, loc_range):
    dist = _dist(a, b)
    return d_min <= dist <= loc_range


@numba.njit(cache=True)
def _violations(pos, k, d_min, loc_range, out):
    """Per MAV: True where it is too close to another or localises fewer than k neighbours."""
    n = pos.shape[0]
    any_bad = False
    for i in range(n):
        near = 0
        bad = False
        for j in range(n):
            if i == j:
                continue
            dist = _dist(pos[i], pos[j])
            if dist < d_min:
                bad = True
            elif dist <= loc_range:
                near += 1
        out[i] = bad or near < k
        any_bad = any_bad or out[i]
    return any_bad


@numba.njit(cache=True)
def _zone_gap(x, y, zones, zone_len):
    """Distance (m) from (x, y) to the nearest edge of any zone."""
    best = np.inf
    for z in range(zones.shape[0]):
        best = min(best, edge_distance2(x, y, zones[z], zone_len[z]))
    return np.sqrt(best)


@numba.njit(cache=True)
def _safe_steps(cur, moving, per_step, zones, zone_len, d_min, loc_range):
    """How many ticks ahead no constraint can change: every pair's distance is further from
    d_min and loc_range, and every moving MAV further from a zone's edge, than the ticks can
    move them. Skipping those ticks gives the same result as checking each.
    """
    n = cur.shape[0]
    fastest = 0.0
    for i in range(n):
        if moving[i]:
            fastest = max(fastest, per_step[i])
    if fastest <= 0.0:
        return 1
    slack = np.inf
    for i in range(n):
        for m in range(i + 1, n):
            if not (moving[i] or moving[m]):
                continue
            dist = _dist(cur[i], cur[m])
            rel = (per_step[i] if moving[i] else 0.0) + (per_step[m] if moving[m] else 0.0)
            slack = min(slack, min(abs(dist - d_min), abs(dist - loc_range)) / rel)
        if moving[i] and zone_len.shape[0]:
            slack = min(slack, _zone_gap(cur[i, 0], cur[i, 1], zones, zone_len) / per_step[i])
    if slack > 1e9:
        return 1 << 30
    return max(1, int(slack) - 1)


@numba.njit(cache=True)
def _stop(cur, cand, moving, outcome, bad, k, d_min, loc_range, swarm_rule):
    """Where the next state ``cand`` of one swarm breaks a constraint, stop MAVs by the stop
    rule (in place: ``cand`` rows back to ``cur``, ``moving`` off, ``outcome`` 1). True when
    the whole swarm stops where it is (``cur``).
    """
    n = cur.shape[0]
    if not _violations(cand, k, d_min, loc_range, bad):
        return False
    if swarm_rule:
        for i in range(n):
            if moving[i]:
                moving[i] = False
                outcome[i] = 1
        return True
    for _ in range(n):
        changed = False
        for i in range(n):
            if not bad[i]:
                continue
            # a moving MAV that breaks a constraint stops; a stopped one that breaks it
            # stops the moving neighbours it would lose
            stopped_bad = not moving[i]
            for m in range(n):
                if not moving[m]:
                    continue
                if m == i or (stopped_bad and _linked(cur[i], cur[m], d_min, loc_range)):
                    _copy(cur[m], cand[m])
                    moving[m] = False
                    outcome[m] = 1
                    changed = True
        if not _violations(cand, k, d_min, loc_range, bad) or not changed:
            break
    if _violations(cand, k, d_min, loc_range, bad):
        for i in range(n):
            if moving[i]:
                moving[i] = False
                outcome[i] = 1
        return True
    return False


@numba.njit(cache=True)
def follow(start, points, count, zones, zone_len, k, d_min, loc_range, step, swarm_rule):
    """Follow every virtual swarm's paths and stop where a constraint would break.

    The swarm advances in ticks (its longest path by ``step`` per tick) and is checked after
    each; ticks in which no constraint can change are skipped (same result, fewer checks).

    Args:
        start: ``(P, n, 3)`` positions p_j(t-1) (feasible).
        points: ``(P, n, w, 3)`` each MAV's path waypoints (m), starting at its start.
        count: ``(P, n)`` waypoints in use.
        zones: ``(Z, v, 2)`` grown no-fly zones (padded vertex arrays).
        zone_len: ``(Z,)`` vertices in use per zone.
        k: required localised neighbours.
        d_min: minimum distance between MAVs (m).
        loc_range: maximal localisation distance (m).
        step: the longest move of one tick (m).
        swarm_rule: True: the whole swarm stops at the first broken tick ("swarm").

    Returns:
        The realised positions p''_j(t) ``(P, n, 3)``, each MAV's outcome ``(P, n)`` (an index
        of :data:`OUTCOMES`) and the length of each realised path ``(P, n)`` (m).

    """
    n_p, n, w = points.shape[0], points.shape[1], points.shape[2]
    out = start.copy()
    outcome = np.zeros((n_p, n), dtype=np.int8)
    travelled = np.zeros((n_p, n))
    cum = np.empty((n, w))
    total = np.empty(n)
    per_step = np.empty(n)
    reached = np.empty(n)
    cand = np.empty((n, 3))
    bad = np.empty(n, dtype=np.bool_)
    moving = np.empty(n, dtype=np.bool_)
    for j in range(n_p):
        longest = 0.0
        for i in range(n):
            total[i] = _lengths(points[j, i], count[j, i], cum[i])
            longest = max(longest, total[i])
            moving[i] = total[i] > 0.0
            reached[i] = 0.0
        steps = int(np.ceil(longest / step)) if longest > 0.0 else 0
        for i in range(n):
            per_step[i] = total[i] / steps if steps else 0.0
        cur = out[j]
        s = 0
        while s < steps:
            s = min(
                steps, s + _safe_steps(cur, moving, per_step, zones, zone_len, d_min, loc_range)
            )
            frac = s / steps
            for i in range(n):
                if moving[i]:
                    _point_at(points[j, i], count[j, i], cum[i], frac * total[i], cand[i])
                    if zone_len.shape[0] and inside_padded(cand[i, 0], cand[i, 1], zones, zone_len):
                        _copy(cur[i], cand[i])
                        moving[i] = False
                        outcome[j, i] = 2
                else:
                    _copy(cur[i], cand[i])
            if _stop(cur, cand, moving, outcome[j], bad, k, d_min, loc_range, swarm_rule):
                break
            any_moving = False
            for i in range(n):
                _copy(cand[i], cur[i])
                if moving[i]:
                    reached[i] = frac
                    any_moving = True
            if not any_moving:
                break
        for i in range(n):
            travelled[j, i] = reached[i] * total[i]
    return out, outcome, travelled


def localised(positions: np.ndarray, k: int, d_min: float, loc_range: float) -> np.ndarray:
    """Whether each swarm ``(..., n, 3)`` keeps the constraints: every MAV at least ``d_min``
    from the others and with at least ``k`` neighbours within ``loc_range``.
    """
    p = np.asarray(positions, dtype=float)
    d = np.linalg.norm(p[..., :, None, :] - p[..., None, :, :], axis=-1)
    n = p.shape[-2]
    off = ~np.eye(n, dtype=bool)
    too_close = ((d < d_min) & off).any(axis=-1)
    near = ((d >= d_min) & (d <= loc_range) & off).sum(axis=-1)
    return (~too_close & (near >= k)).all(axis=-1)
