"""Bubble coverage: the director's placement call ("Rules of the Coverage Algorithm",
"Heuristics of the Coverage Algorithm", Figs. 24-27).

``coverage(pmap, children, rng)`` places one bubble per child on the director's ProbMap with the
report's rules and heuristics: no overlap (R1), centres known and reachable (R2), radii within
every child's limits (R3), one common radius (H1), as many children as possible (H2), maximum
``V = alpha*C - beta*D`` (H3) over frontier centres (H4). The radius starts at the smallest
``r_max`` and shrinks by ``decay`` (0.9) per failed attempt, clamped at the largest ``r_min``;
at the floor a child is removed: one that can reach no VALID cell if any (OURS, switch
``drop_unreachable_first``), else the closest robot ("Removing the Closest Robot"). Idle robots in
the way are moved to the nearest free cell of a square spiral ("Move Idle Robots"; README "Choices":
move idle robots).

Run time: each child's BFS runs once per call and stops as soon as every VALID cell it
could reach is found; C_r is computed only for cells still placeable at radius r; the search
over radii is compiled, and radii that provably cannot succeed (the first two children's
reachable cells are closer than 2r, or a child reaches no VALID cell) are skipped. None of
these shortcuts changes the plan.

Pure functions: no SimPy, no Mesa; the caller's ``numpy.random.Generator`` breaks value ties.
"""

from __future__ import annotations

import enum
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
from numba import njit

from abm import portable
from abm.errors import ConfigError
from models.hierarchy.planning import (
    DistanceField,
    _children_search,
    _framed_base,
    _local_cells,
    _polyline_parts,
    shortest_paths,
    waves,
)
from models.hierarchy.probmap import ProbMap, disc_window

__all__ = [
    "PACKING_RATIO",
    "Child",
    "Plan",
    "Status",
    "closest_robot",
    "coverage",
    "move_idle_robots",
    "radius_schedule",
    "valid_cells",
    "worker_r_min",
]

PACKING_RATIO = (1.0, 2.0, 2.1547, 2.4142, 2.7013, 3.0, 3.0, 3.3048)
"""rho(S), S = 1..8: radius of the smallest circle enclosing S unit discs (optimal packings),
for the worker's minimum bubble [README "Choices": worker r_min]."""

_TOL = 1e-9


class Status(enum.Enum):
    """Outcome of one coverage call (Fig. 24)."""

    COMPLETE = "complete"
    IN_PROGRESS = "in_progress"
    CANNOT_COMPLETE = "cannot_complete"


@dataclass(frozen=True)
class Child:
    """What a director knows of one child from its INFO (``protocol.Info``, M2).

    Attributes:
        key: the child's local number (1..k).
        x, y: its current position (metres).
        r_min, r_max: its bubble limits (metres).

    """

    key: int
    x: float
    y: float
    r_min: float
    r_max: float

    def __post_init__(self) -> None:
        if not (0 < self.r_min <= self.r_max):
            raise ConfigError(
                f"child {self.key}: need 0 < r_min <= r_max, got r_min={self.r_min!r}, "
                f"r_max={self.r_max!r}"
            )

    @property
    def position(self) -> tuple[float, float]:
        """``(x, y)`` in metres."""
        return (self.x, self.y)


