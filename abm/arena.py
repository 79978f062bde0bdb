"""The arena: walls on an occupancy grid, free-space tests and exact vectorised raycasts.

The world is a boolean grid ``free[iy, ix]`` of square pixels of side ``resolution`` metres with
its origin at (0, 0): x grows east (columns), y grows north (rows). Everything outside the grid is
wall. Grid walls make every geometric query exact and cheap: a ray or a move is walked cell by
cell (Amanatides-Woo traversal) in compiled loops over all rays (:mod:`abm.gridkernels`).

The compiled kernels (numba) are imported by the queries that use them, not with this module:
a model's parameters name :class:`Arena` as a type, and checking them (``abm run MODEL
--help``, a refused parameter) should not wait for numba to load.
"""

from collections.abc import Callable, Iterable, Mapping
from pathlib import Path

import numpy as np

from abm.errors import ABMError, MapError, check_range
from abm.memory import check_map_memory

__all__ = [
    "ARENA_BYTES_PER_PIXEL",
    "Arena",
    "CARDINALS",
    "MAX_MAP_PIXELS",
    "MapParts",
    "map_parts",
]

#: Bytes an arena keeps per map pixel: the grid and its padded copy (1 + 1), the free runs in
#: four directions (4 x int32) and the summed-area table of walls (int64).
ARENA_BYTES_PER_PIXEL = 26
#: Bytes per pixel a bitmap file takes while it is decoded (the image, its grey copy and the
#: flipped grid; up to 4 bytes a pixel for an RGBA image), on top of the arena's own.
DECODE_BYTES_PER_PIXEL = 8

#: Most pixels a map may have whatever the memory (ours): 7 km x 7 km at 1 m a pixel. Below it,
#: what a map may cost is set by the memory its model needs (:mod:`abm.memory`).
MAX_MAP_PIXELS = 50_000_000

#: What a model allocates for a map of ``(rows, cols)`` pixels besides the arena: part name ->
#: bytes (its coverage raster, pheromone field, ...), for the memory check of the loaders.
MapParts = Callable[[tuple[int, int]], Mapping[str, float]]

