"""The communication network: a networkx graph of robots in range and line of sight, and
message delivery as SimPy events.

By default links exist between nodes closer than the communication range with a clear line of sight
(reliable within range, nothing beyond). With :class:`~abm.comms.radio.Shadowing` a link is up
with the probability log-normal shadowing gives at its distance, through walls or not. A message
takes ``latency`` seconds. With a loss probability ``loss`` each attempt may be lost; because
robots re-send continually, a lost message arrives on a later attempt, so loss shows up as extra
delay (a geometric number of periods), never as a silent gap.

Faults (:mod:`abm.faults`) act here too: :meth:`CommNetwork.block` takes a link down until
:meth:`CommNetwork.unblock` (the pair cannot link meanwhile, whatever the radio reaches), and
during a loss burst (:meth:`CommNetwork.start_burst`) each transmission is lost with the
burst's probability: it is dropped (``on_drop``), not delayed. A node added without a position
is off the arena (a base station, a laptop): its radio reaches every node.
"""

from collections.abc import Callable, Iterable
from typing import TYPE_CHECKING

import networkx as nx
import numpy as np
import simpy

from abm.arena import Arena
from abm.clock import scheduler
from abm.comms.messages import MessageLog
from abm.comms.policies import LinkPolicy, Node
from abm.comms.radio import SHORTEST_LINK, Shadowing
from abm.errors import LinkError, check_range
from abm.neighbours import NeighbourIndex

if TYPE_CHECKING:  # annotations only: the parts do not need Mesa to run
    from mesa import Agent

__all__ = ["CommNetwork"]


