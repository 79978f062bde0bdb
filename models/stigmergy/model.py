"""StigmergyModel: UAV swarm deployment with virtual pheromone (Arnaldo et al. 2018).

One beacon sits at p0; a new wander robot takes off from p0 every launch period (eta = 0.01
robots per 0.5 s step = one per 50 s). Three SimPy processes tell the story:

- the launcher: a new :class:`~models.stigmergy.agents.UAV` every launch period while the
  swarm has room; each runs its own behaviour, :meth:`UAV.wander
  <models.stigmergy.agents.UAV.wander>` (fly, then land as a beacon);
- the model step (every 0.5 s): each wander checks its link to the swarm and its flight ends
  -- it lands, a beacon that leaves a footprint -- when the nearest beacon is l_i or farther
  away; the others pick their heading f = a1 f1 + a2 f2 + a3 f3
  (:mod:`models.stigmergy.wander`, vectorised over every flyer) and deposit pheromone;
- the coverage sensor (every second): what the wanders see is added to ca; the run ends when
  ca reaches 95 % (or at the time limit).

Between model steps the wanders fly their heading at full speed in the one vectorised physics
process.
"""

import numpy as np
import pandas as pd

from abm.arena import Arena
from abm.coverage import CoverageRaster, raster_bytes
from abm.errors import ConfigError
from abm.model import SwarmModel
from abm.pheromone import PheromoneField, field_bytes
from abm.physics import FlightParams
from abm.styles import StateStyle
from models.environments.bitmap import MAPS, load_map, map_digest, map_entropy
from models.stigmergy import published
from models.stigmergy.agents import UAV
from models.stigmergy.params import P0, StigmergyParams
from models.stigmergy.units import SUMMARY_UNITS
from models.stigmergy.wander import WanderController, nearest_distance

__all__ = ["StigmergyModel"]


