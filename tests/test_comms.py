import networkx as nx
import numpy as np
import pytest
import simpy
from hypothesis import given, settings
from hypothesis import strategies as st

from abm.arena import Arena
from abm.clock import Clock
from abm.comms import CommNetwork, GradientFlood, MessageLog, TreeLinks
from abm.comms.policies import RingLinks
from abm.errors import LinkError


def settle(env: simpy.Environment, *floods: GradientFlood) -> None:
    """Run until no message is in flight and every soft state has had time to expire."""
    env.run(until=env.now + max(f.ttl for f in floods) + 1.0)
    assert all(f.quiescent for f in floods)


def build(points, walls=None, loss=0.0, seed=0):
    free = np.ones((20, 20), dtype=bool) if walls is None else walls
    env = simpy.Environment()
    net = CommNetwork(env, Arena(free, 1.0), np.random.default_rng(seed), 4.0, 0.1, loss)
    forwards = GradientFlood(net, "forwards", 1, +1)
    reverse = GradientFlood(net, "reverse", 127, -1, floor=0)
    for i, p in enumerate(points):
        net.add(i, p)
        forwards.restart()
        reverse.restart()
    return env, net, forwards, reverse


points_strategy = st.lists(
    st.tuples(st.floats(0.5, 19.5), st.floats(0.5, 19.5)), min_size=2, max_size=25
)


