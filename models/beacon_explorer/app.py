"""The beacon/explorer SolaraViz page: the world with beacons, explorers, their desired
directions, comm links and the covered area; sliders for the paper's experimental factors.

Serve it with ``abm viz beacon-explorer`` (or ``solara run models.beacon_explorer.app``).
"""

from abm.viz.controls import slider
from abm.viz.page import make_page
from models.beacon_explorer.model import BeaconExplorerModel

__all__ = ["MODEL_PARAMS", "page"]

#: Sliders and selects of the page (SolaraViz model_params).
MODEL_PARAMS = {
    "world": {"type": "Select", "label": "world", "value": "corridor",
              "values": ["corridor", "open", "mixed"]},
    "complexity": {"type": "Select", "label": "complexity", "value": "high",
                   "values": ["low", "medium", "high"]},
    "launch_period": slider("launch period t (s)", 6.0, 1.0, 30.0, 1.0),
    "n_robots": slider("robots", 20, 2, 40, 1),
    "max_speed": slider("explorer speed (m/s)", 1.0, 0.2, 2.0, 0.1),
    "hover_beacons": {"type": "Checkbox", "label": "beacons hover (no ceiling)", "value": False},
    "seed": slider("seed", 1, 0, 100, 1),
}  # fmt: skip

page = make_page(
    BeaconExplorerModel,
    MODEL_PARAMS,
    name="beacon-explorer",
    series={"coverage": "coverage (% of free area)", "energy": "energy used (J)"},
)
Page = page
