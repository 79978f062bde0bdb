"""Robots: removing one keeps every other robot's position in the Mesa space and the physics
in step (no cached row of Mesa's private index), and its counts and energy stop."""

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from models.beacon_explorer import BeaconExplorerModel
from models.stigmergy import StigmergyModel
from models.stigmergy.agents import UAV


def test_removing_robots_keeps_positions_right_and_the_run_going():
    model = BeaconExplorerModel(world="open", seed=4, launch_period=2.0, trace_interval=None)
    model.run(until=30.0)
    by_id = {r.unique_id: r for r in model.agents}
    flyers = [by_id[i] for i in model.physics.ids.tolist()]
    waiting = [r for r in model.agents if r.state == "ground"]
    assert len(flyers) >= 2 and len(waiting) >= 2
    gone = [waiting[0], flyers[0]]  # an early row and a flying one
    energy = {r.unique_id: model.ledger.energy(r.unique_id) for r in gone}
    for robot in gone:
        robot.remove()
    model.run(until=60.0)
    for rid, used in energy.items():
        assert model.ledger.energy(rid) == pytest.approx(used)  # no power after removal
        assert rid not in model.physics.ids
    for rid, pos in zip(model.physics.ids.tolist(), model.physics.pos, strict=True):
        assert np.array_equal(by_id[rid].position, pos)  # the space mirrors physics
    counts = model.state_counts()
    total = counts[list(model.STATES)].sum(axis=1)
    assert total.iloc[-1] == model.n_robots + 1 - 2
    removed = model.events().query("event == 'removed'")
    assert sorted(removed["robot"].astype(int)) == sorted(energy)


@settings(max_examples=5, deadline=None)
@given(st.integers(0, 1000), st.floats(60.0, 400.0))
def test_a_robot_failed_in_flight_leaves_the_air_and_its_behaviour_ends(seed, when):
    """Stigmergy's wander behaviour does not catch interrupts: a failure still ends it cleanly
    (Robot.start), the robot leaves the physics, and nothing of it happens after."""
    model = StigmergyModel(seed=seed, fault_times=(when,), fault_states=("wander",))
    model.run(until=when + 100.0)
    assume(model.faults.failed)  # else no wander was in the air at that moment
    (rid,) = model.faults.failed
    robot = next(r for r in model.agents_by_type[UAV] if r.unique_id == rid)
    assert robot.failure.state == "wander" and not robot.process.is_alive
    assert rid not in model.physics.ids and robot.beacon_row is None
    events = model.events()
    assert events[(events.robot == rid) & (events.time > when)].empty
    counts = model.state_counts().iloc[-1]
    assert counts[list(model.STATES)].sum() == len(model.agents) and counts.failed == 1


@settings(max_examples=5, deadline=None)
@given(st.integers(0, 1000))
def test_the_space_mirrors_the_flyers_every_tick_while_rows_change(seed):
    """The physics places its flyers through rows looked up once per flyer set
    (``SwarmModel.place_flyers``): after every tick each flyer's robot is where the physics
    has it, while walkers take off (the flyers change) and join the space (new rows) as
    others fly, land, and are removed from the ground and from the air (the rows move up)."""
    from tiny_model import TinyModel

    model = TinyModel(seed=seed, walkers=12, launch_period=1.0, rest_rate=0.3)
    place = model.physics.positions_out
    checked = []
    removed = []

    def checked_place(ids, pos):
        place(ids, pos)
        for rid, xy in zip(ids.tolist(), pos, strict=True):
            assert np.array_equal(model.robot(rid).position, xy)
        checked.append(len(ids))

    def remover():
        for k in range(6):
            yield model.env.timeout(1.75)
            robots = list(model.agents)
            if k % 2:  # one flying (the flyers change too)
                chosen = [r for r in robots if r.unique_id in model.physics.ids][-1:]
            else:  # one resting on an early row: only the flyers' rows change
                chosen = [r for r in robots if r.state == "resting"][:1]
            for robot in chosen:
                robot.remove()
                removed.append(robot.state)

    model.physics.positions_out = checked_place
    model.env.process(remover())
    model.run(until=15.0)
    assert len(checked) > 50 and max(checked) >= 2
    assert "resting" in removed and "walking" in removed


@settings(max_examples=100, deadline=None)
@given(st.integers(1, 30), st.data())
def test_the_compiled_row_assignment_is_numpys(n, data):
    """``place_flyers`` writes the flyers' rows with a compiled loop: numpy's
    ``target[rows] = values``, repeated rows included (the last value wins)."""
    from abm.model import _put_rows

    rows = np.array(data.draw(st.lists(st.integers(0, n - 1), max_size=2 * n)), dtype=np.int64)
    values = np.arange(2.0 * len(rows)).reshape(-1, 2) + 0.5
    expected, got = np.zeros((n, 2)), np.zeros((n, 2))
    expected[rows] = values
    _put_rows(got, rows, values)
    np.testing.assert_array_equal(got, expected)
