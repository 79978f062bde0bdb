"""Stigmergy's robots are UAV agents (models/stigmergy/agents.py) and Mesa's AgentSet is their
only index: what it holds matches the recorder's counts at every time, each live beacon knows
its row of the model's beacon array, and the behaviour (wander, then land) runs on the UAV."""

from collections import Counter

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from abm.pheromone import PheromoneField
from models.stigmergy import StigmergyModel
from models.stigmergy.agents import UAV

#: Times (s) at which a short run is stopped and looked at: before the first launch, while
#: the first wanders fly and land, and later with beacons failed.
TIMES = (0.0, 75.0, 150.0, 400.0, 700.0)


def _check_index(model: StigmergyModel) -> None:
    """The AgentSet holds exactly the swarm: UAVs only, one per launch in launch order, states
    counted as the recorder counts them; the live beacons' rows are the beacon array's rows."""
    uavs = model.agents_by_type[UAV]
    assert set(model.agents_by_type) == {UAV} and len(uavs) == len(model.agents)
    assert [r.launch_index for r in uavs] == list(range(len(uavs)))
    launches = model.events().query("event == 'launch'")
    assert [r.unique_id for r in uavs][1:] == launches.robot.astype(int).tolist()
    counted = {state: n for state, n in model.recorder.counts.items() if n}
    assert Counter(r.state for r in uavs) == counted
    last = model.state_counts().iloc[-1]
    assert all(last[state] == n for state, n in counted.items())
    beacons = sorted((r for r in uavs if r.state == "beacon"), key=lambda r: r.beacon_row)
    assert [r.beacon_row for r in beacons] == list(range(len(model.beacon_positions)))
    assert np.array_equal(model.beacon_positions, np.array([r.position for r in beacons]))
    assert all(r.beacon_row is None for r in uavs if r.state != "beacon")


def test_the_agent_set_is_the_swarm_at_every_time_of_a_run():
    model = StigmergyModel(seed=3, fault_rate=1 / 200, fault_states=("beacon",))
    for until in TIMES:
        model.run(until=until)
        _check_index(model)
    states = Counter(r.state for r in model.agents)
    assert states["failed"] >= 3 and states["beacon"] >= 2 and states["wander"] >= 1


@settings(max_examples=4, deadline=None)
@given(st.integers(0, 2**31), st.floats(1 / 400, 1 / 50))
def test_beacon_rows_follow_failures_in_any_order(seed, rate):
    """Failed beacons leave the beacon array wherever their row is; the later rows move up
    and their UAVs know it (wanders link to exactly the live beacons)."""
    model = StigmergyModel(seed=seed, fault_rate=rate, fault_states=("beacon",))
    for until in TIMES[1:]:
        model.run(until=until)
        _check_index(model)


def test_every_landing_is_the_uav_landing_itself(monkeypatch):
    """The behaviour lives on the class: each "land" of the log is a call of UAV.land on that
    UAV, the launched ones from within their own process (UAV.wander), each leaving the
    footprint of its launch index, C_db = (swarmsize - index) / swarmsize."""
    landed: list[tuple[int, float, bool]] = []
    footprints: list[float] = []
    land, deposit = UAV.land, PheromoneField.deposit

    def spy_land(robot: UAV) -> None:
        own = robot.process is not None and robot.env.active_process is robot.process
        landed.append((robot.unique_id, robot.env.now, own))
        land(robot)
        footprints.append((12 - robot.launch_index) / 12)

    def spy_deposit(field, points, radius, intensity, **kwargs):
        if np.ndim(points) == 1:  # a footprint (the wanders' deposits are (n, 2) arrays)
            footprints.append(intensity)
        return deposit(field, points, radius, intensity, **kwargs)

    monkeypatch.setattr(UAV, "land", spy_land)
    monkeypatch.setattr(PheromoneField, "deposit", spy_deposit)
    model = StigmergyModel(seed=5, swarm_size=12).run(until=900.0)
    lands = model.events().query("event == 'land'")
    assert [(rid, t) for rid, t, _ in landed] == list(
        zip(lands.robot.astype(int), lands.time, strict=True)
    )
    assert len(landed) >= 5
    assert [own for _, _, own in landed] == [False] + [True] * (len(landed) - 1)  # p0's first
    assert footprints[0::2] == footprints[1::2]  # deposited, then expected


def test_add_beacon_gives_wanders_a_link_where_it_stands():
    model = StigmergyModel(seed=2)
    far = np.array([60.0, 40.0])
    assert model.link_distance(far)[0] > model.params.l_i
    seen = model.ca
    row = model.add_beacon(far)
    assert row == 1 and np.array_equal(model.beacon_positions[row], far)
    assert model.link_distance(far)[0] == 0.0 and model.ca > seen
