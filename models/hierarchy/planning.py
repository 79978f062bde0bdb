"""Path planning on a director's ProbMap ("Dijkstra's Algorithm", "Path Planning"): drivability,
BFS/Dijkstra, supercover ray trace, path smoothing and the wave generator.

- Drivability (README "Choices": drivability): a cell is drivable if it is known, not blocked, not
  occupied, and no cell within ``padding`` (8-neighbourhood for 1) is known-blocked or occupied.
  Unknown neighbours are allowed; the source cell of a search is always expandable.
- Dijkstra ("Dijkstra's Algorithm"): 4-connected, unit cost, from one source to all cells, so it is
  a BFS; neighbours in the order N, E, S, W decide predecessor ties.
- Supercover (Fig. 31): every cell a segment passes through plus, where it passes exactly through a
  cell corner, both cells beside the corner (Amanatides-Woo with the tie rule).
- Smoothing ("path optimization", Fig. 32): drop a waypoint while the supercover of the segment that
  skips it is drivable (the start cell exempt); first and last points always stay.
- Waves ("Path Planning", Fig. 33): padded path cells, conflict = shared cell, Welsh-Powell greedy
  colouring.

Paths are ``(n, 2)`` arrays of points in metres. The kernels are compiled with numba (house
style of ``abm/gridkernels.py``) because a coverage call runs one BFS per child on a grid of up to
200 x 200 cells and smooths every placed child's path.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import TYPE_CHECKING

import numpy as np
from numba import njit

from abm.portable import cos_scalar, sin_scalar

if TYPE_CHECKING:
    from models.hierarchy.probmap import ProbMap

__all__ = [
    "DistanceField",
    "padded_cells",
    "path_length",
    "shortest_paths",
    "smooth",
    "supercover",
    "wave_order_violations",
    "waves",
]

_EPS = 1e-9
_NO_TARGET = np.zeros((0, 0), dtype=np.bool_)
_DR = np.array([1, 0, -1, 0], dtype=np.int64)
"""Row step of the neighbours N, E, S, W (north = +y = next row)."""
_DC = np.array([0, 1, 0, -1], dtype=np.int64)
"""Column step of the neighbours N, E, S, W."""


# ---------------------------------------------------------------------------- kernels
@njit(cache=True)
def _supercover_cells(x0, y0, x1, y1):
    """Cells ``(k, 2)`` as (col, row) in cell units met by the segment (x0, y0) -> (x1, y1).

    Cell ``(i, j)`` covers ``[i, i+1) x [j, j+1)``. Where the segment crosses a cell corner
    exactly, the two cells beside the corner are listed before the diagonal cell.
    """
    ix = int(math.floor(x0 + _EPS))
    iy = int(math.floor(y0 + _EPS))
    dx = x1 - x0
    dy = y1 - y0
    limit = 3 * (int(abs(dx)) + int(abs(dy)) + 3)
    out = np.empty((limit, 2), dtype=np.int64)
    out[0, 0] = ix
    out[0, 1] = iy
    n = 1
    step_x = 1 if dx > 0 else -1
    step_y = 1 if dy > 0 else -1
    if dx > 0:
        t_max_x = (ix + 1 - x0) / dx
    elif dx < 0:
        t_max_x = (x0 - ix) / -dx
    else:
        t_max_x = math.inf
    if dy > 0:
        t_max_y = (iy + 1 - y0) / dy
    elif dy < 0:
        t_max_y = (y0 - iy) / -dy
    else:
        t_max_y = math.inf
    t_dx = 1.0 / abs(dx) if dx != 0 else math.inf
    t_dy = 1.0 / abs(dy) if dy != 0 else math.inf
    while n + 3 <= limit:
        t = min(t_max_x, t_max_y)
        if t >= 1.0 - _EPS:
            break
        if abs(t_max_x - t_max_y) <= _EPS:
            out[n, 0] = ix + step_x
            out[n, 1] = iy
            out[n + 1, 0] = ix
            out[n + 1, 1] = iy + step_y
            n += 2
            ix += step_x
            iy += step_y
            t_max_x += t_dx
            t_max_y += t_dy
        elif t_max_x < t_max_y:
            ix += step_x
            t_max_x += t_dx
        else:
            iy += step_y
            t_max_y += t_dy
        out[n, 0] = ix
        out[n, 1] = iy
        n += 1
    return out[:n]


@njit(cache=True)
def _bfs(free, goal, sr, sc, n_target):
    """Unit-cost 4-connected search from local cell (sr, sc) over the drivable cells.

    ``free`` and ``goal`` are framed grids (one ring of False around the map, so neighbours need
    no bounds checks): ``free[r + 1, c + 1]`` tells whether local cell (r, c) is drivable. The
    search stops early once ``n_target`` cells of ``goal`` have been reached (``-1``: search
    everything); distances of cells reached are final either way. Returns framed ``dist``
    (int32, -1 where not reached), framed ``pred`` (int8, the direction N/E/S/W = 0..3 taken
    into the cell, -1 for the source and cells not reached) and whether the search ran to
    exhaustion.
    """
    fy, w = free.shape
    dist = np.full((fy, w), -1, dtype=np.int32)
    pred = np.full((fy, w), -1, dtype=np.int8)
    queue = np.empty(fy * w, dtype=np.int32)
    complete = _bfs_into(free, goal, sr, sc, n_target, dist, pred, queue)
    return dist, pred, complete


@njit(cache=True)
def _bfs_into(free, goal, sr, sc, n_target, dist_grid, pred_grid, queue):
    """:func:`_bfs` into given framed ``dist_grid`` and ``pred_grid`` (filled with -1) with a
    work ``queue`` of one entry per cell; returns whether the search ran to exhaustion.
    """
    w = free.shape[1]
    flat_free = free.ravel()
    flat_goal = goal.ravel()
    dist = dist_grid.ravel()
    pred = pred_grid.ravel()
    start = (sr + 1) * w + sc + 1
    dist[start] = 0
    queue[0] = start
    head = 0
    tail = 1
    found = 1 if flat_goal[start] else 0
    while head < tail and found != n_target:
        k = queue[head]
        head += 1
        d0 = dist[k] + 1
        j = k + w  # N
        if dist[j] < 0 and flat_free[j]:
            dist[j] = d0
            pred[j] = 0
            queue[tail] = j
            tail += 1
            if flat_goal[j]:
                found += 1
        j = k + 1  # E
        if dist[j] < 0 and flat_free[j]:
            dist[j] = d0
            pred[j] = 1
            queue[tail] = j
            tail += 1
            if flat_goal[j]:
                found += 1
        j = k + -w  # S
        if dist[j] < 0 and flat_free[j]:
            dist[j] = d0
            pred[j] = 2
            queue[tail] = j
            tail += 1
            if flat_goal[j]:
                found += 1
        j = k + -1  # W
        if dist[j] < 0 and flat_free[j]:
            dist[j] = d0
            pred[j] = 3
            queue[tail] = j
            tail += 1
            if flat_goal[j]:
                found += 1
    return head >= tail


@njit(cache=True)
def _segment_clear(drivable, x0, y0, x1, y1, sr, sc):
    """Whether every supercover cell of the segment (local cell units) is drivable, the start
    cell (sr, sc) exempt.
    """
    cells = _supercover_cells(x0, y0, x1, y1)
    ny, nx = drivable.shape
    for k in range(cells.shape[0]):
        c = cells[k, 0]
        r = cells[k, 1]
        if r == sr and c == sc:
            continue
        if r < 0 or r >= ny or c < 0 or c >= nx or not drivable[r, c]:
            return False
    return True


@njit(cache=True)
def _smooth_keep(drivable, pts, sr, sc):
    """Keep-mask of the waypoints ``pts`` (local cell units) after the smoothing of Fig. 32."""
    n = pts.shape[0]
    keep = np.zeros(n, dtype=np.bool_)
    keep[0] = True
    if n <= 2:
        keep[:] = True
        return keep
    a = 0
    c = 1
    for k in range(2, n):
        if _segment_clear(drivable, pts[a, 0], pts[a, 1], pts[k, 0], pts[k, 1], sr, sc):
            c = k
        else:
            keep[c] = True
            a = c
            c = k
    keep[c] = True
    return keep


@njit(cache=True)
def _los_mark(scanned, blocked, tau, in_bounds, ox, oy, radius):
    """Mark scanned the in-bounds cells seen from (ox, oy) (local cell units) within ``radius``
    cells; return how many were new (Fig. 30; README "Choices": shadows).

    Rays go to points on the circle with an angular step of at most ``1 / (2 radius)`` (half a
    cell at the rim). A ray stops at the first known-blocked cell, which is itself seen; at an
    exact corner crossing both side cells are seen and either one stops the ray.
    """
    ny, nx = scanned.shape
    r2 = radius * radius + 1e-9
    new = 0
    n_rays = max(8, int(math.ceil(4.0 * math.pi * radius)) + 1)
    for k in range(n_rays):
        theta = 2.0 * math.pi * k / n_rays
        cells = _supercover_cells(
            ox, oy, ox + radius * cos_scalar(theta), oy + radius * sin_scalar(theta)
        )
        m = cells.shape[0]
        for j in range(m):
            c = cells[j, 0]
            r = cells[j, 1]
            if r < 0 or r >= ny or c < 0 or c >= nx:
                break
            hit = scanned[r, c] and blocked[r, c] >= tau
            if not scanned[r, c] and in_bounds[r, c]:
                if (c + 0.5 - ox) ** 2 + (r + 0.5 - oy) ** 2 <= r2:
                    scanned[r, c] = True
                    new += 1
            if hit:
                # the first side cell of a corner crossing: its sibling (diagonal to it in the
                # list) touches the same corner point, so it is seen too
                if j + 1 < m:
                    nc = cells[j + 1, 0]
                    nr = cells[j + 1, 1]
                    if abs(nc - c) == 1 and abs(nr - r) == 1 and 0 <= nr < ny and 0 <= nc < nx:
                        if not scanned[nr, nc] and in_bounds[nr, nc]:
                            if (nc + 0.5 - ox) ** 2 + (nr + 0.5 - oy) ** 2 <= r2:
                                scanned[nr, nc] = True
                                new += 1
                break
    return new


@njit(cache=True)
def _walk(pred, sr, sc, tr, tc):
    """Local cells ``(n, 2)`` as (row, col) from the source (sr, sc) to (tr, tc) along ``pred``."""
    n = 1
    r = tr
    c = tc
    while r != sr or c != sc:
        d = pred[r, c]
        r -= _DR[d]
        c -= _DC[d]
        n += 1
    out = np.empty((n, 2), dtype=np.int64)
    r = tr
    c = tc
    for k in range(n - 1, -1, -1):
        out[k, 0] = r
        out[k, 1] = c
        if k > 0:
            d = pred[r, c]
            r -= _DR[d]
            c -= _DC[d]
    return out


_KEY = 1 << 21
"""Cell key ``(ix + 2^20) * 2^21 + (iy + 2^20)``: unique for |ix|, |iy| < 2^20."""


@njit(cache=True)
def _polyline_parts(pts):
    """The supercover cells ``(k, 2)`` as ``(ix, iy)`` of each segment of the polyline ``pts``
    (cell units), one array per segment (cells at shared corners repeated); a one-point path
    gives its own cell.
    """
    n = pts.shape[0]
    parts = []
    for k in range(max(n - 1, 1)):
        b = min(k + 1, n - 1)
        parts.append(_supercover_cells(pts[k, 0], pts[k, 1], pts[b, 0], pts[b, 1]))
    return parts


@njit(cache=True)
def _padded_keys(pts, padding):
    """Sorted keys of the cells swept by the polyline ``pts`` (cell units), dilated by
    ``padding`` cells (README "Choices": waves).
    """
    parts = _polyline_parts(pts)
    lo_x = 1 << 40
    lo_y = 1 << 40
    hi_x = -(1 << 40)
    hi_y = -(1 << 40)
    for cells in parts:
        for j in range(cells.shape[0]):
            lo_x = min(lo_x, cells[j, 0])
            hi_x = max(hi_x, cells[j, 0])
            lo_y = min(lo_y, cells[j, 1])
            hi_y = max(hi_y, cells[j, 1])
    lo_x -= padding
    lo_y -= padding
    w = hi_x + padding - lo_x + 1
    hgt = hi_y + padding - lo_y + 1
    grid = np.zeros((w, hgt), dtype=np.bool_)
    for cells in parts:
        for j in range(cells.shape[0]):
            cx = cells[j, 0] - lo_x
            cy = cells[j, 1] - lo_y
            grid[cx - padding : cx + padding + 1, cy - padding : cy + padding + 1] = True
    keys = np.empty(np.count_nonzero(grid), dtype=np.int64)
    count = 0
    half = _KEY // 2
    for i in range(w):
        for j in range(hgt):
            if grid[i, j]:
                keys[count] = (i + lo_x + half) * _KEY + (j + lo_y + half)
                count += 1
    return keys


@njit(cache=True)
def _overlap(a, b):
    """Whether the sorted key arrays ``a`` and ``b`` share an element."""
    i = 0
    j = 0
    while i < a.shape[0] and j < b.shape[0]:
        if a[i] == b[j]:
            return True
        if a[i] < b[j]:
            i += 1
        else:
            j += 1
    return False


def _framed_base(pmap: ProbMap, padding: int = 1) -> np.ndarray:
    """Drivability (README "Choices": drivability) before robots are added, framed by one ring of
    False (the layout :func:`_bfs` reads): known, and no known-blocked cell (nor the world's wall)
    within ``padding`` cells.

    The world's boundary is a wall for the padding (a robot body cannot stand in the outermost
    ring of world cells); the edge of a routing region inside the world is not.
    """
    return _framed_base_grid(pmap._scanned, pmap._blocked, pmap.tau, max(padding, 0),
                             *pmap._world_edges)  # fmt: skip


@njit(cache=True)
def _framed_base_grid(scanned, blocked, tau, k, west, south, east, north):
    """:func:`_framed_base` on the map's grids, compiled (each coverage call and each route
    needs it): a scanned cell is drivable unless a known-blocked cell lies in the square of
    ``k`` cells around it (an OR along the rows, then along the columns), or it lies within
    ``k`` cells of a side of the world.
    """
    ny, nx = scanned.shape
    known_blocked = np.empty((ny, nx), dtype=np.bool_)
    for r in range(ny):
        for c in range(nx):
            known_blocked[r, c] = scanned[r, c] & (blocked[r, c] >= tau)
    along_row = known_blocked.copy()
    for d in range(1, k + 1):
        for r in range(ny):
            for c in range(d, nx):
                along_row[r, c] |= known_blocked[r, c - d]
            for c in range(nx - d):
                along_row[r, c] |= known_blocked[r, c + d]
    near = along_row.copy()
    for d in range(1, k + 1):
        for r in range(d, ny):
            for c in range(nx):
                near[r, c] |= along_row[r - d, c]
        for r in range(ny - d):
            for c in range(nx):
                near[r, c] |= along_row[r + d, c]
    out = np.zeros((ny + 2, nx + 2), dtype=np.bool_)
    for r in range(ny):
        for c in range(nx):
            out[r + 1, c + 1] = scanned[r, c] & (near[r, c] == 0)
    band = min(k, ny)  # the world's sides: cells within k of them are not drivable
    if south:
        out[1 : band + 1, :] = False
    if north:
        out[ny + 1 - band : ny + 1, :] = False
    band = min(k, nx)
    if west:
        out[:, 1 : band + 1] = False
    if east:
        out[:, nx + 1 - band : nx + 1] = False
    return out


def _without(
    framed: np.ndarray, pmap: ProbMap, occupied: Sequence[Sequence[float]], padding: int = 1
) -> np.ndarray:
    """A copy of the framed grid with every cell within ``padding`` of an occupied cell made
    undrivable.
    """
    grid = framed.copy()
    rows, cols = _local_cells(pmap, occupied)
    _block_around(grid, rows, cols, max(padding, 0), -1)
    return grid


@njit(cache=True)
def _block_around(grid, rows, cols, k, skip):
    """Make every cell of the framed ``grid`` within ``k`` cells of a robot's local cell
    ``(rows[j], cols[j])`` undrivable (README "Choices": drivability), in place; robot ``skip``
    (the one searching) and robots outside the grid block nothing.
    """
    ny = grid.shape[0] - 2
    nx = grid.shape[1] - 2
    for j in range(rows.shape[0]):
        r = rows[j]
        c = cols[j]
        if j != skip and 0 <= r < ny and 0 <= c < nx:
            grid[max(r - k, 0) + 1 : r + k + 2, max(c - k, 0) + 1 : c + k + 2] = False


@njit(cache=True)
def _children_search(base, goal, goal_flat, occ_r, occ_c, n, k, vx, vy):
    """Every child's step of a coverage call (Fig. 24 steps 8-11) in one compiled call.

    Children are the first ``n`` robots at local cells ``(occ_r[i], occ_c[i])``; the others only
    block. Child i's drivable grid is ``base`` (framed) with every cell within ``k`` of another
    robot's cell made undrivable (:func:`_block_around`, as in :func:`_without`); its search
    stops once every drivable cell of ``goal`` is reached (as a :class:`DistanceField` with a
    target). ``goal_flat`` holds the framed flat indices of the goal cells, ``vx`` and ``vy``
    their centres. Returns, stacked per child, the framed drivable grids and the :func:`_bfs`
    results; the positions in ``goal_flat`` of the goal cells each child reaches with their
    steps (float), child i's at ``offsets[i]:offsets[i + 1]``; and per child the box
    ``(x_min, x_max, y_min, y_max)`` of the centres it reaches (for the coverage call's radius
    bound; NaN if none). A child outside the grid searches nothing and reaches no cell.
    """
    fy, w = base.shape
    ny = fy - 2
    nx = w - 2
    m = goal_flat.shape[0]
    free = np.zeros((n, fy, w), dtype=np.bool_)
    dist = np.full((n, fy, w), -1, dtype=np.int32)
    pred = np.full((n, fy, w), -1, dtype=np.int8)
    complete = np.zeros(n, dtype=np.bool_)
    ids = np.empty(n * m, dtype=np.int64)
    steps = np.empty(n * m, dtype=np.float64)
    offsets = np.zeros(n + 1, dtype=np.int64)
    boxes = np.full((n, 4), np.nan)
    queue = np.empty(fy * w, dtype=np.int32)
    flat_goal = goal.ravel()
    flat_base = base.ravel()
    for i in range(n):
        offsets[i + 1] = offsets[i]
        sr = occ_r[i]
        sc = occ_c[i]
        if not (0 <= sr < ny and 0 <= sc < nx):
            continue
        grid = free[i]
        flat_free = grid.ravel()
        for q in range(fy * w):  # an element loop: numba's slice copy of bools is ~20x slower
            flat_free[q] = flat_base[q]
        _block_around(grid, occ_r, occ_c, k, i)
        n_target = 0
        for q in range(m):
            if flat_free[goal_flat[q]]:
                n_target += 1
        start = (sr + 1) * w + sc + 1
        if flat_goal[start] and not flat_free[start]:
            n_target += 1
        complete[i] = _bfs_into(grid, goal, sr, sc, n_target, dist[i], pred[i], queue)
        flat_dist = dist[i].ravel()
        t = offsets[i]
        for q in range(m):
            if flat_dist[goal_flat[q]] >= 0:
                ids[t] = q
                steps[t] = flat_dist[goal_flat[q]]
                if t == offsets[i]:
                    boxes[i, 0] = boxes[i, 1] = vx[q]
                    boxes[i, 2] = boxes[i, 3] = vy[q]
                boxes[i, 0] = min(boxes[i, 0], vx[q])
                boxes[i, 1] = max(boxes[i, 1], vx[q])
                boxes[i, 2] = min(boxes[i, 2], vy[q])
                boxes[i, 3] = max(boxes[i, 3], vy[q])
                t += 1
        offsets[i + 1] = t
    m = offsets[n]
    return free, dist, pred, complete, ids[:m], steps[:m], offsets, boxes


@njit(cache=True)
def _smoothed_route(pred, drivable, sr, sc, tr, tc, ix0, iy0, h, sx, sy):
    """:meth:`DistanceField.path_to` then :func:`_smooth_on` (Fig. 32) in one compiled call:
    the source point ``(sx, sy)`` (metres) in local cell (sr, sc), the centres of the cells
    along ``pred`` to (tr, tc) (the source cell's own centre dropped when the source stands on
    it), then the smoothing's keep-mask on the points in local cell units.
    """
    cells = _walk(pred, sr, sc, tr, tc)
    m = cells.shape[0]
    x0 = (ix0 + cells[0, 1] + 0.5) * h
    y0 = (iy0 + cells[0, 0] + 0.5) * h
    first = 1 if math.hypot(x0 - sx, y0 - sy) <= 1e-9 * h else 0
    n = m + 1 - first
    path = np.empty((n, 2), dtype=np.float64)
    path[0, 0] = sx
    path[0, 1] = sy
    for k in range(first, m):
        path[k + 1 - first, 0] = (ix0 + cells[k, 1] + 0.5) * h
        path[k + 1 - first, 1] = (iy0 + cells[k, 0] + 0.5) * h
    if n <= 2:
        return path
    local = np.empty((n, 2), dtype=np.float64)
    for k in range(n):
        local[k, 0] = path[k, 0] / h - ix0
        local[k, 1] = path[k, 1] / h - iy0
    keep = _smooth_keep(drivable, local, sr, sc)
    return path[keep]


def _local_cells(pmap: ProbMap, points: Sequence[Sequence[float]]) -> tuple[np.ndarray, np.ndarray]:
    """Local rows and columns (int64; outside the grid for points outside it) of the cells
    holding ``points`` (metres).
    """
    h = pmap.cell_size
    rows = [math.floor(y / h + _EPS) - pmap._iy0 for _, y in points]
    cols = [math.floor(x / h + _EPS) - pmap._ix0 for x, _ in points]
    return np.array(rows, dtype=np.int64), np.array(cols, dtype=np.int64)


def _frame(grid: np.ndarray) -> np.ndarray:
    """Bool ``grid`` inside one ring of False (``np.pad`` with False, without its 15 us of
    set-up a call: this runs several times per coverage call).
    """
    ny, nx = grid.shape
    out = np.zeros((ny + 2, nx + 2), dtype=np.bool_)
    out[1 : ny + 1, 1 : nx + 1] = grid
    return out


def _drivable(
    pmap: ProbMap, occupied: Sequence[Sequence[float]] = (), padding: int = 1
) -> np.ndarray:
    """Drivability grid (README "Choices": drivability) over the map's routing region, robots at
    ``occupied``.
    """
    return _without(_framed_base(pmap, padding), pmap, occupied, padding)[1:-1, 1:-1].copy()


# ---------------------------------------------------------------------------- public API
class DistanceField:
    """Dijkstra (BFS) distances from one robot to every cell of a map ("Dijkstra's Algorithm").

    Built by :func:`shortest_paths`. Distances are in cells (4-connected steps).

    Args:
        pmap: the map.
        source: the robot's position (metres); its cell is always expandable.
        drivable: the drivability grid for this robot (README "Choices": drivability).
        target: optional bool grid; the search may stop once every drivable target cell is
            reached (an exact shortcut: it resumes in full if any other cell is queried).

    """

    def __init__(
        self,
        pmap: ProbMap,
        source: Sequence[float],
        drivable: np.ndarray,
        target: np.ndarray | None = None,
    ) -> None:
        self._start(pmap, source, _frame(drivable), None if target is None else _frame(target))

    @classmethod
    def _from_search(cls, pmap, source, cell, free, dist, pred, complete) -> DistanceField:
        """Wrap the framed results of a search already run (see :func:`_children_search`) from
        ``source`` in local cell ``cell``.
        """
        field = cls.__new__(cls)
        field._map = pmap
        field.source = (float(source[0]), float(source[1]))
        field._cell = cell
        field._free = free
        field._dist_f, field._pred_f, field._complete = dist, pred, complete
        return field

    def _start(self, pmap, source, free, goal) -> None:
        cell = pmap._local(*source)
        if cell is None:
            raise ValueError(f"source {tuple(source)} lies outside the map's routing region")
        self._map = pmap
        self.source = (float(source[0]), float(source[1]))
        self._cell = cell
        self._free = free
        if goal is None:
            goal, n_target = np.zeros_like(free), -1
        else:
            fr, fc = cell[0] + 1, cell[1] + 1
            n_target = int(np.count_nonzero(goal & free)) + int(goal[fr, fc] and not free[fr, fc])
        self._dist_f, self._pred_f, self._complete = _bfs(free, goal, cell[0], cell[1], n_target)

    @property
    def _drivable(self) -> np.ndarray:
        """The robot's drivability grid (a view)."""
        return self._free[1:-1, 1:-1]

    @property
    def _dist(self) -> np.ndarray:
        """Steps to each cell, -1 where not (yet) reached (a view)."""
        return self._dist_f[1:-1, 1:-1]

    @property
    def _pred(self) -> np.ndarray:
        """Direction into each reached cell (a view)."""
        return self._pred_f[1:-1, 1:-1]

    def _finish(self) -> None:
        """Run the search to exhaustion (after an early stop)."""
        if not self._complete:
            self._dist_f, self._pred_f, self._complete = _bfs(
                self._free, np.zeros_like(self._free), self._cell[0], self._cell[1], -1
            )

    @property
    def dist(self) -> np.ndarray:
        """Steps to every cell of the stored grid (-1 where unreachable), searched in full."""
        self._finish()
        return self._dist

    def distance(self, x: float, y: float) -> float:
        """Steps (cells) from the source cell to the cell holding ``(x, y)``; inf if unreachable."""
        cell = self._map._local(x, y)
        if cell is None:
            return math.inf
        if self._dist[cell] < 0:
            self._finish()
        return math.inf if self._dist[cell] < 0 else float(self._dist[cell])

    def reachable(self, x: float, y: float) -> bool:
        """Whether the cell holding ``(x, y)`` can be reached through drivable cells."""
        return math.isfinite(self.distance(x, y))

    def path_to(self, x: float, y: float) -> np.ndarray:
        """Unsmoothed path ``(n, 2)`` in metres: the source position, then the centres of the
        cells after the source cell, ending at the centre of the cell holding ``(x, y)``. When
        the source already stands on that cell centre the path is just the source point.

        Raises:
            ValueError: the target is unreachable.

        """
        if not self.reachable(x, y):
            raise ValueError(f"target ({x}, {y}) is not reachable from {self.source}")
        cell = self._map._local(x, y)
        cells = _walk(self._pred, self._cell[0], self._cell[1], cell[0], cell[1])
        h = self._map.cell_size
        centres = np.column_stack(
            ((self._map._ix0 + cells[:, 1] + 0.5) * h, (self._map._iy0 + cells[:, 0] + 0.5) * h)
        )
        if np.hypot(*(centres[0] - self.source)) <= 1e-9 * h:
            return np.vstack((np.asarray([self.source]), centres[1:]))
        return np.vstack((np.asarray([self.source]), centres))

    def _smoothed_path_to(self, x: float, y: float) -> np.ndarray:
        """:meth:`path_to` smoothed on the field's own drivability (Fig. 32), compiled.

        Raises:
            ValueError: the target is unreachable.

        """
        if not self.reachable(x, y):
            raise ValueError(f"target ({x}, {y}) is not reachable from {self.source}")
        m = self._map
        cell = m._local(x, y)
        return _smoothed_route(
            self._pred, self._drivable, self._cell[0], self._cell[1], cell[0], cell[1], m._ix0,
            m._iy0, m.cell_size, self.source[0], self.source[1],
        )  # fmt: skip