#: Unit vectors of the four compass directions in the order N, E, S, W.
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
        if free.size > MAX_MAP_PIXELS:
            raise MapError(
                f"map {name!r} has {free.size:.3g} pixels, more than {MAX_MAP_PIXELS:.0e}"
            )
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
        #: The free grid with a ring of wall, ``padded[iy + 1, ix + 1]`` (what the kernels read).
        self.padded = np.pad(self.free, 1, constant_values=False)
        self.runs = _free_runs(self.free)
        # Summed-area table of wall cells: walls inside any cell rectangle in O(1).
        # (Built in place: no temporary copies of a large map.)
        self.walls_sat = np.zeros((self.rows + 1, self.cols + 1), dtype=np.int64)
        inner = self.walls_sat[1:, 1:]
        np.logical_not(self.free, out=inner, casting="unsafe")
        np.cumsum(inner, axis=0, out=inner)
        np.cumsum(inner, axis=1, out=inner)

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
        cls,
        path: str | Path,
        resolution: float = 1.0,
        name: str | None = None,
        parts: MapParts | None = None,
    ) -> "Arena":
        """Load a bitmap map: PNG/PGM/BMP (dark pixels = wall) or NPY (True/nonzero = free).

        The file's size is read from its header first, and the memory the arena and ``parts``
        would take is checked against the machine's budget (:mod:`abm.memory`) before any
        pixel is decoded.

        Args:
            path: the file.
            resolution: metres per pixel (default 1 m).
            name: label; defaults to the file's stem.
            parts: what the caller's model allocates for a map of this shape besides the
                arena (bytes by part), counted in the memory check.

        Raises:
            MapError: a missing, unreadable or odd file, no free pixel, or a map whose model
                would need more memory than the budget (the message gives both figures).

        """
        path = Path(path)
        if not path.is_file():
            raise MapError(f"map file {str(path)!r} does not exist")
        name = name or path.stem
        if path.suffix.lower() == ".npy":
            free_top_down = _read_npy(path, parts)
        else:
            free_top_down = _read_image(path, parts)
        # Images store the top row first; the arena stores the south row first.
        try:
            return cls(free_top_down[::-1].copy(), resolution=resolution, name=name)
        except MapError as exc:
            raise MapError(f"map file {str(path)!r}: {exc}") from exc

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
        return self.padded[rows, cols]

    def is_free(self, points: np.ndarray) -> np.ndarray:
        """True for points that lie in free space."""
        return self.free_at(*self.cell_of(points))

    def raycast(self, origins: np.ndarray, directions: np.ndarray, max_range: float) -> np.ndarray:
        """Distance from each origin along its direction to the first wall, capped at max_range.

        Exact for grid walls: every ray is walked cell boundary by cell boundary (compiled, see
        :mod:`abm.gridkernels`), except a ray with no wall within ``max_range`` of its origin
        (a summed-area-table lookup), which reads ``max_range`` at once, as its walk would.
        An origin inside a wall returns 0.

        Args:
            origins: ``(n, 2)`` start points (m), or one point ``(2,)`` for every ray (a
                sensor's sweep, without broadcasting it).
            directions: ``(n, 2)`` directions (need not be normalised).
            max_range: the sensor's range (m).

        """
        from abm import gridkernels

        origins = np.asarray(origins, dtype=float)
        if origins.shape == (2,):
            x, y = origins.tolist()
            return gridkernels.sweep(
                self.padded, self.walls_sat, self.resolution, x, y, _points(directions),
                float(max_range),
            )  # fmt: skip
        origins, directions = _point_pairs(origins, directions)
        return gridkernels.raycasts(
            self.padded, self.walls_sat, self.resolution, origins, directions, float(max_range)
        )

    def cardinal_distances(self, points: np.ndarray, max_range: float) -> np.ndarray:
        """Distances ``(n, 4)`` to the nearest wall to the N, E, S and W of each point.

        Exact and loop-free per point: the distance to the edge of the point's own cell plus the
        run of free cells beyond it in that direction (precomputed per cell), capped at
        ``max_range``; 0 for a point inside a wall.
        """
        from abm import gridkernels

        return gridkernels.cardinal_distances(
            self.padded, self.runs, self.resolution, _points(points), float(max_range)
        )

    def segment_crosses_wall(self, start: np.ndarray, end: np.ndarray) -> np.ndarray:
        """True for each segment ``start -> end`` that enters a wall cell anywhere.

        A segment lies inside the rectangle of cells spanned by its end cells, so when that
        rectangle holds no wall (a summed-area-table lookup) it is clear; only the others are
        walked cell by cell.
        """
        start, end = _point_pairs(start, end)
        from abm import gridkernels

        return gridkernels.segments_cross(self.padded, self.walls_sat, self.resolution, start, end)

    def within_reach(
        self,
        origin: np.ndarray,
        points: np.ndarray,
        max_range: float,
        *,
        shortest: float = 0.0,
        walls_block: bool = True,
    ) -> np.ndarray:
        """True for each point within ``max_range`` of ``origin`` and, if ``walls_block``, in
        its line of sight: a radio's links from one node, in one compiled pass.

        The same verdicts as ``np.hypot`` of ``points - origin`` (raised to ``shortest``)
        compared with ``max_range``, then :meth:`line_of_sight` for the points in range.
        """
        from abm import gridkernels

        x, y = np.asarray(origin, dtype=float).tolist()
        points = np.ascontiguousarray(np.asarray(points, dtype=float).reshape(-1, 2))
        return gridkernels.within_reach(
            self.padded, self.walls_sat, self.resolution, x, y, points, float(max_range),
            float(shortest), bool(walls_block),
        )  # fmt: skip

    def nearest_visible(
        self, points: np.ndarray, targets: np.ndarray, max_range: float
    ) -> np.ndarray:
        """Row of the nearest target within ``max_range`` and in line of sight of each point.

        -1 where no target qualifies; e.g. the beacon an explorer can communicate with.
        """
        from abm import gridkernels

        return gridkernels.nearest_visible(
            self.padded,
            self.walls_sat,
            self.resolution,
            _points(points),
            _points(np.asarray(targets, dtype=float).reshape(-1, 2)),
            float(max_range),
        )

    def wall_lengths(self, points: np.ndarray, targets: np.ndarray) -> np.ndarray:
        """``(n, m)``: metres of wall on the straight line from each point to each target.

        Exact for grid walls (the segment is walked cell boundary by cell boundary); what a
        radio model that attenuates per metre of wall crossed needs.
        """
        from abm import gridkernels

        return gridkernels.wall_lengths(
            self.padded,
            self.resolution,
            _points(points),
            _points(np.asarray(targets, dtype=float).reshape(-1, 2)),
        )

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


