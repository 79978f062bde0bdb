"""What a swarm looks like at one instant, and a matplotlib view that draws it.

A :class:`Scene` holds plain arrays (robot positions and states, comm links, the covered
raster, optional arrows), so the same :class:`SceneView` draws a live model (via
:func:`scene_of`) in the SolaraViz page and a recorded run in ``abm render``. The view builds
its artists once and :meth:`SceneView.update` only swaps their data, which keeps animations fast.
"""

from dataclasses import dataclass, field

import numpy as np
from matplotlib.axes import Axes
from matplotlib.collections import LineCollection
from matplotlib.colors import to_rgba
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

__all__ = [
    "ARROW_COLOUR",
    "COVERED_COLOUR",
    "LINK_COLOUR",
    "STATE_COLOURS",
    "STATE_MARKERS",
    "model_coverage",
    "WALL_COLOUR",
    "Scene",
    "SceneView",
    "scene_of",
    "state_colour",
]

#: Colour-blind-safe colours (Okabe-Ito) per robot state.
STATE_COLOURS = {
    "beacon": "#0072B2",
    "explorer": "#D55E00",
    "ground": "#999999",
    "wander": "#E69F00",
    "depleted": "#000000",
}
WALL_COLOUR = "#3a3a3a"
COVERED_COLOUR = "#9be3a4"
LINK_COLOUR = "#56B4E9"
ARROW_COLOUR = "#CC79A7"  # reddish purple: apart from beacons (blue) and links (sky blue)
#: Marker per state, so states differ in shape as well as colour.
STATE_MARKERS = {"beacon": "o", "explorer": "^", "ground": "s", "wander": "D", "depleted": "X"}
#: Marker area (pt^2) per state; ground robots wait stacked under the base, so their square is
#: drawn large and behind the base beacon's disc.
STATE_SIZES = {"ground": 150.0, "beacon": 55.0}
_SPARE_COLOURS = ("#009E73", "#F0E442", "#000000", "#E69F00")


def state_colour(state: str, states: tuple[str, ...] = ()) -> str:
    """The colour of a robot state (colour-blind-safe Okabe-Ito palette)."""
    if state in STATE_COLOURS:
        return STATE_COLOURS[state]
    index = states.index(state) if state in states else 0
    return _SPARE_COLOURS[index % len(_SPARE_COLOURS)]


@dataclass
class Scene:
    """The swarm at one instant, as plain arrays.

    Attributes:
        time: simulated time (s).
        positions: ``(n, 2)`` robot positions (m).
        states: ``(n,)`` robot states.
        links: ``(m, 2, 2)`` comm links as segments (m).
        covered: boolean coverage raster ``[rows, cols]`` (pixels of ``SceneView.pixel`` m), or
            None when the model keeps none.
        arrows: ``(points, vectors)`` in m, e.g. the beacons' desired directions, or None.

    """

    time: float
    positions: np.ndarray
    states: np.ndarray
    links: np.ndarray = field(default_factory=lambda: np.zeros((0, 2, 2)))
    covered: np.ndarray | None = None
    arrows: tuple[np.ndarray, np.ndarray] | None = None


def model_coverage(model) -> tuple[np.ndarray, float] | None:
    """``(covered raster, pixel side in m)`` of a model with a ``coverage`` CoverageRaster."""
    coverage = getattr(model, "coverage", None)
    if coverage is None or not hasattr(coverage, "covered"):
        return None
    return coverage.covered, float(coverage.pixel)


def scene_of(model, coverage=model_coverage) -> Scene:
    """The current scene of a live SwarmModel (robots, comm links, coverage, arrows).

    Args:
        model: the SwarmModel.
        coverage: ``f(model) -> (covered raster, pixel m) | None``; the default reads the
            model's ``coverage`` CoverageRaster.

    """
    agents = list(model.space.active_agents)
    positions = np.asarray(model.space.agent_positions, dtype=float).reshape(-1, 2)[: len(agents)]
    states = np.array([agent.state for agent in agents], dtype=object)
    graph = model.comms.graph
    links = np.array(
        [[graph.nodes[a]["pos"], graph.nodes[b]["pos"]] for a, b in graph.edges], dtype=float
    ).reshape(-1, 2, 2)
    covered = coverage(model)
    arrows = model.arrows() if hasattr(model, "arrows") else None
    return Scene(
        time=float(model.time),
        positions=positions,
        states=states,
        links=links,
        covered=None if covered is None else covered[0],
        arrows=arrows,
    )


