"""BeaconExplorerModel: incremental deployment of flying robots guided by a beacon network.

Stirling et al. (2010). One pre-deployed base beacon; N explorers wait on the ground below it;
explorer i takes off at i * t_launch, follows beacon to beacon, attaches where a beacon is
required and becomes one; beacons in searched-out areas detach and redeploy. The run ends when
the search is complete (all free area covered), when it cannot progress (no beacon can
redeploy and no explorer can be placed), or at the time limit.

The robots and their stories are in :mod:`models.beacon_explorer.agents`; this module builds
the swarm, records what the robots report, and watches for the end of the run.
"""

import numpy as np

from abm.arena import Arena
from abm.coverage import CoverageRaster, raster_bytes
from abm.energy import Battery
from abm.errors import ConfigError
from abm.model import SwarmModel
from abm.physics import FlightParams
from abm.robot import Robot
from abm.styles import Layer, StateStyle
from models.beacon_explorer import published
from models.beacon_explorer.agents import BaseBeacon, SwarmRobot
from models.beacon_explorer.beacon import BeaconNetwork
from models.beacon_explorer.explorer import ExplorerController
from models.beacon_explorer.params import SWARM_SIZE, BeaconExplorerParams
from models.beacon_explorer.repair import link_fault, robot_failed
from models.beacon_explorer.units import SUMMARY_UNITS
from models.environments import MAPS, WORLD_KINDS, World, builtin_map, make_world

__all__ = ["BeaconExplorerModel"]