@dataclass(frozen=True)
class Plan:
    """Result of a coverage call.

    Attributes:
        status: COMPLETE, IN_PROGRESS or CANNOT_COMPLETE.
        radius: the common bubble radius r (metres); None unless IN_PROGRESS.
        centres: local number -> bubble centre (a cell centre, metres) of every placed child.
        paths: local number -> smoothed path (``(n, 2)`` metres) of every placed child; a
            one-point path means the child already stands on its centre.
        distances: local number -> D, the Dijkstra steps (cells) to its centre.
        idle: children left without a bubble (removed at the floor, "Removing the Closest Robot"),
            local order.
        idle_moves: idle child -> smoothed path to its refuge, for idle robots in the way.
        stranded: idle children in the way for which no reachable refuge exists (diagnostic).
        waves: placed children that must move, grouped into waves ("Path Planning", Fig. 33).
        idle_waves: idle movers grouped into waves; dispatched before ``waves``.
        radii_tried: the final radius's position in the schedule (1 = the first radius; radii
            skipped by the exact bounds count, and each restart after a removal counts one).

    """

    status: Status
    radius: float | None = None
    centres: dict[int, tuple[float, float]] = field(default_factory=dict)
    paths: dict[int, np.ndarray] = field(default_factory=dict)
    distances: dict[int, int] = field(default_factory=dict)
    idle: tuple[int, ...] = ()
    idle_moves: dict[int, np.ndarray] = field(default_factory=dict)
    stranded: tuple[int, ...] = ()
    waves: list[list[int]] = field(default_factory=list)
    idle_waves: list[list[int]] = field(default_factory=list)
    radii_tried: int = 0


def worker_r_min(n_children: int, r_min_child: float) -> float:
    """A worker's minimum bubble radius: ``rho(S) * r_min_child``, the smallest circle that
    holds its S children's minimum bubbles without overlap [README "Choices": worker r_min].

    Raises:
        ConfigError: ``n_children`` outside 1..8 (the tabulated packings) or a bad radius.

    """
    if (
        isinstance(n_children, bool)
        or not isinstance(n_children, int)
        or not (1 <= n_children <= len(PACKING_RATIO))
    ):
        raise ConfigError(
            f"scouts_per_worker must be an integer in 1..{len(PACKING_RATIO)} for the packing "
            f"formula (set worker_r_min to override), got {n_children!r}"
        )
    if not r_min_child > 0:
        raise ConfigError(f"r_min_child must be > 0 m, got {r_min_child!r}")
    return PACKING_RATIO[n_children - 1] * r_min_child


def radius_schedule(r_max: float, r_min: float, decay: float = 0.9) -> list[float]:
    """Radii a call tries: ``r_max, decay*r_max, ...`` clamped so that ``r_min`` is the last
    ("Exponential Decay of the Scan Radius"; scouts: 21 radii from 0.80 m to 0.10 m).
    """
    if not (0 < r_min <= r_max):
        raise ConfigError(f"need 0 < r_min <= r_max, got r_min={r_min!r}, r_max={r_max!r}")
    if not (0 < decay < 1):
        raise ConfigError(f"decay must be in (0, 1), got {decay!r}")
    radii = [float(r_max)]
    while radii[-1] > r_min + _TOL * r_min:
        radii.append(max(radii[-1] * decay, r_min))
    return radii


def closest_robot(children: Sequence[Child]) -> int:
    """Local number of the child with the smallest mean Euclidean distance to the other
    children (Fig. 26; README "Choices": closest robot); ties go to the lowest local number.
    """
    if not children:
        raise ValueError("closest_robot needs at least one child")
    if len(children) == 1:
        return children[0].key
    xy = np.array([c.position for c in children], dtype=np.float64)
    d = np.hypot(xy[:, None, 0] - xy[None, :, 0], xy[:, None, 1] - xy[None, :, 1])
    mean = d.sum(axis=1) / (len(children) - 1)
    best = mean.min()
    return min(c.key for c, m in zip(children, mean, strict=True) if m <= best + _TOL)


def _valid_mask(pmap: ProbMap) -> np.ndarray:
    """VALID of Fig. 24 on the map's grid: in-bounds cells with an in-bounds unscanned
    4-neighbour (matching the 4-connected search, README "Choices": Dijkstra), minus
    EXHAUSTED.
    """
    return _valid_grid(pmap._in, pmap._scanned, pmap._exhausted)


