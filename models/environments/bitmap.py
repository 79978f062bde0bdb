"""Bitmap maps: loading (PNG/PGM/BMP/NPY), the paper's map entropy, and built-in maps.

Arnaldo et al. (2018) run their swarm on bitmap maps at 1 m per pixel, black = not navigable,
and measure a map's complexity by the entropy of its binary image,
``H = -sum_k P_k log2 P_k`` over the two grey levels (wall, free). The built-in maps are
reconstructions of the paper's Table 1 maps (drawn from its description: the images are not
published) plus a few more of other entropy and size, and floor plans of ordinary buildings
(:mod:`models.environments.floorplans`), generated in code so they are exact and reproducible;
:func:`write_builtin_maps` writes them as PNGs (the copies shipped in
``models/environments/maps/``).
"""

import hashlib
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from abm.arena import Arena, MapParts, map_parts
from abm.errors import ConfigError, MapError
from abm.memory import check_map_memory
from models.environments.floorplans import FLOOR_PLANS

__all__ = [
    "MAPS",
    "MapInfo",
    "builtin_map",
    "load_map",
    "map_digest",
    "map_entropy",
    "write_builtin_maps",
    "MAPS_DIR",
]

#: Folder of the shipped PNG copies of the built-in maps.
MAPS_DIR = Path(__file__).parent / "maps"

MAP_SUFFIXES = (".png", ".pgm", ".bmp", ".npy")


def map_entropy(free: np.ndarray | Arena) -> float:
    """Entropy (bits) of a binary map image: ``-sum_k P_k log2 P_k`` over wall and free pixels.

    Args:
        free: a boolean array (True = free) or an :class:`Arena`.

    Returns:
        H in [0, 1]; 0 for an image of one colour. A 100 x 100 hall with a one-pixel perimeter
        wall gives 0.2405 (the paper's map 1).

    """
    if isinstance(free, Arena):
        free = free.free
    free = np.asarray(free)
    if free.dtype != bool:
        raise MapError(f"free must be a boolean array (True = free), got dtype {free.dtype}")
    if free.size == 0:
        raise MapError("free is empty: a map needs at least one pixel")
    p = np.array([free.mean(), 1.0 - free.mean()])
    p = p[p > 0]
    return float(-(p * np.log2(p)).sum() + 0.0)


def map_digest(free: np.ndarray | Arena) -> str:
    """A short fingerprint of a map's walls (and of its resolution, for an arena).

    Two maps of the same name and entropy can differ; result caches key their runs by it.
    """
    resolution = 1.0
    if isinstance(free, Arena):
        free, resolution = free.free, free.resolution
    free = np.asarray(free, dtype=bool)
    text = f"{free.shape}|{resolution!r}|".encode() + np.packbits(free).tobytes()
    return hashlib.sha256(text).hexdigest()[:12]


# ---------------------------------------------------------------------- built-in maps
def _hall(rows: int, cols: int) -> np.ndarray:
    free = np.zeros((rows, cols), dtype=bool)
    free[1:-1, 1:-1] = True
    return free


def _walls(free: np.ndarray, segments, doors=()) -> np.ndarray:
    """Draw 1-pixel walls ``(x0, y0, x1, y1)`` (inclusive, axis-aligned), then cut doors."""
    for x0, y0, x1, y1 in segments:
        free[min(y0, y1) : max(y0, y1) + 1, min(x0, x1) : max(x0, x1) + 1] = False
    for x0, y0, x1, y1 in doors:
        free[min(y0, y1) : max(y0, y1) + 1, min(x0, x1) : max(x0, x1) + 1] = True
    return free


def _divided() -> np.ndarray:
    # Paper map 3: a 100 x 100 hall halved by one wall with one door. A 5 m door makes the
    # entropy 0.2817, the paper's value.
    return _walls(_hall(100, 100), [(50, 1, 50, 98)], [(50, 45, 50, 49)])


#: Narrowest opening of the complex map (m): wider than sqrt(2) r_u = 7.1 m, so a robot on an
#: opening's centre line detects neither side with any of its eight 5 m range beams.
COMPLEX_MIN_OPENING = 8


