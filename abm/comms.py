"""The communication network: a networkx graph of robots in range and line of sight, message
delivery as SimPy events, and hop-count gradient floods.

By default links exist between nodes closer than the communication range with a clear line of
sight (reliable within range, nothing beyond). With :class:`Shadowing` a link is up with the
probability log-normal shadowing gives at its distance (Rappaport's model, the comm range being
the distance at which the mean received power equals the receiver's sensitivity), through walls
or not. A message takes ``latency`` seconds. With a loss
probability ``loss`` each attempt may be lost; because the papers' robots re-send continually,
a lost message arrives on a later attempt, so loss shows up as extra delay (a geometric number
of periods), never as a silent gap.
"""

from collections.abc import Callable, Hashable, Iterable
from dataclasses import dataclass

import networkx as nx
import numpy as np
import simpy
from scipy.special import ndtr

from abm.arena import Arena
from abm.errors import check_range

__all__ = ["CommNetwork", "GradientFlood", "Shadowing"]

Node = Hashable


@dataclass(frozen=True)
class Shadowing:
    """Log-normal shadowing: the received power at distance d is the mean path loss
    ``10 n log10(d)`` plus a Normal(0, sd^2) dB term, so with R the distance at which the mean
    equals the receiver's sensitivity a link is up with probability
    ``Phi(10 n log10(R / d) / sd)``; with ``sd = 0`` that is the disc ``d <= R``.

    Attributes:
        exponent: n, the path-loss exponent (3 for an indoor single floor).
        sd: sigma, the shadowing standard deviation (dB); 0: a disc.
        through_walls: walls do not block (or attenuate) the radio.

    """

    exponent: float = 3.0
    sd: float = 0.0
    through_walls: bool = True

    def __post_init__(self) -> None:
        check_range("exponent", self.exponent, 0.0, low_open=True)
        check_range("sd", self.sd, 0.0)

    def probability(self, distance: np.ndarray, comm_range: float) -> np.ndarray:
        """Probability that a link of each length (m) is up."""
        d = np.maximum(np.asarray(distance, dtype=float), 1e-9)
        if self.sd == 0:
            return (d <= comm_range).astype(float)
        return ndtr(10.0 * self.exponent * np.log10(comm_range / d) / self.sd)


