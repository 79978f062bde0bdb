"""Draw the frames of a matplotlib figure by redrawing only what changes, with a full draw's pixels.

A frame of a run's picture changes only in a few artists (robots, links, covered area, cursors,
legend, title); the axes, ticks, labels, walls and curves stay. :class:`FrameBlitter` draws the
rest once into a background and, for each frame, puts the background back and draws, in
matplotlib's own order, the changing artists *and every artist matplotlib draws after them in
the same axes* (an axis or a frame drawn over the covered area, a legend over a cursor), except
those found, by drawing each alone once per layout, to paint no pixel that what is redrawn before
them may paint: they join the background. Since a draw only paints over what is already there,
the result is the pixels a full draw gives.

Assumes what a figure of side-by-side panels satisfies: no two axes overlap (each axes' changing
part is drawn at that axes' turn, over the background of the axes after it), and no artist
outside the changing ones changes between frames.
"""

from collections.abc import Callable, Iterable
from operator import attrgetter

import numpy as np
from matplotlib.artist import Artist
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.layout_engine import PlaceHolderLayoutEngine
from matplotlib.path import Path
from matplotlib.transforms import Affine2D

__all__ = ["FrameBlitter"]


class FrameBlitter:
    """Renders one Agg figure frame after frame, redrawing only what ``changing`` names.

    Args:
        figure: the figure, on a ``FigureCanvasAgg``.
        changing: returns the artists that may change from one frame to the next (asked anew
            each frame, so artists made later, such as a legend rebuilt per frame, count).

    """

    def __init__(self, figure: Figure, changing: Callable[[], Iterable[Artist]]) -> None:
        self.figure = figure
        self._changing = changing
        self._key: tuple | None = None
        self._background = None
        self._moved: set[Artist] = set()
        #: full (background) draws so far; the rest of the frames were blitted
        self.background_draws = 0

    def render(self) -> np.ndarray:
        """The figure now, as an ``(h, w, 4)`` uint8 RGBA view of the canvas (valid until the
        next draw: copy it to keep it).

        The background is drawn again when the figure's size, its dpi or the set of unchanging
        artists differs from the last frame's, and at every frame while the figure has a layout
        engine (which may move everything; freeze it with ``set_layout_engine("none")``).
        """
        figure = self.figure
        canvas = figure.canvas
        changing = set(self._changing())
        head, tail = _split(figure, changing)
        key = (canvas.get_width_height(physical=True), figure.dpi, head)
        lays_out = not isinstance(figure.get_layout_engine(), PlaceHolderLayoutEngine | None)
        if lays_out or key != self._key:
            self._moved = set() if lays_out else self._apart(tail, changing)
            self._draw_background([a for a in tail if a not in self._moved])
            self._key = None if lays_out else key
        else:
            canvas.get_renderer().restore_region(self._background)
        renderer = canvas.get_renderer()
        for artist in tail:
            if artist not in self._moved:
                artist.draw(renderer)
        return np.asarray(renderer.buffer_rgba())

    def _apart(self, tail: list[Artist], changing: set[Artist]) -> set[Artist]:
        """Unchanging artists of the tail that may join the background: those that paint no
        pixel that a changing artist before them may paint (inside its clip box) nor any
        pixel of an artist before them that stays in the tail. Drawing them earlier then
        changes no pixel. Found by drawing each alone, so it holds for this layout exactly.
        """
        renderer = self.figure.canvas.get_renderer()
        moved: set[Artist] = set()
        taken = np.zeros((renderer.height, renderer.width), dtype=bool)
        place = None
        for artist in tail:
            here = artist.axes if artist.axes is not None else artist.figure
            if here is not place:  # a new axes (or the figure's own): nothing painted there yet
                place, taken[:] = here, False
            if artist in changing:
                taken |= _reach(renderer, artist)
                continue
            painted = _paint(renderer, artist)
            if (painted & taken).any():
                taken |= painted
            else:
                moved.add(artist)
        return moved

    def _draw_background(self, tail: list[Artist]) -> None:
        """A full draw without the ``tail`` (matplotlib skips animated artists), kept."""
        flags = [artist.get_animated() for artist in tail]
        for artist in tail:
            artist.set_animated(True)
        try:
            self.figure.canvas.draw()
        finally:
            for artist, flag in zip(tail, flags, strict=True):
                artist.set_animated(flag)
        self._background = self.figure.canvas.copy_from_bbox(self.figure.bbox)
        self.background_draws += 1


def _split(figure: Figure, changing: set[Artist]) -> tuple[tuple, list[Artist]]:
    """What stays and what is drawn each frame, in the order :meth:`Figure.draw` draws them.

    Returns ``(head, tail)``: the head names the unchanging artists of each place (the figure
    and each axes) up to its first changing one; the tail lists that changing artist and every
    one drawn after it in the same place, axes by axes, then the figure's own.
    """
    head: list = []
    tail: list[Artist] = []
    figure_tail: list[Artist] = []
    redrawn: list[Axes] = []  # axes with a changing part: none may lie under a later axes
    for artist in _figure_order(figure):
        if figure_tail or artist in changing:
            figure_tail.append(artist)
        elif isinstance(artist, Axes):
            if any(ax.bbox.overlaps(artist.bbox) for ax in redrawn):
                raise ValueError("FrameBlitter needs axes that do not overlap")
            order = _axes_order(artist)
            cut = next((i for i, a in enumerate(order) if a in changing), len(order))
            if cut < len(order):
                redrawn.append(artist)
            head.append((artist, tuple(order[:cut])))
            tail.extend(order[cut:])
        else:
            head.append(artist)
    return tuple(head), tail + figure_tail


def _figure_order(figure: Figure) -> list[Artist]:
    """The figure's artists in the order ``Figure.draw`` draws them (after its patch)."""
    artists = [a for a in figure.get_children() if a is not figure.patch and not a.get_animated()]
    return sorted(artists, key=attrgetter("zorder"))


def _axes_order(ax: Axes) -> list[Artist]:
    """The axes' artists in the order ``Axes.draw`` draws them (patch first)."""
    artists = ax.get_children()
    artists.remove(ax.patch)
    framed = ax.axison and ax.get_frame_on()
    if not framed:
        for spine in ax.spines.values():
            artists.remove(spine)
    if not ax.axison:
        for axis in (ax.xaxis, ax.yaxis):
            artists.remove(axis)
    artists = sorted((a for a in artists if not a.get_animated()), key=attrgetter("zorder"))
    return [ax.patch, *artists] if framed else artists


def _paint(renderer, artist: Artist) -> np.ndarray:
    """Pixels ``artist`` paints when drawn alone."""
    renderer.clear()
    artist.draw(renderer)
    return np.asarray(renderer.buffer_rgba())[..., 3] > 0


def _reach(renderer, artist: Artist) -> np.ndarray:
    """Pixels ``artist`` may ever paint: inside its clip box, or anywhere if it has none."""
    box = artist.get_clip_box()
    if not artist.get_clip_on() or box is None:
        return np.ones((renderer.height, renderer.width), dtype=bool)
    renderer.clear()
    gc = renderer.new_gc()
    gc.set_clip_rectangle(box)
    gc.set_linewidth(0)
    whole = Affine2D().scale(renderer.width, renderer.height)
    renderer.draw_path(gc, Path.unit_rectangle(), whole, rgbFace=(0.0, 0.0, 0.0, 1.0))
    gc.restore()
    return np.asarray(renderer.buffer_rgba())[..., 3] > 0
