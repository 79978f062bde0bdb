"""Beacon/explorer's robots are Mesa agents with their behaviour on their class: the base beacon
and the N searching robots are exactly ``model.agents`` (by class, in launch order, in every
state), each robot's place in the space and the physics is its position, the explorer
controller tells a robot which beacon's spot it reached, and a beacon waits for the network's
``free_to_detach`` event to redeploy."""

from collections import Counter

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from abm.robot import Robot
from models.beacon_explorer import BeaconExplorerModel
from models.beacon_explorer.agents import BaseBeacon, SwarmRobot


@pytest.fixture(scope="module")
def checkpoints():
    """One run with faults, stopped at several times: (time, counts of robots by state from
    ``model.agents``, the recorder's counts, each robot's position by the space's and the
    physics' rows), and the model at the end."""
    model = BeaconExplorerModel(
        world="corridor",
        complexity="low",
        seed=3,
        fault_rate=1 / 300,
        launch_period=3.0,
        trace_interval=None,
    )
    seen = []
    for until in (0.0, 20.0, 60.0, 120.0, 600.0):
        model.run(until=until)
        robots = list(model.agents)
        ids = np.array([r.unique_id for r in robots])
        rows = model.rows_of(ids)
        by_id = {r.unique_id: r for r in robots}
        flying = [by_id[i].position for i in model.physics.ids.tolist()]
        seen.append(
            (
                model.env.now,
                Counter(r.state for r in robots),
                {s: n for s, n in model.recorder.counts.items() if n},
                np.array([r.position for r in robots]),
                model.space.agent_positions[rows].copy(),
                np.array(flying).reshape(-1, 2),
                model.physics.pos.copy(),
            )
        )
    return model, seen


def test_the_robots_are_model_agents_by_class_in_launch_order(checkpoints):
    model, _seen = checkpoints
    assert model.end_reason is not None
    (base,) = model.agents_by_type[BaseBeacon]
    assert base is model.base and base.state == "beacon"
    swarm = list(model.agents_by_type[SwarmRobot])
    assert [r.index for r in swarm] == list(range(1, model.n_robots + 1))  # i * t take-offs
    assert set(model.agents_by_type) == {BaseBeacon, SwarmRobot}
    launches = model.events().query("event == 'launch'")
    index = {r.unique_id: r.index for r in swarm}
    assert launches.robot.astype(int).is_monotonic_increasing
    assert np.allclose(launches.time, [index[r] * model.launch_period for r in launches.robot])
    grounded = {r.unique_id for r in swarm} - set(launches.robot)  # failed before their turn
    assert all(
        r.failure.state == "ground" or r.index * model.launch_period > model.env.now
        for r in swarm
        if r.unique_id in grounded
    )


def test_agents_in_every_state_match_the_recorders_counts_through_the_run(checkpoints):
    model, seen = checkpoints
    states = set()
    for now, by_agents, recorded, *_ in seen:
        assert by_agents == recorded, f"t={now}"
        assert sum(by_agents.values()) == model.n_robots + 1
        states |= set(by_agents)
    assert states == {"ground", "explorer", "beacon", "failed"}  # failed robots stay agents
    beacons = {r.unique_id for r in model.agents if r.state == "beacon"}
    assert beacons == set(model.beacons.beacons)  # the network's records are the beacons


def test_each_robots_rows_in_the_space_and_the_physics_hold_its_position(checkpoints):
    """Robot ``k``'s row of ``space.agent_positions`` (``model.rows_of``) is its position,
    and so is its row of the physics while it flies. The one exception is the framework's:
    a robot that has just taken off keeps its place on the ground (the start) until the
    physics' first tick moves it (``Physics.fly`` does not place it)."""
    model, seen = checkpoints
    start = model.world.start
    for now, _a, _r, positions, space_rows, flying, physics_rows in seen:
        assert np.array_equal(positions, space_rows), f"t={now}"
        placed = ~(flying == start).all(axis=1)
        assert placed.sum() >= len(flying) - 1  # at most one takes off per launch period
        assert np.array_equal(flying[placed], physics_rows[placed]), f"t={now}"
    assert any(len(flying) for *_x, flying, _p in seen)


