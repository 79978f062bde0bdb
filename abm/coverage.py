"""Coverage rasters: which free area has been inside a robot's sensor disc.

Stirling et al. (2010) Sect. 3.5: coverage area is the percentage of the free area that was
within the sensor radius S_r of at least one beacon at least once. Walls block the view: a pixel
counts only if the straight line from the sensor to the pixel centre stays in free space.
"""

import numpy as np
from numba import njit

from abm.arena import Arena
from abm.errors import check_range

__all__ = ["CoverageRaster", "visible_cells"]


def visible_cells(
    arena: Arena,
    points: np.ndarray,
    dy: np.ndarray,
    dx: np.ndarray,
    skip: np.ndarray | None = None,
    line_of_sight: bool = True,
) -> np.ndarray:
    """Row-major indices of the free arena cells sensors at ``points`` see (with repeats).

    A sensor sees the cells at offsets ``(dy, dx)`` from its own cell (e.g. a disc from
    :func:`abm.pheromone.disc_offsets`) that are free, not already True in ``skip`` (a
    boolean grid, e.g. what was seen before) and, with ``line_of_sight``, reached by the
    straight line from the sensor to the cell's centre without entering a wall.
    """
    points = np.ascontiguousarray(np.atleast_2d(points), dtype=float)
    skip = np.zeros_like(arena.free) if skip is None else skip
    cells, rows = _disc_cells(
        arena.free, skip, points, arena.resolution, dy.astype(np.int64), dx.astype(np.int64)
    )
    if line_of_sight and len(cells):
        iy, ix = np.divmod(cells, arena.cols)
        ends = (np.stack([ix, iy], axis=1) + 0.5) * arena.resolution
        cells = cells[~arena.segment_crosses_wall(points[rows], ends)]
    return cells


@njit(cache=True)
def _disc_cells(free, skip, points, res, dy, dx):
    """Free, not skipped cells at the offsets around each point's cell, and the point's row."""
    rows, cols = free.shape
    cells = np.empty(points.shape[0] * dy.shape[0], dtype=np.int64)
    owner = np.empty_like(cells)
    m = 0
    for i in range(points.shape[0]):
        ix = int(np.floor(points[i, 0] / res))
        iy = int(np.floor(points[i, 1] / res))
        for k in range(dy.shape[0]):
            cx = ix + dx[k]
            cy = iy + dy[k]
            if 0 <= cx < cols and 0 <= cy < rows and free[cy, cx] and not skip[cy, cx]:
                cells[m] = cy * cols + cx
                owner[m] = i
                m += 1
    return cells[:m], owner[:m]


class CoverageRaster:
    """A fine raster over the arena marking free pixels ever seen.

    Args:
        arena: the world.
        radius: sensing radius (m), S_r.
        pixel: raster pixel side (m); the arena's resolution is split into whole pixels.
        line_of_sight: walls block the view.

    """

    def __init__(
        self, arena: Arena, radius: float = 3.5, pixel: float = 0.25, line_of_sight: bool = True
    ) -> None:
        check_range("radius", radius, 0.0, low_open=True)
        check_range("pixel", pixel, 0.0, low_open=True)
        self.arena = arena
        self.radius = float(radius)
        self.subdivision = max(1, int(round(arena.resolution / pixel)))
        self.pixel = arena.resolution / self.subdivision
        self.line_of_sight = line_of_sight
        self.free = np.repeat(
            np.repeat(arena.free, self.subdivision, axis=0), self.subdivision, axis=1
        )
        self.covered = np.zeros_like(self.free)
        self._n_free = int(self.free.sum())
        r = int(np.ceil(self.radius / self.pixel))
        dy, dx = np.mgrid[-r : r + 1, -r : r + 1]
        self._window = np.stack([dx.ravel(), dy.ravel()], axis=1)

    @property
    def fraction(self) -> float:
        """Fraction of free pixels covered, in [0, 1]."""
        return float(self.covered.sum()) / self._n_free

    @property
    def area(self) -> float:
        """Covered free area (m^2)."""
        return float(self.covered.sum()) * self.pixel**2

    def visible_pixels(self, point: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Row and column indices of the free pixels a sensor at ``point`` sees."""
        point = np.asarray(point, dtype=float)
        centre = np.floor(point / self.pixel).astype(int)
        idx = self._window + centre
        rows, cols = self.free.shape
        inside = (idx[:, 0] >= 0) & (idx[:, 0] < cols) & (idx[:, 1] >= 0) & (idx[:, 1] < rows)
        idx = idx[inside]
        idx = idx[self.free[idx[:, 1], idx[:, 0]]]
        centres = (idx + 0.5) * self.pixel
        near = np.hypot(*(centres - point).T) <= self.radius
        idx, centres = idx[near], centres[near]
        if self.line_of_sight and len(idx):
            seen = self.arena.line_of_sight(np.broadcast_to(point, centres.shape), centres)
            idx = idx[seen]
        return idx[:, 1], idx[:, 0]

    def stamp(self, points: np.ndarray) -> float:
        """Mark what sensors at ``points`` see; return the newly covered area (m^2)."""
        before = self.covered.sum()
        for point in np.atleast_2d(points):
            rows, cols = self.visible_pixels(point)
            self.covered[rows, cols] = True
        return float(self.covered.sum() - before) * self.pixel**2
