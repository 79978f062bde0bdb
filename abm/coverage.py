"""Coverage rasters: which free area has been inside a robot's sensor disc, and since when.

A :class:`CoverageRaster` splits the arena's grid into square pixels and marks a free pixel
covered once a sensor sees it: its centre lies within the sensor radius and, with line of
sight, the straight segment from the sensor to the centre enters no wall cell. It keeps the
time each pixel was first covered, so the area covered at any earlier time (a replay, a
coverage curve) follows without re-running the model. Every model that covers uses this one
implementation; the work over sensors x pixels is a compiled loop.

Two disc conventions, both in use in the models' metrics:

- ``around="point"``: pixels whose centre lies within ``radius`` of the sensor itself;
- ``around="cell"``: pixels whose centre lies within ``radius`` of the centre of the sensor's
  own pixel (a disc fixed on the grid, as a sensor that reports whole cells).
"""

import math

import numpy as np
from numba import njit

from abm.arena import Arena
from abm.disc_cells import disc_offsets
from abm.errors import ConfigError, check_choice, check_range

__all__ = ["MAX_PIXELS", "CoverageRaster", "raster_bytes"]

#: Most pixels a coverage raster may have (ours): with its first-covered times (8 bytes each)
#: that is about a gigabyte.
MAX_PIXELS = 1e8


#: Bytes a raster keeps per raster pixel: free and covered (1 + 1), first-covered time (8).
BYTES_PER_PIXEL = 10


def raster_bytes(shape: tuple[int, int], resolution: float, pixel: float | None = None) -> float:
    """Bytes a :class:`CoverageRaster` of ``pixel`` m takes over a map of ``shape`` pixels of
    ``resolution`` m (for the loaders' memory check, :mod:`abm.memory`, before it exists).
    """
    if pixel is None:
        return BYTES_PER_PIXEL * float(shape[0]) * float(shape[1])
    _check_pixels(shape, resolution, pixel)
    split = max(1, int(round(resolution / pixel)))
    return BYTES_PER_PIXEL * float(shape[0]) * float(shape[1]) * split * split


def _check_pixels(shape: tuple[int, int], resolution: float, pixel: float) -> None:
    """Refuse a raster of more than :data:`MAX_PIXELS` pixels."""
    split = resolution / pixel
    size = float(shape[0]) * float(shape[1])
    if split * split * size > MAX_PIXELS:
        raise ConfigError(
            f"pixel={pixel!r} m splits this {shape[1] * resolution:g} x "
            f"{shape[0] * resolution:g} m arena into more than {MAX_PIXELS:.0e} pixels; pixel "
            f"must be >= {resolution * np.sqrt(size / MAX_PIXELS):.3g} m here"
        )


