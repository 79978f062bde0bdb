"""The explorer controller of Stirling et al. (2010), Sect. 3.4.1 and Fig. 4, for all flyers.

Every control step each explorer measures N, the vector to its nearest beacon (relative
positioning, noisy), reads that beacon's desired direction D (length I_r), forms L = N + D, adds
the collision-avoidance vector C (away from walls sensed by the four distance sensors, magnitude
growing as 1/distance) and flies along T = L + C. When |T| <= eps at a spot where a beacon is
required, it ascends and attaches. All of this is computed at once for every flyer with numpy.
"""

import numpy as np

from abm.arena import CARDINALS, Arena
from abm.physics import Physics
from abm.sensors import distance_sensors, relative_positions
from models.beacon_explorer.beacon import BeaconNetwork
from models.beacon_explorer.params import BeaconExplorerParams

__all__ = ["ExplorerController"]


class ExplorerController:
    """Vectorised explorer behaviour; the physics calls :meth:`control` every tick.

    Args:
        arena: walls.
        beacons: the beacon network whose signals explorers follow.
        rng: the model's generator (sensor noise).
        params: the algorithm's constants.
        max_speed: cruising speed handed to the flight controller (m/s).

    """

    def __init__(
        self,
        arena: Arena,
        beacons: BeaconNetwork,
        rng: np.random.Generator,
        params: BeaconExplorerParams,
        max_speed: float,
        physics: Physics,
    ) -> None:
        self.arena = arena
        self.beacons = beacons
        self.rng = rng
        self.params = params
        self.max_speed = max_speed
        self._version = -1
        self._signals = None
        physics.add_flyer_state("T", 2)
        self._gain = min(1.0, physics.dt / params.filter_time)

    def _current_signals(self):
        if self._version != self.beacons.version:
            self._signals = self.beacons.signals()
            self._version = self.beacons.version
        return self._signals

    def nearest_beacon(self, points: np.ndarray, beacon_pos: np.ndarray) -> np.ndarray:
        """Row of the nearest beacon in line of sight for each point (-1 if none in C_r)."""
        diff = beacon_pos[None, :, :] - points[:, None, :]
        dist = np.hypot(diff[..., 0], diff[..., 1])
        dist[dist > self.params.comm_range] = np.inf
        rows = np.arange(len(points))
        for _ in range(4):
            nearest = np.argmin(dist, axis=1)
            d = dist[rows, nearest]
            check = np.isfinite(d)
            if not check.any():
                break
            blind = np.zeros(len(points), dtype=bool)
            blind[check] = ~self.arena.line_of_sight(points[check], beacon_pos[nearest[check]])
            if not blind.any():
                break
            dist[rows[blind], nearest[blind]] = np.inf
        nearest = np.argmin(dist, axis=1)
        return np.where(np.isfinite(dist[rows, nearest]), nearest, -1)

    def control(self, physics: Physics) -> tuple[np.ndarray, np.ndarray]:
        """Desired velocities of all flyers and which of them attach now."""
        p = self.params
        x = physics.pos
        n = len(x)
        _ids, beacon_pos, desired_vec, to_empty = self._current_signals()
        if len(beacon_pos) == 0:
            return np.zeros((n, 2)), np.zeros(n, dtype=bool)
        k = self.nearest_beacon(x, beacon_pos)
        lost = k < 0
        k = np.maximum(k, 0)
        N = relative_positions(beacon_pos[k] - x, self.rng)  # noqa: N806 - the paper's symbol
        D = desired_vec[k]  # noqa: N806
        L = N + D  # noqa: N806
        reading = distance_sensors(self.arena, x, self.rng, p.sensor_range, p.sensor_noise)
        push = p.avoid_gain * np.maximum(
            0.0, 1.0 / np.maximum(reading, 0.05) - 1.0 / p.sensor_range
        )
        C = -(push @ CARDINALS)  # noqa: N806
        # Each explorer low-pass filters its noisy T (a real sensor stack smooths at 10 Hz).
        T = physics.flyer_state["T"]  # noqa: N806
        T += self._gain * (L + C - T)  # noqa: N806
        size = np.hypot(T[:, 0], T[:, 1])
        desired = T * (self.max_speed / np.maximum(size, p.slow_radius))[:, None]
        desired[lost] = 0.0  # out of touch with every beacon: hover and wait
        attach = (
            ~lost
            & (size <= p.attach_eps)
            & (np.hypot(physics.vel[:, 0], physics.vel[:, 1]) <= p.attach_speed)
            & to_empty[k]
            & (np.hypot(N[:, 0], N[:, 1]) > p.interspace / 2)
        )
        return desired, attach
