"""What a picture of a swarm model shows, as plain arrays: no plotting library needed.

A :class:`Scene` is the swarm at one instant (robot positions and states, comm links, the
covered raster, arrows, the model's layers); a :class:`Backdrop` is what stays put (the arena's
walls, the state styles, the raster's pixel). :class:`abm.viz.scene.SceneView` draws both for
the live page, ``abm run``'s PNG and ``abm render``. Kept apart from the drawing so that a run
can describe its picture without loading matplotlib, and hand the description (it pickles) to
another process that draws it (:mod:`abm.png_process`).
"""

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from abm.styles import Layer, StateStyle

__all__ = ["Backdrop", "Picture", "Scene", "backdrop_of", "picture_of", "scene_of"]


@dataclass
class Scene:
    """The swarm at one instant, as plain arrays.

    Attributes:
        time: simulated time (s).
        positions: ``(n, 2)`` robot positions (m).
        states: ``(n,)`` robot states.
        links: ``(m, 2, 2)`` comm links as segments (m).
        covered: boolean coverage raster ``[rows, cols]`` (pixels of ``Backdrop.pixel`` m), or
            None when the model keeps none.
        arrows: ``(points, vectors)`` in m, e.g. the beacons' desired directions, or None.
        layers: the model's extra :class:`~abm.styles.Layer` s (point clouds, rasters).

    """

    time: float
    positions: np.ndarray
    states: np.ndarray
    links: np.ndarray = field(default_factory=lambda: np.zeros((0, 2, 2)))
    covered: np.ndarray | None = None
    arrows: tuple[np.ndarray, np.ndarray] | None = None
    layers: list[Layer] = field(default_factory=list)


@dataclass(frozen=True)
class Backdrop:
    """What every picture of one model shares: its arena and how its robots look.

    Attributes:
        free: the arena's free grid ``[rows, cols]`` (row 0 = south).
        resolution: side of one arena cell (m).
        styles: state -> :class:`~abm.styles.StateStyle`, in legend order (or a sequence of
            states, styled from the palette).
        pixel: side of one coverage-raster pixel (m); None if there is no coverage raster.
        arrows_label: legend label of the arrows (None: no arrows are drawn).

    """

    free: np.ndarray
    resolution: float
    styles: Mapping[str, StateStyle] | Sequence[str]
    pixel: float | None = None
    arrows_label: str | None = None


@dataclass(frozen=True)
class Picture:
    """One picture of a model, all of it plain data: its backdrop, its scene and its title."""

    backdrop: Backdrop
    scene: Scene
    title: str


def scene_of(model) -> Scene:
    """The current scene of a live SwarmModel (robots, comm links, coverage, arrows)."""
    from abm.checks import arrows_of, layers_of  # loads numba: not for a process that only draws

    agents = list(model.space.active_agents)
    # Mesa's space has no position array before its first agent
    positions = (
        np.asarray(model.space.agent_positions, dtype=float).reshape(-1, 2)
        if agents
        else np.zeros((0, 2))
    )
    states = np.array([agent.state for agent in agents], dtype=object)
    graph = model.comms.graph
    placed = graph.nodes(data="pos")
    links = np.array(
        [
            [placed[a], placed[b]]
            for a, b in graph.edges
            if placed[a] is not None and placed[b] is not None  # off-arena nodes: no line
        ],
        dtype=float,
    ).reshape(-1, 2, 2)
    return Scene(
        time=float(model.time),
        positions=positions,
        states=states,
        links=links,
        covered=None if model.coverage is None else model.coverage.covered,
        arrows=arrows_of(model) if model.ARROWS_LABEL else None,
        layers=layers_of(model),
    )


def backdrop_of(model) -> Backdrop:
    """The backdrop of a live model, from its arena, declared styles and hooks."""
    return Backdrop(
        free=model.arena.free,
        resolution=model.arena.resolution,
        styles=model.state_styles,
        pixel=None if model.coverage is None else model.coverage.pixel,
        arrows_label=model.ARROWS_LABEL,
    )


def picture_of(model, title: str | None = None) -> Picture:
    """The picture of a live model now: titled ``title``, or its time (``t = 120 s``)."""
    return Picture(backdrop_of(model), scene_of(model), title or f"t = {model.time:.0f} s")
