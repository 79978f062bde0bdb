"""The unit and meaning of each key of the stigmergy swarm's summary (Arnaldo et al. 2018,
Table 1); the common keys are documented in :data:`abm.units.COMMON`.
"""

from abm.units import Quantity

__all__ = ["SUMMARY_UNITS"]

SUMMARY_UNITS = {
    "map": Quantity("text", "the map's name"),
    "pheromone_radius": Quantity("m", "radius of a beacon's virtual pheromone C_rb"),
    "seed": Quantity("id", "the run's seed"),
    "wander": Quantity("count", "robots wandering at the end (w)"),
    "beacon": Quantity("count", "robots that became beacons by the end (b)"),
    "robots": Quantity("count", "robots launched by the end (w + b plus any failed)"),
    "ca": Quantity("%", "area covered (ca), share of the free area"),
    "cb": Quantity(
        "%",
        "free area seen (detection range, walls block the view) from the live robots' final "
        "positions (cb), share of the free area",
    ),
    "entropy": Quantity("bit", "the map's entropy sum P log2 P (the a0 regression's covariate)"),
    "envsize": Quantity("m^2", "the map's area (width x height)"),
    "launch_period": Quantity("s", "time between two launches"),
    "map_digest": Quantity("text", "digest of the map's walls (which map the run used)"),
}
