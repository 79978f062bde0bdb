import math
from itertools import pairwise

import networkx as nx
import numpy as np
import pandas as pd
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from abm.errors import ConfigError, MapError
from models.beacon_explorer import BeaconExplorerModel


@pytest.fixture(scope="module")
def corridor_run():
    model = BeaconExplorerModel(world="corridor", complexity="high", seed=5)
    model.physics.trace = []
    model.run()
    return model


def test_run_ends_and_summary_has_the_agreed_keys(corridor_run):
    s = corridor_run.summary()
    for key in (
        "coverage_time",
        "coverage_area",
        "complete",
        "collisions",
        "flight_time",
        "energy_flight",
        "energy_beacon",
        "energy_ground",
        "energy_total",
        "n_beacons_final",
    ):
        assert key in s
    assert not corridor_run.running
    assert corridor_run.end_reason is not None
    assert 0 < s["coverage_area"] <= 100
    assert s["energy_total"] == pytest.approx(
        s["energy_flight"] + s["energy_beacon"] + s["energy_ground"]
    )
    assert corridor_run.time == corridor_run.env.now == s["coverage_time"]


def test_robot_counts_are_conserved(corridor_run):
    counts = corridor_run.state_counts()
    assert list(counts.columns) == ["time", "ground", "explorer", "beacon"]
    total = counts[["ground", "explorer", "beacon"]].sum(axis=1)
    assert (total == corridor_run.n_robots + 1).all()  # + the base beacon
    assert counts.time.is_monotonic_increasing


def test_no_robot_ever_crosses_a_wall(corridor_run):
    trace = corridor_run.physics.trace
    assert len(trace) > 100
    arena = corridor_run.arena
    for (_t0, ids0, p0), (_t1, ids1, p1) in pairwise(trace):
        same = np.intersect1d(ids0, ids1)
        rows0 = {r: i for i, r in enumerate(ids0)}
        rows1 = {r: i for i, r in enumerate(ids1)}
        a = np.array([p0[rows0[r]] for r in same]).reshape(-1, 2)
        b = np.array([p1[rows1[r]] for r in same]).reshape(-1, 2)
        assert not arena.segment_crosses_wall(a, b).any()
        assert arena.is_free(p1).all()


def test_energy_ledger_equals_integral_of_each_robots_power(corridor_run):
    ledger = corridor_run.ledger
    end = corridor_run.env.now
    p = corridor_run.params  # App. C: the paper's powers, model parameters
    power = {"ground": p.power_ground, "flight": p.power_flight, "beacon": p.power_beacon}
    assert power == {"ground": 0.5, "flight": 120.0, "beacon": 5.0}
    total = 0.0
    for robot in (r.unique_id for r in corridor_run.agents):
        segments = [(t, m) for t, r, m in ledger.timeline if r == robot] + [(end, None)]
        expected = sum(power[m] * (t1 - t0) for (t0, m), (t1, _) in pairwise(segments))
        assert ledger.energy(robot) == pytest.approx(expected, rel=1e-12)
        total += expected
    assert corridor_run.summary()["energy_total"] == pytest.approx(total, rel=1e-12)


def run_until_quiescent(model, until):
    """Run to ``until``, then on until both floods have settled everywhere."""
    model.run(until=until)
    floods = (model.beacons.forwards, model.beacons.reverse)
    while model.running and not all(f.settled_everywhere for f in floods):
        model.run(until=model.env.now + 0.05)


def assert_hop_counts_are_bfs_distances(model):
    beacons = model.beacons
    graph = beacons.lattice  # hop counts travel over the lattice links (a comm subgraph)
    assert all(model.comms.graph.has_edge(a, b) for a, b in graph.edges)
    dist = nx.single_source_shortest_path_length(graph, model.base.unique_id)
    sources = [b for b in beacons.reverse.sources if b in graph]
    rdist = nx.multi_source_dijkstra_path_length(graph, sources) if sources else {}
    for node in graph:
        assert beacons.forwards.value(node) == 1 + dist[node]
        assert beacons.reverse.value(node) == (max(0, 127 - rdist[node]) if node in rdist else 0)


