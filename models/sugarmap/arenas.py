"""The arenas of the SugarMap experiments as bitmaps of D = 0.5 m cells (README "Choices": arenas).

The paper gives a 20 m x 20 m square arena "with multiple configurations of boundary walls and
obstacles" (Purohit et al. Sect. 4.1) and describes the three Fig. 10 geometries in one sentence
each (Sect. 4.3.5); no dimensions. These are our readings (README "Choices": arenas), all but the
testbed on a
42 x 42 cell frame: a one-cell wall border around the 40 x 40 cell (20 m) arena, so the border
sits at index 0 and the testbed's "[1,1], [2,1]" are bitmap indices (README "Choices": start):

- ``open``: the plain square of Figs. 5-9;
- ``open10`` (ours): a 10 m x 10 m open square, the smaller place of claim C22;
- ``circle`` (Fig. 10 geometry a): the 10 m-radius disc inscribed in the square, four 1 m x 1 m
  obstacles;
- ``ushape`` (Fig. 10 geometry b): a 10 m x 20 m room joined by the U's base to a 2 m hallway;
- ``serpentine`` (Fig. 10 geometry c, the default reading): one 2 m corridor folded into eight
  lanes, about 160 m long, so its area is comparable with (a) and (b);
- ``corridor`` (Fig. 10 geometry c read literally): one straight 2 m x 20 m corridor;
- ``testbed``: the 5 m x 3 m testbed of Sect. 4.4 with its wall border.

Codes: 0 navigable (the paper's blue), 1 wall (red), 2 obstacle (green); both walls and
obstacles are impassable (Sect. 2.2). The shipped PNGs in ``maps/`` (written by
:func:`write_arena_pngs`) are what a run loads, through the framework's bitmap loader, so a
user's own bitmap (dark = wall or obstacle, one pixel per cell) is loaded the same way.
"""

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from abm.arena import Arena
from abm.errors import ConfigError, check_range

__all__ = [
    "ARENAS",
    "ArenaInfo",
    "arena_codes",
    "load_arena",
    "start_cells",
    "write_arena_pngs",
    "MAPS_DIR",
    "CELL",
]

#: D, the grid cell and sensing footprint (m), Purohit et al. Sect. 4.1.
CELL = 0.5
#: Folder of the shipped PNGs of the built-in arenas.
MAPS_DIR = Path(__file__).parent / "maps"

NAVIGABLE, WALL, OBSTACLE = 0, 1, 2
#: Grey level of each code in the PNGs: the loader reads >= 128 as free, so an obstacle's dark
#: grey is impassable yet still tells obstacles from walls to a human eye.
_GREY = {NAVIGABLE: 255, WALL: 0, OBSTACLE: 90}
_BITMAP_SUFFIXES = (".png", ".pgm", ".bmp", ".npy")
#: Side of the common frame (cells): the 40-cell arena and its one-cell wall border (README
#: "Choices": arenas).
_FRAME = 42


def _walled(rows: int = _FRAME, cols: int = _FRAME) -> np.ndarray:
    """A frame of wall only, ready for the navigable parts to be carved out."""
    return np.full((rows, cols), WALL, dtype=np.int8)


def _open() -> np.ndarray:
    """The open square: x, y in 1..40 navigable."""
    codes = _walled()
    codes[1:41, 1:41] = NAVIGABLE
    return codes


def _open10() -> np.ndarray:
    """A 10 m x 10 m open square (ours, for claim C22: "especially in larger places"): x, y in
    1..20 navigable inside its own one-cell border.
    """
    codes = _walled(22, 22)
    codes[1:21, 1:21] = NAVIGABLE
    return codes


def _circle() -> np.ndarray:
    """Fig. 10 (a): (x + 0.5 - 21)^2 + (y + 0.5 - 21)^2 < 20^2; 2 x 2 obstacles at
    (12|28, 12|28).
    """
    codes = _walled()
    y, x = np.mgrid[0:_FRAME, 0:_FRAME]
    codes[(x + 0.5 - 21) ** 2 + (y + 0.5 - 21) ** 2 < 20**2] = NAVIGABLE
    for cx in (12, 28):
        for cy in (12, 28):
            codes[cy : cy + 2, cx : cx + 2] = OBSTACLE
    return codes


