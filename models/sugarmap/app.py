"""The SugarMap SolaraViz page: the arena with the explorers' true positions, their particle
clouds, the anchors, the brain's GlobalMap (pink: the probability a cell is covered) over the
truly covered cells (green), and coverage against time; sliders for the swarm. It opens on the
paper's 5 m x 3 m testbed (5 anchors, 2 explorers), where the anchors land within a minute;
pick "open" for the 20 m square of the simulations.

Serve it with ``abm viz sugarmap`` (or ``solara run models.sugarmap.app``).
"""

from abm.viz.controls import param_slider, seed_slider
from abm.viz.page import make_page
from models.sugarmap.arenas import ARENAS
from models.sugarmap.model import SugarMapModel

#: The model's parameters: every slider's bounds come from them.
P = SugarMapModel.Params

__all__ = ["MODEL_PARAMS", "page"]

#: Sliders and selects of the page (SolaraViz model_params).
MODEL_PARAMS = {
    "arena": {"type": "Select", "label": "arena", "value": "testbed", "values": list(ARENAS)},
    "n_anchors": param_slider(P, "n_anchors", "anchors", 5),
    "n_explorers": param_slider(P, "n_explorers", "explorers", 2),
    "n_particles": param_slider(P, "n_particles", "particles per explorer", 10),
    "heading_model": {"type": "Select", "label": "heading errors", "value": "literal",
                      "values": ["literal", "accumulate"]},
    "seed": seed_slider(),
}  # fmt: skip

page = make_page(
    SugarMapModel,
    MODEL_PARAMS,
    name="sugarmap",
    series={"coverage": "true coverage (% of navigable cells)"},
)
Page = page
