"""Faults in beacon/explorer: a failed beacon leaves the network, the hop counts heal to BFS
distances on the surviving lattice, the swarm refills the hole (``repair``), runs with faults
are seeded, and link outages re-draw the lattice."""

import networkx as nx
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from models.beacon_explorer import BeaconExplorerModel
from tests.test_beacon_explorer import run_until_quiescent


def assert_hop_counts_are_bfs_on_the_surviving_lattice(model):
    """Forwards: 1 + BFS distance from the base, 0 (the floor: soft state expired) where the
    lattice no longer reaches the base; reverse: 127 - distance to the nearest frontier."""
    beacons = model.beacons
    graph = beacons.lattice
    assert all(model.comms.graph.has_edge(a, b) for a, b in graph.edges)
    dist = nx.single_source_shortest_path_length(graph, model.base.unique_id)
    sources = [b for b in beacons.reverse.sources if b in graph]
    rdist = nx.multi_source_dijkstra_path_length(graph, sources) if sources else {}
    for node in graph:
        assert beacons.forwards.value(node) == (1 + dist[node] if node in dist else 0)
        assert beacons.reverse.value(node) == (max(0, 127 - rdist[node]) if node in rdist else 0)


def _beacon_fault_run(seed: int, when: float, **kw) -> BeaconExplorerModel:
    return BeaconExplorerModel(
        world="corridor",
        seed=seed,
        fault_times=(when,),
        fault_states=("beacon",),
        trace_interval=None,
        **kw,
    )


@settings(max_examples=6, deadline=None)
@given(st.integers(0, 1000), st.floats(40.0, 160.0))
def test_a_failed_beacon_has_no_further_events_and_hop_counts_heal_to_bfs(seed, when):
    model = _beacon_fault_run(seed, when)
    run_until_quiescent(model, when + 5.0)
    failed = model.faults.failed
    if not failed:  # no beacon but the (exempt) base at that time
        assert model.events().query("event == 'fault_skipped'").shape[0] == 1
        assert model.summary()["faults_skipped"] == 1  # said in the summary too, not only logged
        return
    assert model.summary()["faults_skipped"] == 0
    (rid,) = failed
    (robot,) = model.agents.select(lambda r: r.unique_id == rid)
    assert robot.failure.state == "beacon"
    assert rid not in model.beacons.beacons and rid not in model.comms.graph
    assert rid not in model.beacons.lattice and rid not in model.beacons.forwards.values
    events = model.events()
    mine = events[events.robot == rid]
    fault_row = mine.index[mine.event == "fault"][0]
    assert list(mine.loc[fault_row:].event) == ["fault", "state"]
    if model.running:  # a finished run stops the clock before soft states expire
        assert_hop_counts_are_bfs_on_the_surviving_lattice(model)


def test_a_failed_beacon_in_flight_or_on_the_ground_never_acts_again():
    model = BeaconExplorerModel(
        world="corridor", seed=4, fault_rate=1 / 200, trace_interval=None, time_limit=600
    ).run()
    events = model.events()
    faults = events.query("event == 'fault'")
    assert {"explorer", "beacon", "ground"} <= set(faults.state)
    for _i, fault in faults.iterrows():
        later = events[(events.robot == fault.robot) & (events.time >= fault.time)]
        assert list(later.event) == ["fault", "state"]
    assert model.base.unique_id not in model.faults.failures  # the base station is exempt
    counts = model.state_counts()
    assert (counts[list(model.STATES)].sum(axis=1) == model.n_robots + 1).all()
    assert counts.failed.iloc[-1] == model.summary()["n_failed"] == len(faults)


def test_same_seed_with_faults_gives_the_same_event_log():
    kw = dict(world="corridor", fault_rate=1 / 300, link_outage_rate=0.05, trace_interval=None)
    a = BeaconExplorerModel(seed=8, **kw).run(until=300.0)
    b = BeaconExplorerModel(seed=8, **kw).run(until=300.0)
    assert len(a.faults.failures) > 0 and "link_down" in set(a.events().event)
    assert a.events().equals(b.events())


@pytest.mark.parametrize("repair", [True, False])
def test_repair_readvertises_the_hole_and_without_it_the_area_counts_as_searched(repair):
    model = _beacon_fault_run(2, 120.0, repair=repair)
    model.run(until=120.0 - 1e-6)
    network = model.beacons
    seen = {rid: dict(b.neighbour_dirs) for rid, b in network.beacons.items()}
    model.run(until=120.0 + 1e-6)
    (victim,) = model.faults.failed
    holes = [(network.beacons[o], d) for o, dirs in seen.items() for d, n in dirs.items()
             if n == victim and o in network.beacons]  # fmt: skip
    assert holes
    for other, direction in holes:
        assert (direction in other.searched) is not repair
    model.run(until=model.env.now + 30.0)
    (robot,) = model.agents.select(lambda r: r.unique_id == victim)
    spot = robot.position
    _ids, pos, vectors, _empty = network.signals()
    refilled = (np.hypot(*(pos - spot).T) < 1.0).any()
    advertised = (np.hypot(*(pos + vectors - spot).T) < 1.0).any()
    if repair:  # a beacon advertises the hole, or one fills it again
        assert refilled or advertised


def test_a_link_outage_redraws_the_lattice_and_the_counts_still_settle():
    model = BeaconExplorerModel(
        world="corridor", seed=5, link_outage_rate=0.2, link_outage_duration=20.0,
        trace_interval=None,
    )  # fmt: skip
    run_until_quiescent(model, 150.0)
    downs = model.events().query("event == 'link_down'")
    assert len(downs) > 10
    for pair in model.comms._blocked:
        a, b = tuple(pair)
        assert not model.beacons.lattice.has_edge(a, b)
    if model.running:
        assert_hop_counts_are_bfs_on_the_surviving_lattice(model)


@pytest.mark.parametrize("kind", ["stuck", "noisy"])
def test_faulty_distance_sensors_change_what_beacons_sense(kind):
    """Every robot's sensors break within seconds, before it attaches: a stuck sensor gives a
    beacon the wall labels of the first reading it took (whatever it reads since); noisy ones
    (0.3 m sd) add noise to every reading; either changes the run."""
    kw = dict(world="corridor", seed=6, trace_interval=None, time_limit=400.0)
    plain = BeaconExplorerModel(**kw).run()
    faulty = BeaconExplorerModel(
        **kw, sensor_fault_rate=1.0, sensor_fault_kind=kind, sensor_fault_noise=0.3
    ).run()
    broken = set(faulty.events().query("event == 'sensor_fault'").robot.astype(int))
    assert faulty.base.unique_id not in broken and len(broken) == faulty.n_robots
    beacons = [b for rid, b in faulty.beacons.beacons.items() if rid in broken]
    assert len(beacons) >= 3
    threshold = faulty.params.obstacle_threshold
    for beacon in beacons:
        now = faulty.faults.sensed("walls", [beacon.robot], np.zeros((1, 4)))[0]
        labels = tuple(bool(r < threshold) for r in now)
        # stuck: the labels are those of the frozen reading; noisy: a fresh noisy reading of
        # nothing (0 m everywhere) is no longer what it read
        assert (beacon.walls == labels) if kind == "stuck" else not np.array_equal(now, 0.0)
    assert not faulty.events().equals(plain.events())
