"""BeaconExplorerModel: incremental deployment of flying robots guided by a beacon network.

Stirling et al. (2010). One pre-deployed base beacon; N explorers wait on the ground below it;
explorer i takes off at i * t_launch, follows beacon to beacon, attaches where a beacon is
required and becomes one; beacons in searched-out areas detach and redeploy. The run ends when
the search is complete (all free area covered), when it cannot progress (no beacon can
redeploy and no explorer can be placed), or at the time limit.
"""

from pathlib import Path

import numpy as np
import simpy

from abm.arena import Arena
from abm.coverage import CoverageRaster
from abm.energy import Battery
from abm.errors import ConfigError, check_choice, check_range
from abm.model import SwarmModel
from abm.physics import FlightParams
from abm.robot import Robot
from abm.worlds import COMPLEXITIES, WORLD_KINDS, World, make_world
from models.beacon_explorer.beacon import BeaconNetwork
from models.beacon_explorer.explorer import ExplorerController
from models.beacon_explorer.params import DEFAULTS, SWARM_SIZE, BeaconExplorerParams

__all__ = ["BeaconExplorerModel"]


class BeaconExplorerModel(SwarmModel):
    """Beacon/explorer swarm search (SPEC A).

    Args:
        world: "corridor", "open" or "mixed" (generated from the seed), a bitmap map file
            (PNG/PGM/NPY, 1 px = ``map_resolution`` m), or a ready :class:`abm.worlds.World`.
        complexity: corridor branching level, or obstacle density in open rooms: "low",
            "medium" or "high"; default "high" ("medium", the only level the paper uses, for
            mixed worlds).
        n_robots: explorers waiting on the ground; default: the paper's swarm size for the world.
        launch_period: inter-launch period t (s); explorer i takes off at i * t.
        seed: seed of the model's random generator (world, noise, everything).
        hover_beacons: beacons hover in place instead of attaching to the ceiling.
        time_limit: longest simulated run (s).
        step_duration: simulated seconds per ``step()``.
        max_speed: explorer cruising speed (m/s).
        map_resolution: metres per pixel of a bitmap ``world``.
        start: base position (m) for a bitmap world; default: the centre of the first free cell.
        trace_interval: how often robot positions are sampled for rendering (s); None: never.
        battery_capacity: charge of each explorer's battery (J); None (the paper's experiments):
            unlimited. A robot whose battery runs flat fails where it is: a flyer drops out of
            the air, a beacon leaves the network (its neighbours do not take the area beyond it
            as searched), and the robot is counted in the extra state ``failed``. The base
            beacon is pre-deployed at the entrance and is not battery-limited.
        params: the algorithm's constants (see :class:`BeaconExplorerParams`).

    """

    STATES = ("ground", "explorer", "beacon")

    def __init__(
        self,
        world: str | Path | World = "corridor",
        complexity: str | None = None,
        n_robots: int | None = None,
        launch_period: float = 6.0,
        seed: int | None = None,
        hover_beacons: bool = False,
        time_limit: float = 3600.0,
        step_duration: float = 1.0,
        max_speed: float = 1.0,
        map_resolution: float = 1.0,
        start: tuple[float, float] | None = None,
        trace_interval: float | None = 1.0,
        battery_capacity: float | None = None,
        params: BeaconExplorerParams = DEFAULTS,
    ) -> None:
        if complexity is None:
            complexity = "medium" if world == "mixed" else "high"
        check_choice("complexity", complexity, COMPLEXITIES)
        check_range("launch_period", launch_period, 0.0, low_open=True)
        check_range("max_speed", max_speed, 0.0, 5.0, low_open=True)
        if not isinstance(hover_beacons, bool | np.bool_):
            raise ConfigError(f"hover_beacons must be True or False, got {hover_beacons!r}")
        if n_robots is not None:
            check_range("n_robots", n_robots, 1, 10_000, integer=True)
        if battery_capacity is not None:
            check_range("battery_capacity", battery_capacity, 0.0, low_open=True)
            self.STATES = (*type(self).STATES, "failed")
        self.battery_capacity = battery_capacity
        self.world: World | None = None

        def build_world(rng: np.random.Generator) -> Arena:
            self.world = self._make_world(world, complexity, map_resolution, start, rng)
            return self.world.arena

        super().__init__(
            build_world,
            seed=seed,
            step_duration=step_duration,
            time_limit=time_limit,
            comm_range=params.comm_range,
            flight=FlightParams(max_speed=max_speed),
            trace_interval=trace_interval,
        )
        self.params = params
        self.complexity = complexity
        self.launch_period = float(launch_period)
        self.hover_beacons = bool(hover_beacons)
        kind = self.world.kind
        self.n_robots = (
            int(n_robots) if n_robots is not None else SWARM_SIZE.get((kind, complexity), 20)
        )
        self.coverage = CoverageRaster(self.arena, params.sensor_range, params.coverage_pixel)
        self.beacons = BeaconNetwork(
            self.env, self.arena, self.comms, self.rng, params, self.physics.dt, self._may_detach
        )
        self.physics.controller = ExplorerController(
            self.arena, self.beacons, self.rng, params, max_speed, self.physics
        )
        self.robots: dict[int, Robot] = {}
        self._detach_wanted: dict[int, object] = {}
        self.battery = (
            None
            if battery_capacity is None
            else Battery(self.ledger, battery_capacity, self._battery_empty)
        )
        self._build_swarm()
        self.env.process(self._monitor())

    # ------------------------------------------------------------------ set-up
    @staticmethod
    def _make_world(world, complexity: str, resolution: float, start, rng) -> World:
        if isinstance(world, World):
            return world
        if isinstance(world, str) and world in WORLD_KINDS:
            return make_world(world, complexity, rng)
        if isinstance(world, str | Path) and Path(world).suffix.lower() in {
            ".png",
            ".pgm",
            ".bmp",
            ".npy",
        }:
            arena = Arena.from_bitmap(world, resolution=resolution)
            if start is None:
                start = arena.free_cell_centres()[0]
            start = np.asarray(start, dtype=float)
            if not arena.is_free(start[None])[0]:
                raise ConfigError(f"start {tuple(start)} lies inside a wall of map {str(world)!r}")
            iy, ix = np.nonzero(arena.free)
            return World(arena, start, "bitmap", complexity, np.stack([ix, iy], axis=1), None)
        kinds = ", ".join(repr(k) for k in WORLD_KINDS)
        raise ConfigError(
            f"world must be one of {kinds}, a map file (.png, .pgm, .bmp, .npy) or a World, "
            f"got {world!r}"
        )

    def _build_swarm(self) -> None:
        start = self.world.start
        base = Robot(self, start, "beacon", self._beacon_mode())
        if self.battery is not None:
            self.battery.exempt(base.unique_id)  # see ``battery_capacity``
        self.base = base
        self.robots[base.unique_id] = base
        self.recorder.log("attach", base.unique_id, x=start[0], y=start[1])
        self.beacons.attach(base.unique_id, start, is_base=True)
        self.coverage.stamp(start)
        for i in range(1, self.n_robots + 1):
            robot = Robot(self, start, "ground", "ground")
            self.robots[robot.unique_id] = robot
            robot.start(self._explorer_life(robot, i))

    def _beacon_mode(self) -> str:
        return "hover" if self.hover_beacons else "beacon"

    # ------------------------------------------------------------------ behaviour
    def _explorer_life(self, robot: Robot, index: int):
        """One robot's story (Fig. 4): wait, take off, follow beacons, attach, maybe redeploy.

        A flat battery ends it wherever it is (see :meth:`_battery_empty`).
        """
        try:
            yield from self._explore(robot, index)
        except simpy.Interrupt:
            return

    def _explore(self, robot: Robot, index: int):
        yield self.env.timeout(index * self.launch_period)
        robot.set_state("explorer")
        robot.set_mode("flight")
        self.recorder.log("launch", robot.unique_id)
        yield self.env.timeout(self.params.climb_time)
        position = self.world.start + self.rng.normal(0.0, 0.1, 2)
        position = np.where(self.arena.is_free(position[None])[0], position, self.world.start)
        while True:
            arrived = self.physics.fly(robot.unique_id, robot.space_index, position)
            yield arrived
            position = robot.position.copy()
            yield self.env.timeout(self.params.attach_time)
            if self._beacon_near(position, self.params.interspace / 2):
                continue  # another explorer attached here first: fly on
            robot.set_state("beacon")
            robot.set_mode(self._beacon_mode())
            self.recorder.log("attach", robot.unique_id, x=position[0], y=position[1])
            self.beacons.attach(robot.unique_id, position)
            self.coverage.stamp(position)
            yield from self._beacon_until_detach(robot)
            self.beacons.detach(robot.unique_id)
            robot.set_state("explorer")
            robot.set_mode("flight")
            self.recorder.log("detach", robot.unique_id)

    def _beacon_until_detach(self, robot: Robot):
        """Wait until this beacon may detach, one inter-launch period passed, no explorer near."""
        rid = robot.unique_id
        while True:
            wanted = self.env.event()
            self._detach_wanted[rid] = wanted
            if self.beacons.beacons[rid].may_detach:
                wanted.succeed()
            yield wanted
            yield self.env.timeout(self.launch_period)
            beacon = self.beacons.beacons[rid]
            if beacon.may_detach and not self._explorer_near(beacon.position):
                del self._detach_wanted[rid]
                return

    def _battery_empty(self, robot_id: int) -> None:
        """A battery ran flat: the robot fails where it is, whatever it was doing."""
        robot = self.robots[robot_id]
        if robot_id in self.physics.ids:
            self.physics.stop(robot_id)
        if robot_id in self.beacons.beacons:
            self.beacons.detach(robot_id, searched=False)
        self._detach_wanted.pop(robot_id, None)
        if robot.process is not None and robot.process.is_alive:
            robot.process.interrupt("battery empty")
        robot.set_state("failed")
        robot.set_mode("off")
        self.recorder.log("battery_empty", robot_id)

    def _may_detach(self, robot: int) -> None:
        wanted = self._detach_wanted.get(robot)
        if wanted is not None and not wanted.triggered:
            wanted.succeed()

    def _beacon_near(self, position: np.ndarray, radius: float) -> bool:
        _ids, pos, _vectors, _to_empty = self.beacons.signals()
        return bool((np.hypot(*(pos - position).T) < radius).any())

    def _explorer_near(self, position: np.ndarray) -> bool:
        if self.physics.n_flying == 0:
            return False
        d = np.hypot(*(self.physics.pos - position).T)
        return bool((d < self.params.interspace).any())

    def _monitor(self):
        """Check once per period whether the search is over.

        Complete: the free area is covered. Searched: no beacon signals an empty direction and
        every beacon is redeploying (the swarm believes the reachable environment is searched;
        the paper's robots would now return to the base). Stuck: every robot is a beacon and none
        may redeploy. Both are judged only once the network is quiescent (hop counts settled, no
        decision pending), or a robot that has just attached would look unable to redeploy.
        """
        while True:
            yield self.env.timeout(self.params.monitor_period)
            if self.coverage.fraction >= self.params.complete_fraction:
                self.finish("complete")
                return
            if not self.beacons.quiescent:
                continue  # decisions still travelling through the network
            beacons = self.beacons.beacons.values()
            if not any(b.frontier for b in beacons) and all(b.redeploying for b in beacons):
                self.finish("searched: no frontier left and every beacon redeploys")
                return
            counts = self.recorder.counts
            pending = any(b.may_detach for b in beacons)
            if counts["ground"] == 0 and counts["explorer"] == 0 and not pending:
                self.finish("stuck: every robot is a beacon and none can redeploy")
                return

    # ------------------------------------------------------------------ results
    def summary(self) -> dict:
        """Flat dict of the run's metrics (SI units; coverage_area in % of free area)."""
        ledger = self.ledger
        counts = self.recorder.counts
        flight_energy = ledger.energy(mode="flight")
        beacon_energy = ledger.energy(mode="beacon") + ledger.energy(mode="hover")
        ground_energy = ledger.energy(mode="ground")
        return {
            "world": self.world.kind,
            "complexity": self.complexity,
            "n_robots": self.n_robots,
            "launch_period": self.launch_period,
            "hover_beacons": self.hover_beacons,
            "seed": self.seed,
            "coverage_time": float(self.env.now),
            "coverage_area": 100.0 * self.coverage.fraction,
            "complete": self.coverage.fraction >= self.params.complete_fraction,
            "end_reason": self.end_reason or "running",
            "collisions": self.physics.wall_collisions + self.physics.robot_collisions,
            "wall_collisions": self.physics.wall_collisions,
            "robot_collisions": self.physics.robot_collisions,
            "flight_time": ledger.duration("flight"),
            "energy_flight": flight_energy,
            "energy_beacon": beacon_energy,
            "energy_ground": ground_energy,
            "energy_total": flight_energy + beacon_energy + ground_energy,
            "n_beacons_final": counts["beacon"],
            "n_failed": counts.get("failed", 0),
            "branches": self.world.branches,
        }

    def arrows(self) -> tuple[np.ndarray, np.ndarray]:
        """Beacons' desired directions (points, vectors of length I_r) for drawings."""
        _ids, pos, vectors, _to_empty = self.beacons.signals()
        return pos, vectors

    def reporters(self) -> dict:
        """DataCollector columns: robots per state, coverage (%) and energy (J)."""
        return {
            **super().reporters(),
            "coverage": lambda m: 100.0 * m.coverage.fraction,
            "energy": lambda m: m.ledger.energy(),
        }