@settings(max_examples=8, deadline=None)
@given(st.integers(0, 1000), st.sampled_from(["corridor", "open", "mixed"]), st.floats(20, 150))
def test_hop_counts_equal_bfs_distances_on_the_beacon_graph(seed, world, when):
    model = BeaconExplorerModel(world=world, seed=seed, trace_interval=None)
    run_until_quiescent(model, when)
    beacons = model.beacons
    assume(model.running)  # a finished run stops the clock before soft states expire
    assert set(model.comms.graph) == set(beacons.beacons)
    assert_hop_counts_are_bfs_distances(model)


@pytest.mark.parametrize("seed", [3, 27])
def test_a_run_is_declared_stuck_only_on_a_settled_network(seed):
    """ "Stuck" is a verdict on the network: it must not be given while the last robot to attach
    has no hop count yet (a bug that ended runs the moment the last explorer attached)."""
    model = BeaconExplorerModel(
        world="corridor", complexity="low", launch_period=12.0, seed=seed, trace_interval=None
    )
    model.run()
    assert model.end_reason.startswith("stuck")
    assert model.beacons.quiescent
    assert_hop_counts_are_bfs_distances(model)
    assert not any(b.may_detach for b in model.beacons.beacons.values())


def test_same_seed_same_event_log_and_different_seed_differs():
    def log(seed):
        m = BeaconExplorerModel(world="corridor", seed=seed, trace_interval=None, time_limit=150)
        m.run()
        return m.events()

    a, b, c = log(11), log(11), log(12)
    pd.testing.assert_frame_equal(a, b)
    assert not a.equals(c)


def test_longer_period_launches_later_and_robots_launch_in_id_order():
    m = BeaconExplorerModel(world="open", seed=3, launch_period=12.0, trace_interval=None)
    m.run()
    launches = m.events().query("event == 'launch'")
    assert list(launches.time[:3]) == [12.0, 24.0, 36.0]
    assert launches.robot.is_monotonic_increasing


def test_hover_beacons_cost_more_energy():
    kwargs = {"world": "open", "seed": 2, "launch_period": 4.0, "trace_interval": None}
    attached = BeaconExplorerModel(**kwargs).run().summary()
    hovering = BeaconExplorerModel(hover_beacons=True, **kwargs).run().summary()
    assert hovering["energy_beacon"] > 10 * attached["energy_beacon"]


def test_mesa_step_advances_one_slice_of_simulated_time():
    m = BeaconExplorerModel(world="open", seed=1, trace_interval=None)
    for _ in range(5):
        m.step()
    assert m.time == m.env.now == 5.0
    assert m.steps == 5
    assert len(m.datacollector.get_model_vars_dataframe()) == 5


def test_bitmap_world_runs(tmp_path):
    from PIL import Image

    image = np.zeros((12, 30), dtype=np.uint8)
    image[5:8, 1:29] = 255  # a 3 m wide, 28 m long corridor
    Image.fromarray(image).save(tmp_path / "corridor.png")
    m = BeaconExplorerModel(world=str(tmp_path / "corridor.png"), start=(2.5, 5.5), seed=1)
    m.run()
    assert m.summary()["coverage_area"] > 50


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"world": "cave"}, "world must be one of"),
        ({"launch_period": -6.0}, r"launch_period must be in \(0"),
        ({"n_robots": 0}, r"n_robots must be in \[1"),
        ({"complexity": "extreme"}, "complexity must be one of"),
        ({"world": "mixed", "complexity": "high"}, "complexity"),
        ({"seed": "abc"}, "seed must be an integer"),
        ({"max_speed": 0}, "max_speed"),
        ({"battery_capacity": 0.0}, r"battery_capacity must be in \(0"),
        ({"battery_capacity": -5e3}, r"battery_capacity must be in \(0"),
        ({"start": (1.5, 1.5)}, "start applies to map-file worlds only"),
        ({"world": "open", "map_resolution": 0.5}, "map_resolution applies to map-file worlds"),
        ({"attach_eps": 0.0}, r"attach_eps must be in \(0"),
        ({"hover_beacons": 1}, "hover_beacons must be True or False"),
        ({"launch_periods": 6.0}, "unknown parameter 'launch_periods' .did you mean 'launch_p"),
        ({"params": {}}, "unknown parameter 'params'"),
    ],
)
def test_bad_parameters_raise_config_errors(kwargs, match):
    with pytest.raises(ConfigError, match=match):
        BeaconExplorerModel(**kwargs)


