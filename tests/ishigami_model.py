"""A test model whose summary is the Ishigami function of its parameters (not a swarm).

Ishigami and Homma (1990): ``y = sin x1 + a sin^2 x2 + b x3^4 sin x1`` with ``x1, x2, x3``
uniform on ``[-pi, pi]``. With ``a = 7``, ``b = 0.1`` the Sobol' indices are known in closed
form (:data:`S1`, :data:`ST`), so a sensitivity sweep of this model checks the whole path:
design, plan, runs, storage and analysis. ``x4`` is accepted and ignored: an inert parameter
that a screening must rank last.
"""

import math
from dataclasses import dataclass

import numpy as np

from abm.arena import Arena
from abm.model import SwarmModel
from abm.params import SwarmParams, param

A, B = 7.0, 0.1
_V1 = 0.5 * (1 + B * math.pi**4 / 5) ** 2
_V2 = A**2 / 8
_V13 = B**2 * math.pi**8 * (1 / 18 - 1 / 50)
_V = _V1 + _V2 + _V13
#: Closed-form first-order and total indices of x1, x2, x3 (and x4, inert).
S1 = {"x1": _V1 / _V, "x2": _V2 / _V, "x3": 0.0, "x4": 0.0}
ST = {"x1": (_V1 + _V13) / _V, "x2": _V2 / _V, "x3": _V13 / _V, "x4": 0.0}


@dataclass(frozen=True)
class IshigamiParams(SwarmParams):
    """The inputs of the Ishigami function.

    Attributes:
        x1: first input (rad).
        x2: second input (rad).
        x3: third input (rad).
        x4: an input the function ignores.
        time_limit: longest run (s).

    """

    x1: float = param(0.0, low=-math.pi, high=math.pi)
    x2: float = param(0.0, low=-math.pi, high=math.pi)
    x3: float = param(0.0, low=-math.pi, high=math.pi)
    x4: int = param(0, low=0, high=10, integer=True)
    time_limit: float = param(1.0, low=0.0, low_open=True)


class IshigamiModel(SwarmModel):
    """No robots: the run ends at once and its summary holds ``y`` and ``x1_sine``."""

    Params = IshigamiParams
    STATES = ("idle",)

    def __init__(self, *, seed: int | None = None, **params: object) -> None:
        p = self.make_params(**params)
        arena = Arena(np.ones((3, 3), dtype=bool), 1.0, name="cell")
        super().__init__(p, arena, seed=seed, physics=False)  # nothing flies
        self.env.process(self._end())

    def _end(self):
        yield self.env.timeout(0.0)
        self.finish("evaluated")

    def metrics(self) -> dict:
        """The Ishigami function of the inputs, and sin x1 alone (x2, x3 inert for it)."""
        p = self.params
        y = math.sin(p.x1) + A * math.sin(p.x2) ** 2 + B * p.x3**4 * math.sin(p.x1)
        return {"y": y, "x1_sine": math.sin(p.x1)}
