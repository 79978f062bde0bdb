"""abm.polygons and abm.visibility_graph: inside tests, blocking, pushing out, and shortest paths
around polygonal obstacles.
"""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from abm.errors import ConfigError
from abm.polygons import (
    as_polygon,
    inside_any,
    inside_polygon,
    offset_polygon,
    push_outside,
    segments_blocked,
)
from abm.visibility_graph import VisibilityPlanner

SQUARE = np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]])


def test_inside_is_the_open_interior():
    points = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [1.5, 0.0], [0.999, -0.999]])
    assert inside_polygon(points, SQUARE).tolist() == [True, False, False, False, True]


def test_a_clockwise_polygon_is_turned_and_a_flat_one_refused():
    assert np.array_equal(as_polygon(SQUARE[::-1]), SQUARE)  # counter-clockwise again
    with pytest.raises(ConfigError, match="zero area"):
        as_polygon([[0, 0], [1, 1], [2, 2]])
    with pytest.raises(ConfigError, match="3 or more"):
        as_polygon([[0, 0], [1, 1]])


def test_a_grown_square_is_the_square_grown_on_every_side():
    grown = offset_polygon(SQUARE, 0.5)
    assert np.allclose(np.sort(np.abs(grown), axis=0), 1.5)


def test_segments_through_the_interior_are_blocked_and_along_an_edge_not():
    starts = np.array([[-3.0, 0.0], [-3.0, 1.0], [-3.0, 2.0], [-1.0, -1.0]])
    ends = np.array([[3.0, 0.0], [3.0, 1.0], [3.0, 2.0], [1.0, 1.0]])
    assert segments_blocked(starts, ends, [SQUARE]).tolist() == [True, False, False, True]


def test_points_inside_are_pushed_to_the_nearest_edge():
    moved, was_inside = push_outside(np.array([[0.8, 0.1], [2.0, 0.0]]), [SQUARE], margin=1e-3)
    assert was_inside.tolist() == [True, False]
    assert np.allclose(moved[0], [1.001, 0.1])
    assert np.allclose(moved[1], [2.0, 0.0])
    assert not inside_any(moved, [SQUARE]).any()


def test_the_planner_goes_round_a_square_by_the_shortest_way():
    planner = VisibilityPlanner([SQUARE])
    paths = planner.plan(np.array([[-3.0, 0.0], [-3.0, 2.0]]), np.array([[3.0, 0.0], [3.0, 2.0]]))
    assert paths.direct.tolist() == [False, True]
    assert paths.length[0] == pytest.approx(2 * np.hypot(2.0, 1.0) + 2.0, abs=1e-5)
    assert paths.length[1] == pytest.approx(6.0)
    assert paths.count.tolist() == [4, 2]


def test_clearance_keeps_the_path_that_far_from_the_obstacle():
    planner = VisibilityPlanner([SQUARE], clearance=0.5)
    paths = planner.plan(np.array([[-3.0, 0.0]]), np.array([[3.0, 0.0]]))
    pts = paths.points[0, : paths.count[0]]
    dense = np.concatenate([np.linspace(a, b, 50) for a, b in zip(pts[:-1], pts[1:], strict=True)])
    assert np.abs(dense).max(axis=1).min() >= 1.5 - 1e-5


outside = st.tuples(st.floats(-6, 6), st.floats(-6, 6)).filter(
    lambda p: max(abs(p[0]), abs(p[1])) > 1.7
)


@settings(max_examples=60, deadline=None)
@given(start=outside, goal=outside)
def test_planned_paths_never_enter_the_grown_obstacle(start, goal):
    planner = VisibilityPlanner([SQUARE, SQUARE * 0.5 + [4.0, 4.0]], clearance=0.6)
    paths = planner.plan(np.array([start]), np.array([goal]))
    if not np.isfinite(paths.length[0]):  # only when the goal sits in a grown obstacle
        assert inside_any(np.array([goal, start]), planner.grown).any()
        return
    pts = paths.points[0, : paths.count[0]]
    assert not segments_blocked(pts[:-1], pts[1:], planner.grown).any()
    assert paths.length[0] >= np.hypot(*np.subtract(goal, start)) - 1e-9