@njit(cache=True)
def _valid_grid(inside, scanned, exhausted):
    """:func:`_valid_mask` on the map's grids, compiled (each coverage call needs it)."""
    ny, nx = inside.shape
    out = np.zeros((ny, nx), dtype=np.bool_)
    for r in range(ny):
        for c in range(nx):
            if inside[r, c] and not exhausted[r, c]:
                out[r, c] = (
                    (r > 0 and inside[r - 1, c] and not scanned[r - 1, c])
                    or (r + 1 < ny and inside[r + 1, c] and not scanned[r + 1, c])
                    or (c > 0 and inside[r, c - 1] and not scanned[r, c - 1])
                    or (c + 1 < nx and inside[r, c + 1] and not scanned[r, c + 1])
                )
    return out


@njit(cache=True)
def _valid_setup(inside, scanned, exhausted, ix0, iy0, h):
    """What a coverage call needs of the VALID cells (Fig. 24, H4), in one compiled pass:
    their local ``rows`` and ``cols`` (row-major, as ``np.nonzero``), centres ``vx``, ``vy``
    (metres), the row prefix sums of in-bounds-and-unscanned cells for C (``prefix[r, c]``:
    cells before column c), the framed VALID grid (the search's goal) and its framed flat
    indices.
    """
    valid = _valid_grid(inside, scanned, exhausted)
    ny, nx = valid.shape
    n = np.count_nonzero(valid)
    rows = np.empty(n, dtype=np.int64)
    cols = np.empty(n, dtype=np.int64)
    goal = np.zeros((ny + 2, nx + 2), dtype=np.bool_)
    prefix = np.zeros((ny, nx + 1), dtype=np.int64)
    n = 0
    for r in range(ny):
        run = 0  # the row's count in a local, not reloaded from prefix: ~1/3 faster
        for c in range(nx):
            if inside[r, c] and not scanned[r, c]:
                run += 1
            prefix[r, c + 1] = run
            if valid[r, c]:
                rows[n] = r
                cols[n] = c
                goal[r + 1, c + 1] = True
                n += 1
    vx = (ix0 + cols + 0.5) * h
    vy = (iy0 + rows + 0.5) * h
    framed_flat = (rows + 1) * (nx + 2) + cols + 1
    return rows, cols, vx, vy, prefix, goal, framed_flat


def valid_cells(pmap: ProbMap) -> np.ndarray:
    """Centres ``(n, 2)`` (metres) of the VALID cells: in bounds, bordering in-bounds unknown
    space (Fig. 24, H4), not EXHAUSTED.
    """
    rows, cols = np.nonzero(_valid_mask(pmap))
    h = pmap.cell_size
    return np.column_stack(((pmap._ix0 + cols + 0.5) * h, (pmap._iy0 + rows + 0.5) * h))


@njit(cache=True, inline="always")
def _disc_count(prefix, r0, c0, radius):
    """Optimistic gain C (H3; README "Choices": value of a candidate) of cell (r0, c0): the cells
    counted in ``prefix`` (row prefix sums of in-bounds-and-unscanned) whose centres lie within
    ``radius`` cells of its centre.
    """
    ny = prefix.shape[0]
    nx = prefix.shape[1] - 1
    reach = int(math.floor(radius + 1e-9))
    r2 = radius * radius + 1e-9
    total = 0
    for r in range(max(r0 - reach, 0), min(r0 + reach, ny - 1) + 1):
        dy = r - r0
        w = int(math.floor(math.sqrt(max(r2 - dy * dy, 0.0))))
        a = max(c0 - w, 0)
        b = min(c0 + w, nx - 1)
        if b >= a:
            total += prefix[r, b + 1] - prefix[r, a]
    return total


_PLACED, _AT_FLOOR, _NEED_RANDOM = 0, 1, 2
"""Outcomes of one :func:`_search` call."""


