"""Figs. 10-11 of Saska et al. (2016): the state-space search (``method="state_space"``, the
same PSO whose particles jump to their proposals) against tangible PSO, each solution flown by
the same planner; what an unchecked plan breaks (:mod:`models.tangible_pso.flight`) and
claims C6 / C6b judged on the runs.
"""

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from abm.errors import ConfigError
from models.tangible_pso import TangiblePSOModel
from models.tangible_pso.claims import TESTS
from models.tangible_pso.flight import fly_open_loop
from models.tangible_pso.model import FLIGHT_READINGS

#: A quick Fig. 10 case: Table 1's map, 3 MAVs, k = 1, a small population, the solution flown.
QUICK = {"particles": 10, "iterations": 12, "neighbours": 1, "deploy": True}


def _summaries(method: str, seeds) -> pd.DataFrame:
    return pd.DataFrame(
        [TangiblePSOModel(method=method, seed=s, **QUICK).run().summary() for s in seeds]
    )


def test_an_unknown_method_is_refused_naming_the_accepted_ones():
    with pytest.raises(ConfigError, match=r"method.*'tangible'.*'state_space'"):
        TangiblePSOModel(method="statespace")


def test_the_state_space_plan_breaks_the_constraint_where_tangible_pso_keeps_it():
    """The paper's direction on a small quick case: the state-space search's solution, flown
    from the depot past the zone, loses a MAV's neighbour on the way and, under the check,
    never reaches its formation; tangible PSO's plan is flown to its end.
    """
    seeds = range(5)
    state = _summaries("state_space", seeds)
    tangible = _summaries("tangible", seeds)
    assert state["plan_unlocalised"].mean() >= 0.6
    assert state["deploy_deadlock"].mean() >= 0.6
    assert state["reach_time"].isna().mean() >= 0.6
    assert not tangible["plan_unlocalised"].any() and not tangible["deploy_deadlock"].any()
    assert tangible["reach_time"].notna().all()
    # stuck short of its plan, the state-space swarm sees less than it planned to
    stuck = state[state["deploy_deadlock"]]
    assert (stuck["deployed_cost"] >= stuck["best_cost"]).all()
    assert (stuck["deployed_cost"] > stuck["best_cost"]).any()


def test_state_space_particles_jump_and_the_search_takes_no_flight_time():
    m = TangiblePSOModel(method="state_space", particles=8, iterations=10, seed=3).run()
    assert m.time == 0.0 and m.plans == []
    summary = m.summary()
    assert summary["method"] == "state_space"
    assert not set(FLIGHT_READINGS) & set(summary)  # no virtual flight to read
    # a jump lands on the (shifted) proposal: eq. 6 gives back exactly the move made
    moves = np.diff(np.array(m.history), axis=0)
    assert np.abs(moves).max() > 1.0


def test_the_state_space_plan_is_one_leg_from_the_start_to_b_g():
    m = TangiblePSOModel(method="state_space", seed=2, **QUICK).run()
    (end, points, count, reach), *rest = m.plan()
    assert not rest and reach is None
    assert np.allclose(points[:, 0], m.history[0][m.g])
    # the ends are b_g's positions, maybe swapped between MAVs by goal swapping
    assert sorted(map(tuple, np.round(end, 9))) == sorted(map(tuple, np.round(m.best, 9)))
    assert m.summary()["transitions"] == 1


@settings(max_examples=4, deadline=None)
@given(seed=st.integers(0, 10_000), k=st.sampled_from([1, 2]))
def test_tangible_pso_plan_flown_unchecked_breaks_nothing(seed, k):
    """Tangible PSO's plan is made of checked states, tick for tick: flown to its end with
    nothing to stop it, no MAV loses its neighbours, comes within d_min or enters a zone.
    """
    m = TangiblePSOModel(particles=6, iterations=8, neighbours=k, deploy=True, seed=seed).run()
    s = m.summary()
    assert not s["plan_unlocalised"] and not s["plan_collision"]
    assert s["plan_unlocalised_time"] == 0.0 and not s["deploy_deadlock"]


def test_a_vertical_move_the_check_never_made_is_not_flown_unchecked():
    """A proposal straight up or down has a path with no planar length, which holds only the
    goal's altitude: the check keeps the MAV where it was (seed 9117661762786273889 of the
    Figs. 10-11 sweep does that at its 5th transition), and so must the unchecked flight,
    else it reports a localisation the plan never lost.
    """
    m = TangiblePSOModel(neighbours=1, deploy=True, seed=9117661762786273889).run()
    _goal, points, count, reach = m.plan()[4]
    still = np.linalg.norm(np.diff(points, axis=1), axis=(1, 2)) == 0
    assert still.any() and (points[still, 0, 2] != m.history[4][m.g][still, 2]).any()
    assert not m.summary()["plan_unlocalised"]


def test_an_unchecked_leg_counts_the_ticks_two_mavs_are_out_of_range():
    """Two MAVs fly apart along x from 2 m to 12 m in 10 ticks of 1 m (the longest path 10 m,
    the other still): out of 5 m range from the 4th tick on (7 of 11 states, 7 s at 1 m/s).
    """
    points = np.array([[[0.0, 0, 5], [0.0, 0, 5]], [[2.0, 0, 5], [12.0, 0, 5]]])
    count = np.array([1, 2])
    start = points[:, 0]
    loop = fly_open_loop([(start, points, count, None)], [], 1, 1.2, 5.0, speed=1.0, dt=1.0)
    assert (loop.ticks, loop.unlocalised, loop.collided) == (11, 7, 0)
    assert loop.unlocalised_time == pytest.approx(7.0)
    # flown only 2 m of its path (a reach), the pair stays in range
    short = fly_open_loop([(start, points, count, np.array([0, 2.0]))], [], 1, 1.2, 5, 1, 1)
    assert short.unlocalised == 0
    # a zone across the path is a collision, and k = 0 needs no neighbour
    zone = np.array([[6.0, -1], [8.0, -1], [8.0, 1], [6.0, 1]])
    hit = fly_open_loop([(start, points, count, None)], [zone], 0, 1.2, 5.0, 1.0, 1.0)
    assert hit.unlocalised == 0 and hit.collided == 1  # only the state at x = 7 is inside


def _rows(state_lost: int, state_stuck: int, n: int = 20) -> pd.DataFrame:
    rows = []
    for method, lost, stuck in (("tangible", 0, 0), ("state_space", state_lost, state_stuck)):
        for i in range(n):
            rows.append({"method": method, "plan_unlocalised": i < lost,
                         "deploy_deadlock": i < stuck, "best_cost": 1.0 + i % 3,
                         "deployed_cost_ratio": 0.5, "reach_time": np.nan if i < stuck else 60.0,
                         "plan_collision": False})  # fmt: skip
    return pd.DataFrame(rows)


@pytest.mark.parametrize(("lost", "stuck", "holds"), [(18, 17, True), (1, 0, None)])
def test_c6_is_judged_by_welch_intervals_of_the_two_shares(lost, stuck, holds):
    verdict = TESTS["C6"](_rows(lost, stuck), None)
    assert verdict.holds is holds and "Welch 95 % interval" in verdict.rule
    assert verdict.runs == 40


def test_c6_needs_both_methods_flown():
    rows = _rows(18, 17)
    assert TESTS["C6"](rows[rows["method"] == "tangible"], None) is None
    assert TESTS["C6"](rows.drop(columns="plan_unlocalised"), None) is None
    assert TESTS["C6b"](rows, None).holds is None  # equal planned costs: undecided
