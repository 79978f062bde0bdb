"""The beacon/explorer SolaraViz page: the world with beacons, explorers, their desired
directions, comm links and the covered area; sliders for the paper's experimental factors.

Serve it with ``abm viz beacon-explorer`` (or ``solara run models.beacon_explorer.app``).
"""

from abm.viz.controls import param_slider, seed_slider
from abm.viz.page import make_page
from models.beacon_explorer.model import BeaconExplorerModel

#: The model's parameters: every slider's bounds come from them.
P = BeaconExplorerModel.Params

__all__ = ["MODEL_PARAMS", "page"]

#: Sliders and selects of the page (SolaraViz model_params).
MODEL_PARAMS = {
    "world": {"type": "Select", "label": "world", "value": "corridor",
              "values": ["corridor", "open", "mixed"]},
    "complexity": {"type": "Select", "label": "complexity", "value": "high",
                   "values": ["low", "medium", "high"]},
    "launch_period": param_slider(P, "launch_period", "launch period t (s)", step=1.0),
    "n_robots": param_slider(P, "n_robots", "robots", 20),
    "max_speed": param_slider(P, "max_speed", "explorer speed (m/s)", step=0.1),
    "hover_beacons": {"type": "Checkbox", "label": "beacons hover (no ceiling)", "value": False},
    "seed": seed_slider(),
}  # fmt: skip

page = make_page(
    BeaconExplorerModel,
    MODEL_PARAMS,
    name="beacon-explorer",
    series={"coverage": "coverage (% of free area)", "energy": "energy used (J)"},
)
Page = page
