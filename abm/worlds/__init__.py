"""Test environments of Stirling et al. (2010), Sect. 3.5 and Fig. 5, generated from a seed.

Three families on 3 m x 3 m cells: branching corridors (40 cells), open 5 x 5 cell rooms with
obstacle cells, and mixed worlds of two 3 x 3 rooms joined by 22 corridor cells. Every generator
takes ``rng`` (a ``numpy.random.Generator``, an int seed or None) and returns a :class:`World`.
"""

from abm.worlds.corridor import BRANCHING, branch_count, corridor_world, grow_corridor
from abm.worlds.make import make_world
from abm.worlds.mixed import mixed_world
from abm.worlds.open_room import OBSTACLES, open_world, room_layouts
from abm.worlds.world import COMPLEXITIES, WORLD_KINDS, World, as_generator

__all__ = [
    "BRANCHING",
    "COMPLEXITIES",
    "OBSTACLES",
    "WORLD_KINDS",
    "World",
    "as_generator",
    "branch_count",
    "corridor_world",
    "grow_corridor",
    "make_world",
    "mixed_world",
    "open_world",
    "room_layouts",
]

# Bitmap maps (Arnaldo et al. 2018): loading, map entropy, built-in maps.
from abm.worlds.bitmap import (  # noqa: E402
    MAPS,
    MapInfo,
    builtin_map,
    load_map,
    map_digest,
    map_entropy,
    write_builtin_maps,
)

__all__ += [
    "MAPS",
    "MapInfo",
    "builtin_map",
    "load_map",
    "map_digest",
    "map_entropy",
    "write_builtin_maps",
]
