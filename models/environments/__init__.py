"""The papers' environments, shared by the models that reproduce them.

The framework (``abm``) knows arenas and bitmaps but no paper; the worlds and maps the papers
describe live here, with their published sizes and constants.

Generated worlds (Stirling et al. 2010, Sect. 3.5 and Fig. 5; the beacon/explorer model), from a
seed. Three families on 3 m x 3 m cells: branching corridors (40 cells), open 5 x 5 cell rooms with
obstacle cells, and mixed worlds of two 3 x 3 rooms joined by 22 corridor cells. Every generator
takes ``rng`` (a ``numpy.random.Generator``, an int seed or None) and returns a :class:`World`.
"""

from models.environments.corridor import BRANCHING, branch_count, corridor_world, grow_corridor
from models.environments.make import make_world
from models.environments.mixed import mixed_world
from models.environments.open_room import OBSTACLES, open_world, room_layouts
from models.environments.world import COMPLEXITIES, WORLD_KINDS, World, as_generator

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

# Bitmap maps (Arnaldo et al. 2018, Table 1; the stigmergy model): loading, map entropy,
# built-in maps and floor plans of ordinary buildings.
from models.environments.bitmap import (  # noqa: E402
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
