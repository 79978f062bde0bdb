"""A virtual pheromone field on the arena's grid: disc deposits, exponential decay, queries.

A swarm may store virtual pheromone in its robots; we keep it as one numpy
grid over the arena (one value per pixel) that every robot reads and writes. Intensity decays
exponentially at rate ``decay`` (C_eps, 1/s): a value ``q`` deposited at ``t0`` is
``q * exp(-decay * (t - t0))`` at ``t``. The decay is applied exactly and lazily (the whole grid
is scaled once per query time, never per deposit), so the field matches the closed form at any
time whatever the query pattern.

Every query and deposit serves many robots in one call: the cells of a disc of radius r are a
fixed table of flat offsets into the grid (stored with a zero margin as wide as the largest
disc, so no bounds checks), walked by compiled (numba) loops over robots x offsets.
"""

import numpy as np
from numba import njit

from abm import portable
from abm.disc_cells import disc_offsets
from abm.disc_sight import cached_disc_visibility
from abm.errors import ConfigError, check_range

__all__ = ["PheromoneField", "disc_offsets", "field_bytes"]


_NO_TABLE = np.zeros((1, 1), dtype=np.uint8)
_NO_WEIGHTS = np.zeros((0, 2))


@njit(cache=True)
def _cell(x, y, res, rows, cols, pad):
    """Flat index in the padded store and row-major index in the grid of the pixel under
    (x, y), clamped to the grid.
    """
    ix = min(max(int(np.floor(x / res)), 0), cols - 1)
    iy = min(max(int(np.floor(y / res)), 0), rows - 1)
    return (iy + pad) * (cols + 2 * pad) + ix + pad, iy * cols + ix


@njit(cache=True)
def _deposit_discs(store, mask, points, res, rows, cols, pad, offsets, intensity, table, use):
    """Add ``intensity[i]`` on the disc ``offsets`` (flat, padded store) around each point
    where the mask is True, or (``use`` a table) where the point's pixel sees the pixel.
    """
    for i in range(points.shape[0]):
        c, cell = _cell(points[i, 0], points[i, 1], res, rows, cols, pad)
        q = intensity[i]
        for k in range(offsets.shape[0]):
            j = c + offsets[k]
            if use:
                if not (table[cell, k >> 3] >> (7 - (k & 7))) & 1:
                    continue
            elif not mask[j]:
                continue
            store[j] += q


@njit(cache=True)
def _disc_sums(store, points, res, rows, cols, pad, offsets, wx, wy, here_weight):
    """``sum_k (wx[k], wy[k]) * store[pixel + offsets[k]]`` per point, ``(n, 2)``, minus
    ``store[pixel] * here_weight[cell]`` when ``here_weight`` has a row per grid cell (the
    relative reading; the weight is the disc's sum of weights over the masked pixels).
    """
    n = points.shape[0]
    out = np.zeros((n, 2))
    relative = here_weight.shape[0] == rows * cols
    for i in range(n):
        c, cell = _cell(points[i, 0], points[i, 1], res, rows, cols, pad)
        ax = 0.0
        ay = 0.0
        for k in range(offsets.shape[0]):
            v = store[c + offsets[k]]
            ax += wx[k] * v
            ay += wy[k] * v
        if relative:
            ax -= store[c] * here_weight[cell, 0]
            ay -= store[c] * here_weight[cell, 1]
        out[i, 0] = ax
        out[i, 1] = ay
    return out


@njit(cache=True)
def _visible_readings(store, points, res, rows, cols, pad, offsets, weights, table):
    """``sum_k weights[k] * (store[pixel + offsets[k]] - store[pixel])`` per point over the
    offsets its pixel sees (``table``), ``(n, 2)``.
    """
    n = points.shape[0]
    out = np.zeros((n, 2))
    for i in range(n):
        c, cell = _cell(points[i, 0], points[i, 1], res, rows, cols, pad)
        here = store[c]
        ax = 0.0
        ay = 0.0
        for k in range(offsets.shape[0]):
            if not (table[cell, k >> 3] >> (7 - (k & 7))) & 1:
                continue
            v = store[c + offsets[k]] - here
            ax += weights[k, 0] * v
            ay += weights[k, 1] * v
        out[i, 0] = ax
        out[i, 1] = ay
    return out


