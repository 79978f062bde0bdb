"""The tangible-PSO SolaraViz page: the AoI map (green), the no-fly zones (walls), every virtual
MAV of every particle coloured by what the feasibility check did to it, the best swarm b_g
(black) with its localisation links (arrows) and the best particle's trajectories (pink), and
the best cost against time. One Mesa step is one transition's flight or more.

Serve it with ``abm viz tangible-pso`` (or ``solara run models.tangible_pso.app``).
"""

from abm.viz.controls import slider
from abm.viz.page import make_page
from models.tangible_pso.model import TangiblePSOModel
from models.tangible_pso.scenario import SCENARIOS

__all__ = ["MODEL_PARAMS", "page"]

#: Sliders and selects of the page (SolaraViz model_params).
MODEL_PARAMS = {
    "scenario": {"type": "Select", "label": "scenario", "value": "nofly",
                 "values": list(SCENARIOS)},
    "n_mavs": slider("MAVs n_r", 3, 1, 8, 1),
    "neighbours": slider("required neighbours k", 1, 0, 5, 1),
    "motion_planning": {"type": "Checkbox", "label": "motion planning", "value": True},
    "particles": slider("particles", 40, 2, 80, 1),
    "iterations": slider("iterations", 70, 10, 150, 1),
    "seed": slider("seed", 1, 0, 100, 1),
}  # fmt: skip

page = make_page(
    TangiblePSOModel,
    MODEL_PARAMS,
    name="tangible-pso",
    series={"best_cost": "best cost CF (eq. 1)"},
)
Page = page
