"""An MAV controller with tracking error in the feasibility check (Saska et al. 2016, Sect. 6,
Fig. 12: the MAV reaches the position the PSO proposed "smoothly", "but the overshoots in the
position behind the coordinates ... have to be considered in the PSO planning. Mainly the
obstacle avoidance ability of the system is influenced by this position error").

The paper's controller (a geometric tracking controller, its ref. [40]) and its gains are not
published; ours is a second-order follower of the planned path, the same in x, y and z. The
reference r(t) moves along the path as the exact follower does (the longest path at the flight
speed, every MAV the same share of its own path per tick); the MAV's error e = x - r obeys

    e'' = -omega^2 e - 2 zeta omega e' - r'' + w,

with natural frequency omega, damping ratio zeta and white acceleration noise w of intensity
sigma (m s^-1.5): when the reference turns a corner or starts or stops, its velocity jumps and
the MAV lags, then overshoots (zeta < 1). Integrated per tick dt (semi-implicit Euler). After
the reference reaches its end the MAV settles for ``settle`` more ticks, so the overshoot past
the goal of Fig. 12 is flown too.

The feasibility check is the exact follower's, on the MAV's actual positions: an MAV whose next
position lies in a no-fly zone stops where it is (a collision with the zone, outcome 2, the
paper's "collision with obstacles due to the deviation from the followed path", Sect. 5); the
swarm constraints stop MAVs by the stop rule. A stopped MAV hovers where it stopped.
"""

import numba
import numpy as np

from abm.polygons import inside_padded
from models.tangible_pso.feasibility import _copy, _lengths, _point_at, _stop

__all__ = ["follow_tracked", "settle_ticks", "track"]


def settle_ticks(omega: float, zeta: float, dt: float) -> int:
    """Ticks the MAV keeps flying after its reference stopped: the 2 % settling time of the
    error's envelope, 4 / (zeta omega) s.
    """
    return int(np.ceil(4.0 / (zeta * omega) / dt))


@numba.njit(cache=True)
def _tick(e, ev, ref_jump, kick, kp, kd, dt):
    """One tick of the error dynamics of one MAV (in place): the reference's velocity change
    ``ref_jump`` (m/s) enters the error's rate, then the spring, the damper and the noise
    velocity ``kick`` (m/s) act for ``dt``.
    """
    for c in range(3):
        ev[c] += -ref_jump[c] + (-kp * e[c] - kd * ev[c]) * dt + kick[c]
        e[c] += ev[c] * dt


@numba.njit(cache=True)
def track(ref, kp, kd, dt, kicks):
    """The actual positions ``(S, 3)`` of an MAV following the reference positions ``ref``
    ``(S, 3)`` (one per tick, the first the start, where it hovers at rest), with the noise
    velocities ``kicks`` ``(S, 3)`` (m/s per tick; the first unused).
    """
    out = np.empty_like(ref)
    e = np.zeros(3)
    ev = np.zeros(3)
    refv = np.zeros(3)
    jump = np.empty(3)
    out[0] = ref[0]
    for s in range(1, ref.shape[0]):
        for c in range(3):
            v = (ref[s, c] - ref[s - 1, c]) / dt
            jump[c] = v - refv[c]
            refv[c] = v
        _tick(e, ev, jump, kicks[s], kp, kd, dt)
        for c in range(3):
            out[s, c] = ref[s, c] + e[c]
    return out


