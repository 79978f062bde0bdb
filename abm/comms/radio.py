"""The radio channel: log-normal shadowing (the log-distance path-loss model, the comm range
being the distance at which the mean received power equals the receiver's sensitivity).
"""

from dataclasses import dataclass

import numpy as np
from scipy.special import ndtr

from abm import portable
from abm.errors import check_range

__all__ = ["SHORTEST_LINK", "Shadowing"]

#: A link shorter than this (m) counts as this long: the path loss's log10 needs a distance > 0.
SHORTEST_LINK = 1e-9


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
        d = np.maximum(np.asarray(distance, dtype=float), SHORTEST_LINK)
        if self.sd == 0:
            return (d <= comm_range).astype(float)
        return ndtr(10.0 * self.exponent * portable.log10(comm_range / d) / self.sd)