def test_malformed_map_file_raises_map_error(tmp_path):
    bad = tmp_path / "map.png"
    bad.write_text("this is not an image")
    with pytest.raises(MapError, match="not a readable image"):
        BeaconExplorerModel(world=str(bad))
    with pytest.raises(MapError, match="does not exist"):
        BeaconExplorerModel(world=str(tmp_path / "nowhere.png"))


def settled_network(cells, base, others, seed=0):
    """A model on a world of 3 m ``cells`` with beacons attached by hand at ``others`` (m),
    run until the beacons' decisions have settled (no explorer takes off meanwhile)."""
    from abm.arena import Arena
    from models.environments import World

    arena = Arena.from_cells(cells, cell_size=3.0)
    world = World(arena, np.array(base), "bitmap", "high", np.array(cells), None)
    model = BeaconExplorerModel(
        world=world, n_robots=len(others), launch_period=1e4, seed=seed, trace_interval=None
    )
    robots = list(model.agents.select(lambda r: r.state == "ground"))
    for robot, position in zip(robots, others, strict=True):
        model.beacons.attach(robot.unique_id, np.array(position))
    model.run(until=20.0)
    assert model.beacons.quiescent
    return model, [r.unique_id for r in robots]


def test_a_corridor_beacon_does_not_advertise_a_way_another_beacon_fills():
    """The T-junction of a stalled run (seed 4980620767783090268, 24 s): a beacon that drifted to
    the side branch's edge saw the branch as empty although a branch beacon 2.4 m from that spot
    (not its lattice neighbour) covered it; explorers shuttled between the two beacons' targets
    until the time limit. Its noisy relative-positioning sensor must label the branch "beacon"
    (about 95 % of single readings here; the old code: never) and never its own corridor west."""
    corridor = [(ix, 2) for ix in range(5)] + [(2, 1), (2, 0)]  # west-east, branch south at 2
    junction, branch, west_edge = (11.99, 10.64), (11.6, 7.6), (9.2, 10.62)
    model, (_j, b, w) = settled_network(corridor, (15.0, 10.6), [junction, branch, west_edge])
    beacon = model.beacons.beacons[w]
    assert beacon.corridor
    assert b not in beacon.neighbour_dirs.values()  # not lattice-linked: the old blind spot
    readings = [model.beacons._sense_beacons(w)[1] for _ in range(400)]
    assert np.mean([2 in taken for taken in readings]) > 0.9  # south: the branch beacon's
    assert not any(3 in taken for taken in readings)  # west: free corridor, still empty
    assert beacon.desired == 3


@pytest.mark.parametrize("seed", range(5))
def test_a_beacon_does_not_advertise_a_spot_nearer_another_beacon(seed):
    """In an irregular lattice a free direction's spot can lie well inside another beacon's share
    of the room; an explorer there follows that beacon, never attaches, and hovers for ever."""
    room = [(ix, iy) for ix in range(5) for iy in range(5)]
    base = (10.5, 10.5)
    north, off_lattice = (12.0, 13.0), (13.7, 11.7)  # off_lattice: 1.2 m from base's east spot
    model, (n, o) = settled_network(room, base, [north, off_lattice], seed)
    me = model.beacons.beacons[model.base.unique_id]
    assert not me.corridor
    assert o not in me.neighbour_dirs.values()
    assert me.desired != 1  # east's spot (13.5, 10.5) is off_lattice's


