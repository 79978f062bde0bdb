"""Pick a world generator by name: the entry point the models and sweeps call."""

import numpy as np

from abm.errors import ConfigError, check_choice
from abm.worlds.corridor import corridor_world
from abm.worlds.mixed import MIXED_BRANCHING, mixed_world
from abm.worlds.open_room import open_world
from abm.worlds.world import COMPLEXITIES, WORLD_KINDS, World

__all__ = ["make_world"]


def make_world(
    kind: str,
    complexity: str = "medium",
    rng: np.random.Generator | int | None = None,
    cell_size: float = 3.0,
) -> World:
    """Generate a paper test environment (Stirling 2010, Sect. 3.5, Fig. 5).

    Args:
        kind: ``"corridor"`` (40 branching corridor cells), ``"open"`` (a 5 x 5 cell room with
            obstacles) or ``"mixed"`` (two 3 x 3 rooms and 22 corridor cells).
        complexity: ``"low"``, ``"medium"`` or ``"high"``; mixed worlds exist only at
            ``"medium"`` (the paper's medium corridor branching).
        rng: a ``numpy.random.Generator``, an int seed, or None for a fresh generator.
        cell_size: side of a cell (m).

    Raises:
        ConfigError: unknown ``kind`` or ``complexity``, or another bad parameter.

    """
    check_choice("kind", kind, WORLD_KINDS)
    check_choice("complexity", complexity, COMPLEXITIES)
    if kind == "corridor":
        return corridor_world(complexity, rng, cell_size=cell_size)
    if kind == "open":
        return open_world(complexity, rng, cell_size=cell_size)
    if complexity != MIXED_BRANCHING:
        raise ConfigError(
            f"complexity must be {MIXED_BRANCHING!r} for kind='mixed' (the paper's mixed worlds "
            f"use medium corridor branching only), got {complexity!r}"
        )
    return mixed_world(rng, cell_size=cell_size)
