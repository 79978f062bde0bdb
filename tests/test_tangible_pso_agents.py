"""Tangible PSO's robots are the classes of ``agents.py``, and Mesa's ``model.agents`` is their
only index: a virtual MAV per row of the particle arrays, a real MAV per MAV of the swarm
once it deploys, each knowing its row; the states counted on the agents are the recorder's
counts at every step; the real MAVs' behaviour (``MAV.deploy``) ends "deployed", or at the
failure for an MAV that failed; the model keeps no list of its robots beside Mesa's.
"""

from collections import Counter
from collections.abc import Iterator

import numpy as np
import pytest

from abm.arena import Arena
from abm.model import SwarmModel
from abm.robot import Robot
from models.tangible_pso import TangiblePSOModel
from models.tangible_pso.agents import MAV, VirtualMAV

#: A deployment in which two of the six real MAVs fail (seed 3).
FAULTY = {"deploy": True, "n_mavs": 6, "fault_rate": 0.01, "fault_states": ("deploying",)}


def _recorded(m: TangiblePSOModel) -> Counter:
    """The recorder's robots per state now (its last row of counts)."""
    last = m.state_counts().iloc[-1]
    return Counter({s: int(last[s]) for s in m.STATES if last[s]})


def _steps(m: TangiblePSOModel) -> Iterator[float]:
    """Run the model one Mesa step at a time until the run ends; the time after each step."""
    while m.end_reason is None:
        m.step()
        yield m.time


def _check_virtual(m: TangiblePSOModel) -> None:
    """Every virtual MAV names its row of the particle arrays; rows are creation order."""
    n = m.params.n_mavs
    virtual = m.agents_by_type[VirtualMAV].to_list()
    assert len(virtual) == m.params.particles * n
    assert [v.row for v in virtual] == list(range(len(virtual)))
    assert all(v.row == v.particle * n + v.index and 0 <= v.index < n for v in virtual)
    xy = np.array([v.position for v in virtual])
    assert np.array_equal(xy, m.x.reshape(-1, 3)[[v.row for v in virtual], :2])


def test_a_quick_run_is_virtual_mavs_in_their_rows_counted_as_the_recorder_counts():
    m = TangiblePSOModel(seed=1, **TangiblePSOModel.QUICK)
    seen_states = set()
    for _time in _steps(m):
        assert set(m.agents_by_type) == {VirtualMAV}  # no real swarm without deploy
        assert Counter(a.state for a in m.agents) == _recorded(m)
        _check_virtual(m)
        seen_states |= {a.state for a in m.agents}
    assert m.iteration == m.params.iterations and len(seen_states) >= 2  # they did move


def test_the_real_mavs_deploy_as_the_recorder_counts_each_in_its_row_of_the_plan():
    m = TangiblePSOModel(seed=1, particles=10, iterations=12, deploy=True)
    while m.flight is None:
        m.step()
    mavs = m.agents_by_type[MAV].to_list()
    assert [mav.row for mav in mavs] == list(range(m.params.n_mavs))
    flying = 0
    for _time in _steps(m):
        assert Counter(a.state for a in m.agents) == _recorded(m)
        _check_virtual(m)
        flying += all(mav.state == "deploying" for mav in mavs) and m.flight.is_alive
    assert flying >= 2  # counted at several times while the swarm flew the plan
    assert m.end_reason == "deployed" and not m.flight.is_alive
    assert m.agents_by_type[MAV].to_list() == mavs  # the same robots, in the same order
    assert all(mav.state == "deployed" and not mav.process.is_alive for mav in mavs)
    at = np.array([mav.position for mav in mavs])
    assert np.array_equal(at, m.deployed[[mav.row for mav in mavs], :2])
    assert np.allclose(m.deployed, m.best)


def test_a_failed_mav_keeps_its_place_and_stays_indexed_while_the_others_deploy():
    m = TangiblePSOModel(seed=3, **FAULTY).run()
    mavs = m.agents_by_type[MAV]
    failed = mavs.select(lambda a: a.failed)
    assert len(mavs) == m.params.n_mavs and len(failed) == m.summary()["mavs_failed"] >= 1
    assert Counter(a.state for a in m.agents) == _recorded(m)
    assert {a.state for a in failed} == {"failed"}
    assert {a.state for a in mavs.select(lambda a: not a.failed)} == {"deployed"}
    assert not any(mav.process.is_alive for mav in mavs)  # MAV.deploy ended for every MAV
    for mav in mavs:
        assert np.array_equal(mav.position, m.deployed[mav.row, :2])
        assert m.deployed_alive[mav.row] == (not mav.failed)
    trace = m.deployment["trace"]
    for mav in failed:  # where it failed: the first trace entry without it
        first = next(x for _t, x, alive in trace if not alive[mav.row])
        assert np.array_equal(mav.position, first[mav.row, :2])


def _framework_attributes() -> set[str]:
    """What a bare SwarmModel sets on itself (Mesa's own index of agents among it)."""

    class Bare(SwarmModel):
        """A model with no robots of its own."""

        STATES = ("idle",)

    bare = Bare(Bare.make_params(), Arena(np.ones((4, 4), dtype=bool)), physics=False)
    return set(vars(bare))


def _robots_in(value: object, depth: int = 0) -> bool:
    """Whether ``value`` is a robot or holds one: in a container (lists, tuples, sets, dicts,
    object arrays) or in an attribute of one of the model's own parts, a few levels deep.
    """
    if isinstance(value, Robot):
        return True
    if depth > 4:
        return False
    if type(value).__module__.startswith("models.") and hasattr(value, "__dict__"):
        value = list(vars(value).values())
    if isinstance(value, dict):
        value = [*value.keys(), *value.values()]
    if isinstance(value, np.ndarray) and value.dtype == object:
        value = value.ravel().tolist()
    if isinstance(value, list | tuple | set | frozenset):
        return any(_robots_in(v, depth + 1) for v in value)
    return False


@pytest.mark.parametrize("kwargs", [TangiblePSOModel.QUICK, {"seed": 3, **FAULTY}])
def test_the_model_keeps_no_robots_of_its_own_beside_mesas_agents(kwargs):
    m = TangiblePSOModel(**kwargs).run()
    own = {k: v for k, v in vars(m).items() if k not in _framework_attributes()}
    assert {k for k, v in own.items() if _robots_in(v)} == set()
