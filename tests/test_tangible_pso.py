"""Tangible PSO (Saska et al. 2016): the paper's invariants, eq. 1 by hand, goal swapping,
determinism, Table 1's effect of motion planning, and bad input named in errors.
"""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from abm.errors import ConfigError
from abm.polygons import inside_any
from abm.visibility_graph import VisibilityPlanner
from models.tangible_pso import TangiblePSOModel
from models.tangible_pso.cost import CoverageCost
from models.tangible_pso.feasibility import follow, localised
from models.tangible_pso.transition import plan_paths

SMALL = {"particles": 12, "iterations": 15}


def _run(**kw):
    return TangiblePSOModel(**{**SMALL, **kw}).run()


# ---------------------------------------------------------------------- eq. 1 by hand
def test_cost_of_one_mav_at_the_optimal_altitude():
    aoi = np.zeros((4, 4))
    aoi[1, 1] = aoi[3, 3] = 1.0
    cost = CoverageCost(aoi, a_max=1.0, camera_angle=90.0, z_opt=1.0)
    # at z = 1 the footprint is [1, 3] x [1, 3]: it holds cell (1, 1), not cell (3, 3)
    assert cost(np.array([[[2.0, 2.0, 1.0]]]))[0] == pytest.approx(1.0)
    assert cost.total == 2.0


def test_cost_of_high_mavs_sharing_cells():
    aoi = np.zeros((4, 4))
    aoi[0, 0], aoi[2, 3], aoi[3, 1] = 1.0, 0.6, 0.2
    cost = CoverageCost(aoi, a_max=1.0, camera_angle=90.0, z_opt=1.0)
    # at z = 2 the footprint [0, 4]^2 holds every cell, each MAV adding 1 * (1/2)^2 = 0.25
    one = cost(np.array([[2.0, 2.0, 2.0]]))
    two = cost(np.array([[2.0, 2.0, 2.0], [2.0, 2.0, 2.0]]))
    assert one == pytest.approx((1 - 0.25) + (0.6 - 0.25) + 0.0)
    assert two == pytest.approx((1 - 0.5) + (0.6 - 0.5) + 0.0)


def test_below_the_optimal_altitude_an_mav_gains_no_more_per_cell():
    aoi = np.ones((2, 2))
    cost = CoverageCost(aoi, a_max=2.0, camera_angle=90.0, z_opt=1.0)
    # z = 0.5 < z_opt: footprint [0.5, 1.5]^2 holds no whole cell; z = 1: all four at 2 each
    assert cost(np.array([[1.0, 1.0, 0.5]])) == pytest.approx(4.0)
    assert cost(np.array([[1.0, 1.0, 1.0]])) == pytest.approx(0.0)


# ---------------------------------------------------------------------- invariants
def test_with_motion_planning_no_realised_position_is_in_a_no_fly_zone():
    for seed in (11, 12):
        m = _run(seed=seed, neighbours=0, motion_planning=True)
        history = np.array(m.history)
        assert not inside_any(history[..., :2], m.zones).any()
        assert m.summary()["collision"] is False


def test_every_realised_state_keeps_the_localisation_constraint():
    for k in (1, 2):
        m = _run(seed=20 + k, neighbours=k)
        history = np.array(m.history)
        assert localised(history, k, m.params.d_min, m.params.loc_range).all()
        moved = np.linalg.norm(np.diff(history, axis=0), axis=-1).max()
        assert moved > 1.0  # the constraint is kept by flying, not by standing still


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 10_000), k=st.integers(0, 2), swarm_rule=st.booleans())
def test_the_feasibility_check_only_realises_feasible_states(seed, k, swarm_rule):
    rng = np.random.default_rng(seed)
    start = np.array([[0.0, 0.0, 5.0], [2.0, 0.0, 5.0], [1.0, 1.7, 5.0]])[None].repeat(8, 0)
    goal = start + rng.uniform(-8, 8, (8, 3, 3))
    points = np.stack([start, goal], axis=2)
    count = np.full((8, 3), 2, dtype=np.int64)
    zone = np.array([[[3.0, -2.0], [5.0, -2.0], [5.0, 2.0], [3.0, 2.0]]])
    out, outcome, travelled = follow(
        start, points, count, zone, np.array([4]), k, 1.2, 5.0, 0.1, swarm_rule
    )
    assert localised(out, k, 1.2, 5.0).all()
    assert not inside_any(out[..., :2], list(zone)).any()
    assert (travelled <= np.linalg.norm(goal - start, axis=-1) + 1e-9).all()
    free = outcome == 0
    assert np.allclose(out[free], goal[free])


