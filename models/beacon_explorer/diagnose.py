"""Why a corridor search did not complete: the perfect-DFS bounds of a world and the failure cause.

Stirling et al. (2010) search corridors depth first (Sect. 3.3). Two bounds say whether ``n``
explorers (plus the pre-deployed base beacon) can cover a corridor world at all; a run that
did not complete on a world within the bound is then put in one failure class from the state
it ended in (:func:`classify`).

**Cells.** A corridor world is a tree of 3 m cells (:mod:`models.environments.corridor`). Complete
coverage (99.9 % of the free area inside some beacon's S_r = 3.5 m disc) needs a beacon in
every dead-end cell: from the cell before it, the far 1 m of a 3 m cell lies 4.5 m away.

**Path bound** (``path_bound``): the deployed beacons are only ever the chain from the base to
the cell being searched, one per cell. A dead end at ``depth`` cells from the base needs
``depth`` explorers, so the world is coverable iff its deepest cell lies at most ``n`` cells
from the base. No controller that keeps its network connected does better.

**Perfect DFS under the paper's rules** (:func:`paper_dfs_completes`): the beacon controller of
Fig. 2 executed on the cell tree without noise, drift or concurrency: explorers arrive one at a
time, each after the previous has attached and every decision has settled, and a beacon free to
detach does so at once and is the next explorer. An explorer starts at the base and at each
beacon reads its desired direction: the first empty direction clockwise from North (it attaches
there, one cell on), else the unblocked neighbour with the highest forwards hop count (ties:
first clockwise, as :func:`~models.beacon_explorer.flowchart.decide`), else, redeploying, back
towards the base. So a junction fills one cell of *every* side branch before explorers pass it
into the first one clockwise, and those stub beacons wait, one per pending branch, until the
branches before them are searched. A corridor beacon redeploys when every neighbour with a
higher hop count is searched (its branch signalled back) and may detach when it has no such
neighbour left; its parent remembers the direction as searched. The world is completable iff
this search puts a beacon in every cell before all ``n`` explorers are beacons none of which
may detach. Stubs make it stricter than the path bound.
"""

from collections import deque
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from models.environments import World

__all__ = [
    "CAUSES",
    "Diagnosis",
    "cell_depths",
    "classify",
    "diagnose",
    "paper_dfs_completes",
]

Cell = tuple[int, int]

#: Cardinal steps in the flowchart's order, clockwise from North: N, E, S, W as (dx, dy).
_CLOCKWISE: tuple[Cell, ...] = ((0, 1), (1, 0), (0, -1), (-1, 0))

#: Failure classes of a non-completed run on a completable world, in the order they are tested.
CAUSES = (
    "time limit",
    "stalled",
    "wrong searched label",
    "stranded: redeployment never triggers",
    "stranded: detach blocked",
    "lattice drift",
    "side branch over-filled",
    "other",
)


def _tree(world: World) -> tuple[dict[Cell, int], dict[Cell, Cell | None], set[Cell]]:
    cells = {(int(x), int(y)) for x, y in world.cells}
    start = world.start_cell
    depth: dict[Cell, int] = {start: 0}
    parent: dict[Cell, Cell | None] = {start: None}
    queue = deque([start])
    while queue:
        cell = queue.popleft()
        for dx, dy in _CLOCKWISE:
            nb = (cell[0] + dx, cell[1] + dy)
            if nb in cells and nb not in depth:
                depth[nb] = depth[cell] + 1
                parent[nb] = cell
                queue.append(nb)
    return depth, parent, cells


def cell_depths(world: World) -> dict[Cell, int]:
    """Hop distance (cells, 4-connected) of every free cell from the start cell."""
    return _tree(world)[0]


def _children(cell: Cell, depth: dict[Cell, int]) -> list[Cell]:
    """Neighbour cells one hop further from the base, clockwise from North."""
    out = []
    for dx, dy in _CLOCKWISE:
        nb = (cell[0] + dx, cell[1] + dy)
        if depth.get(nb) == depth[cell] + 1:
            out.append(nb)
    return out


def paper_dfs_completes(world: World, n: int) -> bool:
    """Whether the perfect depth-first search under the paper's rules covers ``world``.

    See the module docstring for the rules simulated. Cycles (none in generated corridors) are
    searched on the breadth-first tree of the cell graph.
    """
    depth, parent_of, _cells = _tree(world)
    kids = {c: _children(c, depth) for c in depth}
    base = world.start_cell
    beacons: set[Cell] = {base}
    searched: dict[Cell, set[Cell]] = {base: set()}
    visited: set[Cell] = {base}
    explorers = n

    def redeploying(c: Cell) -> bool:
        return all(
            (k in beacons and redeploying(k)) or (k not in beacons and k in searched[c])
            for k in kids[c]
        )

    while True:
        # Detach every beacon free to: redeploying, no higher neighbour left (a leaf), not base.
        changed = True
        while changed:
            changed = False
            for c in sorted(beacons, key=depth.get, reverse=True):
                if c != base and redeploying(c) and not any(k in beacons for k in kids[c]):
                    beacons.discard(c)
                    searched[parent_of[c]].add(c)
                    explorers += 1
                    changed = True
        if len(visited) == len(depth):
            return True
        if explorers == 0 or redeploying(base):
            return False
        # One explorer follows desired directions from the base until it attaches.
        at = base
        while True:
            empty = [k for k in kids[at] if k not in beacons and k not in searched[at]]
            if empty:
                beacons.add(empty[0])
                searched[empty[0]] = set()
                visited.add(empty[0])
                explorers -= 1
                break
            onward = [k for k in kids[at] if k in beacons and not redeploying(k)]
            if not onward:  # cannot happen below a beacon that is not redeploying
                return False
            at = onward[0]  # equal hop counts: first clockwise


