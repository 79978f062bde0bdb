"""StigmergyModel: UAV swarm deployment with virtual pheromone (Arnaldo et al. 2018), SPEC B.

One beacon sits at p0; a new wander robot takes off from p0 every ``launch_period`` seconds
(eta = 0.01 robots per 0.5 s step = one per 50 s). Wanders fly along f = a1 f1 + a2 f2 + a3 f3
(see :mod:`models.stigmergy.wander`), leave pheromone, and land -- becoming beacons that leave
a footprint -- when the nearest beacon is ``l_i`` or farther away. Launches and landings are
SimPy events; all flight is the one vectorised physics process. The run ends at ``time_limit``
or when ca, the fraction of free area any robot has seen (detection radius 10 m), reaches 95 %.
"""

from pathlib import Path

import numpy as np
import pandas as pd

from abm.arena import Arena
from abm.coverage import visible_cells
from abm.errors import ConfigError, check_range
from abm.model import SwarmModel
from abm.pheromone import PheromoneField, disc_offsets
from abm.physics import FlightParams
from abm.robot import Robot
from abm.worlds.bitmap import MAPS, load_map, map_digest, map_entropy
from models.stigmergy.params import DEFAULTS
from models.stigmergy.wander import WanderController, nearest_distance

__all__ = ["StigmergyModel"]

_D = DEFAULTS