@settings(max_examples=6, deadline=None)
@given(
    st.integers(0, 1000),
    st.sampled_from(["corridor", "open", "mixed"]),
    st.floats(3_000.0, 20_000.0),
)
def test_a_flat_battery_fails_the_robot_after_exactly_its_charge(seed, world, capacity):
    """Battery depletion is a SimPy event: a robot fails the moment the integral of its power
    reaches the capacity, leaves the air or the network, and is counted as failed."""
    model = BeaconExplorerModel(
        world=world, seed=seed, battery_capacity=capacity, trace_interval=None, time_limit=1500
    )
    model.run()
    used = model.ledger.frame().groupby("robot").energy.sum()
    failed = [r.unique_id for r in model.agents if r.state == "failed"]
    assert model.base.unique_id not in failed  # the base is not battery-limited
    for rid in failed:
        assert used[rid] == pytest.approx(capacity, rel=1e-9)
        assert rid not in model.beacons.beacons and rid not in model.physics.ids
        assert rid not in model.comms.graph
    others = used.drop([*failed, model.base.unique_id])
    assert (others < capacity + 1e-6).all()
    counts = model.state_counts()
    assert list(counts.columns) == ["time", "ground", "explorer", "beacon", "failed"]
    assert (
        counts[["ground", "explorer", "beacon", "failed"]].sum(axis=1) == model.n_robots + 1
    ).all()
    assert model.summary()["n_failed"] == len(failed)
    events = model.events()
    logged = events[events.event == "fault"]
    assert set(logged.get("cause", [])) <= {"battery"}
    assert sorted(logged.robot.astype(int)) == sorted(failed)


def test_small_batteries_fail_robots_and_shrink_the_search():
    """With 8 kJ each (about a minute of flight), explorers fail; with no limit none do."""
    runs = {
        cap: BeaconExplorerModel(
            world="corridor", complexity="high", seed=3, battery_capacity=cap, trace_interval=None
        ).run()
        for cap in (None, 8_000.0)
    }
    assert runs[None].summary()["n_failed"] == 0
    assert "failed" not in runs[None].state_counts().columns
    limited = runs[8_000.0].summary()
    assert limited["n_failed"] > 0
    assert limited["coverage_area"] < runs[None].summary()["coverage_area"]


def _open_room_rules(**changes):
    """A 15 m x 15 m room and the explorers' compiled constants (``changes`` replaced)."""
    room = [(ix, iy) for ix in range(5) for iy in range(5)]
    model, _ = settled_network(room, (1.5, 1.5), [(13.5, 13.5)])
    return model.arena, _replaced(model.physics.controller._constants[0], **changes)


def _replaced(constants, **changes):
    """A copy of the controller's constants record with ``changes`` made."""
    copy = np.array([constants])
    for name, value in changes.items():
        copy[name] = value
    return copy[0]


def _guides(points, arena, p, to_empty=(False, False)):
    """The beacon (0 or 1) an explorer follows at each of ``points`` in turn, starting with
    beacon 0, between beacons 0 at (6, 7.5) and 1 at (9, 7.5)."""
    from models.beacon_explorer.explorer import _keep_guide

    ids = np.array([10, 11])
    beacons = np.array([[6.0, 7.5], [9.0, 7.5]])
    guide, followed = 10.0, []
    for point in points:
        nearest = int(np.argmin(np.hypot(*(beacons - point).T)))
        k = _keep_guide(
            arena.padded,
            arena.walls_sat,
            arena.resolution,
            np.asarray(point, dtype=float),
            guide,
            np.array([-1] * 10 + [0, 1]),  # rows by robot id: 10 -> 0, 11 -> 1
            beacons,
            np.array(to_empty),
            nearest,
            p,
        )
        guide = float(ids[k])
        followed.append(k)
    return followed


@settings(max_examples=25, deadline=None)
@given(st.floats(0.02, 0.24), st.integers(2, 12))
def test_an_explorer_keeps_its_guide_until_another_beacon_is_the_hysteresis_nearer(wobble, n):
    """An explorer wobbling about the midpoint between two beacons (noise, drift) follows the
    plain nearest beacon under the paper's rule and flips guide at every crossing: the two
    beacons' signals point to different spots and it shuttles between them (the stalled
    open-room runs). With ``guide_hysteresis`` (0.5 m) it keeps its guide while the other is
    less than that much nearer, and changes once the other is."""
    arena, p = _open_room_rules(guide_commit=False)
    wobbling = [(7.5 + (wobble if k % 2 else -wobble), 7.5) for k in range(2 * n)]
    assert _guides(wobbling, arena, _replaced(p, guide_hysteresis=0.0)) == [0, 1] * n
    assert _guides(wobbling, arena, p) == [0] * (2 * n)
    beyond = 0.5 * p["guide_hysteresis"] + 0.01  # beacon 1 now more than the hysteresis nearer
    assert _guides([(7.5 + beyond, 7.5)], arena, p) == [1]


