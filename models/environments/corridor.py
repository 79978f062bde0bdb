"""Branching corridor worlds: a random tree of one-cell-wide corridors (Stirling 2010, Sect. 3.5).

The paper builds "40 connected 3 m x 3 m corridor cells, creating 120 m of corridor" whose
branching "was adjusted probabilistically" to a mean branch count of 3.56 (sd 1.23), 5.82 (1.07)
and 9.5 (1.63) at low, medium and high complexity. It does not say what a branch is.

**Branch** (our definition): an edge of the corridor's skeleton graph, i.e. a maximal chain of
corridor cells between two *nodes*, where the nodes are the cells with other than two corridor
neighbours (dead ends and junctions). Turns do not end a branch. A straight or bent corridor is
one branch, a T is three, a cross four. This is the usual "branch" of skeleton analysis, it makes
branch length fall as branching rises with the total length fixed (as the paper remarks), and it
is the definition under which all three published means *and* standard deviations can be met.

**Growth.** The corridor grows cell by cell from a root cell in a random direction. Every step
picks one open *arm* (a growing corridor end) uniformly at random and extends it: straight on, or
with probability ``P_TURN`` a 90-degree turn once it has run ``MIN_RUN`` cells straight; if that
cell is not allowed it tries the other directions, and an arm with none left is a dead end. A new
cell is allowed only if it is empty and touches no corridor cell but its parent, so the corridor
is a tree, one cell wide, with no 2 x 2 block of free cells. After each step the new cell becomes a
T junction with probability ``p_branch`` -- it spawns a side arm -- once the arm has grown
``min_gap`` cells since its last junction. The minimum gap makes the junction count more regular
than a Poisson count, which the paper's small standard deviations require. Every junction adds
exactly two branches, so a tree has ``1 + 2 * junctions`` branches. If every arm dies before the
corridor is complete (rare) the growth starts afresh from the same generator.
"""

import numpy as np

from abm.errors import check_choice, check_range
from models.environments.world import COMPLEXITIES, World, as_generator, world_from_cells

__all__ = ["BRANCHING", "MIN_RUN", "P_TURN", "branch_count", "corridor_world", "grow_corridor"]

Cell = tuple[int, int]

#: Probability that an arm turns 90 degrees at a step (once it has run ``MIN_RUN`` cells).
P_TURN = 0.15
#: Shortest straight run (cells) before an arm may turn by choice: no staircases.
MIN_RUN = 2

#: ``complexity -> (p_branch, min_gap)``: probability per grown cell that it becomes a junction,
#: and the cells an arm must grow after a junction before it may branch again. Found with
#: ``python -m models.environments.calibrate``: for each ``min_gap`` in 1..12, bisection on
#: ``p_branch``
#: (to 0.01) for the paper's mean branch count of 40-cell corridors, then the pair minimising
#: ``4 * (relative mean error)^2 + (relative sd error)^2`` over 8000 worlds. Measured there:
#: low 3.52 (sd 1.20), medium 5.84 (1.08), high 9.53 (1.57); paper 3.56 (1.23), 5.82 (1.07),
#: 9.5 (1.63).
BRANCHING: dict[str, tuple[float, int]] = {
    "low": (0.09, 9),
    "medium": (0.36, 8),
    "high": (0.41, 4),
}

_STEPS: tuple[Cell, ...] = ((0, 1), (1, 0), (0, -1), (-1, 0))


def _fits(cell: Cell, parent: Cell, taken: set[Cell]) -> bool:
    """Tell whether ``cell`` is empty and touches no taken cell except ``parent``."""
    if cell in taken:
        return False
    x, y = cell
    for dx, dy in _STEPS:
        nb = (x + dx, y + dy)
        if nb != parent and nb in taken:
            return False
    return True


def _grow_once(
    n_cells: int,
    rng: np.random.Generator,
    p_branch: float,
    min_gap: int,
    root: Cell,
    heading: Cell,
    blocked: frozenset[Cell],
) -> list[Cell] | None:
    """One attempt at growing the tree; None if every arm died before ``n_cells`` cells."""
    taken = set(blocked)
    taken.add(root)
    cells = [root]
    # An arm: [x, y, dx, dy, cells since its last junction, straight run].
    arms = [[root[0], root[1], heading[0], heading[1], 1, 1]]
    while len(cells) < n_cells:
        if not arms:
            return None
        k = int(rng.integers(len(arms))) if len(arms) > 1 else 0
        arm = arms[k]
        x, y, dx, dy, gap, run = arm
        side = 1 if rng.random() < 0.5 else -1
        left, right = (-dy * side, dx * side), (dy * side, -dx * side)
        if run >= MIN_RUN and rng.random() < P_TURN:
            options = (left, right, (dx, dy))
        else:
            options = ((dx, dy), left, right)
        for sx, sy in options:
            cell = (x + sx, y + sy)
            if _fits(cell, (x, y), taken):
                break
        else:
            arms.pop(k)  # a dead end
            continue
        taken.add(cell)
        cells.append(cell)
        run = run + 1 if (sx, sy) == (dx, dy) else 1
        gap += 1
        if gap >= min_gap and len(cells) < n_cells and rng.random() < p_branch:
            for px, py in ((-sy * side, sx * side), (sy * side, -sx * side)):
                branch = (cell[0] + px, cell[1] + py)
                if _fits(branch, cell, taken):
                    taken.add(branch)
                    cells.append(branch)
                    arms.append([branch[0], branch[1], px, py, 1, 1])
                    gap = 0
                    break
        arm[:] = [cell[0], cell[1], sx, sy, gap, run]
    return cells


