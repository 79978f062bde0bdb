"""How a robot state is drawn: colour, marker, size and layer, declared by each model.

A model lists its states in ``STATES`` and may give each a :class:`StateStyle` in
``STATE_STYLES``; states without one get the next colour of a colour-blind-safe palette
(Okabe-Ito) in the order of ``STATES``. The framework knows no state names.
"""

from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass

import numpy as np

__all__ = ["PALETTE", "Layer", "StateStyle", "resolve_styles"]

#: Okabe-Ito colours, in the order undeclared states take them.
PALETTE = ("#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#F0E442", "#000000")


@dataclass(frozen=True)
class StateStyle:
    """The look of one robot state in pictures and the live page.

    Attributes:
        colour: fill colour (any matplotlib colour, e.g. ``"#0072B2"``).
        marker: matplotlib marker (``"o"`` circle, ``"s"`` square, ``"^"`` triangle, ...).
        size: marker area (pt^2).
        layer: drawing order; higher is drawn on top.
        label: legend text (default: the state's name).

    """

    colour: str
    marker: str = "o"
    size: float = 45.0
    layer: float = 6.0
    label: str | None = None

    def as_dict(self) -> dict:
        """Plain data (saved with a run, so its pictures need no model code)."""
        return asdict(self)


def resolve_styles(
    states: Sequence[str], declared: Mapping[str, StateStyle] | None = None
) -> dict[str, StateStyle]:
    """A style for every state: the declared one, else the next palette colour."""
    declared = dict(declared or {})
    out = {}
    spare = iter(c for c in PALETTE * 4 if c not in {s.colour for s in declared.values()})
    for state in states:
        out[state] = declared.get(state) or StateStyle(next(spare))
    return out


@dataclass(frozen=True, eq=False)
class Layer:
    """Something more a model wants drawn over its arena (``SwarmModel.layers``): a cloud of
    points, or a raster of values in [0, 1] shown as the colour's opacity.

    Attributes:
        label: legend text.
        points: ``(n, 2)`` positions (m), or None.
        raster: ``(rows, cols)`` values in [0, 1], row 0 south, or None.
        extent: ``(x0, x1, y0, y1)`` (m) the raster spans.
        colour: its colour.
        size: marker area of the points (pt^2).
        marker: matplotlib marker of the points (e.g. ``"*"`` for one robot the model
            marks, such as a base station).
        layer: drawing order of the points, as :attr:`StateStyle.layer` (robots are drawn at
            their state's, 4-6 in the models here): 3 keeps a cloud under the robots; a marked
            robot's marker goes between the robots it must show over and those it must not hide.
        still: the layer is the same during the whole run (a base station that never
            moves). A saved run keeps the layers of its end only, so ``abm render`` draws a
            still layer in every frame and any other only in a frame at the run's end.

    """

    label: str
    points: np.ndarray | None = None
    raster: np.ndarray | None = None
    extent: tuple[float, float, float, float] | None = None
    colour: str = "#000000"
    size: float = 4.0
    marker: str = "o"
    layer: float = 3.0
    still: bool = False