def shortest_paths(
    pmap: ProbMap,
    source: Sequence[float],
    occupied: Sequence[Sequence[float]] = (),
    padding: int = 1,
) -> DistanceField:
    """BFS from the robot at ``source`` (metres) over ``pmap``'s drivable cells ("Dijkstra's
    Algorithm"; README "Choices": drivability).

    Args:
        pmap: the director's map.
        source: the robot's position; its cell is always expandable.
        occupied: positions of the other robots the director knows (treated as obstacles).
        padding: robot padding in cells (1 = the 8-neighbourhood, README "Choices": drivability).

    """
    return DistanceField(pmap, source, _drivable(pmap, occupied, padding))


def _smooth_on(pmap: ProbMap, path: np.ndarray, drivable: np.ndarray) -> np.ndarray:
    """Smooth ``path`` with a precomputed drivability grid."""
    path = np.asarray(path, dtype=np.float64)
    if path.shape[0] <= 2:
        return path.copy()
    h = pmap.cell_size
    local = np.column_stack((path[:, 0] / h - pmap._ix0, path[:, 1] / h - pmap._iy0))
    start = pmap._local(path[0, 0], path[0, 1])
    sr, sc = start if start is not None else (-1, -1)
    keep = _smooth_keep(drivable, local, sr, sc)
    return path[keep]


