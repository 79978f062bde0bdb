"""Default parameters of the beacon/explorer model, with the paper's values.

Source: Stirling, Roberts, Zufferey, Floreano (2010), "Energy-efficient indoor search by
swarms of simulated flying robots without global information", Swarm Intelligence 4:117-143.
Values not given in the paper are marked "ours".
"""

from dataclasses import dataclass

__all__ = ["BeaconExplorerParams", "SWARM_SIZE", "DEFAULTS"]

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


@dataclass(frozen=True)
class BeaconExplorerParams:
    """Constants of the algorithm and the robots (SI units).

    Attributes:
        interspace: I_r, beacon spacing (m), Sect. 3.3.
        sensor_range: S_r, distance-sensor range and coverage radius (m), Sect. 3.1.
        sensor_noise: std of the distance sensors (m), App. B.
        comm_range: C_r (m), Sect. 3.1.
        corridor_width: two opposing walls closer than this make a corridor beacon (m).
        obstacle_threshold: a direction whose wall reading is below this is an obstacle (m; ours:
            I_r, so a lattice that drifted up to a metre still reads the wall beyond the next
            cell as empty; wall avoidance then stops the explorer short of that wall).
        open_diagonal: five rays into the quadrant between two free cardinal directions all
            reading more than this (nothing sensed within noise) mean open space (m; ours, see
            README).
        spot_taken: a beacon labels a direction "beacon" when another beacon it senses is
            closer than this to the lattice spot I_r away in that direction (m; ours: I_r less a
            margin for lattice drift, so a drifted diagonal neighbour does not hide a free spot).
        attach_eps: epsilon of |T| <= eps, the attach condition, on T low-pass filtered over
            ``filter_time`` (m; ours, calibrated: the paper gives no value). It sets how long an
            explorer takes to settle at its spot (the filtered noise of T is about 7 cm), and so
            how explorers queue at the frontier when they launch close together (the paper: more
            concurrent flyers, more unnecessary flight and collisions). With 0.15 m explorers
            settled at once, and 24 s instead of 6 s saved only 15 % of the flight in
            high-complexity corridors and no energy (+2.5 %); with 0.05 m (and, later, the
            guide hysteresis): -28.1 % and -13.6 % (paper -41.5 / -30.8 %). See the README,
            "Reproduction".
        attach_speed: an explorer attaches only once it has slowed below this (m/s; ours).
        guide_hysteresis: an explorer keeps following its beacon until another in touch is
            nearer by more than this (m; ours: 0 is the paper's plain nearest beacon, which let
            explorers shuttle for ever between two beacons' spots in 0.3 % of runs).
        filter_time: time constant of the explorer's filter of its noisy T (s; ours).
        avoid_gain: gain of the collision-avoidance vector C = gain * (1/d - 1/S_r) (m^2; ours).
        slow_radius: inside this |T| the flight controller slows proportionally (m; ours).
        climb_time: take-off and ascent to flight altitude (s; ours).
        attach_time: ascent to the ceiling and attachment (s; ours).
        forwards_start: hop count at the base (1), Sect. 3.3.
        reverse_start: hop count at frontier beacons (127), Sect. 3.3.
        coverage_pixel: raster pixel of the coverage map (m; ours).
        complete_fraction: coverage fraction counted as a complete search (ours).
        monitor_period: how often the end-of-search conditions are checked (s; ours).

    """

    interspace: float = 3.0
    sensor_range: float = 3.5
    sensor_noise: float = 0.05
    comm_range: float = 4.0
    corridor_width: float = 3.0
    obstacle_threshold: float = 3.0
    open_diagonal: float = 3.45
    spot_taken: float = 2.2
    attach_eps: float = 0.05
    attach_speed: float = 0.2
    guide_hysteresis: float = 0.5
    filter_time: float = 0.3
    avoid_gain: float = 0.5
    slow_radius: float = 1.0
    climb_time: float = 2.0
    attach_time: float = 1.0
    forwards_start: int = 1
    reverse_start: int = 127
    coverage_pixel: float = 0.25
    complete_fraction: float = 0.999
    monitor_period: float = 1.0


DEFAULTS = BeaconExplorerParams()
