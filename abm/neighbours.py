"""Who is within r: fixed-radius neighbour search at linear cost (cell lists).

Every "who is within r of whom" question of the framework goes through here: robot-robot
contacts in the physics, links of the comm graph, and any model's own neighbour queries. An
N x N distance matrix is quadratic (at 1,000 agents it is already slower than a per-agent
Python loop, see NOTES), a KD-tree rebuilt per tick pays a tree build and Python objects; a
uniform grid of cells at least ``r`` wide needs only the 3 x 3 cells around a point.

- :func:`pairs_within`: all pairs closer than ``r`` among ``n`` points (compiled; walled or
  periodic), in lexicographic order, so results never depend on how the search is organised.
- :func:`within`: for each query point the indices of the points within ``r`` (compiled; CSR).
- :func:`new_pairs`: the pairs close now that were not close before, as sorted pair keys
  (compiled; what counts a contact or an approach once, not every tick it lasts);
  :func:`same_keys` tells whether nothing changed (so a kernel need not return its keys).
- :class:`NeighbourIndex`: a dynamic index of keyed points that come, move and go one at a
  time (event-driven users such as the comm graph), answering ``near(point, r)`` with the
  keys in the 3 x 3 cells around the point (a superset: the caller measures the distance).
"""

import math
from collections.abc import Hashable

import numpy as np
from numba import njit

from abm.errors import ConfigError

__all__ = [
    "NeighbourIndex",
    "cell_grid",
    "cell_of",
    "nearest_distance",
    "new_pairs",
    "pairs_within",
    "same_keys",
    "within",
]


@njit(cache=True)
def new_pairs(now: np.ndarray, before: np.ndarray) -> np.ndarray:
    """The keys of ``now`` not in ``before``, both sorted arrays of unique int64 pair keys (the
    pairs close now, and at the last look): a binary search each.
    """
    if before.shape[0] == 0:
        return now
    at = np.minimum(np.searchsorted(before, now), before.shape[0] - 1)
    return now[before[at] != now]


@njit(cache=True)
def same_keys(now: np.ndarray, before: np.ndarray) -> bool:
    """Whether two 1-d key arrays hold the same values in the same order (``np.array_equal``,
    compiled for the kernels that return nothing when their keys did not change).
    """
    if now.shape[0] != before.shape[0]:
        return False
    for k in range(now.shape[0]):
        if now[k] != before[k]:
            return False
    return True


def _check_radius(radius: float) -> float:
    if not (isinstance(radius, int | float | np.floating) and radius > 0 and math.isfinite(radius)):
        raise ConfigError(f"radius must be a finite number > 0 (m), got {radius!r}")
    return float(radius)


def _as_points(points: np.ndarray, name: str = "points") -> np.ndarray:
    array = np.ascontiguousarray(points, dtype=float)
    if array.ndim != 2 or array.shape[1] != 2:
        raise ConfigError(f"{name} must be an (n, 2) array of x, y, got shape {array.shape}")
    return array


def _as_box(box: tuple[float, float] | None) -> np.ndarray:
    if box is None:
        return np.zeros(2)
    size = np.asarray(box, dtype=float)
    if size.shape != (2,) or not (size > 0).all():
        raise ConfigError(f"box must be (width, height) > 0 of a periodic space, got {box!r}")
    return size


def pairs_within(
    points: np.ndarray,
    radius: float,
    box: tuple[float, float] | None = None,
    *,
    inclusive: bool = False,
) -> tuple[np.ndarray, np.ndarray]:
    """Index pairs ``i < j`` of points closer than ``radius``, sorted by ``i`` then ``j``.

    Args:
        points: ``(n, 2)`` positions (m).
        radius: r (m).
        box: ``(width, height)`` of a periodic space (distances by the nearest image; points
            must lie in ``[0, width) x [0, height)``); None: a walled (open) plane.
        inclusive: count pairs exactly ``radius`` apart too (``<=`` instead of ``<``).

    Returns:
        Two int64 arrays ``(i, j)``.

    """
    pts = _as_points(points)
    r = _check_radius(radius)
    size = _as_box(box)
    return _pairs(pts, r, size, box is not None, inclusive)


