"""The message log: every transmission counted, one row per hop, by kind, sender, receiver,
payload items and bytes (the unit message comparisons count).
"""

import pandas as pd

from abm.comms.policies import Node

__all__ = ["MessageLog"]


class MessageLog:
    """Every transmission over one link, one row per hop (the unit the comparisons count).

    Columns: ``time`` (s), ``src``, ``dst``, ``kind``, ``items`` (points, cells or waypoints
    carried), ``bytes`` (under the sender's declared encoding), ``phase`` ("startup" or
    "task"), ``origin`` (the node where the information arose; the sender when it is its own)
    and ``hop`` (0 for the first transmission of that information).
    """

    COLUMNS = ("time", "src", "dst", "kind", "items", "bytes", "phase", "origin", "hop")

    def __init__(self) -> None:
        self._rows: list[tuple] = []

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
        """Log one transmission."""
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
            )
        )

    def __len__(self) -> int:
        return len(self._rows)

    def frame(self) -> pd.DataFrame:
        """The log as a DataFrame, in sending order."""
        return pd.DataFrame(self._rows, columns=list(self.COLUMNS))

    def load(self) -> pd.Series:
        """Messages sent plus received per node (the per-node load of a topology)."""
        frame = self.frame()
        if frame.empty:
            return pd.Series(dtype=int)
        return pd.concat([frame["src"], frame["dst"]]).value_counts()
