"""Compiled (numba) kernels for the grid geometry the arena, the physics and controllers share.

A 20-robot run calls these queries a dozen times per 0.1 s tick on arrays of a few rows, where
numpy's per-call overhead dominates; compiled loops over the rows make a tick tens of times
cheaper. Every kernel works on the arena's precomputed arrays:

- ``padded``: the free grid with a one-cell ring of wall, ``padded[iy + 1, ix + 1]``;
- ``runs[iy, ix, d]``: free cells beyond a cell in direction d (N, E, S, W);
- ``sat``: summed-area table of wall cells, ``sat[iy, ix]`` = walls below row iy, left of ix.

Geometry is exact for grid walls: rays are walked cell boundary by cell boundary
(Amanatides-Woo), bodies are stopped flush against walls axis by axis.
"""

import math

import numpy as np
from numba import njit

from abm.neighbours import cell_grid, cell_of
from abm.portable import cos_scalar, sin_scalar

#: Radians per degree, as numpy's ``radians`` multiplies by it.
_RAD = math.pi / 180.0

__all__ = [
    "bump_moves",
    "cardinal_distances",
    "flight_rows",
    "nearest_visible",
    "nearest_visible_on",
    "raycasts",
    "segments_cross",
    "sweep",
    "wall_lengths",
    "within_reach",
]


@njit(cache=True, inline="always")
def _free(padded: np.ndarray, ix: int, iy: int) -> bool:
    """Tell whether cell (ix, iy) is inside the grid and free (anything outside is wall)."""
    r = min(max(iy + 1, 0), padded.shape[0] - 1)
    c = min(max(ix + 1, 0), padded.shape[1] - 1)
    return padded[r, c]


@njit(cache=True, inline="always")
def _first_boundary(origin, direction, cell, res):
    """Along one axis: ray length to the first cell boundary, and between boundaries (inf if
    the ray does not move along this axis).
    """
    if direction == 0.0:
        return math.inf, math.inf
    inv = 1.0 / abs(direction)
    edge = (cell + 1) * res - origin if direction > 0.0 else origin - cell * res
    return edge * inv, res * inv


@njit(cache=True)
def _raycast(padded, res, ox, oy, dx, dy, max_range):
    """Distance from (ox, oy) along (dx, dy) to the first wall cell, capped at max_range."""
    norm = math.hypot(dx, dy)
    if norm > 0.0:
        dx /= norm
        dy /= norm
    ix = int(math.floor(ox / res))
    iy = int(math.floor(oy / res))
    if not _free(padded, ix, iy):
        return 0.0
    step_x = 1 if dx > 0.0 else -1
    step_y = 1 if dy > 0.0 else -1
    t_max_x, t_delta_x = _first_boundary(ox, dx, ix, res)
    t_max_y, t_delta_y = _first_boundary(oy, dy, iy, res)
    for _ in range(int(math.ceil(max_range / res)) * 2 + 2):
        if t_max_x < t_max_y:
            t_here = t_max_x
            if t_here >= max_range:
                return max_range
            ix += step_x
            t_max_x += t_delta_x
        else:
            t_here = t_max_y
            if t_here >= max_range:
                return max_range
            iy += step_y
            t_max_y += t_delta_y
        if not _free(padded, ix, iy):
            return t_here
    return max_range


@njit(cache=True)
def _no_wall_within(sat, res, ox, oy, reach):
    """Tell whether no wall cell lies within ``reach`` of (ox, oy): the square of cells around
    the disk (one cell wider on every side, against rounding) is inside the grid and holds no
    wall (a summed-area-table lookup). False for a point or reach that is not finite.
    """
    if not (math.isfinite(ox) and math.isfinite(oy) and math.isfinite(reach)) or reach < 0.0:
        return False
    rows = sat.shape[0] - 1
    cols = sat.shape[1] - 1
    lo_x = int(math.floor((ox - reach) / res)) - 1
    hi_x = int(math.floor((ox + reach) / res)) + 1
    lo_y = int(math.floor((oy - reach) / res)) - 1
    hi_y = int(math.floor((oy + reach) / res)) + 1
    if lo_x < 0 or lo_y < 0 or hi_x >= cols or hi_y >= rows:
        return False
    walls = sat[hi_y + 1, hi_x + 1] - sat[lo_y, hi_x + 1] - sat[hi_y + 1, lo_x] + sat[lo_y, lo_x]
    return walls == 0


