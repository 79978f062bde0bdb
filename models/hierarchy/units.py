"""The unit and meaning of each key of the hierarchical swarm's summary; the common keys are
documented in :data:`abm.units.COMMON`.

Every key is in SI like the other models': scan areas in m^2, drive distances in m. The report
the model reproduces gives them in cm^2 and cm ("Data Collection"; the axes of Figs. 36-38);
divide its numbers by 10^4 (areas) and 100 (distances) to compare: Fig. 37's axis runs to
3,000,000 cm^2 = 300 m^2.
"""

from abm.units import Quantity

__all__ = ["SUMMARY_UNITS"]

SUMMARY_UNITS = {
    "topology": Quantity("text", "the swarm's topology: hst (the tree), star, fc or ring"),
    "N": Quantity("count", "robots in the run, queen included (1 + W + W S in the hierarchy)"),
    "links": Quantity("count", "links of the comm graph"),
    "W": Quantity("count", "workers W"),
    "S": Quantity("count", "scouts per worker S"),
    "scouts": Quantity("count", "scouts in all"),
    "complete": Quantity("flag", "the queen called the coverage complete (1.0) or not (0.0)"),
    "completion_time": Quantity(
        "s", "simulated time of the queen's call, COMPLETE or CANNOT_COMPLETE (NaN: none)"
    ),
    "scout_scan_area": Quantity("m^2", "sum of pi r^2 over a scout's SCANs, mean per scout"),
    "worker_scan_area": Quantity("m^2", "sum of pi r^2 of a worker's bubbles, mean per worker"),
    "queen_scan_area": Quantity("m^2", "the world's area, the queen's bubble"),
    "scout_drive": Quantity("m", "smoothed path length driven, mean per scout"),
    "worker_drive": Quantity("m", "smoothed path length driven, mean per worker"),
    "queen_iterations": Quantity("count", "the queen's planning iterations"),
    "worker_iterations": Quantity("count", "planning iterations, mean per worker"),
    "known_free_fraction": Quantity("1", "share of the free cells the queen's map knows free"),
    "wave_order_violations": Quantity("count", "moves out of wave order"),
    "robot_proximity_events": Quantity("count", "two robots closer than the safety distance"),
    "sibling_proximity_events": Quantity("count", "two scouts of one worker too close"),
    "path_cells_blocked": Quantity("count", "planned path cells found blocked"),
    "stalled_moves": Quantity("count", "moves the path follower gave up"),
    "workers_failed": Quantity("count", "workers failed"),
    "reattached": Quantity("count", "scouts reattached to another worker"),
    "messages": Quantity("count", "messages sent"),
    "messages_task": Quantity(
        "count", "messages sent during the task, one per destination (per-destination accounting)"
    ),
    "transmissions_task": Quantity(
        "count",
        "radio transmissions during the task, one per broadcast to several destinations on a "
        "shared channel (broadcast accounting)",
    ),
    "messages_startup": Quantity("count", "messages sent during start-up"),
    "bytes": Quantity("byte", "bytes of all messages"),
    "max_node_load": Quantity("count", "most messages sent plus received by one robot"),
    "queen_load": Quantity("count", "messages sent plus received by the queen"),
    "worker_load_max": Quantity("count", "most messages sent plus received by a worker"),
    "scout_load_max": Quantity("count", "most messages sent plus received by a scout"),
    "msg_*": Quantity("count", "messages of the kind *"),
}