@njit(cache=True)
def _search(
    r, floor, decay, span, n_active, ids, dist, offsets, vx, vy, alpha, beta,
    prefix, rows, cols, inv_h, gain, stamp, gen, gen_r, uniforms, cursor,
):  # fmt: skip
    """The loop of Fig. 24 from radius ``r`` down: place the active children in
    order (fail-fast), each at the reachable VALID cell of maximum ``alpha*C - beta*D`` at least
    2r from the centres placed before it; on a failure shrink r by ``decay`` (clamped at
    ``floor``) and start again.

    Child j's reachable VALID cells are ``ids[offsets[j]:offsets[j+1]]`` (indices into the VALID
    arrays) with Dijkstra steps ``dist``. C is computed lazily and cached per radius (``gain``
    is valid where ``stamp == gen``, for radius ``gen_r``). Ties take ``uniforms[cursor]``.
    Radii with ``2r > span`` (an upper bound on how far apart the first two children's cells
    are) cannot succeed and are skipped.

    Returns ``(outcome, r, steps, cursor, placed, steps_to, gen, gen_r)``: PLACED (every
    child placed at r), AT_FLOOR (failed at the floor) or NEED_RANDOM (more uniforms needed);
    on NEED_RANDOM the attempt is rewound, so calling again with more uniforms gives the same
    result as an uninterrupted search.
    """
    placed = np.empty(n_active, dtype=np.int64)
    steps_to = np.empty(n_active, dtype=np.int64)
    longest = 0
    for j in range(n_active):
        longest = max(longest, offsets[j + 1] - offsets[j])
    ties = np.empty(max(longest, 1), dtype=np.int64)
    steps = 0
    at_floor = r <= floor * (1.0 + 1e-9)
    while True:
        while n_active > 1 and 2.0 * r > span + 1e-9 and not at_floor:
            r = max(r * decay, floor)
            steps += 1
            at_floor = r <= floor * (1.0 + 1e-9)
        if r != gen_r:
            gen += 1
            gen_r = r
        limit = 4.0 * r * r - 1e-9
        radius_cells = r * inv_h
        start = cursor
        failed = False
        hopeless = False
        for j in range(n_active):
            s0 = offsets[j]
            s1 = offsets[j + 1]
            if s1 == s0:
                failed = True
                hopeless = True  # no reachable VALID cell: fails at every radius
                break
            best = -np.inf
            count = 0
            for k in range(s0, s1):
                i = ids[k]
                ok = True
                for q in range(j):
                    p = placed[q]
                    if (vx[i] - vx[p]) ** 2 + (vy[i] - vy[p]) ** 2 < limit:
                        ok = False
                        break
                if not ok:
                    continue
                if stamp[i] != gen:
                    gain[i] = _disc_count(prefix, rows[i], cols[i], radius_cells)
                    stamp[i] = gen
                v = alpha * gain[i] - beta * dist[k]
                if v > best:
                    best = v
                    count = 0
                if v == best:
                    ties[count] = k
                    count += 1
            if count == 0:
                failed = True
                break
            pick = ties[0]
            if count > 1:
                if cursor >= uniforms.shape[0]:
                    return _NEED_RANDOM, r, steps, start, placed, steps_to, gen, gen_r
                pick = ties[int(uniforms[cursor] * count)]
                cursor += 1
            placed[j] = ids[pick]
            steps_to[j] = int(dist[pick])
        if not failed:
            return _PLACED, r, steps, cursor, placed, steps_to, gen, gen_r
        if at_floor:
            return _AT_FLOOR, r, steps, cursor, placed, steps_to, gen, gen_r
        if hopeless:
            while not at_floor:
                r = max(r * decay, floor)
                steps += 1
                at_floor = r <= floor * (1.0 + 1e-9)
        else:
            r = max(r * decay, floor)
            steps += 1
            at_floor = r <= floor * (1.0 + 1e-9)