@njit(cache=True)
def raycasts(padded, sat, res, origins, directions, max_range):
    """Wall distance along each ray ``(n,)``; an origin inside a wall reads 0.

    A ray from an origin with no wall within ``max_range`` (:func:`_no_wall_within`) reads
    ``max_range`` without being walked: the value the walk returns for a miss. A sensor sweep's
    rays share their origin, so its test is made once per run of equal origins.
    """
    n = origins.shape[0]
    out = np.empty(n)
    last_x = math.nan
    last_y = math.nan
    clear = False
    for k in range(n):
        ox = origins[k, 0]
        oy = origins[k, 1]
        if ox != last_x or oy != last_y:
            clear = _no_wall_within(sat, res, ox, oy, max_range)
            last_x = ox
            last_y = oy
        if clear:
            out[k] = max_range
        else:
            out[k] = _raycast(padded, res, ox, oy, directions[k, 0], directions[k, 1], max_range)
    return out


@njit(cache=True)
def sweep(padded, sat, res, ox, oy, directions, max_range):
    """Wall distance along each ray ``(n,)`` from the one origin (ox, oy): a sensor's sweep.
    The same values as :func:`raycasts` with that origin on every row.
    """
    n = directions.shape[0]
    out = np.empty(n)
    if _no_wall_within(sat, res, ox, oy, max_range):
        out[:] = max_range
        return out
    for k in range(n):
        out[k] = _raycast(padded, res, ox, oy, directions[k, 0], directions[k, 1], max_range)
    return out


@njit(cache=True)
def cardinal_distances(padded, runs, res, points, max_range):
    """Distances ``(n, 4)`` to the nearest wall N, E, S and W: edge of own cell + free run."""
    n = points.shape[0]
    out = np.zeros((n, 4))
    for k in range(n):
        x = points[k, 0]
        y = points[k, 1]
        ix = int(math.floor(x / res))
        iy = int(math.floor(y / res))
        if not _free(padded, ix, iy):
            continue
        out[k, 0] = min((iy + 1) * res - y + runs[iy, ix, 0] * res, max_range)
        out[k, 1] = min((ix + 1) * res - x + runs[iy, ix, 1] * res, max_range)
        out[k, 2] = min(y - iy * res + runs[iy, ix, 2] * res, max_range)
        out[k, 3] = min(x - ix * res + runs[iy, ix, 3] * res, max_range)
    return out


@njit(cache=True)
def segment_crosses(padded, sat, res, x0, y0, x1, y1):
    """Tell whether the segment (x0, y0) -> (x1, y1) enters a wall cell anywhere."""
    sx = int(math.floor(x0 / res))
    sy = int(math.floor(y0 / res))
    ex = int(math.floor(x1 / res))
    ey = int(math.floor(y1 / res))
    if not _free(padded, sx, sy) or not _free(padded, ex, ey):
        return True
    # No wall in the rectangle of cells the segment spans: clear without walking it.
    rows = sat.shape[0] - 1
    cols = sat.shape[1] - 1
    lo_x = min(max(min(sx, ex), 0), cols - 1)
    hi_x = min(max(max(sx, ex), 0), cols - 1) + 1
    lo_y = min(max(min(sy, ey), 0), rows - 1)
    hi_y = min(max(max(sy, ey), 0), rows - 1) + 1
    if sat[hi_y, hi_x] - sat[lo_y, hi_x] - sat[hi_y, lo_x] + sat[lo_y, lo_x] == 0:
        return False
    length = math.hypot(x1 - x0, y1 - y0)
    return _raycast(padded, res, x0, y0, x1 - x0, y1 - y0, length + res) < length


@njit(cache=True)
def segments_cross(padded, sat, res, starts, ends):
    """``(n,)`` True where segment ``starts[k] -> ends[k]`` enters a wall cell."""
    n = starts.shape[0]
    out = np.empty(n, dtype=np.bool_)
    for k in range(n):
        out[k] = segment_crosses(
            padded, sat, res, starts[k, 0], starts[k, 1], ends[k, 0], ends[k, 1]
        )
    return out


@njit(cache=True)
def within_reach(padded, sat, res, x, y, points, max_range, shortest, walls_block):
    """``(n,)`` True where ``points[k]`` is within ``max_range`` of ``(x, y)`` (a distance below
    ``shortest`` counts as ``shortest``) and, if ``walls_block``, the segment ``(x, y) ->
    points[k]`` enters no wall cell.

    The distance is ``np.hypot`` of the point minus the origin, as numpy computes it.
    """
    n = points.shape[0]
    out = np.empty(n, dtype=np.bool_)
    for k in range(n):
        px, py = points[k, 0], points[k, 1]
        up = max(np.hypot(px - x, py - y), shortest) <= max_range
        if up and walls_block:
            up = not segment_crosses(padded, sat, res, x, y, px, py)
        out[k] = up
    return out


