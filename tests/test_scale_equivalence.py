"""The scale work's shortcuts give what the plain full searches they replace give.

- The comm graph looks for links among nearby cells: same links, same neighbour order (the
  order messages go out in) as measuring every node.
- The beacon lattice is updated around each change: same lattice, same neighbour order as
  rebuilding it from all beacons.
- A broadcast shares one event and hands its copies over in bulk: the same deliveries in the
  same order as one send each (links checked when the copies arrive together); a Clock
  gathers a flood's broadcasts per instant: the same run as one event each.
- A beacon's view of its neighbours (comm neighbours, their positions, which are lattice
  neighbours) is kept until its links change: the same as looking them up afresh.
"""

import networkx as nx
import numpy as np
import simpy
from hypothesis import given, settings
from hypothesis import strategies as st

from abm.arena import CARDINALS, Arena
from abm.clock import Clock, call_later
from abm.comms import CommNetwork, GradientFlood, MessageLog
from models.beacon_explorer import BeaconExplorerModel
from models.beacon_explorer.flowchart import opposite


def walled_arena() -> Arena:
    free = np.ones((30, 30), dtype=bool)
    free[[0, -1], :] = free[:, [0, -1]] = False
    free[10, 3:25] = False
    free[3:20, 20] = False
    return Arena(free, 1.0)


@settings(max_examples=25, deadline=None)
@given(st.integers(0, 2**32 - 1), st.sampled_from([2.5, 4.0, 9.0]))
def test_comm_graph_with_index_equals_full_scan(seed, comm_range):
    rng = np.random.default_rng(seed)
    arena = walled_arena()
    nets = [
        CommNetwork(simpy.Environment(), arena, np.random.default_rng(0), comm_range, 0.1)
        for _ in range(2)
    ]
    nets[1]._index = None  # the full scan over every node
    free = arena.free_cell_centres()
    placed: set[int] = set()
    for _ in range(150):
        node = int(rng.integers(40))
        action = rng.random()
        where = free[rng.integers(len(free))] + rng.uniform(-0.4, 0.4, 2)
        if node in placed and action < 0.2:
            results = [net.remove(node) for net in nets]
            placed.discard(node)
        elif node in placed:
            results = [net.move(node, where) for net in nets]
        else:
            off_arena = action > 0.95
            results = [net.add(node, None if off_arena else where) for net in nets]
            placed.add(node)
        assert results[0] == results[1]
    a, b = (net.graph for net in nets)
    assert list(a.nodes) == list(b.nodes)
    assert {n: list(a.adj[n]) for n in a} == {n: list(b.adj[n]) for n in b}


def bulk_and_single_deliveries(loss: float, breaker: int | None, seed: int):
    """Each node of a small line broadcasts to the others: what broadcast() hands over (as
    one entry per copy) and what one send() per copy delivers, with the messages sent and
    logged. ``breaker``: a receiver whose handling removes node 3 (its link breaks while
    copies to it are arriving).
    """
    results = []
    for bulk in (True, False):
        env = simpy.Environment()
        net = CommNetwork(
            env, walled_arena(), np.random.default_rng(seed), 9.0, 0.1, loss, log=MessageLog()
        )
        for node, x in enumerate((2.0, 4.0, 6.0, 8.0, 10.0)):
            net.add(node, np.array([x, 2.0]))
        got = []

        def handle(src, dst, payload, got=got, net=net):
            got.append((net.env.now, src, dst, payload))
            if dst == breaker and 3 in net.graph:
                net.remove(3)

        def dropped(src, dst, payload, got=got, net=net):
            got.append((net.env.now, "dropped", src, payload))

        def arrival(src, delivered, n_dropped, payload, got=got, net=net):
            for dst in delivered:
                handle(src, dst, payload)
            got.extend([(net.env.now, "dropped", src, payload)] * n_dropped)

        for src in range(5):
            others = [n for n in (4, 0, 2, 1, 3) if n != src]
            if bulk:
                assert net.broadcast(src, others, src, arrival, kind="k") == len(others)
            else:
                for dst in others:
                    net.send(src, dst, src, handle, dropped, kind="k")
        env.run()
        results.append((got, net.messages_sent, net.log.frame().to_dict("records")))
    return results


@settings(max_examples=30, deadline=None)
@given(st.sampled_from([0.0, 0.3]), st.integers(0, 2**32 - 1))
def test_a_bulk_broadcast_delivers_what_single_copies_deliver(loss, seed):
    bulk, single = bulk_and_single_deliveries(loss, None, seed)
    assert bulk == single
    assert len(bulk[0]) == 20  # every copy delivered once (loss only delays)


def test_a_bulk_broadcast_checks_the_links_of_copies_arriving_together_on_arrival():
    bulk, single = bulk_and_single_deliveries(0.0, 2, 0)
    # node 0's copies go out 4, 2, 1, 3: handling the copy to 2 breaks the link to 3; one
    # copy at a time drops the copy to 3, in bulk all four had arrived before any handling
    assert (0.1, 0, 3, 0) in bulk[0] and (0.1, "dropped", 0, 0) in single[0]
    assert bulk[1:] == single[1:]  # the same messages sent and logged


