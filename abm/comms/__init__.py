"""Communication between robots, one concept per module.

- :mod:`~abm.comms.network`: :class:`CommNetwork`, the graph of who can talk to whom and
  message delivery as SimPy events (latency, loss, link faults and loss bursts);
- :mod:`~abm.comms.radio`: :class:`Shadowing`, a log-normal shadowing radio in place of the
  default disc with line of sight;
- :mod:`~abm.comms.policies`: :class:`LinkPolicy` and two of them, :class:`TreeLinks` (a rooted
  tree's parent/child edges) and :class:`RingLinks`, which say which links may carry messages;
- :mod:`~abm.comms.messages`: :class:`MessageLog`, every transmission, one row per hop;
- :mod:`~abm.comms.flood`: :class:`GradientFlood`, hop-count gradients kept by message floods;
- :mod:`~abm.comms.inbox`: :class:`Inbox`, the messages a process takes one at a time
  (``simpy.Store``'s events, exactly, at less cost).
"""

from abm.comms.flood import GradientFlood
from abm.comms.inbox import Inbox
from abm.comms.messages import MessageLog
from abm.comms.network import CommNetwork
from abm.comms.policies import LinkPolicy, RingLinks, TreeLinks
from abm.comms.radio import Shadowing

__all__ = [
    "CommNetwork",
    "GradientFlood",
    "Inbox",
    "LinkPolicy",
    "MessageLog",
    "RingLinks",
    "Shadowing",
    "TreeLinks",
]