def coverage(
    pmap: ProbMap,
    children: Sequence[Child],
    rng: np.random.Generator,
    *,
    alpha: float = 1.0,
    beta: float = 3.0,
    decay: float = 0.9,
    occupied: Sequence[Sequence[float]] = (),
    padding: int = 1,
    reset_radius_after_removal: bool = False,
    drop_unreachable_first: bool = True,
) -> Plan:
    """One call of the coverage algorithm (Fig. 24).

    Args:
        pmap: the director's map.
        children: every child in local order (1..k), with current position and radius limits.
        rng: the model's generator; breaks ties between equal values.
        alpha: weight of the gain C in ``V = alpha*C - beta*D`` (report: 1).
        beta: weight of the drive distance D in cells (report: 3).
        decay: radius factor per failed attempt (report: 0.9).
        occupied: further robot positions that block routing (e.g. the worker itself, README
            "Choices": the queen).
        padding: robot padding in cells (README "Choices": drivability).
        reset_radius_after_removal: after a closest-robot removal, restart the radius at the
            smallest r_max (True) or stay at the floor (False, the pseudo-code; README "Choices":
            common radius of mixed children).
        drop_unreachable_first: at the floor, first remove a child that cannot reach any VALID
            cell (lowest local number), and use the closest-robot rule only when every child
            could be placed alone [OURS: reading of H2 "as many bubbles as possible"; with False
            the closest robot goes even if an unplaceable child stays, as in the pseudo-code].

    Returns:
        The Plan; COMPLETE if no VALID cell is left, CANNOT_COMPLETE if every child had to be
        removed, else IN_PROGRESS with centres, radius, smoothed paths, idle moves and waves.

    """
    if not children:
        raise ConfigError("coverage needs at least one child, got none")
    if not (0 < decay < 1):
        raise ConfigError(f"decay must be in (0, 1), got {decay!r}")
    h = pmap.cell_size
    rows, cols, vx, vy, prefix, goal, framed_flat = _valid_setup(
        pmap._in, pmap._scanned, pmap._exhausted, pmap._ix0, pmap._iy0, h
    )
    if rows.size == 0:
        return Plan(Status.COMPLETE)
    base = _framed_base(pmap, padding)
    occ_r, occ_c = _local_cells(pmap, [c.position for c in children] + list(occupied))
    # Steps 8-11: every child's Dijkstra, once per call, the other robots blocking it, and its
    # reachable VALID cells (none for a child outside the map's routing region: it has no
    # route and stays idle).
    free, dist_f, pred_f, complete, all_ids, all_steps, all_offsets, boxes = _children_search(
        base, goal, framed_flat, occ_r, occ_c, len(children), max(padding, 0), vx, vy
    )
    ny, nx = pmap._scanned.shape
    fields: dict[int, DistanceField] = {}
    reach: dict[int, tuple[np.ndarray, np.ndarray]] = {}
    box: dict[int, list[float]] = {}
    cells = list(zip(occ_r.tolist(), occ_c.tolist(), strict=True))
    for i, (child, span_box) in enumerate(zip(children, boxes.tolist(), strict=True)):
        a, b = all_offsets[i], all_offsets[i + 1]
        reach[child.key] = (all_ids[a:b], all_steps[a:b])
        box[child.key] = span_box
        cell = cells[i]
        if 0 <= cell[0] < ny and 0 <= cell[1] < nx:  # in the map's routing region
            fields[child.key] = DistanceField._from_search(
                pmap, child.position, cell, free[i], dist_f[i], pred_f[i], bool(complete[i])
            )

    def pair_span(a: Child, b: Child) -> float:
        """Upper bound on the distance between any reachable VALID cells of ``a`` and ``b``
        (their bounding boxes' farthest corners): if 2r exceeds it, ``b`` cannot be placed
        once ``a`` is, so that radius fails whatever the ties.
        """
        if reach[a.key][0].size == 0 or reach[b.key][0].size == 0:
            return math.inf  # handled as hopeless by the search
        ax0, ax1, ay0, ay1 = box[a.key]
        bx0, bx1, by0, by1 = box[b.key]
        return math.hypot(max(ax1 - bx0, bx1 - ax0), max(ay1 - by0, by1 - ay0))

    gain = np.zeros(rows.size, dtype=np.int64)
    stamp = np.zeros(rows.size, dtype=np.int64)
    gen, gen_r = 0, -1.0
    uniforms = rng.random(8)
    cursor = 0
    active = list(children)
    idle: list[int] = []
    r = min(c.r_max for c in active)
    floor = max(c.r_min for c in active)
    tried = 1
    ids, dist, offsets = all_ids, all_steps, all_offsets
    span = pair_span(active[0], active[1]) if len(active) > 1 else math.inf
    while True:
        outcome, r, steps, cursor, placed, steps_to, gen, gen_r = _search(
            r, floor, decay, span, len(active), ids, dist, offsets, vx, vy, float(alpha),
            float(beta), prefix, rows, cols, 1.0 / h, gain, stamp, gen, gen_r, uniforms, cursor,
        )  # fmt: skip
        tried += steps
        if outcome == _NEED_RANDOM:
            uniforms = np.concatenate((uniforms, rng.random(uniforms.size)))
        elif outcome == _PLACED:
            keys = [c.key for c in active]
            return _plan(
                pmap, children, active, idle, dict(zip(keys, placed.tolist(), strict=True)),
                dict(zip(keys, steps_to.tolist(), strict=True)), vx, vy, r, fields, occupied,
                padding, tried,
            )  # fmt: skip
        else:  # failed at the floor: remove a child (Fig. 26)
            stuck = [c.key for c in active if drop_unreachable_first and not reach[c.key][0].size]
            victim = stuck[0] if stuck else closest_robot(active)
            active = [c for c in active if c.key != victim]
            idle.append(victim)
            if not active:
                return Plan(Status.CANNOT_COMPLETE, idle=tuple(sorted(idle)), radii_tried=tried)
            ids = np.concatenate([reach[c.key][0] for c in active])
            dist = np.concatenate([reach[c.key][1] for c in active])
            offsets = np.zeros(len(active) + 1, dtype=np.int64)
            offsets[1:] = np.cumsum([reach[c.key][0].size for c in active])
            span = pair_span(active[0], active[1]) if len(active) > 1 else math.inf
            if reset_radius_after_removal:
                r = min(c.r_max for c in active)
                floor = max(c.r_min for c in active)
                tried += 1