def _ushape() -> np.ndarray:
    """Fig. 10 (b): room x 1..20, hallway x 37..40 (y 1..40), base x 21..36, y 1..4."""
    codes = _walled()
    codes[1:41, 1:21] = NAVIGABLE
    codes[1:41, 37:41] = NAVIGABLE
    codes[1:5, 21:37] = NAVIGABLE
    return codes


def _serpentine() -> np.ndarray:
    """Fig. 10 (c), serpentine: walls at x = 5, 15, 25, 35 over y 1..36 (gap north),
    x = 10, 20, 30 over y 5..40 (gap south), and x = 40.
    """
    codes = _open()
    codes[:, 40] = WALL
    codes[1:37, 5:40:10] = WALL
    codes[5:41, 10:40:10] = WALL
    return codes


def _corridor() -> np.ndarray:
    """Fig. 10 (c), straight: x 19..22, y 1..40."""
    codes = _walled()
    codes[1:41, 19:23] = NAVIGABLE
    return codes


def _testbed() -> np.ndarray:
    """The testbed: a 12 x 8 bitmap, navigable x 1..10, y 1..6."""
    codes = _walled(8, 12)
    codes[1:7, 1:11] = NAVIGABLE
    return codes


@dataclass(frozen=True)
class ArenaInfo:
    """A built-in arena.

    Attributes:
        name: its name, also its PNG's stem.
        title: one line, with where the paper describes it.
        build: returns its codes, int8 ``[rows, cols]``, row 0 = south.
        navigable: its navigable cell count in our reading (README "Choices": arenas).

    """

    name: str
    title: str
    build: Callable[[], np.ndarray]
    navigable: int


ARENAS: dict[str, ArenaInfo] = {
    info.name: info
    for info in (
        ArenaInfo("open", "20 m x 20 m open square (Sect. 4.1)", _open, 1600),
        ArenaInfo("open10", "10 m x 10 m open square (ours, claim C22)", _open10, 400),
        ArenaInfo("circle", "Fig. 10 (a): 10 m disc, four obstacles", _circle, 1248),
        ArenaInfo("ushape", "Fig. 10 (b): room and 2 m hallway, a U", _ushape, 1024),
        ArenaInfo("serpentine", "Fig. 10 (c): 2 m corridor in eight lanes", _serpentine, 1308),
        ArenaInfo("corridor", "Fig. 10 (c) literal: straight 2 m corridor", _corridor, 160),
        ArenaInfo("testbed", "the 5 m x 3 m testbed of Sect. 4.4", _testbed, 60),
    )
}


def _names() -> str:
    return ", ".join(repr(name) for name in ARENAS)


def arena_codes(name: str) -> np.ndarray:
    """The codes of a built-in arena, a fresh array on every call.

    Args:
        name: one of :data:`ARENAS`.

    Returns:
        int8 ``[rows, cols]``, row 0 = south: 0 navigable, 1 wall, 2 obstacle.

    Raises:
        ConfigError: an unknown name.

    """
    if name not in ARENAS:
        raise ConfigError(f"arena must be one of {_names()}, got {name!r}")
    return ARENAS[name].build()


def write_arena_pngs(folder: str | Path = MAPS_DIR) -> list[Path]:
    """Write every built-in arena as an 8-bit grey PNG named after it, one pixel per cell.

    Navigable cells are white, walls black and obstacles dark grey (below the loader's 128,
    so impassable); the image's top row is north, as the framework's loader expects.

    Args:
        folder: where to write; created if missing.

    Returns:
        The paths written, in the order of :data:`ARENAS`.

    """
    from PIL import Image

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    paths = []
    for name in ARENAS:
        codes = arena_codes(name)
        grey = np.zeros(codes.shape, dtype=np.uint8)
        for code, level in _GREY.items():
            grey[codes == code] = level
        path = folder / f"{name}.png"
        Image.fromarray(grey[::-1]).save(path)
        paths.append(path)
    return paths


