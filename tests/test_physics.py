import math
from itertools import pairwise

import numpy as np
import pytest
import simpy
from hypothesis import given, settings
from hypothesis import strategies as st
from numba import njit

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


def random_flight(seed: int, resolution: float, n: int, until: float):
    """``n`` random pilots from free cells of a seeded 10 x 10 room with 35 % wall cells, flown
    with their positions traced: (arena, start positions, physics)."""
    rng = np.random.default_rng(seed)
    free = rng.random((10, 10)) > 0.35
    arena = Arena(free, resolution)
    env = simpy.Environment()
    physics = Physics(env, arena, rng, RandomPilot(rng), params=FlightParams(max_speed=2.0))
    physics.trace = []
    starts = arena.free_cell_centres()[rng.integers(0, free.sum(), n)]
    for i, p in enumerate(starts):
        physics.fly(i, p)
    env.run(until=until)
    return arena, starts, physics


@settings(max_examples=15, deadline=None)
@given(st.integers(0, 10_000), st.sampled_from([1.0, 3.0]), st.integers(1, 30))
def test_robots_never_pass_through_walls(seed, resolution, n):
    arena, _starts, physics = random_flight(seed, resolution, n, until=30.0)
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


class Crowd:
    """Random pilots in a crowd: some flyers land and new ones take off as it runs."""

    def __init__(self, rng):
        self.rng = rng
        self.next_id = 0

    def control(self, physics):
        n = physics.n_flying
        done = self.rng.random(n) < 0.02
        return self.rng.normal(0, 2.0, (n, 2)), done


def crowd_run(seed: int, monkeypatch, **settings) -> tuple[list, int, int]:
    """A seeded crowd of flyers in a walled room, some joining later: trace and collisions."""
    import abm.physics

    for name, value in settings.items():
        monkeypatch.setattr(abm.physics, name, value)
    rng = np.random.default_rng(seed)
    free = np.ones((8, 8), dtype=bool)
    free[3, 2:6] = False
    arena = Arena(free, 1.0)
    env = simpy.Environment()
    params = FlightParams(max_speed=2.0, body_noise=0.02, body_radius=0.2)
    physics = Physics(env, arena, rng, Crowd(rng), params=params)
    physics.trace = []
    cells = arena.free_cell_centres()

    def launches():
        for robot in range(60):
            physics.fly(robot, cells[rng.integers(len(cells))] + rng.uniform(-0.2, 0.2, 2))
            yield env.timeout(rng.exponential(0.3))

    env.process(launches())
    env.run(until=20.0)
    return physics.trace, physics.robot_collisions, physics.wall_collisions


def same_runs(a, b) -> bool:
    (trace_a, *counts_a), (trace_b, *counts_b) = a, b
    return counts_a == counts_b and all(
        ta == tb and np.array_equal(ia, ib) and np.array_equal(pa, pb)
        for (ta, ia, pa), (tb, ib, pb) in zip(trace_a, trace_b, strict=True)
    )


@settings(max_examples=6, deadline=None)
@given(st.integers(0, 10_000))
def test_contacts_from_the_verlet_list_equal_a_search_every_tick(seed):
    """The skin only saves searches: a run with a zero skin (a fresh cell-list search every
    tick) moves every flyer and counts every collision exactly as the default does."""
    with pytest.MonkeyPatch.context() as monkeypatch:
        every_tick = crowd_run(seed, monkeypatch, CONTACT_SKIN_TICKS=0)
    with pytest.MonkeyPatch.context() as monkeypatch:
        reused = crowd_run(seed, monkeypatch)
    assert reused[1] > 0  # the crowd does collide
    assert same_runs(every_tick, reused)


@settings(max_examples=4, deadline=None)
@given(st.integers(0, 10_000))
def test_the_flight_step_split_over_threads_equals_one_pass(seed):
    with pytest.MonkeyPatch.context() as monkeypatch:
        one_pass = crowd_run(seed, monkeypatch)
    with pytest.MonkeyPatch.context() as monkeypatch:
        threaded = crowd_run(seed, monkeypatch, ROWS_PER_THREAD=3, _CPUS=4)
    assert same_runs(one_pass, threaded)


@pytest.mark.parametrize("direct_pairs", [0, 1000])
def test_contacts_are_the_pairs_closer_than_two_radii(direct_pairs, monkeypatch):
    """Checked tick by tick against a direct search while flyers join, move and leave: the
    contacts kept (as id keys) and the new ones counted and reported; and the new wall
    contacts: the bodies touching a wall now and not before the tick, each flush against one.
    With the contact candidates (``DIRECT_PAIRS`` 0) and with every pair measured in the
    tick's one call (1000)."""
    import abm.physics
    from abm.neighbours import pairs_within

    monkeypatch.setattr(abm.physics, "DIRECT_PAIRS", direct_pairs)
    rng = np.random.default_rng(3)
    free = np.ones((6, 6), dtype=bool)
    free[2, 1:4] = False
    arena = Arena(free, 1.0)
    env = simpy.Environment()
    reported = {"robot": [], "wall": []}
    ticks = []
    start = {}  # the contacts, the counts and who touched a wall before the tick

    def checked_contacts(ids, pos):
        """The physics' positions_out: after a tick's contacts, before its arrivals leave."""
        r = physics.params.body_radius
        i, j = pairs_within(pos, 2 * r)
        a, b = ids[i], ids[j]
        expected = np.sort(np.minimum(a, b) << 32 | np.maximum(a, b))
        assert np.array_equal(physics._pairs_in_contact, expected)
        new = sorted(set(expected.tolist()) - start["contacts"])
        assert reported["robot"] == [(key >> 32, key & (2**32 - 1)) for key in new]
        assert physics.robot_collisions - start["robots"] == 2 * len(new)
        walls = ids[physics._wall_contact & ~start["touching"]].tolist()
        assert reported["wall"] == [(rid, None) for rid in walls]
        assert physics.wall_collisions - start["walls"] == len(walls)
        hit = pos[physics._wall_contact]
        assert not square_in_free_space(arena, hit, r + 1e-6).any()  # flush against a wall
        ticks.append((len(expected), len(new), len(walls)))

    physics = Physics(env, arena, rng, Crowd(rng), params=FlightParams(max_speed=2.0),
                      positions_out=checked_contacts)  # fmt: skip
    physics.on_collision = lambda kind, a, b: reported[kind].append((a, b))
    tick = physics.tick

    def checked_tick():
        start["contacts"] = set(physics._pairs_in_contact.tolist())
        start["robots"], start["walls"] = physics.robot_collisions, physics.wall_collisions
        start["touching"] = physics._wall_contact.copy()
        reported["robot"].clear()
        reported["wall"].clear()
        tick()

    physics.tick = checked_tick
    cells = arena.free_cell_centres()
    physics.fly_many(range(40), cells[rng.integers(len(cells), size=40)])
    env.run(until=200 * physics.dt)
    assert len(ticks) >= 150
    assert all(sum(t[k] for t in ticks) > 0 for k in range(3))  # contacts, new ones, walls


