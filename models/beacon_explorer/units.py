"""The unit and meaning of each key of the beacon/explorer swarm's summary (Stirling et al.
2010); the common keys are documented in :data:`abm.units.COMMON`.
"""

from abm.units import Quantity

__all__ = ["SUMMARY_UNITS"]

SUMMARY_UNITS = {
    "world": Quantity("text", "the world's kind (corridor, open, mixed, bitmap)"),
    "complexity": Quantity("text", "the corridor world's complexity (low, medium, high)"),
    "n_robots": Quantity("count", "robots launched from the base: the swarm, without the base"),
    "robots": Quantity(
        "count",
        "robots in the run: n_robots plus the base beacon, which stands at the entrance from "
        "the start (Sect. 3) and is drawn as the base in the pictures",
    ),
    "launch_period": Quantity("s", "inter-launch period T_l"),
    "hover_beacons": Quantity("flag", "beacons hover instead of attaching to the ceiling"),
    "seed": Quantity("id", "the run's seed"),
    "coverage_time": Quantity("s", "simulated time when the run ended (coverage or time limit)"),
    "complete": Quantity("flag", "the covered share reached complete_fraction"),
    "flight_time": Quantity("s", "total swarm flight time, summed over robots"),
    "flight_distance": Quantity(
        "m", "path length flown by the explorers, summed over robots (the robots' odometry)"
    ),
    "mean_flight_speed": Quantity(
        "m/s", "flight_distance / flight_time: the explorers' mean ground speed in flight"
    ),
    "energy_flight": Quantity("J", "energy drawn in flight, summed over robots"),
    "energy_beacon": Quantity("J", "energy drawn as a beacon (attached or hovering)"),
    "energy_ground": Quantity("J", "energy drawn waiting on the ground"),
    "n_beacons_final": Quantity("count", "beacons at the end, the base beacon included"),
    "n_failed": Quantity("count", "robots failed (injected faults)"),
    "branches": Quantity("count", "branches of the corridor world"),
}