def _points(a: np.ndarray) -> np.ndarray:
    """Points as a contiguous ``(n, 2)`` float array, as the kernels read them."""
    return np.ascontiguousarray(np.atleast_2d(np.asarray(a, dtype=float)))


def _point_pairs(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two ``(n, 2)`` float arrays, broadcast against each other and contiguous for the kernels
    (arrays of one shape as they are: ``np.broadcast_arrays`` costs several microseconds).
    """
    a, b = _points(a), _points(b)
    if a.shape == b.shape:
        return a, b
    a, b = np.broadcast_arrays(a, b)
    return np.ascontiguousarray(a), np.ascontiguousarray(b)


def map_parts(
    shape: tuple[int, int], parts: MapParts | None = None, decoding: bool = True
) -> dict[str, float]:
    """Bytes a map of ``shape`` pixels takes, by part: the arena's grids (and decoding its
    file), then what ``parts`` says the model adds.
    """
    pixels = float(shape[0]) * float(shape[1])
    out = {"arena": ARENA_BYTES_PER_PIXEL * pixels}
    if decoding:
        out["decoding the file"] = DECODE_BYTES_PER_PIXEL * pixels
    if parts is not None:
        out.update(parts(shape))
    return out


def _check_size(path: Path, shape: tuple[int, ...], parts: MapParts | None) -> None:
    """Refuse a file map with too many pixels, or whose model would not fit in memory."""
    pixels = float(np.prod([float(n) for n in shape]))
    if pixels > MAX_MAP_PIXELS:
        raise MapError(
            f"map file {str(path)!r} has {pixels:.3g} pixels ({' x '.join(map(str, shape))}), "
            f"more than {MAX_MAP_PIXELS:.0e}"
        )
    check_map_memory(str(path), (int(shape[0]), int(shape[1])), map_parts(shape, parts))


#: The first bytes of every .npy file (numpy's format, version 1 to 3).
_NPY_MAGIC = b"\x93NUMPY"


def _read_npy(path: Path, parts: MapParts | None = None) -> np.ndarray:
    """The free grid of a .npy map, top row first (True / nonzero = free); shape and memory
    checked first. A NaN is neither wall nor free: a map holding one is refused.
    """
    where = str(path)
    if path.is_symlink():
        where += f" (a link to {str(path.resolve())!r})"
    with open(path, "rb") as f:
        head = f.read(len(_NPY_MAGIC))
    if head != _NPY_MAGIC:
        raise MapError(
            f"map file {where!r} is not a .npy array file: it does not begin with numpy's "
            "header (save the map with numpy.save, or give a PNG/PGM/BMP image)"
        )
    try:
        image = np.load(path, mmap_mode="r", allow_pickle=False)
    except Exception as exc:  # numpy raises several types for a bad file
        raise MapError(f"map file {where!r} is not a readable .npy array: {exc}") from exc
    if image.ndim != 2:
        raise MapError(f"map file {where!r} must hold a 2-D array, got {image.shape}")
    _check_size(path, image.shape, parts)
    if image.dtype.kind not in "biuf":
        raise MapError(f"map file {where!r} must hold booleans or numbers, got dtype {image.dtype}")
    if image.dtype.kind == "f":
        nan = int(np.isnan(image).sum())
        if nan:
            raise MapError(
                f"map file {where!r} holds {nan} NaN of {image.size} values: NaN is neither "
                "wall (0) nor free (nonzero); give every pixel a number"
            )
    return np.asarray(image).astype(bool)


#: Largest ``alpha * (255 - grey)`` (both 0..255) of a free pixel: blended over white by its
#: alpha, ``grey * a + 255 * (255 - a) >= 128 * 255``.
_FREE_BLEND = 127 * 255


def _read_image(path: Path, parts: MapParts | None = None) -> np.ndarray:
    """The free grid of a PNG/PGM/BMP map, top row first (grey >= 128 = free); the image's size
    and memory are checked from its header before its pixels are decoded.

    An image with transparency is read as it shows on a white page: each pixel's grey is
    blended with white by its alpha (a fully transparent pixel is free whatever its colour).
    An image transparent everywhere shows nothing and is refused.
    """
    import warnings

    from PIL import Image

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", Image.DecompressionBombWarning)  # checked below
            with Image.open(path) as img:
                _check_size(path, (img.height, img.width), parts)
                if "A" in img.getbands() or "transparency" in img.info:
                    grey_alpha = np.asarray(img.convert("RGBA").convert("LA"))
                    grey, alpha = grey_alpha[..., 0], grey_alpha[..., 1]
                else:
                    grey, alpha = np.asarray(img.convert("L")), None
    except ABMError:  # the size and memory checks' own refusals
        raise
    except Image.DecompressionBombError as exc:  # Pillow's own check, at twice its limit
        raise MapError(
            f"map file {str(path)!r} has more than {MAX_MAP_PIXELS:.0e} pixels ({exc})"
        ) from exc
    except Exception as exc:  # Pillow raises OSError, SyntaxError, ValueError, ... for bad files
        raise MapError(
            f"map file {str(path)!r} is not a readable image (PNG, PGM, BMP or .npy): {exc}"
        ) from exc
    if alpha is None:
        return grey >= 128
    if not alpha.any():
        raise MapError(
            f"map file {str(path)!r} is transparent everywhere (alpha 0 in every pixel): it "
            "shows no wall and no free space; give the image opaque pixels (dark = wall)"
        )
    darkness = np.subtract(255, grey, dtype=np.uint16)
    darkness *= alpha
    return darkness <= _FREE_BLEND


def _free_runs(free: np.ndarray) -> np.ndarray:
    """``runs[iy, ix, d]``: free cells beyond cell (ix, iy) in direction d (N, E, S, W).

    The four runs of a cell sit side by side (one memory access per point in a large arena);
    they are written in place, so a large map needs no temporary copies.
    """
    rows, cols = free.shape
    runs = np.zeros((rows, cols, 4), dtype=np.int32)
    for iy in range(rows - 2, -1, -1):  # north: rows above
        np.multiply(free[iy + 1], runs[iy + 1, :, 0] + 1, out=runs[iy, :, 0])
    for iy in range(1, rows):  # south
        np.multiply(free[iy - 1], runs[iy - 1, :, 2] + 1, out=runs[iy, :, 2])
    for ix in range(cols - 2, -1, -1):  # east
        np.multiply(free[:, ix + 1], runs[:, ix + 1, 1] + 1, out=runs[:, ix, 1])
    for ix in range(1, cols):  # west
        np.multiply(free[:, ix - 1], runs[:, ix - 1, 3] + 1, out=runs[:, ix, 3])
    return runs