def test_an_explorer_committed_to_an_empty_spot_keeps_its_guide_while_in_touch():
    """With ``guide_commit`` an explorer keeps following a beacon that advertises an empty
    spot while it is in touch (within C_r) even when another beacon is much nearer (a spot
    2.2-2.5 m from another beacon: the circling swarms of the floor plans); out of range it
    takes the nearest."""
    arena, p = _open_room_rules()
    near_1 = [(8.8, 7.5)]  # 2.8 m from beacon 0, 0.2 m from beacon 1
    assert _guides(near_1, arena, p, to_empty=(True, False)) == [0]
    assert _guides(near_1, arena, _replaced(p, guide_commit=False), to_empty=(True, False)) == [1]
    assert _guides([(10.5, 7.5)], arena, p, to_empty=(True, False)) == [1]  # 4.5 m > C_r


def _slides(points, goal, walls, p):
    """What ``_slide_side`` answers for a flyer at each of ``points`` in turn (one per tick),
    its goal L = ``goal`` and its four cardinal sensors reading ``walls`` (N, E, S, W)."""
    from models.beacon_explorer.explorer import _slide_side

    state = np.zeros(5)
    return [
        _slide_side(state, np.asarray(pt, float), *goal, np.asarray(walls, float), p)
        for pt in points
    ]


def test_an_explorer_pressed_against_an_obstacle_slides_along_it():
    """A flyer whose goal lies ahead but that stays put for ``slide_after`` seconds is pressed
    against an obstacle (the cardinal sensors' C pushes straight back, never sideways): it then
    slides across L for ``slide_after`` seconds towards the side that reads farther, and when
    both read alike alternates sides (a door's edge: the first way may lead back). Moving, or
    near its goal, it never slides; ``slide_after=None`` turns the rule off."""
    _arena, p = _open_room_rules()
    ticks = int(round(p["slide_after"] / p["dt"]))
    still = [(5.0, 5.0)] * (4 * ticks + 4)
    east = (3.0, 0.0)  # goal 3 m east: left of it is north
    answers = _slides(still, east, (5.0, 1.0, 1.0, 1.0), p)  # north reads far
    first = answers.index(1.0)
    assert first == pytest.approx(ticks - 1, abs=1)
    assert answers[:first] == [0.0] * first
    assert answers[first : first + ticks] == [1.0] * ticks
    alike = _slides(still, east, (2.0, 1.0, 2.0, 1.0), p)
    assert [a for k, a in enumerate(alike) if a and not alike[k - 1]] == [1.0, -1.0]
    moving = [(5.0 + 0.1 * k, 5.0) for k in range(4 * ticks)]
    assert not any(_slides(moving, east, (5.0, 1.0, 1.0, 1.0), p))
    assert not any(_slides(still, (0.3, 0.0), (5.0, 1.0, 1.0, 1.0), p))  # goal reached
    assert not any(_slides(still, east, (5.0, 1.0, 1.0, 1.0), _replaced(p, slide_after=math.inf)))


@settings(max_examples=40, deadline=None)
@given(width=st.sampled_from([1, 2]), x=st.floats(4.0, 26.0), across=st.floats(0.15, 0.85))
def test_two_opposing_walls_closer_than_3_m_make_a_corridor_beacon(width, x, across):
    """The paper's corridor test (Sect. 3.3.1) holds without code of its own: opposing walls
    within the obstacle threshold leave no open quadrant."""
    from abm.arena import Arena
    from models.environments import World

    free = np.zeros((width + 2, 30), dtype=bool)
    free[1:-1, 1:-1] = True  # an east-west corridor, width m wide, 1 m pixels
    arena = Arena(free, 1.0)
    start = np.array([2.5, 1.5])
    world = World(arena, start, "bitmap", "high", np.argwhere(free)[:, ::-1], None)
    model = BeaconExplorerModel(world=world, n_robots=1, seed=int(x * 100), trace_interval=None)
    walls, corridor = model.beacons._sense_walls(np.array([x, 1.0 + across * width]))
    assert corridor and walls[0] and walls[2]