@njit(cache=True)
def bump_moves(padded, sat, res, positions, heading, distance):
    """The bump model's moves (:func:`abm.kinematics.bump_moves`), row by row: ``positions[k]``
    plus ``distance[k] * (sin, cos)`` of compass ``heading[k]`` (deg), unless that end point's
    cell is not free or the straight path enters a wall cell; then the robot stays.

    Returns:
        ``(positions, blocked)``: new ``(n, 2)`` positions and ``(n,)`` bool.

    """
    n = positions.shape[0]
    out = positions.copy()
    blocked = np.empty(n, dtype=np.bool_)
    for k in range(n):
        rad = heading[k] * _RAD
        x0, y0 = positions[k, 0], positions[k, 1]
        x1 = x0 + distance[k] * sin_scalar(rad)
        y1 = y0 + distance[k] * cos_scalar(rad)
        free = _free(padded, int(math.floor(x1 / res)), int(math.floor(y1 / res)))
        blocked[k] = not free or segment_crosses(padded, sat, res, x0, y0, x1, y1)
        if not blocked[k]:
            out[k, 0], out[k, 1] = x1, y1
    return out, blocked


@njit(cache=True)
def _wall_length(padded, res, x0, y0, x1, y1):
    """Length (m) of the segment (x0, y0) -> (x1, y1) that lies inside wall cells."""
    length = math.hypot(x1 - x0, y1 - y0)
    if length == 0.0:
        return 0.0
    dx = (x1 - x0) / length
    dy = (y1 - y0) / length
    ix = int(math.floor(x0 / res))
    iy = int(math.floor(y0 / res))
    step_x = 1 if dx > 0.0 else -1
    step_y = 1 if dy > 0.0 else -1
    t_max_x, t_delta_x = _first_boundary(x0, dx, ix, res)
    t_max_y, t_delta_y = _first_boundary(y0, dy, iy, res)
    inside = 0.0
    t_here = 0.0
    while t_here < length:
        t_next = min(t_max_x, t_max_y, length)
        if not _free(padded, ix, iy):
            inside += t_next - t_here
        t_here = t_next
        if t_max_x < t_max_y:
            ix += step_x
            t_max_x += t_delta_x
        else:
            iy += step_y
            t_max_y += t_delta_y
    return inside


@njit(cache=True)
def wall_lengths(padded, res, points, targets):
    """``(n, m)``: length (m) of wall cells on the segment from point k to target j."""
    n = points.shape[0]
    m = targets.shape[0]
    out = np.zeros((n, m))
    for k in range(n):
        for j in range(m):
            out[k, j] = _wall_length(
                padded, res, points[k, 0], points[k, 1], targets[j, 0], targets[j, 1]
            )
    return out


@njit(cache=True)
def nearest_visible(padded, sat, res, points, targets, max_range):
    """Row of the nearest target within ``max_range`` and in line of sight per point, or -1.

    Only targets in the cells around a point are measured (:func:`abm.neighbours.cell_grid`),
    so the cost grows with points x targets nearby, not points x all targets.
    """
    if targets.shape[0] == 0:
        return np.full(points.shape[0], -1, dtype=np.int64)
    lo, width, dims, _which, start, order = cell_grid(targets, max_range)
    return nearest_visible_on(
        padded, sat, res, points, targets, max_range, lo, width, dims, start, order
    )


@njit(cache=True)
def nearest_visible_on(padded, sat, res, points, targets, max_range, lo, width, dims, start, order):
    """:func:`nearest_visible` on a grid of the targets built beforehand.

    ``lo, width, dims, start, order`` are those of ``cell_grid(targets, max_range)``: a caller
    whose targets stay put for many calls (an explorer's beacons, tick after tick) builds the
    grid once, which costs more than the search itself when a few robots look for their beacon.
    """
    n = points.shape[0]
    m = targets.shape[0]
    out = np.full(n, -1, dtype=np.int64)
    if m == 0:
        return out
    rows = np.empty(m, dtype=np.int64)
    dist = np.empty(m)
    rank = np.empty(m, dtype=np.int64)
    for k in range(n):
        cx, cy = cell_of(lo, width, points[k, 0], points[k, 1])
        found = 0
        for y in range(max(cy - 1, 0), min(cy + 2, dims[1])):
            for x in range(max(cx - 1, 0), min(cx + 2, dims[0])):
                c = y * dims[0] + x
                for s in range(start[c], start[c + 1]):
                    j = order[s]
                    d = math.hypot(targets[j, 0] - points[k, 0], targets[j, 1] - points[k, 1])
                    if d <= max_range:
                        rows[found] = j
                        dist[found] = d
                        found += 1
        for t in _ascending(dist, found, rank):
            j = rows[t]
            if not segment_crosses(
                padded, sat, res, points[k, 0], points[k, 1], targets[j, 0], targets[j, 1]
            ):
                out[k] = j
                break
    return out


#: Up to this many keys numba's ``np.argsort`` (quicksort) is a plain insertion sort.
_INSERTION_SORT_KEYS = 15


