"""A PNG of a swarm model's current state, drawn with the same scene code as the live page.

Walls, covered area, comm links, robots by state (in the model's declared styles) and the
model's arrows: :class:`abm.viz.scene.SceneView` draws them for the SolaraViz page and
``abm render`` alike; this module only puts one view in a figure file. It uses matplotlib's
figures directly, not pyplot: no backend is chosen for the caller (a notebook keeps its own)
and pyplot's own import is saved.
"""

from pathlib import Path

from matplotlib.axes import Axes
from matplotlib.figure import Figure

from abm.scene import Picture, picture_of
from abm.viz.scene import SceneView, view_on

__all__ = ["draw_picture", "draw_swarm", "save_picture", "save_swarm_png"]


def draw_picture(picture: Picture, ax: Axes | None = None) -> SceneView:
    """Draw ``picture`` (arena, covered area, comm links, robots, arrows) on ``ax``, or on a
    new figure's axes; its legend goes to the right of the arena.
    """
    if ax is None:
        ax = Figure(figsize=(7, 7)).add_subplot()
    view = view_on(ax, picture.backdrop)
    view.update(picture.scene)
    ax.legend(
        handles=view.legend_handles(),
        loc="upper left",
        bbox_to_anchor=(1.01, 1.0),
        fontsize=9,
        frameon=False,
    )
    ax.set_title(picture.title)
    return view


def draw_swarm(model, ax: Axes | None = None, title: str | None = None) -> SceneView:
    """Draw the arena, the covered area, comm links and robots of ``model`` on ``ax``."""
    return draw_picture(picture_of(model, title), ax)


def save_picture(picture: Picture, path: str | Path) -> Path:
    """Draw ``picture`` and save it as a PNG; returns the path."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig = Figure(figsize=(8, 7))
    draw_picture(picture, fig.add_subplot())
    fig.tight_layout()
    fig.savefig(path, dpi=110, bbox_inches="tight")  # a long legend is never cut off
    return path


def save_swarm_png(model, path: str | Path, title: str | None = None) -> Path:
    """Draw ``model`` and save it as a PNG; returns the path."""
    return save_picture(picture_of(model, title), path)
