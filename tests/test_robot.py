"""Robots: removing one keeps every other robot's position in the Mesa space and the physics
in step (no cached row of Mesa's private index), and its counts and energy stop."""

import numpy as np
import pytest

from models.beacon_explorer import BeaconExplorerModel


def test_removing_robots_keeps_positions_right_and_the_run_going():
    model = BeaconExplorerModel(world="open", seed=4, launch_period=2.0, trace_interval=None)
    model.run(until=30.0)
    flyers = [model.robots[i] for i in model.physics.ids.tolist()]
    waiting = [r for r in model.robots.values() if r.state == "ground"]
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
        assert np.array_equal(model.robots[rid].position, pos)  # the space mirrors physics
    counts = model.state_counts()
    total = counts[list(model.STATES)].sum(axis=1)
    assert total.iloc[-1] == model.n_robots + 1 - 2
    removed = model.events().query("event == 'removed'")
    assert sorted(removed["robot"].astype(int)) == sorted(energy)