class CommNetwork:
    """Who can talk to whom, and how messages travel.

    Args:
        env: the SimPy environment.
        arena: walls block links.
        rng: the model's random generator (message loss).
        comm_range: the range within which nodes in line of sight are linked (m); with
            shadowing, its nominal range R.
        latency: delay of one message (s).
        loss: probability that one transmission attempt is lost.
        shadowing: a radio with log-normal shadowing (links drawn from the model's generator)
            instead of the default disc with line of sight.

    """

    def __init__(
        self,
        env: simpy.Environment,
        arena: Arena,
        rng: np.random.Generator,
        comm_range: float,
        latency: float,
        loss: float = 0.0,
        shadowing: Shadowing | None = None,
    ) -> None:
        check_range("comm_range", comm_range, 0.0, low_open=True)
        check_range("latency", latency, 0.0, low_open=True)
        check_range("loss", loss, 0.0, 0.99)
        self.env = env
        self.arena = arena
        self.rng = rng
        self.comm_range = float(comm_range)
        self.latency = float(latency)
        self.loss = float(loss)
        self.shadowing = shadowing
        self.graph = nx.Graph()
        self.messages_sent = 0
        self._listeners: list[Callable[[str, Node, Node], None]] = []

    def on_link_change(self, listener: Callable[[str, Node, Node], None]) -> None:
        """Call ``listener("up"|"down", a, b)`` whenever a link appears or disappears."""
        self._listeners.append(listener)

    def add(self, node: Node, position: np.ndarray) -> list[Node]:
        """Add a node at ``position`` and link it to every node the link model reaches."""
        position = np.asarray(position, dtype=float)
        others = list(self.graph.nodes)
        self.graph.add_node(node, pos=position)
        linked = self._reachable(position, others)
        for other in linked:
            self.graph.add_edge(node, other)
        for other in linked:
            self._notify("up", node, other)
        return linked

    def move(self, node: Node, position: np.ndarray) -> list[Node]:
        """A node moved to ``position``: its links are drawn again (those that change are
        reported to the listeners); returns its neighbours now.
        """
        position = np.asarray(position, dtype=float)
        self.graph.nodes[node]["pos"] = position
        others = [o for o in self.graph.nodes if o != node]
        now = self._reachable(position, others)
        before = set(self.graph.neighbors(node))
        gone = [o for o in before if o not in set(now)]
        new = [o for o in now if o not in before]
        for other in gone:
            self.graph.remove_edge(node, other)
        for other in new:
            self.graph.add_edge(node, other)
        for other in gone:
            self._notify("down", node, other)
        for other in new:
            self._notify("up", node, other)
        return now

    def _reachable(self, position: np.ndarray, others: list[Node]) -> list[Node]:
        """The nodes among ``others`` a node at ``position`` is linked to."""
        if not others:
            return []
        pts = np.array([self.graph.nodes[o]["pos"] for o in others])
        distance = np.hypot(*(pts - position).T)
        if self.shadowing is None:
            up = distance <= self.comm_range
            walls_block = True
        else:
            p = self.shadowing.probability(distance, self.comm_range)
            up = self.rng.random(len(others)) < p if self.shadowing.sd > 0 else p > 0
            walls_block = not self.shadowing.through_walls
        if walls_block and up.any():
            visible = self.arena.line_of_sight(np.broadcast_to(position, pts[up].shape), pts[up])
            up[np.nonzero(up)[0][~visible]] = False
        return [o for o, ok in zip(others, up, strict=True) if ok]

    def remove(self, node: Node) -> list[Node]:
        """Remove a node and all its links."""
        neighbours = list(self.graph.neighbors(node))
        self.graph.remove_node(node)
        for other in neighbours:
            self._notify("down", node, other)
        return neighbours

    def _notify(self, kind: str, a: Node, b: Node) -> None:
        for listener in self._listeners:
            listener(kind, a, b)

    def neighbours(self, node: Node) -> list[Node]:
        """The nodes linked to ``node``."""
        return list(self.graph.neighbors(node))

    def position(self, node: Node) -> np.ndarray:
        """Where a node is (m)."""
        return self.graph.nodes[node]["pos"]

    def delivery_delay(self) -> float:
        """Time until a message arrives: latency times the number of attempts it needs."""
        if self.loss == 0.0:
            return self.latency
        return self.latency * float(self.rng.geometric(1.0 - self.loss))

    def send(
        self,
        src: Node,
        dst: Node,
        payload: object,
        handler: Callable[[Node, Node, object], None],
        on_drop: Callable[[Node, Node, object], None] | None = None,
    ) -> simpy.Event:
        """Deliver ``payload`` from ``src`` to ``dst`` as a SimPy event.

        On arrival ``handler(src, dst, payload)`` runs; if a node left the network or the link
        broke while the message was in flight, ``on_drop(src, dst, payload)`` runs instead.
        """
        self.messages_sent += 1
        event = self.env.timeout(self.delivery_delay(), value=payload)

        def deliver(_event: simpy.Event) -> None:
            if self.graph.has_edge(src, dst):
                handler(src, dst, payload)
            elif on_drop is not None:
                on_drop(src, dst, payload)

        event.callbacks.append(deliver)
        return event


