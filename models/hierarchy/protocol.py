"""The HST message catalogue (M1-M10: "Communication", "Scout", "Queen / Worker") as dataclasses
with their byte encoding.

Every message a node sends is one of these; the comm network logs its ``KIND``, its payload
``items`` (points, cells or waypoints carried) and its ``nbytes`` under one fixed encoding
[README "Choices": message bytes], so that batching cannot hide data volume:

- a header of 2 bytes (kind, local address) on every message;
- a coordinate or radius: 2 bytes (centimetres, 16 bit), so a point or waypoint is 4 bytes and a
  reported obstacle point 6 (x, y and sigma in millimetres);
- cells: one flag byte per cell, run-length encoded as (flag, run length <= 255) pairs.

Addresses are local ("Communication"): a node sends to 0 (its parent) or 1..k (its children); the
payloads never carry a global identity or the swarm's size.
"""

from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

__all__ = [
    "HEADER",
    "KINDS",
    "ArrivedMsg",
    "AssignMsg",
    "InfoMsg",
    "LosHintMsg",
    "MapDownMsg",
    "MapReportMsg",
    "Message",
    "MoveMsg",
    "PointMsg",
    "RequestInfoMsg",
    "ScanCompleteMsg",
    "ScanMsg",
    "SettledMsg",
    "StartMsg",
    "rle_bytes",
]

#: Bytes of every message's header: kind and local address.
HEADER = 2
#: Bytes of one coordinate, radius or sigma (16 bit).
WORD = 2


def rle_bytes(flags: np.ndarray) -> int:
    """Bytes of a flag raster (row-major) run-length encoded as (flag, length <= 255) pairs."""
    flat = np.asarray(flags).ravel()
    if flat.size == 0:
        return 0
    starts = np.flatnonzero(np.r_[True, flat[1:] != flat[:-1]])
    lengths = np.diff(np.r_[starts, flat.size])
    return int(2 * np.ceil(lengths / 255).sum())


@dataclass(frozen=True)
class Message:
    """Base of every message: its kind and what the log counts."""

    KIND: ClassVar[str] = "message"
    #: "startup" messages (radius discovery) are counted apart from "task" messages (README
    #: "Choices": message bytes).
    PHASE: ClassVar[str] = "task"

    @property
    def items(self) -> int:
        """Points, cells or waypoints carried."""
        return 0

    @property
    def nbytes(self) -> int:
        """Size under the fixed encoding."""
        return HEADER


@dataclass(frozen=True)
class RequestInfoMsg(Message):
    """M1, parent -> child at start-up: "give me your location and bubble limits"."""

    KIND: ClassVar[str] = "REQUEST_INFO"
    PHASE: ClassVar[str] = "startup"


@dataclass(frozen=True)
class InfoMsg(Message):
    """M2, child -> parent: current location and the child's bubble limits (m)."""

    KIND: ClassVar[str] = "INFO"
    PHASE: ClassVar[str] = "startup"
    x: float
    y: float
    r_min: float
    r_max: float

    @property
    def nbytes(self) -> int:
        """Size under the fixed encoding."""
        return HEADER + 4 * WORD


@dataclass(frozen=True)
class MoveMsg(Message):
    """M3, parent -> child: drive these waypoints (m, ``(k, 2)``; the smoothed path)."""

    KIND: ClassVar[str] = "MOVE"
    waypoints: np.ndarray = field(compare=False)

    @property
    def items(self) -> int:
        """Items carried."""
        return len(self.waypoints)

    @property
    def nbytes(self) -> int:
        """Size under the fixed encoding."""
        return HEADER + 1 + 2 * WORD * len(self.waypoints)


@dataclass(frozen=True)
class ArrivedMsg(Message):
    """M4, child -> parent: the last waypoint is reached."""

    KIND: ClassVar[str] = "ARRIVED"


@dataclass(frozen=True)
class SettledMsg(Message):
    """Worker -> queen, only with ``subtree_transits="staggered"`` (ours, not the report's):
    every scout the worker placed (or moved out of the way) in its bubble's first round has
    arrived, so the next subtree may move.
    """

    KIND: ClassVar[str] = "SETTLED"


@dataclass(frozen=True)
class ScanMsg(Message):
    """M5, parent -> child: gather information within radius ``r`` (m) of where you are."""

    KIND: ClassVar[str] = "SCAN"
    r: float

    @property
    def nbytes(self) -> int:
        """Size under the fixed encoding."""
        return HEADER + WORD


