"""The coverage path planner of Fig. 4 (Purohit et al. Sect. 3.2); P1-P18 in the
code number the flowchart's steps as we read them.

A depth-first, spanning-tree planner on the brain's grid of D-cells, one instance per explorer,
run at the base station (README "Choices": where the planner runs). It reads the GlobalMap ``G``
(eq. 10): a neighbour counts as "not covered" while ``G < COVER_TH`` (Sect. 3.2, 4.3.6). Among the
uncovered N/E/S/W neighbours it picks one at random, "the probability of picking a cell is inverse
of its confidence of coverage" (read as ``1 - G + eps``, README "Choices": next-cell weight; option
``1 / (G + eps)``), makes it a child in its tree and heads there. When every neighbour is covered or
blocked it backtracks:

- ``"soft"`` (default, README "Choices": backtracking): "increments the probability of picking the
  last covered cell", read as any unblocked neighbour with the tree parent's weight raised by
  ``beta`` (the last covered cell read as the tree parent);
- ``"hard"``: the idealised DFS, straight back to the tree parent; at the root with nothing
  left the explorer idles and re-checks every tick (COVER_TH is "an exit condition");
- ``"frontier"`` (ours, a control for Fig. 11): the first step of a shortest path through cells
  counted covered to the nearest uncovered, unblocked cell (a breadth-first search on the
  estimate grid, as OMSTC's help step), so an explorer whose surroundings others have covered
  heads for what is left instead of back along its own tree; "soft" when there is none.

The explorer has no range sensor, so a cell is known to be blocked only by bumping into it
(README "Choices": walls); the mark lives in the brain's frame, which drifts from the true one, so
it expires after ``blocked_ttl`` s. Neighbours outside the estimate grid count as blocked.
"""

from bisect import bisect_right
from collections import deque
from itertools import accumulate

import numpy as np

from abm.errors import ConfigError, check_choice, check_range

__all__ = ["CoveragePlanner", "HEADINGS", "heading_to"]

Cell = tuple[int, int]

#: The backtracking rules (module docstring).
BACKTRACKS = ("soft", "hard", "frontier")

#: Compass heading (deg, clockwise from north, README "Choices": heading frame) of each 4-neighbour
#: step (dx, dy).
HEADINGS = {(0, 1): 0.0, (1, 0): 90.0, (0, -1): 180.0, (-1, 0): 270.0}


def heading_to(cell: Cell, target: Cell) -> float:
    """The cardinal heading (deg) from a cell to a 4-adjacent target (N 0, E 90, S 180, W 270).

    Raises:
        ConfigError: the target is not 4-adjacent to the cell.

    """
    step = (target[0] - cell[0], target[1] - cell[1])
    if step not in HEADINGS:
        raise ConfigError(f"target must be 4-adjacent to cell {cell}, got {target}")
    return HEADINGS[step]


def _neighbours(cell: Cell) -> list[Cell]:
    """The 4-neighbours, in the order N, E, S, W."""
    return [(cell[0] + dx, cell[1] + dy) for dx, dy in HEADINGS]


def _probability(coverage: np.ndarray, cell: Cell) -> float:
    """G at a cell, checked to be a probability (a bad weight would skew every draw)."""
    g = float(coverage[cell[1], cell[0]])
    if not 0.0 <= g <= 1.0:
        raise ConfigError(f"coverage must hold probabilities in [0, 1], got {g} at {cell}")
    return g


def _as_cell(name: str, value: object) -> Cell:
    """A cell ``(ix, iy)`` of two integers, or ConfigError naming the parameter."""
    try:
        ix, iy = value
        if int(ix) != ix or int(iy) != iy:
            raise ValueError
    except (TypeError, ValueError):
        raise ConfigError(
            f"{name} must be a cell (ix, iy) of two integers, got {value!r}"
        ) from None
    return int(ix), int(iy)


