"""Open-space worlds: a 5 x 5 cell room with randomly placed obstacle cells (Stirling 2010, 3.5).

"Low, medium and high obstacle densities were generated with 5, 7 or 10 obstacles, respectively.
Obstacles were randomly placed on the grid while ensuring that all free-space was accessible and
no corridors were inadvertently generated." We read the two conditions as:

(a) the free cells are 4-connected;
(b) no free cell is a corridor cell: none has blocked cells (obstacles or the room's outer wall)
    both north and south of it, or both east and west of it. (A beacon there would sense two
    opposing walls closer than 3 m and act as a corridor beacon.)

Rule (b) needs no relaxation: an exhaustive enumeration of all placements finds 405, 774 and 730
valid layouts for 5, 7 and 10 obstacles (of 53,130, 480,700 and 3,268,760). With 10 obstacles
most valid layouts pack the obstacles against the wall (a full row or column of obstacles is
common), because every free cell needs a free neighbour on both axes.

Rejection sampling would need about 4,500 tries per 10-obstacle room, so instead the valid layouts
are enumerated once per process (row by row, in milliseconds) and one is drawn uniformly: the same
distribution as placing obstacles at random and rejecting bad layouts.
"""

from functools import cache

import numpy as np

from abm.errors import ConfigError, check_choice, check_range
from models.environments.world import COMPLEXITIES, World, as_generator, world_from_cells

__all__ = ["OBSTACLES", "ROOM_CELLS", "open_world", "room_layouts"]

#: Side of the square room (cells).
ROOM_CELLS = 5
#: Obstacle cells per complexity level.
OBSTACLES = {"low": 5, "medium": 7, "high": 10}


def _row_ok(row: int, size: int) -> bool:
    """Tell whether every free cell of the row bitmask has a free east or west neighbour."""
    for ix in range(size):
        if row >> ix & 1 and not (ix > 0 and row >> (ix - 1) & 1 or row >> (ix + 1) & 1):
            return False
    return True


@cache
def room_layouts(size: int, n_obstacles: int) -> np.ndarray:
    """All valid layouts of a ``size`` x ``size`` room with ``n_obstacles`` obstacle cells.

    Valid means rules (a) and (b) of the module docstring hold.

    Args:
        size: side of the room (cells); keep it small, the search grows as ``rows ** size``.
        n_obstacles: number of obstacle cells.

    Returns:
        Read-only int64 array of free-cell bitmasks, bit ``iy * size + ix`` set when the cell
        ``(ix, iy)`` is free, in increasing order.

    """
    check_range("size", size, 1, 7, integer=True)
    check_range("n_obstacles", n_obstacles, 0, size * size - 1, integer=True)
    patterns = np.array([r for r in range(1 << size) if _row_ok(r, size)], dtype=np.int64)
    counts = np.array([r.bit_count() for r in patterns.tolist()])
    index = np.indices((len(patterns),) * size, dtype=np.int64).reshape(size, -1).T
    index = index[counts[index].sum(axis=1) == size * size - n_obstacles]
    rows = patterns[index]  # (m, size): row iy's free bitmask
    # Rule (b), north-south: each free cell needs a free cell above or below (walls outside).
    padded = np.pad(rows, ((0, 0), (1, 1)))
    vertical = (rows & ~(padded[:, :-2] | padded[:, 2:])) == 0
    rows = rows[vertical.all(axis=1)]
    free = (rows << (size * np.arange(size))).sum(axis=1)
    # Rule (a): flood fill from the lowest free cell with bit shifts.
    full = (1 << size * size) - 1
    has_west = sum(1 << (iy * size + ix) for iy in range(size) for ix in range(1, size))
    has_east = sum(1 << (iy * size + ix) for iy in range(size) for ix in range(size - 1))
    reached = free & -free
    for _ in range(size * size):
        grown = reached | ((reached << 1) & has_west) | ((reached >> 1) & has_east)
        grown = (grown | (reached << size) | (reached >> size)) & free & full
        if np.array_equal(grown, reached):
            break
        reached = grown
    layouts = np.sort(free[reached == free])
    layouts.setflags(write=False)
    return layouts


def open_world(
    complexity: str = "medium",
    rng: np.random.Generator | int | None = None,
    cell_size: float = 3.0,
    room_cells: int = ROOM_CELLS,
) -> World:
    """Generate a square room with obstacle cells: the paper's 5 x 5 cells with 5, 7 or 10
    obstacles, or a larger room of k x k such rooms.

    A larger room (``room_cells`` = 5 k) is tiled with k x k independent draws of the paper's
    layouts joined without walls: the obstacle density is the paper's, rule (b) holds because
    joining tiles only adds free neighbours, and rule (a) is checked on the whole room (a
    disconnected room is redrawn). The start cell is a random free cell.

    Args:
        complexity: ``"low"``, ``"medium"`` or ``"high"`` obstacle density (5, 7, 10 cells
            per 5 x 5 cells).
        rng: a ``numpy.random.Generator``, an int seed, or None for a fresh generator.
        cell_size: side of a cell (m).
        room_cells: side of the room (cells): 5 (the paper's) or a multiple of 5.

    Raises:
        ConfigError: a parameter is out of range or not one of its accepted values.

    """
    check_choice("complexity", complexity, COMPLEXITIES)
    check_range("cell_size", cell_size, 0.0, low_open=True)
    check_range("room_cells", room_cells, ROOM_CELLS, 500, integer=True)
    if room_cells % ROOM_CELLS:
        raise ConfigError(
            f"room_cells must be a multiple of {ROOM_CELLS} (rooms are tiled with the paper's "
            f"{ROOM_CELLS} x {ROOM_CELLS} layouts), got {room_cells!r}"
        )
    gen = as_generator(rng)
    layouts = room_layouts(ROOM_CELLS, OBSTACLES[complexity])
    tiles = room_cells // ROOM_CELLS
    while True:
        free = np.zeros((room_cells, room_cells), dtype=bool)
        for ty in range(tiles):
            for tx in range(tiles):
                mask = int(layouts[gen.integers(len(layouts))])
                for iy in range(ROOM_CELLS):
                    for ix in range(ROOM_CELLS):
                        if mask >> (iy * ROOM_CELLS + ix) & 1:
                            free[ty * ROOM_CELLS + iy, tx * ROOM_CELLS + ix] = True
        if tiles == 1 or _connected(free):
            break
    iy, ix = np.nonzero(free)
    cells = list(zip(ix.tolist(), iy.tolist(), strict=True))
    start = cells[int(gen.integers(len(cells)))]
    # The arena always holds the whole room, even when a row of obstacles lines one wall.
    room = ((0, 0), (room_cells - 1, room_cells - 1))
    return world_from_cells(cells, start, "open", complexity, None, cell_size, extent=room)


def _connected(free: np.ndarray) -> bool:
    """Tell whether the free cells are 4-connected."""
    from scipy import ndimage  # 0.4 s to import: only when a room is made, not for `--help`

    _labels, count = ndimage.label(free)
    return count == 1
