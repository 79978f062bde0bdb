"""Parameters of the beacon/explorer model, with the paper's values.

Source: Stirling, Roberts, Zufferey, Floreano (2010), "Energy-efficient indoor search by
swarms of simulated flying robots without global information", Swarm Intelligence 4:117-143.
Values not given in the paper are marked "ours".
"""

import math
from dataclasses import dataclass
from pathlib import Path

from abm.errors import ConfigError
from abm.params import SwarmParams, param
from models.environments import COMPLEXITIES, MAPS, WORLD_KINDS, World

__all__ = ["BeaconExplorerParams", "DEFAULTS", "MAP_SUFFIXES", "SWARM_SIZE"]

#: Robots available per world and complexity (Sect. 3.5): 20 in corridor and mixed worlds;
#: 15 / 18 / 20 in open rooms with low / medium / high obstacle density.
SWARM_SIZE = {
    ("corridor", "low"): 20,
    ("corridor", "medium"): 20,
    ("corridor", "high"): 20,
    ("mixed", "low"): 20,
    ("mixed", "medium"): 20,
    ("mixed", "high"): 20,
    ("open", "low"): 15,
    ("open", "medium"): 18,
    ("open", "high"): 20,
}

#: File suffixes a ``world`` map file may have.
MAP_SUFFIXES = (".png", ".pgm", ".bmp", ".npy")