@dataclass(frozen=True)
class Diagnosis:
    """One corridor run judged against its world's bounds.

    Attributes:
        max_depth: cells from the base to the deepest cell.
        path_bound: coverable by a chain to every cell (``max_depth <= n``).
        completable: covered by the perfect DFS under the paper's rules.
        complete: the run reached complete coverage.
        cause: the failure class (one of :data:`CAUSES`) of a completable run that did not
            complete; "" otherwise.
        stranded: beacons left in fully covered branches.
        extra_in_side: beacons beyond the first one in a side branch explorers should not enter.
        shared_cells: beacons sharing a cell with another.

    """

    max_depth: int
    path_bound: bool
    completable: bool
    complete: bool
    cause: str
    stranded: int
    extra_in_side: int
    shared_cells: int


def _cell_covered(model, cells: Iterable[Cell]) -> dict[Cell, bool]:
    cov = model.coverage
    sub = cov.subdivision
    out = {}
    for ix, iy in cells:
        block = np.s_[iy * sub : (iy + 1) * sub, ix * sub : (ix + 1) * sub]
        free = cov.free[block]
        out[(ix, iy)] = bool((cov.covered[block] | ~free).all())
    return out


def classify(model) -> Diagnosis:
    """Judge a finished corridor run of :class:`~models.beacon_explorer.BeaconExplorerModel`.

    The cause of a completable run that did not complete is the first of :data:`CAUSES` that
    applies: the run hit the time limit or was stalled; a beacon remembers (or was told) a
    direction as searched or taken while no beacon is there and cells beyond it are uncovered;
    a beacon sits in a branch whose cells are all covered (never redeploying, or redeploying
    but kept by a higher neighbour); two beacons share a cell; a side branch holds more than its
    one stub beacon while a branch clockwise before it is not searched yet; else "other".
    """
    world = model.world
    n = model.n_robots
    depth, _parent, _cells = _tree(world)
    max_depth = max(depth.values())
    completable = paper_dfs_completes(world, n)
    complete = model.coverage.fraction >= model.params.complete_fraction
    covered = _cell_covered(model, depth)
    kids = {c: _children(c, depth) for c in depth}

    subtree_done: dict[Cell, bool] = {}
    for c in sorted(depth, key=depth.get, reverse=True):
        subtree_done[c] = covered[c] and all(subtree_done[k] for k in kids[c])

    res = world.cell_size
    at: dict[Cell, list] = {}
    for beacon in model.beacons.beacons.values():
        cell = (int(beacon.position[0] // res), int(beacon.position[1] // res))
        at.setdefault(cell, []).append(beacon)
    shared = sum(len(bs) - 1 for bs in at.values() if len(bs) > 1)

    stranded = [b for c, bs in at.items() for b in bs if c in depth and subtree_done[c]]
    stranded = [b for b in stranded if not b.is_base]

    wrong = False
    for c, bs in at.items():
        if c not in depth:
            continue
        for b in bs:
            for d in b.searched | b.reported_taken:
                dx, dy = _CLOCKWISE[d]
                nb = (c[0] + dx, c[1] + dy)
                if nb in kids[c] and nb not in at and not subtree_done[nb]:
                    wrong = True

    extra = 0
    for c in depth:
        pending = [k for k in kids[c] if not subtree_done[k]]
        for k in pending[1:]:  # explorers belong in the first pending branch clockwise
            extra += max(0, _count_beacons(k, kids, at) - 1)

    reason = model.end_reason or ""
    cause = ""
    if completable and not complete:
        if reason.startswith("time limit"):
            cause = "time limit"
        elif reason.startswith("stalled"):
            cause = "stalled"
        elif wrong or reason.startswith("searched"):
            cause = "wrong searched label"
        elif any(not b.redeploying for b in stranded):
            cause = "stranded: redeployment never triggers"
        elif stranded:
            cause = "stranded: detach blocked"
        elif shared:
            cause = "lattice drift"
        elif extra:
            cause = "side branch over-filled"
        else:
            cause = "other"
    return Diagnosis(
        max_depth,
        max_depth <= n,
        completable,
        complete,
        cause,
        len(stranded),
        extra,
        shared,
    )


def _count_beacons(cell: Cell, kids: dict[Cell, list[Cell]], at: dict[Cell, list]) -> int:
    total, stack = 0, [cell]
    while stack:
        c = stack.pop()
        total += len(at.get(c, ()))
        stack.extend(kids[c])
    return total


def diagnose(model) -> dict:
    """:func:`classify` as a flat row for tables."""
    d = classify(model)
    return {
        "max_depth": d.max_depth,
        "path_bound": d.path_bound,
        "completable": d.completable,
        "complete": d.complete,
        "cause": d.cause,
        "stranded": d.stranded,
        "extra_in_side": d.extra_in_side,
        "shared_cells": d.shared_cells,
    }