class CoverageRaster:
    """A raster over the arena marking the free pixels sensors have seen.

    Args:
        arena: the world.
        radius: sensing radius (m).
        pixel: raster pixel side (m); the arena's resolution is split into whole pixels.
            None: the arena's resolution.
        line_of_sight: walls block the view.
        around: ``"point"`` or ``"cell"``, the centre of the sensing disc (see the module).

    """

    def __init__(
        self,
        arena: Arena,
        radius: float,
        pixel: float | None = None,
        line_of_sight: bool = True,
        around: str = "point",
    ) -> None:
        check_range("radius", radius, 0.0, low_open=True)
        check_choice("around", around, ("point", "cell"))
        pixel = arena.resolution if pixel is None else pixel
        check_range("pixel", pixel, 0.0, low_open=True)
        self.arena = arena
        self.radius = float(radius)
        _check_pixels(arena.free.shape, arena.resolution, pixel)
        split = arena.resolution / pixel
        self.subdivision = max(1, int(round(split)))
        self.pixel = arena.resolution / self.subdivision
        self.line_of_sight = bool(line_of_sight)
        self.around = around
        self.free = np.ascontiguousarray(
            np.repeat(np.repeat(arena.free, self.subdivision, axis=0), self.subdivision, axis=1)
        )
        self.covered = np.zeros_like(self.free)
        #: Simulated time (s) each pixel was first covered; inf where it never was.
        self.first_covered = np.full(self.free.shape, np.inf)
        self._n_free = int(self.free.sum())
        self._n_covered = 0
        reach = max(self.free.shape)  # a farther offset lands on no pixel of the raster
        if around == "cell":
            dy, dx = disc_offsets(self.radius, self.pixel, max_offset=reach)
        else:
            r = int(min(np.ceil(self.radius / self.pixel), reach))
            dy, dx = (a.ravel() for a in np.mgrid[-r : r + 1, -r : r + 1])
        self._dy = np.ascontiguousarray(dy, dtype=np.int64)
        self._dx = np.ascontiguousarray(dx, dtype=np.int64)

    @property
    def fraction(self) -> float:
        """Fraction of free pixels covered, in [0, 1]."""
        return self._n_covered / self._n_free

    @property
    def area(self) -> float:
        """Covered free area (m^2)."""
        return self._n_covered * self.pixel**2

    def visible(self, points: np.ndarray, skip: np.ndarray | None = None) -> np.ndarray:
        """Row-major indices of the free pixels sensors at ``points`` see (with repeats).

        Args:
            points: ``(n, 2)`` sensor positions (m).
            skip: boolean raster of pixels not to test (e.g. those already covered).

        """
        points = np.ascontiguousarray(np.atleast_2d(np.asarray(points, dtype=float)))
        if len(points) == 0:
            return np.zeros(0, dtype=np.int64)
        skip = np.zeros_like(self.free) if skip is None else skip
        cells, owners = _disc_pixels(
            self.free,
            skip,
            points,
            self.pixel,
            self._dy,
            self._dx,
            self.radius,
            self.around == "point",
        )
        if self.line_of_sight and len(cells):
            iy, ix = np.divmod(cells, self.free.shape[1])
            ends = (np.stack([ix, iy], axis=1) + 0.5) * self.pixel
            cells = cells[~self.arena.segment_crosses_wall(points[owners], ends)]
        return cells

    def seen_fraction(self, points: np.ndarray) -> float:
        """Fraction of the free area sensors at ``points`` see now (covered or not)."""
        return len(np.unique(self.visible(points))) / self._n_free

    def stamp(self, points: np.ndarray, time: float = 0.0) -> float:
        """Mark what sensors at ``points`` see at simulated ``time`` (s); return the newly
        covered area (m^2).
        """
        cells = np.unique(self.visible(points, skip=self.covered))
        self.covered.ravel()[cells] = True
        self.first_covered.ravel()[cells] = time
        self._n_covered += len(cells)
        return len(cells) * self.pixel**2

    def covered_at(self, time: float) -> np.ndarray:
        """Boolean raster of the pixels covered at or before ``time`` (s)."""
        return self.first_covered <= time

    def fraction_at(self, times: np.ndarray) -> np.ndarray:
        """Fraction of the free area covered at or before each of ``times`` (s)."""
        first = np.sort(self.first_covered[np.isfinite(self.first_covered)])
        return np.searchsorted(first, np.asarray(times, dtype=float), side="right") / self._n_free


@njit(cache=True)
def _disc_pixels(free, skip, points, pixel, dy, dx, radius, around_point):
    """Free, not skipped pixels at the offsets around each point's pixel that lie within
    ``radius`` (of the point, or of its pixel's centre), and the point's row for each.
    """
    rows, cols = free.shape
    cells = np.empty(points.shape[0] * dy.shape[0], dtype=np.int64)
    owner = np.empty_like(cells)
    m = 0
    for i in range(points.shape[0]):
        ix = int(np.floor(points[i, 0] / pixel))
        iy = int(np.floor(points[i, 1] / pixel))
        for k in range(dy.shape[0]):
            cx = ix + dx[k]
            cy = iy + dy[k]
            if not (0 <= cx < cols and 0 <= cy < rows) or not free[cy, cx] or skip[cy, cx]:
                continue
            if around_point:
                ex = (cx + 0.5) * pixel - points[i, 0]
                ey = (cy + 0.5) * pixel - points[i, 1]
                if math.hypot(ex, ey) > radius:
                    continue
            cells[m] = cy * cols + cx
            owner[m] = i
            m += 1
    return cells[:m], owner[:m]