def smooth(
    pmap: ProbMap,
    path: np.ndarray,
    occupied: Sequence[Sequence[float]] = (),
    padding: int = 1,
) -> np.ndarray:
    """Path optimisation by ray tracing (Fig. 32): remove a waypoint while the straight
    segment skipping it crosses only drivable cells (the start cell exempt). The first and last
    points are never removed.

    Args:
        pmap: the director's map.
        path: ``(n, 2)`` waypoints in metres (e.g. ``DistanceField.path_to``).
        occupied: positions of the other robots (obstacles, as for the search).
        padding: robot padding in cells.

    """
    return _smooth_on(pmap, path, _drivable(pmap, occupied, padding))


def supercover(a: Sequence[float], b: Sequence[float], cell_size: float) -> np.ndarray:
    """Global lattice cells ``(k, 2)`` as ``(ix, iy)`` met by the segment a -> b (Fig. 31).

    Includes both cells beside any cell corner the segment passes exactly through.
    """
    h = float(cell_size)
    return _supercover_cells(a[0] / h, a[1] / h, b[0] / h, b[1] / h).copy()


@njit(cache=True)
def _blocked_on_path(pts, ix0, iy0, scanned, blocked, tau):
    """How many distinct cells of the polyline ``pts`` (cell units; its supercover, no padding:
    :func:`padded_cells` with ``padding=0``) are known blocked on the map grids (scanned and at
    or above ``tau``; cells outside the grid are not), for the model's path diagnostics.
    """
    ny, nx = scanned.shape
    seen = np.zeros((ny, nx), dtype=np.bool_)
    count = 0
    for cells in _polyline_parts(pts):
        for j in range(cells.shape[0]):
            c = cells[j, 0] - ix0
            r = cells[j, 1] - iy0
            if 0 <= r < ny and 0 <= c < nx and not seen[r, c]:
                seen[r, c] = True
                if scanned[r, c] and blocked[r, c] >= tau:
                    count += 1
    return count


