"""Floor plans of ordinary buildings, the kind of map users bring (1 px = 1 m).

The generated worlds of Stirling et al. (2010) are built from 3 m cells, so a lattice of 3 m
steps from the base always meets walls where it expects them. Real floor plans do not: corridors
and doors of 1-5 m, rooms of different sizes, walls at any offset from the base, pillars,
L-shaped halls, diagonal walls drawn as staircases of pixels. These plans exercise a model on
such places; each builder returns the boolean free grid (row 0 = south, True = free) with a
one-pixel outer wall, and :data:`models.environments.MAPS` registers them with a start point.
"""

import numpy as np

__all__ = ["FLOOR_PLANS", "office", "office_small", "lhall", "pillar_room", "diagonal_hall"]


def _box(rows: int, cols: int) -> np.ndarray:
    free = np.zeros((rows, cols), dtype=bool)
    free[1:-1, 1:-1] = True
    return free


def _wall(free: np.ndarray, x0: int, y0: int, x1: int, y1: int, value: bool = False) -> None:
    """Set the inclusive pixel rectangle x0..x1, y0..y1 to ``value`` (False = wall)."""
    free[min(y0, y1) : max(y0, y1) + 1, min(x0, x1) : max(x0, x1) + 1] = value


def _door(free: np.ndarray, x0: int, y0: int, x1: int, y1: int) -> None:
    _wall(free, x0, y0, x1, y1, value=True)


def office() -> np.ndarray:
    """The office of issue 18: 64 x 40 m, a 5 m corridor along its length (y 18-22), 4 m doors
    into eight rooms of about 16 x 16 m, one 2 x 2 m pillar in a room.
    """
    free = _box(40, 64)
    _wall(free, 1, 17, 62, 17)  # corridor's south wall
    _wall(free, 1, 23, 62, 23)  # corridor's north wall
    for x in (17, 33, 49):  # room partitions, south and north
        _wall(free, x, 1, x, 16)
        _wall(free, x, 24, x, 38)
    for x0 in (6, 23, 40, 55):  # 4 m doors, at different offsets in each room
        _door(free, x0, 17, x0 + 3, 17)
    for x0 in (11, 19, 43, 52):
        _door(free, x0, 23, x0 + 3, 23)
    _wall(free, 26, 30, 27, 31)  # a pillar in a north room
    return free


def office_small() -> np.ndarray:
    """A 45 x 31 m office: a 3 m corridor, rooms of 6 to 20 m with doors of 1 to 3 m, and an
    open-plan area at the east end through a 5 m opening.
    """
    free = _box(31, 45)
    _wall(free, 1, 12, 33, 12)  # corridor y 13-15
    _wall(free, 1, 16, 33, 16)
    for x in (8, 15, 26):
        _wall(free, x, 1, x, 11)
    for x in (12, 20):
        _wall(free, x, 17, x, 29)
    _wall(free, 34, 1, 34, 29)  # open-plan area x 35-43 behind a wall with a 5 m opening
    _door(free, 34, 11, 34, 15)
    for x0, width in ((3, 1), (10, 2), (19, 3), (29, 2)):
        _door(free, x0, 12, x0 + width - 1, 12)
    for x0, width in ((5, 3), (15, 1), (25, 2)):
        _door(free, x0, 16, x0 + width - 1, 16)
    return free


def lhall() -> np.ndarray:
    """An L-shaped hall, 37 x 29 m overall with arms 13 and 11 m wide."""
    free = _box(29, 37)
    _wall(free, 14, 12, 36, 28)  # the solid north-east block
    return free


def pillar_room() -> np.ndarray:
    """A 25 x 18 m room with a 1 x 1 m pillar and a 2 x 3 m column, and a 4 m wide side room
    behind a 2 m door.
    """
    free = _box(20, 32)
    _wall(free, 8, 9, 8, 9)  # pillar
    _wall(free, 17, 5, 18, 7)  # column
    _wall(free, 26, 1, 26, 18)  # side room x 27-30 behind a 2 m door
    _door(free, 26, 14, 26, 15)
    return free


def diagonal_hall() -> np.ndarray:
    """A 34 x 28 m hall cut by a 45 degree wall drawn as a staircase of pixels (steps of 1 m)
    with passages of 2 and 5 m at its ends, and a wall at 2:1 slope closing a wedge.
    """
    free = _box(28, 34)
    for k in range(19):  # 45 degrees from (6, 6) to (24, 24)
        _wall(free, 6 + k, 6 + k, 7 + k, 6 + k)
    for k in range(8):  # 2:1 slope from (20, 3)
        _wall(free, 20 + 2 * k, 3 + k, 21 + 2 * k, 3 + k)
    return free


#: name -> (builder, start point (m), one-line description).
FLOOR_PLANS = {
    "office": (office, (4.3, 20.6), "64 x 40 m office: 5 m corridor, 4 m doors, 8 rooms, pillar"),
    "office_small": (
        office_small,
        (2.7, 14.2),
        "45 x 31 m office: 3 m corridor, doors of 1-3 m, rooms of 6-20 m, open-plan end",
    ),
    "lhall": (lhall, (5.8, 4.4), "L-shaped hall, 37 x 29 m, arms 13 and 11 m wide"),
    "pillar_room": (
        pillar_room,
        (3.6, 16.1),
        "25 x 18 m room with a pillar and a column, 4 m side room behind a 2 m door",
    ),
    "diagonal_hall": (
        diagonal_hall,
        (3.2, 24.7),
        "34 x 28 m hall cut by staircase-pixel diagonal walls (45 deg and 2:1)",
    ),
}
