"""A PNG of a swarm model's current state, drawn with the same scene code as the live page.

Walls, covered area, comm links, robots by state (in the model's declared styles) and the
model's arrows: :class:`abm.viz.scene.SceneView` draws them for the SolaraViz page and
``abm render`` alike; this module only puts one view in a figure file.
"""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from abm.viz.scene import SceneView, scene_of, view_of  # noqa: E402

__all__ = ["draw_swarm", "save_swarm_png"]


def draw_swarm(model, ax=None, title: str | None = None) -> SceneView:
    """Draw the arena, the covered area, comm links and robots of ``model`` on ``ax``."""
    if ax is None:
        _fig, ax = plt.subplots(figsize=(7, 7))
    view = view_of(model, ax)
    view.update(scene_of(model))
    ax.legend(
        handles=view.legend_handles(),
        loc="upper left",
        bbox_to_anchor=(1.01, 1.0),
        fontsize=9,
        frameon=False,
    )
    ax.set_title(title or f"t = {model.time:.0f} s")
    return view


def save_swarm_png(model, path: str | Path, title: str | None = None) -> Path:
    """Draw ``model`` and save it as a PNG; returns the path."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig, ax = plt.subplots(figsize=(8, 7))
    draw_swarm(model, ax, title)
    fig.tight_layout()
    fig.savefig(path, dpi=110, bbox_inches="tight")  # a long legend is never cut off
    plt.close(fig)
    return path
