"""The director's probability map (ProbMap: "Data Representation" and "Interpreting
Incoming Data").

Every director (queen or worker) keeps an occupancy grid of what its subtree reported. A cell
holds ``scanned`` (known), ``blocked`` (probability of a permanent obstacle, counted as blocked at
``blocked >= tau``) and ``in_bounds`` (inside the director's assigned region and the world).

Two regions per map [README "Choices": two regions]: ``in_bounds`` (the assigned rectangle or
bubble, clipped to the world) governs VALID, the optimistic gain C, placement centres and which
reported data is accepted; the *routing region* is the whole stored rectangle (the region's
circumscribing box, widened by any boxes given in ``cover``, e.g. a MAP_DOWN window) and governs
path planning.

The public API speaks metres only. Every map of a run shares one global lattice: cell
``(ix, iy)`` covers ``[ix*h, (ix+1)*h) x [iy*h, (iy+1)*h)`` for the cell size ``h``, so windows of
one map merge into another without resampling. Grid indices stay inside this package.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np
from numba import njit
from scipy.special import ndtr

from abm import portable
from abm.errors import ConfigError
from models.hierarchy.planning import _blocked_on_path, _los_mark

__all__ = ["STAMPS", "Bubble", "MapWindow", "ProbMap", "Rect", "disc_window"]

STAMPS = ("mass", "peak")
"""How a reported point is spread over cells (Fig. 28; README "Choices": point stamping, switch
``stamp``)."""

_ALL = slice(None)
_EPS = 1e-9
"""Tolerance (in cells) so that a coordinate on a cell boundary lands in the upper cell."""


@dataclass(frozen=True)
class Rect:
    """An axis-aligned rectangle in metres (the world, the queen's region, a MAP_DOWN box)."""

    x_min: float
    y_min: float
    x_max: float
    y_max: float

    def __post_init__(self) -> None:
        if not (self.x_max > self.x_min and self.y_max > self.y_min):
            raise ConfigError(f"Rect needs x_max > x_min and y_max > y_min, got {self}")

    def union(self, other: Rect) -> Rect:
        """The smallest rectangle holding both."""
        return Rect(
            min(self.x_min, other.x_min),
            min(self.y_min, other.y_min),
            max(self.x_max, other.x_max),
            max(self.y_max, other.y_max),
        )


@dataclass(frozen=True)
class Bubble:
    """A circular region: centre ``(x, y)`` and radius ``r`` in metres ("Thinking in Bubbles")."""

    x: float
    y: float
    r: float

    def __post_init__(self) -> None:
        if not self.r > 0:
            raise ConfigError(f"Bubble radius r must be > 0 m, got {self.r!r}")

    def box(self) -> Rect:
        """The circumscribing rectangle, as the report stores a bubble."""
        return Rect(self.x - self.r, self.y - self.r, self.x + self.r, self.y + self.r)


@dataclass(frozen=True)
class MapWindow:
    """A rectangle of known cells cut from a ProbMap: the MAP_DOWN payload (README "Choices":
    MAP_DOWN).

    ``scanned[j, i]`` and ``blocked[j, i]`` describe global cell ``(ix0 + i, iy0 + j)``.
    """

    cell_size: float
    ix0: int
    iy0: int
    scanned: np.ndarray
    blocked: np.ndarray

    @property
    def known_cells(self) -> int:
        """Number of scanned cells carried (the message's payload items, README "Choices":
        MAP_DOWN).
        """
        return int(self.scanned.sum())

    @property
    def box(self) -> Rect:
        """The window's extent in metres."""
        h = self.cell_size
        ny, nx = self.scanned.shape
        return Rect(self.ix0 * h, self.iy0 * h, (self.ix0 + nx) * h, (self.iy0 + ny) * h)


def _cell(v: float, h: float) -> int:
    """Global cell index of coordinate ``v`` (metres)."""
    return math.floor(v / h + _EPS)


@njit(cache=True)
def disc_window(x, y, r, h, ix0, iy0, ny, nx):
    """Local bounds ``(r0, r1, c0, c1)`` (ends exclusive) of the cells of a stored grid of
    ``ny`` x ``nx`` cells with origin cell (ix0, iy0) that cover the disc of radius ``r`` at
    (x, y) (metres; cells of :func:`_cell`), clipped to the grid (compiled: coverage calls use
    it in their own kernels).
    """
    c0 = min(max(math.floor((x - r) / h + _EPS) - ix0, 0), nx)
    c1 = min(max(math.floor((x + r) / h + _EPS) - ix0 + 1, c0), nx)
    r0 = min(max(math.floor((y - r) / h + _EPS) - iy0, 0), ny)
    r1 = min(max(math.floor((y + r) / h + _EPS) - iy0 + 1, r0), ny)
    return r0, r1, c0, c1


class ProbMap:
    """Occupancy grid of one director's assigned region ("Data Representation", Figs. 28-29).

    Args:
        region: the assigned region: a ``Rect`` (the queen: the whole map) or a ``Bubble`` (a
            worker's assignment). ``in_bounds`` = cell centre inside the region and inside
            ``world``.
        world: the world rectangle; cells outside it are never stored (README "Choices": world
            boundary).
        cell_size: cell edge ``h`` in metres (README "Choices": cell size, 0.10 m).
        tau: blocked threshold; a scanned cell with ``blocked >= tau`` is an obstacle (ours 0.5,
            README "Choices": blocked threshold tau).
        stamp: ``"mass"`` (probability mass of N(p, sigma^2 I) over the cell) or ``"peak"``
            (``exp(-d^2 / 2 sigma^2)`` at the cell centre), README "Choices": point stamping.
        cover: further rectangles the stored (routing) grid must include, e.g. the MAP_DOWN box of
            the previous and the new bubble (README "Choices": MAP_DOWN).

    Raises:
        ConfigError: a bad cell size, threshold, stamp or a region outside the world.

    """

    def __init__(
        self,
        region: Rect | Bubble,
        world: Rect,
        *,
        cell_size: float = 0.10,
        tau: float = 0.5,
        stamp: str = "mass",
        cover: Sequence[Rect] = (),
    ) -> None:
        if not (isinstance(cell_size, int | float) and cell_size > 0):
            raise ConfigError(f"cell_size must be a number > 0 m, got {cell_size!r}")
        if not (isinstance(tau, int | float) and 0 < tau <= 1):
            raise ConfigError(f"tau must be in (0, 1], got {tau!r}")
        if stamp not in STAMPS:
            raise ConfigError(f"stamp must be one of {STAMPS}, got {stamp!r}")
        h = float(cell_size)
        self.cell_size = h
        self.tau = float(tau)
        self.stamp = stamp
        self.region = region
        self.world = world
        box = region.box() if isinstance(region, Bubble) else region
        for extra in cover:
            box = box.union(extra)
        wx0, wy0 = _cell(world.x_min, h), _cell(world.y_min, h)
        wx1, wy1 = math.ceil(world.x_max / h - _EPS), math.ceil(world.y_max / h - _EPS)
        ix0 = max(_cell(box.x_min, h), wx0)
        iy0 = max(_cell(box.y_min, h), wy0)
        ix1 = min(math.ceil(box.x_max / h - _EPS), wx1)
        iy1 = min(math.ceil(box.y_max / h - _EPS), wy1)
        if ix1 <= ix0 or iy1 <= iy0:
            raise ConfigError(f"region {region} does not intersect the world {world}")
        self._ix0, self._iy0 = ix0, iy0
        self._world_edges = (ix0 == wx0, iy0 == wy0, ix1 == wx1, iy1 == wy1)
        """Which sides of the stored grid (W, S, E, N) are the world's walls."""
        shape = (iy1 - iy0, ix1 - ix0)
        self._scanned = np.zeros(shape, dtype=np.bool_)
        self._blocked = np.zeros(shape, dtype=np.float64)
        self._exhausted = np.zeros(shape, dtype=np.bool_)
        cx, cy = self._centres()
        if isinstance(region, Bubble):
            inside = (cx - region.x) ** 2 + (cy - region.y) ** 2 <= region.r**2 + _EPS * h * h
        else:
            inside = (
                (cx >= region.x_min)
                & (cx < region.x_max)
                & (cy >= region.y_min)
                & (cy < region.y_max)
            )
        in_world = (
            (cx >= world.x_min) & (cx < world.x_max) & (cy >= world.y_min) & (cy < world.y_max)
        )
        self._in = inside & in_world
        self._n_scanned = 0
        self._points: list[tuple[float, float, float]] = []

    # ------------------------------------------------------------------ geometry (private)
    def _centres(self) -> tuple[np.ndarray, np.ndarray]:
        """Cell-centre coordinates (metres) of the stored grid, each shaped like the grid."""
        ny, nx = self._scanned.shape
        h = self.cell_size
        xs = (self._ix0 + np.arange(nx) + 0.5) * h
        ys = (self._iy0 + np.arange(ny) + 0.5) * h
        return np.broadcast_to(xs, (ny, nx)), np.broadcast_to(ys[:, None], (ny, nx))

    def _local(self, x: float, y: float) -> tuple[int, int] | None:
        """Local ``(row, col)`` of the cell holding ``(x, y)``, or None outside the stored grid."""
        col = _cell(x, self.cell_size) - self._ix0
        row = _cell(y, self.cell_size) - self._iy0
        ny, nx = self._scanned.shape
        if 0 <= row < ny and 0 <= col < nx:
            return row, col
        return None

    def _centre_of(self, row: int, col: int) -> tuple[float, float]:
        """Cell centre (metres) of local cell ``(row, col)``."""
        h = self.cell_size
        return ((self._ix0 + col + 0.5) * h, (self._iy0 + row + 0.5) * h)

    def _set_scanned(self, mask: np.ndarray, rows: slice = _ALL, cols: slice = _ALL) -> int:
        """Mark scanned the cells of ``mask`` (covering ``[rows, cols]``); return how many were
        new.
        """
        view = self._scanned[rows, cols]
        new = int(np.count_nonzero(mask & ~view))
        view |= mask
        self._n_scanned += new
        return new

    def _disc_window(self, x: float, y: float, r: float) -> tuple[slice, slice]:
        """Row and column slices of the stored grid covering the disc of radius r at (x, y)."""
        ny, nx = self._scanned.shape
        r0, r1, c0, c1 = disc_window(x, y, r, self.cell_size, self._ix0, self._iy0, ny, nx)
        return slice(r0, r1), slice(c0, c1)

    # ------------------------------------------------------------------ queries (metres)
    @property
    def bounds(self) -> Rect:
        """The stored (routing) rectangle in metres."""
        h = self.cell_size
        ny, nx = self._scanned.shape
        return Rect(self._ix0 * h, self._iy0 * h, (self._ix0 + nx) * h, (self._iy0 + ny) * h)

    @property
    def n_scanned(self) -> int:
        """Number of scanned cells in the stored grid (README "Choices": no-progress guard)."""
        return self._n_scanned

    @property
    def n_in_bounds(self) -> int:
        """Number of in-bounds cells."""
        return int(self._in.sum())

    @property
    def n_unscanned_in_bounds(self) -> int:
        """In-bounds cells not yet scanned (0 when the director's region is fully known)."""
        return int(np.count_nonzero(self._in & ~self._scanned))

    @property
    def points(self) -> list[tuple[float, float, float]]:
        """Every accepted POINT ``(x, y, sigma)`` in arrival order (the MAP_REPORT payload)."""
        return list(self._points)

    def in_bounds(self, x: float, y: float) -> bool:
        """Whether ``(x, y)`` lies in an in-bounds cell."""
        cell = self._local(x, y)
        return cell is not None and bool(self._in[cell])

    def in_routing(self, x: float, y: float) -> bool:
        """Whether ``(x, y)`` lies in the stored (routing) grid."""
        return self._local(x, y) is not None

    def scanned(self, x: float, y: float) -> bool:
        """Whether the cell holding ``(x, y)`` is known (False outside the stored grid)."""
        cell = self._local(x, y)
        return cell is not None and bool(self._scanned[cell])

    def blocked(self, x: float, y: float) -> float:
        """Blocked probability of the cell holding ``(x, y)`` (0 for unknown or outside)."""
        cell = self._local(x, y)
        return 0.0 if cell is None else float(self._blocked[cell])

    def known_free(self, x: float, y: float) -> bool:
        """Whether the cell holding ``(x, y)`` is scanned and below the blocked threshold."""
        cell = self._local(x, y)
        return cell is not None and bool(self._scanned[cell]) and self._blocked[cell] < self.tau

    def known_blocked(self, x: float, y: float) -> bool:
        """Whether the cell holding ``(x, y)`` is scanned and at or above the threshold."""
        cell = self._local(x, y)
        return cell is not None and bool(self._scanned[cell]) and self._blocked[cell] >= self.tau

    def known_blocked_at(self, points: np.ndarray) -> np.ndarray:
        """Vectorised :meth:`known_blocked`: one bool per row of ``points`` ``(n, 2)``."""
        pts = np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 2)
        return _known_blocked_at(
            pts, self.cell_size, self._ix0, self._iy0, self._scanned, self._blocked, self.tau
        )

    def known_blocked_on(self, path: np.ndarray) -> int:
        """How many distinct cells of the polyline ``path`` (metres; the cells it sweeps, no
        padding) are known blocked: the plan log's count of blocked cells on a path.
        """
        pts = np.asarray(path, dtype=np.float64) / self.cell_size
        return int(
            _blocked_on_path(pts, self._ix0, self._iy0, self._scanned, self._blocked, self.tau)
        )

    def cell_centre(self, x: float, y: float) -> tuple[float, float]:
        """Centre (metres) of the lattice cell holding ``(x, y)``."""
        h = self.cell_size
        return ((_cell(x, h) + 0.5) * h, (_cell(y, h) + 0.5) * h)

    def unscanned_points(self) -> np.ndarray:
        """Centres ``(n, 2)`` of in-bounds cells not scanned: the MAP_REPORT's unscanned list."""
        rows, cols = np.nonzero(self._in & ~self._scanned)
        h = self.cell_size
        return np.column_stack(((self._ix0 + cols + 0.5) * h, (self._iy0 + rows + 0.5) * h))

    def raster(self) -> tuple[np.ndarray, Rect]:
        """Known-map raster for display: -1 unknown, 0 free, 1 blocked, NaN out of bounds.

        Rows run south to north (row 0 is the lowest y); returns the raster and its extent.
        """
        out = np.where(self._scanned, (self._blocked >= self.tau).astype(float), -1.0)
        out[~self._in] = np.nan
        return out, self.bounds

    # ------------------------------------------------------------------ updates
    def mark_free(self, positions: Iterable[Sequence[float]]) -> int:
        """Mark the cells under ``positions`` scanned and free: a robot knows its own cell is free
        (README "Choices": initial knowledge). Positions outside the stored grid are ignored.

        Returns:
            The number of newly scanned cells.

        """
        new = 0
        for x, y in positions:
            cell = self._local(x, y)
            if cell is None:
                continue
            if not self._scanned[cell]:
                new += 1
                self._scanned[cell] = True
            self._blocked[cell] = 0.0
        self._n_scanned += new
        return new

    def exhaust(self, x: float, y: float) -> None:
        """Remove the cell holding ``(x, y)`` from VALID for good (README "Choices": no-progress
        guard).
        """
        cell = self._local(x, y)
        if cell is not None:
            self._exhausted[cell] = True

    def stamp_point(self, x: float, y: float, sigma: float = 0.0) -> bool:
        """Merge one POINT report ("Interpreting Incoming Data", Fig. 28).

        A point outside the in-bounds region is discarded (rule R1a). Otherwise in-bounds cells
        within 3 sigma get ``p`` (mass or peak of the Gaussian; sigma = 0 gives the containing
        cell p = 1), combined noisy-OR, ``b <- 1 - (1 - b)(1 - p)``, and are marked scanned.

        Returns:
            True if the point was accepted.

        """
        if sigma < 0 or not math.isfinite(sigma):
            raise ConfigError(f"sigma must be a finite number >= 0 m, got {sigma!r}")
        cell = self._local(x, y)
        if cell is None or not self._in[cell]:
            return False
        self._points.append((float(x), float(y), float(sigma)))
        if sigma == 0.0:
            self._blocked[cell] = 1.0
            if not self._scanned[cell]:
                self._scanned[cell] = True
                self._n_scanned += 1
            return True
        h = self.cell_size
        ext = math.ceil(3.0 * sigma / h)
        row, col = cell
        ny, nx = self._scanned.shape
        r0, r1 = max(row - ext, 0), min(row + ext + 1, ny)
        c0, c1 = max(col - ext, 0), min(col + ext + 1, nx)
        xs = (self._ix0 + np.arange(c0, c1)) * h
        ys = (self._iy0 + np.arange(r0, r1)) * h
        if self.stamp == "mass":
            px = ndtr((xs + h - x) / sigma) - ndtr((xs - x) / sigma)
            py = ndtr((ys + h - y) / sigma) - ndtr((ys - y) / sigma)
            p = py[:, None] * px[None, :]
        else:
            dx = xs + 0.5 * h - x
            dy = ys + 0.5 * h - y
            p = portable.exp(-(dy[:, None] ** 2 + dx[None, :] ** 2) / (2.0 * sigma**2))
            p[row - r0, col - c0] = max(p[row - r0, col - c0], 1.0)
        window = self._in[r0:r1, c0:c1]
        p = np.where(window, p, 0.0)
        block = self._blocked[r0:r1, c0:c1]
        block[...] = 1.0 - (1.0 - block) * (1.0 - p)
        self._set_scanned(window & (p > 0), slice(r0, r1), slice(c0, c1))
        return True

    def infer_scan(self, x: float, y: float, r: float) -> int:
        """Line-of-sight inference after a scout's SCAN_COMPLETE (Fig. 30; README "Choices":
        shadows).

        Rays go from the scan position ``(x, y)`` to points on the circle of radius ``r`` with an
        angular step of at most ``cell / (2 r)``; each ray's supercover cells are visible up to
        and including the first known-blocked cell. Visible in-bounds cells with centre within
        ``r`` are marked scanned; shadowed cells stay unknown.

        Returns:
            The number of newly scanned cells.

        """
        h = self.cell_size
        if self._local(x, y) is None:
            return 0
        new = _los_mark(
            self._scanned,
            self._blocked,
            self.tau,
            self._in,
            x / h - self._ix0,
            y / h - self._iy0,
            r / h,
        )
        self._n_scanned += new
        return new

    def mark_bubble(
        self, x: float, y: float, r: float, unscanned: Iterable[Sequence[float]] = ()
    ) -> int:
        """Merge a worker's finished bubble ("Communication": the worker lists the cells it did
        not scan): every in-bounds cell with centre
        within ``r`` of ``(x, y)`` becomes scanned, except the cells holding the ``unscanned``
        points the worker listed. No shadow inference.

        Returns:
            The number of newly scanned cells.

        """
        rows, cols = self._disc_window(x, y, r)
        xs = (self._ix0 + np.arange(cols.start, cols.stop) + 0.5) * self.cell_size
        ys = (self._iy0 + np.arange(rows.start, rows.stop) + 0.5) * self.cell_size
        tol = _EPS * self.cell_size**2
        mask = (xs[None, :] - x) ** 2 + (ys[:, None] - y) ** 2 <= r * r + tol
        mask &= self._in[rows, cols]
        for ux, uy in unscanned:
            cell = self._local(ux, uy)
            if cell is not None and rows.start <= cell[0] < rows.stop:
                if cols.start <= cell[1] < cols.stop:
                    mask[cell[0] - rows.start, cell[1] - cols.start] = False
        return self._set_scanned(mask, rows, cols)

    def window(self, box: Rect) -> MapWindow:
        """Cut the known cells inside ``box`` (clipped to the stored grid) as a MAP_DOWN payload."""
        h = self.cell_size
        ny, nx = self._scanned.shape
        c0 = min(max(_cell(box.x_min, h) - self._ix0, 0), nx)
        r0 = min(max(_cell(box.y_min, h) - self._iy0, 0), ny)
        c1 = min(max(math.ceil(box.x_max / h - _EPS) - self._ix0, c0), nx)
        r1 = min(max(math.ceil(box.y_max / h - _EPS) - self._iy0, r0), ny)
        scanned = self._scanned[r0:r1, c0:c1].copy()
        blocked = np.where(scanned, self._blocked[r0:r1, c0:c1], 0.0)
        return MapWindow(h, self._ix0 + c0, self._iy0 + r0, scanned, blocked)

    def merge(self, window: MapWindow) -> int:
        """Merge a MAP_DOWN window (or a retained copy) into the stored grid (README "Choices":
        MAP_DOWN).

        Scanned cells of the window become scanned here; their blocked value is the larger of
        the two (idempotent, so merging the same knowledge twice changes nothing). Cells outside
        the stored grid are dropped.

        Returns:
            The number of newly scanned cells.

        """
        if not math.isclose(window.cell_size, self.cell_size):
            raise ConfigError(
                f"window cell_size {window.cell_size} differs from the map's {self.cell_size}"
            )
        ny, nx = self._scanned.shape
        wy, wx = window.scanned.shape
        c0 = max(window.ix0 - self._ix0, 0)
        r0 = max(window.iy0 - self._iy0, 0)
        c1 = min(window.ix0 + wx - self._ix0, nx)
        r1 = min(window.iy0 + wy - self._iy0, ny)
        if c1 <= c0 or r1 <= r0:
            return 0
        wc0, wr0 = c0 + self._ix0 - window.ix0, r0 + self._iy0 - window.iy0
        src_s = window.scanned[wr0 : wr0 + r1 - r0, wc0 : wc0 + c1 - c0]
        src_b = window.blocked[wr0 : wr0 + r1 - r0, wc0 : wc0 + c1 - c0]
        dst_b = self._blocked[r0:r1, c0:c1]
        dst_s = self._scanned[r0:r1, c0:c1]
        dst_b[...] = np.where(src_s, np.where(dst_s, np.maximum(dst_b, src_b), src_b), dst_b)
        return self._set_scanned(src_s, slice(r0, r1), slice(c0, c1))


@njit(cache=True)
def _known_blocked_at(pts, h, ix0, iy0, scanned, blocked, tau):
    """:meth:`ProbMap.known_blocked_at`, compiled (it runs for every planned path): the cell
    of each point as :func:`_cell` finds it, then scanned and at or above ``tau``; a point
    outside the grid (or not finite) is not known blocked.
    """
    ny, nx = scanned.shape
    out = np.zeros(pts.shape[0], dtype=np.bool_)
    for i in range(pts.shape[0]):
        col = np.floor(pts[i, 0] / h + _EPS) - ix0
        row = np.floor(pts[i, 1] / h + _EPS) - iy0
        if 0 <= row < ny and 0 <= col < nx:
            r, c = int(row), int(col)
            out[i] = scanned[r, c] and blocked[r, c] >= tau
    return out
