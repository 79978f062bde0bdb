"""The coverage call (the report's Figs. 24-27): unit tests from hand-made maps and hypothesis
properties of the plans it returns."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from abm.errors import ConfigError
from models.hierarchy.coverage import (
    Child,
    Status,
    _disc_grid,
    _mark_path,
    closest_robot,
    coverage,
    move_idle_robots,
    radius_schedule,
    valid_cells,
    worker_r_min,
)
from models.hierarchy.planning import _drivable, padded_cells, shortest_paths, supercover
from models.hierarchy.probmap import Bubble, ProbMap, Rect

H = 0.10
WORLD = Rect(0.0, 0.0, 20.0, 20.0)
SMALL = Rect(0.0, 0.0, 4.0, 4.0)


def scout(key: int, x: float, y: float) -> Child:
    return Child(key, x, y, r_min=0.10, r_max=0.80)


def fresh_map(children, world: Rect = WORLD) -> ProbMap:
    """The map at t = 0: only the children's own cells are known (README "Choices":
    initial knowledge)."""
    pmap = ProbMap(world, world, cell_size=H)
    pmap.mark_free([c.position for c in children])
    return pmap


def test_an_all_known_map_is_complete():
    pmap = ProbMap(SMALL, SMALL, cell_size=H)
    pmap.mark_bubble(2.0, 2.0, 10.0)
    plan = coverage(pmap, [scout(1, 1.05, 1.05)], np.random.default_rng(0))
    assert plan.status is Status.COMPLETE and not plan.centres
    assert valid_cells(pmap).shape == (0, 2)


def test_two_scouts_030_apart_stay_on_their_cells_with_r_0148():
    kids = [scout(1, 1.05, 1.05), scout(2, 1.35, 1.05)]
    plan = coverage(fresh_map(kids), kids, np.random.default_rng(1))
    assert plan.status is Status.IN_PROGRESS
    assert plan.centres == {1: (1.05, 1.05), 2: pytest.approx((1.35, 1.05))}
    first_fit = next(r for r in radius_schedule(0.8, 0.1) if 2 * r <= 0.30)
    assert plan.radius == pytest.approx(first_fit) == pytest.approx(0.8 * 0.9**16)
    assert plan.radius == pytest.approx(0.148, abs=5e-4)
    assert plan.distances == {1: 0, 2: 0} and plan.waves == [] and not plan.idle


def test_adjacent_scouts_lose_the_lower_number_and_the_other_gets_the_floor():
    kids = [scout(1, 1.05, 1.05), scout(2, 1.15, 1.05)]
    plan = coverage(fresh_map(kids), kids, np.random.default_rng(2))
    assert plan.idle == (1,)  # equal mean distances: the lower local number goes
    assert plan.centres == {2: pytest.approx((1.15, 1.05))}
    assert plan.radius == pytest.approx(0.10)  # the radius stays at the floor
    assert plan.stranded == (1,)  # in the way, but nothing around it is known yet


def test_radius_stays_at_the_floor_unless_the_reset_switch_is_on():
    kids = [scout(1, 1.05, 1.05), scout(2, 1.15, 1.05), scout(3, 2.05, 1.05)]
    pmap = fresh_map(kids)
    stay = coverage(pmap, kids, np.random.default_rng(3))
    reset = coverage(pmap, kids, np.random.default_rng(3), reset_radius_after_removal=True)
    assert stay.idle == reset.idle == (2,)  # the middle one is closest to the others
    assert stay.radius == pytest.approx(0.10)
    assert reset.radius == pytest.approx(0.8 * 0.9**5)  # restarted: first 2r <= 1.0 m


def test_queen_radius_sequence_starts_400_360_324():
    r_min = worker_r_min(4, 0.10)
    schedule = radius_schedule(400.0, r_min)
    assert schedule[:3] == pytest.approx([400.0, 360.0, 324.0])
    assert schedule[-1] == pytest.approx(r_min) and schedule[-2] > r_min
    assert sum(r > 10.0 for r in schedule) == 36  # 400 * 0.9**35 = 10.01 m: 36 steps to <= 10 m
    workers = [Child(k, 2.05 + 3.0 * k, 5.05, r_min, 400.0) for k in (1, 2)]
    plan = coverage(fresh_map(workers), workers, np.random.default_rng(5))
    fits = [r for r in schedule if 2 * r <= 3.0]
    assert plan.radius == pytest.approx(fits[0])  # the call walks the same schedule
    assert plan.radii_tried == schedule.index(fits[0]) + 1


def test_scout_schedule_has_21_radii_from_080_to_010():
    schedule = radius_schedule(0.80, 0.10)
    assert len(schedule) == 21 and schedule[-1] == 0.10
    assert all(
        b == pytest.approx(0.9 * a) for a, b in zip(schedule[:-2], schedule[1:-1], strict=True)
    )


def test_value_picks_the_nearer_of_two_equal_gain_candidates():
    near, far = (2.55, 2.05), (0.75, 2.05)  # two single unknown cells, 1.8 m apart
    pmap = ProbMap(SMALL, SMALL, cell_size=H)
    pmap.mark_bubble(2.0, 2.0, 10.0, unscanned=[near, far])
    kid = scout(1, 2.05, 2.05)
    plan = coverage(pmap, [kid], np.random.default_rng(4))
    cx, cy = plan.centres[1]
    assert math.hypot(cx - near[0], cy - near[1]) == pytest.approx(H)  # borders the near pocket
    assert plan.distances[1] == 4  # (2.05 -> 2.45, 2.05) is the nearest frontier cell


def test_closest_robot_is_the_one_in_the_middle():
    kids = [scout(1, 0.0, 0.0), scout(2, 1.0, 0.0), scout(3, 2.1, 0.0)]
    assert closest_robot(kids) == 2
    assert closest_robot([scout(4, 0.0, 0.0), scout(2, 1.0, 0.0)]) == 2


def test_worker_minimum_bubble_from_circle_packing():
    assert [round(worker_r_min(s, 0.10), 3) for s in range(2, 9)] == [
        0.2,
        0.215,
        0.241,
        0.27,
        0.3,
        0.3,
        0.33,
    ]
    with pytest.raises(ConfigError, match="scouts_per_worker"):
        worker_r_min(9, 0.10)
    with pytest.raises(ConfigError, match="scouts_per_worker"):
        worker_r_min(0, 0.10)


def test_bad_coverage_input_raises():
    with pytest.raises(ConfigError, match="r_min"):
        Child(1, 0.0, 0.0, r_min=0.9, r_max=0.8)
    with pytest.raises(ConfigError, match="child"):
        coverage(ProbMap(SMALL, SMALL), [], np.random.default_rng(0))
    with pytest.raises(ConfigError, match="decay"):
        radius_schedule(0.8, 0.1, decay=1.0)


def test_idle_robot_in_the_way_moves_to_the_nearest_free_spiral_cell():
    pmap = ProbMap(SMALL, SMALL, cell_size=H)
    pmap.mark_bubble(2.0, 2.0, 10.0)
    idle = scout(2, 2.05, 2.05)
    moves, stranded = move_idle_robots(pmap, [idle], {1: (1.55, 2.05)}, 0.55, {})
    assert not stranded
    end = moves[2][-1]
    assert math.hypot(end[0] - 1.55, end[1] - 2.05) > 0.55  # out of the bubble
    # ring 1 clockwise from north: N (2.05, 2.15) is 0.51 m from the centre, NE is the first free
    assert end.tolist() == pytest.approx([2.15, 2.15])


def test_same_seed_same_plan():
    kids = [scout(k, 0.55 + 0.3 * k, 1.05) for k in range(1, 6)]
    pmap = fresh_map(kids)
    pmap.mark_bubble(1.5, 1.0, 1.2)
    a = coverage(pmap, kids, np.random.default_rng(9))
    b = coverage(pmap, kids, np.random.default_rng(9))
    assert a.centres == b.centres and a.radius == b.radius
    assert all(np.array_equal(a.paths[k], b.paths[k]) for k in a.paths)


# ------------------------------------------------------------------ properties
@st.composite
def scenes(draw):
    """A 4 m x 4 m world with random known patches, obstacles and 1-6 scouts on free cells."""
    pmap = ProbMap(SMALL, SMALL, cell_size=H)
    for _ in range(draw(st.integers(1, 4))):
        x, y = draw(st.floats(0.3, 3.7)), draw(st.floats(0.3, 3.7))
        pmap.mark_bubble(x, y, draw(st.floats(0.3, 1.5)))
    for _ in range(draw(st.integers(0, 12))):
        pmap.stamp_point(draw(st.floats(0.05, 3.95)), draw(st.floats(0.05, 3.95)))
    n = draw(st.integers(1, 6))
    free = [
        ((ix + 0.5) * H, (iy + 0.5) * H)
        for ix in range(40)
        for iy in range(40)
        if pmap.known_free((ix + 0.5) * H, (iy + 0.5) * H)
    ]
    spots = draw(st.lists(st.sampled_from(free), min_size=n, max_size=n, unique=True))
    kids = [scout(k + 1, x, y) for k, (x, y) in enumerate(spots)]
    pmap.mark_free(spots)
    return pmap, kids, draw(st.integers(0, 2**32 - 1))


@settings(max_examples=60, deadline=None)
@given(scenes())
def test_plan_obeys_the_placement_rules(scene):
    pmap, kids, seed = scene
    plan = coverage(pmap, kids, np.random.default_rng(seed))
    if plan.status is not Status.IN_PROGRESS:
        return
    r = plan.radius
    assert 0.10 - 1e-12 <= r <= 0.80
    centres = list(plan.centres.values())
    for i, (ax, ay) in enumerate(centres):  # R1: no overlap (touching allowed)
        for bx, by in centres[i + 1 :]:
            assert math.hypot(ax - bx, ay - by) >= 2 * r - 1e-9
    positions = {c.key: c.position for c in kids}
    for key, (cx, cy) in plan.centres.items():  # R2: known, free, in bounds, reachable
        assert pmap.known_free(cx, cy) and pmap.in_bounds(cx, cy)
        others = [p for k, p in positions.items() if k != key]
        field = shortest_paths(pmap, positions[key], others)
        assert field.distance(cx, cy) == plan.distances[key]
    assert set(plan.centres) | set(plan.idle) == set(positions)


@settings(max_examples=60, deadline=None)
@given(scenes())
def test_no_path_cell_is_known_blocked_or_undrivable(scene):
    pmap, kids, seed = scene
    plan = coverage(pmap, kids, np.random.default_rng(seed))
    positions = {c.key: c.position for c in kids}
    for key, path in {**plan.paths, **plan.idle_moves}.items():
        drivable = _drivable(pmap, [p for k, p in positions.items() if k != key])
        start = tuple(supercover(path[0], path[0], H)[0])
        for a, b in zip(path[:-1], path[1:], strict=True):
            for ix, iy in supercover(a, b, H):
                if (ix, iy) == start:
                    continue
                assert drivable[iy, ix] and not pmap.known_blocked((ix + 0.5) * H, (iy + 0.5) * H)
    cells = {k: {tuple(c) for c in padded_cells(p, H)} for k, p in plan.paths.items()}
    for wave in plan.waves:
        for i, a in enumerate(wave):
            for b in wave[i + 1 :]:
                assert not cells[a] & cells[b]


def test_a_child_with_no_route_is_dropped_before_the_closest_robot():
    pmap = ProbMap(Bubble(1.0, 1.0, 0.6), SMALL, cell_size=H)
    free, stranded = scout(1, 1.05, 1.05), scout(2, 3.55, 3.55)  # 2 is outside the routing grid
    pmap.mark_free([free.position])
    kids = [free, stranded]
    plan = coverage(pmap, kids, np.random.default_rng(6))
    assert plan.idle == (2,) and set(plan.centres) == {1}
    literal = coverage(pmap, kids, np.random.default_rng(6), drop_unreachable_first=False)
    assert literal.status is Status.CANNOT_COMPLETE  # the tie removes the placeable 1 first


def brute_gain(pmap: ProbMap, x: float, y: float, r: float) -> int:
    """C by definition: in-bounds unscanned cells with centre within r of (x, y)."""
    rows, cols = np.nonzero(pmap._in & ~pmap._scanned)
    cx = (pmap._ix0 + cols + 0.5) * H
    cy = (pmap._iy0 + rows + 0.5) * H
    return int(np.count_nonzero((cx - x) ** 2 + (cy - y) ** 2 <= r * r + 1e-9))


@settings(max_examples=25, deadline=None)
@given(scenes())
def test_a_single_child_gets_a_cell_of_maximum_value(scene):
    pmap, kids, seed = scene
    kid = kids[0]
    plan = coverage(pmap, [kid], np.random.default_rng(seed), alpha=1.0, beta=3.0)
    field = shortest_paths(pmap, kid.position)
    values = {
        (x, y): brute_gain(pmap, x, y, 0.8) - 3.0 * field.distance(x, y)
        for x, y in valid_cells(pmap)
        if field.reachable(x, y)
    }
    if not values:
        assert plan.status is not Status.IN_PROGRESS
        return
    assert plan.radius == 0.8  # one child: the first radius always fits
    best = max(values.values())
    (cx, cy), *_ = plan.centres.values()
    chosen = min(values, key=lambda p: math.hypot(p[0] - cx, p[1] - cy))
    assert math.hypot(chosen[0] - cx, chosen[1] - cy) < 1e-9
    assert values[chosen] == best


# ------------------------------------------------------------ compiled CONFLICT vs numpy rules
coords = st.floats(-0.5, 4.5, allow_nan=False).map(lambda v: round(v, 2))


@settings(max_examples=150, deadline=None)
@given(st.lists(st.tuples(coords, coords), max_size=4), st.sampled_from([0.1, 0.25, 0.33, 0.8]),
       st.lists(st.lists(st.tuples(coords, coords), min_size=1, max_size=5), max_size=3),
       st.integers(0, 2), st.tuples(st.integers(0, 9), st.integers(0, 9)))  # fmt: skip
def test_the_compiled_conflict_grid_is_the_numpy_rule(centres, r, paths, padding, origin):
    pmap = ProbMap(
        Rect(*(v * H for v in origin), *(v * H + 3.0 for v in origin)), WORLD, cell_size=H
    )
    ny, nx = pmap._scanned.shape
    want = np.zeros((ny, nx), dtype=bool)
    for cx, cy in centres:  # Fig. 27 as numpy computed it: the discs, then the padded paths
        rs, cs = pmap._disc_window(cx, cy, r)
        xs = (pmap._ix0 + np.arange(cs.start, cs.stop) + 0.5) * H
        ys = (pmap._iy0 + np.arange(rs.start, rs.stop) + 0.5) * H
        want[rs, cs] |= (xs[None, :] - cx) ** 2 + (ys[:, None] - cy) ** 2 <= r * r + 1e-9 * H * H
    got = _disc_grid(ny, nx, pmap._ix0, pmap._iy0, H, np.array(centres).reshape(-1, 2), r)
    assert np.array_equal(got, want)
    for path in paths:
        cells = padded_cells(np.array(path), H, padding)
        cc, rr = cells[:, 0] - pmap._ix0, cells[:, 1] - pmap._iy0
        ok = (cc >= 0) & (cc < nx) & (rr >= 0) & (rr < ny)
        want[rr[ok], cc[ok]] = True
        _mark_path(got, np.array(path) / H, padding, pmap._ix0, pmap._iy0)
    assert np.array_equal(got, want)