def test_a_beacon_attached_at_the_spot_its_guide_advertised(checkpoints):
    """``guide`` (set by the explorer controller when the robot stops) names the beacon whose
    empty spot the robot reached: a beacon that hung there then, one interspace I_r away."""
    model, _seen = checkpoints
    events = model.events()
    attaches = events.query("event == 'attach'")
    robots = [r for r in model.agents_by_type[SwarmRobot] if r.state == "beacon"]
    assert robots
    for robot in robots:
        mine = attaches[attaches.robot == robot.unique_id].iloc[-1]
        before = attaches[(attaches.robot == robot.guide) & (attaches.time <= mine.time)]
        assert not before.empty, robot.unique_id
        hung = before.iloc[-1]
        gap = np.hypot(mine.x - hung.x, mine.y - hung.y)
        assert gap == pytest.approx(model.params.interspace, abs=1.0)


def test_the_model_keeps_no_container_of_robots(checkpoints):
    """The model's own attributes and parts (beacon network, explorer controller, world) hold
    robot ids and numbers, never robot objects: ``model.agents`` is the only index."""
    model, _seen = checkpoints
    own = {k: v for k, v in vars(model).items() if not _framework(k, model)}
    parts = {"beacons": model.beacons, "controller": model.physics.controller, **own}
    found = [name for name, value in parts.items() if _holds_robots(value, set())]
    assert not found, f"containers of robots: {found}"


def _framework(name: str, model: BeaconExplorerModel) -> bool:
    """Attributes that Mesa or SwarmModel set (their indexes are theirs)."""
    return name.startswith("_") and name != "_stall_mark" or name in {
        "space", "env", "comms", "ledger", "recorder", "faults", "physics", "arena",
        "coverage", "random", "rng", "done",
    }  # fmt: skip


def _holds_robots(value: object, seen: set[int], depth: int = 0) -> bool:
    if id(value) in seen or depth > 4:
        return False
    seen.add(id(value))
    if isinstance(value, dict):
        items = [*value.keys(), *value.values()]
    elif isinstance(value, list | tuple | set | frozenset):
        items = list(value)
    elif type(value).__module__.startswith("models.beacon_explorer"):
        items = list(vars(value).values()) if hasattr(value, "__dict__") else []
        return any(_holds_robots(v, seen, depth + 1) for v in items)
    else:
        return False
    return any(isinstance(v, Robot) for v in items) or any(
        _holds_robots(v, seen, depth + 1) for v in items
    )


def test_free_to_detach_fires_when_a_dead_end_beacon_may_redeploy_and_never_for_the_base():
    """A beacon waits on ``network.free_to_detach(robot)``: the event fires when the
    network's flowchart first finds the beacon free to detach (a corridor's dead end whose
    only neighbour is lower), at once when it already is, and never for the base."""
    from abm.arena import Arena
    from models.environments import World

    cells = [(0, 0), (1, 0)]  # two 3 m cells (the arena pads one cell around them)
    world = World(Arena.from_cells(cells, cell_size=3.0), np.array((4.5, 4.5)), "bitmap",
                  "high", np.array(cells), None)  # fmt: skip
    model = BeaconExplorerModel(world=world, n_robots=1, launch_period=1e4, seed=0,
                                trace_interval=None)  # fmt: skip
    (robot,) = model.agents_by_type[SwarmRobot]
    network = model.beacons
    network.attach(robot.unique_id, np.array((7.5, 4.5)))
    wanted = network.free_to_detach(robot.unique_id)
    base_wanted = network.free_to_detach(model.base.unique_id)
    assert not wanted.triggered  # it has not run its flowchart yet
    times = []
    wanted.callbacks.append(lambda _e: times.append(model.env.now))
    model.run(until=20.0)
    assert network.quiescent and network.beacons[robot.unique_id].may_detach
    assert wanted.processed and 0.0 < times[0] < 20.0
    assert network.free_to_detach(robot.unique_id).triggered  # free already: at once
    assert not base_wanted.triggered  # the base never detaches


@settings(max_examples=4, deadline=None)
@given(
    st.integers(0, 10_000),
    st.sampled_from(["corridor", "open", "mixed"]),
    st.lists(st.floats(1.0, 150.0), min_size=1, max_size=3),
)
def test_agents_are_the_counted_robots_at_any_time_of_any_run(seed, world, stops):
    """Property: at any time of a run (faults and flat batteries included), ``model.agents``
    holds the base and the N robots, and their states are the recorder's counts."""
    model = BeaconExplorerModel(
        world=world, seed=seed, fault_rate=1 / 400, battery_capacity=6000.0, trace_interval=None
    )
    for until in sorted(stops):
        model.run(until=until)
        assert len(model.agents_by_type[BaseBeacon]) == 1
        assert len(model.agents_by_type[SwarmRobot]) == model.n_robots
        counted = {s: n for s, n in model.recorder.counts.items() if n}
        assert Counter(r.state for r in model.agents) == counted
