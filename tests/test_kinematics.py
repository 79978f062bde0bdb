"""Kinematic moves with the bump model: compass headings, no robot ever enters or crosses a
wall, blocked moves leave the robot in place."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from abm.arena import Arena
from abm.kinematics import bump_moves, heading_vectors, wrap_degrees


def test_compass_headings():
    v = heading_vectors(np.array([0.0, 90.0, 180.0, 270.0]))
    assert np.allclose(v, [[0, 1], [1, 0], [0, -1], [-1, 0]], atol=1e-12)


def _arena() -> Arena:
    free = np.ones((12, 12), dtype=bool)
    free[[0, -1], :] = free[:, [0, -1]] = False
    free[3:9, 6] = False  # a wall
    free[2, 2] = False  # a pillar
    return Arena(free, 0.5)


@settings(max_examples=60, deadline=None)
@given(
    st.lists(
        st.tuples(
            st.floats(0.55, 5.45), st.floats(0.55, 5.45), st.floats(0, 360), st.floats(0.0, 0.45)
        ),
        min_size=1,
        max_size=20,
    )  # fmt: skip
)
def test_no_move_enters_or_crosses_a_wall(moves):
    arena = _arena()
    pos = np.array([[x, y] for x, y, _, _ in moves])
    keep = arena.is_free(pos)
    pos = pos[keep]
    heading = np.array([h for _, _, h, _ in moves])[keep]
    distance = np.array([d for _, _, _, d in moves])[keep]
    new, blocked = bump_moves(arena, pos, heading, distance)
    assert arena.is_free(new).all()
    assert not arena.segment_crosses_wall(pos, new).any()
    assert np.array_equal(new[blocked], pos[blocked])
    free_moves = ~blocked
    want = pos[free_moves] + distance[free_moves, None] * heading_vectors(heading[free_moves])
    assert np.allclose(new[free_moves], want)


def test_a_move_into_the_wall_is_blocked_and_a_move_along_it_is_not():
    arena = _arena()
    start = np.array([[2.75, 3.0], [2.75, 3.0]])  # just west of the wall at x in [3, 3.5)
    new, blocked = bump_moves(arena, start, np.array([90.0, 0.0]), np.array([0.4, 0.4]))
    assert list(blocked) == [True, False]
    assert np.array_equal(new[0], start[0]) and np.allclose(new[1], [2.75, 3.4])


@given(st.floats(-1e4, 1e4, allow_nan=False))
def test_wrapped_angles_lie_in_the_half_open_circle_and_point_the_same_way(angle):
    wrapped = float(wrap_degrees(angle))
    assert -180.0 < wrapped <= 180.0
    assert np.allclose(heading_vectors(np.array([wrapped])), heading_vectors(np.array([angle])))
    assert wrap_degrees(180.0) == 180.0 and wrap_degrees(-180.0) == 180.0