def field_bytes(
    shape: tuple[int, int],
    resolution: float,
    radii: tuple[float, ...] = (),
    seen_radii: tuple[float, ...] = (),
    relative_radii: tuple[float, ...] = (),
) -> dict[str, float]:
    """Bytes a :class:`PheromoneField` over a map of ``shape`` pixels takes, by part (for the
    loaders' memory check, :mod:`abm.memory`, before it exists).

    Args:
        shape: ``(rows, cols)``.
        resolution: pixel side (m).
        radii: every disc radius (m) it deposits or reads with (they widen the zero margin).
        seen_radii: the radii used with ``line_of_sight``: each has a visibility table of one
            bit per disc pixel per grid pixel.
        relative_radii: the radii read as relative readings without line of sight: each has
            two weights (float64) per grid pixel, and 40 bytes a pixel more while they are
            computed (the pixel centres and the mask as floats).

    """
    rows, cols = (float(s) for s in shape)
    # A disc is clipped to the grid (an offset beyond its larger side lands on no pixel).
    reach = min(max([0.0, *(np.ceil(r / resolution) for r in radii)]), max(rows, cols))
    out = {"pheromone field": 9.0 * (rows + 2 * reach) * (cols + 2 * reach)}
    for r in sorted(set(seen_radii)):
        k = len(disc_offsets(r, resolution, 1, int(max(rows, cols)))[0])
        out[f"pheromone visibility, {r:g} m disc"] = rows * cols * (np.ceil(k / 8) + 1)
    for r in sorted(set(relative_radii)):
        out[f"pheromone weights, {r:g} m disc"] = 56.0 * rows * cols
    return out


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
        self._tables: dict[tuple[float, int], np.ndarray] = {}
        self._flat: dict[tuple[float, int], np.ndarray] = {}
        self._derived: dict[tuple, object] = {}

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
            self._store *= portable.exp(-self.decay * elapsed)
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
        line_of_sight: bool = False,
    ) -> None:
        """Add ``intensity`` to every pixel within ``radius`` (m) of each point.

        Args:
            points: ``(n, 2)`` positions (m).
            radius: disc radius (m): C_rw for a flying robot, C_rb for a landing footprint.
            intensity: one value or one per point (C_dw, C_db).
            time: deposit time (s); the field is first decayed to it.
            line_of_sight: only on the pixels the point's pixel sees (the mask's False pixels
                are walls, :mod:`abm.disc_sight`); otherwise on the whole disc within the mask.

        """
        if time is not None:
            self.advance(time)
        points = np.atleast_2d(np.asarray(points, dtype=float))
        if len(points) == 0:
            return
        intensity = np.ascontiguousarray(
            np.broadcast_to(np.asarray(intensity, dtype=float), (len(points),))
        )
        offsets = self._offsets(radius)
        _deposit_discs(
            self._store.ravel(),
            self._mask_store.ravel(),
            points,
            self.resolution,
            self.rows,
            self.cols,
            self._pad,
            offsets,
            intensity,
            self._visibility(radius, 1) if line_of_sight else _NO_TABLE,
            line_of_sight,
        )

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
        line_of_sight: bool = False,
    ) -> np.ndarray:
        """The repulsion from pheromone: a vector towards less pheromone, ``(n, 2)``.

        ``f1 = -sum_c v_c / |v_c|^(1 + falloff) * field(p + v_c)`` over the pixels ``c`` within
        ``radius`` of ``p`` (``v_c`` the offset from the robot's pixel to ``c``): each pheromone
        reading pushes away from itself with an importance ``1 / |v_c|^falloff``. ``falloff = 2``
        makes the importance of a reading fall with the square of its distance; ``falloff = 1``
        weights the offsets as ``v / |v|^2``. Not normalised. ``stride`` reads only every stride-th
        pixel in x and y (the sensor's discretisation of the circle); the sum is then scaled by
        ``stride**2``.

        ``relative`` (default): only pixels inside the mask are read, each relative to the
        reading under the robot, ``field(p + v_c) - field(p)``. In open space this is the
        same vector (the ``field(p)`` terms of a full disc cancel); where walls or the grid's
        edge cut the disc it stops the cut-away part, which can hold no pheromone, from
        reading as the least marked place around and pulling robots into walls.

        ``line_of_sight`` (implies ``relative``): read only the pixels the robot's pixel sees,
        with the mask's False pixels as walls (:mod:`abm.disc_sight`), so pheromone behind a
        wall neither pulls nor pushes.
        """
        check_range("falloff", falloff, 0.0)
        points = np.atleast_2d(np.asarray(points, dtype=float))
        if len(points) == 0:
            return np.zeros((0, 2))
        offsets = self._offsets(radius, stride)
        _, _, weights, _ = self._disc(radius, stride, falloff)
        grid = (self.resolution, self.rows, self.cols, self._pad)
        if line_of_sight:
            table = self._visibility(radius, stride)
            f1 = _visible_readings(self._store.ravel(), points, *grid, offsets, weights, table)
        else:
            wx, wy = self._split(radius, stride, falloff)
            here = self._here_weights(radius, stride, falloff) if relative else _NO_WEIGHTS
            f1 = _disc_sums(self._store.ravel(), points, *grid, offsets, wx, wy, here)
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
            dy, dx = disc_offsets(radius, self.resolution, stride, max(self.rows, self.cols))
            v = np.stack([dx, dy], axis=1) * self.resolution
            d = np.hypot(v[:, 0], v[:, 1])
            scale = np.zeros_like(d)
            scale[d > 0] = portable.power(d[d > 0], -(1.0 + falloff))
            centre = int(np.nonzero((dx == 0) & (dy == 0))[0][0])
            self._discs[key] = (dy, dx, v * scale[:, None], centre)
        return self._discs[key]

    def _visibility(self, radius: float, stride: int) -> np.ndarray:
        """The visibility table of the disc over the mask (built once, shared by equal masks)."""
        key = (float(radius), int(stride))
        if key not in self._tables:
            dy, dx, _, _ = self._disc(radius, stride)
            mask = np.ones((self.rows, self.cols), dtype=bool) if self.mask is None else self.mask
            self._tables[key] = cached_disc_visibility(mask, dy, dx)
        return self._tables[key]

    def _split(self, radius: float, stride: int, falloff: float) -> tuple[np.ndarray, np.ndarray]:
        """The disc's f1 weights as two contiguous arrays (x, y)."""
        key = ("split", float(radius), int(stride), float(falloff))
        if key not in self._derived:
            weights = self._disc(radius, stride, falloff)[2]
            self._derived[key] = (weights[:, 0].copy(), weights[:, 1].copy())
        return self._derived[key]

    def _here_weights(self, radius: float, stride: int, falloff: float) -> np.ndarray:
        """Per grid cell ``(rows * cols, 2)``: the f1 weights summed over the disc's masked
        pixels, what the reading under the robot is multiplied by in a relative reading.
        """
        key = ("here", float(radius), int(stride), float(falloff))
        if key not in self._derived:
            iy, ix = np.mgrid[0 : self.rows, 0 : self.cols]
            centres = (np.stack([ix.ravel(), iy.ravel()], axis=1) + 0.5) * self.resolution
            mask = self._mask_store.astype(float).ravel()
            wx, wy = self._split(radius, stride, falloff)
            offsets = self._offsets(radius, stride)  # may widen the margin: before ``grid``
            grid = (self.resolution, self.rows, self.cols, self._pad)
            self._derived[key] = _disc_sums(mask, centres, *grid, offsets, wx, wy, _NO_WEIGHTS)
        return self._derived[key]

    def _offsets(self, radius: float, stride: int = 1) -> np.ndarray:
        """Flat offsets in the padded store of the disc's pixels (widens the margin first)."""
        key = (float(radius), int(stride))
        if key not in self._flat:
            dy, dx, _, _ = self._disc(radius, stride)
            reach = int(max(np.abs(dx).max(), np.abs(dy).max()))
            if reach > self._pad:
                self._repad(reach)
            self._flat[key] = dy * (self.cols + 2 * self._pad) + dx
        return self._flat[key]

    def _repad(self, pad: int) -> None:
        grid = self._grid.copy()
        self._pad = pad
        self._store = np.pad(grid, pad)
        mask = np.ones((self.rows, self.cols), dtype=bool) if self.mask is None else self.mask
        self._mask_store = np.pad(mask, pad)
        self._flat.clear()