class CommNetwork:
    """Who can talk to whom, and how messages travel.

    Args:
        env: the SimPy environment.
        arena: walls block links.
        rng: the model's random generator (message loss).
        comm_range: the range within which nodes in line of sight are linked (m); with
            shadowing, its nominal range R.
        latency: delay of one message (s; 0: delivered at the same instant, after the sender's
            current step).
        loss: probability that one transmission attempt is lost.
        shadowing: a radio with log-normal shadowing (links drawn from the model's generator)
            instead of the default disc with line of sight.
        policy: which links may carry messages (None: every link the radio reaches); set it
            before adding nodes.
        log: a message log that records every transmission (None: only ``messages_sent``).

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
        policy: LinkPolicy | None = None,
        log: MessageLog | None = None,
    ) -> None:
        check_range("comm_range", comm_range, 0.0, low_open=True)
        check_range("latency", latency, 0.0)
        check_range("loss", loss, 0.0, 0.99)
        self.env = env
        self.arena = arena
        self.rng = rng
        self.comm_range = float(comm_range)
        self.latency = float(latency)
        self.loss = float(loss)
        self.shadowing = shadowing
        self.policy = policy
        self.log = log
        self.graph = nx.Graph()
        self.messages_sent = 0
        self.messages_lost = 0  # dropped by loss bursts
        self._listeners: list[Callable[[str, Node, Node], None]] = []
        self._blocked: set[frozenset] = set()
        self._burst: tuple[float, np.random.Generator] | None = None
        self._burst_listeners: list[Callable[[], None]] = []
        # Placed nodes on a grid of cells a little wider than the range, so a node's possible
        # links are found among its neighbours (in the graph's node order: ``_seq``), not by
        # measuring every node. A shadowing radio draws a number per node and keeps the scan.
        self._index: NeighbourIndex | None = None
        if shadowing is None or shadowing.sd == 0:
            self._index = NeighbourIndex(self.comm_range * (1.0 + 1e-9))
        self._seq: dict[Node, int] = {}
        self._added = 0
        # Each node's attributes ("pos": where it is, None off the arena): networkx's own dict,
        # read directly, as the node view's lookup costs more than the links drawn from it.
        self._attrs = self.graph._node
        self._unplaced: dict[Node, None] = {}
        self._call_later = scheduler(env)

    def on_link_change(self, listener: Callable[[str, Node, Node], None]) -> None:
        """Call ``listener("up"|"down", a, b)`` whenever a link appears or disappears."""
        self._listeners.append(listener)

    def add(self, node: Node, position: np.ndarray | None) -> list[Node]:
        """Add a node at ``position`` and link it to every node the link model reaches (and the
        policy allows); ``position`` None: an off-arena node whose radio reaches every node.
        """
        position = None if position is None else np.asarray(position, dtype=float)
        others = self._candidates(position, node)
        self.graph.add_node(node, pos=position)
        self._seq[node] = self._added
        self._added += 1
        self._place(node, position)
        linked = self._reachable(position, others, node)
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
        self._attrs[node]["pos"] = position
        self._place(node, position)
        others = self._candidates(position, node)
        now = self._reachable(position, others, node)
        before = set(self.graph.neighbors(node))
        linked = set(now)
        gone = [o for o in before if o not in linked]
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

    def _place(self, node: Node, position: np.ndarray | None) -> None:
        """Keep the index of placed nodes (and the list of off-arena ones) up to date."""
        if position is None:
            self._unplaced[node] = None
            if self._index is not None:
                self._index.remove(node)
            return
        self._unplaced.pop(node, None)
        if self._index is not None:
            self._index.add(node, position)

    def _candidates(self, position: np.ndarray | None, node: Node) -> list[Node]:
        """The nodes ``node`` at ``position`` may link to, in the graph's node order: every
        node, or with the index the off-arena nodes and the placed nodes the policy allows in
        nearby cells (:meth:`_reachable` keeps only those the policy allows and measures the
        placed ones). A policy that lists a node's partners gives the placed ones among them
        instead, wherever they are: fewer to look at, the same links once measured.
        """
        if position is None or self._index is None:
            return [o for o in self.graph.nodes if o != node]
        partners = getattr(self.policy, "partners", None)
        if partners is not None:
            near = [
                o
                for o in partners(node)
                if o in self._seq and o not in self._unplaced and o != node
            ]
        else:
            near = [o for o in self._index.near(position) if o != node]
            if self.policy is not None:
                allows = self.policy.allows
                near = [o for o in near if allows(node, o)]
        near.sort(key=self._seq.get)
        return [o for o in self._unplaced if o != node] + near

    def _reachable(self, position: np.ndarray | None, others: list[Node], node: Node) -> list[Node]:
        """The nodes among ``others`` that ``node`` at ``position`` is linked to."""
        if self.policy is not None:
            others = [o for o in others if self.policy.allows(node, o)]
        if self._blocked:
            others = [o for o in others if frozenset((node, o)) not in self._blocked]
        attrs = self._attrs
        unplaced = [o for o in others if attrs[o]["pos"] is None]
        if position is None or len(unplaced) == len(others):
            return others if position is None else unplaced
        placed = [o for o in others if attrs[o]["pos"] is not None]
        return unplaced + self._in_range(position, placed)

    def _in_range(self, position: np.ndarray, others: list[Node]) -> list[Node]:
        """The placed nodes among ``others`` the radio of a node at ``position`` reaches.

        A disc (no shadowing, or shadowing without spread) is one compiled pass over the
        nodes; a shadowing radio with spread draws one number per node, in their order.
        """
        pts = np.array([self._attrs[o]["pos"] for o in others])
        shadowing = self.shadowing
        if shadowing is None or shadowing.sd == 0:
            up = self.arena.within_reach(
                position,
                pts,
                self.comm_range,
                shortest=0.0 if shadowing is None else SHORTEST_LINK,
                walls_block=shadowing is None or not shadowing.through_walls,
            )
        else:
            p = shadowing.probability(np.hypot(*(pts - position).T), self.comm_range)
            up = self.rng.random(len(others)) < p
            if not shadowing.through_walls and up.any():
                visible = self.arena.line_of_sight(
                    np.broadcast_to(position, pts[up].shape), pts[up]
                )
                up[np.nonzero(up)[0][~visible]] = False
        return [o for o, ok in zip(others, up.tolist(), strict=True) if ok]

    def remove(self, node: Node) -> list[Node]:
        """Remove a node and all its links."""
        neighbours = list(self.graph.neighbors(node))
        self.graph.remove_node(node)
        self._seq.pop(node, None)
        self._unplaced.pop(node, None)
        if self._index is not None:
            self._index.remove(node)
        for other in neighbours:
            self._notify("down", node, other)
        return neighbours

    def robot_left(self, robot: "Agent") -> None:
        """A robot failed or was removed (a lifecycle event): its node, if it has one, and its
        links go (messages in flight to or from it are dropped).
        """
        if robot.unique_id in self.graph:
            self.remove(robot.unique_id)

    def block(self, a: Node, b: Node) -> None:
        """A link outage: ``a`` and ``b`` cannot link until :meth:`unblock` (their link, if
        up, goes down now and messages in flight over it are dropped).
        """
        self._blocked.add(frozenset((a, b)))
        if self.graph.has_edge(a, b):
            self.graph.remove_edge(a, b)
            self._notify("down", a, b)

    def unblock(self, a: Node, b: Node) -> bool:
        """The outage of ``a``-``b`` ended: the link is drawn again (both nodes still in the
        network and reachable); returns True if it came back up.
        """
        self._blocked.discard(frozenset((a, b)))
        if a not in self.graph or b not in self.graph or self.graph.has_edge(a, b):
            return False
        if not self._reachable(self._attrs[a]["pos"], [b], a):
            return False
        self.graph.add_edge(a, b)
        self._notify("up", a, b)
        return True

    def start_burst(self, loss: float, rng: np.random.Generator) -> None:
        """A message-loss burst begins: each transmission from now on is lost with
        probability ``loss`` (drawn from ``rng``) until :meth:`end_burst`.
        """
        check_range("loss_burst_loss", loss, 0.0, 1.0, low_open=True)
        self._burst = (float(loss), rng)

    def end_burst(self) -> None:
        """The loss burst is over; listeners of :meth:`on_burst_end` are told."""
        self._burst = None
        for listener in self._burst_listeners:
            listener()

    def on_burst_end(self, listener: Callable[[], None]) -> None:
        """Call ``listener()`` when a loss burst ends (senders that re-send continually
        repeat what was lost).
        """
        self._burst_listeners.append(listener)

    def _notify(self, kind: str, a: Node, b: Node) -> None:
        for listener in self._listeners:
            listener(kind, a, b)

    def neighbours(self, node: Node) -> list[Node]:
        """The nodes linked to ``node``."""
        return list(self.graph.neighbors(node))

    def position(self, node: Node) -> np.ndarray:
        """Where a node is (m)."""
        return self._attrs[node]["pos"]

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
        *,
        kind: str = "message",
        items: int = 0,
        nbytes: int = 0,
        phase: str = "task",
        origin: Node | None = None,
        hop: int = 0,
    ) -> simpy.Event:
        """Deliver ``payload`` from ``src`` to ``dst`` as a SimPy event.

        On arrival ``handler(src, dst, payload)`` runs; if a node left the network or the link
        broke while the message was in flight, ``on_drop(src, dst, payload)`` runs instead.
        A message lost in a loss burst is dropped the same way. ``kind``, ``items``,
        ``nbytes``, ``phase``, ``origin`` and ``hop`` describe the message
        for the log (see :class:`MessageLog`).

        Raises:
            LinkError: the policy forbids the pair (e.g. two siblings of a tree).

        """
        delay, lost = self._transmit(src, dst, kind, items, nbytes, phase, origin, hop)
        event = self.env.timeout(delay, value=payload)
        message = (src, dst, payload, handler, on_drop, lost)
        event.callbacks.append(lambda _event: self._arrive_one(message))
        return event

    def post(
        self,
        src: Node,
        dst: Node,
        payload: object,
        handler: Callable[[Node, Node, object], None],
        on_drop: Callable[[Node, Node, object], None] | None = None,
        *,
        kind: str = "message",
        items: int = 0,
        nbytes: int = 0,
        phase: str = "task",
        origin: Node | None = None,
        hop: int = 0,
    ) -> None:
        """:meth:`send` for a sender that never waits on the delivery: the same checks, log
        row, random draws and arrival, at the same place among the events (a plain call on the
        clock, :func:`~abm.clock.call_later`, instead of a timeout of its own). A
        message-driven model posts tens of thousands of messages a run; the copies a sender
        posts one after another at one instant then arrive as one event.

        Raises:
            LinkError: the policy forbids the pair (e.g. two siblings of a tree).

        """
        delay, lost = self._transmit(src, dst, kind, items, nbytes, phase, origin, hop)
        self._call_later(delay, self._arrive_one, (src, dst, payload, handler, on_drop, lost))

    def _transmit(
        self,
        src: Node,
        dst: Node,
        kind: str,
        items: int,
        nbytes: int,
        phase: str,
        origin: Node | None,
        hop: int,
    ) -> tuple[float, bool]:
        """One transmission of :meth:`send` or :meth:`post`: checked against the policy,
        logged and counted; its delay (s) and whether a loss burst lost it.
        """
        self._check_policy(src, dst, kind)
        if self.log is not None:
            self.log.record(self.env.now, src, dst, kind, items, nbytes, phase, origin, hop)
        self.messages_sent += 1
        lost = False
        if self._burst is not None:
            loss, rng = self._burst
            lost = bool(rng.random() < loss)
            self.messages_lost += lost
        return self.delivery_delay(), lost

    def _arrive_one(self, message: tuple) -> None:
        """A sent or posted message arrives: handed over if its link held, else dropped."""
        src, dst, payload, handler, on_drop, lost = message
        if not lost and self.graph.has_edge(src, dst):
            handler(src, dst, payload)
        elif on_drop is not None:
            on_drop(src, dst, payload)

    def _check_policy(self, src: Node, dst: Node, kind: str) -> None:
        """Raise LinkError if the link policy forbids a message from ``src`` to ``dst``."""
        if self.policy is not None and not self.policy.allows(src, dst):
            raise LinkError(f"no link may carry {kind} from {src!r} to {dst!r}")

    def broadcast(
        self,
        src: Node,
        dsts: Iterable[Node],
        payload: object,
        on_arrival: Callable[[Node, list[Node], int, object], None],
        *,
        kind: str = "message",
        items: int = 0,
        nbytes: int = 0,
        phase: str = "task",
        origin: Node | None = None,
        hop: int = 0,
    ) -> int:
        """Send ``payload`` from ``src`` to each of ``dsts`` and hand the copies over in bulk:
        ``on_arrival(src, delivered, dropped, payload)`` runs once per arrival instant with the
        receivers whose link held (in ``dsts`` order) and the number of copies dropped.

        The same messages, log rows and random draws as one :meth:`send` per copy, in ``dsts``
        order; without message loss (and outside a loss burst) the copies share one event and
        their links are checked together when they arrive, before any is handled (one send
        per copy would drop the copies handled after a handler that breaks their link). With
        loss or in a burst each copy travels alone and arrives on its own. A flood's millions
        of copies then cost one call per broadcast, not one per copy.

        Returns:
            The number of copies sent (``len(dsts)``).

        """
        dsts = list(dsts)
        if self.loss > 0.0 or self._burst is not None:  # each copy travels alone
            for dst in dsts:
                self.send(
                    src,
                    dst,
                    payload,
                    lambda s, d, p: on_arrival(s, [d], 0, p),
                    lambda s, _d, p: on_arrival(s, [], 1, p),
                    kind=kind,
                    items=items,
                    nbytes=nbytes,
                    phase=phase,
                    origin=origin,
                    hop=hop,
                )
            return len(dsts)
        if self.policy is not None:  # refuse the whole broadcast before any copy is logged
            for dst in dsts:
                self._check_policy(src, dst, kind)
        if self.log is not None:
            now = self.env.now
            for dst in dsts:
                self.log.record(now, src, dst, kind, items, nbytes, phase, origin, hop)
        self.messages_sent += len(dsts)
        if dsts:
            arrival = (src, dsts, payload, on_arrival)
            self._call_later(self.latency, self._arrive_together, arrival)
        return len(dsts)

    def broadcast_together(
        self, src: Node, dsts: list[Node], on_arrival: Callable[[object], None], value: object
    ) -> bool:
        """:meth:`broadcast`'s bulk path alone, for senders of millions of copies (floods):
        when no copy can be lost (no loss, no burst), no policy checks pairs and no log records
        them, send a copy to each of ``dsts`` as one event, ``on_arrival(value)`` when they
        arrive, and return True; otherwise send nothing and return False (then call
        :meth:`broadcast`).

        The receivers then take only the copies whose link still holds, in ``dsts`` order,
        checked together before any is handled (:meth:`delivered`): the same messages, order and
        arrival as :meth:`broadcast`, without its per-call options, its copy of ``dsts`` and a
        call per arrival to sort the copies (``value`` carries what the receiver needs: the
        sender, ``dsts``, the payload). ``dsts`` must not change until the copies arrive.
        """
        if self.loss > 0.0 or self._burst is not None or self.policy is not None:
            return False
        if self.log is not None:
            return False
        if dsts:
            self.messages_sent += len(dsts)
            self._call_later(self.latency, on_arrival, value)
        return True

    def delivered(self, src: Node, dsts: list[Node]) -> list[Node]:
        """Which copies of a broadcast from ``src`` to ``dsts`` arriving now are delivered:
        those whose link still holds (none once ``src`` left), in ``dsts`` order, all checked
        before any is handled. ``dsts`` itself when every link holds (do not change it).
        """
        linked = self.graph._adj.get(src, ())
        for dst in dsts:
            if dst not in linked:
                return [dst for dst in dsts if dst in linked]
        return dsts

    def _arrive_together(self, arrival: tuple) -> None:
        """The copies of one broadcast arrive: their links checked together, then handed over."""
        src, dsts, payload, on_arrival = arrival
        delivered = self.delivered(src, dsts)
        on_arrival(src, delivered, len(dsts) - len(delivered), payload)