def grow_corridor(
    n_cells: int,
    rng: np.random.Generator,
    complexity: str = "medium",
    root: Cell = (0, 0),
    heading: Cell | None = None,
    blocked: frozenset[Cell] = frozenset(),
    branching: tuple[float, int] | None = None,
) -> list[Cell]:
    """Grow a one-cell-wide random corridor tree of ``n_cells`` cells (see the module docstring).

    Args:
        n_cells: number of corridor cells.
        rng: the generator all choices are drawn from.
        complexity: branching level, a key of :data:`BRANCHING`.
        root: the first cell; it may touch ``blocked`` cells (a doorway), no other cell may.
        heading: the first arm's direction as a unit step ``(dx, dy)``; random if None.
        blocked: cells the corridor must neither occupy nor touch (e.g. a room).
        branching: ``(p_branch, min_gap)`` to use instead of ``BRANCHING[complexity]``.

    Returns:
        The corridor cells ``(ix, iy)``, root first.

    Raises:
        ConfigError: a parameter is out of range or not one of its accepted values.

    """
    check_range("n_cells", n_cells, 1, integer=True)
    if heading is not None:
        check_choice("heading", tuple(heading), _STEPS)
    if branching is None:
        check_choice("complexity", complexity, COMPLEXITIES)
        branching = BRANCHING[complexity]
    p_branch, min_gap = branching
    while True:
        start = heading if heading is not None else _STEPS[int(rng.integers(4))]
        cells = _grow_once(n_cells, rng, p_branch, min_gap, root, start, blocked)
        if cells is not None:
            return cells


def branch_count(cells: np.ndarray | list[Cell] | set[Cell]) -> int:
    """Count the branches of a set of corridor cells (4-connected grid cells).

    A branch is a maximal chain of cells between two nodes, a node being a cell with other than
    two neighbouring cells (a dead end or a junction); see the module docstring. An isolated
    cell counts as one branch, and so does a loop without any node.

    Args:
        cells: ``(k, 2)`` array or iterable of ``(ix, iy)`` cells.

    """
    points = {(int(x), int(y)) for x, y in np.asarray(list(cells), dtype=np.int64).reshape(-1, 2)}
    degree = {(x, y): sum((x + dx, y + dy) in points for dx, dy in _STEPS) for x, y in points}
    ends = sum(d for d in degree.values() if d != 2)
    isolated = sum(d == 0 for d in degree.values())
    # Cells on loops without a node are not reached from any node: count one branch per loop.
    seen: set[Cell] = set()
    _flood([c for c, d in degree.items() if d != 2], points, seen)
    loops = 0
    for cell in points - seen:
        if cell not in seen:
            loops += 1
            _flood([cell], points, seen)
    return ends // 2 + isolated + loops


def _flood(start: list[Cell], points: set[Cell], seen: set[Cell]) -> None:
    """Add to ``seen`` every cell of ``points`` 4-connected to the ``start`` cells."""
    seen.update(start)
    stack = list(start)
    while stack:
        x, y = stack.pop()
        for dx, dy in _STEPS:
            nb = (x + dx, y + dy)
            if nb in points and nb not in seen:
                seen.add(nb)
                stack.append(nb)


def corridor_world(
    complexity: str = "medium",
    rng: np.random.Generator | int | None = None,
    n_cells: int = 40,
    cell_size: float = 3.0,
) -> World:
    """Generate a branching corridor world of ``n_cells`` one-cell-wide cells.

    The start cell is a random corridor cell.

    Args:
        complexity: ``"low"``, ``"medium"`` or ``"high"`` branching (mean branch counts 3.56,
            5.82, 9.5 for 40 cells).
        rng: a ``numpy.random.Generator``, an int seed, or None for a fresh generator.
        n_cells: number of corridor cells (the paper: 40, i.e. 120 m of 3 m cells).
        cell_size: side of a cell (m).

    Raises:
        ConfigError: a parameter is out of range or not one of its accepted values.

    """
    check_choice("complexity", complexity, COMPLEXITIES)
    check_range("n_cells", n_cells, 2, integer=True)
    check_range("cell_size", cell_size, 0.0, low_open=True)
    gen = as_generator(rng)
    cells = grow_corridor(int(n_cells), gen, complexity)
    start = cells[int(gen.integers(len(cells)))]
    return world_from_cells(cells, start, "corridor", complexity, branch_count(cells), cell_size)
