"""The wander robots' flight, vectorised over every flying robot.

At every model step (0.5 s, a SimPy process of the model) each wander robot:

1. checks its link to the swarm: when the nearest beacon is ``l_i`` away or farther, it lands
   (its flight ends at once; its SimPy process then turns it into a beacon); with
   ``link_model="radio"`` the link is a received-power margin (:func:`radio_margin`) and it
   lands when the margin falls to 0;
2. picks its heading ``f_hat = f / |f|`` with ``f = a1 f1 + a2 f2 + a3 f3``:
   f1 towards less pheromone within C_rb (:meth:`PheromoneField.lower_direction`), every
   pixel of the disc read, a reading's importance falling as 1 / distance^2 (``f1_falloff``),
   f2 away from the walls within r_u (a precomputed repulsion grid, one lookup per robot),
   f3 = f_hat(t-1) + a4 * U[-1, 1]^2, a slight random variation of the current heading;
   each component is normalised to a unit vector before weighting (our reading: the paper's
   weights 0.2 / 0.4 / 0.4 only make sense for components of comparable size);
3. deposits pheromone (radius C_rw, intensity C_dw).

A robot picks its first heading when it takes off. Between model steps the robots keep their
heading at full speed: the physics asks :meth:`WanderController.control` every tick.
"""

import numpy as np
from numba import njit
from scipy import ndimage

from abm import neighbours, portable
from abm.arena import Arena
from abm.disc_cells import disc_offsets
from abm.errors import check_range
from abm.pheromone import PheromoneField
from abm.physics import Physics

__all__ = [
    "WanderController",
    "nearest_distance",
    "radio_margin",
    "repulsion_grid",
    "sonar_grid",
    "unit",
]


def unit(v: np.ndarray) -> np.ndarray:
    """Row-wise unit vectors (zero rows stay zero)."""
    norm = np.hypot(v[:, 0], v[:, 1])
    return v / np.where(norm > 0, norm, 1.0)[:, None]


def repulsion_grid(arena: Arena, radius: float) -> np.ndarray:
    """f2 per pixel, ``(rows, cols, 2)``: ``sum_j (p - r_j) / |p - r_j|`` over wall pixels r_j
    within ``radius`` of the pixel p (outside the map counts as wall).
    """
    dy, dx = disc_offsets(radius, arena.resolution)
    r = int(max(np.abs(dx).max(), np.abs(dy).max()))
    kx = np.zeros((2 * r + 1, 2 * r + 1))
    ky = np.zeros_like(kx)
    d = np.hypot(dx, dy)
    ok = d > 0
    kx[dy[ok] + r, dx[ok] + r] = -dx[ok] / d[ok]
    ky[dy[ok] + r, dx[ok] + r] = -dy[ok] / d[ok]
    walls = (~arena.free).astype(float)
    fx = ndimage.correlate(walls, kx, mode="constant", cval=1.0)
    fy = ndimage.correlate(walls, ky, mode="constant", cval=1.0)
    return np.stack([fx, fy], axis=-1)


def sonar_grid(arena: Arena, radius: float, beams: int) -> np.ndarray:
    """f2 per pixel from a ring of ``beams`` range sensors, ``(rows, cols, 2)``.

    From each pixel centre p, beam j (world-fixed, every 360 / beams degrees, the first along
    +x) detects the first wall within ``radius`` at r_j; ``f2 = sum_j (p - r_j) / |p - r_j|``
    over the beams that detect one (the paper's "obstacles detected by the ultrasonic
    sensors", each pointing away from its obstacle).
    """
    check_range("beams", beams, 1, integer=True)
    iy, ix = np.nonzero(arena.free)
    centres = arena.cell_centre(ix, iy)
    angles = 2 * np.pi * np.arange(beams) / beams
    directions = np.stack([portable.cos(angles), portable.sin(angles)], axis=1)
    out = np.zeros(arena.free.shape + (2,))
    for d in directions:
        hit = arena.raycast(centres, np.broadcast_to(d, centres.shape), radius) < radius
        out[iy[hit], ix[hit]] -= d
    return out