class GradientFlood:
    """A hop-count gradient kept up to date by message floods (a distributed BFS).

    Sources hold ``start``; every hop adds ``step`` (+1 forwards from the base, -1 for the
    reverse gradient from frontier beacons), never going below ``floor``. The sources of the
    papers re-emit continually; between two changes of topology or sources every re-emission
    carries the same values, so we simulate one flood *wave* per change (an epoch). A node
    takes the best value of the newest wave that reaches it. A node no wave reaches within
    ``ttl`` seconds (cut off from all sources) decays to ``floor``, as a continually refreshed
    soft state would.

    Args:
        network: the comm network the messages travel on.
        name: label (e.g. "forwards").
        start: value at a source (1 forwards, 127 reverse in Stirling et al.).
        step: change per hop (+1 or -1).
        floor: lowest value; also the value of an unreached node.
        ttl: soft-state lifetime (s); by default the time a wave needs to cross every node of
            the network once (longer with message loss).

    """

    def __init__(
        self,
        network: CommNetwork,
        name: str,
        start: int,
        step: int,
        floor: int = 0,
        ttl: float | None = None,
        links: Callable[[Node], Iterable[Node]] | None = None,
    ) -> None:
        if step not in (1, -1):
            raise ValueError(f"step must be +1 or -1, got {step}")
        self.network = network
        self.name = name
        self.start = int(start)
        self.step = int(step)
        self.floor = int(floor)
        self._ttl = ttl
        self.links = links or network.neighbours
        self.values: dict[Node, int] = {}
        self._epoch_of: dict[Node, int] = {}
        self.sources: frozenset[Node] = frozenset()
        self.epoch = 0
        self.restarted_at = network.env.now
        self.in_flight = 0
        self._listeners: list[Callable[[Node, int, int], None]] = []

    def on_change(self, listener: Callable[[Node, int, int], None]) -> None:
        """Call ``listener(node, old, new)`` whenever a node's value changes."""
        self._listeners.append(listener)

    @property
    def quiescent(self) -> bool:
        """True when no message of this gradient is in flight."""
        return self.in_flight == 0

    @property
    def settled_everywhere(self) -> bool:
        """True when no message is in flight and unreached nodes have decayed (after a wave)."""
        return self.quiescent and self.network.env.now >= self.restarted_at + self.ttl

    def settled(self, node: Node) -> bool:
        """True once the newest wave reached the node (or its soft state expired)."""
        return self._epoch_of.get(node, 0) == self.epoch

    def value(self, node: Node) -> int:
        """The node's current value (``floor`` if it has none yet)."""
        return self.values.get(node, self.floor)

    def set_sources(self, sources: Iterable[Node]) -> None:
        """Replace the set of sources; starts a new wave if it changed."""
        sources = frozenset(sources)
        if sources != self.sources:
            self.sources = sources
            self.restart()

    def forget(self, node: Node) -> None:
        """Drop a node that left the network."""
        self.values.pop(node, None)
        self._epoch_of.pop(node, None)

    def restart(self) -> None:
        """Start a new wave from the current sources (call after the topology changed)."""
        self.epoch += 1
        self.restarted_at = self.network.env.now
        epoch = self.epoch
        for source in self.sources:
            if source in self.network.graph:
                self._receive(source, epoch, self.start)
        expiry = self.network.env.timeout(self.ttl)
        expiry.callbacks.append(lambda _ev: self._expire(epoch))

    @property
    def ttl(self) -> float:
        """Soft-state lifetime (s) of a node's value that no wave refreshes."""
        if self._ttl is not None:
            return float(self._ttl)
        hops = self.network.graph.number_of_nodes() + 1
        return self.network.latency * hops * (1.0 + 20.0 * self.network.loss)

    def _better(self, new: int, old: int) -> bool:
        return new < old if self.step > 0 else new > old

    def _receive(self, node: Node, epoch: int, value: int) -> None:
        current_epoch = self._epoch_of.get(node, 0)
        if epoch < current_epoch:
            return
        if epoch == current_epoch and not self._better(value, self.values[node]):
            return
        self._epoch_of[node] = epoch
        self._set(node, value)
        onward = value + self.step
        if onward < self.floor:
            return
        for other in self.links(node):
            self.in_flight += 1
            self.network.send(node, other, (epoch, onward), self._deliver, self._dropped)

    def _deliver(self, _src: Node, dst: Node, payload: tuple[int, int]) -> None:
        self.in_flight -= 1
        epoch, value = payload
        self._receive(dst, epoch, value)

    def _dropped(self, _src: Node, _dst: Node, _payload: tuple[int, int]) -> None:
        self.in_flight -= 1

    def _expire(self, epoch: int) -> None:
        for node in list(self.network.graph.nodes):
            if self._epoch_of.get(node, 0) < epoch:
                self._epoch_of[node] = epoch
                self._set(node, self.floor)

    def _set(self, node: Node, value: int) -> None:
        old = self.values.get(node, self.floor)
        self.values[node] = value
        if old != value:
            for listener in self._listeners:
                listener(node, old, value)