@pytest.mark.parametrize("knob", [{"message_loss": 0.5}, {"latency": 0.3}])
def test_message_loss_and_latency_act_and_hop_counts_still_settle(knob):
    """Both reach the comm network: the run differs, and once the floods have settled every
    hop count is still the BFS distance (lost messages are re-sent, they only arrive later).
    The hop counts are checked on launches 30 s apart: at 50 % loss a wave's soft state lives
    about 20 s, and a swarm that attaches faster restarts the waves before they settle."""
    plain = BeaconExplorerModel(world="corridor", seed=21, trace_interval=None)
    changed = BeaconExplorerModel(world="corridor", seed=21, trace_interval=None, **knob)
    plain.run(until=80.0)
    changed.run(until=80.0)
    assert not changed.events().equals(plain.events())
    model = BeaconExplorerModel(
        world="corridor", seed=21, launch_period=30.0, trace_interval=None, **knob
    )
    run_until_quiescent(model, 80.0)
    assert model.running  # settled before the run ended: the check below means something
    assert_hop_counts_are_bfs_distances(model)


# ---------------------------------------------------------------------- floor plans (issue 18)
#: The rules added for floor plans, all off: the model then gives the event log of the code
#: before them (checked on these set-ups, given to it as PNG files with the same start).
OLD_RULES = {
    "guide_commit": False,
    "report_taken": False,
    "lost_return": False,
    "searched_follows_signal": False,
    "slide_after": None,
    "taken_hold": None,
}


def _floor_plan_end(world: str, n_robots: int, period: float, seed: int, **rules) -> str:
    """How a run on a built-in floor plan ends within 1500 s: its end reason's first word
    ("stalled" from the stall detector, 600 s without an attach)."""
    model = BeaconExplorerModel(
        world=world,
        n_robots=n_robots,
        launch_period=period,
        seed=seed,
        time_limit=1500.0,
        trace_interval=None,
        **rules,
    ).run()
    return model.end_reason.split(":")[0]


# The seeds of the whole-run tests below are set-ups on which a pathology shows: found by
# searching seeds for a stall with the rule off (they are not tuned to pass; with the rule on,
# the same run ends). Re-found on 2026-11-26, when beacons stopped polling for hop-count waves
# and every run changed: `test_explorers_commit_...` seed 0 -> 1, `..._behind_a_pillar_...`
# 0 -> 8, `..._out_of_touch_...` 100 -> 11, `..._reopens_a_way_...` 6097586779079702662 ->
# 230, the stall detector's 0 -> 1; in seeds 0-399 no run showed the sliding and hysteresis
# stalls any more, so those rules are tested on their own (above).


def _ends_only_with(rule: str, world: str, n_robots: int, period: float, seed: int) -> None:
    """The old rules stall; today's rules without ``rule`` stall; today's rules end."""
    assert _floor_plan_end(world, n_robots, period, seed, **OLD_RULES) == "stalled"
    assert _floor_plan_end(world, n_robots, period, seed, **{rule: OLD_RULES[rule]}) == "stalled"
    assert _floor_plan_end(world, n_robots, period, seed) == "stuck"


def test_explorers_commit_to_an_advertised_spot_nearer_another_beacon():
    """Pillar room, 20 robots, 24 s: a beacon beside the north wall advertised a spot 2.2-2.5 m
    from the base (sensed as free, spot_taken = 2.2 m); explorers reaching it found the base
    0.5 m nearer, followed its signal back and circled for ever. (Found on seed 0; since the
    beacons wait for hop-count waves instead of polling, seed 1 of the same set-up shows it.)"""
    _ends_only_with("guide_commit", "pillar_room", 20, 24.0, 1)


