"""The baselines of Purohit et al. Sect. 4.2, run on the same arena, motion and noise.

- Random walk (Gage [8]): the paper gives no rule (README "Choices": random walk).
  :func:`lattice_turns` is the default, a random cardinal turn every tick (the paper likens a
  degraded SugarMap's "high variance" to a random walk's, Sect. 4.3.1); :class:`BounceWalk` flies
  straight until it bumps, then takes a heading uniform in [0, 360) (Gage's randomised straight-line
  search).
- OMSTC (Hazon, Mieli, Kaminka [9]): online multi-robot spanning-tree coverage with accurate
  positions, the paper's ideal reference. :class:`OMSTC` is our D-cell version (README "Choices":
  OMSTC), not the mega-cell Spiral-STC of [7].

Every function here returns commands only; the caller executes them with the truth model and
the bump model (README "Choices": walls) and reports the bumps back.
"""

from collections import deque

import numpy as np

from abm import portable
from abm.errors import ConfigError, check_range

__all__ = ["BounceWalk", "OMSTC", "lattice_turns"]

Cell = tuple[int, int]

#: The lattice walk's turns (deg): straight, right, left, back (README "Choices": random walk).
_TURNS = np.array([0.0, 90.0, -90.0, 180.0])
#: The 4-neighbour steps (dx, dy) in counter-clockwise order from north: N, W, S, E.
_CCW = ((0, 1), (-1, 0), (0, -1), (1, 0))


def lattice_turns(rng: np.random.Generator, n: int) -> np.ndarray:
    """The lattice random walk's commanded turns for one tick (README "Choices": random walk).

    Args:
        rng: the generator.
        n: robots (>= 0).

    Returns:
        ``(n,)`` turns (deg), each uniform over {0, 90, -90, 180}, relative to the last
        commanded heading.

    """
    check_range("n", n, 0, integer=True)
    return _TURNS[rng.integers(0, len(_TURNS), n)]


class BounceWalk:
    """Gage-style random straight-line search: fly straight until blocked, then a new heading
    uniform in [0, 360) (README "Choices": random walk, option ``rw="bounce"``).

    Every robot starts facing north (0 deg), as every node does at tau = 0 (README "Choices":
    start); the start therefore draws nothing from ``rng``, which the constructor takes only so that
    it is built like every other random part of a run.

    Args:
        n: robots (>= 1).
        rng: the run's generator (not drawn from at construction).

    Attributes:
        heading: ``(n,)`` the absolute headings (deg) last issued.

    """

    def __init__(self, n: int, rng: np.random.Generator) -> None:
        check_range("n", n, 1, integer=True)
        self.heading = np.zeros(int(n))

    def headings(self, blocked: np.ndarray, rng: np.random.Generator) -> np.ndarray:
        """The absolute headings (deg) of this tick: a fresh draw where the last move bumped.

        Args:
            blocked: ``(n,)`` True where the last move bumped.
            rng: the generator of the new headings (one draw per blocked robot).

        Returns:
            ``(n,)`` headings (deg), a copy.

        Raises:
            ConfigError: ``blocked`` does not have one entry per robot.

        """
        blocked = np.asarray(blocked, dtype=bool)
        if blocked.shape != self.heading.shape:
            raise ConfigError(f"blocked must have shape {self.heading.shape}, got {blocked.shape}")
        self.heading[blocked] = rng.uniform(0.0, 360.0, int(blocked.sum()))
        return self.heading.copy()