def _complex() -> np.ndarray:
    # Paper map 4, "a complex 100x100m hall, with multiple walls and corridors" (Table 1), "the
    # labyrinth" (Fig 4); the image is not published. 588 wall pixels inside the perimeter give
    # the paper's entropy 0.4639. Every door, gap and corridor is at least 8 m wide: the paper's
    # maps have "navigable areas ... [large] enough so that navigation and avoidance of obstacles
    # is developed effectively" (Sect. "Experimentation"), with walls spread evenly ("similar
    # areas distributed with the same density"). Our first reconstruction had 4-6 m gaps in
    # corners, narrower than sqrt(2) r_u: the obstacle term f2 (weight 0.4, twice f1's) turned
    # wanders back at each one, and at C_rb = 40 m the two north-east rooms behind three such
    # gaps were never entered in 17 of 30 runs (see models/stigmergy/README.md).
    free = _hall(100, 100)
    segments = [
        (20, 1, 20, 98),  # west corridor (x 1-19) holding the launch point
        (21, 50, 98, 50),  # north / south halves
        (40, 51, 40, 98),
        (70, 51, 70, 98),
        (21, 25, 80, 25),
        (60, 1, 60, 24),
        (80, 26, 80, 40),
        (49, 75, 61, 75),
        (79, 70, 98, 70),
        (30, 9, 45, 9),
        (45, 9, 45, 16),
        (85, 9, 85, 16),
        (69, 9, 76, 9),
        (30, 40, 46, 40),
        (55, 40, 71, 40),
        (49, 60, 61, 60),
        (85, 79, 85, 98),
        (1, 20, 11, 20),
        (90, 26, 90, 41),
        (21, 60, 31, 60),
        (21, 80, 31, 80),
        (51, 85, 61, 85),
        (10, 40, 19, 40),
        (10, 1, 10, 8),
        (10, 49, 10, 74),
        (85, 62, 85, 69),
        (71, 60, 76, 60),
        (60, 26, 60, 31),
        (70, 26, 70, 31),
        (40, 34, 40, 39),
        (55, 61, 55, 66),
    ]
    doors = [
        (20, 84, 20, 91),
        (20, 29, 20, 36),
        (54, 50, 61, 50),
        (84, 50, 91, 50),
        (40, 69, 40, 76),
        (70, 86, 70, 93),
        (29, 25, 36, 25),
        (60, 9, 60, 16),
    ]
    return _walls(free, segments, doors)


def _rooms4() -> np.ndarray:
    # Four 50 x 50 rooms joined by four doors.
    return _walls(
        _hall(100, 100),
        [(50, 1, 50, 98), (1, 50, 98, 50)],
        [(50, 70, 50, 77), (50, 20, 50, 27), (20, 50, 27, 50), (70, 50, 77, 50)],
    )


def _serpentine() -> np.ndarray:
    # A 100 x 100 hall folded into five 19 m wide corridors (a long narrow path).
    segs, doors = [], []
    for k, y in enumerate((20, 40, 60, 80)):
        segs.append((1, y, 98, y))
        doors.append((90, y, 98, y) if k % 2 == 0 else (1, y, 9, y))
    return _walls(_hall(100, 100), segs, doors)


def _pillars() -> np.ndarray:
    # A 100 x 100 hall with a regular grid of 4 x 4 m pillars (unstructured-looking clutter).
    free = _hall(100, 100)
    for cx in range(18, 95, 16):
        for cy in range(10, 95, 16):
            free[cy : cy + 4, cx : cx + 4] = False
    return free


def _lshape() -> np.ndarray:
    # An L-shaped 100 x 100 hall: the south-east 60 x 60 quadrant is solid.
    free = _hall(100, 100)
    free[:60, 40:] = False
    return free


def _wide() -> np.ndarray:
    # A 100 x 150 hall with two partial walls (a larger, mildly structured space).
    return _walls(_hall(100, 150), [(50, 1, 50, 60), (100, 40, 100, 98)])


@dataclass(frozen=True)
class MapInfo:
    """A built-in map.

    Attributes:
        name: registry key (also the PNG file's stem).
        title: one-line description.
        build: returns the boolean free grid (row 0 = south, 1 px = 1 m).
        start: default launch point p0 (m).
        paper_id: the map's Id in Arnaldo et al. (2018) Table 1, or None.
        paper_entropy: the entropy the paper gives for it, or None.

    """

    name: str
    title: str
    build: Callable[[], np.ndarray]
    start: tuple[float, float] = (5.0, 80.0)
    paper_id: int | None = None
    paper_entropy: float | None = None