@njit(cache=True)
def _ascending(dist, found, rank):
    """The order ``np.argsort(dist[:found])`` gives, in ``rank`` (reused between calls).

    Numba's argsort sorts up to :data:`_INSERTION_SORT_KEYS` keys by insertion (stable: equal
    keys keep their order), the same loop as here, but builds its index array and its
    partition stack anew on every call: two thirds of a search's time for the handful of
    beacons around an explorer. More keys go to ``np.argsort`` itself, whose partitions may
    order equal keys otherwise. The keys are finite distances (``<`` is numba's float order
    for them).
    """
    if found > _INSERTION_SORT_KEYS:
        return np.argsort(dist[:found])
    for i in range(found):
        key = dist[i]
        j = i
        while j > 0 and key < dist[rank[j - 1]]:
            rank[j] = rank[j - 1]
            j -= 1
        rank[j] = i
    return rank[:found]


@njit(cache=True, inline="always")
def _cap_below(cap):
    """The ``cap2`` argument of :func:`_capped` for a cap."""
    return (cap * (1.0 - 1e-9)) ** 2 if cap >= 1e-12 else -1.0


@njit(cache=True, inline="always")
def _capped(x, y, cap, cap2):
    """Factor that shortens vector (x, y) to length ``cap`` if it is longer (1.0 otherwise).

    ``cap2`` is ``(cap (1 - 1e-9))^2`` (or -1 to always measure): a vector whose squared
    length is below it is certainly shorter than ``cap`` whatever the rounding, so the factor
    is exactly 1.0 without the slower ``hypot``; the result is bit for bit that of
    ``min(1, cap / max(hypot(x, y), 1e-12))``.
    """
    if x * x + y * y <= cap2:
        return 1.0
    return min(1.0, cap / max(math.hypot(x, y), 1e-12))


@njit(cache=True, nogil=True)
def flight_rows(
    pos,
    vel,
    desired,
    noise,
    noise_scale,
    padded,
    res,
    mass,
    tau,
    max_force,
    drag,
    max_speed,
    dt,
    radius,
    contact,
    first,
    last,
):
    """Advance flyers ``first`` to ``last - 1`` one tick in place; ``contact[k]`` tells whether
    body k touches a wall now. Returns the path length these flyers moved (m): each one's
    displacement this tick, after walls stopped it, summed (an odometer, for the distance flown).

    Control force ``m (v_desired - v) / tau`` capped at ``max_force``, quadratic drag
    ``-drag |v| v`` (drag = rho A C_d / 2), speed capped at ``max_speed``, then the displacement
    ``v dt + noise_scale * noise`` (``noise``: standard normal draws) applied one axis at a
    time: a square body of half-width ``radius`` that would enter a wall cell stops flush
    against it and loses that velocity component.

    Rows are independent and the GIL is released, so disjoint row ranges may run on threads
    at once with the same result as one call over all rows.
    """
    force_cap2 = _cap_below(max_force)
    speed_cap2 = _cap_below(max_speed)
    travelled = 0.0
    for k in range(first, last):
        x0 = pos[k, 0]
        y0 = pos[k, 1]
        fx = mass * (desired[k, 0] - vel[k, 0]) / tau
        fy = mass * (desired[k, 1] - vel[k, 1]) / tau
        scale = _capped(fx, fy, max_force, force_cap2)
        speed = math.hypot(vel[k, 0], vel[k, 1])
        fx = fx * scale - drag * speed * vel[k, 0]
        fy = fy * scale - drag * speed * vel[k, 1]
        vel[k, 0] += fx * dt / mass
        vel[k, 1] += fy * dt / mass
        scale = _capped(vel[k, 0], vel[k, 1], max_speed, speed_cap2)
        vel[k, 0] *= scale
        vel[k, 1] *= scale
        touching = False
        for axis in range(2):
            other = 1 - axis
            d = vel[k, axis] * dt + noise_scale * noise[k, axis]
            new = pos[k, axis] + d
            sign = 1.0 if d >= 0.0 else -1.0
            lead = int(math.floor((new + sign * radius) / res))
            lo = int(math.floor((pos[k, other] - radius) / res))
            hi = int(math.floor((pos[k, other] + radius) / res))
            if axis == 0:
                blocked = not _free(padded, lead, lo) or not _free(padded, lead, hi)
            else:
                blocked = not _free(padded, lo, lead) or not _free(padded, hi, lead)
            if blocked and d != 0.0:
                flush = lead * res - radius if sign > 0.0 else (lead + 1) * res + radius
                new = flush - sign * 1e-9
                vel[k, axis] = 0.0
                touching = True
            pos[k, axis] = new
        contact[k] = touching
        travelled += math.hypot(pos[k, 0] - x0, pos[k, 1] - y0)
    return travelled
