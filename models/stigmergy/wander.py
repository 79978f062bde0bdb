"""The wander robots' flight, vectorised over every flying robot (one call per physics tick).

Every model step (0.5 s) each wander robot:

1. checks its link to the swarm: when the nearest beacon is ``l_i`` away or farther, it lands
   (the physics' done mask; the robot's SimPy process then turns it into a beacon);
2. picks its heading ``f_hat = f / |f|`` with ``f = a1 f1 + a2 f2 + a3 f3``:
   f1 towards less pheromone within C_rb (:meth:`PheromoneField.lower_direction`), every
   pixel of the disc read, a reading's importance falling as 1 / distance^2 (``f1_falloff``),
   f2 away from the walls within r_u (a precomputed repulsion grid, one lookup per robot),
   f3 = f_hat(t-1) + a4 * U[-1, 1]^2, a slight random variation of the current heading;
   each component is normalised to a unit vector before weighting (our reading: the paper's
   weights 0.2 / 0.4 / 0.4 only make sense for components of comparable size);
3. deposits pheromone (radius C_rw, intensity C_dw).

Between model steps (the physics ticks faster) the robots keep their heading at full speed.
"""

import numpy as np
from scipy import ndimage

from abm.arena import Arena
from abm.pheromone import PheromoneField, disc_offsets
from abm.physics import Physics

__all__ = ["WanderController", "repulsion_grid", "unit"]


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


class WanderController:
    """The physics controller of a :class:`StigmergyModel`.

    Args:
        model: the model (reads its parameters, pheromone field, beacons and coverage).

    """

    def __init__(self, model) -> None:
        self.model = model
        self.field: PheromoneField = model.pheromone
        self.rng = model.rng
        self.arena = model.arena
        self.repulsion = repulsion_grid(model.arena, model.obstacle_range)
        self.heading = model.physics.add_flyer_state("heading", 2)
        self._next_step = 0.0
        self._next_coverage = 0.0

    def control(self, physics: Physics) -> tuple[np.ndarray, np.ndarray]:
        """Desired velocities of all flyers and the mask of those landing now."""
        m = self.model
        now = physics.env.now
        heading = physics.flyer_state["heading"]
        n = physics.n_flying
        done = np.zeros(n, dtype=bool)
        due = now >= self._next_step - 1e-9
        fresh = np.hypot(heading[:, 0], heading[:, 1]) == 0
        if due or fresh.any():
            rows = np.arange(n) if due else np.nonzero(fresh)[0]
            heading[rows] = self._headings(physics.pos[rows], heading[rows])
        if due:
            self._next_step = now + m.model_step
            pos = physics.pos
            done = m.link_distance(pos) >= m.link_threshold
            self.field.deposit(pos[~done], m.wander_radius, m.wander_intensity, time=now)
            if now >= self._next_coverage - 1e-9:
                self._next_coverage = now + m.coverage_interval
                m.stamp_coverage(pos)
        return heading * m.max_speed, done

    def _headings(self, pos: np.ndarray, previous: np.ndarray) -> np.ndarray:
        m = self.model
        self.field.advance(m.env.now)
        f1 = unit(
            self.field.lower_direction(
                pos, m.pheromone_radius, falloff=m.f1_falloff, relative=m.f1_relative
            )
        )
        ix, iy = self.arena.cell_of(pos)
        ix = np.clip(ix, 0, self.arena.cols - 1)
        iy = np.clip(iy, 0, self.arena.rows - 1)
        f2 = unit(self.repulsion[iy, ix])
        f3 = unit(previous + m.a4 * self.rng.uniform(-1.0, 1.0, size=pos.shape))
        f = m.a1 * f1 + m.a2 * f2 + m.a3 * f3
        f_hat = unit(f)
        still = np.hypot(f_hat[:, 0], f_hat[:, 1]) == 0
        if still.any():  # a perfect cancellation: keep the random heading
            f_hat[still] = unit(self.rng.normal(size=(int(still.sum()), 2)))
        return f_hat