class WanderController:
    """The wanders' decisions (:meth:`model_step`, :meth:`launched`) and their flight
    (:meth:`control`, the physics' controller).

    Args:
        model: the model (reads its parameters, beacons and coverage).

    """

    def __init__(self, model) -> None:
        p = model.params
        self.model = model
        self.params = p
        self.physics: Physics = model.physics
        self.rng = model.rng
        self.arena = model.arena
        self.field: PheromoneField = model.pheromone
        if p.obstacle_beams:
            self.repulsion = sonar_grid(model.arena, p.obstacle_range, p.obstacle_beams)
        else:
            self.repulsion = repulsion_grid(model.arena, p.obstacle_range)
        self.physics.add_flyer_state("heading", 2)

    def control(self, physics: Physics) -> tuple[np.ndarray, np.ndarray]:
        """Every tick: fly the current headings at full speed (no flight ends here)."""
        heading = physics.flyer_state["heading"]
        return heading * self.params.max_speed, np.zeros(physics.n_flying, dtype=bool)

    def launched(self) -> None:
        """The newest flyer (the last row) picks its first heading."""
        heading = self.physics.flyer_state["heading"]
        heading[-1:] = self._headings(self.physics.pos[-1:], heading[-1:])

    def model_step(self) -> None:
        """Links, landings, headings and deposits of every flyer (one model step)."""
        physics = self.physics
        if physics.n_flying == 0:
            return
        p = self.params
        heading = physics.flyer_state["heading"]
        heading[:] = self._headings(physics.pos, heading)
        landing = self.landing(physics.pos)
        self.field.deposit(
            physics.pos[~landing],
            p.c_rw,
            p.wander_intensity,
            time=physics.env.now,
            line_of_sight=p.deposit_line_of_sight,
        )
        if landing.any():
            physics.finish(physics.ids[landing])

    def landing(self, pos: np.ndarray) -> np.ndarray:
        """Which flyers at ``pos`` find their link to the swarm at the threshold (land now)."""
        p = self.params
        beacons = self.model.beacon_positions
        if p.link_model == "distance":
            return nearest_distance(pos, beacons) >= p.l_i
        margin = radio_margin(
            pos,
            beacons,
            self.arena.wall_lengths(pos, beacons),
            p.l_i,
            p.link_exponent,
            p.link_wall_loss,
        )
        if p.link_fading_sd > 0:
            margin = margin + self.rng.normal(0.0, p.link_fading_sd, size=margin.shape)
        return margin <= 0.0

    def _headings(self, pos: np.ndarray, previous: np.ndarray) -> np.ndarray:
        p = self.params
        self.field.advance(self.physics.env.now)
        f1 = self.field.lower_direction(
            pos,
            p.pheromone_radius,
            falloff=p.f1_falloff,
            relative=p.f1_relative,
            line_of_sight=p.f1_line_of_sight,
        )
        noise = self.rng.uniform(-1.0, 1.0, size=pos.shape)
        f_hat = _steer(
            f1, pos, previous, noise, self.repulsion, self.arena.resolution, p.a1, p.a2, p.a3, p.a4
        )
        still = (f_hat[:, 0] == 0) & (f_hat[:, 1] == 0)
        if still.any():  # a perfect cancellation: keep the random heading
            f_hat[still] = unit(self.rng.normal(size=(int(still.sum()), 2)))
        return f_hat


@njit(cache=True)
def _unit(x, y):
    norm = np.hypot(x, y)
    if norm > 0:
        return x / norm, y / norm
    return 0.0, 0.0


@njit(cache=True)
def _steer(f1, pos, previous, noise, repulsion, res, a1, a2, a3, a4):
    """``f_hat = unit(a1 unit(f1) + a2 unit(f2) + a3 unit(previous + a4 noise))`` per flyer,
    with f2 read from the repulsion grid under the flyer.
    """
    rows, cols = repulsion.shape[0], repulsion.shape[1]
    out = np.empty_like(f1)
    for i in range(f1.shape[0]):
        f1x, f1y = _unit(f1[i, 0], f1[i, 1])
        ix = min(max(int(np.floor(pos[i, 0] / res)), 0), cols - 1)
        iy = min(max(int(np.floor(pos[i, 1] / res)), 0), rows - 1)
        f2x, f2y = _unit(repulsion[iy, ix, 0], repulsion[iy, ix, 1])
        f3x, f3y = _unit(previous[i, 0] + a4 * noise[i, 0], previous[i, 1] + a4 * noise[i, 1])
        out[i, 0], out[i, 1] = _unit(a1 * f1x + a2 * f2x + a3 * f3x, a1 * f1y + a2 * f2y + a3 * f3y)
    return out


def radio_margin(
    points: np.ndarray,
    beacons: np.ndarray,
    walls: np.ndarray,
    threshold: float,
    exponent: float,
    wall_loss: float,
) -> np.ndarray:
    """Received-power margin (dB) of each point's best link over the landing threshold.

    ``max_j [10 n log10(l_i / d_j) - L w_j]``: log-distance path loss relative to the power
    at l_i in the open, minus L dB per metre of wall on the line to beacon j (a multi-wall
    radio model). Positive: the link is better than at l_i in the open; -inf without beacons.

    Args:
        points: ``(n, 2)`` positions (m).
        beacons: ``(m, 2)`` beacon positions (m).
        walls: ``(n, m)`` metres of wall between them (:meth:`Arena.wall_lengths`).
        threshold: l_i (m).
        exponent: n, the path-loss exponent.
        wall_loss: L (dB per metre of wall).

    """
    if beacons.shape[0] == 0:
        return np.full(points.shape[0], -np.inf)
    d = np.hypot(*(points[:, None, :] - beacons[None, :, :]).transpose(2, 0, 1))
    gain = 10.0 * exponent * portable.log10(threshold / np.maximum(d, 1e-9))
    power = gain - wall_loss * walls
    return power.max(axis=1)


def nearest_distance(points: np.ndarray, targets: np.ndarray) -> np.ndarray:
    """Distance from each point to the nearest target (inf without targets)."""
    return neighbours.nearest_distance(
        np.ascontiguousarray(points, dtype=float), np.ascontiguousarray(targets, dtype=float)
    )