def _plan(pmap, children, active, idle, placed, dists, vx, vy, r, fields, occupied, padding, tried):
    """Assemble the IN_PROGRESS plan: smoothed paths, idle moves and waves (steps 17-19)."""
    centres = {k: (float(vx[i]), float(vy[i])) for k, i in placed.items()}
    paths = {}
    for child in active:
        f = fields[child.key]
        paths[child.key] = f._smoothed_path_to(*centres[child.key])
    idle_children = [c for c in children if c.key in set(idle)]
    idle_moves, stranded = move_idle_robots(
        pmap,
        idle_children,
        centres,
        r,
        paths,
        everyone=children,
        occupied=occupied,
        padding=padding,
        fields=fields,
    )
    moving = {k: p for k, p in paths.items() if p.shape[0] > 1}
    return Plan(
        Status.IN_PROGRESS,
        radius=float(r),
        centres=centres,
        paths=paths,
        distances=dists,
        idle=tuple(sorted(idle)),
        idle_moves=idle_moves,
        stranded=stranded,
        waves=waves(moving, pmap.cell_size, padding),
        idle_waves=waves(idle_moves, pmap.cell_size, padding),
        radii_tried=tried,
    )


@njit(cache=True)
def _disc_grid(ny, nx, ix0, iy0, h, xy, r):
    """The bubbles' part of CONFLICT (Fig. 27) on a map of ``ny`` x ``nx`` cells with origin
    cell (ix0, iy0): cells whose centre lies within ``r`` of a centre ``xy[i]`` (metres),
    compiled; each disc is tested over the cells of its window (:func:`disc_window`) only.
    """
    out = np.zeros((ny, nx), dtype=np.bool_)
    limit = r * r + _TOL * h * h
    for i in range(xy.shape[0]):
        cx = xy[i, 0]
        cy = xy[i, 1]
        r0, r1, c0, c1 = disc_window(cx, cy, r, h, ix0, iy0, ny, nx)
        for row in range(r0, r1):
            dy = (iy0 + row + 0.5) * h - cy
            for col in range(c0, c1):
                dx = (ix0 + col + 0.5) * h - cx
                if dx * dx + dy * dy <= limit:
                    out[row, col] = True
    return out


