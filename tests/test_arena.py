import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numba import njit

from abm.arena import CARDINALS, Arena
from abm.errors import ConfigError, MapError


def random_arena(seed: int, shape=(12, 15), resolution=1.0, density=0.3) -> Arena:
    rng = np.random.default_rng(seed)
    free = rng.random(shape) > density
    free[0, 0] = True
    return Arena(free, resolution)


def test_from_cells_places_free_cells_with_a_wall_ring():
    arena = Arena.from_cells([(0, 0), (1, 0), (1, 1)], cell_size=3.0)
    assert arena.free.shape == (4, 4)
    assert arena.free.sum() == 3
    assert not arena.free[0].any() and not arena.free[:, 0].any()
    assert arena.free_area == pytest.approx(27.0)


def test_cardinal_distances_in_a_corridor_cell():
    arena = Arena.from_cells([(0, 0), (1, 0), (2, 0)], cell_size=3.0)
    d = arena.cardinal_distances([[7.5, 4.5]], max_range=20.0)[0]
    np.testing.assert_allclose(d, [1.5, 4.5, 1.5, 4.5])
    assert arena.cardinal_distances([[7.5, 4.5]], max_range=3.5)[0].max() == 3.5


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 10_000), st.sampled_from([0.5, 1.0, 3.0]))
def test_cardinal_table_agrees_with_raycast(seed, resolution):
    arena = random_arena(seed, resolution=resolution)
    rng = np.random.default_rng(seed)
    pts = rng.random((200, 2)) * [arena.width, arena.height]
    table = arena.cardinal_distances(pts, 5.0)
    rays = arena.raycast(np.repeat(pts, 4, 0), np.tile(CARDINALS, (200, 1)), 5.0).reshape(-1, 4)
    np.testing.assert_allclose(table, rays, atol=1e-9)


def segment_hits_box(a, b, lo, hi) -> bool:
    """Exact Liang-Barsky test: does segment a->b meet the open box (lo, hi)?"""
    t0, t1 = 0.0, 1.0
    d = b - a
    for axis in (0, 1):
        if d[axis] == 0.0:
            if not lo[axis] < a[axis] < hi[axis]:
                return False
            continue
        ta, tb = (lo[axis] - a[axis]) / d[axis], (hi[axis] - a[axis]) / d[axis]
        t0, t1 = max(t0, min(ta, tb)), min(t1, max(ta, tb))
    return t0 < t1


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 10_000))
def test_segment_crossing_matches_exact_box_tests(seed):
    arena = random_arena(seed)
    rng = np.random.default_rng(seed)
    a = rng.random((200, 2)) * [arena.width, arena.height]
    b = a + rng.normal(0, 2.5, a.shape)
    # every wall cell, plus a ring of wall around the grid (outside the grid is wall)
    padded = np.pad(arena.free, 1, constant_values=False)
    iy, ix = np.nonzero(~padded)
    lows = (np.stack([ix, iy], axis=1) - 1) * arena.resolution
    fast = arena.segment_crosses_wall(a, b)
    for i in range(len(a)):
        exact = any(segment_hits_box(a[i], b[i], lo, lo + arena.resolution) for lo in lows)
        assert fast[i] == exact, (a[i], b[i])


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 10_000), st.integers(0, 40), st.sampled_from([1.5, 4.0, 9.0]))
def test_nearest_visible_is_the_nearest_target_in_range_and_sight(seed, m, max_range):
    """The cell-grid search (and the same search on a grid built beforehand, as the explorer
    keeps it between ticks) against every target measured: the nearest within range whose
    segment crosses no wall, -1 when none.
    """
    from abm.gridkernels import nearest_visible_on
    from abm.neighbours import cell_grid

    arena = random_arena(seed)
    rng = np.random.default_rng(seed)
    points = rng.random((30, 2)) * [arena.width, arena.height]
    targets = rng.random((m, 2)) * [arena.width, arena.height]
    found = arena.nearest_visible(points, targets, max_range)
    if m:
        lo, width, dims, _which, start, order = cell_grid(targets, max_range)
        kept = nearest_visible_on(
            arena.padded, arena.walls_sat, arena.resolution, points, targets, max_range,
            lo, width, dims, start, order,
        )  # fmt: skip
        np.testing.assert_array_equal(kept, found)
    for k, point in enumerate(points):
        dist = np.hypot(*(targets - point).T)
        seen = [
            j
            for j in np.argsort(dist, kind="stable")
            if dist[j] <= max_range
            and not arena.segment_crosses_wall(point[None], targets[j][None])[0]
        ]
        assert found[k] == (seen[0] if seen else -1)


