"""The neighbour index answers exactly what a brute-force search over all points answers."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from abm.errors import ConfigError
from abm.neighbours import NeighbourIndex, nearest_distance, pairs_within, same_keys, within


def brute_pairs(points, radius, box=None, inclusive=False):
    d = points[:, None, :] - points[None, :, :]
    if box is not None:
        size = np.asarray(box)
        d = (d + size / 2) % size - size / 2
    dist2 = (d**2).sum(axis=2)
    close = dist2 <= radius**2 if inclusive else dist2 < radius**2
    return np.nonzero(np.triu(close, 1))


clouds = st.tuples(
    st.integers(0, 120),  # points
    st.floats(0.1, 5.0),  # radius
    st.floats(1.0, 60.0),  # width
    st.floats(1.0, 60.0),  # height
    st.integers(0, 2**32 - 1),  # seed
)


@settings(max_examples=60, deadline=None)
@given(clouds, st.booleans())
def test_pairs_match_brute_force_walled_and_periodic(cloud, periodic):
    n, radius, width, height, seed = cloud
    rng = np.random.default_rng(seed)
    points = rng.uniform(0, 1, (n, 2)) * (width, height)
    if rng.random() < 0.3:  # clumps: many points per cell
        points = np.round(points / 3) * 3 % (width, height)
    box = (width, height) if periodic else None
    i, j = pairs_within(points, radius, box)
    bi, bj = brute_pairs(points, radius, box)
    np.testing.assert_array_equal(i, bi)  # same pairs, in lexicographic order
    np.testing.assert_array_equal(j, bj)


def test_inclusive_counts_pairs_exactly_radius_apart():
    points = np.array([[0.0, 0.0], [1.0, 0.0], [3.0, 0.0]])
    assert len(pairs_within(points, 1.0)[0]) == 0
    assert pairs_within(points, 1.0, inclusive=True)[1].tolist() == [1]


@settings(max_examples=40, deadline=None)
@given(clouds, st.booleans())
def test_within_matches_brute_force(cloud, periodic):
    n, radius, width, height, seed = cloud
    rng = np.random.default_rng(seed)
    points = rng.uniform(0, 1, (n, 2)) * (width, height)
    queries = rng.uniform(0, 1, (7, 2)) * (width, height)
    box = (width, height) if periodic else None
    offsets, indices = within(points, queries, radius, box)
    for q, point in enumerate(queries):
        d = points - point
        if periodic:
            d = (d + np.asarray(box) / 2) % box - np.asarray(box) / 2
        want = np.nonzero((d**2).sum(axis=1) <= radius**2)[0]
        np.testing.assert_array_equal(indices[offsets[q] : offsets[q + 1]], want)


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 2**32 - 1), st.floats(0.5, 5.0))
def test_dynamic_index_finds_every_key_in_range_after_moves(seed, cell):
    rng = np.random.default_rng(seed)
    index = NeighbourIndex(cell)
    where = {}
    for step in range(200):
        key = int(rng.integers(30))
        action = rng.random()
        if action < 0.15:
            index.remove(key)
            where.pop(key, None)
        else:
            where[key] = rng.uniform(-20, 20, 2)
            index.add(key, where[key])
        if step % 20 == 0:
            probe = rng.uniform(-20, 20, 2)
            near = set(index.near(probe))
            assert near <= where.keys()
            assert {k for k, p in where.items() if np.hypot(*(p - probe)) <= cell} <= near
    assert len(index) == len(where)


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda: pairs_within(np.zeros((3, 2)), 0.0), "radius"),
        (lambda: pairs_within(np.zeros((3, 3)), 1.0), "points"),
        (lambda: pairs_within(np.zeros((3, 2)), 1.0, box=(0.0, 5.0)), "box"),
        (lambda: NeighbourIndex(-1.0), "radius"),
    ],
)
def test_bad_input_is_a_config_error(call, match):
    with pytest.raises(ConfigError, match=match):
        call()


@settings(max_examples=40, deadline=None)
@given(st.integers(0, 60), st.integers(0, 60), st.integers(0, 2**32 - 1))
def test_nearest_distance_equals_the_minimum_over_all_targets(n, m, seed):
    rng = np.random.default_rng(seed)
    points = rng.uniform(-20, 80, (n, 2))  # some outside the targets' box
    targets = rng.uniform(0, 50, (m, 2)) * rng.uniform(0, 1, 2)  # clustered, even on a line
    want = np.full(n, np.inf)
    if m:
        want = np.hypot(*(points[:, None] - targets[None]).transpose(2, 0, 1)).min(axis=1)
    np.testing.assert_array_equal(nearest_distance(points, targets), want)


@settings(max_examples=200, deadline=None)
@given(
    st.lists(st.integers(-3, 3), max_size=6),
    st.lists(st.integers(-3, 3), max_size=6),
)
def test_same_keys_is_numpys_array_equal(a, b):
    a, b = np.array(a, dtype=np.int64), np.array(b, dtype=np.int64)
    assert same_keys(a, b) == np.array_equal(a, b)
    assert same_keys(a, a.copy())
