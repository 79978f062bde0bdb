"""A test model whose summary is one noisy measurement of a parameter (not a swarm).

``y ~ N(mu, sigma^2)`` with ``sigma`` known: with a uniform prior on ``mu`` much wider than
``sigma`` and one observation ``y0``, the posterior of ``mu`` is (to within the prior's cut
tails) the conjugate normal ``N(y0, sigma^2)``, so a calibration of ``mu`` against ``y0`` has a
known answer: mean ``y0``, standard deviation ``sigma``. :data:`PUBLISHED` holds such an
observation as a level with a spread, beside two records ``--target published`` must skip.
"""

from dataclasses import dataclass

import numpy as np

from abm.arena import Arena
from abm.model import SwarmModel
from abm.params import SwarmParams, param
from abm.published import Published


@dataclass(frozen=True)
class NormalParams(SwarmParams):
    """The mean and spread of the measurement.

    Attributes:
        mu: the measured quantity's true value.
        sigma: the measurement noise's standard deviation.
        time_limit: longest run (s).

    """

    mu: float = param(0.0, low=-100.0, high=100.0)
    sigma: float = param(1.0, low=0.0, low_open=True)
    time_limit: float = param(1.0, low=0.0, low_open=True)


#: One usable level (y0 = 3 with spread 1 at sigma = 1); one without a spread; one whose
#: condition fixes mu (skipped when mu is free).
PUBLISHED = (
    Published("toy", "y", {"sigma": 1.0}, 3.0, "level", "y", "band", spread=1.0, source="T1"),
    Published("toy", "y", {"sigma": 1.0}, 3.0, "level", "y", "band", source="T2"),
    Published("toy", "y", {"mu": 2.0}, 2.0, "level", "y", "band", spread=1.0, source="T3"),
)


class NormalModel(SwarmModel):
    """No robots: the run ends at once; its summary holds ``y``, drawn from the run's seed."""

    Params = NormalParams
    STATES = ("idle",)
    PUBLISHED = PUBLISHED

    def __init__(self, *, seed: int | None = None, **params: object) -> None:
        p = self.make_params(**params)
        arena = Arena(np.ones((3, 3), dtype=bool), 1.0, name="cell")
        super().__init__(p, arena, seed=seed, physics=False)  # nothing flies
        self._y = float(np.random.default_rng(seed).normal(p.mu, p.sigma))
        self.env.process(self._end())

    def _end(self):
        yield self.env.timeout(0.0)
        self.finish("measured")

    def metrics(self) -> dict:
        """The noisy measurement ``y``."""
        return {"y": self._y}
