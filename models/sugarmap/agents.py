"""The two roles of a SugarMap swarm (Purohit et al. 2013, Sect. 3): anchors and explorers.

Anchors fly out from the entrance, spread by RToF checks (Fig. 3) and land to serve as the
radio beacons every signature is measured to; explorers wait at their start cells until the
anchors have landed, then cover the arena while the base station localises them by their
signatures (Sect. 3.2-3.4, eqs. 1-11).

The per-tick work over all robots of a role -- the flight step of the dispersing anchors, the
explorers' motion, signatures and particle filters -- is vectorised on the model over rows of
its arrays; each robot knows its row (``row``) and holds its own part of the flowchart: an
anchor's RToF check and landing, an explorer's deployment, bump, stop and revisit record.
"""

import numpy as np

from abm.robot import Robot
from models.sugarmap.particles import Match
from models.sugarmap.planner import CoveragePlanner

__all__ = ["FALSE_MATCH", "Anchor", "Explorer"]

#: A match whose two true positions are farther apart than this is a false match (m).
FALSE_MATCH = 2.0


class Anchor(Robot):
    """An anchor MAV: disperses from the entrance (Fig. 3), then sits landed as a beacon.

    Args:
        model: the SugarMap model.
        position: where it takes off (m).
        row: its row in the model's anchor arrays.

    Attributes:
        row: its launch index, and its row in the model's anchor arrays: flight positions
            (``anchor_pos``), headings, ``flying``, the RToF model's anchors and the column
            of every signature (its dimension of eq. 11).

    """

    def __init__(self, model, position: np.ndarray, row: int) -> None:
        super().__init__(model, position, "dispersing", "fly")
        self.row = row

    def launch(self) -> None:
        """Take off (Fig. 3, start): join the radio network where it is."""
        self.model.comms.add(self.unique_id, self.position.copy())
        self.model.recorder.log("launch", self.unique_id)

    def check(
        self, ids: np.ndarray, positions: np.ndarray, heading: float, proximity: float
    ) -> float | None:
        """One RToF check of Fig. 3 (D9-D15), at the end of a dispersion leg.

        It asks every other anchor for an RToF reading (true distance plus Gaussian noise of
        sd ``rtof_noise``): if one does not answer, it retraces; if none is within
        ``proximity`` (the proximity threshold), or it is the only anchor, it stops.

        Args:
            ids: the anchors' ids, by row.
            positions: the anchors' positions by row (m).
            heading: its heading on the leg it ends (deg).
            proximity: the proximity threshold (m).

        Returns:
            The heading of its next leg (deg): its own turned by 180 deg to retrace, or a
            new uniformly random one; None when it should land here.

        """
        others = np.delete(np.arange(len(ids)), self.row)
        if not len(others):
            return None
        linked = set(self.model.comms.neighbours(self.unique_id))
        if any(ids[o] not in linked for o in others):
            return (heading + 180.0) % 360.0
        model = self.model
        rtof = np.hypot(*(positions[others] - positions[self.row]).T) + model.rng.normal(
            0.0, model.params.rtof_noise, len(others)
        )
        if rtof.min() > proximity:
            return None
        return float(model.rng.uniform(0.0, 360.0))

    def land(self) -> None:
        """Land for good where it is (Fig. 3, D13 or InitCutoff): from now on a beacon."""
        self.set_state("anchor")
        self.set_mode("landed")
        x, y = self.position
        self.model.recorder.log("land", self.unique_id, x=x, y=y)


class Explorer(Robot):
    """An explorer MAV: waits at its start cell, then covers the arena (Sect. 3.2-3.4).

    Args:
        model: the SugarMap model.
        position: its start (the centre of its start cell, m).
        row: its row in the model's explorer arrays.

    Attributes:
        row: its row in the model's explorer arrays: true and presumed positions, headings,
            ``active``, its signatures and particles in the filter.
        planner: its coverage planner (Fig. 4) on the estimate grid; None but for SugarMap.
        truth: the true positions where the base station stored its signatures, in the
            order stored (to score a revisit match as true or false).
        true_matches: its revisit matches within :data:`FALSE_MATCH` of the truth.
        false_matches: its revisit matches farther than that (false matches).

    """

    def __init__(self, model, position: np.ndarray, row: int) -> None:
        super().__init__(model, position, "waiting", "fly")
        self.row = row
        self.planner: CoveragePlanner | None = None
        self.truth: list[np.ndarray] = []
        self.true_matches = 0
        self.false_matches = 0

    def deploy(self) -> None:
        """The anchors have landed (tau = 0): start exploring, on the radio network."""
        self.set_state("exploring")
        self.model.comms.add(self.unique_id, self.position.copy())

    def bumped(self) -> None:
        """It flew into a wall it could not see: a collision, and its planner learns the way
        ahead is blocked for a while.
        """
        self.model.collision("wall", self.unique_id)
        if self.planner is not None:
            self.planner.blocked(self.model.env.now)

    def stop(self) -> None:
        """No anchor in radio range: it stops for good (README "Choices": stop rule)."""
        self.set_state("stopped")
        self.model.recorder.log("stopped", self.unique_id)

    def record(self, match: Match, here: np.ndarray) -> None:
        """The base station's revisit test on its new signature (eq. 11) gave ``match``:
        score a match against the true positions (a false match when farther than
        :data:`FALSE_MATCH`), or note where the new signature was stored.

        Args:
            match: the revisit test's result.
            here: its true position now (m).

        """
        if match.matched:
            gap = np.hypot(*(here - self.truth[match.index]))
            self.false_matches += int(gap > FALSE_MATCH)
            self.true_matches += int(gap <= FALSE_MATCH)
        else:
            self.truth.append(here.copy())
