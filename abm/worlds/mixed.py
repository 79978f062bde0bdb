"""Mixed worlds: two 3 x 3 cell rooms joined by 22 corridor cells (Stirling 2010, Sect. 3.5).

"The mixed environments ... consisted of two rooms of 3 x 3 cells (9 m x 9 m) and 22 corridor
cells, so approximately half the environment being corridor and half open space. Medium
complexity corridor branching was used to generate the corridors."

Construction: room A sits at the origin; a doorway cell is chosen just outside a random cell of a
random side of it, and a medium-branching corridor tree (:func:`~abm.worlds.grow_corridor`) of 22
cells grows from that doorway, never touching room A elsewhere. Room B is then attached beyond a
random dead end of the corridor (or, if no dead end has room, beside any corridor cell, which
becomes a junction), in line with it or offset by one cell sideways. Each room touches the
corridor only at its doorway cell, so the corridors stay one cell wide and the rooms stay 3 x 3.
A layout with nowhere to put room B (rare) is redrawn from the same generator.
"""

import numpy as np

from abm.errors import check_range
from abm.worlds.corridor import branch_count, grow_corridor
from abm.worlds.world import World, as_generator, world_from_cells

__all__ = ["MIXED_BRANCHING", "MIXED_CORRIDOR_CELLS", "ROOM_SIDE", "mixed_world"]

Cell = tuple[int, int]

#: Side of each of the two square rooms (cells).
ROOM_SIDE = 3
#: Corridor cells between and around the rooms.
MIXED_CORRIDOR_CELLS = 22
#: Corridor branching level of mixed worlds (the paper uses medium).
MIXED_BRANCHING = "medium"

_STEPS: tuple[Cell, ...] = ((0, 1), (1, 0), (0, -1), (-1, 0))


def _room(corner: Cell) -> list[Cell]:
    """Cells of the square room whose south-west cell is ``corner``."""
    x0, y0 = corner
    return [(x0 + dx, y0 + dy) for dy in range(ROOM_SIDE) for dx in range(ROOM_SIDE)]


def _room_beyond(door: Cell, step: Cell, offset: int, taken: set[Cell]) -> list[Cell] | None:
    """Return the room entered from ``door`` going ``step``, or None if it does not fit.

    ``offset`` shifts the room sideways by -1, 0 or 1 cells; the door always faces one of the
    room's cells. The room may touch no taken cell but the door.
    """
    sx, sy = step
    px, py = -sy, sx  # sideways
    cells = [
        (door[0] + f * sx + lat * px, door[1] + f * sy + lat * py)
        for f in range(1, ROOM_SIDE + 1)
        for lat in range(offset - 1, offset + 2)
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
    corridor: list[Cell], taken: set[Cell], rng: np.random.Generator
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
            if (room := _room_beyond(door, step, offset, taken)) is not None
        ]
        if options:
            return options[int(rng.integers(len(options)))]
    return None


def _layout(rng: np.random.Generator) -> tuple[list[Cell], list[Cell]] | None:
    """One attempt: ``(room cells, corridor cells)``, or None if room B found no place."""
    room_a = _room((0, 0))
    side = _STEPS[int(rng.integers(4))]
    along = int(rng.integers(ROOM_SIDE))
    # The doorway: the cell just outside the room's ``side`` wall, at column or row ``along``.
    outside = ROOM_SIDE if max(side) > 0 else -1
    door = (along, outside) if side[0] == 0 else (outside, along)
    corridor = grow_corridor(
        MIXED_CORRIDOR_CELLS,
        rng,
        MIXED_BRANCHING,
        root=door,
        heading=side,
        blocked=frozenset(room_a),
    )
    taken = set(room_a) | set(corridor)
    room_b = _attach_room(corridor, taken, rng)
    if room_b is None:
        return None
    return room_a + room_b, corridor


def mixed_world(rng: np.random.Generator | int | None = None, cell_size: float = 3.0) -> World:
    """Generate two 3 x 3 cell rooms joined by 22 medium-branching corridor cells.

    The start cell is a random free cell.

    Args:
        rng: a ``numpy.random.Generator``, an int seed, or None for a fresh generator.
        cell_size: side of a cell (m).

    Returns:
        A World of kind ``"mixed"``, complexity ``"medium"``, 40 free cells, whose ``branches``
        is the branch count of the corridor cells alone.

    Raises:
        ConfigError: a parameter is out of range or of the wrong type.

    """
    check_range("cell_size", cell_size, 0.0, low_open=True)
    gen = as_generator(rng)
    layout = None
    while layout is None:
        layout = _layout(gen)
    rooms, corridor = layout
    cells = rooms + corridor
    start = cells[int(gen.integers(len(cells)))]
    return world_from_cells(
        cells, start, "mixed", MIXED_BRANCHING, branch_count(corridor), cell_size
    )
