"""The SugarMap SolaraViz page: the arena with the explorers' true positions, their particle
clouds, the anchors, the brain's GlobalMap (pink: the probability a cell is covered) over the
truly covered cells (green), and coverage against time; sliders for the swarm. It opens on the
paper's 5 m x 3 m testbed (5 anchors, 2 explorers), where the anchors land within a minute;
pick "open" for the 20 m square of the simulations.

Serve it with ``abm viz sugarmap`` (or ``solara run models.sugarmap.app``).
"""

from abm.viz.controls import slider
from abm.viz.page import make_page
from models.sugarmap.arenas import ARENAS
from models.sugarmap.model import SugarMapModel

__all__ = ["MODEL_PARAMS", "page"]

#: Sliders and selects of the page (SolaraViz model_params).
MODEL_PARAMS = {
    "arena": {"type": "Select", "label": "arena", "value": "testbed", "values": list(ARENAS)},
    "n_anchors": slider("anchors", 5, 1, 12, 1),
    "n_explorers": slider("explorers", 2, 1, 8, 1),
    "n_particles": slider("particles per explorer", 10, 1, 100, 1),
    "heading_model": {"type": "Select", "label": "heading errors", "value": "literal",
                      "values": ["literal", "accumulate"]},
    "seed": slider("seed", 1, 0, 100, 1),
}  # fmt: skip

page = make_page(
    SugarMapModel,
    MODEL_PARAMS,
    name="sugarmap",
    series={"coverage": "true coverage (% of navigable cells)"},
)
Page = page
