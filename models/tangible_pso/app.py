"""The tangible-PSO SolaraViz page: the AoI map (green), the no-fly zones (walls), every virtual
MAV of every particle coloured by what the feasibility check did to it, the best swarm b_g
(black) with its localisation links (arrows) and the best particle's trajectories (pink), and
the best cost against time. One Mesa step is one transition's flight or more.

Serve it with ``abm viz tangible-pso`` (or ``solara run models.tangible_pso.app``).
"""

from abm.viz.controls import param_slider, seed_slider
from abm.viz.page import make_page
from models.tangible_pso.model import TangiblePSOModel
from models.tangible_pso.scenario import SCENARIOS

#: The model's parameters: every slider's bounds come from them.
P = TangiblePSOModel.Params

__all__ = ["MODEL_PARAMS", "page"]

#: Sliders and selects of the page (SolaraViz model_params).
MODEL_PARAMS = {
    "scenario": {"type": "Select", "label": "scenario", "value": "nofly",
                 "values": list(SCENARIOS)},
    "n_mavs": param_slider(P, "n_mavs", "MAVs n_r"),
    "neighbours": param_slider(P, "neighbours", "required neighbours k"),
    "motion_planning": {"type": "Checkbox", "label": "motion planning", "value": True},
    "particles": param_slider(P, "particles", "particles"),
    "iterations": param_slider(P, "iterations", "iterations"),
    "seed": seed_slider(),
}  # fmt: skip

page = make_page(
    TangiblePSOModel,
    MODEL_PARAMS,
    name="tangible-pso",
    series={"best_cost": "best cost CF (eq. 1)"},
)
Page = page