def test_goal_swapping_resolves_two_crossing_paths():
    planner = VisibilityPlanner([np.array([[50.0, 50], [51, 50], [51, 51], [50, 51]])])
    start = np.array([[[0.0, 0.0, 5.0], [4.0, 0.0, 5.0]]])
    goal = np.array([[[4.0, 0.0, 5.0], [0.0, 0.0, 5.0]]])  # head-on: they meet half way
    plans = plan_paths(planner, start, goal, d_min=1.2)
    assert (plans.conflicts, plans.resolved) == (1, 1)
    ends = plans.points[0, np.arange(2), plans.count[0] - 1]
    assert np.allclose(ends, start[0])  # each now flies to the other's goal: nowhere


def test_motion_planning_swaps_goals_on_an_open_plane_too():
    kw = {"scenario": "open", "n_mavs": 6, "neighbours": 2, "iterations": 8, "seed": 4}
    assert _run(motion_planning=True, **kw).summary()["swap_conflicts"] > 0
    assert _run(motion_planning=False, **kw).summary()["swap_conflicts"] == 0


def test_the_same_seed_gives_the_same_optimisation():
    a, b = _run(seed=5, neighbours=1), _run(seed=5, neighbours=1)
    assert np.array_equal(np.array(a.history), np.array(b.history))
    assert a.events().equals(b.events())
    assert repr(a.summary()) == repr(b.summary())
    c = _run(seed=6, neighbours=1)
    assert not np.array_equal(np.array(a.history), np.array(c.history))


# ---------------------------------------------------------------------- Table 1's effect
def test_motion_planning_lowers_zone_stops_and_cost_at_k0():
    """Table 1, k = 0, on fresh seeds: with motion planning no MAV is ever stopped at the zone
    and the best cost is lower on average.
    """
    without = [
        _run(seed=s, neighbours=0, motion_planning=False, iterations=40) for s in range(100, 106)
    ]
    with_mp = [
        _run(seed=s, neighbours=0, motion_planning=True, iterations=40) for s in range(100, 106)
    ]
    assert np.mean([m.summary()["collision"] for m in without]) >= 0.5
    assert not any(m.summary()["collision"] for m in with_mp)
    assert np.mean([m.summary()["best_cost"] for m in with_mp]) < np.mean(
        [m.summary()["best_cost"] for m in without]
    )


# ---------------------------------------------------------------------- bad input
@pytest.mark.parametrize(
    ("kw", "match"),
    [
        ({"n_mavs": 0}, "n_mavs"),
        ({"n_mavs": 3, "neighbours": 3}, "neighbours"),
        ({"depot": (15.0, 15.0)}, "depot .* inside a no-fly zone"),
        ({"depot": (45.0, 5.0)}, "depot .* operational area"),
        ({"scenario": "atlantis"}, "scenario 'atlantis'"),
        ({"z_max": 4.0}, "z_max"),
        ({"stop_rule": "never"}, "stop_rule"),
        ({"depot_radius": 2.0}, "depot_radius .* only acts with init='depot'"),
        ({"init": "depot", "depot_radius": 0.5, "neighbours": 0}, "depot_radius 0.5 m"),
    ],
)
def test_bad_input_names_the_parameter(kw, match):
    with pytest.raises(ConfigError, match=match):
        TangiblePSOModel(seed=1, **kw)


def test_an_aoi_map_with_negative_values_is_refused(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text(
        "size = [10.0, 10.0]\ndepot = [1.0, 1.0]\n[[aoi]]\ncentre = [5.0, 5.0]\nradius = 2.0\n"
        "value = -1.0\n"
    )
    with pytest.raises(ConfigError, match=r"scenario .*bad.toml.*AoI values .* got -1"):
        TangiblePSOModel(seed=1, scenario=str(path))
