"""A virtual pheromone field on the arena's grid: disc deposits, exponential decay, queries.

Arnaldo et al. (2018) store virtual pheromone in the landed robots; we keep it as one numpy
grid over the arena (one value per pixel) that every robot reads and writes. Intensity decays
exponentially at rate ``decay`` (C_eps, 1/s): a value ``q`` deposited at ``t0`` is
``q * exp(-decay * (t - t0))`` at ``t``. The decay is applied exactly and lazily (the whole grid
is scaled once per query time, never per deposit), so the field matches the closed form at any
time whatever the query pattern.

Every query and deposit is vectorised over many robots at once: the cells of a disc of radius r
are a fixed table of offsets, so n discs are one ``(n, k)`` fancy-indexing operation.
"""

import numpy as np
from scipy.signal import fftconvolve

from abm.errors import ConfigError, check_range

__all__ = ["PheromoneField", "disc_offsets"]


def disc_offsets(
    radius: float, resolution: float = 1.0, stride: int = 1
) -> tuple[np.ndarray, np.ndarray]:
    """Integer cell offsets ``(dy, dx)`` of the cells whose centres lie within ``radius`` (m),
    on a lattice of every ``stride``-th cell (a coarser sensor).
    """
    check_range("radius", radius, 0.0)
    check_range("stride", stride, 1, integer=True)
    r = int(np.floor(radius / resolution))
    r -= r % stride
    dy, dx = np.mgrid[-r : r + 1 : stride, -r : r + 1 : stride]
    inside = np.hypot(dx, dy) * resolution <= radius + 1e-9
    return dy[inside].ravel(), dx[inside].ravel()


