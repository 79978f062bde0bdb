"""The stigmergy SolaraViz page: the map with wanders, beacons and the area seen (ca); sliders
for the map, the pheromone radius C_rb, the launch rate and the UAV speed.

Serve it with ``abm viz stigmergy`` (or ``solara run models.stigmergy.app``).
"""

from abm.viz.controls import slider
from abm.viz.page import make_page
from models.environments.bitmap import MAPS
from models.stigmergy.model import StigmergyModel

__all__ = ["MODEL_PARAMS", "page"]

#: Sliders and selects of the page (SolaraViz model_params).
MODEL_PARAMS = {
    "map": {"type": "Select", "label": "map", "value": "hall100", "values": list(MAPS)},
    "pheromone_radius": slider("pheromone radius C_rb (m)", 20.0, 5.0, 60.0, 5.0),
    "launch_rate": slider("launch rate eta (robots per 0.5 s)", 0.01, 0.005, 0.1, 0.005),
    "max_speed": slider("UAV speed (m/s)", 2.0, 0.5, 5.0, 0.5),
    "seed": slider("seed", 1, 0, 100, 1),
}

page = make_page(
    StigmergyModel,
    MODEL_PARAMS,
    name="stigmergy",
    series={"coverage": "area seen ca (% of free area)"},
)
Page = page