class BeaconExplorerModel(SwarmModel):
    """Beacon/explorer swarm search (Stirling et al. 2010).

    Every field of :class:`BeaconExplorerParams` is a keyword of the constructor, e.g.
    ``BeaconExplorerModel(world="corridor", complexity="high", launch_period=6.0, seed=1)``.

    Args:
        seed: seed of the model's random generator (world, noise, everything).
        **params: fields of :class:`BeaconExplorerParams`.

    """

    Params = BeaconExplorerParams
    STATES = ("ground", "explorer", "beacon")
    STATE_STYLES = {
        # ground robots wait stacked under the base: a large square behind the base's disc
        "ground": StateStyle("#999999", marker="s", size=150.0, layer=4.0),
        "explorer": StateStyle("#D55E00", marker="^", size=45.0, layer=6.0),
        "beacon": StateStyle("#0072B2", marker="o", size=55.0, layer=5.0),
        "failed": StateStyle("#000000", marker="X", size=45.0, layer=6.0),
    }
    MACRO = published.MACRO
    ARROWS_LABEL = "beacon's desired direction"
    PUBLISHED = published.PUBLISHED
    CENSORED = published.CENSORED
    REPORT = published.REPORT
    APP = "models.beacon_explorer.app"
    FAULTS = frozenset({"robot", "link", "sensor"})

    SUMMARY_UNITS = SUMMARY_UNITS

    def __init__(self, *, seed: int | None = None, **params: object) -> None:
        p = self.make_params(**params)
        self.world: World | None = None

        def build_world(rng: np.random.Generator) -> Arena:
            self.world = self._make_world(p, rng)
            return self.world.arena

        super().__init__(
            p,
            build_world,
            seed=seed,
            failures=p.battery_capacity is not None,
            comm_range=p.comm_range,
            latency=p.latency,
            message_loss=p.message_loss,
            powers=p.powers,
            flight=FlightParams(
                mass=p.mass,
                max_speed=p.max_speed,
                max_force=p.max_force,
                tau=p.tau,
                rho=p.air_density,
                area=p.frontal_area,
                drag_coefficient=p.drag_coefficient,
                body_noise=p.body_noise,
                body_radius=p.body_radius,
            ),
        )
        self.complexity = p.level
        self.launch_period = p.launch_period
        self.n_robots = p.n_robots or SWARM_SIZE.get((self.world.kind, self.complexity), 20)
        self.coverage = CoverageRaster(self.arena, p.sensor_range, p.coverage_pixel)
        self.beacons = BeaconNetwork(self.env, self.arena, self.comms, self.rng, p, self.physics.dt)
        self.beacons.sensed = self.faults.sensed  # a beacon's distance sensors may be faulty
        self.physics.controller = ExplorerController(
            self.arena, self.beacons, self.rng, p, self.physics, self._stopped_to_attach
        )
        self.battery = (
            None
            if p.battery_capacity is None
            else Battery(self.ledger, p.battery_capacity, self._battery_empty)
        )
        self._stall_mark = (0.0, 0)  # (time, collisions) when the stall watch last reset
        self._build_swarm()
        self.env.process(self._monitor())
        if p.stall_time is not None:
            self.env.process(self._stall_watch())

    # ------------------------------------------------------------------ set-up
    @staticmethod
    def _make_world(p: BeaconExplorerParams, rng: np.random.Generator) -> World:
        if isinstance(p.world, World):
            return p.world
        if p.world in WORLD_KINDS:
            return make_world(p.world, p.level, rng)
        if isinstance(p.world, str) and p.world in MAPS:
            arena = builtin_map(p.world)
            start = np.asarray(MAPS[p.world].start if p.start is None else p.start, dtype=float)
        else:
            arena = Arena.from_bitmap(
                p.world, resolution=p.map_resolution or 1.0, parts=_map_parts(p)
            )
            start = arena.free_cell_centres()[0] if p.start is None else np.asarray(p.start)
        if not arena.is_free(start[None])[0]:
            raise ConfigError(
                f"start {tuple(start.tolist())} lies inside a wall of map {str(p.world)!r}"
            )
        iy, ix = np.nonzero(arena.free)
        return World(arena, start, "bitmap", p.level, np.stack([ix, iy], axis=1), None)

    def _build_swarm(self) -> None:
        """The base beacon at the start, attached, and the N robots waiting below it, each
        running its story (:meth:`SwarmRobot.search`).
        """
        start = self.world.start
        self.beacon_attached(BaseBeacon(self, start), start)
        for i in range(1, self.n_robots + 1):
            robot = SwarmRobot(self, start, i)
            robot.start(robot.search())

    @property
    def beacon_mode(self) -> str:
        """The power mode of a beacon: "beacon" (attached to the ceiling) or "hover"."""
        return "hover" if self.params.hover_beacons else "beacon"

    @property
    def base(self) -> BaseBeacon:
        """The pre-deployed base beacon."""
        (base,) = self.agents_by_type[BaseBeacon]
        return base

    # ------------------------------------------------------------------ what robots report
    def beacon_attached(self, robot: Robot, position: np.ndarray) -> None:
        """``robot`` attached at ``position`` (m) and serves as a beacon: it is logged, joins
        the beacon network, its sensors cover the area around it, and the stall watch
        restarts (an attach is progress).
        """
        self.recorder.log("attach", robot.unique_id, x=position[0], y=position[1])
        self._stall_mark = (self.env.now, self.collisions)
        self.beacons.attach(robot.unique_id, position, is_base=isinstance(robot, BaseBeacon))
        self.coverage.stamp(position, self.env.now)

    def _stopped_to_attach(self, robot_id: int, guide: int) -> None:
        """The explorer controller stopped a flyer to attach at beacon ``guide``'s spot."""
        self.robot(robot_id).guide = guide

    def _battery_empty(self, robot_id: int) -> None:
        """A battery ran flat: the robot fails where it is, whatever it was doing."""
        self.faults.fail(self.robot(robot_id), "battery")

    def on_robot_failed(self, robot: Robot) -> None:
        """A robot failed (a fault or a flat battery): the beacon network follows
        (:func:`repair.robot_failed`).
        """
        robot_failed(self.beacons, robot.unique_id, self.params.repair)

    def on_link_fault(self, a: object, b: object, up: bool) -> None:
        """A link outage began or ended: see :func:`repair.link_fault`."""
        link_fault(self.beacons, a, b)

    def _monitor(self):
        """Check once per period whether the search is over.

        Complete: the free area is covered. Searched: no beacon signals an empty direction and
        every beacon is redeploying (the swarm believes the reachable environment is searched;
        the paper's robots would now return to the base). Stuck: every robot is a beacon and none
        may redeploy (the reason names the failed robots, which are no beacons, when any did).
        Both are judged only once the network is quiescent (hop counts settled, no decision
        pending), or a robot that has just attached would look unable to redeploy.
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
                failed = len(self.faults.failures)
                if failed:  # the failed are no beacons: say how many robots are left
                    left = f"{len(beacons)} beacon{'' if len(beacons) == 1 else 's'} left"
                    self.finish(f"stuck: every robot left is a beacon ({failed} failed, {left}) "
                                "and none can redeploy")  # fmt: skip
                else:
                    self.finish("stuck: every robot is a beacon and none can redeploy")
                return

    def _stall_watch(self):
        """End a run whose explorers fly on without any beacon attaching, colliding.

        The window restarts at every attach and whenever no explorer flies; once it is
        ``stall_time`` long with at least ``stall_collisions`` collisions in it, the run ends
        "stalled", naming the beacon most flyers follow and its signal (the usual culprit), and
        an event ``stall`` records the same.
        """
        p = self.params
        while True:
            yield self.env.timeout(p.monitor_period)
            now, collisions = self.env.now, self.collisions
            if self.physics.n_flying == 0:
                self._stall_mark = (now, collisions)
                continue
            since, before = self._stall_mark
            if now - since < p.stall_time or collisions - before < p.stall_collisions:
                continue
            self._stall(now - since, collisions - before)
            return

    def _stall(self, duration: float, collisions: int) -> None:
        guides = self.physics.flyer_state["guide"][:, 0].astype(int)
        ids, counts = np.unique(guides, return_counts=True)
        guide = int(ids[np.argmax(counts)])
        beacon = self.beacons.beacons.get(guide)
        where = "" if beacon is None else " at ({:.1f}, {:.1f})".format(*beacon.position)
        signal = "none" if beacon is None or beacon.desired < 0 else "NESW"[beacon.desired]
        self.recorder.log(
            "stall",
            guide,
            flyers=self.physics.n_flying,
            followers=int(counts.max()),
            duration=duration,
            collisions=collisions,
        )
        self.finish(
            f"stalled: {self.physics.n_flying} explorers flew {duration:.0f} s without an "
            f"attach ({collisions} collisions); {int(counts.max())} followed beacon {guide}"
            f"{where} signalling {signal}"
        )

    # ------------------------------------------------------------------ results
    def metrics(self) -> dict:
        """The paper's metrics (SI units; besides the common keys of ``summary()``)."""
        ledger = self.ledger
        counts = self.recorder.counts
        flight = ledger.duration("flight")
        distance = self.physics.distance
        return {
            "world": self.world.kind,
            "complexity": self.complexity,
            "n_robots": self.n_robots,
            "robots": self.n_robots + 1,
            "hover_beacons": self.params.hover_beacons,
            "seed": self.seed,
            "coverage_time": float(self.env.now),
            "complete": self.coverage.fraction >= self.params.complete_fraction,
            "flight_time": flight,
            "flight_distance": distance,
            # NaN when no robot left the ground
            "mean_flight_speed": distance / flight if flight > 0 else float("nan"),
            "energy_flight": ledger.energy(mode="flight"),
            "energy_beacon": ledger.energy(mode="beacon") + ledger.energy(mode="hover"),
            "energy_ground": ledger.energy(mode="ground"),
            "n_beacons_final": counts["beacon"],
            "n_failed": counts.get("failed", 0),
            "branches": self.world.branches,
        }

    def layers(self) -> list[Layer]:
        """The base beacon, marked: it stands at the entrance from the start (Sect. 3) and is
        the one robot of ``robots`` that is not among the ``n_robots`` launched. It never moves
        (still), and its star is drawn over the ground robots waiting under it (layer 4), under
        the beacons' circles (5), so the base's own circle sits in the star.
        """
        base = np.asarray([self.base.pos], dtype=float)
        return [Layer("base beacon (robots = n_robots + 1)", points=base, colour="#E69F00",
                      size=420.0, marker="*", layer=4.5, still=True)]  # fmt: skip

    def arrows(self) -> tuple[np.ndarray, np.ndarray]:
        """Beacons' desired directions (points, vectors of length I_r) for drawings."""
        _ids, pos, vectors, _to_empty = self.beacons.signals()
        return pos, vectors


def _map_parts(p: BeaconExplorerParams):
    """What the model allocates per map pixel besides the arena (bytes by part, for the map
    loader's memory check): the coverage raster of ``coverage_pixel`` and the world's list of
    free cells (two int64 a pixel, and as much while it is built).
    """

    def parts(shape: tuple[int, int]) -> dict[str, float]:
        resolution = p.map_resolution or 1.0
        return {
            "coverage raster": raster_bytes(shape, resolution, p.coverage_pixel),
            "free-cell list": 32.0 * shape[0] * shape[1],
        }

    return parts