@njit(cache=True)
def _mark_path(grid, pts, padding, ix0, iy0):
    """Mark in ``grid`` (local cells, origin cell (ix0, iy0)) the cells a robot following the
    polyline ``pts`` (cell units) sweeps: :func:`~models.hierarchy.planning.padded_cells`
    (the supercover of every segment dilated by ``padding``; a one-point path gives its cell),
    compiled, without the sorted keys.
    """
    ny, nx = grid.shape
    for cells in _polyline_parts(pts):
        for j in range(cells.shape[0]):
            c = cells[j, 0] - ix0
            r = cells[j, 1] - iy0
            for row in range(max(r - padding, 0), min(r + padding + 1, ny)):
                for col in range(max(c - padding, 0), min(c + padding + 1, nx)):
                    grid[row, col] = True


def move_idle_robots(
    pmap: ProbMap,
    idle: Sequence[Child],
    centres: Mapping[int, Sequence[float]],
    r: float,
    paths: Mapping[int, np.ndarray],
    *,
    everyone: Sequence[Child] = (),
    occupied: Sequence[Sequence[float]] = (),
    padding: int = 1,
    fields: Mapping[int, DistanceField] | None = None,
) -> tuple[dict[int, np.ndarray], tuple[int, ...]]:
    """Move idle robots out of the way of the placed ones (Fig. 27).

    CONFLICT = cells with centre within ``r`` of a placed centre plus the padded cells of every
    placed path. Each idle robot standing in CONFLICT (list order) goes to the first cell of a
    square spiral around its cell (rings 1, 2, ...; clockwise from north) that is outside
    CONFLICT and reachable through drivable cells; its refuge and padded path join CONFLICT.

    Args:
        pmap: the director's map.
        idle: the idle children, in local order.
        centres: placed children's bubble centres (metres).
        r: the common bubble radius (metres).
        paths: placed children's smoothed paths.
        everyone: all children (their positions block routing); defaults to ``idle``.
        occupied: further blocking positions (e.g. the worker itself).
        padding: robot padding in cells.
        fields: distance fields already computed for these children (reused when given).

    Returns:
        ``(moves, stranded)``: idle child -> smoothed path to its refuge, and the idle children in
        the way that found no refuge (they stay put).

    """
    if not idle:
        return {}, ()
    ny, nx = pmap._scanned.shape
    h = pmap.cell_size
    xy = np.array(list(centres.values()), dtype=np.float64).reshape(-1, 2)
    conflict = _disc_grid(ny, nx, pmap._ix0, pmap._iy0, h, xy, float(r))

    def add_path(path: np.ndarray) -> None:
        pts = np.asarray(path, dtype=np.float64) / h
        _mark_path(conflict, pts, int(padding), pmap._ix0, pmap._iy0)

    for path in paths.values():
        add_path(path)
    everyone = list(everyone) or list(idle)
    moves: dict[int, np.ndarray] = {}
    stranded: list[int] = []
    for child in idle:
        here = pmap._local(*child.position)
        if here is None or not conflict[here]:
            continue
        f = fields.get(child.key) if fields else None
        if f is None:
            others = [c.position for c in everyone if c.key != child.key]
            f = shortest_paths(pmap, child.position, others + list(occupied), padding)
        free = np.argwhere(~conflict & (f.dist >= 0))
        if free.size == 0:
            stranded.append(child.key)
            continue
        dr = free[:, 0] - here[0]
        dc = free[:, 1] - here[1]
        ring = np.maximum(np.abs(dr), np.abs(dc))
        angle = np.mod(portable.arctan2(dc, dr), 2 * np.pi)
        best = np.lexsort((angle, ring))[0]
        target = pmap._centre_of(int(free[best, 0]), int(free[best, 1]))
        path = f._smoothed_path_to(*target)
        moves[child.key] = path
        conflict[free[best, 0], free[best, 1]] = True
        add_path(path)
    return moves, tuple(stranded)