class SceneView:
    """Draws scenes of one arena on a matplotlib Axes.

    Args:
        ax: where to draw.
        free: the arena's free grid ``[rows, cols]`` (row 0 = south).
        resolution: side of one arena cell (m).
        states: the model's robot states, in legend order.
        pixel: side of one coverage-raster pixel (m); None if there is no coverage raster.
        arrows_label: legend label of the arrows (None: no arrows are drawn).

    """

    def __init__(
        self,
        ax: Axes,
        free: np.ndarray,
        resolution: float,
        states: tuple[str, ...],
        pixel: float | None = None,
        arrows_label: str | None = "beacon's desired direction",
    ) -> None:
        self.ax = ax
        self.states = tuple(states)
        self.pixel = pixel
        self.arrows_label = arrows_label
        rows, cols = free.shape
        self.width, self.height = cols * resolution, rows * resolution
        extent = (0.0, self.width, 0.0, self.height)
        walls = np.zeros((rows, cols, 4))
        walls[~free] = to_rgba(WALL_COLOUR)
        walls[free] = (1.0, 1.0, 1.0, 1.0)
        ax.imshow(walls, origin="lower", extent=extent, interpolation="nearest", zorder=0)
        self._covered_rgba = np.array(to_rgba(COVERED_COLOUR, 0.75))
        self._cover = None
        if pixel is not None:
            blank = np.zeros((int(round(self.height / pixel)), int(round(self.width / pixel)), 4))
            self._cover = ax.imshow(
                blank, origin="lower", extent=extent, interpolation="nearest", zorder=1
            )
        self._links = LineCollection([], colors=LINK_COLOUR, linewidths=1.4, zorder=2)
        ax.add_collection(self._links)
        self._quiver = None
        self._robots = {}
        for state in self.states:
            self._robots[state] = ax.scatter(
                [],
                [],
                s=STATE_SIZES.get(state, 45.0),
                marker=STATE_MARKERS.get(state, "o"),
                color=state_colour(state, self.states),
                edgecolor="black",
                linewidths=0.6,
                zorder={"ground": 4, "beacon": 5}.get(state, 6),  # movers on top
            )
        ax.set_xlim(0, self.width)
        ax.set_ylim(0, self.height)
        ax.set_aspect("equal")
        ax.set_xlabel("x (m)")
        ax.set_ylabel("y (m)")
        self.counts = dict.fromkeys(self.states, 0)

    def update(self, scene: Scene) -> None:
        """Show ``scene``: robots, links, covered area and arrows."""
        states = np.asarray(scene.states, dtype=object)
        unknown = set(states.tolist()) - set(self.states)
        if unknown:
            raise ValueError(f"robot states {sorted(unknown)} are not among {self.states}")
        for state, artist in self._robots.items():
            mask = states == state
            artist.set_offsets(scene.positions[mask].reshape(-1, 2))
            self.counts[state] = int(mask.sum())
        self._links.set_segments(list(np.asarray(scene.links).reshape(-1, 2, 2)))
        if self._cover is not None and scene.covered is not None:
            rgba = np.zeros((*scene.covered.shape, 4))
            rgba[scene.covered] = self._covered_rgba
            self._cover.set_data(rgba)
        if self._quiver is not None:
            self._quiver.remove()
            self._quiver = None
        if self.arrows_label and scene.arrows is not None:
            points, vectors = (np.asarray(a, dtype=float).reshape(-1, 2) for a in scene.arrows)
            keep = np.hypot(*vectors.T) > 0 if len(vectors) else np.zeros(0, dtype=bool)
            if keep.any():
                self._quiver = self.ax.quiver(
                    *points[keep].T,
                    *vectors[keep].T,
                    angles="xy",
                    scale_units="xy",
                    scale=1.4,
                    color=ARROW_COLOUR,
                    edgecolor="black",
                    linewidth=0.4,
                    width=0.007,
                    headwidth=3.5,
                    headlength=4.0,
                    zorder=5.5,  # over the beacons they start from, under the explorers
                )

    def legend_handles(self) -> list:
        """Legend entries: each state with its current count, links, arrows, coverage, walls."""
        handles = [
            Line2D(
                [],
                [],
                linestyle="none",
                marker=STATE_MARKERS.get(state, "o"),
                markersize=8,
                markerfacecolor=state_colour(state, self.states),
                markeredgecolor="black",
                label=f"{state} robots ({self.counts[state]})",
            )
            for state in self.states
        ]
        handles.append(Line2D([], [], color=LINK_COLOUR, lw=1.6, label="comm link"))
        if self.arrows_label:
            handles.append(
                Line2D(
                    [],
                    [],
                    color=ARROW_COLOUR,
                    lw=1.6,
                    marker=">",
                    markevery=[1],
                    label=self.arrows_label,
                )
            )
        if self.pixel is not None:
            handles.append(Patch(facecolor=COVERED_COLOUR, label="covered area"))
        handles.append(Patch(facecolor=WALL_COLOUR, label="wall"))
        return handles
