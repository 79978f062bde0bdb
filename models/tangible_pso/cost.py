"""The coverage cost of eq. 1 (Saska et al. 2016, Sect. 4.1), for many swarm distributions at once.

``CF(X) = sum_xy max(0, A_xy - A_max sum_{i in O(x,y)} S_opt / S_i)``: O(x, y) are the MAVs whose
camera footprint fully contains cell (x, y); S_i is the area of MAV i's footprint and S_opt the
area at the optimal altitude. The footprint is a square of side ``2 z tan(theta / 2)`` under a
level MAV (our reading: no pitch or roll); below the optimal altitude an MAV gains no more per
cell, so ``S_opt / S_i = min(1, (z_opt / z)^2)``. Only cells with A > 0 can add cost, so only
they are evaluated.
"""

from dataclasses import dataclass

import numpy as np

from abm import portable

__all__ = ["CoverageCost"]


@dataclass(frozen=True, eq=False)
class CoverageCost:
    """Eq. 1 on one AoI map.

    Attributes:
        aoi: the AoI map A, ``(rows, cols)``, 1 m cells, row 0 south.
        a_max: A_max.
        camera_angle: theta, the camera's viewing angle (degrees).
        z_opt: the optimal altitude (m).

    """

    aoi: np.ndarray
    a_max: float
    camera_angle: float
    z_opt: float

    def __post_init__(self) -> None:
        rows, cols = np.nonzero(self.aoi > 0)
        object.__setattr__(self, "_x0", cols.astype(float))
        object.__setattr__(self, "_y0", rows.astype(float))
        object.__setattr__(self, "_a", self.aoi[rows, cols].astype(float))

    @property
    def total(self) -> float:
        """The cost with nothing observed: the sum of A."""
        return float(self._a.sum())

    def half_side(self, z: np.ndarray) -> np.ndarray:
        """Half the side of the footprint square at altitude ``z`` (m)."""
        return z * portable.tan(np.radians(self.camera_angle) / 2.0)

    def __call__(self, positions: np.ndarray) -> np.ndarray:
        """CF of every distribution: ``(..., n, 3)`` MAV positions (m) -> ``(...)`` costs."""
        p = np.asarray(positions, dtype=float)
        x, y, z = p[..., 0, None], p[..., 1, None], p[..., 2, None]
        h = self.half_side(z) + 1e-9  # a cell on the footprint's edge is inside it
        inside = (self._x0 >= x - h) & (self._x0 + 1.0 <= x + h)
        inside &= (self._y0 >= y - h) & (self._y0 + 1.0 <= y + h)
        share = np.minimum(1.0, (self.z_opt / np.maximum(z, 1e-12)) ** 2)
        gained = self.a_max * (inside * share).sum(axis=-2)
        return np.maximum(0.0, self._a - gained).sum(axis=-1)