class PheromoneField:
    """Pheromone intensity per grid pixel.

    Args:
        shape: ``(rows, cols)`` of the grid (row 0 is the south edge, as in :class:`Arena`).
        resolution: side of one pixel (m).
        decay: C_eps, exponential decay rate (1/s); 0 means no decay.
        mask: optional boolean ``(rows, cols)``; deposits land only where it is True (free space).
        time: the clock's time when the field is created (s).

    """

    def __init__(
        self,
        shape: tuple[int, int],
        resolution: float = 1.0,
        decay: float = 0.0,
        mask: np.ndarray | None = None,
        time: float = 0.0,
    ) -> None:
        rows, cols = (int(s) for s in shape)
        if rows <= 0 or cols <= 0:
            raise ConfigError(f"shape must be two positive integers, got {shape!r}")
        check_range("resolution", resolution, 0.0, low_open=True)
        check_range("decay", decay, 0.0)
        if mask is not None:
            mask = np.asarray(mask, dtype=bool)
            if mask.shape != (rows, cols):
                raise ConfigError(f"mask must have shape {(rows, cols)}, got {mask.shape}")
        self.rows, self.cols = rows, cols
        self.resolution = float(resolution)
        self.decay = float(decay)
        self.mask = mask
        self.time = float(time)
        # The grid is stored with a margin of ``_pad`` pixels of zero on every side (never
        # written), so a disc near the edge is read and written without bounds checks.
        self._pad = 0
        self._store = np.zeros((rows, cols))
        self._mask_store = np.ones((rows, cols), dtype=bool) if mask is None else mask.copy()
        self._discs: dict[tuple[float, int, float], tuple] = {}
        self._sums: dict[tuple[float, int, float], tuple[np.ndarray, np.ndarray]] = {}

    @property
    def _grid(self) -> np.ndarray:
        p = self._pad
        return self._store[p : p + self.rows, p : p + self.cols]

    # ------------------------------------------------------------------ time
    @property
    def values(self) -> np.ndarray:
        """The intensity grid at :attr:`time` (a view: do not write)."""
        return self._grid

    def advance(self, time: float) -> None:
        """Decay the field to simulated ``time`` (s), exactly: ``exp(-decay * elapsed)``."""
        elapsed = float(time) - self.time
        if elapsed < -1e-9:
            raise ConfigError(f"time must not go backwards: field at {self.time}, got {time}")
        if elapsed > 0 and self.decay > 0:
            self._store *= np.exp(-self.decay * elapsed)
        self.time = max(self.time, float(time))

    def total(self) -> float:
        """Sum of all intensity (intensity x pixels)."""
        return float(self._store.sum())

    # ------------------------------------------------------------------ writing
    def deposit(
        self,
        points: np.ndarray,
        radius: float,
        intensity: float | np.ndarray,
        time: float | None = None,
    ) -> None:
        """Add ``intensity`` to every pixel within ``radius`` (m) of each point.

        Args:
            points: ``(n, 2)`` positions (m).
            radius: disc radius (m): C_rw for a flying robot, C_rb for a landing footprint.
            intensity: one value or one per point (C_dw, C_db).
            time: deposit time (s); the field is first decayed to it.

        """
        if time is not None:
            self.advance(time)
        points = np.atleast_2d(np.asarray(points, dtype=float))
        if len(points) == 0:
            return
        intensity = np.broadcast_to(np.asarray(intensity, dtype=float), (len(points),))
        flat, _ = self._cells(points, radius)
        weights = np.broadcast_to(intensity[:, None], flat.shape)
        valid = self._mask_store.ravel()[flat]
        flat, weights = flat[valid], weights[valid]
        added = np.bincount(flat.ravel(), weights=weights.ravel(), minlength=self._store.size)
        self._store += added.reshape(self._store.shape)

    # ------------------------------------------------------------------ reading
    def value_at(self, points: np.ndarray) -> np.ndarray:
        """Intensity of the pixel under each point (0 outside the grid)."""
        points = np.atleast_2d(np.asarray(points, dtype=float))
        ix = np.floor(points[:, 0] / self.resolution).astype(np.int64)
        iy = np.floor(points[:, 1] / self.resolution).astype(np.int64)
        inside = (ix >= 0) & (ix < self.cols) & (iy >= 0) & (iy < self.rows)
        out = np.zeros(len(points))
        out[inside] = self._grid[iy[inside], ix[inside]]
        return out

    def lower_direction(
        self,
        points: np.ndarray,
        radius: float,
        stride: int = 1,
        falloff: float = 2.0,
        relative: bool = True,
    ) -> np.ndarray:
        """f1 of Arnaldo et al.: a vector towards less pheromone, ``(n, 2)``.

        ``f1 = -sum_c v_c / |v_c|^(1 + falloff) * field(p + v_c)`` over the pixels ``c`` within
        ``radius`` of ``p`` (``v_c`` the offset from the robot's pixel to ``c``): each
        pheromone reading pushes away from itself with an importance ``1 / |v_c|^falloff``.
        ``falloff = 2`` is the paper's text ("the importance of a detected pheromone decreases
        with the square of the distance"); ``falloff = 1`` is its formula read literally
        (``v / |v|^2``). Not normalised. ``stride`` reads only every stride-th pixel in x and y
        (the sensor's discretisation of the circle); the sum is then scaled by ``stride**2``.

        ``relative`` (default): only pixels inside the mask are read, each relative to the
        reading under the robot, ``field(p + v_c) - field(p)``. In open space this is the
        same vector (the ``field(p)`` terms of a full disc cancel); where walls or the grid's
        edge cut the disc it stops the cut-away part, which can hold no pheromone, from
        reading as the least marked place around and pulling robots into walls.
        """
        check_range("falloff", falloff, 0.0)
        points = np.atleast_2d(np.asarray(points, dtype=float))
        if len(points) == 0:
            return np.zeros((0, 2))
        flat, weights = self._cells(points, radius, stride, falloff)
        store = self._store.ravel()
        f1 = store[flat] @ weights
        if relative:
            centre = flat[:, self._disc(radius, stride, falloff)[3]]
            sx, sy = self._mask_sums(radius, stride, falloff)
            f1 -= store[centre][:, None] * np.stack([sx[centre], sy[centre]], axis=1)
        return -f1 * stride**2

    def gradient(self, points: np.ndarray) -> np.ndarray:
        """Central-difference gradient (intensity per m) at each point, ``(n, 2)``."""
        points = np.atleast_2d(np.asarray(points, dtype=float))
        gy, gx = np.gradient(self._grid, self.resolution)
        ix = np.clip(np.floor(points[:, 0] / self.resolution).astype(np.int64), 0, self.cols - 1)
        iy = np.clip(np.floor(points[:, 1] / self.resolution).astype(np.int64), 0, self.rows - 1)
        return np.stack([gx[iy, ix], gy[iy, ix]], axis=1)

    # ------------------------------------------------------------------ plumbing
    def _disc(
        self, radius: float, stride: int = 1, falloff: float = 2.0
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, int]:
        """Offsets ``dy, dx`` of a disc, its f1 weights ``(k, 2)`` and the index of (0, 0)."""
        key = (float(radius), int(stride), float(falloff))
        if key not in self._discs:
            dy, dx = disc_offsets(radius, self.resolution, stride)
            v = np.stack([dx, dy], axis=1) * self.resolution
            d = np.hypot(v[:, 0], v[:, 1])
            scale = np.zeros_like(d)
            scale[d > 0] = d[d > 0] ** -(1.0 + falloff)
            centre = int(np.nonzero((dx == 0) & (dy == 0))[0][0])
            self._discs[key] = (dy, dx, v * scale[:, None], centre)
        return self._discs[key]

    def _mask_sums(
        self, radius: float, stride: int, falloff: float
    ) -> tuple[np.ndarray, np.ndarray]:
        """Per pixel of the padded store, the f1 weights summed over the disc's masked pixels
        (flat arrays, x and y): what ``field(p)`` is multiplied by in a relative reading.
        """
        key = (float(radius), int(stride), float(falloff))
        if key not in self._sums:
            dy, dx, weights, _ = self._disc(radius, stride, falloff)
            r = int(max(np.abs(dx).max(), np.abs(dy).max()))
            mask = self._mask_store.astype(float)
            sums = []
            for axis in (0, 1):
                kernel = np.zeros((2 * r + 1, 2 * r + 1))
                kernel[dy + r, dx + r] = weights[:, axis]
                # correlate: out[p] = sum_k kernel[k] * mask[p + k - r]
                sums.append(fftconvolve(mask, kernel[::-1, ::-1], mode="same").ravel())
            self._sums[key] = (sums[0], sums[1])
        return self._sums[key]

    def _cells(
        self, points: np.ndarray, radius: float, stride: int = 1, falloff: float = 2.0
    ) -> tuple[np.ndarray, np.ndarray]:
        """Flat indices ``(n, k)`` into the padded store of each point's disc, and f1 weights.

        Points outside the grid are clamped to its edge pixels.
        """
        dy, dx, weights, _ = self._disc(radius, stride, falloff)
        reach = int(max(np.abs(dx).max(), np.abs(dy).max()))
        if reach > self._pad:
            self._repad(reach)
        p = self._pad
        width = self.cols + 2 * p
        ix = np.clip(np.floor(points[:, 0] / self.resolution).astype(np.int64), 0, self.cols - 1)
        iy = np.clip(np.floor(points[:, 1] / self.resolution).astype(np.int64), 0, self.rows - 1)
        centre = (iy + p) * width + (ix + p)
        flat = centre[:, None] + (dy * width + dx)[None, :]
        return flat, weights

    def _repad(self, pad: int) -> None:
        grid = self._grid.copy()
        self._pad = pad
        self._store = np.pad(grid, pad)
        mask = np.ones((self.rows, self.cols), dtype=bool) if self.mask is None else self.mask
        self._mask_store = np.pad(mask, pad)
        self._sums.clear()
