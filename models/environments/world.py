"""The World record every generator returns, and the shared seeding and assembly helpers.

A world is a set of free 3 m x 3 m cells on a grid (Stirling et al. 2010, Sect. 3.5): one grid
pixel of the :class:`~abm.arena.Arena` is one cell, everything else is wall. The start point is
the centre of one free cell; the base beacon sits there and the robots wait on the ground below
it ("start cluster at a random location").
"""

from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from abm.arena import Arena
from abm.errors import ConfigError, check_choice, check_range

__all__ = ["COMPLEXITIES", "WORLD_KINDS", "World", "as_generator", "world_from_cells"]

#: The three environment families of the paper's Fig. 5.
WORLD_KINDS = ("corridor", "open", "mixed")
#: Kinds a World may have: the generated families plus maps loaded from bitmap files.
ALL_KINDS = (*WORLD_KINDS, "bitmap")
#: The three complexity levels (corridor branching or obstacle density).
COMPLEXITIES = ("low", "medium", "high")

#: Wall cells left around the free cells on every side of the arena.
BORDER_CELLS = 1


@dataclass(frozen=True, eq=False)
class World:
    """A generated test environment.

    Attributes:
        arena: the walls; one grid pixel is one ``cell_size`` x ``cell_size`` cell (m).
        start: ``(x, y)`` centre of the start cell (m); the base beacon sits there.
        kind: ``"corridor"``, ``"open"`` or ``"mixed"``.
        complexity: ``"low"``, ``"medium"`` or ``"high"``.
        cells: ``(k, 2)`` int array of the free cells' ``(ix, iy)`` in the arena grid, sorted by
            ``iy`` then ``ix``; read-only.
        branches: branch count of the corridor cells (see :func:`models.environments.branch_count`);
            None for open rooms.

    """

    arena: Arena
    start: np.ndarray
    kind: str
    complexity: str
    cells: np.ndarray
    branches: int | None

    def __post_init__(self) -> None:
        check_choice("kind", self.kind, ALL_KINDS)
        check_choice("complexity", self.complexity, COMPLEXITIES)
        for array in (self.start, self.cells):
            array.setflags(write=False)

    @property
    def start_cell(self) -> tuple[int, int]:
        """Grid indices ``(ix, iy)`` of the start cell."""
        ix, iy = self.arena.cell_of(self.start)
        return int(ix), int(iy)

    @property
    def cell_size(self) -> float:
        """Side of one cell (m)."""
        return self.arena.resolution

    @property
    def free_area(self) -> float:
        """Free area (m^2)."""
        return len(self.cells) * self.cell_size**2

    def __repr__(self) -> str:
        branches = "" if self.branches is None else f", branches={self.branches}"
        x, y = self.start
        return (
            f"World({self.kind!r}, {self.complexity!r}, {len(self.cells)} cells of "
            f"{self.cell_size:g} m{branches}, start=({x:g}, {y:g}) m)"
        )


def as_generator(rng: np.random.Generator | int | None) -> np.random.Generator:
    """Return ``rng`` itself, a generator seeded with the int ``rng``, or a fresh one for None.

    Raises:
        ConfigError: ``rng`` is of another type or a negative seed.

    """
    if isinstance(rng, np.random.Generator):
        return rng
    if rng is None or (isinstance(rng, int | np.integer) and not isinstance(rng, bool)):
        if rng is not None and rng < 0:
            raise ConfigError(f"rng must be a non-negative int seed, got {rng!r}")
        return np.random.default_rng(rng)
    raise ConfigError(
        f"rng must be a numpy.random.Generator, an int seed or None, got {type(rng).__name__}"
    )


def world_from_cells(
    cells: Iterable[tuple[int, int]],
    start: tuple[int, int],
    kind: str,
    complexity: str,
    branches: int | None,
    cell_size: float,
    extent: tuple[tuple[int, int], tuple[int, int]] | None = None,
) -> World:
    """Assemble a World from free cells in any integer frame (shifted here into the arena's).

    The arena spans the cells' bounding box (or ``extent``) plus a ring of ``BORDER_CELLS`` wall
    cells.

    Args:
        cells: free cells ``(ix, iy)``; may be negative.
        start: the start cell, one of ``cells``, in the same frame.
        kind: world kind.
        complexity: complexity level.
        branches: corridor branch count or None.
        cell_size: side of a cell (m).
        extent: ``((ix_min, iy_min), (ix_max, iy_max))`` the arena must include even where those
            cells are walls (a room whose edge row is all obstacles); default: the cells' box.

    """
    check_range("cell_size", cell_size, 0.0, low_open=True)
    raw = np.array(list(cells), dtype=np.int64).reshape(-1, 2)
    low, high = raw.min(axis=0), raw.max(axis=0)
    if extent is not None:
        low = np.minimum(low, extent[0])
        high = np.maximum(high, extent[1])
    shifted = raw - low + BORDER_CELLS
    cols, rows = high - low + 1 + 2 * BORDER_CELLS
    free = np.zeros((rows, cols), dtype=bool)
    free[shifted[:, 1], shifted[:, 0]] = True
    arena = Arena(free, resolution=float(cell_size), name=f"{kind}-{complexity}")
    shifted = shifted[np.lexsort((shifted[:, 0], shifted[:, 1]))]
    start_xy = (np.asarray(start, dtype=float) - low + BORDER_CELLS + 0.5) * float(cell_size)
    return World(arena, start_xy, kind, complexity, shifted, branches)
