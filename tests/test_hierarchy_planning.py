"""Planning on the director's map (Figs. 28-33): ProbMap merging, shadow inference, supercover,
smoothing, BFS and the wave generator. Unit tests from hand-made maps plus hypothesis properties."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from abm.errors import ConfigError
from models.hierarchy.coverage import _valid_grid, _valid_setup
from models.hierarchy.planning import (
    DistanceField,
    _children_search,
    _drivable,
    _frame,
    _framed_base,
    _framed_base_grid,
    _local_cells,
    _smooth_on,
    _without,
    padded_cells,
    path_length,
    shortest_paths,
    smooth,
    supercover,
    wave_order_violations,
    waves,
)
from models.hierarchy.probmap import Bubble, ProbMap, Rect

H = 0.10
WORLD = Rect(0.0, 0.0, 3.0, 3.0)


def known_map(world: Rect = WORLD, unknown=()) -> ProbMap:
    """A map of ``world`` with every cell known and free except the cells of ``unknown``."""
    pmap = ProbMap(world, world, cell_size=H)
    pmap.mark_bubble(world.x_max / 2, world.y_max / 2, 10 * world.x_max, unknown)
    return pmap


def cells_of(points) -> set[tuple[int, int]]:
    return {(math.floor(x / H + 1e-9), math.floor(y / H + 1e-9)) for x, y in points}


# ------------------------------------------------------------------ ProbMap (Figs. 28-30)
def test_point_outside_the_bubble_is_discarded():
    pmap = ProbMap(Bubble(1.0, 1.0, 0.5), WORLD, cell_size=H)
    assert not pmap.stamp_point(1.8, 1.0)
    assert pmap.n_scanned == 0 and pmap.points == []
    assert pmap.stamp_point(1.32, 1.04)
    assert pmap.known_blocked(1.32, 1.04) and pmap.points == [(1.32, 1.04, 0.0)]


def test_point_stamp_noisy_or_and_mass():
    pmap = ProbMap(WORLD, WORLD, cell_size=H)
    pmap.stamp_point(1.05, 1.05, sigma=0.05)
    once = pmap.blocked(1.05, 1.05)
    # mass of N(0, 0.05^2) over a 0.1 m square centred on the mean: (2 Phi(1) - 1)^2
    assert once == pytest.approx(0.6827**2, abs=1e-3)
    pmap.stamp_point(1.05, 1.05, sigma=0.05)
    assert pmap.blocked(1.05, 1.05) == pytest.approx(1 - (1 - once) ** 2)
    assert pmap.known_blocked(1.05, 1.05) and not pmap.known_blocked(1.25, 1.05)
    probe = np.array([(1.05, 1.05), (1.25, 1.05), (9.0, 9.0)])
    assert pmap.known_blocked_at(probe).tolist() == [True, False, False]
    assert pmap.scanned(1.25, 1.05)  # within 3 sigma: known, mostly free


coordinate = st.floats(-1.0, 4.0) | st.sampled_from([0.0, 0.1, 0.3, 2.9, 3.0, math.nan, math.inf])


@settings(max_examples=80, deadline=None)
@given(
    st.lists(st.tuples(coordinate, coordinate), max_size=30),
    st.lists(st.tuples(st.floats(0.0, 3.0), st.floats(0.0, 3.0)), max_size=12),
)
def test_known_blocked_at_is_known_blocked_point_by_point(points, stamps):
    pmap = ProbMap(Rect(0.5, 0.5, 2.5, 2.5), WORLD, cell_size=H)  # a region: cells off it
    for x, y in stamps:
        pmap.stamp_point(x, y, sigma=0.05)
    # and the corners of the cells stamped: on cell boundaries, where the rounding decides
    points = points + [(round(x / H) * H, round(y / H) * H) for x, y in stamps]
    probe = np.array(points, dtype=float).reshape(-1, 2)
    # the vectorised numpy rule the compiled one replaced
    h = pmap.cell_size
    with np.errstate(invalid="ignore"):  # NaN and inf cast to some integer off the grid
        cols = np.floor(probe[:, 0] / h + 1e-9).astype(np.int64) - pmap._ix0
        rows = np.floor(probe[:, 1] / h + 1e-9).astype(np.int64) - pmap._iy0
    ny, nx = pmap._scanned.shape
    inside = (rows >= 0) & (rows < ny) & (cols >= 0) & (cols < nx)
    want = np.zeros(len(probe), dtype=bool)
    r, c = rows[inside], cols[inside]
    want[inside] = pmap._scanned[r, c] & (pmap._blocked[r, c] >= pmap.tau)
    assert pmap.known_blocked_at(probe).tolist() == want.tolist()
    finite = [(x, y) for x, y in points if math.isfinite(x) and math.isfinite(y)]
    if finite:
        got = pmap.known_blocked_at(np.array(finite)).tolist()
        assert got == [pmap.known_blocked(x, y) for x, y in finite]


def test_a_point_on_a_cell_boundary_is_in_the_upper_cell_for_both_rules():
    pmap = ProbMap(WORLD, WORLD, cell_size=H)
    pmap.stamp_point(0.35, 1.05, sigma=0.01)  # cell (3, 10) only; 0.3 / 0.1 < 3 in floats
    assert pmap.known_blocked(0.3, 1.05) and not pmap.known_blocked(0.29, 1.05)
    assert pmap.known_blocked_at(np.array([(0.3, 1.05), (0.29, 1.05)])).tolist() == [True, False]


@given(st.integers(0, 6), st.integers(0, 6), st.randoms())
def test_a_framed_grid_is_the_grid_padded_with_false(ny, nx, random):
    grid = np.array([random.random() < 0.4 for _ in range(ny * nx)], dtype=bool).reshape(ny, nx)
    framed = _frame(grid)
    assert framed.dtype == np.bool_ and framed.flags.c_contiguous
    assert np.array_equal(framed, np.pad(grid, 1, constant_values=False))


def test_blocked_cell_shadows_the_cells_behind_it():
    pmap = ProbMap(WORLD, WORLD, cell_size=H)
    pmap.stamp_point(1.55, 1.05)
    pmap.infer_scan(1.05, 1.05, 0.8)
    assert pmap.known_free(1.35, 1.05)  # in front of the obstacle
    assert not pmap.scanned(1.75, 1.05) and not pmap.scanned(1.85, 1.05)  # behind it
    assert pmap.known_free(1.05, 1.65)  # beside the scout, clear line of sight
    assert not pmap.scanned(1.05, 1.95)  # beyond the radius


def test_worker_bubble_marks_all_but_the_listed_cells():
    pmap = ProbMap(WORLD, WORLD, cell_size=H)
    new = pmap.mark_bubble(1.5, 1.5, 0.3, unscanned=[(1.55, 1.55)])
    assert not pmap.scanned(1.55, 1.55) and pmap.scanned(1.45, 1.45)
    inside = sum(
        (ix + 0.5) ** 2 + (iy + 0.5) ** 2 <= 9.0 + 1e-9
        for ix in range(-4, 4)
        for iy in range(-4, 4)
    )
    assert new == inside - 1
    assert not pmap.scanned(1.5, 1.85)


def test_map_down_window_merges_into_a_worker_map():
    queen = ProbMap(WORLD, WORLD, cell_size=H)
    queen.stamp_point(1.25, 1.25)
    queen.mark_bubble(1.0, 1.0, 0.5)
    box = Rect(0.5, 0.5, 1.5, 1.5)
    window = queen.window(box)
    worker = ProbMap(Bubble(2.0, 2.0, 0.5), WORLD, cell_size=H, cover=[box])
    assert worker.merge(window) == window.known_cells > 0
    assert worker.known_blocked(1.25, 1.25) and worker.known_free(1.0, 1.0)
    assert not worker.in_bounds(1.0, 1.0) and worker.in_routing(1.0, 1.0)
    assert worker.merge(window) == 0  # idempotent


def test_bad_map_arguments_raise():
    with pytest.raises(ConfigError, match="cell_size"):
        ProbMap(WORLD, WORLD, cell_size=0)
    with pytest.raises(ConfigError, match="tau"):
        ProbMap(WORLD, WORLD, tau=1.5)
    with pytest.raises(ConfigError, match="stamp"):
        ProbMap(WORLD, WORLD, stamp="gauss")
    with pytest.raises(ConfigError, match="does not intersect"):
        ProbMap(Bubble(50.0, 50.0, 1.0), WORLD)


# ------------------------------------------------------------------ supercover (Fig. 31)
def test_supercover_through_a_corner_includes_the_vertex_sharing_cells():
    cells = {tuple(c) for c in supercover((0.05, 0.05), (0.25, 0.25), H)}
    assert cells == {(0, 0), (1, 0), (0, 1), (1, 1), (2, 1), (1, 2), (2, 2)}
    off_corner = {tuple(c) for c in supercover((0.05, 0.05), (0.25, 0.15), H)}
    assert off_corner == {(0, 0), (1, 0), (1, 1), (2, 1)}


half_cells = st.integers(0, 40).map(lambda k: (k + 0.5) * H)


@settings(max_examples=200, deadline=None)
@given(half_cells, half_cells, half_cells, half_cells)
def test_supercover_is_symmetric_and_connected(x0, y0, x1, y1):
    forward = {tuple(c) for c in supercover((x0, y0), (x1, y1), H)}
    backward = {tuple(c) for c in supercover((x1, y1), (x0, y0), H)}
    assert forward == backward
    assert cells_of([(x0, y0), (x1, y1)]) <= forward
    # 4-connected as a set
    start = next(iter(forward))
    seen, todo = {start}, [start]
    while todo:
        cx, cy = todo.pop()
        for nxt in ((cx + 1, cy), (cx - 1, cy), (cx, cy + 1), (cx, cy - 1)):
            if nxt in forward and nxt not in seen:
                seen.add(nxt)
                todo.append(nxt)
    assert seen == forward


# ------------------------------------------------------------------ BFS and smoothing (Fig. 32)
def test_manhattan_staircase_with_clear_sight_smooths_to_two_points():
    pmap = known_map()
    stairs = [(0.55 + 0.1 * (k // 2 + k % 2), 0.55 + 0.1 * (k // 2)) for k in range(11)]
    assert path_length(stairs) == pytest.approx(1.0)
    smoothed = smooth(pmap, np.array(stairs))
    assert smoothed.tolist() == [list(stairs[0]), list(stairs[-1])]


def test_smoothing_keeps_a_corner_around_an_obstacle():
    pmap = known_map()
    for y in np.arange(0.55, 2.0, 0.1):
        pmap.stamp_point(1.55, y)
    field = shortest_paths(pmap, (1.05, 1.05))
    raw = field.path_to(2.05, 1.05)
    assert field.distance(2.05, 1.05) == len(raw) - 1
    smoothed = smooth(pmap, raw)
    assert 2 < smoothed.shape[0] < raw.shape[0]
    drivable = _drivable(pmap)
    for a, b in zip(smoothed[:-1], smoothed[1:], strict=True):
        for ix, iy in supercover(a, b, H):
            assert drivable[iy, ix]


def test_bfs_routes_around_occupied_cells_and_not_through_unknown():
    pmap = known_map(unknown=[(1.55, y) for y in np.arange(0.05, 3.0, 0.1)])
    field = shortest_paths(pmap, (1.05, 1.05))
    assert not field.reachable(2.05, 1.05)  # a wall of unknown cells
    open_map = known_map()
    blocked = shortest_paths(open_map, (1.05, 1.05), occupied=[(1.25, 1.05)])
    free = shortest_paths(open_map, (1.05, 1.05))
    assert free.distance(1.45, 1.05) == 4
    assert blocked.distance(1.45, 1.05) > 4  # detours around the other robot and its padding
    assert not blocked.reachable(1.25, 1.05)


def test_bfs_ties_follow_the_neighbour_order_north_east_south_west():
    field = shortest_paths(known_map(), (1.05, 1.05))
    north_first = [[1.05, 1.05], [1.05, 1.15], [1.05, 1.25], [1.15, 1.25], [1.25, 1.25]]
    assert field.path_to(1.25, 1.25) == pytest.approx(np.array(north_first))
    east_first = [[1.05, 1.05], [1.15, 1.05], [1.25, 1.05], [1.25, 0.95], [1.25, 0.85]]
    assert field.path_to(1.25, 0.85) == pytest.approx(np.array(east_first))


def test_the_world_boundary_is_a_wall_for_the_padding():
    pmap = known_map()
    field = shortest_paths(pmap, (1.05, 1.05))
    assert not field.reachable(0.05, 1.05) and field.reachable(0.15, 1.05)


# ------------------------------------------------------------------ waves (Fig. 33)
def test_crossing_paths_give_two_waves_disjoint_paths_one():
    across = np.array([(0.55, 1.05), (1.55, 1.05)])
    down = np.array([(1.05, 0.55), (1.05, 1.55)])
    far = np.array([(2.55, 0.55), (2.55, 1.55)])
    assert waves({1: across, 2: down}, H) == [[1], [2]]
    assert waves({1: across, 2: far}, H) == [[1, 2]]


paths_strategy = st.dictionaries(
    st.integers(1, 8),
    st.lists(st.tuples(half_cells, half_cells), min_size=1, max_size=4).map(np.array),
    min_size=1,
    max_size=8,
)


@settings(max_examples=100, deadline=None)
@given(paths_strategy)
def test_no_conflict_inside_a_wave_and_every_move_in_one_wave(paths):
    result = waves(paths, H)
    assert sorted(k for w in result for k in w) == sorted(paths)
    cells = {k: {tuple(c) for c in padded_cells(p, H)} for k, p in paths.items()}
    for wave in result:
        for i, a in enumerate(wave):
            for b in wave[i + 1 :]:
                assert not cells[a] & cells[b]
    for later, wave in enumerate(result[1:], start=1):  # greedy: each clashes with every earlier
        for k in wave:
            for earlier in result[:later]:
                assert any(cells[k] & cells[j] for j in earlier)


@settings(max_examples=60, deadline=None)
@given(st.floats(0.9, 2.1), st.floats(0.9, 2.1), st.floats(0.10, 0.80))
def test_a_clear_scan_leaves_no_gap_between_rays(x, y, r):
    pmap = ProbMap(WORLD, WORLD, cell_size=H)
    new = pmap.infer_scan(x, y, r)
    inside = [
        ((ix + 0.5) * H, (iy + 0.5) * H)
        for ix in range(30)
        for iy in range(30)
        if ((ix + 0.5) * H - x) ** 2 + ((iy + 0.5) * H - y) ** 2 <= r * r - 1e-9
    ]
    assert all(pmap.scanned(cx, cy) for cx, cy in inside)
    assert new == pmap.n_scanned >= len(inside)


@settings(max_examples=60, deadline=None)
@given(
    st.lists(st.tuples(st.floats(0.0, 3.0), st.floats(0.0, 3.0), st.sampled_from([0.0, 0.03])),
             max_size=15),
    st.lists(st.tuples(st.floats(0.5, 2.5), st.floats(0.5, 2.5), st.floats(0.1, 0.8)), max_size=4),
    st.sampled_from(["mass", "peak"]),
)  # fmt: skip
def test_reports_never_add_knowledge_outside_the_bubble(points, scans, stamp):
    pmap = ProbMap(Bubble(1.5, 1.5, 0.6), WORLD, cell_size=H, stamp=stamp)
    for px, py, sigma in points:
        accepted = pmap.stamp_point(px, py, sigma)
        assert accepted == pmap.in_bounds(px, py)
    for sx, sy, sr in scans:
        pmap.infer_scan(sx, sy, sr)
    assert not (pmap._scanned & ~pmap._in).any()  # a map never gains data outside its region
    assert ((pmap._blocked >= 0) & (pmap._blocked <= 1)).all()


def test_peak_stamp_gives_the_containing_cell_full_weight():
    pmap = ProbMap(WORLD, WORLD, cell_size=H, stamp="peak")
    pmap.stamp_point(1.02, 1.02, sigma=0.05)
    assert pmap.blocked(1.02, 1.02) == 1.0
    assert pmap.blocked(1.15, 1.05) == pytest.approx(math.exp(-(0.13**2 + 0.03**2) / 0.005))


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(half_cells, half_cells), min_size=2, max_size=12))
def test_smoothing_keeps_the_ends_and_never_lengthens(points):
    pmap = known_map(Rect(0.0, 0.0, 4.2, 4.2))
    raw = np.array(points)
    smoothed = smooth(pmap, raw)
    assert smoothed[0].tolist() == raw[0].tolist() and smoothed[-1].tolist() == raw[-1].tolist()
    assert path_length(smoothed) <= path_length(raw) + 1e-9
    assert all(any(np.array_equal(p, q) for q in raw) for p in smoothed)  # a subsequence


def test_wave_order_violation_counts_a_later_path_over_an_earlier_end():
    first = np.array([(0.55, 1.05), (1.05, 1.05)])  # ends where the second path passes
    second = np.array([(1.05, 0.55), (1.05, 1.55)])
    assert waves({1: first, 2: second}, H) == [[1], [2]]
    assert wave_order_violations([[1], [2]], {1: first, 2: second}, H) == 1
    apart = np.array([(2.55, 0.55), (2.55, 1.55)])
    assert wave_order_violations([[1], [3]], {1: first, 3: apart}, H) == 0


# ---------------------------------------------------------------- compiled grids vs numpy rules
def _dilate_by_shifts(mask: np.ndarray, k: int) -> np.ndarray:
    """Bool dilation of ``mask`` by a (2k+1)-square, by shifted ORs (the numpy rule)."""
    out = mask.copy()
    ny, nx = mask.shape
    for dr in range(-k, k + 1):
        for dc in range(-k, k + 1):
            dst_r = slice(max(dr, 0), ny + min(dr, 0))
            src_r = slice(max(-dr, 0), ny + min(-dr, 0))
            dst_c = slice(max(dc, 0), nx + min(dc, 0))
            src_c = slice(max(-dc, 0), nx + min(-dc, 0))
            out[dst_r, dst_c] |= mask[src_r, src_c]
    return out


def _framed_base_by_numpy(scanned, blocked, tau, k, edges):
    """The framed drivability as numpy computed it before it was compiled: the world's sides
    as walls in a ring of ``k`` cells outside the grid, dilated with the known-blocked cells.
    """
    known_blocked = scanned & (blocked >= tau)
    out = np.zeros((scanned.shape[0] + 2, scanned.shape[1] + 2), dtype=bool)
    if k == 0:
        out[1:-1, 1:-1] = scanned & ~known_blocked
        return out
    wall = np.pad(known_blocked, k, constant_values=False)
    west, south, east, north = edges
    if west:
        wall[:, :k] = True
    if south:
        wall[:k, :] = True
    if east:
        wall[:, -k:] = True
    if north:
        wall[-k:, :] = True
    out[1:-1, 1:-1] = scanned & ~_dilate_by_shifts(wall, k)[k:-k, k:-k]
    return out


grids = st.tuples(st.integers(1, 9), st.integers(1, 9)).flatmap(
    lambda shape: st.tuples(
        *(st.lists(st.booleans(), min_size=shape[0] * shape[1], max_size=shape[0] * shape[1])
          for _ in range(3)),
        st.lists(st.sampled_from([0.0, 0.3, 0.5, 0.7, 1.0]), min_size=shape[0] * shape[1],
                 max_size=shape[0] * shape[1]),
    ).map(lambda lists: [np.array(v).reshape(shape) for v in lists])
)  # fmt: skip


@settings(max_examples=150, deadline=None)
@given(grids, st.integers(0, 4), st.tuples(*[st.booleans()] * 4))
def test_the_compiled_drivability_is_the_numpy_rule(arrays, k, edges):
    scanned, _, _, blocked = arrays
    want = _framed_base_by_numpy(scanned, blocked, 0.5, k, edges)
    assert np.array_equal(_framed_base_grid(scanned, blocked, 0.5, k, *edges), want)


@settings(max_examples=150, deadline=None)
@given(grids)
def test_the_compiled_valid_cells_are_the_numpy_rule(arrays):
    inside, scanned, exhausted, _ = arrays
    open_ = inside & ~scanned
    near = np.zeros_like(open_)
    near[1:, :] |= open_[:-1, :]
    near[:-1, :] |= open_[1:, :]
    near[:, 1:] |= open_[:, :-1]
    near[:, :-1] |= open_[:, 1:]
    assert np.array_equal(_valid_grid(inside, scanned, exhausted), inside & near & ~exhausted)


@settings(max_examples=150, deadline=None)
@given(grids, st.integers(-50, 50), st.integers(-50, 50), st.sampled_from([0.1, 0.05, 0.3]))
def test_the_compiled_valid_setup_is_the_numpy_rule(arrays, ix0, iy0, h):
    inside, scanned, exhausted, _ = arrays
    valid = _valid_grid(inside, scanned, exhausted)
    rows, cols = np.nonzero(valid)
    open_ = (inside & ~scanned).astype(np.int64)
    prefix = np.zeros((open_.shape[0], open_.shape[1] + 1), dtype=np.int64)
    np.cumsum(open_, axis=1, out=prefix[:, 1:])
    want = (rows, cols, (ix0 + cols + 0.5) * h, (iy0 + rows + 0.5) * h, prefix, _frame(valid),
            (rows + 1) * (valid.shape[1] + 2) + cols + 1)  # fmt: skip
    got = _valid_setup(inside, scanned, exhausted, ix0, iy0, h)
    for a, b in zip(got, want, strict=True):
        assert a.dtype == b.dtype and np.array_equal(a, b)


SMALL = Rect(0.0, 0.0, 1.2, 1.2)
"""A 12 x 12-cell world for the per-child kernels."""
cells_12 = st.lists(st.booleans(), min_size=144, max_size=144).map(
    lambda v: np.array(v).reshape(12, 12)
)
points_12 = st.tuples(st.floats(0.0, 1.1999), st.floats(0.0, 1.1999))


def random_map(scanned: np.ndarray, blocked: np.ndarray) -> ProbMap:
    """A map of the small world whose known and known-blocked cells are the given grids."""
    pmap = ProbMap(SMALL, SMALL, cell_size=H)
    pmap._scanned[:] = scanned
    pmap._blocked[:] = np.where(blocked, 1.0, 0.0)
    return pmap


@settings(max_examples=150, deadline=None)
@given(cells_12, cells_12, cells_12, st.lists(points_12, min_size=1, max_size=5),
       st.integers(1, 5), st.integers(0, 2))  # fmt: skip
def test_the_compiled_children_search_is_the_numpy_rule(scanned, blocked, goal, robots, n, k):
    pmap = random_map(scanned, blocked)
    robots = [*robots, (-0.05, 0.5)]  # a child outside the grid: no search, no cell
    n = min(n, len(robots))
    base = _framed_base(pmap, k)
    rows, cols = np.nonzero(goal)
    flat = (rows + 1) * 14 + cols + 1
    occ_r, occ_c = _local_cells(pmap, robots)
    vx, vy = (cols + 0.5) * H, (rows + 0.5) * H
    free, dist, pred, complete, ids, steps, offsets, boxes = _children_search(
        base, _frame(goal), flat, occ_r, occ_c, n, k, vx, vy
    )
    assert offsets.shape == (n + 1,) and ids.shape == steps.shape == (offsets[-1],)
    for j in range(n):
        got_ids, got_steps = ids[offsets[j] : offsets[j + 1]], steps[offsets[j] : offsets[j + 1]]
        if got_ids.size:
            want_box = [vx[got_ids].min(), vx[got_ids].max(), vy[got_ids].min(), vy[got_ids].max()]
            assert boxes[j].tolist() == want_box
        else:
            assert np.isnan(boxes[j]).all()
        if pmap._local(*robots[j]) is None:
            assert got_ids.size == 0
            continue
        others = robots[:j] + robots[j + 1 :]
        want = DistanceField(pmap, robots[j], _without(base, pmap, others, k)[1:-1, 1:-1], goal)
        assert np.array_equal(free[j], want._free)
        assert np.array_equal(dist[j], want._dist_f) and np.array_equal(pred[j], want._pred_f)
        assert complete[j] == want._complete
        d = want._dist_f.ravel()[flat]
        assert np.array_equal(got_ids, np.flatnonzero(d >= 0))
        assert np.array_equal(got_steps, d[d >= 0])


@settings(max_examples=150, deadline=None)
@given(cells_12, cells_12, points_12, st.booleans(), st.integers(0, 143))
def test_the_compiled_smoothed_route_is_path_to_then_smoothing(scanned, blocked, source,
                                                               centred, target):  # fmt: skip
    pmap = random_map(scanned, blocked)
    if centred:  # the source on its cell centre: the path leaves the duplicate centre out
        source = pmap._centre_of(*pmap._local(*source))
    field = shortest_paths(pmap, source)
    x, y = pmap._centre_of(target // 12, target % 12)
    if not field.reachable(x, y):
        with pytest.raises(ValueError):
            field._smoothed_path_to(x, y)
        return
    want = _smooth_on(pmap, field.path_to(x, y), field._drivable)
    assert np.array_equal(field._smoothed_path_to(x, y), want)


@settings(max_examples=150, deadline=None)
@given(cells_12, cells_12, st.lists(st.tuples(st.floats(-0.3, 1.5), st.floats(-0.3, 1.5)),
                                    min_size=1, max_size=6))  # fmt: skip
def test_the_compiled_blocked_path_count_is_the_numpy_rule(scanned, blocked, path):
    pmap = random_map(scanned, blocked)
    path = np.array(path)
    want = int(pmap.known_blocked_at((padded_cells(path, H, padding=0) + 0.5) * H).sum())
    got = pmap.known_blocked_on(path)
    assert got == want


def _waves_by_sets(paths, h, padding=1):
    """Fig. 33 as it was written with Python sets of padded cells (the reference rule)."""
    keys = sorted(paths)
    cells = {k: {tuple(c) for c in padded_cells(paths[k], h, padding)} for k in keys}
    conflict = {k: {j for j in keys if j != k and cells[k] & cells[j]} for k in keys}
    result = []
    for k in sorted(keys, key=lambda k: (-len(conflict[k]), k)):
        for wave in result:
            if not conflict[k] & set(wave):
                wave.append(k)
                break
        else:
            result.append([k])
    return [sorted(w) for w in result]


def _violations_by_sets(wave_list, paths, h, padding=1):
    """The wave-order diagnostic as it was written with Python sets (the reference rule)."""
    cell = lambda p: (math.floor(p[0] / h + 1e-9), math.floor(p[1] / h + 1e-9))  # noqa: E731
    cells = {k: {tuple(c) for c in padded_cells(paths[k], h, padding)} for k in paths}
    return sum(
        cell(paths[a][-1]) in cells[b] or cell(paths[b][0]) in cells[a]
        for i, early in enumerate(wave_list) for late in wave_list[i + 1 :]
        for a in early for b in late
    )  # fmt: skip


@settings(max_examples=150, deadline=None)
@given(paths_strategy, st.integers(0, 2), st.randoms(use_true_random=False))
def test_the_compiled_waves_and_violations_are_the_set_rules(paths, padding, random):
    assert waves(paths, H, padding) == _waves_by_sets(paths, H, padding)
    keys = sorted(paths)
    random.shuffle(keys)
    cuts = sorted(random.sample(range(1, len(keys)), random.randint(0, len(keys) - 1)))
    wave_list = [keys[a:b] for a, b in zip([0, *cuts], [*cuts, len(keys)], strict=True)]
    want = _violations_by_sets(wave_list, paths, H, padding)
    assert wave_order_violations(wave_list, paths, H, padding) == want