def test_a_spot_found_taken_behind_a_pillar_is_no_longer_advertised():
    """Pillar room, 40 robots, 6 s, once explorers commit to their spot: the pillar hides a
    beacon from the beacon advertising the spot it holds (the distance sensor's ray passes
    beside the pillar), so explorers queued at the spot, ascended, found it held and flew on,
    for ever (the old code: time limit). An explorer that finds the spot held now says so."""
    found_with = {**OLD_RULES, "guide_commit": True}
    assert _floor_plan_end("pillar_room", 40, 6.0, 8, **found_with) == "stalled"
    fixed = {**found_with, "report_taken": True}
    assert _floor_plan_end("pillar_room", 40, 6.0, 8, **fixed) == "stuck"


def test_an_explorer_out_of_touch_flies_back_instead_of_hovering_for_ever():
    """Small office, 20 robots, 12 s: an explorer overshot a 1 m door into a room where no
    beacon is in line of sight and hovered there for ever (the old code: time limit). Flying
    back to where it was last in touch ends the run."""
    assert _floor_plan_end("office_small", 20, 12.0, 11, **OLD_RULES) == "stalled"
    fixed = {**OLD_RULES, "lost_return": True}
    assert _floor_plan_end("office_small", 20, 12.0, 11, **fixed) == "stuck"


def test_a_corridor_beacon_reopens_a_way_its_neighbour_no_longer_signals_back():
    """Diagonal hall, 40 robots, 12 s, once explorers commit to their spot: a corridor beacon
    had remembered for good the way to an open-space neighbour as searched when that
    neighbour's reverse gradient pointed back; later the only frontier lay beyond it, the
    beacon signalled back, its other neighbour sent explorers to it, and they shuttled between
    the two. (The old code ended this set-up "stuck": explorers did not get that far.)"""
    found_with = {**OLD_RULES, "guide_commit": True}
    world = ("diagonal_hall", 40, 12.0, 230)
    assert _floor_plan_end(*world, **found_with) == "stalled"
    fixed = {**found_with, "searched_follows_signal": True}
    assert _floor_plan_end(*world, **fixed) == "stuck"


@pytest.mark.parametrize("seed", [1, 3])
def test_explorers_read_what_beacons_signal_now(seed):
    """The explorers' copy of the beacons' signals is renewed whenever a signal changes. A
    beacon's spot is "empty" unless a lattice neighbour holds it, and a neighbour re-sensed in
    another direction changed that without renewing the copy: explorers then took a free spot
    for held and hovered beside it for ever (small office, 12 s; the old code had stale copies
    in every run, and seed 3 ran to the time limit)."""
    model = BeaconExplorerModel(
        world="office_small", n_robots=20, launch_period=12.0, seed=seed, trace_interval=None
    )
    controller = model.physics.controller
    checked = 0
    while model.running:
        model.run(until=model.time + 1.0)
        if controller._version == model.beacons.version:
            cached, fresh = controller._current_signals()[3], model.beacons.signals()[3]
            assert np.array_equal(cached, fresh), f"stale signals at t = {model.time}"
            checked += 1
    assert checked > 100
    assert model.end_reason.split(":")[0] in ("stuck", "complete")


def test_the_stall_detector_ends_a_stalled_run_and_records_why():
    """The old rules on the pillar room: explorers circle without attaching, colliding. The
    detector ends the run stall_time (600 s) into a window with no attach, names the beacon
    most of them follow, and logs a ``stall`` event; without it the run burns to the time
    limit."""
    model = BeaconExplorerModel(
        world="pillar_room",
        n_robots=20,
        launch_period=24.0,
        seed=1,
        trace_interval=None,
        **OLD_RULES,
    ).run()
    assert model.end_reason.startswith("stalled: ")
    events = model.events()
    stall = events.query("event == 'stall'").iloc[0]
    last_attach = events.query("event == 'attach'").time.max()
    assert stall.time == model.time >= last_attach + 600.0
    assert stall.duration == pytest.approx(600.0, abs=1.5)  # no attach in the window
    assert stall.collisions >= 20 and stall.followers >= 1
    assert f"beacon {int(stall.robot)}" in model.end_reason
    unwatched = BeaconExplorerModel(
        world="pillar_room",
        n_robots=20,
        launch_period=24.0,
        seed=1,
        trace_interval=None,
        time_limit=1500.0,
        stall_time=None,
        **OLD_RULES,
    ).run()
    assert unwatched.end_reason == "time limit"


