"""Link policies: which pairs of nodes may ever exchange messages, whatever the radio
reaches (a rooted tree's parent/child edges, a ring's neighbours). Sending over a pair the
policy forbids raises :class:`~abm.errors.LinkError`.
"""

from collections.abc import Hashable, Iterable, Mapping
from typing import Protocol

from abm.errors import LinkError

__all__ = ["LinkPolicy", "Node", "RingLinks", "TreeLinks"]

#: A node of the comm network: a robot's id, or any other hashable (a base station).
Node = Hashable


class LinkPolicy(Protocol):
    """Which pairs of nodes may ever exchange messages (whatever the radio reaches).

    A policy may also offer ``partners(node)``: every node ``b`` with ``allows(node, b)``.
    The network then draws a moved node's links from that short list instead of asking
    ``allows`` of every node in range (the tree and the ring offer it).
    """

    def allows(self, a: Node, b: Node) -> bool:
        """True if a message may travel between ``a`` and ``b`` (in either direction)."""
        ...


class TreeLinks:
    """A rooted tree's links: a node talks only to its parent and its children, never to a
    sibling, a cousin or across levels (the rule of hierarchical swarms).

    Args:
        parents: node -> its parent (None for the root); more nodes join with :meth:`attach`.

    """

    def __init__(self, parents: Mapping[Node, Node | None] | None = None) -> None:
        self.parent: dict[Node, Node | None] = {}
        self._children: dict[Node, list[Node]] = {}
        for node, parent in (parents or {}).items():
            self.attach(node, parent)

    def attach(self, node: Node, parent: Node | None) -> None:
        """Add ``node`` below ``parent`` (None: ``node`` is the root; there is only one)."""
        if node in self.parent:
            raise LinkError(f"node {node!r} is already in the tree")
        if parent is None and any(p is None for p in self.parent.values()):
            raise LinkError(f"node {node!r} cannot be a second root")
        self.parent[node] = parent
        self._children.setdefault(node, [])
        if parent is not None:
            self._children.setdefault(parent, []).append(node)

    def reattach(self, node: Node, parent: Node) -> None:
        """Move ``node`` (with its subtree) below ``parent``, e.g. an orphan whose parent
        failed: from now on it may talk to ``parent`` and no longer to its old parent.

        Raises:
            LinkError: ``node`` is the root or not in the tree, ``parent`` is not in the
                tree, or ``parent`` lies in ``node``'s own subtree (a cycle).

        """
        if node not in self.parent or self.parent[node] is None:
            raise LinkError(f"node {node!r} is not a non-root node of the tree")
        if parent not in self.parent:
            raise LinkError(f"parent {parent!r} is not in the tree")
        above = parent
        while above is not None:
            if above == node:
                raise LinkError(f"node {node!r} cannot move below its own descendant {parent!r}")
            above = self.parent[above]
        self._children[self.parent[node]].remove(node)
        self.parent[node] = parent
        self._children[parent].append(node)

    def allows(self, a: Node, b: Node) -> bool:
        """True for a parent/child pair."""
        return (a in self.parent and self.parent[a] == b and b is not None) or (
            b in self.parent and self.parent[b] == a and a is not None
        )

    def partners(self, node: Node) -> list[Node]:
        """The nodes ``node`` may talk to: its parent (unless it is the root) and children."""
        parent = self.parent.get(node)
        return ([] if parent is None else [parent]) + self._children.get(node, [])

    def children(self, node: Node) -> list[Node]:
        """``node``'s children in the order they were attached (local numbers 1..k)."""
        return list(self._children.get(node, []))

    def level(self, node: Node) -> int:
        """Depth of ``node`` (the root is level 0)."""
        depth = 0
        while self.parent[node] is not None:
            node = self.parent[node]
            depth += 1
        return depth

    @property
    def edges(self) -> list[tuple[Node, Node]]:
        """Every (parent, child) pair."""
        return [(p, c) for c, p in self.parent.items() if p is not None]


class RingLinks:
    """A ring's links: each node talks only to its two neighbours in ``order`` (a cycle).

    Args:
        order: the nodes around the ring.

    """

    def __init__(self, order: Iterable[Node]) -> None:
        self.order = list(order)
        self._index = {node: i for i, node in enumerate(self.order)}
        if len(self._index) != len(self.order):
            raise LinkError("a ring lists every node once")

    def allows(self, a: Node, b: Node) -> bool:
        """True for neighbours on the ring."""
        if a not in self._index or b not in self._index or a == b:
            return False
        gap = abs(self._index[a] - self._index[b])
        return gap == 1 or gap == len(self.order) - 1

    def partners(self, node: Node) -> list[Node]:
        """The nodes ``node`` may talk to: its neighbours on the ring (none off the ring)."""
        if node not in self._index or len(self.order) < 2:
            return []
        i = self._index[node]
        ahead, behind = self.order[(i + 1) % len(self.order)], self.order[i - 1]
        return [ahead] if ahead == behind else [ahead, behind]

    def step(self, node: Node, direction: int) -> Node:
        """The neighbour of ``node`` clockwise (+1) or counter-clockwise (-1)."""
        return self.order[(self._index[node] + direction) % len(self.order)]