@numba.njit(cache=True)
def follow_tracked(
    start, points, count, zones, zone_len, k, d_min, loc_range, step, swarm_rule, kp, kd, dt,
    settle, kicks,
):  # fmt: skip
    """The feasibility check with the second-order follower (see the module).

    Args:
        start: ``(P, n, 3)`` positions p_j(t-1) (feasible).
        points: ``(P, n, w, 3)`` each MAV's path waypoints (m).
        count: ``(P, n)`` waypoints in use.
        zones: ``(Z, v, 2)`` grown no-fly zones (padded vertex arrays).
        zone_len: ``(Z,)`` vertices in use per zone.
        k: required localised neighbours.
        d_min: minimum distance between MAVs (m).
        loc_range: maximal localisation distance (m).
        step: the reference's longest move of one tick (m).
        swarm_rule: True: the whole swarm stops at the first broken tick.
        kp: omega^2 (1/s^2).
        kd: 2 zeta omega (1/s).
        dt: the tick (s).
        settle: ticks flown after the reference reached its end.
        kicks: ``(P, n, S, 3)`` noise velocities per tick (m/s), S >= every swarm's ticks.

    Returns:
        The realised positions ``(P, n, 3)``, each MAV's outcome ``(P, n)`` (an index of
        :data:`~models.tangible_pso.feasibility.OUTCOMES`), the length of the reference each
        followed ``(P, n)`` (m), the ticks each swarm flew ``(P,)`` and each MAV's largest
        distance from its reference ``(P, n)`` (m).

    """
    n_p, n, w = points.shape[0], points.shape[1], points.shape[2]
    out = start.copy()
    outcome = np.zeros((n_p, n), dtype=np.int8)
    travelled = np.zeros((n_p, n))
    ticks = np.zeros(n_p, dtype=np.int64)
    worst = np.zeros((n_p, n))
    cum = np.empty((n, w))
    total = np.empty(n)
    reached = np.empty(n)
    ref = np.empty((n, 3))
    new_ref = np.empty(3)
    refv = np.empty((n, 3))
    jump = np.empty(3)
    e = np.empty((n, 3))
    ev = np.empty((n, 3))
    cand = np.empty((n, 3))
    bad = np.empty(n, dtype=np.bool_)
    active = np.empty(n, dtype=np.bool_)
    for j in range(n_p):
        longest = 0.0
        for i in range(n):
            total[i] = _lengths(points[j, i], count[j, i], cum[i])
            longest = max(longest, total[i])
            active[i] = True
            reached[i] = 0.0
            _copy(start[j, i], ref[i])
            for c in range(3):
                refv[i, c] = 0.0
                e[i, c] = 0.0
                ev[i, c] = 0.0
        steps = int(np.ceil(longest / step)) if longest > 0.0 else 0
        cur = out[j]
        s = 0
        while s < steps + settle:
            s += 1
            frac = min(1.0, s / steps) if steps else 1.0
            for i in range(n):
                if not active[i]:
                    _copy(cur[i], cand[i])
                    continue
                if total[i] > 0.0:
                    _point_at(points[j, i], count[j, i], cum[i], frac * total[i], new_ref)
                else:
                    _copy(ref[i], new_ref)
                for c in range(3):
                    v = (new_ref[c] - ref[i, c]) / dt
                    jump[c] = v - refv[i, c]
                    refv[i, c] = v
                    ref[i, c] = new_ref[c]
                _tick(e[i], ev[i], jump, kicks[j, i, s - 1], kp, kd, dt)
                for c in range(3):
                    cand[i, c] = ref[i, c] + e[i, c]
                if zone_len.shape[0] and inside_padded(cand[i, 0], cand[i, 1], zones, zone_len):
                    _copy(cur[i], cand[i])
                    active[i] = False
                    outcome[j, i] = 2
            if _stop(cur, cand, active, outcome[j], bad, k, d_min, loc_range, swarm_rule):
                break
            any_active = False
            for i in range(n):
                _copy(cand[i], cur[i])
                if active[i]:
                    reached[i] = frac
                    any_active = True
                    gap = np.sqrt(e[i, 0] ** 2 + e[i, 1] ** 2 + e[i, 2] ** 2)
                    worst[j, i] = max(worst[j, i], gap)
            ticks[j] = s
            if not any_active:
                break
        for i in range(n):
            travelled[j, i] = reached[i] * total[i]
    return out, outcome, travelled, ticks, worst
