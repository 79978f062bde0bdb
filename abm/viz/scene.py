"""A matplotlib view that draws what a swarm looks like (:mod:`abm.scene`).

A :class:`~abm.scene.Scene` holds plain arrays (robot positions and states, comm links, the
covered raster, optional arrows), so the same :class:`SceneView` draws a live model (via
:func:`~abm.scene.scene_of`) in the SolaraViz page and ``abm run``'s PNG, and a recorded run in
``abm render``. The view builds its artists once and :meth:`SceneView.update` only swaps their
data, which keeps animations fast.
"""

from collections.abc import Mapping, Sequence

import numpy as np
from matplotlib.axes import Axes
from matplotlib.collections import LineCollection
from matplotlib.colors import to_rgba
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from abm.scene import Backdrop, Scene, backdrop_of
from abm.styles import Layer, StateStyle, resolve_styles

__all__ = [
    "ARROW_COLOUR",
    "COVERED_COLOUR",
    "LINK_COLOUR",
    "WALL_COLOUR",
    "SceneView",
    "view_of",
    "view_on",
]

WALL_COLOUR = "#3a3a3a"
COVERED_COLOUR = "#9be3a4"
LINK_COLOUR = "#56B4E9"
ARROW_COLOUR = "#CC79A7"  # reddish purple: apart from the palette's first colours


def view_of(model, ax: Axes) -> "SceneView":
    """A :class:`SceneView` of a live model on ``ax``, from the model's declared hooks."""
    return view_on(ax, backdrop_of(model))


def view_on(ax: Axes, backdrop: Backdrop) -> "SceneView":
    """A :class:`SceneView` of ``backdrop`` on ``ax``."""
    return SceneView(
        ax,
        backdrop.free,
        backdrop.resolution,
        backdrop.styles,
        pixel=backdrop.pixel,
        arrows_label=backdrop.arrows_label,
    )


class SceneView:
    """Draws scenes of one arena on a matplotlib Axes.

    Args:
        ax: where to draw.
        free: :attr:`abm.scene.Backdrop.free`.
        resolution: :attr:`abm.scene.Backdrop.resolution`.
        styles: :attr:`abm.scene.Backdrop.styles`.
        pixel: :attr:`abm.scene.Backdrop.pixel`.
        arrows_label: :attr:`abm.scene.Backdrop.arrows_label`.

    :func:`view_on` passes a whole backdrop.

    """

    def __init__(
        self,
        ax: Axes,
        free: np.ndarray,
        resolution: float,
        styles: Mapping[str, StateStyle] | Sequence[str],
        pixel: float | None = None,
        arrows_label: str | None = None,
    ) -> None:
        if not isinstance(styles, Mapping):
            styles = resolve_styles(tuple(styles))
        self.ax = ax
        self.styles = dict(styles)
        self.states = tuple(styles)
        self.pixel = pixel
        self.arrows_label = arrows_label
        rows, cols = free.shape
        self.has_walls = bool((~free).any())
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
        self._layers: dict[str, object] = {}
        self._layer_specs: dict[str, Layer] = {}
        self._robots = {}
        for state, style in self.styles.items():
            self._robots[state] = ax.scatter(
                [],
                [],
                s=style.size,
                marker=style.marker,
                color=style.colour,
                edgecolor="black",
                linewidths=0.6,
                zorder=style.layer,
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
        self._draw_layers(scene.layers)
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

    def changing_artists(self) -> list:
        """The artists :meth:`update` changes; the rest of the view (walls, axes) stays as
        built, so a renderer may draw it once for many scenes.
        """
        artists = [*self._robots.values(), self._links, *self._layers.values()]
        return artists + [a for a in (self._cover, self._quiver) if a is not None]

    def _draw_layers(self, layers: list[Layer]) -> None:
        """Extra point clouds and rasters, each artist made once and then updated; a layer
        drawn before but absent from this scene is hidden and leaves the legend.
        """
        shown = {layer.label for layer in layers}
        for label, artist in self._layers.items():
            artist.set_visible(label in shown)
            if label not in shown:
                self._layer_specs.pop(label, None)
        for layer in layers:
            artist = self._layers.get(layer.label)
            if layer.raster is not None:
                rgba = np.zeros((*layer.raster.shape, 4))
                rgba[..., :3] = to_rgba(layer.colour)[:3]
                rgba[..., 3] = 0.6 * np.clip(layer.raster, 0.0, 1.0)
                if artist is None:
                    self._layers[layer.label] = self.ax.imshow(
                        rgba, origin="lower", extent=layer.extent, interpolation="nearest",
                        zorder=0.5,  # over the walls, under the covered area: pink = believed only
                    )  # fmt: skip
                    self.ax.set_xlim(0, self.width)
                    self.ax.set_ylim(0, self.height)
                else:
                    artist.set_data(rgba)
            elif layer.points is not None:
                points = np.asarray(layer.points, dtype=float).reshape(-1, 2)
                if artist is None:
                    self._layers[layer.label] = self.ax.scatter(
                        *points.T, s=layer.size, color=layer.colour, marker=layer.marker,
                        linewidths=0, zorder=layer.layer,
                    )  # fmt: skip
                else:
                    artist.set_offsets(points)
            self._layer_specs[layer.label] = layer

    def legend_handles(self) -> list:
        """Legend entries: each state with its current count, links, arrows, coverage, walls
        (when the arena has any).
        """
        handles = [
            Line2D(
                [],
                [],
                linestyle="none",
                marker=style.marker,
                markersize=8,
                markerfacecolor=style.colour,
                markeredgecolor="black",
                label=f"{style.label or state} ({self.counts[state]})",
            )
            for state, style in self.styles.items()
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
        for label, layer in self._layer_specs.items():
            if layer.raster is not None:
                handles.append(Patch(facecolor=layer.colour, alpha=0.6, label=label))
            else:
                size = float(np.clip(np.sqrt(layer.size), 4.0, 12.0))
                handles.append(Line2D([], [], linestyle="none", marker=layer.marker,
                                      markersize=size, color=layer.colour, alpha=0.6,
                                      label=label))  # fmt: skip
        if self.has_walls:  # a periodic square has none
            handles.append(Patch(facecolor=WALL_COLOUR, label="wall"))
        return handles
