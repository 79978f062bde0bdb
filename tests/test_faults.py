"""The fault injector (abm.faults) on a model defined only in the tests: failures stop a robot
for good, keep the counts and the energy ledger exact, are seeded, and bad keywords are named."""

import networkx as nx
import numpy as np
import pytest
import simpy
from hypothesis import given, settings
from hypothesis import strategies as st

from abm.arena import Arena
from abm.comms import CommNetwork, GradientFlood
from abm.errors import ConfigError
from abm.faults import FAILED
from abm.robot import RobotFailedError
from tests.tiny_model import TinyModel


class FaultyTiny(TinyModel):
    """The tiny walkers, declaring every fault kind (they have no structures to repair)."""

    FAULTS = frozenset({"robot", "link", "sensor"})


def _run(**kw):
    model = FaultyTiny(seed=kw.pop("seed", 3), trace_interval=None, **kw)
    return model.run()


def test_a_robot_failed_in_flight_has_no_further_events_and_draws_no_power():
    model = FaultyTiny(
        seed=5, trace_interval=None, walkers=6, rest_rate=0.001, fault_times=(40.0,),
        fault_states=("walking",),
    )  # fmt: skip
    model.run(until=40.0 - 1e-9)
    flying = {a.unique_id: model.ledger.energy(a.unique_id) for a in model.agents}
    model.run(until=40.0 + 1e-9)
    flyer = next(a for a in model.agents if a.failed)
    assert flyer.unique_id in flying  # it was in the air
    energy = flying[flyer.unique_id] + 1e-9 * 10.0
    assert not model.faults.fail(flyer, "again")  # nothing is done twice
    model.run(until=120.0)
    events = model.events()
    mine = events[events.robot == flyer.unique_id]
    fault = mine.index[mine.event == "fault"][0]
    after = mine.loc[fault:]
    assert list(after.event) == ["fault", "state"] and after.iloc[-1].state == FAILED
    assert (after.time == 40.0).all()
    assert flyer.unique_id not in model.physics.ids
    assert model.ledger.energy(flyer.unique_id) == pytest.approx(energy, abs=1e-6)
    assert flyer.failure.state == "walking" and flyer.failure.cause == "scheduled"
    assert not flyer.process.is_alive
    with pytest.raises(RobotFailedError, match="cannot enter state 'walking'"):
        flyer.set_state("walking")


@settings(max_examples=12, deadline=None)
@given(
    seed=st.integers(0, 10_000),
    rate=st.floats(0.002, 0.05),
    shape=st.sampled_from([0.7, 1.0, 2.5]),
)
def test_counts_energy_and_coverage_stay_exact_with_faults_on(seed, rate, shape):
    model = _run(seed=seed, fault_rate=rate, fault_shape=shape, walkers=8)
    counts = model.state_counts()
    n_robots = len(model.agents)
    born = counts[list(model.STATES)].sum(axis=1)
    assert born.is_monotonic_increasing and born.iloc[-1] == n_robots  # conserved
    assert counts[FAILED].iloc[-1] == len(model.faults.failures) == model.summary()["failed"]
    # every robot's energy is its power integrated up to its failure (or the end), exactly
    end = model.env.now
    for robot in model.agents:
        stop = robot.failure.time if robot.failed else end
        segments = [(t, m) for t, r, m in model.ledger.timeline if r == robot.unique_id]
        times = [t for t, _ in segments] + [stop]
        expected = sum(
            {"walk": 10.0, "rest": 1.0}[m] * (t1 - t0)
            for (_t, m), t0, t1 in zip(segments, times, times[1:], strict=False)
        )
        assert model.ledger.energy(robot.unique_id) == pytest.approx(expected, abs=1e-9)
    # coverage only grows, and is what the raster holds
    assert model.summary()["coverage_area"] == pytest.approx(100 * model.coverage.fraction)


def test_same_seed_with_faults_gives_the_same_event_log():
    kw = dict(fault_rate=0.02, fault_shape=1.5, link_outage_rate=0.5, sensor_fault_rate=0.01)
    a, b = _run(seed=11, **kw), _run(seed=11, **kw)
    assert len(a.faults.failures) > 0
    assert a.events().equals(b.events())
    assert not a.events().equals(_run(seed=12, **kw).events())


def test_faults_leave_the_models_own_random_stream_alone_until_the_first_fault():
    plain = _run(seed=4)
    faulty = _run(seed=4, fault_times=(20.0,))
    first = faulty.faults.failures[faulty.faults.failed[0]].time
    assert first == 20.0 and not plain.events().equals(faulty.events())
    before = plain.events().query("time < @first").reset_index(drop=True)
    after = faulty.events().query("time < @first").reset_index(drop=True)[before.columns]
    assert len(before) > 3 and after.equals(before)


