"""A robot's lifecycle: failing and removal each happen in one place and every part that keeps
something per robot (physics, comm network, energy ledger, faults) forgets the robot alike,
told through ``model.lifecycle``; the model's robots are exactly Mesa's ``model.agents``."""

from collections import Counter

import pytest

from abm.errors import ConfigError
from abm.faults import FAILED
from abm.lifecycle import EVENTS, Lifecycle
from abm.record import Recorder
from tests.tiny_model import TinyModel, Walker


class FallibleTinyModel(TinyModel):
    """The tiny model whose walkers can fail (so a failure and a removal can be compared)."""

    FAULTS = frozenset({"robot"})


def _resting_and_walking(model: TinyModel) -> tuple[list[Walker], list[Walker]]:
    walkers = list(model.agents_by_type[Walker])
    return (
        [w for w in walkers if w.state == "resting"],
        [w for w in walkers if w.state == "walking"],
    )


def _run_until_two_of_each(model: TinyModel) -> None:
    while model.running:
        model.run(until=model.time + 5.0)
        resting, walking = _resting_and_walking(model)
        if len(resting) >= 2 and len(walking) >= 2:
            return
    pytest.fail("the tiny run never had two resting and two walking walkers")


@pytest.mark.parametrize("seed", [3, 11])
def test_a_removed_and_a_failed_robot_leave_the_air_the_network_and_the_ledger_alike(seed):
    model = FallibleTinyModel(
        seed=seed, walkers=12, rest_rate=0.1, launch_period=2.0, fault_times=(199.0,)
    )
    _run_until_two_of_each(model)
    resting, walking = _resting_and_walking(model)
    gone = {"removed": [resting[0], walking[0]], "failed": [resting[1], walking[1]]}
    for robot in gone["removed"]:
        robot.remove()
    for robot in gone["failed"]:
        assert model.faults.fail(robot, "test")
    energy = {r.unique_id: model.ledger.energy(r.unique_id) for rs in gone.values() for r in rs}
    model.run(until=model.time + 20.0)
    for robot in (r for rs in gone.values() for r in rs):
        rid = robot.unique_id
        assert rid not in model.comms.graph  # removal used to leave a robot in the network
        assert rid not in model.physics.ids
        assert model.ledger.energy(rid) == pytest.approx(energy[rid])
        assert not robot.process.is_alive
    assert all(r not in model.agents for r in gone["removed"])
    assert all(r in model.agents and r.state == FAILED for r in gone["failed"])


def test_the_counts_are_the_agents_states_at_every_change():
    """Every state change, failure and removal leaves the recorder's counts equal to the
    states of ``model.agents``, and the space holds exactly those agents."""
    model = FallibleTinyModel(seed=5, walkers=10, launch_period=1.0, fault_rate=0.02)
    mismatches = []

    def check(*_args) -> None:
        counted = {s: n for s, n in model.recorder.counts.items() if n}
        if counted != Counter(a.state for a in model.agents):
            mismatches.append(model.time)
        if set(model.space.active_agents) != set(model.agents):
            mismatches.append(model.time)

    for event in ("state", "removed"):
        model.lifecycle.subscribe(event, check)
    model.run(until=30.0)
    for walker in list(model.agents_by_type[Walker])[:2]:
        if not walker.failed:
            walker.remove()
            check()
    model.run()
    assert model.faults.failed, "no walker failed: the run does not exercise failures"
    assert not mismatches


def test_subscribers_hear_events_in_order_and_an_unknown_event_is_refused():
    lifecycle = Lifecycle()
    heard = []
    lifecycle.subscribe("state", lambda robot, old, new: heard.append(("a", old, new)))
    lifecycle.subscribe("state", lambda robot, old, new: heard.append(("b", old, new)))
    lifecycle.publish("state", object(), None, "walking")
    assert heard == [("a", None, "walking"), ("b", None, "walking")]
    with pytest.raises(ConfigError, match="unknown lifecycle event 'landed'.*failed"):
        lifecycle.subscribe("landed", print)
    assert EVENTS == ("state", "failed", "removed")


