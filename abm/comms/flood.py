"""Hop-count gradients kept up to date by message floods over a comm network (a distributed
breadth-first search, one flood wave per change of topology or sources).
"""

from collections.abc import Callable, Container, Iterable

from abm.clock import scheduler
from abm.comms.network import CommNetwork
from abm.comms.policies import Node

__all__ = ["GradientFlood"]


class GradientFlood:
    """A hop-count gradient kept up to date by message floods (a distributed BFS).

    Sources hold ``start``; every hop adds ``step`` (+1 forwards from the base, -1 for the
    reverse gradient from frontier beacons), never going below ``floor``. Sources re-emit
    continually; between two changes of topology or sources every re-emission
    carries the same values, so we simulate one flood *wave* per change (an epoch). A node
    takes the best value of the newest wave that reaches it. A node no wave reaches within
    ``ttl`` seconds (cut off from all sources) decays to ``floor``, as a continually refreshed
    soft state would.

    Args:
        network: the comm network the messages travel on.
        name: label (e.g. "forwards").
        start: value at a source (e.g. 1 for a gradient rising from the base, a large value for
            a falling one).
        step: change per hop (+1 or -1).
        floor: lowest value; also the value of an unreached node.
        ttl: soft-state lifetime (s); by default the time a wave needs to cross every node of
            the network once (longer with message loss).
        links: the nodes a node passes its value to, as a list that stays as it is until the
            copies arrive (by default its comm neighbours, ``network.neighbours``).

    """

    def __init__(
        self,
        network: CommNetwork,
        name: str,
        start: int,
        step: int,
        floor: int = 0,
        ttl: float | None = None,
        links: Callable[[Node], list[Node]] | None = None,
    ) -> None:
        if step not in (1, -1):
            raise ValueError(f"step must be +1 or -1, got {step}")
        self.network = network
        self._call_later = scheduler(network.env)
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
        self._lost_since_restart = False
        self._listeners: list[Callable[[Node, int, int], None]] = []
        self._reach_listeners: list[tuple[Callable[[Node], None], Container[Node]]] = []
        network.on_burst_end(self._after_burst)

    def on_change(self, listener: Callable[[Node, int, int], None]) -> None:
        """Call ``listener(node, old, new)`` whenever a node's value changes."""
        self._listeners.append(listener)

    def on_reach(self, listener: Callable[[Node], None], only: Container[Node]) -> None:
        """Call ``listener(node)`` whenever the newest wave reaches a node in ``only`` (or its
        soft state expires), i.e. whenever :meth:`settled` turns true for it: who waits on
        settled values is woken then instead of looking again and again. ``only`` is read at
        each arrival (the nodes someone waits on now): a wave reaches every node, and a call
        per node would cost a flood a call per value it takes.
        """
        self._reach_listeners.append((listener, only))

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

    def settled_all(self, nodes: Iterable[Node]) -> bool:
        """True once the newest wave reached every one of ``nodes`` (see :meth:`settled`)."""
        epoch_of, epoch = self._epoch_of, self.epoch
        for node in nodes:  # a loop, not all(...): this runs for every beacon decision
            if epoch_of.get(node, 0) != epoch:
                return False
        return True

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
        self._lost_since_restart = False
        epoch = self.epoch
        for source in self.sources:
            if source in self.network.graph:
                self._receive(source, epoch, self.start)
        self._call_later(self.ttl, self._expire, epoch)

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
        self._take(node, epoch, value, current_epoch)

    def _take(self, node: Node, epoch: int, value: int, current_epoch: int) -> None:
        """``node``, which holds a value of wave ``current_epoch``, adopts ``value`` of wave
        ``epoch`` and passes it on.
        """
        reached = epoch == self.epoch and current_epoch != epoch
        self._epoch_of[node] = epoch
        values = self.values
        old = values.get(node, self.floor)
        values[node] = value
        if old != value:  # _set inlined: a flood takes millions of values
            for listener in self._listeners:
                listener(node, old, value)
        if reached:  # _reached inlined
            for listener, only in self._reach_listeners:
                if node in only:
                    listener(node)
        onward = value + self.step
        if onward < self.floor:
            return
        dsts = self.links(node)
        if self.network.broadcast_together(
            node, dsts, self._arrive_together, (node, dsts, epoch, onward)
        ):
            self.in_flight += len(dsts)
        else:
            self.in_flight += self.network.broadcast(node, dsts, (epoch, onward), self._arrive)

    def _arrive(self, src: Node, delivered: list[Node], dropped: int, payload: tuple) -> None:
        """Copies sent by :meth:`CommNetwork.broadcast` arrived (in sending order) or were
        dropped.
        """
        self.in_flight -= dropped
        if dropped:
            self._lost_since_restart = True
        epoch, value = payload
        self._arrive_together((src, delivered, epoch, value))

    def _arrive_together(self, arrival: tuple[Node, list[Node], int, int]) -> None:
        """The copies of one node's broadcast arrived (sent together: see
        :meth:`CommNetwork.broadcast_together`): those whose link still holds, all checked
        before any is handled, are taken in sending order.
        """
        src, dsts, epoch, value = arrival
        self.in_flight -= len(dsts)
        delivered = self.network.delivered(src, dsts)
        if len(delivered) != len(dsts):  # a link broke on the way: its copy is dropped
            self._lost_since_restart = True
        epoch_of, values, step = self._epoch_of, self.values, self.step
        for dst in delivered:
            # _receive inlined: most copies of a wave arrive where a value as good is held
            current_epoch = epoch_of.get(dst, 0)
            if epoch < current_epoch:
                continue
            if epoch == current_epoch and (value - values[dst]) * step >= 0:
                continue
            self._take(dst, epoch, value, current_epoch)

    def _after_burst(self) -> None:
        """The sources re-emit continually: what a loss burst dropped arrives with the next
        emission, i.e. a new wave once the burst is over.
        """
        if self._lost_since_restart:
            self.restart()

    def _expire(self, epoch: int) -> None:
        for node in list(self.network.graph.nodes):
            if self._epoch_of.get(node, 0) < epoch:
                self._epoch_of[node] = epoch
                self._set(node, self.floor)
                if epoch == self.epoch:
                    self._reached(node)

    def _reached(self, node: Node) -> None:
        """The newest wave settled ``node``: tell the listeners watching it (:meth:`on_reach`)."""
        for listener, only in self._reach_listeners:
            if node in only:
                listener(node)

    def _set(self, node: Node, value: int) -> None:
        old = self.values.get(node, self.floor)
        self.values[node] = value
        if old != value:
            for listener in self._listeners:
                listener(node, old, value)