@settings(max_examples=60, deadline=None)
@given(
    st.integers(0, 10_000),
    st.integers(0, 30),
    st.sampled_from([5e-10, 1.5, 4.0, 9.0]),
    st.sampled_from([0.0, 1e-9]),
    st.booleans(),
)
def test_within_reach_is_numpys_distance_test_then_line_of_sight(
    seed, m, max_range, shortest, walls_block
):
    """A radio's links in one compiled pass give numpy's verdicts: ``np.hypot`` of the point
    minus the origin, raised to ``shortest``, at most ``max_range``, then the line of sight;
    points exactly at the range (along an axis) and at the origin itself included.
    """
    arena = random_arena(seed)
    rng = np.random.default_rng(seed)
    origin = rng.random(2) * [arena.width, arena.height]
    points = np.concatenate(
        [
            rng.random((m, 2)) * [arena.width, arena.height],
            origin + [[max_range, 0.0], [0.0, -max_range], [0.0, 0.0]],
        ]
    )
    distance = np.maximum(np.hypot(*(points - origin).T), shortest)
    expected = distance <= max_range
    if walls_block:
        expected &= arena.line_of_sight(np.broadcast_to(origin, points.shape), points)
    found = arena.within_reach(
        origin, points, max_range, shortest=shortest, walls_block=walls_block
    )
    np.testing.assert_array_equal(found, expected)
    assert arena.within_reach(origin, np.empty((0, 2)), max_range).shape == (0,)


@njit
def _numba_argsort(values):
    return np.argsort(values)


@settings(max_examples=200, deadline=None)
@given(st.lists(st.integers(0, 5), max_size=30), st.integers(0, 5))
def test_the_search_ranks_candidates_as_numba_argsort_does(keys, spare):
    """The nearest-visible search ranks its candidates without numba's argsort call (its
    index array and partition stack cost most of a search): the same order, ties included
    (few distinct keys), up to and beyond the 15 keys numba sorts by insertion.
    """
    from abm.gridkernels import _ascending

    found = len(keys)
    dist = np.array([*keys, *[99.0] * spare], dtype=float)  # slots past ``found`` are ignored
    rank = np.full(len(dist), -7, dtype=np.int64)
    np.testing.assert_array_equal(_ascending(dist, found, rank), _numba_argsort(dist[:found]))


def test_points_outside_the_grid_are_walls():
    arena = random_arena(1)
    assert not arena.is_free(np.array([[-0.5, 1.0], [1.0, -3.0], [1e6, 1.0]])).any()


def test_bitmap_png_round_trip(tmp_path):
    from PIL import Image

    image = np.zeros((5, 8), dtype=np.uint8)
    image[1:4, 1:7] = 255  # top row of the image = north
    image[1, 1] = 0
    Image.fromarray(image).save(tmp_path / "map.png")
    arena = Arena.from_bitmap(tmp_path / "map.png", resolution=2.0)
    assert arena.free.shape == (5, 8)
    assert arena.resolution == 2.0
    assert not arena.is_free([[3.0, 7.0]])[0]  # image pixel (1, 1) is the north-west corner
    assert arena.is_free([[5.0, 7.0]])[0]


def test_bad_maps_raise_map_errors(tmp_path):
    with pytest.raises(MapError, match="no free cell"):
        Arena(np.zeros((3, 3), dtype=bool))
    with pytest.raises(MapError, match="does not exist"):
        Arena.from_bitmap(tmp_path / "missing.png")
    (tmp_path / "broken.png").write_bytes(b"not a png at all")
    with pytest.raises(MapError, match="not a readable image"):
        Arena.from_bitmap(tmp_path / "broken.png")
    with pytest.raises(MapError, match="boolean"):
        Arena(np.ones((3, 3)))
    with pytest.raises(ConfigError, match="resolution"):
        Arena(np.ones((3, 3), dtype=bool), resolution=-1.0)


