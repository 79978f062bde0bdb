"""The arena: walls on an occupancy grid, free-space tests and exact vectorised raycasts.

The world is a boolean grid ``free[iy, ix]`` of square pixels of side ``resolution`` metres with
its origin at (0, 0): x grows east (columns), y grows north (rows). Everything outside the grid is
wall. Grid walls make every geometric query exact and cheap: a ray or a move is walked cell by
cell (Amanatides-Woo traversal), vectorised over all rays at once with numpy.
"""

from collections.abc import Iterable
from pathlib import Path

import numpy as np

from abm.errors import MapError, check_range

__all__ = ["Arena", "CARDINALS"]

#: Unit vectors of the four compass directions in the order the papers use: N, E, S, W.
CARDINALS = np.array([[0.0, 1.0], [1.0, 0.0], [0.0, -1.0], [-1.0, 0.0]])


class Arena:
    """Walls and free space of a 2-D world on a square grid.

    Args:
        free: boolean array ``[rows, cols]``, True where a robot may be; row 0 is the south edge.
        resolution: side of one grid pixel (m).
        name: a label for reports.

    """

    def __init__(self, free: np.ndarray, resolution: float = 1.0, name: str = "arena") -> None:
        free = np.asarray(free)
        if free.ndim != 2 or free.size == 0:
            raise MapError(f"free must be a non-empty 2-D array, got shape {free.shape}")
        if free.dtype != bool:
            raise MapError(f"free must be a boolean array, got dtype {free.dtype}")
        if not free.any():
            raise MapError(f"map {name!r} has no free cell: nothing can move in it")
        check_range("resolution", resolution, 0.0, low_open=True)
        self.free = np.ascontiguousarray(free)
        self.resolution = float(resolution)
        self.name = name
        self.rows, self.cols = free.shape
        self.width = self.cols * self.resolution
        self.height = self.rows * self.resolution
        # A ring of wall around the grid: clipping any index into the padded grid then answers
        # "free?" for points anywhere, inside or outside, with one fancy-indexing operation.
        self._padded = np.pad(self.free, 1, constant_values=False)
        self._runs = _free_runs(self.free)
        # Summed-area table of wall cells: walls inside any cell rectangle in O(1).
        self._walls_sat = np.pad(
            (~self.free).astype(np.int64).cumsum(0).cumsum(1), ((1, 0), (1, 0))
        )

    # ------------------------------------------------------------------ construction
    @classmethod
    def from_cells(
        cls,
        cells: Iterable[tuple[int, int]],
        cell_size: float = 3.0,
        border: int = 1,
        name: str = "cells",
    ) -> "Arena":
        """Build an arena whose free space is the given grid cells ``(ix, iy)``.

        The cells are shifted so the lowest index sits ``border`` cells from the edge, leaving a
        ring of wall around the world.
        """
        cells = np.array(list(cells), dtype=int).reshape(-1, 2)
        if len(cells) == 0:
            raise MapError("cells is empty: a world needs at least one free cell")
        check_range("border", border, 0, integer=True)
        shifted = cells - cells.min(axis=0) + border
        cols, rows = shifted.max(axis=0) + 1 + border
        free = np.zeros((rows, cols), dtype=bool)
        free[shifted[:, 1], shifted[:, 0]] = True
        return cls(free, resolution=cell_size, name=name)

    @classmethod
    def from_bitmap(
        cls, path: str | Path, resolution: float = 1.0, name: str | None = None
    ) -> "Arena":
        """Load a bitmap map: PNG/PGM/BMP (dark pixels = wall) or NPY (True/nonzero = free).

        Args:
            path: the file.
            resolution: metres per pixel (the papers use 1 m).
            name: label; defaults to the file's stem.

        """
        path = Path(path)
        if not path.is_file():
            raise MapError(f"map file {str(path)!r} does not exist")
        name = name or path.stem
        if path.suffix.lower() == ".npy":
            try:
                image = np.load(path, allow_pickle=False)
            except Exception as exc:  # numpy raises several types for a bad file
                raise MapError(
                    f"map file {str(path)!r} is not a readable .npy array: {exc}"
                ) from exc
            if image.ndim != 2:
                raise MapError(f"map file {str(path)!r} must hold a 2-D array, got {image.shape}")
            free_top_down = image.astype(bool)
        else:
            from PIL import Image, UnidentifiedImageError

            try:
                with Image.open(path) as img:
                    grey = np.asarray(img.convert("L"), dtype=float)
            except (UnidentifiedImageError, OSError) as exc:
                raise MapError(
                    f"map file {str(path)!r} is not a readable image (PNG, PGM, BMP or .npy): {exc}"
                ) from exc
            free_top_down = grey >= 128.0
        # Images store the top row first; the arena stores the south row first.
        return cls(free_top_down[::-1].copy(), resolution=resolution, name=name)

    # ------------------------------------------------------------------ queries
    @property
    def free_area(self) -> float:
        """Area of free space (m^2)."""
        return float(self.free.sum()) * self.resolution**2

    def cell_of(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Grid indices ``(ix, iy)`` of points (may lie outside the grid)."""
        points = np.asarray(points, dtype=float)
        idx = np.floor(points / self.resolution).astype(np.int64)
        return idx[..., 0], idx[..., 1]

    def cell_centre(self, ix: np.ndarray, iy: np.ndarray) -> np.ndarray:
        """Centre (m) of grid cells."""
        return (np.stack([ix, iy], axis=-1) + 0.5) * self.resolution

    def free_at(self, ix: np.ndarray, iy: np.ndarray) -> np.ndarray:
        """True where cell ``(ix, iy)`` is inside the grid and free."""
        rows = np.minimum(np.maximum(np.asarray(iy) + 1, 0), self.rows + 1)
        cols = np.minimum(np.maximum(np.asarray(ix) + 1, 0), self.cols + 1)
        return self._padded[rows, cols]

    def is_free(self, points: np.ndarray) -> np.ndarray:
        """True for points that lie in free space."""
        return self.free_at(*self.cell_of(points))

    def raycast(self, origins: np.ndarray, directions: np.ndarray, max_range: float) -> np.ndarray:
        """Distance from each origin along its direction to the first wall, capped at max_range.

        Exact for grid walls: every ray is walked cell boundary by cell boundary, all rays in one
        vectorised loop of at most ``max_range / resolution + 2`` iterations. An origin inside a
        wall returns 0.

        Args:
            origins: ``(n, 2)`` start points (m).
            directions: ``(n, 2)`` directions (normalised here).
            max_range: the sensor's range (m).

        """
        origins = np.atleast_2d(np.asarray(origins, dtype=float))
        directions = np.atleast_2d(np.asarray(directions, dtype=float))
        origins, directions = np.broadcast_arrays(origins, directions)
        n = origins.shape[0]
        norm = np.linalg.norm(directions, axis=1)
        d = directions / np.where(norm > 0, norm, 1.0)[:, None]
        res = self.resolution
        ix, iy = self.cell_of(origins)
        step_x = np.where(d[:, 0] > 0, 1, -1)
        step_y = np.where(d[:, 1] > 0, 1, -1)
        with np.errstate(divide="ignore", invalid="ignore"):
            inv_x = np.where(d[:, 0] != 0, 1.0 / np.abs(d[:, 0]), np.inf)
            inv_y = np.where(d[:, 1] != 0, 1.0 / np.abs(d[:, 1]), np.inf)
            next_x = np.where(d[:, 0] > 0, (ix + 1) * res - origins[:, 0], origins[:, 0] - ix * res)
            next_y = np.where(d[:, 1] > 0, (iy + 1) * res - origins[:, 1], origins[:, 1] - iy * res)
            t_max_x = np.where(np.isfinite(inv_x), next_x * inv_x, np.inf)
            t_max_y = np.where(np.isfinite(inv_y), next_y * inv_y, np.inf)
        t_delta_x = res * inv_x
        t_delta_y = res * inv_y
        dist = np.full(n, float(max_range))
        active = self.free_at(ix, iy)
        dist[~active] = 0.0
        for _ in range(int(np.ceil(max_range / res)) * 2 + 2):
            if not active.any():
                break
            go_x = t_max_x < t_max_y
            t_here = np.where(go_x, t_max_x, t_max_y)
            beyond = t_here >= max_range
            active &= ~beyond
            ix = np.where(active & go_x, ix + step_x, ix)
            iy = np.where(active & ~go_x, iy + step_y, iy)
            hit = active & ~self.free_at(ix, iy)
            dist[hit] = t_here[hit]
            active &= ~hit
            t_max_x = np.where(go_x, t_max_x + t_delta_x, t_max_x)
            t_max_y = np.where(~go_x, t_max_y + t_delta_y, t_max_y)
        return dist

    def cardinal_distances(self, points: np.ndarray, max_range: float) -> np.ndarray:
        """Distances ``(n, 4)`` to the nearest wall to the N, E, S and W of each point.

        Exact and loop-free: the distance to the edge of the point's own cell plus the run of
        free cells beyond it in that direction (precomputed per cell), capped at ``max_range``.
        """
        points = np.atleast_2d(np.asarray(points, dtype=float))
        res = self.resolution
        ix, iy = self.cell_of(points)
        inside = self.free_at(ix, iy)
        ix = np.minimum(np.maximum(ix, 0), self.cols - 1)
        iy = np.minimum(np.maximum(iy, 0), self.rows - 1)
        x, y = points[:, 0], points[:, 1]
        edge = np.stack(
            [(iy + 1) * res - y, (ix + 1) * res - x, y - iy * res, x - ix * res], axis=1
        )
        dist = edge + self._runs[:, iy, ix].T * res
        dist[~inside] = 0.0
        return np.minimum(dist, max_range)

    def walls_in_rectangle(self, ix0, iy0, ix1, iy1) -> np.ndarray:
        """Number of wall cells in the cell rectangles spanned by two corner cells (inclusive).

        Corners are clipped to the grid (cells outside it are walls but are not counted here).
        """
        lo_x = np.minimum(np.maximum(np.minimum(ix0, ix1), 0), self.cols - 1)
        hi_x = np.minimum(np.maximum(np.maximum(ix0, ix1), 0), self.cols - 1) + 1
        lo_y = np.minimum(np.maximum(np.minimum(iy0, iy1), 0), self.rows - 1)
        hi_y = np.minimum(np.maximum(np.maximum(iy0, iy1), 0), self.rows - 1) + 1
        t = self._walls_sat
        return t[hi_y, hi_x] - t[lo_y, hi_x] - t[hi_y, lo_x] + t[lo_y, lo_x]

    def segment_crosses_wall(self, start: np.ndarray, end: np.ndarray) -> np.ndarray:
        """True for each segment ``start -> end`` that enters a wall cell anywhere.

        A segment lies inside the rectangle of cells spanned by its end cells, so when that
        rectangle holds no wall (a summed-area-table lookup) it is clear; only the others are
        walked cell by cell.
        """
        start = np.atleast_2d(np.asarray(start, dtype=float))
        end = np.atleast_2d(np.asarray(end, dtype=float))
        start, end = np.broadcast_arrays(start, end)
        sx, sy = self.cell_of(start)
        ex, ey = self.cell_of(end)
        out = ~self.free_at(sx, sy) | ~self.free_at(ex, ey)
        clear = self.walls_in_rectangle(sx, sy, ex, ey) == 0
        moving = ~out & ~clear
        if moving.any():
            length = np.hypot(*(end[moving] - start[moving]).T)
            reach = self.raycast(
                start[moving], end[moving] - start[moving], float(length.max()) + self.resolution
            )
            out[moving] = reach < length
        return out

    def line_of_sight(self, start: np.ndarray, end: np.ndarray) -> np.ndarray:
        """True for each pair of points that see each other (no wall cell between them)."""
        return ~self.segment_crosses_wall(start, end)

    def free_cell_centres(self) -> np.ndarray:
        """Centres (m) of all free grid cells, ``(k, 2)``."""
        iy, ix = np.nonzero(self.free)
        return self.cell_centre(ix, iy)

    def __repr__(self) -> str:
        return (
            f"Arena({self.name!r}, {self.cols}x{self.rows} px of {self.resolution:g} m, "
            f"free area {self.free_area:g} m^2)"
        )


def _free_runs(free: np.ndarray) -> np.ndarray:
    """``runs[d, iy, ix]``: free cells beyond cell (ix, iy) in direction d (N, E, S, W)."""
    rows, cols = free.shape
    runs = np.zeros((4, rows, cols), dtype=np.int64)
    f = free.astype(np.int64)
    for iy in range(rows - 2, -1, -1):  # north: rows above
        runs[0, iy] = f[iy + 1] * (runs[0, iy + 1] + 1)
    for iy in range(1, rows):  # south
        runs[2, iy] = f[iy - 1] * (runs[2, iy - 1] + 1)
    for ix in range(cols - 2, -1, -1):  # east
        runs[1, :, ix] = f[:, ix + 1] * (runs[1, :, ix + 1] + 1)
    for ix in range(1, cols):  # west
        runs[3, :, ix] = f[:, ix - 1] * (runs[3, :, ix - 1] + 1)
    return runs