def test_hazard_counts_only_time_spent_in_the_chosen_states():
    model = _run(seed=2, fault_rate=0.05, fault_states=("resting",), walkers=10, time_limit=400.0)
    assert model.faults.failures
    assert {f.state for f in model.faults.failures.values()} == {"resting"}
    events = model.events()
    for rid, failure in model.faults.failures.items():
        rested = events[(events.robot == rid) & (events.state == "resting")]
        assert failure.time >= rested.time.min()  # no exposure before it rested


def test_exponential_lifetimes_have_mean_one_over_the_rate():
    # 200 walkers, failing in any state: the mean time from a robot's first state to its
    # failure is 1/lambda
    model = _run(seed=8, fault_rate=0.01, walkers=200, launch_period=0.01, time_limit=3000.0)
    events = model.events()
    first = events[events.event == "state"].groupby("robot").time.min()
    failed = events[events.event == "fault"].set_index("robot").time
    life = failed - first.loc[failed.index]
    assert len(life) > 150
    assert life.mean() == pytest.approx(100.0, rel=0.2)


def test_scheduled_faults_fail_one_eligible_robot_at_each_time():
    model = _run(seed=6, fault_times=(30.0, 60.0, 60.0), walkers=6)
    faults = model.events().query("event == 'fault'")
    assert list(faults.time) == [30.0, 60.0, 60.0]
    assert faults.robot.nunique() == 3 and set(faults.cause) == {"scheduled"}


@pytest.mark.parametrize(
    ("kw", "match"),
    [
        ({"fault_rate": -0.1}, r"fault_rate must be in \[0"),
        ({"fault_rate": float("inf")}, "fault_rate must be a finite number"),
        ({"fault_rate": float("nan")}, "fault_rate must be a number"),
        ({"fault_shape": 0.0}, r"fault_shape must be in \(0"),
        ({"fault_times": (-5.0,)}, "fault_times must hold finite times >= 0"),
        ({"fault_times": ("soon",)}, "fault_times must hold numbers"),
        ({"fault_states": ("walking", "walking")}, "fault_states must name distinct states"),
        ({"fault_rate": 0.1, "fault_states": ("flying",)}, "fault_states names 'flying'"),
        ({"link_outage_duration": 0.0}, r"link_outage_duration must be in \(0"),
        ({"loss_burst_loss": 1.5}, r"loss_burst_loss must be in \(0, 1\]"),
        ({"sensor_fault_kind": "melted"}, "sensor_fault_kind must be one of 'stuck', 'noisy'"),
    ],
)
def test_bad_fault_keywords_raise_config_errors_naming_them(kw, match):
    with pytest.raises(ConfigError, match=match):
        FaultyTiny(seed=1, **kw)


def test_a_model_refuses_faults_it_does_not_handle():
    with pytest.raises(ConfigError, match=r"link_outage_rate=0.1: TinyModel does not handle link"):
        TinyModel(seed=1, link_outage_rate=0.1)
    with pytest.raises(ConfigError, match=r"fault_rate=0.1: TinyModel does not handle robot"):
        TinyModel(seed=1, fault_rate=0.1)


def test_faults_off_add_no_failed_state_and_no_summary_key():
    model = TinyModel(seed=1, trace_interval=None).run()
    assert FAILED not in model.STATES and "failed" not in model.summary()
    assert FAILED in FaultyTiny(seed=1, fault_rate=0.01).STATES


def _network(n: int = 4):
    env = simpy.Environment()
    free = np.ones((3, 12), dtype=bool)
    net = CommNetwork(env, Arena(free, 1.0), np.random.default_rng(0), 1.5, latency=0.5)
    for i in range(n):
        net.add(i, np.array([1.0 + i, 1.5]))
    return env, net


def test_a_link_outage_drops_messages_in_flight_and_blocks_relinking_until_it_ends():
    env, net = _network()
    got, lost = [], []
    net.send(0, 1, "a", lambda s, d, p: got.append(p), lambda s, d, p: lost.append(p))
    net.block(0, 1)
    assert not net.graph.has_edge(0, 1)
    net.move(1, np.array([2.0, 1.6]))  # in range, but the outage holds
    assert not net.graph.has_edge(0, 1)
    env.run(until=1.0)
    assert got == [] and lost == ["a"]
    assert net.unblock(0, 1) and net.graph.has_edge(0, 1)


