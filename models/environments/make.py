"""Pick a world generator by name: the entry point the models and sweeps call."""

import math

import numpy as np

from abm.errors import ConfigError, check_choice, check_range
from models.environments.corridor import corridor_world
from models.environments.mixed import MIXED_BRANCHING, MIXED_CORRIDOR_CELLS, ROOM_SIDE, mixed_world
from models.environments.open_room import OBSTACLES, ROOM_CELLS, open_world
from models.environments.world import COMPLEXITIES, WORLD_KINDS, World

__all__ = ["make_world"]


def make_world(
    kind: str,
    complexity: str = "medium",
    rng: np.random.Generator | int | None = None,
    cell_size: float = 3.0,
    size: int | None = None,
) -> World:
    """Generate a paper test environment (Stirling 2010, Sect. 3.5, Fig. 5).

    Args:
        kind: ``"corridor"`` (40 branching corridor cells), ``"open"`` (a 5 x 5 cell room with
            obstacles) or ``"mixed"`` (two 3 x 3 rooms and 22 corridor cells).
        complexity: ``"low"``, ``"medium"`` or ``"high"``; mixed worlds exist only at
            ``"medium"`` (the paper's medium corridor branching).
        rng: a ``numpy.random.Generator``, an int seed, or None for a fresh generator.
        cell_size: side of a cell (m).
        size: about how many free cells the world should have (a 2,000-robot swarm needs
            room); None: the paper's 40-cell corridors, 5 x 5 rooms and 40-cell mixed worlds.
            Corridors get exactly ``size`` cells; open rooms the side (a multiple of 5 cells)
            whose expected free area is nearest; mixed worlds two rooms holding about half of
            it and corridors the rest.

    Raises:
        ConfigError: unknown ``kind`` or ``complexity``, or another bad parameter.

    """
    check_choice("kind", kind, WORLD_KINDS)
    check_choice("complexity", complexity, COMPLEXITIES)
    if size is not None:
        check_range("size", size, 10, 1_000_000, integer=True)
    if kind == "corridor":
        return corridor_world(complexity, rng, n_cells=size or 40, cell_size=cell_size)
    if kind == "open":
        if size is None:
            return open_world(complexity, rng, cell_size=cell_size)
        free_share = 1.0 - OBSTACLES[complexity] / ROOM_CELLS**2
        tiles = max(1, round(math.sqrt(size / free_share) / ROOM_CELLS))
        return open_world(complexity, rng, cell_size=cell_size, room_cells=ROOM_CELLS * tiles)
    if complexity != MIXED_BRANCHING:
        raise ConfigError(
            f"complexity must be {MIXED_BRANCHING!r} for kind='mixed' (the paper's mixed worlds "
            f"use medium corridor branching only), got {complexity!r}"
        )
    if size is None:
        return mixed_world(rng, cell_size=cell_size)
    room_side = max(ROOM_SIDE, round(math.sqrt(size / 4)))
    corridor = max(MIXED_CORRIDOR_CELLS, size - 2 * room_side**2)
    return mixed_world(rng, cell_size=cell_size, room_side=room_side, corridor_cells=corridor)