class CoveragePlanner:
    """One explorer's coverage path planner (Fig. 4).

    Args:
        root: the explorer's start cell ``(ix, iy)`` in the estimate grid.
        cover_th: COVER_TH in (0, 1]: a cell with ``G >= cover_th`` counts as covered; 0.95
            (Sect. 4.3.6).
        backtrack: ``"soft"``, ``"hard"`` or ``"frontier"`` (see the module docstring; README
            "Choices": backtracking).
        beta: the tree parent's weight bonus under soft backtracking (>= 0; ours: 1).
        blocked_ttl: seconds a bumped cell stays blocked (> 0; ours: 30, README "Choices": walls).
        pick: a candidate's weight: ``"one_minus"`` ``(1 - G) + eps`` or ``"inverse"``
            ``1 / (G + eps)`` (README "Choices": next-cell weight).
        self_cover: what is "covered by itself" (Sect. 3.2's step 1): ``"map"``, only what the
            GlobalMap says at COVER_TH, as for the other explorers; ``"tree"``, also every cell
            this planner has stood in (:attr:`visited`), whatever the GlobalMap says there.
        eps: keeps every weight positive and finite (> 0).

    Attributes:
        root: the start cell; it has no tree parent.
        target: the cell the explorer is heading for, or None.
        tree_parent: cell -> its parent in the spanning tree (None if it was entered from a
            cell that is not 4-adjacent, e.g. after a jump of the pose estimate).
        prev_cell: the cell of the last decision (P6).
        idle: True while hard backtracking has nothing left at the root (P15).
        visited: the cells this planner has decided in (its own path, by its pose estimate).
        blocked_at: cell -> the time (s) it was last bumped into (P18).

    """

    def __init__(
        self,
        root: Cell,
        *,
        cover_th: float = 0.95,
        backtrack: str = "soft",
        beta: float = 1.0,
        blocked_ttl: float = 30.0,
        pick: str = "one_minus",
        self_cover: str = "map",
        eps: float = 1e-3,
    ) -> None:
        self.root = _as_cell("root", root)
        check_range("cover_th", cover_th, 0.0, 1.0, low_open=True)
        check_choice("backtrack", backtrack, BACKTRACKS)
        check_range("beta", beta, 0.0)
        check_range("blocked_ttl", blocked_ttl, 0.0, low_open=True)
        check_choice("pick", pick, ("one_minus", "inverse"))
        check_choice("self_cover", self_cover, ("map", "tree"))
        check_range("eps", eps, 0.0, low_open=True)
        self.cover_th = float(cover_th)
        self.backtrack = backtrack
        self.beta = float(beta)
        self.blocked_ttl = float(blocked_ttl)
        self.pick = pick
        self.self_cover = self_cover
        self.eps = float(eps)
        self.target: Cell | None = None
        self.tree_parent: dict[Cell, Cell | None] = {}
        self.prev_cell: Cell | None = None
        self.idle = False
        self.visited: set[Cell] = set()
        self.blocked_at: dict[Cell, float] = {}

    def decide(
        self, cell: Cell, coverage: np.ndarray, now: float, rng: np.random.Generator
    ) -> float | None:
        """Steps P1-P17: the heading toward this tick's target.

        Args:
            cell: P1, the explorer's current cell ``(ix, iy)`` in the estimate grid, as the
                caller computes it (particle mean or presumed pose; never the truth).
            coverage: the GlobalMap ``G[iy, ix]`` in [0, 1], shape ``(H, W)``.
            now: the simulation time (s), for the blocked marks' TTL.
            rng: the generator of every random choice.

        Returns:
            The target's cardinal heading (deg), or None when there is nothing to do this tick:
            idle at the root under hard backtracking (:attr:`idle` is then True), or every
            neighbour blocked (the explorer hovers until a mark expires).

        Raises:
            ConfigError: ``cell`` is not two integers, ``coverage`` is not 2-D or a
                neighbour's value is not in [0, 1].

        """
        cell = _as_cell("cell", cell)
        coverage = np.asarray(coverage)
        if coverage.ndim != 2:
            raise ConfigError(f"coverage must be a 2-D array (H, W), got shape {coverage.shape}")
        self.idle = False
        target = self.target
        if target is not None and (cell == target or target not in _neighbours(cell)):  # P2
            target = self.target = None
        if target is not None:  # P3: hold the target until it is entered
            return heading_to(cell, target)
        self._expire(now)  # P4
        if cell not in self.tree_parent and cell != self.root:  # P5
            prev = self.prev_cell
            self.tree_parent[cell] = prev if prev in _neighbours(cell) else None
        self.prev_cell = cell  # P6
        self.visited.add(cell)
        self.target = self._choose(cell, coverage, rng)
        return None if self.target is None else heading_to(cell, self.target)  # P17

    def blocked(self, now: float) -> None:
        """P18: the move toward the target was blocked: mark the target at ``now``, drop it."""
        if self.target is not None:
            self.blocked_at[self.target] = float(now)
        self.target = None

    def _expire(self, now: float) -> None:
        """P4: forget the marks ``blocked_ttl`` s old or older."""
        self.blocked_at = {c: t for c, t in self.blocked_at.items() if now - t < self.blocked_ttl}

    def _choose(self, cell: Cell, coverage: np.ndarray, rng: np.random.Generator) -> Cell | None:
        """P7-P16: the next target, or None (idle or hemmed in)."""
        rows, cols = coverage.shape
        free = [
            n
            for n in _neighbours(cell)
            if 0 <= n[0] < cols and 0 <= n[1] < rows and n not in self.blocked_at
        ]
        g = {n: _probability(coverage, n) for n in free}
        mine = self.visited if self.self_cover == "tree" else set()
        uncovered = [n for n in free if g[n] < self.cover_th and n not in mine]  # P7
        if uncovered:  # P8-P11
            child = self._draw(uncovered, g, rng)
            if child not in self.tree_parent and child != self.root:  # P10: a tree edge
                self.tree_parent[child] = cell
            return child
        parent = self.tree_parent.get(cell)
        if self.backtrack == "frontier":
            step = self._toward_frontier(cell, coverage, mine)
            if step is not None:
                return step
        if self.backtrack != "hard":  # P13
            return self._draw(free, g, rng, bonus=parent) if free else None
        if parent in free:  # P14
            return parent
        if cell == self.root:  # P15: the exit condition, re-checked every tick
            self.idle = True
            return None
        return free[int(rng.integers(len(free)))] if free else None  # P16: escape

    def _toward_frontier(self, cell: Cell, coverage: np.ndarray, mine: set[Cell]) -> Cell | None:
        """The first step of a shortest 4-neighbour path from ``cell`` through covered cells
        (G >= COVER_TH, or its own path under ``self_cover="tree"``) to the nearest uncovered
        cell, blocked cells avoided; None when no uncovered cell is reachable so.
        """
        rows, cols = coverage.shape
        first: dict[Cell, Cell | None] = {cell: None}
        queue = deque([cell])
        while queue:
            here = queue.popleft()
            for n in _neighbours(here):
                if n in first or not (0 <= n[0] < cols and 0 <= n[1] < rows):
                    continue
                if n in self.blocked_at:
                    continue
                step = first[here] or n
                if coverage[n[1], n[0]] < self.cover_th and n not in mine:
                    return step
                first[n] = step
                queue.append(n)
        return None

    def _draw(
        self,
        cells: list[Cell],
        probability: dict[Cell, float],
        rng: np.random.Generator,
        bonus: Cell | None = None,
    ) -> Cell:
        """One of ``cells`` with probability proportional to its weight (P9, P13).

        Plain floats, not numpy: at most four weights, where numpy's per-call cost is most of
        the work; the sums and the search are the same (a running sum, the first cumulative
        weight above the draw).
        """
        eps = self.eps
        if self.pick == "one_minus":
            weights = [1.0 - probability[c] + eps for c in cells]
        else:
            weights = [1.0 / (probability[c] + eps) for c in cells]
        if bonus is not None:
            weights = [w + self.beta * (c == bonus) for w, c in zip(weights, cells, strict=True)]
        cumulative = list(accumulate(weights))
        k = bisect_right(cumulative, rng.random() * cumulative[-1])
        return cells[min(k, len(cells) - 1)]