class StigmergyModel(SwarmModel):
    """Wander/beacon swarm with virtual stigmergy.

    Every field of :class:`StigmergyParams` is a keyword of the constructor, e.g.
    ``StigmergyModel(map="hall100", pheromone_radius=20.0, seed=1)``. The parameters follow the
    paper's tuples Psi = (C_dw, C_db, C_eps, C_rw, C_rb, l_i) and Gamma = (r_u, eta, p0,
    a1..a4), as we read the garbled text (see :mod:`models.stigmergy.params`).

    Args:
        seed: seed of the model's random generator.
        **params: fields of :class:`StigmergyParams`.

    """

    Params = StigmergyParams
    STATES = ("wander", "beacon")
    STATE_STYLES = {
        "wander": StateStyle("#E69F00", marker="D", size=40.0, layer=6.0),
        "beacon": StateStyle("#0072B2", marker="o", size=45.0, layer=5.0),
    }
    MACRO = published.MACRO
    PUBLISHED = published.PUBLISHED
    CENSORED = published.CENSORED
    REPORT = published.REPORT
    APP = "models.stigmergy.app"
    FAULTS = frozenset({"robot"})

    SUMMARY_UNITS = SUMMARY_UNITS

    def __init__(self, *, seed: int | None = None, **params: object) -> None:
        p = self.make_params(**params)
        if isinstance(p.map, str) and p.map in MAPS and p.map_resolution is not None:
            raise ConfigError(
                f"map_resolution applies to map files and arrays; the built-in map {p.map!r} "
                f"has 1 m pixels, got map_resolution={p.map_resolution!r}"
            )
        arena = load_map(p.map, resolution=p.map_resolution or 1.0, parts=_map_parts(p))
        start = self._start(p, arena)
        super().__init__(
            p,
            arena,
            seed=seed,
            comm_range=p.l_i,
            flight=FlightParams(
                max_speed=p.max_speed, body_radius=p.body_radius, body_noise=p.body_noise
            ),
        )
        self.start = start
        self.launch_period = p.launch_period
        self.swarm_size = p.swarmsize
        self.map_name = arena.name
        self.entropy = map_entropy(arena)
        self.envsize = arena.width * arena.height
        self.coverage = CoverageRaster(
            arena, p.detection_range, line_of_sight=p.coverage_line_of_sight, around="cell"
        )
        self.pheromone = PheromoneField(
            arena.free.shape, arena.resolution, p.decay, mask=arena.free
        )
        self.controller = WanderController(self)
        self.physics.controller = self.controller
        #: positions (m) of the live beacons, the swarm a wander links to; row k is the
        #: beacon whose ``beacon_row`` is k
        self.beacon_positions = np.empty((0, 2))
        first = UAV(self, start, "beacon", "beacon", launch_index=0)
        self.faults.exempt(first)  # p0's beacon stands for the launch site
        first.land()
        self.env.process(self._launcher())
        self.env.process(self._model_steps())
        self.env.process(self._coverage_sensor())

    @staticmethod
    def _start(p: StigmergyParams, arena: Arena) -> np.ndarray:
        """p0: the given start, else the built-in map's, else (5, 80); must lie in free space."""
        if p.start is not None:
            start = p.start
        elif isinstance(p.map, str) and p.map in MAPS:
            start = MAPS[p.map].start
        else:
            start = P0
        start = np.asarray(start, dtype=float)
        if not arena.is_free(start[None])[0]:
            raise ConfigError(
                f"start {tuple(start.tolist())} lies inside a wall (or outside) of map "
                f"{arena.name!r} ({arena.width:g} x {arena.height:g} m)"
            )
        return start

    # ------------------------------------------------------------------ processes
    def _launcher(self):
        """A new UAV every launch period, while the swarm has room; it wanders, then lands."""
        while len(self.agents_by_type[UAV]) < self.swarm_size:
            yield self.env.timeout(self.launch_period)
            index = len(self.agents_by_type[UAV])  # p0's beacon is 0
            robot = UAV(self, self.start, "wander", "flight", launch_index=index)
            self.recorder.log("launch", robot.unique_id)
            robot.start(robot.wander())

    def _model_steps(self):
        """The paper's model step: links checked, landings, headings and deposits."""
        while True:
            yield self.env.timeout(self.params.model_step)
            self.controller.model_step()

    def _coverage_sensor(self):
        """Every ``coverage_interval`` s what the flying robots see is added to ca."""
        while True:
            yield self.env.timeout(self.params.coverage_interval)
            if self.physics.n_flying:
                self.stamp_coverage(self.physics.pos)

    # ------------------------------------------------------------------ beacons
    def add_beacon(self, position: np.ndarray) -> int:
        """A UAV landed at ``position`` (m): from now on it relays (wanders link to it) and its
        sensors see around it. Returns its row in :attr:`beacon_positions`.
        """
        row = len(self.beacon_positions)
        self.beacon_positions = np.vstack([self.beacon_positions, position[None]])
        self.stamp_coverage(position[None])
        return row

    def on_robot_failed(self, robot: UAV) -> None:
        """A failed beacon stops relaying: wanders no longer link to it (so they fly on until
        the next live beacon is l_i away), and the beacons after its row move up one. Its
        footprint stays and decays like every deposit (C_eps); a failed wander has left the
        air already.
        """
        row = robot.beacon_row
        if row is None:
            return
        robot.beacon_row = None
        self.beacon_positions = np.delete(self.beacon_positions, row, axis=0)
        for uav in self.agents_by_type[UAV]:
            if uav.beacon_row is not None and uav.beacon_row > row:
                uav.beacon_row -= 1

    # ------------------------------------------------------------------ sensing
    def link_distance(self, points: np.ndarray) -> np.ndarray:
        """Distance (m) from each point to the nearest beacon (its link to the swarm)."""
        return nearest_distance(np.atleast_2d(points), self.beacon_positions)

    def stamp_coverage(self, points: np.ndarray) -> None:
        """Add what sensors at ``points`` see to ca; ends the run at the coverage target."""
        self.coverage.stamp(points, self.env.now)
        if self.ca >= self.params.coverage_target:
            self.finish("coverage")

    @property
    def ca(self) -> float:
        """Fraction of free area seen by any robot at any time."""
        return self.coverage.fraction

    def cb(self) -> float:
        """Fraction of free area seen by the robots where they are now (all states)."""
        live = [r.position for r in self.agents_by_type[UAV] if not r.failed]
        return self.coverage.seen_fraction(np.array(live).reshape(-1, 2))

    # ------------------------------------------------------------------ data
    def state_counts(self) -> pd.DataFrame:
        """Robots per state after every change: columns ``time``, ``wander``, ``beacon``."""
        return super().state_counts()

    def samples(self) -> pd.DataFrame:
        """The area seen, ca (%), every ``ca_sample_period`` s from 0 until the first sample
        at or after the end of the run (which holds the final ca).
        """
        step = self.params.ca_sample_period
        times = step * np.arange(int(np.ceil(self.env.now / step)) + 1)
        return pd.DataFrame({"time": times, "ca": 100.0 * self.coverage.fraction_at(times)})

    def metrics(self) -> dict:
        """The run's Table 1 row: final w, b, ca, cb (%), and the map's figures."""
        counts = self.recorder.counts
        return {
            "map": self.map_name,
            "seed": self.seed,
            "wander": counts["wander"],
            "beacon": counts["beacon"],
            "robots": len(self.agents_by_type[UAV]),
            "ca": 100.0 * self.ca,
            "cb": 100.0 * self.cb(),
            "entropy": self.entropy,
            "envsize": self.envsize,
            "map_digest": map_digest(self.arena),
        }


def _map_parts(p: StigmergyParams):
    """What the model allocates per map pixel besides the arena (bytes by part, for the map
    loader's memory check): the coverage raster, the pheromone field with its visibility
    tables or weights, and the obstacle field f2 (two float64 a pixel).
    """
    radii = (p.c_rw, p.pheromone_radius)
    seen = radii if p.deposit_line_of_sight else ()
    if p.f1_line_of_sight:
        seen = (*seen, p.pheromone_radius)
    relative = (p.pheromone_radius,) if p.f1_relative and not p.f1_line_of_sight else ()

    def parts(shape: tuple[int, int]) -> dict[str, float]:
        resolution = 1.0 if isinstance(p.map, str) and p.map in MAPS else p.map_resolution or 1.0
        return {
            "coverage raster": raster_bytes(shape, resolution),
            **field_bytes(shape, resolution, radii, seen, relative),
            "obstacle field f2": 16.0 * shape[0] * shape[1],
        }

    return parts