@dataclass(frozen=True)
class AssignMsg(Message):
    """M3 + M5 as one message (switch ``combine_move_scan``): drive, then scan radius ``r``."""

    KIND: ClassVar[str] = "ASSIGN"
    waypoints: np.ndarray = field(compare=False)
    r: float = 0.0

    @property
    def items(self) -> int:
        """Items carried."""
        return len(self.waypoints)

    @property
    def nbytes(self) -> int:
        """Size under the fixed encoding."""
        return HEADER + 1 + 2 * WORD * len(self.waypoints) + WORD


@dataclass(frozen=True)
class PointMsg(Message):
    """M6, child -> parent: an obstacle at ``(x, y)`` (m) with position std ``sigma`` (m)."""

    KIND: ClassVar[str] = "POINT"
    x: float
    y: float
    sigma: float

    @property
    def items(self) -> int:
        """Items carried."""
        return 1

    @property
    def nbytes(self) -> int:
        """Size under the fixed encoding."""
        return HEADER + 3 * WORD


@dataclass(frozen=True)
class ScanCompleteMsg(Message):
    """M7, child -> parent: the bubble is done; ``infer_los`` asks the parent to infer
    line-of-sight shadowing (a scout) or not (a worker, which lists its unscanned cells).
    """

    KIND: ClassVar[str] = "SCAN_COMPLETE"
    infer_los: bool

    @property
    def nbytes(self) -> int:
        """Size under the fixed encoding."""
        return HEADER + 1


@dataclass(frozen=True)
class LosHintMsg(Message):
    """The scout's line-of-sight hint as its own message (switch ``los_hint_separate``)."""

    KIND: ClassVar[str] = "LOS_HINT"


@dataclass(frozen=True)
class MapReportMsg(Message):
    """M8, worker -> parent: accepted obstacle points ``(k, 3)`` (x, y, sigma; m) and the
    in-bubble cells still unscanned (centres, ``(m, 2)``), encoded as a flag raster of the
    bubble's box with ``unscanned_rle`` bytes.
    """

    KIND: ClassVar[str] = "MAP_REPORT"
    points: np.ndarray = field(compare=False)
    unscanned: np.ndarray = field(compare=False)
    unscanned_rle: int = 0

    @property
    def items(self) -> int:
        """Items carried."""
        return len(self.points) + len(self.unscanned)

    @property
    def nbytes(self) -> int:
        """Size under the fixed encoding."""
        return HEADER + WORD + 3 * WORD * len(self.points) + 4 * WORD + self.unscanned_rle


@dataclass(frozen=True)
class MapDownMsg(Message):
    """M9, parent -> a child with children: the parent's known cells in a window (a
    :class:`~models.hierarchy.probmap.MapWindow`), each cell one flag (unknown, free, blocked).
    """

    KIND: ClassVar[str] = "MAP_DOWN"
    window: object = field(compare=False)
    tau: float = 0.5

    @property
    def items(self) -> int:
        """Items carried."""
        return int(self.window.known_cells)

    @property
    def nbytes(self) -> int:
        """Size under the fixed encoding."""
        flags = np.where(
            self.window.scanned, np.where(self.window.blocked >= self.tau, 2, 1), 0
        ).astype(np.uint8)
        return HEADER + 4 * WORD + rle_bytes(flags)


@dataclass(frozen=True)
class StartMsg(Message):
    """M10, operator -> queen: the bounds of the area to map (m)."""

    KIND: ClassVar[str] = "START"
    x_min: float
    y_min: float
    x_max: float
    y_max: float

    @property
    def nbytes(self) -> int:
        """Size under the fixed encoding."""
        return HEADER + 4 * WORD


#: Every message kind, in catalogue order (SETTLED, sent only when transits are staggered, is
#: counted apart so that the summary of the report's set-up keeps its columns).
KINDS = tuple(
    m.KIND
    for m in (
        RequestInfoMsg,
        InfoMsg,
        MoveMsg,
        ArrivedMsg,
        ScanMsg,
        PointMsg,
        ScanCompleteMsg,
        MapReportMsg,
        MapDownMsg,
        StartMsg,
        AssignMsg,
        LosHintMsg,
    )
)