def flood_trace(env: simpy.Environment, points, moves, starts_process: int) -> list:
    """Two floods over moving nodes, whose hop changes wake nodes a latency later and start a
    process (an urgent event) at every ``starts_process``-th change; everything that runs is
    logged with its time, in the order it runs.
    """
    net = CommNetwork(env, Arena(np.ones((20, 20), dtype=bool), 1.0), None, 4.0, 0.1)
    forwards = GradientFlood(net, "forwards", 1, +1)
    reverse = GradientFlood(net, "reverse", 127, -1, floor=0)
    log = []

    def started(node):
        log.append((env.now, "process", node))
        yield env.timeout(0.1)
        log.append((env.now, "process ends", node))

    changes = iter(range(1, 10**9))

    def changed(node, old, new):
        log.append((env.now, "change", node, old, new))
        call_later(env, 0.1, lambda _value: log.append((env.now, "woken", node)))
        if next(changes) % starts_process == 0:
            env.process(started(node))

    forwards.on_change(changed)
    reverse.on_change(changed)

    def mover():
        for node, (x, y) in moves:
            yield env.timeout(0.1)
            log.append((env.now, "move", node))
            net.move(node % len(points), np.array([x, y]))
            forwards.restart()
            reverse.set_sources({0, node % len(points)})

    for i, p in enumerate(points):
        net.add(i, np.array(p))
    forwards.set_sources({0})
    reverse.set_sources({len(points) - 1})
    env.process(mover())
    env.run(until=10.0)
    log.append((net.messages_sent, forwards.values, reverse.values))
    return log


@settings(max_examples=40, deadline=None)
@given(
    st.lists(st.tuples(st.floats(0.5, 19.5), st.floats(0.5, 19.5)), min_size=2, max_size=30),
    st.lists(st.tuples(st.integers(0, 29), st.tuples(st.floats(0.5, 19.5), st.floats(0.5, 19.5)))),
    st.integers(1, 7),
)
def test_broadcasts_gathered_per_instant_run_as_one_event_each_would(points, moves, every):
    assert flood_trace(Clock(), points, moves, every) == flood_trace(
        simpy.Environment(), points, moves, every
    )


def rebuilt_lattice(network) -> dict[int, list[int]]:
    """The lattice built afresh from every beacon (the code the incremental update replaced)."""
    picks = {}
    for robot, beacon in network.beacons.items():
        nearest = {}
        for other in network.comms.neighbours(robot):
            rel = network.beacons[other].position - beacon.position
            d = int(np.argmax(CARDINALS @ rel))
            r = float(np.hypot(*rel))
            if d not in nearest or r < nearest[d][0]:
                nearest[d] = (r, other)
        picks[robot] = {d: other for d, (_r, other) in nearest.items()}
    lattice = nx.Graph()
    lattice.add_nodes_from(network.beacons)
    lattice.add_edges_from(
        (robot, other)
        for robot, chosen in picks.items()
        for d, other in chosen.items()
        if picks[other].get(opposite(d)) == robot
    )
    return {robot: list(lattice.neighbors(robot)) for robot in lattice}


def test_incremental_lattice_equals_rebuild_through_attaches_and_detaches():
    model = BeaconExplorerModel(world="corridor", complexity="high", seed=3)
    network = model.beacons
    update = network._update_lattice
    checks = []

    def checked():
        update()
        want = rebuilt_lattice(network)
        assert {r: network.lattice_neighbours(r) for r in network.beacons} == want
        checks.append(len(want))

    network._update_lattice = checked
    model.run()
    detaches = (model.events()["event"] == "detach").sum()
    assert detaches > 0 and len(checks) > 20


def test_a_beacons_cached_view_of_its_neighbours_equals_a_fresh_look():
    model = BeaconExplorerModel(world="corridor", complexity="high", seed=3)
    network = model.beacons
    sense = network._sense_beacons
    checks = []

    def checked(robot):
        cached = network._near.get(robot)
        if cached is not None:
            others, rows, linked = cached
            fresh = network.comms.neighbours(robot)
            assert others == fresh
            assert rows.tolist() == [network._turn[n] for n in fresh]
            assert network._xy[rows].tolist() == [
                network.beacons[n].position.tolist() for n in fresh
            ]
            lattice = network.lattice_neighbours(robot)
            assert linked.tolist() == [n in lattice for n in fresh]
            checks.append(robot)
        return sense(robot)

    network._sense_beacons = checked
    model.run()
    assert (model.events()["event"] == "detach").sum() > 0 and len(checks) > 100


def test_the_signal_arrays_kept_through_attaches_and_detaches_equal_a_rebuild():
    """What explorers read (ids, positions, desired vectors D, target-is-empty, corridor) is
    kept row by row as beacons come and go: the same arrays as built afresh from every beacon.
    """
    model = BeaconExplorerModel(world="corridor", complexity="high", seed=3)
    network = model.beacons
    checks = []

    def rebuilt():
        kept, network._members = network._members, None
        fresh = network._current_members()
        network._members = kept
        return fresh

    def check(change):
        def checked(robot, *args, **kwargs):
            out = change(robot, *args, **kwargs)
            network._current_members()
            kept, fresh = network._members, rebuilt()
            for name in ("ids", "pos", "corridor", "vectors", "to_empty"):
                np.testing.assert_array_equal(getattr(kept, name), getattr(fresh, name))
            ids = kept.ids.tolist()
            assert [kept.rows[r] for r in ids] == list(range(len(ids)))
            assert (kept.rows >= 0).sum() == len(ids)
            checks.append(robot)
            return out

        return checked

    network.attach, network.detach = check(network.attach), check(network.detach)
    model.run()
    assert (model.events()["event"] == "detach").sum() > 0 and len(checks) > 20