def load_arena(arena: str | Path, cell: float = CELL) -> Arena:
    """A built-in arena by name, or a user's bitmap file, at ``cell`` metres per pixel.

    Both go through the framework's bitmap loader (:meth:`abm.arena.Arena.from_bitmap`), so a
    built-in arena is exactly its shipped PNG.

    Args:
        arena: a name in :data:`ARENAS`, or the path of a PNG/PGM/BMP (dark = impassable, top
            row north) or .npy (nonzero = free, row 0 north) bitmap.
        cell: metres per pixel; D = 0.5 m (Sect. 4.1).

    Raises:
        ConfigError: ``arena`` is neither a built-in name nor an existing bitmap file, or
            ``cell`` is not positive.
        MapError: the file cannot be read as a map.

    """
    check_range("cell", cell, 0.0, low_open=True)
    if isinstance(arena, str) and arena in ARENAS:
        return Arena.from_bitmap(MAPS_DIR / f"{arena}.png", resolution=cell, name=arena)
    path = Path(arena)
    if path.suffix.lower() not in _BITMAP_SUFFIXES or not path.is_file():
        raise ConfigError(
            f"arena must be one of {_names()} or an existing bitmap file "
            f"({', '.join(_BITMAP_SUFFIXES)}), got {str(arena)!r}"
        )
    return Arena.from_bitmap(path, resolution=cell)


def start_cells(
    free: np.ndarray, n: int, entrance: tuple[int, int] | None = None
) -> list[tuple[int, int]]:
    """The start cells of n nodes: the leftmost contiguous free cells of the lowest free row,
    continuing along that row (left to right), then the next free row up (README "Choices": start).

    The nodes enter "through an accessible opening" (Sect. 2.2) and the testbed's explorers
    started in a corner at [1, 1] and [2, 1] (Sect. 4.4), hence a corner of the lowest row.
    "Continuing along that row" is meant literally: past a wall in that row it takes
    the next free cells of the same row (in the serpentine, the next lane) before going up.

    Args:
        free: True where navigable, ``[rows, cols]``, row 0 = south.
        n: how many cells.
        entrance: a free cell ``(ix, iy)`` to start from instead: the n cells are then the
            entrance and the free cells nearest to it through free space.

    Returns:
        ``(ix, iy)`` cell indices, in order.

    Raises:
        ConfigError: ``free`` is not a 2-D boolean array, ``n`` is not a positive integer, or
            there are fewer than n free cells.

    """
    free = np.asarray(free)
    if free.ndim != 2 or free.dtype != bool:
        raise ConfigError(
            f"free must be a 2-D boolean array, got shape {free.shape} dtype {free.dtype}"
        )
    check_range("n", n, 1, integer=True)
    if free.sum() < n:
        raise ConfigError(f"n must be at most the {int(free.sum())} free cells, got {n}")
    if entrance is not None:
        return _nearest_free(free, n, entrance)
    iy, ix = np.nonzero(free)  # row-major: lowest row first, left to right within a row
    return [(int(x), int(y)) for x, y in zip(ix[:n], iy[:n], strict=True)]


def _nearest_free(free: np.ndarray, n: int, entrance: tuple[int, int]) -> list[tuple[int, int]]:
    """The entrance cell and the n - 1 free cells nearest to it through free space
    (breadth-first over the 4-neighbours east, north, west, south); fewer reachable cells
    than n is a ConfigError.
    """
    rows, cols = free.shape
    ix, iy = entrance
    if not (0 <= ix < cols and 0 <= iy < rows and free[iy, ix]):
        raise ConfigError(f"entrance cell {entrance} is a wall or outside the {cols} x {rows} map")
    order, seen = [(ix, iy)], {(ix, iy)}
    for x, y in order:
        if len(order) >= n:
            break
        for nx, ny in ((x + 1, y), (x, y + 1), (x - 1, y), (x, y - 1)):
            if 0 <= nx < cols and 0 <= ny < rows and free[ny, nx] and (nx, ny) not in seen:
                seen.add((nx, ny))
                order.append((nx, ny))
    if len(order) < n:
        raise ConfigError(
            f"n must be at most the {len(order)} free cells reachable from the entrance "
            f"{entrance}, got {n}"
        )
    return order[:n]