@dataclass(frozen=True)
class BeaconExplorerParams(SwarmParams):
    """Everything a beacon/explorer run can vary (SI units).

    Attributes:
        world: "corridor", "open" or "mixed" (generated from the seed, Sect. 3.5 and Fig. 5),
            a built-in map's name (``models.environments.MAPS``, e.g. the floor plans "office",
            "office_small", "lhall", "pillar_room", "diagonal_hall"; 1 m per pixel), a bitmap
            map file (PNG/PGM/BMP/NPY; dark pixels are walls) or a ready
            :class:`models.environments.World`.
        complexity: corridor branching, or obstacle density in open rooms: "low", "medium" or
            "high"; None: "medium" for mixed worlds (the only level the paper uses there), else
            "high".
        n_robots: explorers waiting on the ground below the base; None: the paper's swarm size
            for the world (15 / 18 / 20 in open rooms, 20 elsewhere, Sect. 3.5).
        launch_period: t, the inter-launch period: explorer i takes off at i * t (s).
        hover_beacons: beacons hover in place instead of attaching to the ceiling (the paper's
            energy comparison at the end of Sect. 4).
        battery_capacity: charge of each explorer's battery (J); None (the paper's
            experiments): unlimited. A flat battery fails the robot where it is: a flyer drops
            out of the air, a beacon leaves the network without its neighbours taking the area
            beyond it as searched, and the robot is counted in the extra state "failed". The
            pre-deployed base is not battery-limited.
        repair: the beacons tell a failed neighbour (a fault of :mod:`abm.faults`, a flat
            battery) from one that detached after its search: they advertise its spot as
            empty again, so explorers and redeploying beacons fill the hole and the hop counts
            beyond it heal (ours: the paper has no failures). Off, a failed beacon looks like
            one that detached -- the paper's controller knows no other way to lose a
            neighbour -- and the area beyond it counts as searched.
        start: base position (m) in a map world; None: a built-in map's own start point, or
            the centre of a map file's first free pixel. Generated worlds place the base in a
            random start cell, and a World carries its own start, so giving start for them is
            an error.
        map_resolution: metres per pixel of a map-file world; None: 1 m. An error for generated
            worlds (their cells are 3 m, Sect. 3.5).
        interspace: I_r, beacon spacing (m), Sect. 3.3.
        sensor_range: S_r, range of the distance sensors and radius of the coverage disc (m),
            Sect. 3.1.
        sensor_noise: std of the distance sensors' readings (m), App. B.
        range_noise: std of the relative-positioning sensor's range at reference_range (m),
            App. B (Pugh et al. 2009); it grows linearly with range (ours).
        bearing_noise: std of the relative-positioning sensor's bearing (rad; 6.1 deg), App. B.
        reference_range: the range at which range_noise holds (m), App. B.
        comm_range: C_r, reliable communication range with line of sight (m), Sect. 3.1.
        obstacle_threshold: a direction whose wall reading is below this is an obstacle (m; ours:
            I_r, so a lattice that drifted up to a metre still reads the wall beyond the next
            cell as empty; wall avoidance then stops the explorer short of that wall). It is
            also the paper's corridor test: a beacon between two opposing walls closer than
            this (3 m in the paper) is a corridor beacon (see open_diagonal).
        open_diagonal: a beacon is an open-space beacon only if, between two adjacent free
            cardinal directions, five rays all read more than this (nothing sensed within
            noise; m; ours). Two opposing walls nearer than obstacle_threshold leave no two
            adjacent free directions, so the paper's corridor test is implied by this one,
            which also keeps T-junctions (one wall sensed) as corridor beacons. See README.
        spot_taken: a beacon labels a direction "beacon" when another beacon it senses is
            closer than this to the lattice spot I_r away in that direction (m; ours: I_r less a
            margin for lattice drift, so a drifted diagonal neighbour does not hide a free spot).
        attach_eps: epsilon of |T| <= eps, the attach condition, on T low-pass filtered over
            filter_time (m; ours, calibrated: the paper gives no value). It sets how long an
            explorer takes to settle at its spot (the filtered noise of T is about 7 cm), and so
            how explorers queue at the frontier when they launch close together (the paper: more
            concurrent flyers, more unnecessary flight and collisions). With 0.15 m explorers
            settled at once, and 24 s instead of 6 s saved only 15 % of the flight in
            high-complexity corridors and no energy (+2.5 %); with 0.05 m (and the guide
            hysteresis): -28.1 % and -13.6 % (paper -41.5 / -30.8 %). See the README.
        attach_speed: an explorer attaches only once it has slowed below this (m/s; ours).
        guide_hysteresis: an explorer keeps following its beacon until another in touch is
            nearer by more than this (m; ours: 0 is the paper's plain nearest beacon, which let
            explorers shuttle for ever between two beacons' spots in 0.3 % of runs).
        guide_commit: an explorer whose beacon signals an empty spot keeps that beacon, however
            near another one is, while it stays in touch (C_r, line of sight), until it attaches
            or the signal changes (ours: the paper's explorer follows its nearest beacon; where
            a wall stops the lattice short, an advertised spot can lie nearer another beacon,
            and explorers circled between the two for ever; see the README).
        taken_hold: an explorer committed to a corridor beacon's empty spot whose spot is taken
            (another explorer attached there first) keeps following that beacon, not the
            newcomer, until that beacon is its nearest again or the explorer has reached
            the spot the beacon turned to, unless the beacon still signals
            the taken spot's direction after this long (it has decided, and the newcomer
            carries the search on, as along a chain: the explorer then follows the newcomer)
            (s; ours: 1 s, ten control periods, covers the beacon's decision after a neighbour
            attaches. None: off, the paper's explorer following its nearest beacon, i.e. the
            newcomer, whose onward signal at a junction sends it into a side branch: two
            beacons where the depth-first search of Sect. 3.3, "deploying robots serially down
            a single corridor branch", puts one; see the README).
        report_taken: an explorer that flew to a beacon's advertised spot and finds another
            beacon within I_r / 2 of it tells that beacon, which labels the direction "beacon"
            from then on (ours: the paper's beacons label directions only from their own
            sensors; a pillar can hide the beacon holding a spot from the beacon advertising
            it, and explorers then queued at the spot for ever; see the README).
        searched_follows_signal: a corridor beacon counts a direction as searched (Sect. 3.3:
            the neighbour there has a higher forwards hop count and signals back) only while
            that neighbour still signals back; only a neighbour that detached is remembered
            (ours: remembering every signal for good, a corridor beacon beside an open-space
            beacon that had pointed back while the frontier lay elsewhere closed the only way
            to a later frontier, and explorers shuttled at it for ever; see the README).
        lost_return: an explorer out of touch with every beacon (none within C_r in line of
            sight) flies back to where it last was in touch, by its own odometry (ours: the
            paper does not say; otherwise it hovers where it is, and an explorer that overshot
            a 1 m door into a room waited there for ever).
        slide_after: an explorer whose goal L (= N + D, before collision avoidance) lies more
            than slow_radius / 2 away but that has stayed within slow_radius / 2 of one point
            for this long is pressed against an obstacle and slides across L for as long,
            towards the side its cardinal sensors read more open, or the other side than its
            last slide when both read alike (s; ours; None: never. The
            paper's C points away from the nearest obstacle; with four cardinal sensors it
            pushes straight back from a pillar or wall on the line to the goal, and explorers
            stayed pressed against one for ever; see the README).
        filter_time: time constant of the explorer's filter of its noisy T (s; ours).
        avoid_gain: gain of the collision-avoidance vector C = gain * (1/d - 1/S_r) (m^2; ours).
        slow_radius: inside this |T| the flight controller slows proportionally (m; ours).
        climb_time: take-off and ascent to flight altitude (s; ours).
        attach_time: ascent to the ceiling and attachment (s; ours).
        forwards_start: hop count at the base (1), Sect. 3.3.
        reverse_start: hop count at frontier beacons (127), Sect. 3.3.
        coverage_pixel: pixel side of the coverage raster (m; ours).
        complete_fraction: coverage fraction counted as a complete search (ours).
        monitor_period: how often the end-of-search conditions are checked (s; ours).
        stall_time: the stall detector ends a run ("stalled: ...", naming the beacon most
            flyers follow) once explorers have flown this long without any beacon attaching
            and with stall_collisions or more collisions meanwhile (s; ours; None: off, runs go
            to the time limit). Healthy runs attach at least every few launch periods.
        stall_collisions: collisions within the stall window that make it a stall (ours).
        power_ground: P of a robot waiting on the ground: low-power electronics (W), App. C.
        power_flight: P of a flying robot: motors 110 W + high-rate electronics 10 W (W),
            App. C.
        power_beacon: P of a beacon on the ceiling: medium-rate electronics (W), App. C.
        power_hover: P of a hovering beacon: motors 110 W + medium-rate electronics 5 W (W;
            our reading of the paper's hover-vs-attach comparison).
        max_speed: explorer cruising speed, the flight controller's speed cap (m/s; ours).
        mass: m, robot mass (kg; ours), App. B's point-mass dynamics.
        max_force: cap on the flight controller's force (N; ours).
        tau: flight-controller time constant (s; ours).
        air_density: rho in the drag force (kg/m^3).
        frontal_area: A in the drag force (m^2; ours).
        drag_coefficient: C_d in the drag force (ours).
        body_noise: std of the Gaussian displacement of a flying body per 0.1 s tick (m),
            App. B.
        body_radius: half-width of a robot's body for contacts (m; ours).
        dt: the control period: explorers sense and steer, and the physics moves them, at
            10 Hz (s), Sect. 3.4.
        latency: one message takes one control period (s; ours).
        message_loss: probability that one transmission attempt is lost; the robots re-send
            every control period, so a loss delays a message by a period (0: the paper's
            reliable links within C_r, Sect. 3.1).

    """

    world: str | Path | World = "corridor"
    complexity: str | None = param(None, choices=COMPLEXITIES)
    n_robots: int | None = param(None, low=1, high=10_000, integer=True, shown=(2, 40))
    launch_period: float = param(6.0, low=0.0, low_open=True, shown=(1.0, 30.0))
    hover_beacons: bool = False
    battery_capacity: float | None = param(None, low=0.0, low_open=True)
    repair: bool = True
    start: tuple[float, float] | None = None
    map_resolution: float | None = param(None, low=0.0, low_open=True)
    interspace: float = param(3.0, low=0.0, low_open=True)
    sensor_range: float = param(3.5, low=0.0, low_open=True)
    sensor_noise: float = param(0.05, low=0.0)
    range_noise: float = param(0.17, low=0.0)
    bearing_noise: float = param(math.radians(6.1), low=0.0)
    reference_range: float = param(3.0, low=0.0, low_open=True)
    comm_range: float = param(4.0, low=0.0, low_open=True)
    obstacle_threshold: float = param(3.0, low=0.0, low_open=True)
    open_diagonal: float = param(3.45, low=0.0, low_open=True)
    spot_taken: float = param(2.2, low=0.0, low_open=True)
    attach_eps: float = param(0.05, low=0.0, low_open=True)
    attach_speed: float = param(0.2, low=0.0, low_open=True)
    guide_hysteresis: float = param(0.5, low=0.0)
    guide_commit: bool = True
    taken_hold: float | None = param(1.0, low=0.0, low_open=True)
    report_taken: bool = True
    lost_return: bool = True
    searched_follows_signal: bool = True
    slide_after: float | None = param(2.0, low=0.0, low_open=True)
    filter_time: float = param(0.3, low=0.0, low_open=True)
    avoid_gain: float = param(0.5, low=0.0)
    slow_radius: float = param(1.0, low=0.0, low_open=True)
    climb_time: float = param(2.0, low=0.0)
    attach_time: float = param(1.0, low=0.0)
    forwards_start: int = param(1, low=0, integer=True)
    reverse_start: int = param(127, low=1, integer=True)
    coverage_pixel: float = param(0.25, low=0.0, low_open=True)
    complete_fraction: float = param(0.999, low=0.0, high=1.0, low_open=True)
    monitor_period: float = param(1.0, low=0.0, low_open=True, period=True)
    stall_time: float | None = param(600.0, low=0.0, low_open=True)
    stall_collisions: int = param(20, low=0, integer=True)
    power_ground: float = param(0.5, low=0.0)
    power_flight: float = param(110.0 + 10.0, low=0.0)
    power_beacon: float = param(5.0, low=0.0)
    power_hover: float = param(110.0 + 5.0, low=0.0)
    max_speed: float = param(1.0, low=0.0, high=5.0, low_open=True, shown=(0.2, 2.0))
    mass: float = param(0.5, low=0.0, low_open=True)
    max_force: float = param(2.0, low=0.0, low_open=True)
    tau: float = param(0.5, low=0.0, low_open=True)
    air_density: float = param(1.2, low=0.0)
    frontal_area: float = param(0.03, low=0.0)
    drag_coefficient: float = param(1.0, low=0.0)
    body_noise: float = param(0.025, low=0.0)
    body_radius: float = param(0.2, low=0.0, low_open=True)
    dt: float = param(0.1, low=0.0, low_open=True)
    latency: float = param(0.1, low=0.0, low_open=True)
    message_loss: float = param(0.0, low=0.0, high=0.99)

    def __post_init__(self) -> None:
        super().__post_init__()
        world = self.world
        generated = isinstance(world, str) and world in WORLD_KINDS
        builtin = isinstance(world, str) and world in MAPS
        is_file = isinstance(world, str | Path) and Path(world).suffix.lower() in MAP_SUFFIXES
        if not (generated or builtin or is_file or isinstance(world, World)):
            kinds = ", ".join(repr(k) for k in WORLD_KINDS)
            raise ConfigError(
                f"world must be one of {kinds}, a built-in map ({', '.join(MAPS)}), a map file "
                f"({', '.join(MAP_SUFFIXES)}) or a World, got {world!r}"
            )
        if builtin and self.map_resolution is not None:
            raise ConfigError(
                f"map_resolution applies to map files only; the built-in map {world!r} is 1 m "
                f"per pixel, got {self.map_resolution!r}"
            )
        if not (is_file or builtin):
            for name in ("start", "map_resolution"):
                if getattr(self, name) is not None:
                    raise ConfigError(
                        f"{name} applies to map-file worlds only; world={world!r} "
                        + (
                            "places its base in a random start cell with 3 m cells"
                            if generated
                            else "carries its own start and cell size"
                        )
                    )

    @property
    def level(self) -> str:
        """The complexity in effect (the default resolved: medium for mixed, else high)."""
        if self.complexity is not None:
            return self.complexity
        return "medium" if self.world == "mixed" else "high"

    @property
    def powers(self) -> dict[str, float]:
        """Power (W) per mode, for the energy ledger (App. C)."""
        return {
            "ground": self.power_ground,
            "flight": self.power_flight,
            "beacon": self.power_beacon,
            "hover": self.power_hover,
            "off": 0.0,
        }


DEFAULTS = BeaconExplorerParams()
