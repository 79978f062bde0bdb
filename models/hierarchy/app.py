"""The HST SolaraViz page: the room with the workers (squares) and scouts (circles) coloured by
what they do, the tree's radio links (worker to scout; the queen has no position, so her links
are not drawn), the bubbles of the current rounds (pink rings) and the queen's known map (green:
known free, black: known obstacle); the share of free cells known against time below.
It opens on a 10 m room with 4 boxes, where a round takes seconds; set 20 m and 0 boxes for
the report's room.

Serve it with ``abm viz hierarchy`` (or ``solara run models.hierarchy.app``).
"""

from abm.viz.controls import param_slider, seed_slider
from abm.viz.page import make_page
from models.hierarchy.model import HierarchyModel

#: The model's parameters: every slider's bounds come from them.
P = HierarchyModel.Params

__all__ = ["MODEL_PARAMS", "page"]

#: Sliders and selects of the page (SolaraViz model_params).
MODEL_PARAMS = {
    "workers": param_slider(P, "workers", "workers W", 3),
    "scouts_per_worker": param_slider(P, "scouts_per_worker", "scouts per worker S", 3),
    "world_size": param_slider(P, "world_size", "room side (m)", 10.0, 1.0),
    "boxes": param_slider(P, "boxes", "box obstacles", 4),
    "wave_generator": {"type": "Checkbox", "label": "wave generator", "value": True},
    "subtree_transits": {"type": "Select", "label": "subtree transits", "value": "together",
                         "values": ["together", "staggered"]},
    "seed": seed_slider(),
}  # fmt: skip

page = make_page(
    HierarchyModel,
    MODEL_PARAMS,
    name="hierarchy",
    series={"known": "free cells in the queen's map (%)"},
)
Page = page
