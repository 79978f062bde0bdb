"""The flat arms of the topology comparison (README, "The message comparison"): the same scouts, map
and planning code as the hierarchy, coordinated by *replicated planning* over a fully connected
graph (FC) or a ring (RING).

Every node keeps a full-world replica of the map and runs the same deterministic coverage call
each round with all scouts as children (model RNG: identical on every node), so no MOVE, SCAN
or assignment message is needed; instead every POINT, ARRIVED and SCAN_COMPLETE (and at
start-up every INFO) is disseminated to **all** other nodes: on FC one transmission to each of
the n - 1 others, on the ring forwarded hop by hop both ways until every node has it once (n - 1
transmissions, up to ceil((n - 1) / 2) hops). On a shared radio channel the FC copies are one
broadcast, and so are the ring origin's first hops both ways: the log marks each as one
transmission (``MessageLog.shared``; the summary's ``transmissions_task``). With reliable,
zero-latency delivery (the comparison's setting) every replica equals the map holder's after
each message, so the simulation plans once, on the holder's replica, and counts every
transmission on the network.
"""

import numpy as np

from abm import portable
from abm.comms import RingLinks
from models.hierarchy.agents import Queen, Scout
from models.hierarchy.protocol import Message

__all__ = ["FlatHolder", "FlatScout", "disseminate", "ring_order"]

HOLDER = "holder"


def ring_order(holder: object, scouts: list, positions: np.ndarray) -> list:
    """The ring's order [ours, README "The message comparison"]: the map holder first, then the
    scouts in angular order of their start positions about their centroid.
    """
    centre = positions.mean(axis=0)
    angle = portable.arctan2(positions[:, 1] - centre[1], positions[:, 0] - centre[0])
    return [holder, *(scouts[i] for i in np.argsort(angle, kind="stable"))]


def disseminate(model, origin: object, msg: Message) -> None:
    """Send ``msg`` from ``origin`` to every other node (FC: directly; ring: hop by hop both
    ways); the holder's copy goes into its inbox, the scouts' replicas need no simulation.
    """
    comms = model.comms
    others = [n for n in model.member_ids() if n != origin]

    def arrive(src, dst, payload) -> None:
        msg_, direction, left, hop = payload
        if dst == HOLDER:
            model.queen.receive(origin, msg_)
        if left > 0:
            forward(dst, direction, left, hop + 1)

    def forward(node, direction, left, hop) -> None:
        nxt = comms.policy.step(node, direction)
        comms.send(node, nxt, (msg, direction, left - 1, hop), arrive, kind=msg.KIND,
                   items=msg.items, nbytes=msg.nbytes, phase=msg.PHASE, origin=origin,
                   hop=hop)  # fmt: skip

    if isinstance(comms.policy, RingLinks):
        n = len(others)
        with comms.log.shared():  # the origin's first hop both ways: one broadcast
            forward(origin, +1, (n + 1) // 2, 0)
            if n // 2:
                forward(origin, -1, n // 2, 0)
        return
    with comms.log.shared():  # one broadcast heard by every other node
        for dst in others:
            comms.send(origin, dst, (msg, 0, 0, 0), arrive, kind=msg.KIND, items=msg.items,
                       nbytes=msg.nbytes, phase=msg.PHASE, origin=origin)  # fmt: skip


class FlatScout(Scout):
    """A scout of a flat arm: whatever it would tell a parent it tells everyone."""

    def send(self, local: int, msg: Message, origin: object = None, hop: int = 0) -> None:
        """Disseminate ``msg`` to every other node (``local`` is always the holder's 0)."""
        disseminate(self.model, self.id, msg)


class FlatHolder(Queen):
    """The designated map holder of a flat arm (no body, no scanning): its replica decides when
    the map is complete (README "The message comparison", item 2). Its "sends" to scouts are the
    scouts' own identical computation, so they reach the scout without a transmission.
    """

    id = HOLDER

    def send(self, local: int, msg: Message, origin: object = None, hop: int = 0) -> None:
        """Hand a plan step to the scout that computed the same plan itself (no message)."""
        self.model.member(self.links[local]).receive(self.id, msg)
