"""The flocking SolaraViz page: the periodic square with every bird and its next move, the
flock's polarisation live, and sliders for the flock's size, space, sight and the three rule
weights.

Serve it with ``abm viz flocking`` (or ``solara run models.flocking.app``).
"""

from abm.viz.controls import slider
from abm.viz.page import make_page
from models.flocking.model import FlockingModel

__all__ = ["MODEL_PARAMS", "page"]

#: Sliders of the page (SolaraViz model_params); the defaults are the comparison's small case.
MODEL_PARAMS = {
    "birds": slider("birds N", 200, 10, 1000, 10),
    "extent": slider("side of the square (m)", 100.0, 60.0, 300.0, 10.0),
    "visual_distance": slider("visual distance (m)", 5.0, 1.0, 30.0, 0.5),
    "cohere_factor": slider("cohere factor", 0.03, 0.0, 0.3, 0.01),
    "separate_factor": slider("separate factor", 0.015, 0.0, 0.3, 0.005),
    "match_factor": slider("match factor", 0.05, 0.0, 0.5, 0.01),
    "seed": slider("seed", 1, 0, 100, 1),
}

page = make_page(
    FlockingModel,
    MODEL_PARAMS,
    name="flocking",
    series={"polarisation": "polarisation |mean unit velocity|"},
)
Page = page
