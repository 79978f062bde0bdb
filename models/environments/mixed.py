"""Mixed worlds: two 3 x 3 cell rooms joined by 22 corridor cells (Stirling 2010, Sect. 3.5).

"The mixed environments ... consisted of two rooms of 3 x 3 cells (9 m x 9 m) and 22 corridor
cells, so approximately half the environment being corridor and half open space. Medium
complexity corridor branching was used to generate the corridors."

Construction: room A sits at the origin; a doorway cell is chosen just outside a random cell of a
random side of it, and a medium-branching corridor tree
(:func:`~models.environments.grow_corridor`) of 22
cells grows from that doorway, never touching room A elsewhere. Room B is then attached beyond a
random dead end of the corridor (or, if no dead end has room, beside any corridor cell, which
becomes a junction), in line with it or offset by one cell sideways. Each room touches the
corridor only at its doorway cell, so the corridors stay one cell wide and the rooms stay 3 x 3.
A layout with nowhere to put room B (rare) is redrawn from the same generator.
"""

import numpy as np

from abm.errors import check_range
from models.environments.corridor import branch_count, grow_corridor
from models.environments.world import World, as_generator, world_from_cells

__all__ = ["MIXED_BRANCHING", "MIXED_CORRIDOR_CELLS", "ROOM_SIDE", "mixed_world"]

Cell = tuple[int, int]

#: Side of each of the two square rooms (cells).
ROOM_SIDE = 3
#: Corridor cells between and around the rooms.
MIXED_CORRIDOR_CELLS = 22
#: Corridor branching level of mixed worlds (the paper uses medium).
MIXED_BRANCHING = "medium"

_STEPS: tuple[Cell, ...] = ((0, 1), (1, 0), (0, -1), (-1, 0))


def _room(corner: Cell, side: int) -> list[Cell]:
    """Cells of the square room of ``side`` cells whose south-west cell is ``corner``."""
    x0, y0 = corner
    return [(x0 + dx, y0 + dy) for dy in range(side) for dx in range(side)]


def _room_beyond(
    door: Cell, step: Cell, offset: int, taken: set[Cell], side: int
) -> list[Cell] | None:
    """Return the room entered from ``door`` going ``step``, or None if it does not fit.

    ``offset`` shifts the room sideways by -1, 0 or 1 cells (for the paper's 3-cell rooms;
    a wider room is centred on the door the same way); the door always faces one of the
    room's cells. The room may touch no taken cell but the door.
    """
    sx, sy = step
    px, py = -sy, sx  # sideways
    half = side // 2
    cells = [
        (door[0] + f * sx + lat * px, door[1] + f * sy + lat * py)
        for f in range(1, side + 1)
        for lat in range(offset - half, offset - half + side)
    ]
    for x, y in cells:
        if (x, y) in taken:
            return None
        for dx, dy in _STEPS:
            nb = (x + dx, y + dy)
            if nb in taken and nb != door:
                return None
    return cells


def _attach_room(
    corridor: list[Cell], taken: set[Cell], rng: np.random.Generator, side: int
) -> list[Cell] | None:
    """Room B's cells beyond a random dead end (else beside any corridor cell), or None."""
    points = set(corridor)
    degree = {c: sum((c[0] + dx, c[1] + dy) in points for dx, dy in _STEPS) for c in corridor}
    doors = corridor[1:]  # corridor[0] is room A's doorway
    for candidates in ([c for c in doors if degree[c] == 1], doors):
        options = [
            room
            for door in candidates
            for step in _STEPS
            for offset in (-1, 0, 1)
            if (room := _room_beyond(door, step, offset, taken, side)) is not None
        ]
        if options:
            return options[int(rng.integers(len(options)))]
    return None


def _layout(
    rng: np.random.Generator, room_side: int, corridor_cells: int
) -> tuple[list[Cell], list[Cell]] | None:
    """One attempt: ``(room cells, corridor cells)``, or None if room B found no place."""
    room_a = _room((0, 0), room_side)
    side = _STEPS[int(rng.integers(4))]
    along = int(rng.integers(room_side))
    # The doorway: the cell just outside the room's ``side`` wall, at column or row ``along``.
    outside = room_side if max(side) > 0 else -1
    door = (along, outside) if side[0] == 0 else (outside, along)
    corridor = grow_corridor(
        corridor_cells,
        rng,
        MIXED_BRANCHING,
        root=door,
        heading=side,
        blocked=frozenset(room_a),
    )
    taken = set(room_a) | set(corridor)
    room_b = _attach_room(corridor, taken, rng, room_side)
    if room_b is None:
        return None
    return room_a + room_b, corridor


def mixed_world(
    rng: np.random.Generator | int | None = None,
    cell_size: float = 3.0,
    room_side: int = ROOM_SIDE,
    corridor_cells: int = MIXED_CORRIDOR_CELLS,
) -> World:
    """Generate two square rooms joined by medium-branching corridor cells: the paper's two
    3 x 3 cell rooms and 22 corridor cells, or larger ones.

    The start cell is a random free cell.

    Args:
        rng: a ``numpy.random.Generator``, an int seed, or None for a fresh generator.
        cell_size: side of a cell (m).
        room_side: side of each room (cells; the paper: 3).
        corridor_cells: corridor cells (the paper: 22).

    Returns:
        A World of kind ``"mixed"``, complexity ``"medium"``, ``2 room_side^2 +
        corridor_cells`` free cells (40 by default), whose ``branches`` is the branch count of
        the corridor cells alone.

    Raises:
        ConfigError: a parameter is out of range or of the wrong type.

    """
    check_range("cell_size", cell_size, 0.0, low_open=True)
    check_range("room_side", room_side, 1, 200, integer=True)
    check_range("corridor_cells", corridor_cells, 1, 100_000, integer=True)
    gen = as_generator(rng)
    layout = None
    while layout is None:
        layout = _layout(gen, int(room_side), int(corridor_cells))
    rooms, corridor = layout
    cells = rooms + corridor
    start = cells[int(gen.integers(len(cells)))]
    return world_from_cells(
        cells, start, "mixed", MIXED_BRANCHING, branch_count(corridor), cell_size
    )
