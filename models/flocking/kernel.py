"""The flock's update step, compiled: every bird in turn, each seeing the birds moved before it.

The declaration updates birds *sequentially* in a random order: a bird activated late in a
step sees the new positions and velocities of the birds activated before it. So one step is
one loop over the birds in that order (compiled with numba), and the neighbour index must stay
correct after every single move, not once per step.

The index is a cell list on the periodic square: ``cells x cells`` square cells whose side is
at least the visual distance, so all neighbours of a bird lie in its own cell and the eight
around it (wrapping at the edges). Each cell keeps a doubly linked list of its birds
(``head``, ``after``, ``before``), so a bird that crosses into another cell is unlinked and
linked again in O(1) right after it moves. With fewer than three cells per side the eight
surrounding cells would repeat, so there is then one cell holding every bird.

Whether a candidate is a neighbour is decided on the squared distance against a squared limit
(:func:`squared_limit`) that gives exactly the decisions of comparing the distance itself, so
the loop takes no square root per candidate and the run is the same bit for bit.
"""

import math

import numba
import numpy as np

__all__ = ["CellList", "flock_step", "order_parameters", "squared_limit", "wrap"]


class CellList:
    """The cell list of a flock on a periodic square of side ``extent`` (m).

    Args:
        positions: ``(N, 2)`` positions (m), each in ``[0, extent)``.
        extent: side of the square (m).
        radius: the largest search radius (m): the cells' side is at least this.

    Attributes:
        cells: cells per side (1 when fewer than three would fit: every bird is looked at).
        side: side of one cell (m).
        head: first bird of each cell (-1: empty), cells numbered ``ix + cells * iy``.
        after: next bird in the same cell (-1: last).
        before: previous bird in the same cell (-1: first).
        cell: the cell of each bird.
        around: ``around[c]``: cell c and the eight around it on the torus (c alone when
            there is one cell).

    """

    def __init__(self, positions: np.ndarray, extent: float, radius: float) -> None:
        n = len(positions)
        # Cells no narrower than the radius, and not many more cells than birds (a tiny
        # radius would otherwise ask for millions of empty cells).
        per_side = min(int(extent // radius), max(3, 2 * math.isqrt(n) + 1))
        self.cells = per_side if per_side >= 3 else 1
        self.side = extent / self.cells
        self.head = np.full(self.cells**2, -1, dtype=np.int64)
        self.after = np.full(n, -1, dtype=np.int64)
        self.before = np.full(n, -1, dtype=np.int64)
        self.cell = np.zeros(n, dtype=np.int64)
        self.around = _around(self.cells)
        _fill(positions, self.cells, self.side, self.head, self.after, self.before, self.cell)


def squared_limit(limit: float, strict: bool = False) -> float:
    """The largest squared distance ``s`` (m^2) with ``sqrt(s) <= limit`` (``< limit`` when
    ``strict``); -1 when there is none (``strict`` with ``limit`` 0).

    IEEE square roots are correctly rounded, so ``sqrt`` is monotone on doubles and
    ``sqrt(s) <= limit`` holds exactly when ``s <= squared_limit(limit)``: the same decision as
    on the distance, without the root. ``limit * limit`` itself can be off by an ulp (for a
    visual distance of 5 m, ``sqrt(25.000000000000004)`` rounds to 5.0, a neighbour), hence
    the search from it to the exact boundary.
    """
    inside = (lambda s: math.sqrt(s) < limit) if strict else (lambda s: math.sqrt(s) <= limit)
    s = limit * limit
    if math.isinf(s):
        return s
    while not inside(s):
        if s <= 0.0:
            return -1.0
        s = math.nextafter(s, -math.inf)
    while inside(math.nextafter(s, math.inf)):
        s = math.nextafter(s, math.inf)
    return s


@numba.njit(cache=True)
def _around(cells):
    if cells == 1:
        return np.zeros((1, 1), dtype=np.int64)
    out = np.empty((cells * cells, 9), dtype=np.int64)
    for c in range(cells * cells):
        ix, iy = c % cells, c // cells
        q = 0
        for oy in range(-1, 2):
            for ox in range(-1, 2):
                out[c, q] = (ix + ox) % cells + cells * ((iy + oy) % cells)
                q += 1
    return out


@numba.njit(cache=True)
def wrap(x: float, extent: float) -> float:
    """``x`` (m) brought back into ``[0, extent)`` on the periodic axis."""
    if x < 0.0:
        x += extent
        if x < 0.0:  # a move longer than the side
            x -= extent * math.floor(x / extent)
    elif x >= extent:
        x -= extent
        if x >= extent:
            x -= extent * math.floor(x / extent)
    if x >= extent:  # x was a hair below 0: it is at the origin
        x = 0.0
    return x


@numba.njit(cache=True)
def _cell_index(x, y, cells, side):
    ix = min(int(x / side), cells - 1)
    iy = min(int(y / side), cells - 1)
    return ix + cells * iy


@numba.njit(cache=True)
def _link(i, c, head, after, before, cell):
    first = head[c]
    after[i] = first
    before[i] = -1
    if first >= 0:
        before[first] = i
    head[c] = i
    cell[i] = c


@numba.njit(cache=True)
def _unlink(i, head, after, before, cell):
    prev, nxt = before[i], after[i]
    if prev >= 0:
        after[prev] = nxt
    else:
        head[cell[i]] = nxt
    if nxt >= 0:
        before[nxt] = prev


@numba.njit(cache=True)
def _fill(positions, cells, side, head, after, before, cell):
    for i in range(positions.shape[0]):
        _link(i, _cell_index(positions[i, 0], positions[i, 1], cells, side),
              head, after, before, cell)  # fmt: skip


@numba.njit(cache=True)
def flock_step(
    pos: np.ndarray,
    vel: np.ndarray,
    order: np.ndarray,
    extent: float,
    visual_sq: float,
    separation_sq: float,
    factors: np.ndarray,
    move: float,
    cells: int,
    side: float,
    around: np.ndarray,
    head: np.ndarray,
    after: np.ndarray,
    before: np.ndarray,
    cell: np.ndarray,
    seen: np.ndarray,
) -> tuple[float, float]:
    """One update step of the whole flock, in place, birds taken in ``order``; returns the
    flock's order parameters after it (:func:`order_parameters`: polarisation, mean
    neighbours), which the model samples every step.

    Each bird: the neighbours within the visual distance (excluding itself) give cohere =
    mean offset x cohere factor, separate = minus the mean offset to those closer than the
    separation distance x separate factor, match = mean velocity x match factor (means over
    all neighbours, 1 when there are none); its velocity becomes the unit vector of (vel +
    cohere + separate + match) / 2 (unchanged in the measure-zero case of a zero sum), and it
    moves ``move`` (m) along it, wrapping on the periodic square. ``seen[i]`` is set to bird
    i's neighbour count.

    Args:
        pos: ``(N, 2)`` positions (m), updated.
        vel: ``(N, 2)`` unit velocities, updated.
        order: the activation order of this step (a permutation of the rows).
        extent: side of the periodic square (m).
        visual_sq: ``squared_limit(visual distance)`` (m^2): a bird at distance d is a
            neighbour when d <= the visual distance, i.e. when d^2 <= visual_sq.
        separation_sq: ``squared_limit(separation, strict=True)`` (m^2): a neighbour is
            pushed away from when d < the separation distance, i.e. d^2 <= separation_sq.
        factors: cohere, separate and match factors.
        move: distance moved per step (m).
        cells: cells per side of the cell list (1: search every bird).
        side: side of one cell (m).
        around: the cells to search from each cell (itself and its neighbours).
        head: the cell list's first bird per cell, updated.
        after: next bird in the same cell, updated.
        before: previous bird in the same cell, updated.
        cell: each bird's cell, updated.
        seen: ``(N,)`` neighbour counts, written.

    Returns:
        ``order_parameters(vel, seen)`` after the step.

    """
    half = 0.5 * extent
    cohere_factor, separate_factor, match_factor = factors[0], factors[1], factors[2]
    for k in range(order.shape[0]):
        i = order[k]
        px, py = pos[i, 0], pos[i, 1]
        seen_i = 0.0
        cohere_x = cohere_y = separate_x = separate_y = match_x = match_y = 0.0
        c = cell[i]
        for q in range(around.shape[1]):
            j = head[around[c, q]]
            while j >= 0:
                if j != i:
                    dx = pos[j, 0] - px
                    dy = pos[j, 1] - py
                    if dx > half:  # the nearest image on the periodic square
                        dx -= extent
                    elif dx < -half:
                        dx += extent
                    if dy > half:
                        dy -= extent
                    elif dy < -half:
                        dy += extent
                    squared = dx * dx + dy * dy
                    # weights 1 or 0 instead of branches: whether a candidate is a neighbour
                    # is a coin toss the processor cannot predict
                    near = 1.0 if squared <= visual_sq else 0.0
                    close = near if squared <= separation_sq else 0.0
                    seen_i += near
                    cohere_x += near * dx
                    cohere_y += near * dy
                    separate_x -= close * dx
                    separate_y -= close * dy
                    match_x += near * vel[j, 0]
                    match_y += near * vel[j, 1]
                j = after[j]
        count = max(seen_i, 1.0)
        vx = (
            vel[i, 0]
            + cohere_x / count * cohere_factor
            + separate_x / count * separate_factor
            + match_x / count * match_factor
        ) / 2.0
        vy = (
            vel[i, 1]
            + cohere_y / count * cohere_factor
            + separate_y / count * separate_factor
            + match_y / count * match_factor
        ) / 2.0
        norm = math.sqrt(vx * vx + vy * vy)
        if norm > 0.0:
            vel[i, 0] = vx / norm
            vel[i, 1] = vy / norm
        x = wrap(px + vel[i, 0] * move, extent)
        y = wrap(py + vel[i, 1] * move, extent)
        pos[i, 0] = x
        pos[i, 1] = y
        seen[i] = int(seen_i)
        c_new = _cell_index(x, y, cells, side)
        if c_new != c:
            _unlink(i, head, after, before, cell)
            _link(i, c_new, head, after, before, cell)
    return order_parameters(vel, seen)


@numba.njit(cache=True)
def order_parameters(vel: np.ndarray, seen: np.ndarray) -> tuple[float, float]:
    """The flock's polarisation ``|mean unit velocity|`` (0: headings at random, 1: all
    aligned) and the mean of ``seen`` (neighbours per bird).
    """
    n = vel.shape[0]
    sx = sy = 0.0
    total = 0
    for i in range(n):
        sx += vel[i, 0]
        sy += vel[i, 1]
        total += seen[i]
    return math.sqrt(sx * sx + sy * sy) / n, total / n
