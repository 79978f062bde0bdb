"""The message log: every transmission counted, one row per hop, by kind, sender, receiver,
payload items and bytes (the unit message comparisons count), and which rows one radio
broadcast on a shared channel sent at once (the other accounting, :meth:`MessageLog.transmissions`).
"""

from collections.abc import Iterator
from contextlib import contextmanager
from itertools import count

import pandas as pd

from abm.comms.policies import Node

__all__ = ["MessageLog"]


class MessageLog:
    """Every transmission over one link, one row per hop (the unit the comparisons count).

    Columns: ``time`` (s), ``src``, ``dst``, ``kind``, ``items`` (points, cells or waypoints
    carried), ``bytes`` (under the sender's declared encoding), ``phase`` ("startup" or
    "task"), ``origin`` (the node where the information arose; the sender when it is its own),
    ``hop`` (0 for the first transmission of that information) and ``tx``: the radio
    transmission the row belongs to. Rows recorded inside one :meth:`shared` block are the
    copies of one message sent to several destinations at once, which a shared channel carries
    as one broadcast and so share a ``tx``; every other row is a transmission of its own.
    """

    COLUMNS = ("time", "src", "dst", "kind", "items", "bytes", "phase", "origin", "hop", "tx")

    def __init__(self) -> None:
        self._rows: list[tuple] = []
        self._ids = count()
        self._shared: int | None = None

    @contextmanager
    def shared(self) -> Iterator[None]:
        """Within the block, every row recorded is a copy of one broadcast (one ``tx``); nested
        blocks join the outer one.
        """
        if self._shared is not None:
            yield
            return
        self._shared = next(self._ids)
        try:
            yield
        finally:
            self._shared = None

    def record(
        self,
        time: float,
        src: Node,
        dst: Node,
        kind: str,
        items: int = 0,
        nbytes: int = 0,
        phase: str = "task",
        origin: Node | None = None,
        hop: int = 0,
    ) -> None:
        """Log one transmission (a copy of the current :meth:`shared` broadcast, if any)."""
        tx = next(self._ids) if self._shared is None else self._shared
        self._rows.append(
            (
                time,
                src,
                dst,
                kind,
                int(items),
                int(nbytes),
                phase,
                src if origin is None else origin,
                int(hop),
                tx,
            )
        )

    def __len__(self) -> int:
        return len(self._rows)

    def frame(self) -> pd.DataFrame:
        """The log as a DataFrame, in sending order."""
        return pd.DataFrame(self._rows, columns=list(self.COLUMNS))

    def transmissions(self, phase: str | None = None) -> int:
        """Radio transmissions on a shared channel (broadcast accounting): one per broadcast,
        however many destinations it reached, and one per other row; ``phase`` keeps only the
        rows of that phase. ``len(log)`` is the per-destination count.
        """
        return len({row[-1] for row in self._rows if phase is None or row[6] == phase})

    def load(self, frame: pd.DataFrame | None = None) -> pd.Series:
        """Messages sent plus received per node (the per-node load of a topology); ``frame``:
        the log's :meth:`frame` if the caller has it already (a large log's frame costs a
        tenth of a second).
        """
        if frame is None:
            frame = self.frame()
        if frame.empty:
            return pd.Series(dtype=int)
        return pd.concat([frame["src"], frame["dst"]]).value_counts()