def test_without_robot_or_sensor_faults_nothing_follows_the_robots_state():
    """A model whose robots cannot fail pays nothing per state change for faults."""
    plain = TinyModel(seed=1)
    fallible = FallibleTinyModel(seed=1, fault_rate=0.01)
    assert plain.lifecycle.subscribers("state") == ()
    assert fallible.lifecycle.subscribers("state") == (fallible.faults.state_changed,)


def test_a_robot_is_found_by_its_id_until_it_is_removed():
    model = TinyModel(seed=2, walkers=6, launch_period=1.0)
    model.run(until=8.0)
    walkers = list(model.agents_by_type[Walker])
    assert all(model.robot(w.unique_id) is w for w in walkers)
    walkers[1].remove()
    with pytest.raises(KeyError, match=f"no robot {walkers[1].unique_id}"):
        model.robot(walkers[1].unique_id)
    assert all(model.robot(w.unique_id) is w for w in walkers if w is not walkers[1])
    with pytest.raises(KeyError):
        model.robot(10_000)


def test_robots_of_a_role_is_an_empty_agentset_before_the_first_is_made():
    model = TinyModel(seed=2, walkers=3, launch_period=5.0)
    assert len(model.robots_of(Walker)) == 0
    model.run(until=11.0)
    assert list(model.robots_of(Walker)) == list(model.agents_by_type[Walker])
    assert len(model.robots_of(Walker)) == 2


@pytest.mark.parametrize("capped", [False, True])
def test_robots_entered_together_log_count_and_publish_as_one_by_one(capped):
    """``Robot.enter_all`` (a flock made at once) leaves the same event rows, counts and
    lifecycle events as ``set_state`` on each robot in turn, also for a capped event kind."""

    def made(together):
        model = TinyModel(seed=1, walkers=3)
        if capped:
            model.recorder = Recorder(model.env, model.STATES, row_limits={"state": 2})
        heard = []
        model.lifecycle.subscribe(
            "state", lambda r, old, new: heard.append((r.unique_id, old, new))
        )
        walkers = [Walker(model, model.centre, None) for _ in range(4)]
        if together:
            Walker.enter_all(walkers, "resting")
        else:
            for walker in walkers:
                walker.set_state("resting")
        return model, heard, walkers

    (one, heard_one, _), (all_, heard_all, walkers) = made(False), made(True)
    assert heard_all == heard_one and len(heard_all) == 4
    assert all_.events().equals(one.events()) and len(all_.events()) == (3 if capped else 4)
    assert all_.state_counts().equals(one.state_counts())
    assert all_.recorder.counts == {"walking": 0, "resting": 4}
    assert all_.recorder.dropped == one.recorder.dropped
    with pytest.raises(ValueError, match="already has a state"):
        Walker.enter_all(walkers, "walking")
    with pytest.raises(ValueError, match="unknown state 'flying'"):
        Walker.enter_all([Walker(all_, all_.centre, None)], "flying")


def test_position_samples_follow_joins_state_changes_and_removals():
    """The trace reuses the ids and states of the space's rows between samples: a robot that
    joins, changes state or leaves shows in the very next sample."""
    model = TinyModel(seed=2, walkers=6, launch_period=0.7, rest_rate=1e-6, trace_interval=1.0)
    model.run(until=3.2)
    walkers = list(model.agents_by_type[Walker])
    walkers[0].set_state("resting")
    walkers[1].remove()
    model.run(until=4.1)
    samples = model.positions().groupby("time")
    last = samples.get_group(4.0).set_index("robot")["state"]
    assert last[walkers[0].unique_id] == "resting"
    assert walkers[1].unique_id not in last.index
    assert sorted(last.index) == sorted(a.unique_id for a in model.agents)
    before = samples.get_group(3.0).set_index("robot")["state"]
    assert len(before) == len(last) == 4 and (before == "walking").all()
    assert model.recorder.moves == model.events()["event"].isin(["state", "removed"]).sum()
