"""The flocking SolaraViz page: the periodic square with every bird and its next move, the
flock's polarisation live, and sliders for the flock's size, space, sight and the three rule
weights.

Serve it with ``abm viz flocking`` (or ``solara run models.flocking.app``).
"""

from abm.viz.controls import param_slider, seed_slider
from abm.viz.page import make_page
from models.flocking.model import FlockingModel

#: The model's parameters: every slider's bounds come from them.
P = FlockingModel.Params

__all__ = ["MODEL_PARAMS", "page"]

#: Sliders of the page (SolaraViz model_params); the defaults are the comparison's small case.
MODEL_PARAMS = {
    "birds": param_slider(P, "birds", "birds N", step=10),
    "extent": param_slider(P, "extent", "side of the square (m)", step=10.0),
    "visual_distance": param_slider(P, "visual_distance", "visual distance (m)", step=0.5),
    "cohere_factor": param_slider(P, "cohere_factor", "cohere factor", step=0.01),
    "separate_factor": param_slider(P, "separate_factor", "separate factor", step=0.005),
    "match_factor": param_slider(P, "match_factor", "match factor", step=0.01),
    "seed": seed_slider(),
}

page = make_page(
    FlockingModel,
    MODEL_PARAMS,
    name="flocking",
    series={"polarisation": "polarisation |mean unit velocity|"},
)
Page = page