def test_floor_plans_are_built_in_maps_with_a_free_start():
    from models.environments import MAPS
    from models.environments.floorplans import FLOOR_PLANS

    for name in FLOOR_PLANS:
        model = BeaconExplorerModel(world=name, n_robots=1, seed=0, trace_interval=None)
        assert np.allclose(model.world.start, MAPS[name].start)
        assert model.arena.is_free(model.world.start[None])[0]
    moved = BeaconExplorerModel(world="office", start=(30.5, 20.5), n_robots=1, seed=0)
    assert np.allclose(moved.world.start, (30.5, 20.5))
    with pytest.raises(ConfigError, match="map_resolution applies to map files only"):
        BeaconExplorerModel(world="office", map_resolution=0.5)


def test_a_beacon_the_newest_wave_has_not_reached_waits_for_it_without_looking_again():
    """A beacon woken while the newest hop-count wave has not reached it or its lattice
    neighbours decides nothing, and looks again only one control period after the wave has
    reached the last of them, then decides (until 2026-11-26 it looked again every message
    latency plus control period, re-sensing its neighbours each time: most of a large swarm's
    work)."""
    corridor = [(ix, 1) for ix in range(8)]
    chain = [(4.5 + 3.0 * k, 4.5) for k in range(1, 7)]
    model, robots = settled_network(corridor, (4.5, 4.5), chain)
    network, far = model.beacons, robots[-1]
    looks, reached = [], {}
    evaluate, publish = network._evaluate, network._publish
    decided = []

    def looking(robot):
        decided.clear()
        evaluate(robot)
        looks.append((model.env.now, robot, bool(decided)))

    def publishing(beacon, *args):
        decided.append(beacon.robot)
        return publish(beacon, *args)

    network._evaluate, network._publish = looking, publishing
    network.forwards.on_reach(
        lambda node: reached.setdefault(node, model.env.now), only=network.beacons
    )
    now = model.env.now
    network.forwards.restart()  # a new wave from the base: the chain's far end hears it last
    network.wake(far)
    model.run(until=now + 5.0)
    mine = [(t - now, d) for t, r, d in looks if r == far]
    nodes = (far, *network.beacons[far].neighbour_dirs.values())
    last_reached = max(reached[n] for n in nodes) - now
    assert last_reached == pytest.approx(6 * model.params.latency)  # six hops from the base
    assert mine[0] == (pytest.approx(model.physics.dt), False)  # stale: it waits
    assert mine[1] == (pytest.approx(last_reached + model.physics.dt), True)
    assert len(mine) == 2  # and nothing in between


@pytest.mark.parametrize("world", ["corridor", "open"])
def test_no_beacon_is_left_waiting_once_the_waves_have_reached_every_beacon(world):
    """Whenever both gradients' newest waves have reached every beacon, no beacon still waits
    for them: a beacon that found stale hop counts is always woken (or re-looks after its links
    changed), so none sits out a decision for good."""
    model = BeaconExplorerModel(world=world, seed=12, trace_interval=None, time_limit=600.0)
    network = model.beacons
    checked = 0
    while model.running:
        model.run(until=model.time + 0.5)
        everyone = list(network.beacons)
        if network.forwards.settled_all(everyone) and network.reverse.settled_all(everyone):
            assert not network._waiting, f"beacons {sorted(network._waiting)} left waiting"
            checked += 1
    assert checked > 100


def test_a_run_stuck_after_robots_failed_says_they_failed_not_that_all_are_beacons():
    # 100 J batteries: 20 of 21 robots run flat; the one beacon left cannot redeploy
    model = BeaconExplorerModel(battery_capacity=100.0, seed=1)
    model.run()
    summary = model.summary()
    assert summary["failed"] == 20 and summary["n_beacons_final"] == 1
    assert summary["end_reason"] == (
        "stuck: every robot left is a beacon (20 failed, 1 beacon left) and none can redeploy"
    )
