"""abm.pso: the PSO update rules (eqs. 2-5 of Saska et al. 2016) and the plain optimiser."""

import numpy as np
import pytest

from abm.errors import ConfigError
from abm.pso import inertia_weight, minimise, update_bests, velocity_update


def sphere(x: np.ndarray) -> np.ndarray:
    return (x**2).sum(axis=1)


def test_inertia_falls_linearly_from_start_to_end():
    assert inertia_weight(0, 10, 0.9, 0.4) == pytest.approx(0.9)
    assert inertia_weight(5, 10, 0.9, 0.4) == pytest.approx(0.65)
    assert inertia_weight(10, 10, 0.9, 0.4) == pytest.approx(0.4)


def test_velocity_moves_each_component_between_the_particle_and_its_attractors():
    rng = np.random.default_rng(0)
    p = np.zeros((500, 2))
    u = np.zeros((500, 2))
    new = velocity_update(u, p, np.ones((500, 2)), np.array([2.0, 2.0]), rng, c1=1.0, c2=1.0)
    # u = r1 * (1 - 0) + r2 * (2 - 0): each component in [0, 3], mean 1.5
    assert new.min() >= 0.0 and new.max() <= 3.0
    assert new.mean() == pytest.approx(1.5, abs=0.05)


def test_without_attraction_the_inertia_alone_scales_the_velocity_and_u_max_clips():
    rng = np.random.default_rng(1)
    u = np.array([[4.0, -4.0]])
    same = velocity_update(u, np.zeros((1, 2)), np.zeros((1, 2)), np.zeros(2), rng, c1=0, c2=0)
    assert np.array_equal(same, u)
    half = velocity_update(u, np.zeros((1, 2)), np.zeros((1, 2)), np.zeros(2), rng, c1=0, c2=0,
                           w=0.5, u_max=1.5)  # fmt: skip
    assert np.array_equal(half, [[1.5, -1.5]])


def test_bests_only_improve():
    best_cost = np.array([3.0, 1.0])
    best_p = np.zeros((2, 1))
    g = update_bests(np.array([2.0, 5.0]), np.array([[7.0], [8.0]]), best_cost, best_p)
    assert best_cost.tolist() == [2.0, 1.0] and best_p.ravel().tolist() == [7.0, 0.0] and g == 1


def test_constricted_pso_finds_the_sphere_minimum_and_repeats_under_a_seed():
    def run(seed):
        rng = np.random.default_rng(seed)
        x0 = rng.uniform(-5, 5, (30, 4))
        v0 = rng.uniform(-1, 1, (30, 4))
        return minimise(sphere, x0, v0, 150, rng, c1=1.49618, c2=1.49618, w_start=0.7298)

    a, b = run(3), run(3)
    assert a.cost < 1e-6
    assert np.array_equal(a.history, b.history)
    assert np.all(np.diff(a.history) <= 0)  # the best never gets worse


def test_bad_shapes_are_refused():
    rng = np.random.default_rng(0)
    with pytest.raises(ConfigError, match="x0 and v0"):
        minimise(sphere, np.zeros((3, 2)), np.zeros((3, 3)), 5, rng)
    with pytest.raises(ConfigError, match="iterations"):
        minimise(sphere, np.zeros((3, 2)), np.zeros((3, 2)), 0, rng)


def test_the_same_as_pyswarms_global_best_on_the_sphere():
    """The optimiser core against pyswarms' GlobalBestPSO with the same settings: the median
    best cost after 100 iterations agrees within an order of magnitude (20 seeds each).
    """
    ps = pytest.importorskip("pyswarms")
    options = {"c1": 1.49618, "c2": 1.49618, "w": 0.7298}
    ours, theirs = [], []
    for seed in range(20):
        rng = np.random.default_rng(seed)
        x0 = rng.uniform(-5, 5, (20, 5))
        v0 = rng.uniform(0, 1, (20, 5))  # pyswarms draws U[0, 1) without a clamp
        ours.append(minimise(sphere, x0, v0, 100, rng, c1=1.49618, c2=1.49618, w_start=0.7298).cost)
        np.random.seed(seed)
        opt = ps.single.GlobalBestPSO(20, 5, options=options, init_pos=x0)
        theirs.append(opt.optimize(sphere, 100, verbose=False)[0])
    ratio = np.median(ours) / np.median(theirs)
    assert 0.1 < ratio < 10.0
