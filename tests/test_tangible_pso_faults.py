"""Tangible PSO's deployment with a failing MAV: the real swarm flies the best particle's
transitions; the failed MAV does nothing more, the survivors stop and fly on to their planned
places under the feasibility check, so wherever they were localised when it failed they stay
localised at every realised state; the same seed gives the same event log."""

import numpy as np
import pandas as pd
import pytest

from abm.errors import ConfigError
from models.tangible_pso import TangiblePSOModel
from models.tangible_pso.agents import MAV
from models.tangible_pso.feasibility import localised

SMALL = {"deploy": True}
FAULTY = {"fault_rate": 0.03, "fault_states": ("deploying",)}


def _run(seed: int, **kw) -> TangiblePSOModel:
    return TangiblePSOModel(seed=seed, **{**SMALL, **kw}).run()


def test_without_faults_the_real_swarm_ends_at_the_best_distribution():
    m = _run(1)
    s = m.summary()
    assert s["end_reason"] == "deployed" and s["mavs_failed"] == 0
    assert np.allclose(m.deployed, m.best)
    assert s["deployed_cost"] == pytest.approx(s["best_cost"])
    assert all(mav.state == "deployed" for mav in m.agents_by_type[MAV])
    for _t, pos, _alive in m.deployment["trace"]:
        assert localised(pos, m.params.neighbours, m.params.d_min, m.params.loc_range)


@pytest.mark.parametrize("seed", [1, 3, 5])
def test_survivors_localised_when_it_failed_stay_localised_and_the_failed_one_stays(seed):
    m = _run(seed, n_mavs=6, fault_rate=0.01, fault_states=("deploying",))
    p = m.params
    events = m.events()
    faults = events[events["event"] == "fault"]
    assert not faults.empty
    for rid in faults["robot"].astype(int):
        mine = events[events["robot"] == rid]
        after = mine.loc[mine.index[mine["event"] == "fault"][0] + 1 :]
        assert after[~((after["event"] == "state") & (after["state"] == "failed"))].empty
        (i,) = (mav.row for mav in m.agents_by_type[MAV] if mav.unique_id == rid)
        gone = [pos[i] for _t, pos, alive in m.deployment["trace"] if not alive[i]]
        assert all(np.array_equal(gone[0], x) for x in gone)  # it stays where it failed
    trace = m.deployment["trace"]
    first = next(j for j, (_t, _x, alive) in enumerate(trace) if not alive.all())
    survivors = [x[a] for _t, x, a in trace[first:]]
    assert localised(survivors[0], p.neighbours, p.d_min, p.loc_range)
    moved = False
    for x in survivors:
        if len(x) < len(survivors[0]):
            break  # a second failure: what holds after it is not this test's
        assert localised(x, p.neighbours, p.d_min, p.loc_range)
        moved |= not np.array_equal(x, survivors[0])
    assert moved  # they did fly on


def test_with_k_equal_n_minus_1_the_constraint_cannot_hold_after_a_failure_and_they_freeze():
    """Two survivors can localise at most one neighbour each: k = 2 cannot hold, so every
    move breaks the constraint and the feasibility check keeps them where they stopped."""
    for seed in range(10):
        m = _run(seed, neighbours=2, fault_times=(), **FAULTY)
        if m.summary()["mavs_failed"] == 1:
            break
    s = m.summary()
    assert s["mavs_failed"] == 1 and s["survivors_localised"] == 0.0
    trace = m.deployment["trace"]
    first = next(j for j, (_t, _x, alive) in enumerate(trace) if not alive.all())
    assert all(np.array_equal(trace[first][1], x) for _t, x, _a in trace[first:])


def test_the_cost_counts_only_the_survivors():
    m = _run(3, **FAULTY)
    s = m.summary()
    assert s["mavs_failed"] >= 1
    alive = m.deployed_alive
    assert s["deployed_cost"] == pytest.approx(float(m.cost(m.deployed[alive])))
    assert s["deployed_cost"] >= float(m.cost(m.deployed))


def test_same_seed_with_faults_gives_the_same_event_log():
    a, b = _run(5, **FAULTY), _run(5, **FAULTY)
    assert a.summary()["mavs_failed"] >= 1
    pd.testing.assert_frame_equal(a.events(), b.events())


@pytest.mark.parametrize(
    "kwargs",
    [
        {"fault_rate": 0.01, "fault_states": ("deploying",), "deploy": False},
        {"fault_rate": 0.01, "fault_states": ("free",), "deploy": True},
    ],
)
def test_mav_failures_need_the_deployment(kwargs):
    with pytest.raises(ConfigError, match="deploy"):
        TangiblePSOModel(**kwargs)