def test_a_loss_burst_drops_messages_and_floods_heal_after_it():
    env, net = _network(6)
    flood = GradientFlood(net, "forwards", 1, +1)
    net.start_burst(1.0, np.random.default_rng(1))
    flood.set_sources([0])
    env.run(until=5.0)
    assert net.messages_lost > 0 and flood.value(5) == 0  # the wave was lost
    net.end_burst()
    env.run(until=20.0)
    bfs = nx.single_source_shortest_path_length(net.graph, 0)
    assert {n: flood.value(n) for n in net.graph} == {n: d + 1 for n, d in bfs.items()}


def test_link_faults_are_injected_and_logged_in_a_run():
    model = _run(seed=9, link_outage_rate=1.0, link_outage_duration=4.0, loss_burst_rate=0.05)
    events = model.events()
    assert {"loss_burst", "loss_burst_end", "link_down", "link_up"} <= set(events.event)
    down = events.query("event == 'link_down'")
    for _i, up in events.query("event == 'link_up'").iterrows():
        pair = down[(down.robot == up.robot) & (down.other == up.other)]
        assert (up.time - pair.time).round(9).isin([4.0]).any()  # up after its outage only


@pytest.mark.parametrize("kind", ["stuck", "noisy"])
def test_faulty_sensors_report_stuck_or_noisy_readings(kind):
    model = FaultyTiny(seed=2, sensor_fault_rate=0.05, sensor_fault_kind=kind, trace_interval=None)
    model.run(until=150.0)
    ids = np.array([a.unique_id for a in model.agents])
    broken = np.array([model.faults.sensor_broken(i) for i in ids])
    assert broken.any() and not broken.all()
    first = model.faults.sensed("range", ids, np.arange(len(ids), dtype=float)[:, None])
    second = model.faults.sensed("range", ids, 10.0 + np.arange(len(ids), dtype=float)[:, None])
    healthy = ~broken
    assert np.array_equal(second[healthy, 0], 10.0 + np.arange(len(ids))[healthy])
    if kind == "stuck":
        assert np.array_equal(second[broken], first[broken])
    else:
        assert not np.allclose(second[broken, 0], 10.0 + np.arange(len(ids))[broken])
    assert set(model.events().query("event == 'sensor_fault'").robot) == set(ids[broken])


@settings(max_examples=80, deadline=None)
@given(
    name=st.sampled_from(["link_outage_rate", "loss_burst_rate"]),
    rate=st.floats(0.0, 1e15, allow_nan=False),
    time_limit=st.floats(1e-3, 1e7, allow_nan=False),
)
def test_a_network_wide_fault_rate_may_ask_for_at_most_a_million_events(name, rate, time_limit):
    from abm.params import MAX_FAULT_EVENTS

    keywords = {name: rate, "time_limit": time_limit}
    if rate * time_limit <= MAX_FAULT_EVENTS:
        assert getattr(FaultyTiny.make_params(**keywords), name) == rate
    else:
        with pytest.raises(ConfigError, match=f"^{name}={rate!r} per s asks for .* events in"):
            FaultyTiny.make_params(**keywords)


def test_an_outage_storm_is_refused_before_it_starts_naming_the_keyword():
    """``link_outage_rate=1e12`` over 30 s ran for over 20 s, 3e13 outages asked for; per-robot
    hazards need no such rule (each robot fails once at most)."""
    from models.beacon_explorer import BeaconExplorerModel

    with pytest.raises(ConfigError, match=r"link_outage_rate=1000000000000.0 .* <= 33333.3 here"):
        BeaconExplorerModel(seed=1, link_outage_rate=1e12, time_limit=30.0)
    assert FaultyTiny(seed=1, fault_rate=1e12, time_limit=30.0).run().time <= 30.0


def test_a_scheduled_fault_that_finds_no_robot_is_counted_in_the_summary():
    # a fault time with no robot in fault_states left nothing in the summary but a log row
    from models.hierarchy import HierarchyModel

    quick = {**HierarchyModel.QUICK, "time_limit": 400.0, "trace_interval": None}
    model = HierarchyModel(seed=1, fault_times=(100.0,), fault_states=("worker_idle",), **quick)
    summary = model.run().summary()
    skipped = model.events().query("event == 'fault_skipped'").shape[0]
    assert summary["faults_skipped"] == skipped == 1  # no worker idle at 100 s (seed 1)
    assert "faults_skipped" not in HierarchyModel(seed=1, **quick).run().summary()
