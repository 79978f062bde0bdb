"""The stigmergy SolaraViz page: the map with wanders, beacons and the area seen (ca); sliders
for the map, the pheromone radius C_rb, the launch rate and the UAV speed.

Serve it with ``abm viz stigmergy`` (or ``solara run models.stigmergy.app``).
"""

from abm.viz.controls import param_slider, seed_slider
from abm.viz.page import make_page
from models.environments.bitmap import MAPS
from models.stigmergy.model import StigmergyModel

#: The model's parameters: every slider's bounds come from them.
P = StigmergyModel.Params

__all__ = ["MODEL_PARAMS", "page"]

#: Sliders and selects of the page (SolaraViz model_params).
MODEL_PARAMS = {
    "map": {"type": "Select", "label": "map", "value": "hall100", "values": list(MAPS)},
    "pheromone_radius": param_slider(P, "pheromone_radius", "pheromone radius C_rb (m)", step=5.0),
    "launch_rate": param_slider(P, "launch_rate", "launch rate eta (robots per 0.5 s)", step=0.005),
    "max_speed": param_slider(P, "max_speed", "UAV speed (m/s)", step=0.5),
    "seed": seed_slider(),
}

page = make_page(
    StigmergyModel,
    MODEL_PARAMS,
    name="stigmergy",
    series={"coverage": "area seen ca (% of free area)"},
)
Page = page