MAPS: dict[str, MapInfo] = {
    m.name: m
    for m in (
        MapInfo(
            "hall100",
            "empty 100 x 100 m hall (paper map 1)",
            lambda: _hall(100, 100),
            paper_id=1,
            paper_entropy=0.2405,
        ),
        MapInfo(
            "hall100x200",
            "empty 100 x 200 m hall (paper map 2)",
            lambda: _hall(100, 200),
            paper_id=2,
            paper_entropy=0.0027,
        ),
        MapInfo(
            "divided",
            "100 x 100 m hall halved by a wall with one door (paper map 3)",
            _divided,
            paper_id=3,
            paper_entropy=0.2817,
        ),
        MapInfo(
            "complex",
            "100 x 100 m hall with walls and corridors (paper map 4)",
            _complex,
            paper_id=4,
            paper_entropy=0.4639,
        ),
        MapInfo("rooms4", "four 50 x 50 m rooms joined by doors", _rooms4),
        MapInfo("serpentine", "100 x 100 m hall folded into five corridors", _serpentine),
        MapInfo("pillars", "100 x 100 m hall with a grid of 4 x 4 m pillars", _pillars),
        MapInfo("lshape", "L-shaped hall in a 100 x 100 m square", _lshape),
        MapInfo("wide", "100 x 150 m hall with two partial walls", _wide),
        # Floor plans of ordinary buildings (models.environments.floorplans), walls off any
        # 3 m lattice.
        *(
            MapInfo(name, title, build, start=start)
            for name, (build, start, title) in FLOOR_PLANS.items()
        ),
    )
}


def builtin_map(name: str) -> Arena:
    """The built-in map ``name`` as an arena (1 m per pixel)."""
    if name not in MAPS:
        raise ConfigError(
            f"map must be one of {', '.join(MAPS)}, a map file or an Arena, got {name!r}"
        )
    return Arena(MAPS[name].build(), resolution=1.0, name=name)


def load_map(
    map: str | Path | Arena | np.ndarray,  # noqa: A002
    resolution: float = 1.0,
    parts: MapParts | None = None,
) -> Arena:
    """Turn a built-in map name, a bitmap file, a boolean array or an arena into an arena.

    A file's size is read from its header and the memory the arena and ``parts`` would take
    is checked against the machine's budget (:mod:`abm.memory`) before any pixel is decoded;
    an array's or an arena's before its model allocates more for it.

    Args:
        map: a name from :data:`MAPS`, a PNG/PGM/BMP/NPY path (black = not navigable), a boolean
            array (True = free, row 0 = south) or an :class:`Arena`.
        resolution: metres per pixel of a file or array (default 1 m, the paper's).
        parts: what the caller's model allocates for a map of a given shape besides the arena
            (bytes by part: its coverage raster, pheromone field, ...).

    Raises:
        MapError: unreadable or odd file, no free cell, more memory than the budget.
        ConfigError: an unknown name.

    """
    if isinstance(map, Arena):
        if parts is not None:
            check_map_memory(map.name, map.free.shape, parts(map.free.shape))
        return map
    if isinstance(map, np.ndarray):
        if map.ndim == 2:
            check_map_memory("array", map.shape, map_parts(map.shape, parts, decoding=False))
        return Arena(map, resolution=resolution, name="array")
    if isinstance(map, str) and map in MAPS:
        if resolution != 1.0:
            raise ConfigError(f"resolution of a built-in map is 1 m, got {resolution!r}")
        return builtin_map(map)
    if isinstance(map, str | Path) and Path(map).suffix.lower() in MAP_SUFFIXES:
        return Arena.from_bitmap(map, resolution=resolution, parts=parts)
    raise ConfigError(
        f"map must be one of {', '.join(MAPS)}, a map file ({', '.join(MAP_SUFFIXES)}), a "
        f"boolean array or an Arena, got {map!r}"
    )


def write_builtin_maps(folder: str | Path = MAPS_DIR) -> list[Path]:
    """Write every built-in map as a black/white PNG (top row = north); returns the paths."""
    from PIL import Image

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    paths = []
    for info in MAPS.values():
        image = (info.build()[::-1] * 255).astype(np.uint8)
        path = folder / f"{info.name}.png"
        Image.fromarray(image, mode="L").save(path, optimize=True)
        paths.append(path)
    return paths