class OMSTC:
    """Online multi-robot spanning-tree coverage on true D-cells, the paper's ideal reference
    (Sect. 4.2; README "Choices": OMSTC, the D-cell version).

    Each robot grows its own depth-first tree from its start cell over the cells no robot has
    covered yet (the shared binary map of true coverage), scanning the 4-neighbours
    counter-clockwise from its parent's direction (N first at the root). The first new one
    (uncovered, unblocked, and not the cell another robot is heading for as its new child: [9]'s
    robots keep out of cells another robot's tree has claimed, and without it two robots that
    meet would move as one, since no collisions are modelled) becomes a child and the target;
    with none left it backtracks to its tree parent. Back at a subtree's root with nothing left
    it helps: a breadth-first search over covered cells (known free, since a robot stood in
    them) finds the nearest covered cell with a new neighbour; the robot walks there and grows a
    new subtree from it. It stops when no such cell is reachable.

    Walls and obstacles are found only by bumping, as SugarMap's explorers find them ("for
    parity", README "Choices": OMSTC): the true map's values are never read, only its shape, the
    extent of the grid. A bump marks the target cell blocked for that robot alone, as
    SugarMap's planners keep their marks to themselves. A bump on the way to a covered cell
    (backtracking or a help walk) cannot be a wall, since a robot stood there: it is actuation
    noise grazing a wall, so the robot keeps that target and tries again.

    Args:
        free: the true arena's navigable cells ``[rows, cols]`` at D; only its shape is used.
        roots: each robot's start cell ``(ix, iy)``.

    Attributes:
        parent: per robot, cell -> its tree parent (None at the root of each subtree).
        obstacles: per robot, the cells it bumped into.
        target: per robot, the cell it is heading for, or None.
        route: per robot, the cells still to walk on a help walk, ending at the new root.
        done: per robot, True once no uncovered cell is left in its reach; it then stops for
            good (coverage only grows and its bumped cells stay blocked).

    """

    def __init__(self, free: np.ndarray, roots: list[Cell]) -> None:
        shape = np.shape(free)
        if len(shape) != 2 or 0 in shape:
            raise ConfigError(f"free must be a non-empty 2-D array, got shape {shape}")
        self.shape: tuple[int, int] = (int(shape[0]), int(shape[1]))
        roots = [self._root(r) for r in roots]
        if not roots:
            raise ConfigError("roots must list at least one start cell, got none")
        self.parent: list[dict[Cell, Cell | None]] = [{r: None} for r in roots]
        self.obstacles: list[set[Cell]] = [set() for _ in roots]
        self.target: list[Cell | None] = [None] * len(roots)
        self.route: list[list[Cell]] = [[] for _ in roots]
        self.done = [False] * len(roots)
        self._last: list[Cell | None] = list(roots)
        self._exploring = [False] * len(roots)

    def command(
        self,
        robot: int,
        position: np.ndarray,
        covered: np.ndarray,
        cell: float,
        speed: float,
        dt: float,
    ) -> tuple[float, float] | None:
        """The robot's command this tick (closed loop on its true position, README "Choices":
        OMSTC).

        Args:
            robot: its index in ``roots``.
            position: its true position (m) from the arena's south-west corner.
            covered: the shared binary map of true coverage ``[rows, cols]``, including every
                robot's current cell.
            cell: D (m).
            speed: v_cmd (m/s).
            dt: the tick (s).

        Returns:
            ``(heading, speed)``: the compass heading (deg) toward the target cell's centre and
            ``min(speed, distance / dt)`` (m/s); None when no uncovered cell is in reach: for
            good (:attr:`done`) once none is left, for this tick only while the only ones are
            claimed by other robots.

        Raises:
            ConfigError: ``covered`` does not have the arena's shape.

        """
        if np.shape(covered) != self.shape:
            raise ConfigError(f"covered must have shape {self.shape}, got {np.shape(covered)}")
        if self.done[robot]:
            return None
        here = (int(position[0] // cell), int(position[1] // cell))
        target = self.target[robot]
        if target is None or here == target or not _adjacent(here, target):
            target = self.target[robot] = self._next(robot, here, covered)
        if target is None:
            return None
        offset = (np.array(target) + 0.5) * cell - np.asarray(position, dtype=float)
        distance = float(np.hypot(*offset))
        heading = float(np.degrees(portable.arctan2(offset[0], offset[1])) % 360.0)
        return heading, min(speed, distance / dt)

    def blocked(self, robot: int) -> None:
        """The robot's last move bumped: an uncovered target is an obstacle to it, out of its
        tree; a covered target (backtracking, helping) is kept and tried again.
        """
        target = self.target[robot]
        if target is None or not self._exploring[robot]:
            return
        self.obstacles[robot].add(target)
        self.parent[robot].pop(target, None)
        self.target[robot] = None

    def _root(self, cell: object) -> Cell:
        """A start cell inside the grid, or ConfigError."""
        try:
            ix, iy = cell
            if int(ix) != ix or int(iy) != iy:
                raise ValueError
        except (TypeError, ValueError):
            raise ConfigError(f"roots must hold cells (ix, iy) of integers, got {cell!r}") from None
        ix, iy = int(ix), int(iy)
        if not self._inside((ix, iy)):
            rows, cols = self.shape
            raise ConfigError(f"roots must lie in the {cols} x {rows} cell grid, got {cell!r}")
        return ix, iy

    def _next(self, robot: int, here: Cell, covered: np.ndarray) -> Cell | None:
        """The next target: the next cell of a help walk, a new child, the tree parent, or the
        first cell of a new help walk; None if no uncovered cell is in reach (see
        :meth:`_help`).
        """
        step = self._follow_route(robot, here)
        if step is not None:
            return step
        parent = self.parent[robot]
        if here not in parent:  # pushed off the tree by noise: hang here on the last cell
            last = self._last[robot]
            parent[here] = last if last in parent and _adjacent(last, here) else None
        self._last[robot] = here
        child = self._child(robot, here, covered)
        self._exploring[robot] = child is not None
        if child is not None:
            parent[child] = here
            return child
        if parent[here] is not None:
            return parent[here]
        route = self._help(robot, here, covered)
        self.done[robot] = route == []
        self.route[robot] = route or []
        return route[0] if route else None

    def _follow_route(self, robot: int, here: Cell) -> Cell | None:
        """The next cell of the help walk, or None; the walk's end (or leaving it, pushed by
        noise) makes ``here`` the root of a new subtree.
        """
        route = self.route[robot]
        if not route:
            return None
        if route[0] == here:
            route.pop(0)
        self._exploring[robot] = False
        if route and _adjacent(here, route[0]):
            return route[0]
        route.clear()
        self.parent[robot][here] = None
        return None

    def _child(self, robot: int, here: Cell, covered: np.ndarray) -> Cell | None:
        """The first new neighbour (see :meth:`_new`), counter-clockwise from the parent's
        direction (from N at a root).
        """
        up = self.parent[robot][here]
        start = 0 if up is None else _CCW.index((up[0] - here[0], up[1] - here[1])) + 1
        claimed = self._claimed(robot)
        for k in range(len(_CCW)):
            dx, dy = _CCW[(start + k) % len(_CCW)]
            n = (here[0] + dx, here[1] + dy)
            if self._open(robot, n) and self._new(n, covered, claimed):
                return n
        return None

    def _help(self, robot: int, here: Cell, covered: np.ndarray) -> list[Cell] | None:
        """The help step's walk: BFS over covered cells from ``here`` to the nearest covered
        cell with a new neighbour; the cells to enter, ending with that one.

        Returns:
            The walk; None if the only uncovered cells in reach are claimed by other robots
            (wait: entering them may open new ground); empty if nothing is left in reach.

        """
        claimed = self._claimed(robot)
        came_from: dict[Cell, Cell | None] = {here: None}
        queue = deque([here])
        waiting = False
        while queue:
            cell = queue.popleft()
            for dx, dy in _CCW:
                n = (cell[0] + dx, cell[1] + dy)
                if n in came_from or not self._open(robot, n):
                    continue
                if covered[n[1], n[0]]:
                    came_from[n] = cell
                    queue.append(n)
                elif n in claimed:
                    waiting = True
                else:
                    return _walk(came_from, cell)
        return None if waiting else []

    def _claimed(self, robot: int) -> set[Cell]:
        """The uncovered cells the other robots are heading for as new children of their trees
        (Hazon et al.'s robots keep out of the cells another robot's tree has claimed).
        """
        return {
            target
            for other, target in enumerate(self.target)
            if other != robot and target is not None and self._exploring[other]
        }

    @staticmethod
    def _new(cell: Cell, covered: np.ndarray, claimed: set[Cell]) -> bool:
        """Neither covered by any robot nor claimed by another robot's tree."""
        return not covered[cell[1], cell[0]] and cell not in claimed

    def _open(self, robot: int, cell: Cell) -> bool:
        """Inside the grid and not bumped into by this robot."""
        return self._inside(cell) and cell not in self.obstacles[robot]

    def _inside(self, cell: Cell) -> bool:
        rows, cols = self.shape
        return 0 <= cell[0] < cols and 0 <= cell[1] < rows


def _walk(came_from: dict[Cell, Cell | None], end: Cell) -> list[Cell]:
    """The BFS path to ``end``, without its start cell."""
    path = [end]
    while came_from[path[-1]] is not None:
        path.append(came_from[path[-1]])
    return path[-2::-1]


def _adjacent(a: Cell, b: Cell) -> bool:
    return abs(a[0] - b[0]) + abs(a[1] - b[1]) == 1
