"""The path follower drives ground robots along their polylines through the physics: every
waypoint in turn, landing exactly on the last one, in about the path's length over the speed.
Several robots drive at once, each in its own band of an open room, so no two ever touch.
"""

import numpy as np
import simpy
from hypothesis import given, settings
from hypothesis import strategies as st

from abm.arena import Arena
from abm.pathfollow import PathFollower, ground_robot
from abm.physics import Physics

SPEED, DT, RADIUS = 0.5, 0.1, 0.05
STEP = SPEED * DT  # the most a robot moves in one tick (m)


def _distance_to_segment(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
    ab = b - a
    t = 0.0 if not ab.any() else float(np.clip(np.dot(p - a, ab) / np.dot(ab, ab), 0.0, 1.0))
    return float(np.hypot(*(p - (a + t * ab))))


def _band_path(band: int):
    """A start and 1-5 waypoints inside band ``band`` (y between 1 + 3 band and 2.5 + 3 band)."""
    point = st.tuples(st.floats(1.0, 9.0), st.floats(1.0 + 3 * band, 2.5 + 3 * band))
    return st.lists(point, min_size=2, max_size=6).map(lambda pts: np.array(pts, dtype=float))


@settings(max_examples=40, deadline=None)
@given(st.integers(1, 3).flatmap(lambda n: st.tuples(*(_band_path(b) for b in range(n)))))
def test_robots_drive_their_polylines_and_land_on_the_last_waypoint(paths):
    env = simpy.Environment()
    trace: dict[int, list[np.ndarray]] = {i: [] for i in range(len(paths))}

    def positions_out(ids, pos):
        for rid, xy in zip(ids.tolist(), pos, strict=True):
            trace[rid].append(xy.copy())

    room = Arena(np.ones((10, 10), dtype=bool), 1.0)
    physics = Physics(env, room, np.random.default_rng(0), positions_out=positions_out,
                      params=ground_robot(SPEED, RADIUS, DT), dt=DT)  # fmt: skip
    follower = PathFollower(physics, SPEED)
    arrived = {}
    for rid, path in enumerate(paths):
        event = follower.drive(rid, path[0], path[1:])
        event.callbacks.append(lambda _e, rid=rid: arrived.setdefault(rid, env.now))
    env.run(until=200.0)
    assert sorted(arrived) == list(range(len(paths))) and follower.stalled == 0
    for rid, path in enumerate(paths):
        seen = np.array([path[0], *trace[rid]])  # where it started, then after each tick
        assert np.allclose(seen[-1], path[-1], atol=1e-9, rtol=0)  # landed exactly there
        # never further from its polyline than one tick's travel
        segments = list(zip(path[:-1], path[1:], strict=True))
        for p in seen:
            assert min(_distance_to_segment(p, a, b) for a, b in segments) <= STEP + 1e-9
        # every waypoint in turn: each one within a tick's travel, after the one before
        tick = 0
        for waypoint in path[1:]:
            close = np.flatnonzero(np.hypot(*(seen[tick:] - waypoint).T) <= STEP + 1e-9)
            assert close.size, f"waypoint {waypoint} not reached in turn"
            tick += int(close[0])
        length = float(np.hypot(*np.diff(path, axis=0).T).sum())
        corners = len(path) - 2
        # a corner is left within a tick's travel of it: up to two ticks' travel cut there
        assert length / SPEED - (2 * corners + 1) * DT - 1e-9 <= arrived[rid]
        assert arrived[rid] <= length / SPEED + (corners + 2) * DT + 1e-9  # a tick per corner