@settings(max_examples=6, deadline=None)
@given(st.integers(0, 10_000))
def test_a_tick_measuring_every_pair_equals_one_with_contact_candidates(seed):
    """:func:`abm.physics._tick_direct` (every row pair, up to ``DIRECT_PAIRS`` flyers) moves
    every flyer and counts every collision exactly as the flight step and the contact
    candidates do, over a crowd whose size changes as flyers join and land."""
    with pytest.MonkeyPatch.context() as monkeypatch:
        candidates = crowd_run(seed, monkeypatch, DIRECT_PAIRS=0)
    with pytest.MonkeyPatch.context() as monkeypatch:
        direct = crowd_run(seed, monkeypatch, DIRECT_PAIRS=1000)
    assert direct[1] > 0 and direct[2] > 0  # robots and walls are hit
    assert same_runs(candidates, direct)


@settings(max_examples=100, deadline=None)
@given(st.lists(st.tuples(st.booleans(), st.booleans()), max_size=40))
def test_new_wall_contacts_are_the_numpy_rule(flags):
    """The compiled new-contact step: ``np.flatnonzero(contact & ~before)``, and ``before``
    overwritten with ``contact``."""
    from abm.physics import _new_contacts

    contact = np.array([c for c, _ in flags], dtype=bool)
    before = np.array([b for _, b in flags], dtype=bool)
    expected = np.flatnonzero(contact & ~before)
    np.testing.assert_array_equal(_new_contacts(contact, before), expected)
    np.testing.assert_array_equal(before, contact)


@settings(max_examples=300, deadline=None)
@given(
    st.floats(-1e6, 1e6, allow_nan=False),
    st.floats(-1e6, 1e6, allow_nan=False),
    st.floats(1e-13, 1e3),
    st.floats(0.999, 1.001),
)
def test_the_cap_factor_equals_the_measured_one_bit_for_bit(x, y, cap, near):
    """The flight kernel skips ``hypot`` for vectors clearly under a cap: the factor must be
    exactly the compiled ``min(1, cap / max(hypot, 1e-12))`` anyway (numba's ``hypot`` can
    differ from CPython's in the last bit), including vectors right at the cap."""
    from abm.gridkernels import _cap_below, _capped

    norm = math.hypot(x, y)
    if norm > 0:  # also try the vector scaled to lie right at the cap
        for vx, vy in ((x, y), (x * cap * near / norm, y * cap * near / norm)):
            assert _capped(vx, vy, cap, _cap_below(cap)) == _measured_cap_factor(vx, vy, cap)


@njit(cache=True)
def _measured_cap_factor(x: float, y: float, cap: float) -> float:
    """The flight kernel's cap factor before the ``hypot`` skip."""
    return min(1.0, cap / max(math.hypot(x, y), 1e-12))


@settings(max_examples=10, deadline=None)
@given(st.integers(0, 10_000), st.integers(1, 20))
def test_the_odometer_is_the_path_length_of_the_trace(seed, n):
    """``Physics.distance`` sums each flyer's displacement per tick, walls' stops and body
    noise included: exactly the length of the polyline the trace draws from the starts."""
    _arena, starts, physics = random_flight(seed, 1.0, n, until=20.0)
    points = [starts] + [pos for _t, _ids, pos in physics.trace]
    path = sum(np.hypot(*(b - a).T).sum() for a, b in pairwise(points))
    assert physics.distance == pytest.approx(path, rel=1e-9)


@settings(max_examples=200, deadline=None)
@given(st.integers(0, 150), st.integers(0, 150), st.integers(1, 400), st.integers(0, 2**32))
def test_membership_of_ids_is_numpys_isin(n_values, n_pool, spread, seed):
    """The compiled membership test the physics uses for flyer ids and contact pairs gives
    ``np.isin``'s answer on short and long arrays alike (its direct path, and its sorted path
    once both exceed 16 and their product 4096), with repeats (values drawn from ``spread``
    integers) and 64-bit pair keys.
    """
    from abm.physics import _member_of

    rng = np.random.default_rng(seed)
    a = rng.integers(0, spread, n_values, dtype=np.int64)
    b = rng.integers(0, spread, n_pool, dtype=np.int64)
    np.testing.assert_array_equal(_member_of(a, b), np.isin(a, b))
    a, b = (a << 32) | a, (b << 32) | b
    np.testing.assert_array_equal(_member_of(a, b), np.isin(a, b))
