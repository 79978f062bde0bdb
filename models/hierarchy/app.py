"""The HST SolaraViz page: the room with the workers (squares) and scouts (circles) coloured by
what they do, the tree's radio links (worker to scout; the queen has no position, so her links
are not drawn), the bubbles of the current rounds (pink rings) and the queen's known map (green:
known free, black: known obstacle); the share of free cells known against time below.
It opens on a 10 m room with 4 boxes, where a round takes seconds; set 20 m and 0 boxes for
the report's room.

Serve it with ``abm viz hierarchy`` (or ``solara run models.hierarchy.app``).
"""

from abm.viz.controls import slider
from abm.viz.page import make_page
from models.hierarchy.model import HierarchyModel

__all__ = ["MODEL_PARAMS", "page"]

#: Sliders and selects of the page (SolaraViz model_params).
MODEL_PARAMS = {
    "workers": slider("workers W", 3, 1, 7, 1),
    "scouts_per_worker": slider("scouts per worker S", 3, 1, 8, 1),
    "world_size": slider("room side (m)", 10.0, 4.0, 20.0, 1.0),
    "boxes": slider("box obstacles", 4, 0, 20, 1),
    "wave_generator": {"type": "Checkbox", "label": "wave generator", "value": True},
    "seed": slider("seed", 1, 0, 100, 1),
}  # fmt: skip

page = make_page(
    HierarchyModel,
    MODEL_PARAMS,
    name="hierarchy",
    series={"known": "free cells in the queen's map (%)"},
)
Page = page