def _path_keys(path: np.ndarray, cell_size: float, padding: int = 1) -> np.ndarray:
    """Sorted cell keys swept by ``path`` (metres), dilated by ``padding``."""
    pts = np.asarray(path, dtype=np.float64) / float(cell_size)
    return _padded_keys(pts, int(padding))


def _keys_of(
    paths: Sequence[np.ndarray], cell_size: float, padding: int = 1
) -> tuple[np.ndarray, np.ndarray]:
    """:func:`_path_keys` of every path (metres) in one compiled call: the keys concatenated,
    path i's at ``offsets[i]:offsets[i + 1]`` (a wave plan's paths cost one call, not one each).
    """
    parts = [np.asarray(path, dtype=np.float64).reshape(-1, 2) for path in paths]
    lengths = np.array([part.shape[0] for part in parts], dtype=np.int64)
    return _padded_keys_many(np.concatenate(parts) / float(cell_size), lengths, int(padding))


@njit(cache=True)
def _padded_keys_many(pts, lengths, padding):
    """:func:`_padded_keys` of each polyline of ``pts`` (the polylines' points one after the
    other, ``lengths[i]`` points for polyline i): the sorted keys of all, concatenated, and the
    ``offsets`` of each one's.
    """
    n = lengths.shape[0]
    starts = np.zeros(n + 1, dtype=np.int64)
    for i in range(n):
        starts[i + 1] = starts[i] + lengths[i]
    parts = [_padded_keys(pts[starts[i] : starts[i + 1]], padding) for i in range(n)]
    offsets = np.zeros(n + 1, dtype=np.int64)
    for i in range(n):
        offsets[i + 1] = offsets[i] + parts[i].shape[0]
    keys = np.empty(offsets[n], dtype=np.int64)
    for i in range(n):
        keys[offsets[i] : offsets[i + 1]] = parts[i]
    return keys, offsets