@settings(max_examples=40, deadline=None)
@given(points_strategy, st.data(), st.floats(0.0, 0.5))
def test_hop_counts_equal_bfs_distances_after_quiescence(points, data, loss):
    env, net, forwards, reverse = build(points, loss=loss)
    forwards.set_sources([0])
    n = len(points)
    sources = data.draw(st.sets(st.integers(0, n - 1), max_size=3))
    reverse.set_sources(sources)
    # remove a few nodes (links break mid-flight), then let everything settle
    for gone in data.draw(st.sets(st.integers(1, n - 1), max_size=n // 3)):
        env.run(until=env.now + 0.15)
        net.remove(gone)
        forwards.forget(gone)
        reverse.forget(gone)
        forwards.restart()
        reverse.restart()
    settle(env, forwards, reverse)
    g = net.graph
    dist = nx.single_source_shortest_path_length(g, 0) if 0 in g else {}
    live_sources = [s for s in reverse.sources if s in g]
    rdist = nx.multi_source_dijkstra_path_length(g, live_sources) if live_sources else {}
    for node in g:
        assert forwards.value(node) == (1 + dist[node] if node in dist else 0)
        expected = max(0, 127 - rdist[node]) if node in rdist else 0
        assert reverse.value(node) == expected


@settings(max_examples=40, deadline=None)
@given(points_strategy, st.data(), st.floats(0.0, 0.5))
def test_a_node_is_reported_reached_exactly_when_the_newest_wave_settles_it(points, data, loss):
    """``on_reach`` is what a node waiting for settled hop counts is woken by: the listener
    hears of a node exactly when :meth:`GradientFlood.settled` turns true for it (the newest
    wave arrived, or its soft state expired), never for an older wave, and every node of the
    network is reached once per wave, even with lost messages and nodes leaving mid-wave; a
    listener hears only of the nodes in its ``only``."""
    env, net, forwards, _reverse = build(points, loss=loss)
    forwards.set_sources([0])
    settle(env, forwards)
    heard = []
    base_heard = []
    forwards.on_reach(
        lambda node: heard.append((node, forwards.epoch, forwards.settled(node))),
        only=range(len(points)),
    )
    forwards.on_reach(base_heard.append, only={0})  # only the nodes someone waits on
    n = len(points)
    gone = data.draw(st.sets(st.integers(1, n - 1), max_size=n // 3))
    forwards.restart()
    for node in gone:
        env.run(until=env.now + 0.15)
        net.remove(node)
        forwards.forget(node)
        forwards.restart()
    settle(env, forwards)
    assert all(settled for _node, _epoch, settled in heard)
    newest = [node for node, epoch, _ in heard if epoch == forwards.epoch]
    assert sorted(newest) == sorted(net.graph)  # every node once in the newest wave
    assert base_heard == [node for node, _epoch, _settled in heard if node == 0]
    assert all(forwards.settled(node) for node in net.graph)


def test_links_need_range_and_line_of_sight():
    walls = np.ones((10, 10), dtype=bool)
    walls[:, 5] = False  # a wall column at x in [5, 6)
    env, net, *_ = build([(4.5, 5.0), (6.5, 5.0), (1.0, 5.0), (4.5, 8.5)], walls=walls)
    g = net.graph
    assert not g.has_edge(0, 1)  # 2 m apart but the wall is between
    assert g.has_edge(0, 2)  # 3.5 m, clear
    assert g.has_edge(0, 3)  # 3.5 m, clear
    assert not g.has_edge(2, 3)  # 4.9 m > C_r


def test_messages_arrive_after_the_latency_as_events():
    env, net, *_ = build([(1.0, 1.0), (3.0, 1.0)])
    log = []
    net.send(0, 1, "hello", lambda s, d, p: log.append((s, d, p, env.now)))
    env.run()
    assert log == [(0, 1, "hello", 0.1)]


def _deliveries(how: str, make_env, sends: list, loss: float) -> list:
    """Every step of a scenario where node 0 sends (``how``: "send" or "post") to the nodes
    ``sends`` lists as ``(pause in ticks, receiver)``, a bystander process wakes
    every tick, and node 3 leaves at t = 0.25 (its copies in flight are dropped); then the
    count of messages and the generator's next draw.
    """
    env = make_env()
    net = CommNetwork(env, Arena(np.ones((20, 20), dtype=bool), 1.0),
                      np.random.default_rng(3), 4.0, 0.1, loss)  # fmt: skip
    for i, p in enumerate([(1.0, 1.0), (3.0, 1.0), (1.0, 3.0), (3.0, 3.0)]):
        net.add(i, p)
    steps = []
    arrive = lambda s, d, p: steps.append((env.now, "got", s, d, p))  # noqa: E731
    drop = lambda s, d, p: steps.append((env.now, "drop", s, d, p))  # noqa: E731

    def sender():
        for k, (pause, dst) in enumerate(sends):
            yield env.timeout(pause * 0.05)
            getattr(net, how)(0, dst, k, arrive, drop)
            steps.append((env.now, "sent", k))

    def bystander():
        for _ in range(30):
            steps.append((env.now, "tick"))
            yield env.timeout(0.05)

    def leaver():
        yield env.timeout(0.25)
        net.remove(3)

    for process in (sender, bystander, leaver):
        env.process(process())
    env.run()
    return [steps, net.messages_sent, net.rng.random()]


@settings(max_examples=60, deadline=None)
@given(
    st.lists(st.tuples(st.integers(0, 2), st.integers(1, 3)), max_size=12),
    st.sampled_from([0.0, 0.4]),
    st.sampled_from([simpy.Environment, Clock]),
)
def test_a_posted_message_arrives_or_is_dropped_as_a_sent_one(sends, loss, make_env):
    """Posting gives the steps of sending, in the same order (same-instant bursts, a
    bystander waking at the arrival instants, a receiver leaving while copies are in flight,
    message loss delaying copies), the same count and the same random draws.
    """
    assert _deliveries("post", make_env, sends, loss) == _deliveries("send", make_env, sends, loss)


def _broadcast_arrivals(how: str, **network) -> list:
    """What a broadcast from node 0 of four to [2, 1, 3] delivers through ``CommNetwork.how``
    (node 3 leaves before its copy arrives), with ``network`` attributes set first; then the
    messages counted (``None`` in place of the arrivals if the method declined). Copies sent
    together are sorted at arrival as their receivers sort them, by the links that hold then
    (``CommNetwork.delivered``)."""
    env, net, *_ = build([(1.0, 1.0), (3.0, 1.0), (1.0, 3.0), (3.0, 3.0)])
    for name, value in network.items():
        setattr(net, name, value)
    got = []

    def arrived_together(value: tuple) -> None:
        src, dsts, payload = value
        delivered = net.delivered(src, dsts)
        got.append((src, delivered, len(dsts) - len(delivered), payload, env.now))

    dsts = [2, 1, 3]
    if how == "broadcast":
        sent = net.broadcast(0, dsts, "hop", lambda *a: got.append((*a, env.now)))
    else:
        sent = net.broadcast_together(0, dsts, arrived_together, (0, dsts, "hop"))
    net.remove(3)
    env.run()
    return [got if sent is not False else None, net.messages_sent]


def test_a_broadcast_together_arrives_as_a_broadcast_does_or_is_declined():
    """``broadcast_together`` (a flood's bulk path) delivers what ``broadcast`` delivers, when,
    and in which order, a broken link's copy dropped alike; it declines, sending nothing,
    where a copy could be lost or a log records it."""
    together = _broadcast_arrivals("broadcast_together")
    assert together == _broadcast_arrivals("broadcast")
    assert together == [[(0, [2, 1], 1, "hop", 0.1)], 3]
    assert _broadcast_arrivals("broadcast_together", loss=0.1) == [None, 0]
    assert _broadcast_arrivals("broadcast_together", log=MessageLog()) == [None, 0]


@settings(max_examples=40, deadline=None)
@given(points_strategy, st.data())
def test_a_flood_sent_together_is_the_flood_sent_copy_by_copy(points, data):
    """A flood's bulk path (copies together, links checked by the flood at arrival) changes
    the same values at the same times, reaches the same nodes in the same order and sends as
    many messages as the same flood through ``broadcast`` (a message log makes the network
    decline the bulk path), with nodes leaving mid-wave so that copies are dropped."""
    n = len(points)
    sources = data.draw(st.sets(st.integers(0, n - 1), min_size=1, max_size=3))
    gone = data.draw(st.lists(st.integers(1, n - 1), unique=True, max_size=n // 3))
    pauses = data.draw(st.lists(st.sampled_from([0.05, 0.1, 0.15, 0.3]), min_size=len(gone)))

    def history(log: MessageLog | None) -> tuple[list, list, int]:
        env, net, _forwards, reverse = build(points)
        net.log = log
        changes, reached = [], []
        reverse.on_change(lambda node, old, new: changes.append((env.now, node, old, new)))
        reverse.on_reach(lambda node: reached.append((env.now, node)), only=range(n))
        reverse.set_sources(sources)
        for node, pause in zip(gone, pauses, strict=False):
            env.run(until=env.now + pause)
            net.remove(node)
            reverse.forget(node)
            reverse.restart()
        settle(env, reverse)
        return changes, reached, net.messages_sent

    assert history(None) == history(MessageLog())


def _network(shadowing=None, seed=0, free=None):
    import simpy

    from abm.comms import CommNetwork

    free = np.ones((10, 40), dtype=bool) if free is None else free
    return CommNetwork(simpy.Environment(), Arena(free), np.random.default_rng(seed), 10.0, 0.1,
                       shadowing=shadowing)  # fmt: skip


def test_shadowing_links_follow_the_log_normal_probability():
    """P(up at d) = Phi(10 n log10(R/d) / sd): 1/2 at the nominal range, and the share of links
    drawn at each distance matches it."""
    from scipy.stats import norm

    from abm.comms import Shadowing

    radio = Shadowing(exponent=3.0, sd=6.0)
    assert radio.probability(np.array([10.0]), 10.0)[0] == pytest.approx(0.5)
    for d in (5.0, 10.0, 16.0):
        net = _network(radio, seed=int(d))
        net.add("a", [1.0, 5.0])
        hits = 0
        for k in range(2000):
            net.add(("b", k), [1.0 + d, 5.0])
            hits += ("b", k) in net.neighbours("a")
            net.remove(("b", k))
        want = norm.cdf(30.0 * np.log10(10.0 / d) / 6.0)
        assert hits / 2000 == pytest.approx(want, abs=0.035)
    disc = Shadowing(sd=0.0)
    assert list(disc.probability(np.array([9.9, 10.1]), 10.0)) == [1.0, 0.0]


def test_radio_through_walls_or_not():
    from abm.comms import Shadowing

    free = np.ones((10, 40), dtype=bool)
    free[:, 5] = False  # a wall between x = 5 and 6 m
    for through, linked in ((True, True), (False, False)):
        net = _network(Shadowing(through_walls=through), free=free)
        net.add("a", [2.5, 5.0])
        net.add("b", [8.5, 5.0])
        assert net.graph.has_edge("a", "b") is linked
    plain = _network(None, free=free)  # the default: a disc with line of sight
    plain.add("a", [2.5, 5.0])
    plain.add("b", [8.5, 5.0])
    assert not plain.graph.has_edge("a", "b")


def test_moving_a_node_redraws_its_links_and_reports_the_changes():
    net = _network(None)
    changes = []
    net.on_link_change(lambda kind, a, b: changes.append((kind, {a, b})))
    net.add("anchor", [5.0, 5.0])
    net.add("explorer", [8.0, 5.0])
    assert changes == [("up", {"anchor", "explorer"})]
    assert net.move("explorer", [20.0, 5.0]) == []
    assert changes[-1] == ("down", {"anchor", "explorer"})
    assert net.move("explorer", [12.0, 5.0]) == ["anchor"]
    assert changes[-1] == ("up", {"anchor", "explorer"}) and len(changes) == 3
    assert np.array_equal(net.position("explorer"), [12.0, 5.0])


# ---------------------------------------------------------------------- link policy and log
def tree_network(log=None):
    """A queen off the arena, two workers, two scouts under worker 1 (all in radio range)."""
    env = simpy.Environment()
    tree = TreeLinks({"q": None, "w1": "q", "w2": "q", "s1": "w1", "s2": "w1"})
    net = CommNetwork(
        env,
        Arena(np.ones((20, 20), dtype=bool), 1.0),
        np.random.default_rng(0),
        50.0,
        0.5,
        policy=tree,
        log=log,
    )
    net.add("q", None)
    for i, node in enumerate(["w1", "w2", "s1", "s2"]):
        net.add(node, np.array([2.0 + i, 2.0]))
    return env, net, tree


def test_a_tree_policy_links_only_parents_and_children():
    _env, net, tree = tree_network()
    assert {frozenset(e) for e in net.graph.edges} == {frozenset(e) for e in tree.edges}
    assert tree.level("s2") == 2 and tree.children("w1") == ["s1", "s2"]


class _AllowsOnly:
    """A policy as a third party may write one: ``allows`` only, no list of partners."""

    def __init__(self, policy) -> None:
        self.allows = policy.allows


def _random_policy(data, nodes: list[int]):
    if data.draw(st.booleans(), label="ring"):
        return RingLinks(data.draw(st.permutations(nodes), label="order"))
    tree = TreeLinks({nodes[0]: None})
    for k, node in enumerate(nodes[1:], start=1):
        tree.attach(node, nodes[data.draw(st.integers(0, k - 1), label="parent")])
    return tree


@settings(max_examples=60, deadline=None)
@given(st.integers(1, 12), st.data())
def test_a_policy_listing_partners_links_and_reports_as_asking_allows_does(n, data):
    nodes = list(range(n))
    policy = _random_policy(data, nodes)
    for a in nodes:  # the list is exactly what allows says
        assert sorted(policy.partners(a)) == [b for b in nodes if policy.allows(a, b)]
    walls = np.ones((20, 20), dtype=bool)
    walls[8:12, 3:17] = False
    spot = st.tuples(st.floats(0.5, 19.5), st.floats(0.5, 19.5))
    starts = [data.draw(spot | st.none(), label="start") for _ in nodes]  # None: off the arena
    moves = data.draw(st.lists(st.tuples(st.sampled_from(nodes), spot), max_size=15))
    seen = []
    for chosen in (policy, _AllowsOnly(policy)):
        net = CommNetwork(simpy.Environment(), Arena(walls, 1.0), np.random.default_rng(0), 6.0,
                          0.1, policy=chosen)  # fmt: skip
        changes = []
        net.on_link_change(lambda kind, a, b, changes=changes: changes.append((kind, a, b)))
        answers = [net.add(i, None if p is None else np.array(p)) for i, p in enumerate(starts)]
        answers += [net.move(i, np.array(p)) for i, p in moves]
        seen.append((answers, changes, sorted(map(sorted, net.graph.edges))))
    assert seen[0] == seen[1]


@pytest.mark.parametrize("pair", [("w1", "w2"), ("s1", "s2"), ("s1", "q"), ("q", "s2")])
def test_sending_between_siblings_or_across_levels_raises(pair):
    _env, net, _tree = tree_network()
    with pytest.raises(LinkError, match="no link may carry MOVE"):
        net.send(*pair, None, lambda *a: None, kind="MOVE")


def test_a_reattached_node_talks_to_its_new_parent_only():
    _env, net, tree = tree_network()
    tree.reattach("s1", "q")
    net.move("s1", np.array([4.0, 2.0]))  # links are drawn again under the new tree
    assert tree.level("s1") == 1 and tree.children("w1") == ["s2"] and "s1" in tree.children("q")
    assert net.graph.has_edge("s1", "q") and not net.graph.has_edge("s1", "w1")
    net.send("s1", "q", None, lambda *a: None, kind="INFO")
    with pytest.raises(LinkError, match="no link may carry MOVE"):
        net.send("w1", "s1", None, lambda *a: None, kind="MOVE")


@pytest.mark.parametrize(
    ("node", "parent", "match"),
    [("q", "w1", "non-root"), ("s1", "zz", "not in the tree"), ("w1", "s1", "descendant")],
)
def test_reattaching_the_root_to_a_stranger_or_below_itself_is_refused(node, parent, match):
    _env, _net, tree = tree_network()
    with pytest.raises(LinkError, match=match):
        tree.reattach(node, parent)


def test_the_log_counts_every_transmission_with_kind_items_and_bytes():
    log = MessageLog()
    env, net, _tree = tree_network(log)
    got = []
    net.send(
        "q", "w1", "a", lambda s, d, p: got.append((env.now, p)), kind="MOVE", items=3, nbytes=12
    )
    net.send(
        "s1", "w1", "b", lambda s, d, p: got.append((env.now, p)), kind="POINT", items=1, nbytes=4
    )
    net.send(
        "w1",
        "q",
        "c",
        lambda s, d, p: got.append((env.now, p)),
        kind="POINT",
        items=1,
        nbytes=4,
        origin="s1",
        hop=1,
    )
    env.run()
    assert got == [(0.5, "a"), (0.5, "b"), (0.5, "c")]
    frame = log.frame()
    assert frame["kind"].tolist() == ["MOVE", "POINT", "POINT"]
    assert frame["bytes"].sum() == 20 and frame["items"].sum() == 5
    assert frame["origin"].tolist() == ["q", "s1", "s1"] and frame["hop"].tolist() == [0, 0, 1]
    assert log.load().to_dict() == {"w1": 3, "q": 2, "s1": 1}


def test_an_off_arena_node_reaches_placed_nodes_whatever_the_distance():
    env = simpy.Environment()
    net = CommNetwork(
        env, Arena(np.ones((20, 20), dtype=bool), 1.0), np.random.default_rng(0), 1.0, 0.1
    )
    net.add("a", np.array([1.0, 1.0]))
    net.add("far", np.array([18.0, 18.0]))
    assert net.add("base", None) == ["a", "far"]
    assert not net.graph.has_edge("a", "far")