@given(
    seed=st.integers(0, 10_000),
    resolution=st.sampled_from([0.5, 1.0]),
)
@settings(max_examples=25, deadline=None)
def test_wall_lengths_match_fine_sampling(seed, resolution):
    """Metres of wall on a segment: exact cell walk vs a 1 mm sampling of the segment."""
    rng = np.random.default_rng(seed)
    free = rng.random((12, 16)) > 0.3
    arena = Arena(free, resolution)
    a = rng.uniform(0, [arena.width, arena.height], size=(3, 2))
    b = rng.uniform(0, [arena.width, arena.height], size=(4, 2))
    got = arena.wall_lengths(a, b)
    assert got.shape == (3, 4)
    for i in range(3):
        for j in range(4):
            length = float(np.hypot(*(b[j] - a[i])))
            n = max(2, int(length / 1e-3))
            s = (np.arange(n) + 0.5) / n
            samples = a[i] + s[:, None] * (b[j] - a[i])
            walled = ~arena.is_free(samples)
            want = length * float(np.mean(walled))
            # the sampling misplaces each wall/free boundary by at most one sample spacing
            boundaries = int(np.count_nonzero(np.diff(walled))) + 1
            assert got[i, j] == pytest.approx(want, abs=boundaries * length / n + 1e-9)


def test_wall_lengths_across_one_wall():
    free = np.ones((5, 9), dtype=bool)
    free[:, 4] = False  # a 1 m wall at x in [4, 5)
    arena = Arena(free)
    got = arena.wall_lengths(np.array([[1.5, 2.5]]), np.array([[7.5, 2.5], [3.5, 0.5]]))
    assert got[0, 0] == pytest.approx(1.0)  # straight across
    assert got[0, 1] == 0.0  # same side
    diagonal = arena.wall_lengths(np.array([[1.5, 0.5]]), np.array([[7.5, 3.5]]))
    assert diagonal[0, 0] == pytest.approx(np.hypot(6, 3) / 6)  # 1 m of x at slope 1/2


@settings(max_examples=60, deadline=None)
@given(
    st.integers(0, 10_000),
    st.sampled_from([0.0, 0.02, 0.1]),
    st.sampled_from([0.2, 1.0]),
    st.floats(0.0, 6.0),
)
def test_raycasts_skip_only_rays_with_no_wall_in_range(seed, density, resolution, reach):
    """The sweep shortcut (no wall within range: read the range) gives every ray exactly what
    walking it gives: sparse walls, origins shared by sweeps of rays, near the border too; and
    a sweep from one origin ``(2,)`` gives what the same origin on every row gives.
    """
    from abm import gridkernels

    arena = random_arena(seed, shape=(30, 40), resolution=resolution, density=density)
    rng = np.random.default_rng(seed)
    centres = rng.random((12, 2)) * [arena.width, arena.height]
    angles = np.linspace(0.0, 2 * np.pi, 37)
    dirs = np.tile(np.column_stack((np.cos(angles), np.sin(angles))), (len(centres), 1))
    origins = np.repeat(centres, len(angles), axis=0)
    walked = np.array(
        [
            gridkernels._raycast(arena.padded, resolution, *o, *d, reach)
            for o, d in zip(origins, dirs, strict=True)
        ]
    )
    assert np.array_equal(arena.raycast(origins, dirs, reach), walked)
    sweeps = [arena.raycast(centre, dirs[: len(angles)], reach) for centre in centres]
    assert np.array_equal(np.concatenate(sweeps), walked)


def test_raycast_shortcut_answers_for_an_open_room_and_not_near_walls():
    """In a room with one wall cell, a sweep far from it reads the range on every ray, one
    beside it hits the wall, one near the outer border hits the border.
    """
    free = np.ones((50, 50), dtype=bool)
    free[10, 10] = False
    arena = Arena(free, 0.2)
    dirs = np.column_stack((np.cos(np.arange(8) * np.pi / 4), np.sin(np.arange(8) * np.pi / 4)))
    assert (arena.raycast(np.broadcast_to([6.0, 6.0], dirs.shape), dirs, 1.0) == 1.0).all()
    assert arena.raycast([[2.1, 1.5]], [[0.0, 1.0]], 1.0)[0] == pytest.approx(0.5)
    assert arena.raycast([[9.9, 5.0]], [[1.0, 0.0]], 1.0)[0] == pytest.approx(0.1)