@njit(cache=True)
def _conflicts(keys, offsets):
    """Which pairs of padded paths share a cell (:func:`_overlap` of every pair), as a
    symmetric bool matrix; path i's sorted keys are ``keys[offsets[i]:offsets[i + 1]]``.
    """
    n = offsets.shape[0] - 1
    out = np.zeros((n, n), dtype=np.bool_)
    for a in range(n):
        for b in range(a + 1, n):
            if _overlap(keys[offsets[a] : offsets[a + 1]], keys[offsets[b] : offsets[b + 1]]):
                out[a, b] = out[b, a] = True
    return out


def _decode(keys: np.ndarray) -> np.ndarray:
    """Global cells ``(k, 2)`` as ``(ix, iy)`` of cell keys."""
    half = _KEY // 2
    return np.column_stack((keys // _KEY - half, keys % _KEY - half))


def padded_cells(path: np.ndarray, cell_size: float, padding: int = 1) -> np.ndarray:
    """Global cells ``(k, 2)`` as ``(ix, iy)`` swept by a robot following ``path``: the
    supercover of every segment, dilated by ``padding`` cells (README "Choices": waves). A one-point
    path gives its cell (dilated).
    """
    return _decode(_path_keys(path, cell_size, padding))


def path_length(path: np.ndarray) -> float:
    """Length (metres) of the polyline ``path`` (the drive distance, README "Choices": drive
    distance).
    """
    path = np.asarray(path, dtype=np.float64)
    if path.shape[0] < 2:
        return 0.0
    step = path[1:] - path[:-1]  # np.diff's values, without its generic set-up (a drive each)
    return float(np.hypot(step[:, 0], step[:, 1]).sum())


@njit(cache=True)
def _order_violations(wave, keys, offsets, first, last):
    """Pairs (a, b) of moves with ``wave[a] < wave[b]`` where b's padded path holds a's end
    cell key ``last[a]``, or a's holds b's start cell key ``first[b]`` (move i's sorted padded
    cell keys are ``keys[offsets[i]:offsets[i + 1]]``).
    """
    n = wave.shape[0]
    count = 0
    for a in range(n):
        keys_a = keys[offsets[a] : offsets[a + 1]]
        for b in range(n):
            if wave[a] < wave[b]:
                keys_b = keys[offsets[b] : offsets[b + 1]]
                i = np.searchsorted(keys_b, last[a])
                j = np.searchsorted(keys_a, first[b])
                if (i < keys_b.shape[0] and keys_b[i] == last[a]) or (
                    j < keys_a.shape[0] and keys_a[j] == first[b]
                ):
                    count += 1
    return count


def waves(paths: Mapping[int, np.ndarray], cell_size: float, padding: int = 1) -> list[list[int]]:
    """Group moves into waves so that no two moves of a wave share a padded path cell (Fig. 33).

    Welsh-Powell: moves in descending conflict degree (ties: ascending key, the local number),
    each into the first wave holding no conflicting move, else a new wave. Disjoint paths give a
    single wave ("all the children will be told to move simultaneously").

    Args:
        paths: local number -> smoothed path (metres). Pass only robots that actually move.
        cell_size: lattice cell size (metres).
        padding: robot padding in cells.

    Returns:
        Waves in dispatch order, each a list of local numbers in ascending order.

    """
    keys = sorted(paths)
    if not keys:
        return []
    clash = _conflicts(*_keys_of([paths[k] for k in keys], cell_size, padding)).tolist()
    conflict = {a: {b for b, hit in zip(keys, row, strict=True) if hit}
                for a, row in zip(keys, clash, strict=True)}  # fmt: skip
    order = sorted(keys, key=lambda k: (-len(conflict[k]), k))
    result: list[list[int]] = []
    for k in order:
        for wave in result:
            if not conflict[k] & set(wave):
                wave.append(k)
                break
        else:
            result.append([k])
    return [sorted(w) for w in result]


def wave_order_violations(
    wave_list: Sequence[Sequence[int]],
    paths: Mapping[int, np.ndarray],
    cell_size: float,
    padding: int = 1,
) -> int:
    """Count ordered pairs the symmetric conflict rule cannot protect (README "Choices": wave-order
    and proximity diagnostics): a later wave's padded path crossing an earlier wave's end cell, or
    an earlier wave's padded path crossing a later wave's start cell.
    """
    moves = [(i, k) for i, wave in enumerate(wave_list) for k in wave]
    if len(wave_list) < 2 or not moves:
        return 0
    h = float(cell_size)
    half = _KEY // 2

    def cell_key(point: np.ndarray) -> int:
        ix = math.floor(point[0] / h + _EPS)
        iy = math.floor(point[1] / h + _EPS)
        return (ix + half) * _KEY + (iy + half)

    chosen = [np.asarray(paths[k]) for _, k in moves]
    keys, offsets = _keys_of(chosen, cell_size, padding)
    wave = np.array([i for i, _ in moves], dtype=np.int64)
    first = np.array([cell_key(p[0]) for p in chosen], dtype=np.int64)
    last = np.array([cell_key(p[-1]) for p in chosen], dtype=np.int64)
    return int(_order_violations(wave, keys, offsets, first, last))
