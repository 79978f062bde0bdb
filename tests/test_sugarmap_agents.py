"""SugarMap's robots are its two roles, Anchor and Explorer, held by Mesa's AgentSet alone:
every robot of a run is in ``model.agents_by_type`` under its role in every state it reaches
(failed ones included), each knows its row in the model's arrays, and the model keeps no list
of robots beside them."""

from collections import Counter

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from abm.robot import Robot
from models.sugarmap import SugarMapModel
from models.sugarmap.agents import Anchor, Explorer

#: The model's quick set-up, with one scheduled anchor failure after deployment and random
#: failures of anchors and explorers, so the robots pass through every state.
FAULTY = {
    **SugarMapModel.QUICK,
    "horizon": 200.0,
    "fault_rate": 4e-3,
    "fault_states": ("dispersing", "anchor", "exploring"),
}
#: The times (s) at which the robots are compared with the recorder's counts.
TIMES = (0.0, 3.0, 20.0, 45.0, 80.0, 150.0, 400.0)

ANCHOR_STATES = {"dispersing", "anchor", "failed"}
EXPLORER_STATES = {"waiting", "exploring", "stopped", "failed"}


def _check_robots(model: SugarMapModel) -> None:
    """The AgentSet holds the roles with the right counts and states, as the recorder counts
    them, and each robot's row names its place in the model's arrays.
    """
    p = model.params
    by_type = model.agents_by_type
    assert set(by_type) == {Anchor, Explorer}
    anchors, explorers = by_type[Anchor], by_type[Explorer]
    assert len(anchors) == p.anchors and len(explorers) == p.n_explorers
    assert [r.row for r in anchors] == list(range(p.anchors))
    assert [r.row for r in explorers] == list(range(p.n_explorers))
    assert {r.state for r in anchors} <= ANCHOR_STATES
    assert {r.state for r in explorers} <= EXPLORER_STATES
    states = Counter(r.state for r in model.agents)
    assert {s: states[s] for s in model.STATES} == model.recorder.counts
    last = model.state_counts().iloc[-1]
    assert {s: int(last[s]) for s in model.STATES} == model.recorder.counts
    for anchor in anchors:
        assert model.anchor_ids[anchor.row] == anchor.unique_id
        np.testing.assert_array_equal(model.anchor_pos[anchor.row], anchor.position)
        assert model.flying[anchor.row] == (anchor.state == "dispersing")
    if model.t_deploy is None:  # still dispersing
        return
    for anchor in anchors:
        np.testing.assert_array_equal(model.rtof.anchors[anchor.row], anchor.position)
    for explorer in explorers:
        assert model.explorer_ids[explorer.row] == explorer.unique_id
        np.testing.assert_array_equal(model.pos[explorer.row], explorer.position)
        assert model.active[explorer.row] == (explorer.state == "exploring")


def _holds_robot(value: object, depth: int = 0) -> bool:
    """True if ``value`` is a robot or a container (nested up to three deep) holding one."""
    if isinstance(value, Robot):
        return True
    if isinstance(value, dict):
        value = [*value.keys(), *value.values()]
    elif isinstance(value, np.ndarray) and value.dtype == object:
        value = list(value.ravel())
    if depth < 3 and isinstance(value, list | tuple | set | frozenset):
        return any(_holds_robot(item, depth + 1) for item in value)
    return False


def _robot_containers(owner: object) -> list[str]:
    """The attributes of ``owner`` that are containers holding a robot (a single robot, e.g.
    a robot's model, is not a container).
    """
    return [
        name
        for name, value in vars(owner).items()
        if not isinstance(value, Robot) and _holds_robot(value)
    ]


def test_the_robots_are_anchors_and_explorers_in_the_agentset_at_every_time():
    model = SugarMapModel(seed=3, **FAULTY)
    for time in TIMES:
        model.run(until=time)
        _check_robots(model)
    states = Counter(r.state for r in model.agents)
    assert states["failed"] > 0 and states["anchor"] > 0  # the run reached those states


def test_the_model_and_its_robots_hold_no_list_of_robots():
    model = SugarMapModel(seed=3, **FAULTY).run()
    assert _robot_containers(model) == []
    for robot in model.agents:
        assert _robot_containers(robot) == []


def test_a_baseline_deploys_explorers_only():
    model = SugarMapModel(seed=2, algorithm="random_walk", arena="testbed", n_explorers=3)
    model.run(until=50.0)
    assert set(model.agents_by_type) == {Explorer}
    assert [r.row for r in model.agents_by_type[Explorer]] == [0, 1, 2]
    assert model.summary()["failed_anchors"] == 0


def test_the_explorers_match_counts_are_the_runs():
    model = SugarMapModel(seed=1, **SugarMapModel.QUICK, horizon=300.0).run()
    explorers = model.agents_by_type[Explorer]
    summary = model.summary()
    true = sum(r.true_matches for r in explorers)
    false = sum(r.false_matches for r in explorers)
    assert summary["matches"] == true + false > 0
    assert summary["false_match_rate"] == false / (true + false)
    samples = model.samples().iloc[-1]
    assert (samples["matches"], samples["false_matches"]) == (true + false, false)
    for explorer in explorers:  # one stored truth per signature the base station stored
        assert len(explorer.truth) == model.filter.n_stored[explorer.row]


def test_a_lone_anchor_lands_at_its_first_check():
    quick = {**SugarMapModel.QUICK, "n_anchors": 1, "dispersion_period": 7.0}
    model = SugarMapModel(seed=4, **quick).run(until=20.0)
    (anchor,) = model.agents_by_type[Anchor]
    events = model.events()
    land = events[(events["event"] == "land") & (events["robot"] == anchor.unique_id)]
    assert land["time"].tolist() == [7.0]
    assert anchor.state == "anchor" and not model.flying[anchor.row]


def test_an_anchor_failing_in_flight_leaves_its_row_where_it_fell():
    model = SugarMapModel(seed=7, **SugarMapModel.QUICK, fault_times=(10.0,))
    model.run(until=10.5)
    (fallen,) = [r for r in model.agents_by_type[Anchor] if r.failed]
    assert fallen.failure.state == "dispersing" and not model.flying[fallen.row]
    where = model.anchor_pos[fallen.row].copy()
    model.run(until=40.0)
    np.testing.assert_array_equal(model.anchor_pos[fallen.row], where)
    np.testing.assert_array_equal(fallen.position, where)


@settings(max_examples=6, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 2**16), until=st.sampled_from((30.0, 70.0, 120.0)))
def test_any_run_keeps_its_robots_in_the_agentset(seed, until):
    model = SugarMapModel(seed=seed, **FAULTY)
    model.run(until=until)
    _check_robots(model)
    assert _robot_containers(model) == []