class StigmergyModel(SwarmModel):
    """Wander/beacon swarm with virtual stigmergy.

    Parameters follow the paper's tuples (our reading of the garbled text, see
    :mod:`models.stigmergy.params`): Psi = (C_dw = ``wander_intensity`` 0.03, C_db =
    (swarmsize - robotId) / swarmsize, C_eps = ``decay`` 1e-4 /s, C_rw = ``wander_radius``
    (default C_rb / 2), C_rb = ``pheromone_radius``, l_i = ``link_threshold`` (default C_rb));
    Gamma = (r_u = ``obstacle_range`` 5 m, an unlabelled 5 (unused), eta = ``launch_rate``
    0.01 robots per ``model_step`` of 0.5 s, p0 = ``start`` (5, 80), a1..a4 = 0.2, 0.4, 0.4, 0.4).

    Args:
        map: a built-in map name (``abm.worlds.MAPS``), a bitmap file (PNG/PGM/BMP/NPY, black
            = not navigable, ``map_resolution`` m per pixel) or an :class:`Arena`.
        pheromone_radius: C_rb, beacon footprint radius (m).
        seed: seed of the model's random generator.
        wander_radius: C_rw (m); None = C_rb / 2.
        wander_intensity: C_dw per step.
        decay: C_eps (1/s), exponential.
        link_threshold: l_i (m): a wander lands when no beacon is closer; None = C_rb.
        obstacle_range: r_u (m).
        obstacle_beams: range sensors in f2's ring (ours); 0 = every wall pixel within r_u.
        launch_rate: eta, robots per ``model_step``.
        model_step: the paper's model step (s): heading updates, deposits and landing checks.
        start: p0 (m); None = the map's default ((5, 80) for every built-in map).
        a1: weight of f1, towards less pheromone.
        a2: weight of f2, away from obstacles.
        a3: weight of f3, random walk.
        a4: random increment of f3.
        f1_falloff: a pheromone reading's importance in f1 falls as 1 / distance^f1_falloff
            (2: the paper's text; 1: its formula v / |v|^2 read literally).
        f1_relative: f1 reads only free pixels, each relative to the pheromone under the
            robot (ours; the paper is silent on walls). False: walls and the map's outside
            read as zero pheromone, which pulls wanders into walls and corners.
        deposit_line_of_sight: pheromone is laid only where the robot sees (walls block it).
        f1_line_of_sight: f1 reads only the pixels the robot sees (walls block the pheromone
            sensor; ours, the paper is silent). False: pheromone is read through walls, and
            wanders gather at a wall with less pheromone behind it instead of finding the door.
        swarm_size: swarmsize in C_db; None = 1 + time_limit / launch period.
        max_speed: UAV speed (m/s).
        detection_range: sensing radius of ca and cb (m).
        coverage_target: ca fraction that ends the run.
        coverage_interval: how often wanders' views are added to ca (s).
        coverage_line_of_sight: walls block the view of the coverage sensor.
        time_limit: longest run (s).
        map_resolution: metres per pixel of a map file.
        dt: physics tick (s).
        body_radius: UAV half-width for contacts (m).
        body_noise: per-tick body jitter (m).
        step_duration: simulated seconds per Mesa ``step()``.
        trace_interval: position sampling for rendering (s); None = off (fast).

    """

    STATES = ("wander", "beacon")

    def __init__(
        self,
        map: str | Path | Arena = "hall100",  # noqa: A002 - the paper's and the issue's name
        pheromone_radius: float = 20.0,
        seed: int | None = None,
        *,
        wander_radius: float | None = None,
        wander_intensity: float = _D.wander_intensity,
        decay: float = _D.decay,
        link_threshold: float | None = None,
        obstacle_range: float = _D.obstacle_range,
        launch_rate: float = _D.launch_rate,
        model_step: float = _D.step,
        start: tuple[float, float] | None = None,
        a1: float = _D.a1,
        a2: float = _D.a2,
        a3: float = _D.a3,
        a4: float = _D.a4,
        f1_falloff: float = _D.f1_falloff,
        f1_relative: bool = True,
        f1_line_of_sight: bool = False,
        deposit_line_of_sight: bool = True,
        obstacle_beams: int = 8,
        swarm_size: int | None = None,
        max_speed: float = _D.max_speed,
        detection_range: float = _D.detection_range,
        coverage_target: float = _D.coverage_target,
        coverage_interval: float = 1.0,
        coverage_line_of_sight: bool = True,
        time_limit: float = _D.time_limit,
        map_resolution: float = 1.0,
        dt: float = _D.dt,
        body_radius: float = _D.body_radius,
        body_noise: float = _D.body_noise,
        step_duration: float = 0.5,
        trace_interval: float | None = None,
    ) -> None:
        check_range("pheromone_radius", pheromone_radius, 0.0, low_open=True)
        wander_radius = pheromone_radius / 2 if wander_radius is None else wander_radius
        link_threshold = pheromone_radius if link_threshold is None else link_threshold
        check_range("wander_radius", wander_radius, 0.0)
        check_range("wander_intensity", wander_intensity, 0.0)
        check_range("decay", decay, 0.0)
        check_range("link_threshold", link_threshold, 0.0, low_open=True)
        check_range("obstacle_range", obstacle_range, 0.0, low_open=True)
        check_range("obstacle_beams", obstacle_beams, 0, integer=True)
        check_range("launch_rate", launch_rate, 0.0, 1.0, low_open=True)
        check_range("model_step", model_step, 0.0, low_open=True)
        for name, value in (
            ("a1", a1),
            ("a2", a2),
            ("a3", a3),
            ("a4", a4),
            ("f1_falloff", f1_falloff),
        ):
            check_range(name, value, 0.0)
        check_range("max_speed", max_speed, 0.0, low_open=True)
        check_range("detection_range", detection_range, 0.0, low_open=True)
        check_range("coverage_target", coverage_target, 0.0, 1.0, low_open=True)
        check_range("coverage_interval", coverage_interval, 0.0, low_open=True)
        check_range("time_limit", time_limit, 0.0, low_open=True)
        launch_period = model_step / launch_rate
        if swarm_size is None:
            swarm_size = 1 + int(time_limit // launch_period)
        check_range("swarm_size", swarm_size, 1, integer=True)
        arena = load_map(map, resolution=map_resolution)
        if start is None:
            start = MAPS[map].start if isinstance(map, str) and map in MAPS else _D.start
        start = np.asarray(start, dtype=float)
        if start.shape != (2,):
            raise ConfigError(f"start must be a point (x, y) in metres, got {start!r}")
        if not arena.is_free(start[None])[0]:
            raise ConfigError(
                f"start {tuple(start.tolist())} lies inside a wall (or outside) of map "
                f"{arena.name!r} ({arena.width:g} x {arena.height:g} m)"
            )
        super().__init__(
            arena,
            seed=seed,
            step_duration=step_duration,
            time_limit=time_limit,
            comm_range=link_threshold,
            flight=FlightParams(
                max_speed=max_speed, body_radius=body_radius, body_noise=body_noise
            ),
            dt=dt,
            trace_interval=trace_interval,
        )
        self.map_name = arena.name
        self.pheromone_radius = float(pheromone_radius)
        self.wander_radius = float(wander_radius)
        self.wander_intensity = float(wander_intensity)
        self.decay = float(decay)
        self.link_threshold = float(link_threshold)
        self.obstacle_range = float(obstacle_range)
        self.obstacle_beams = int(obstacle_beams)
        self.launch_rate = float(launch_rate)
        self.model_step = float(model_step)
        self.launch_period = launch_period
        self.start = start
        self.a1, self.a2, self.a3, self.a4 = float(a1), float(a2), float(a3), float(a4)
        self.f1_falloff = float(f1_falloff)
        self.f1_relative = bool(f1_relative)
        self.f1_line_of_sight = bool(f1_line_of_sight)
        self.deposit_line_of_sight = bool(deposit_line_of_sight)
        self.swarm_size = int(swarm_size)
        self.max_speed = float(max_speed)
        self.detection_range = float(detection_range)
        self.coverage_target = float(coverage_target)
        self.coverage_interval = float(coverage_interval)
        self.coverage_line_of_sight = bool(coverage_line_of_sight)
        self.entropy = map_entropy(arena)
        self.envsize = arena.width * arena.height
        self.pheromone = PheromoneField(
            arena.free.shape, arena.resolution, decay, mask=arena.free, time=0.0
        )
        self.seen = np.zeros_like(arena.free)
        self._n_free = int(arena.free.sum())
        dy, dx = disc_offsets(detection_range, arena.resolution)
        self._view = (dy, dx)
        self.beacon_positions = np.empty((0, 2))
        self.robots: list[Robot] = []
        self.physics.controller = WanderController(self)
        first = Robot(self, start, "beacon", "beacon")
        self.robots.append(first)
        self._land(first, 0, start)
        self.env.process(self._launcher())

    # ------------------------------------------------------------------ behaviour
    def _launcher(self):
        """A new wander robot every launch period, while the swarm has room."""
        while len(self.robots) < self.swarm_size:
            yield self.env.timeout(self.launch_period)
            robot = Robot(self, self.start, "wander", "flight")
            index = len(self.robots)
            self.robots.append(robot)
            self.recorder.log("launch", robot.unique_id)
            robot.start(self._wander(robot, index))

    def _wander(self, robot: Robot, index: int):
        """One robot's story: fly until the link to the swarm weakens to l_i, then land."""
        landed = self.physics.fly(robot.unique_id, robot.space_index, self.start)
        yield landed
        self._land(robot, index, robot.position.copy())

    def _land(self, robot: Robot, index: int, position: np.ndarray) -> None:
        """Become a beacon: land, leave the footprint (radius C_rb, intensity C_db)."""
        if robot.state != "beacon":
            robot.set_state("beacon")
            robot.set_mode("beacon")
        robot.position = position
        self.recorder.log("land", robot.unique_id, x=position[0], y=position[1])
        intensity = max(0.0, (self.swarm_size - index) / self.swarm_size)
        self.pheromone.deposit(
            position,
            self.pheromone_radius,
            intensity,
            time=self.env.now,
            line_of_sight=self.deposit_line_of_sight,
        )
        self.beacon_positions = np.vstack([self.beacon_positions, position[None]])
        self.stamp_coverage(position[None])

    # ------------------------------------------------------------------ sensing
    def link_distance(self, points: np.ndarray) -> np.ndarray:
        """Distance (m) from each point to the nearest beacon (its link to the swarm)."""
        return nearest_distance(np.atleast_2d(points), self.beacon_positions)

    def stamp_coverage(self, points: np.ndarray) -> None:
        """Add what sensors at ``points`` see to ca; ends the run at the coverage target."""
        dy, dx = self._view
        cells = visible_cells(
            self.arena, points, dy, dx, skip=self.seen, line_of_sight=self.coverage_line_of_sight
        )
        self.seen.ravel()[cells] = True
        if self.ca >= self.coverage_target:
            self.finish("coverage")

    @property
    def ca(self) -> float:
        """Fraction of free area seen by any robot at any time."""
        return float(self.seen.sum()) / self._n_free

    def cb(self) -> float:
        """Fraction of free area seen by the robots where they are now (all states)."""
        points = np.array([r.position for r in self.robots])
        dy, dx = self._view
        cells = visible_cells(self.arena, points, dy, dx, line_of_sight=self.coverage_line_of_sight)
        return float(len(np.unique(cells))) / self._n_free

    # ------------------------------------------------------------------ data
    def reporters(self) -> dict:
        """Counts per state and ca (for Mesa's DataCollector)."""
        return {**super().reporters(), "ca": lambda m: m.ca}

    def state_counts(self) -> pd.DataFrame:
        """Robots per state after every change: columns ``time``, ``wander``, ``beacon``."""
        return super().state_counts()

    def summary(self) -> dict:
        """The run's Table 1 row: final w, b, time t, ca, cb (%), and the settings."""
        counts = self.recorder.counts
        return {
            "map": self.map_name,
            "pheromone_radius": self.pheromone_radius,
            "seed": self.seed,
            "time": self.env.now,
            "end_reason": self.end_reason,
            "wander": counts["wander"],
            "beacon": counts["beacon"],
            "robots": len(self.robots),
            "ca": 100.0 * self.ca,
            "cb": 100.0 * self.cb(),
            "entropy": self.entropy,
            "envsize": self.envsize,
            "map_digest": map_digest(self.arena),
            "wall_collisions": self.physics.wall_collisions,
            "robot_collisions": self.physics.robot_collisions,
        }
