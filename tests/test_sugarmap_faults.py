"""SugarMap with failing robots: a landed anchor that fails takes its dimension out of every
later signature, a failed explorer stops for good, and the run stays exact (counts conserved,
the same seed giving the same event log)."""

import numpy as np
import pandas as pd
import pytest

from abm.errors import ConfigError
from models.sugarmap import SugarMapModel
from models.sugarmap.agents import Anchor, Explorer

#: The testbed set-up of the contract tests, long enough for faults after the deployment.
SMALL = {"arena": "testbed", "n_anchors": 5, "n_explorers": 2, "init_cutoff": 60.0}


def _events_after_fault(model: SugarMapModel, robot: int) -> pd.DataFrame:
    """The robot's events logged after its fault, but its own move into the failed state."""
    events = model.events()
    mine = events[events["robot"] == robot]
    at = mine.index[mine["event"] == "fault"][0]
    after = mine.loc[at + 1 :]
    return after[~((after["event"] == "state") & (after["state"] == "failed"))]


def _failed(model: SugarMapModel) -> list[int]:
    events = model.events()
    return [int(r) for r in events.loc[events["event"] == "fault", "robot"]]


@pytest.mark.parametrize("seed", [3, 11])
def test_a_failed_anchor_is_missing_from_every_later_signature_and_has_no_events(seed):
    m = SugarMapModel(
        seed=seed, horizon=200.0, fault_times=(150.0,), fault_states=("anchor",), **SMALL
    )
    m.run()
    (anchor,) = _failed(m)
    assert _events_after_fault(m, anchor).empty
    (column,) = [r.row for r in m.agents_by_type[Anchor] if r.unique_id == anchor]
    f = m.filter
    later = [
        f.signatures[e, j, column]
        for e in range(f.n_explorers)
        for j in range(f.n_stored[e])
        if f.stored_at[e, j] > 150.0
    ]
    earlier = [
        f.signatures[e, j, column]
        for e in range(f.n_explorers)
        for j in range(f.n_stored[e])
        if f.stored_at[e, j] < 150.0
    ]
    assert later and np.isnan(later).all()
    assert earlier and np.isfinite(earlier).all()
    assert m.summary()["failed_anchors"] == 1


def test_with_every_anchor_failed_the_explorers_stop_and_coverage_freezes():
    times = tuple(100.0 + i for i in range(5))
    m = SugarMapModel(seed=5, horizon=250.0, fault_times=times, fault_states=("anchor",), **SMALL)
    m.run()
    assert m.summary()["failed_anchors"] == 5
    assert all(r.state == "stopped" for r in m.agents_by_type[Explorer])
    samples = m.samples()
    after = samples.loc[samples["time"] > 106.0, "coverage"]
    assert after.nunique() == 1  # nothing is covered once no anchor answers


def test_a_failed_explorer_stays_where_it_failed_and_the_others_go_on():
    m = SugarMapModel(
        seed=2, horizon=250.0, fault_times=(120.0,), fault_states=("exploring",), **SMALL
    )
    m.run(until=121.0)
    (rid,) = _failed(m)
    (e,) = [r.row for r in m.agents_by_type[Explorer] if r.unique_id == rid]
    where = m.pos[e].copy()
    others = np.delete(m.pos, e, axis=0).copy()
    m.run()
    assert np.array_equal(m.pos[e], where)
    assert not np.array_equal(np.delete(m.pos, e, axis=0), others)
    assert _events_after_fault(m, rid).empty
    assert m.summary()["failed_explorers"] == 1


def test_by_default_only_anchors_fail_and_one_failing_in_flight_falls_where_it_is():
    m = SugarMapModel(seed=6, horizon=100.0, fault_rate=0.01, trace_interval=1.0, **SMALL).run()
    events = m.events()
    failed = events[events["event"] == "fault"]
    anchors = {r.unique_id for r in m.agents_by_type[Anchor]}
    assert set(failed["robot"].astype(int)) <= anchors
    in_flight = failed[failed["state"] == "dispersing"]
    assert len(in_flight) > 0
    positions = m.positions()
    for rid, at in zip(in_flight["robot"].astype(int), in_flight["time"], strict=True):
        track = positions[positions["robot"] == rid]
        before, after = track[track["time"] < at], track[track["time"] > at]
        assert before[["x", "y"]].drop_duplicates().shape[0] > 1  # it flew
        assert len(after) > 0 and after[["x", "y"]].drop_duplicates().shape[0] == 1
        assert _events_after_fault(m, rid).empty  # it never lands


@pytest.mark.parametrize("seed", [1, 8])
def test_counts_are_conserved_and_coverage_never_falls_under_random_failures(seed):
    m = SugarMapModel(
        seed=seed, horizon=300.0, fault_rate=5e-3, fault_states=("anchor", "exploring"), **SMALL
    )
    m.run()
    counts = m.state_counts()
    assert (counts[list(m.STATES)].sum(axis=1) == 7).all()
    assert counts["failed"].iloc[-1] == len(_failed(m)) > 0
    assert np.all(np.diff(m.samples()["coverage"]) >= 0)


def test_same_seed_with_faults_gives_the_same_event_log():
    kw = {"horizon": 200.0, "fault_rate": 4e-3, "fault_states": ("anchor",), **SMALL}
    a, b = SugarMapModel(seed=4, **kw).run(), SugarMapModel(seed=4, **kw).run()
    assert _failed(a)
    pd.testing.assert_frame_equal(a.events(), b.events())
    pd.testing.assert_frame_equal(a.samples(), b.samples())


@pytest.mark.parametrize("states", [("waiting",), ("anchor", "waiting")])
def test_failures_of_waiting_explorers_are_refused(states):
    with pytest.raises(ConfigError, match="fault_states"):
        SugarMapModel(fault_rate=1e-3, fault_states=states, **SMALL)