def within(
    points: np.ndarray,
    queries: np.ndarray,
    radius: float,
    box: tuple[float, float] | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """For each query point the indices of the points within ``radius`` (``<=``), ascending.

    Returns:
        CSR arrays ``(offsets, indices)``: query ``q``'s neighbours are
        ``indices[offsets[q]:offsets[q + 1]]``.

    """
    pts = _as_points(points)
    qs = _as_points(queries, "queries")
    r = _check_radius(radius)
    size = _as_box(box)
    return _within(pts, qs, r, size, box is not None)


# ---------------------------------------------------------------------- compiled cell lists
@njit(cache=True)
def cell_grid(points, radius):
    """Compiled building block: bucket walled-plane points into cells at least ``radius`` wide.

    Returns ``(lo, width, dims, which, start, order)``: the grid's lower corner, cell sides,
    cells per axis, each point's cell (``iy * dims[0] + ix``), and CSR arrays listing the
    points of cell ``c`` as ``order[start[c]:start[c + 1]]`` (ascending). Every point within
    ``radius`` of a location lies in the 3 x 3 cells around that location's cell
    (:func:`cell_of`, which may fall outside the grid).
    """
    size = np.zeros(2)
    return _grid(points, _cell_size(points, radius, size, False), size, False)


@njit(cache=True)
def cell_of(lo, width, x, y):
    """Cell indices ``(ix, iy)`` of location ``(x, y)`` in a :func:`cell_grid` (unclamped)."""
    return int(math.floor((x - lo[0]) / width[0])), int(math.floor((y - lo[1]) / width[1]))


@njit(cache=True)
def _grid(points, cell, size, periodic):
    """Bucket points into cells: (origin, cell sides, dims, cell per point, CSR start, order)."""
    n = points.shape[0]
    lo = np.zeros(2)
    dims = np.ones(2, dtype=np.int64)
    if periodic:
        for a in range(2):
            dims[a] = max(1, int(size[a] // cell))
    elif n > 0:
        for a in range(2):
            lo[a] = points[:, a].min()
            dims[a] = int((points[:, a].max() - lo[a]) // cell) + 1
    width = np.empty(2)
    for a in range(2):
        width[a] = size[a] / dims[a] if periodic else cell
    which, start, order = _bucket(points, lo, width, dims)
    return lo, width, dims, which, start, order


@njit(cache=True)
def _offset(d, size, periodic):
    if periodic:
        if d > 0.5 * size:
            return d - size
        if d < -0.5 * size:
            return d + size
    return d


@njit(cache=True)
def _cell_size(points, radius, size, periodic):
    """At least r; in a walled plane also large enough that the grid has about n cells."""
    n = points.shape[0]
    if periodic or n == 0:
        return radius
    area = max(
        (points[:, 0].max() - points[:, 0].min()) * (points[:, 1].max() - points[:, 1].min()),
        1e-12,
    )
    longest = max(points[:, 0].max() - points[:, 0].min(), points[:, 1].max() - points[:, 1].min())
    # about n cells in all, and at most about n along a thin strip
    return max(radius, math.sqrt(area / n), longest / n)


@njit(cache=True)
def _pairs(points, radius, size, periodic, inclusive):
    """Cell by cell over points stored in cell order: each pair of neighbouring cells once
    (the cell itself and four of its eight neighbours), then the pairs sorted.
    """
    n = points.shape[0]
    cell = _cell_size(points, 0.5 * radius, size, periodic)
    cell = max(cell, radius)
    if periodic:  # fewer than three cells across an axis: one cell spans it (no double visits)
        dims = np.ones(2, dtype=np.int64)
        for a in range(2):
            dims[a] = max(1, int(size[a] // cell))
            if dims[a] < 3:
                dims[a] = 1
        width = size / dims
        which, start, order = _bucket(points, np.zeros(2), width, dims)
    else:
        lo, width, dims, which, start, order = _grid(points, cell, size, periodic)
    xs = np.empty(n)
    ys = np.empty(n)
    for s in range(n):
        xs[s] = points[order[s], 0]
        ys[s] = points[order[s], 1]
    r2 = radius * radius
    cap = max(16, n)
    keys = np.empty(cap, dtype=np.int64)
    found = 0
    steps_x = np.array([0, 1, -1, 0, 1])
    steps_y = np.array([0, 0, 1, 1, 1])
    for cy in range(dims[1]):
        for cx in range(dims[0]):
            c = cy * dims[0] + cx
            for k in range(5):
                x = cx + steps_x[k]
                y = cy + steps_y[k]
                if periodic and (
                    (steps_x[k] != 0 and dims[0] == 1) or (steps_y[k] != 0 and dims[1] == 1)
                ):
                    continue
                if periodic:
                    x %= dims[0]
                    y %= dims[1]
                elif x < 0 or x >= dims[0] or y >= dims[1]:
                    continue
                c2 = y * dims[0] + x
                for s in range(start[c], start[c + 1]):
                    first = s + 1 if k == 0 else start[c2]
                    for t in range(first, start[c2 + 1]):
                        ddx = _offset(xs[t] - xs[s], size[0], periodic)
                        ddy = _offset(ys[t] - ys[s], size[1], periodic)
                        d2 = ddx * ddx + ddy * ddy
                        if d2 < r2 or (inclusive and d2 == r2):
                            i = min(order[s], order[t])
                            j = max(order[s], order[t])
                            if found == cap:
                                cap *= 2
                                keys = np.concatenate((keys, np.empty(cap - found, np.int64)))
                            keys[found] = i * n + j
                            found += 1
    keys = np.sort(keys[:found])
    return keys // n, keys % n


@njit(cache=True)
def _bucket(points, lo, width, dims):
    """Cell of each point and the CSR listing of the points per cell (ascending)."""
    n = points.shape[0]
    which = np.empty(n, dtype=np.int64)
    for k in range(n):
        cx = min(max(int((points[k, 0] - lo[0]) // width[0]), 0), dims[0] - 1)
        cy = min(max(int((points[k, 1] - lo[1]) // width[1]), 0), dims[1] - 1)
        which[k] = cy * dims[0] + cx
    start = np.zeros(dims[0] * dims[1] + 1, dtype=np.int64)
    for k in range(n):
        start[which[k] + 1] += 1
    for c in range(dims[0] * dims[1]):
        start[c + 1] += start[c]
    fill = start[:-1].copy()
    order = np.empty(n, dtype=np.int64)
    for k in range(n):
        order[fill[which[k]]] = k
        fill[which[k]] += 1
    return which, start, order


@njit(cache=True)
def _within(points, queries, radius, size, periodic):
    n = points.shape[0]
    cell = _cell_size(points, radius, size, periodic)
    lo, width, dims, which, start, order = _grid(points, cell, size, periodic)
    r2 = radius * radius
    nq = queries.shape[0]
    offsets = np.zeros(nq + 1, dtype=np.int64)
    cap = max(16, 4 * nq)
    out = np.empty(cap, dtype=np.int64)
    near = np.empty(max(n, 1), dtype=np.int64)
    seen = np.full(dims[0] * dims[1], -1, dtype=np.int64)
    for q in range(nq):
        fx = (queries[q, 0] - lo[0]) / width[0]
        fy = (queries[q, 1] - lo[1]) / width[1]
        cx = int(math.floor(fx))
        cy = int(math.floor(fy))
        if periodic:
            cx = min(max(cx, 0), dims[0] - 1)
            cy = min(max(cy, 0), dims[1] - 1)
        m = 0
        for dy in range(-1, 2):
            y = cy + dy
            if periodic:
                y %= dims[1]
            elif y < 0 or y >= dims[1]:
                continue
            for dx in range(-1, 2):
                x = cx + dx
                if periodic:
                    x %= dims[0]
                elif x < 0 or x >= dims[0]:
                    continue
                c = y * dims[0] + x
                if seen[c] == q:
                    continue
                seen[c] = q
                for s in range(start[c], start[c + 1]):
                    j = order[s]
                    ddx = _offset(points[j, 0] - queries[q, 0], size[0], periodic)
                    ddy = _offset(points[j, 1] - queries[q, 1], size[1], periodic)
                    if ddx * ddx + ddy * ddy <= r2:
                        near[m] = j
                        m += 1
        near[:m].sort()
        if offsets[q] + m > cap:
            cap = 2 * (offsets[q] + m)
            out = np.concatenate((out, np.empty(cap - out.shape[0], dtype=np.int64)))
        for k in range(m):
            out[offsets[q] + k] = near[k]
        offsets[q + 1] = offsets[q] + m
    return offsets, out[: offsets[nq]].copy()


@njit(cache=True)
def nearest_distance(points, targets):
    """Distance from each point to its nearest target (inf without targets); compiled.

    Cells are searched ring by ring around the point (its cell clamped into the targets'
    grid) until no unsearched cell can hold a nearer target, so the cost grows with the
    targets near a point, not with all targets.
    """
    n = points.shape[0]
    m = targets.shape[0]
    out = np.full(n, np.inf)
    if m == 0:
        return out
    lo, width, dims, _which, start, order = cell_grid(targets, 1e-9)
    step = min(width[0], width[1])
    for i in range(n):
        px, py = points[i, 0], points[i, 1]
        cx, cy = cell_of(lo, width, px, py)
        cx = min(max(cx, 0), dims[0] - 1)
        cy = min(max(cy, 0), dims[1] - 1)
        best = np.inf
        ring = 0
        while True:
            for y in range(max(cy - ring, 0), min(cy + ring, dims[1] - 1) + 1):
                edge_y = y == cy - ring or y == cy + ring
                for x in range(max(cx - ring, 0), min(cx + ring, dims[0] - 1) + 1):
                    if not edge_y and x != cx - ring and x != cx + ring:
                        continue  # inside the ring: searched already
                    c = y * dims[0] + x
                    for s in range(start[c], start[c + 1]):
                        j = order[s]
                        d = np.hypot(px - targets[j, 0], py - targets[j, 1])
                        if d < best:
                            best = d
            covered = cx - ring <= 0 and cy - ring <= 0
            covered = covered and cx + ring >= dims[0] - 1 and cy + ring >= dims[1] - 1
            if covered or best <= ring * step:
                break
            ring += 1
        out[i] = best
    return out


# ---------------------------------------------------------------------- dynamic index
class NeighbourIndex:
    """Keyed points on a grid of square cells, updated one point at a time.

    Adding, moving and removing a point cost O(1); :meth:`near` returns the keys in the 3 x 3
    cells around a point, so with cells at least as wide as the query radius every key within
    that radius is among them (the caller measures distances: it decides ``<`` or ``<=``).

    Args:
        cell: side of a cell (m): the largest radius :meth:`near` answers for.

    """

    def __init__(self, cell: float) -> None:
        self.cell = _check_radius(cell)
        self._cells: dict[tuple[int, int], dict[Hashable, None]] = {}
        self._where: dict[Hashable, tuple[int, int]] = {}

    def _cell_of(self, point: np.ndarray) -> tuple[int, int]:
        return (math.floor(point[0] / self.cell), math.floor(point[1] / self.cell))

    def __len__(self) -> int:
        return len(self._where)

    def __contains__(self, key: Hashable) -> bool:
        return key in self._where

    def add(self, key: Hashable, point: np.ndarray) -> None:
        """Put ``key`` at ``point`` (moves it if it is there already)."""
        if key in self._where:
            self.remove(key)
        cell = self._cell_of(point)
        self._cells.setdefault(cell, {})[key] = None
        self._where[key] = cell

    def remove(self, key: Hashable) -> None:
        """Take ``key`` out (nothing happens if it is not in)."""
        cell = self._where.pop(key, None)
        if cell is None:
            return
        members = self._cells[cell]
        del members[key]
        if not members:
            del self._cells[cell]

    def near(self, point: np.ndarray, radius: float | None = None) -> list[Hashable]:
        """The keys in the cells around ``point`` that can lie within ``radius`` (default: one
        cell) of it, cell row by cell row.
        """
        reach = 1 if radius is None else max(1, math.ceil(radius / self.cell))
        cx, cy = self._cell_of(point)
        cells = self._cells
        found: list[Hashable] = []
        for y in range(cy - reach, cy + reach + 1):
            for x in range(cx - reach, cx + reach + 1):
                members = cells.get((x, y))
                if members:
                    found.extend(members)
        return found
