"""Faults in stigmergy: a failed beacon stops relaying (wanders no longer link to it), acts no
more, and runs with faults are seeded; ca over time is the coverage raster's history."""

import numpy as np
import pytest

from abm.errors import ConfigError
from models.stigmergy import StigmergyModel
from models.stigmergy.agents import UAV


@pytest.fixture(scope="module")
def faulty_run():
    return StigmergyModel(seed=4, fault_rate=1 / 500, fault_states=("beacon",)).run()


def test_failed_beacons_stop_relaying_and_never_act_again(faulty_run):
    model = faulty_run
    failed = model.faults.failed
    assert len(failed) >= 3
    uavs = model.agents_by_type[UAV]
    assert all(r.beacon_row is None for r in uavs if r.failed)  # nobody links to a failed beacon
    live = sorted((r for r in uavs if r.state == "beacon"), key=lambda r: r.beacon_row)
    assert [r.beacon_row for r in live] == list(range(len(model.beacon_positions)))
    assert np.array_equal(model.beacon_positions, np.array([r.position for r in live]))
    events = model.events()
    for rid in failed:
        mine = events[events.robot == rid]
        after = mine.loc[mine.index[mine.event == "fault"][0] :]
        assert list(after.event) == ["fault", "state"]
    assert uavs[0].launch_index == 0 and uavs[0].unique_id not in failed  # p0's is exempt
    counts = model.state_counts()
    assert (counts[list(model.STATES)].sum(axis=1).diff().fillna(1) >= 0).all()
    assert counts.iloc[-1][list(model.STATES)].sum() == len(model.agents)


def test_same_seed_with_faults_gives_the_same_event_log(faulty_run):
    again = StigmergyModel(seed=4, fault_rate=1 / 500, fault_states=("beacon",)).run()
    assert again.events().equals(faulty_run.events())


def test_ca_over_time_rises_to_the_final_ca(faulty_run):
    ca = faulty_run.samples()
    step = faulty_run.params.ca_sample_period
    assert ca.time.iloc[0] == 0.0 and np.allclose(np.diff(ca.time), step)
    assert faulty_run.env.now <= ca.time.iloc[-1] < faulty_run.env.now + step
    assert ca.ca.is_monotonic_increasing
    assert ca.ca.iloc[-1] == pytest.approx(100 * faulty_run.ca)


def test_stigmergy_refuses_link_and_sensor_faults():
    with pytest.raises(ConfigError, match="link_outage_rate=0.1: StigmergyModel does not handle"):
        StigmergyModel(seed=1, link_outage_rate=0.1)
    with pytest.raises(ConfigError, match="fault_states names 'explorer'"):
        StigmergyModel(seed=1, fault_rate=0.01, fault_states=("explorer",))
