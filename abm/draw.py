"""Matplotlib drawing of a swarm model's current state: walls, coverage, links, robots.

Generic over SwarmModel: robots are coloured by state; a model may add arrows (e.g. the
beacons' desired directions) by defining ``arrows() -> (points, vectors)``.
"""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.colors import ListedColormap  # noqa: E402
from matplotlib.patches import Patch  # noqa: E402

__all__ = ["draw_swarm", "save_swarm_png", "STATE_COLOURS"]

#: Colour-blind-safe colours (Okabe-Ito) per robot state.
STATE_COLOURS = {
    "beacon": "#0072B2",
    "explorer": "#D55E00",
    "ground": "#999999",
    "wander": "#E69F00",
    "depleted": "#000000",
}


def draw_swarm(model, ax=None, title: str | None = None):
    """Draw the arena, the covered area, comm links and robots of ``model`` on ``ax``."""
    if ax is None:
        _fig, ax = plt.subplots(figsize=(7, 7))
    arena = model.arena
    extent = (0, arena.width, 0, arena.height)
    ax.imshow(~arena.free, origin="lower", extent=extent, cmap=ListedColormap(["white", "#333333"]))
    coverage = getattr(model, "coverage", None)
    if coverage is not None:
        shade = np.ma.masked_where(~coverage.covered, coverage.covered)
        ax.imshow(shade, origin="lower", extent=extent, cmap=ListedColormap(["#9be3a4"]), alpha=0.6)
    graph = model.comms.graph
    for a, b in graph.edges:
        pa, pb = graph.nodes[a]["pos"], graph.nodes[b]["pos"]
        ax.plot([pa[0], pb[0]], [pa[1], pb[1]], color="#56B4E9", lw=1.2, zorder=2)
    positions = model.space.agent_positions
    states = np.array([agent.state for agent in model.space.active_agents])
    handles = []
    for state in model.STATES:
        mask = states == state
        colour = STATE_COLOURS.get(state, "#CC79A7")
        if mask.any():
            ax.scatter(*positions[mask].T, s=40, color=colour, edgecolor="black", lw=0.5, zorder=4)
        handles.append(Patch(color=colour, label=f"{state} ({int(mask.sum())})"))
    if hasattr(model, "arrows"):
        points, vectors = model.arrows()
        if len(points):
            ax.quiver(
                *points.T,
                *vectors.T,
                angles="xy",
                scale_units="xy",
                scale=1.6,
                color="#0072B2",
                width=0.004,
                zorder=3,
            )
    handles.append(Patch(color="#9be3a4", label="covered area"))
    handles.append(Patch(color="#333333", label="wall"))
    ax.legend(
        handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=9, frameon=False
    )
    ax.set_xlim(0, arena.width)
    ax.set_ylim(0, arena.height)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title(title or f"t = {model.time:.0f} s")
    return ax


def save_swarm_png(model, path: str | Path, title: str | None = None) -> Path:
    """Draw ``model`` and save it as a PNG; returns the path."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig, ax = plt.subplots(figsize=(8, 7))
    draw_swarm(model, ax, title)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
