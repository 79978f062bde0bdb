from itertools import pairwise

import numpy as np
import pytest
import simpy
from hypothesis import given, settings
from hypothesis import strategies as st

from abm.arena import Arena
from abm.errors import ConfigError
from abm.physics import FlightParams, Physics


class RandomPilot:
    """Flies every robot towards random, changing goals; never finishes."""

    def __init__(self, rng):
        self.rng = rng

    def control(self, physics):
        n = physics.n_flying
        return self.rng.normal(0, 2.0, (n, 2)), np.zeros(n, dtype=bool)


def square_in_free_space(arena: Arena, pos: np.ndarray, r: float) -> np.ndarray:
    corners = np.array([[-r, -r], [-r, r], [r, -r], [r, r]]) * (1 - 1e-6)
    return np.all([arena.is_free(pos + c) for c in corners], axis=0)


@settings(max_examples=15, deadline=None)
@given(st.integers(0, 10_000), st.sampled_from([1.0, 3.0]), st.integers(1, 30))
def test_robots_never_pass_through_walls(seed, resolution, n):
    rng = np.random.default_rng(seed)
    free = rng.random((10, 10)) > 0.35
    arena = Arena(free, resolution)
    env = simpy.Environment()
    physics = Physics(env, arena, rng, RandomPilot(rng), params=FlightParams(max_speed=2.0))
    physics.trace = []
    starts = arena.free_cell_centres()[rng.integers(0, free.sum(), n)]
    for i, p in enumerate(starts):
        physics.fly(i, p)
    env.run(until=30.0)
    r = physics.params.body_radius
    for (_t0, ids0, p0), (_t1, ids1, p1) in pairwise(physics.trace):
        assert (ids0 == ids1).all()
        assert not arena.segment_crosses_wall(p0, p1).any()
        assert square_in_free_space(arena, p1, r).all()


def test_a_robot_robot_contact_counts_two_collisions():
    arena = Arena(np.ones((5, 10), dtype=bool), 1.0)
    env = simpy.Environment()

    class Towards:
        def control(self, physics):
            v = np.array([[1.0, 0.0], [-1.0, 0.0]])[: physics.n_flying]
            return v, np.zeros(physics.n_flying, dtype=bool)

    params = FlightParams(body_noise=0.0)
    physics = Physics(env, arena, np.random.default_rng(0), Towards(), params=params)
    physics.fly(1, [3.0, 2.5])
    physics.fly(2, [7.0, 2.5])
    while physics.robot_collisions == 0 and env.now < 10.0:
        env.run(until=env.now + 0.1)
    assert physics.robot_collisions == 2
    assert physics.wall_collisions == 0
    # the pair bounced apart: their velocities now point away from each other
    assert physics.vel[0, 0] <= 0.0 <= physics.vel[1, 0]


def test_the_physics_sleeps_while_nothing_flies():
    arena = Arena(np.ones((5, 5), dtype=bool), 1.0)
    env = simpy.Environment()
    physics = Physics(env, arena, np.random.default_rng(0), RandomPilot(np.random.default_rng(0)))
    env.run(until=1000.0)
    assert physics.ticks == 0


def test_arrival_is_a_simpy_event():
    arena = Arena(np.ones((5, 5), dtype=bool), 1.0)
    env = simpy.Environment()

    class StopAfterTen:
        def control(self, physics):
            return np.zeros((physics.n_flying, 2)), np.full(physics.n_flying, physics.ticks >= 10)

    physics = Physics(env, arena, np.random.default_rng(0), StopAfterTen())
    arrived = physics.fly(1, [2.5, 2.5])
    env.run(until=arrived)
    assert env.now == pytest.approx(0.9)
    assert physics.n_flying == 0


def test_a_tick_too_long_for_the_grid_is_rejected():
    arena = Arena(np.ones((5, 5), dtype=bool), 1.0)
    with pytest.raises(ConfigError, match="dt=1.0 s is too long"):
        Physics(simpy.Environment(), arena, np.random.default_rng(0), dt=1.0)
