import numpy as np
import pytest

from abm.arena import Arena
from abm.errors import ConfigError, MapError
from models.environments import MAPS, builtin_map, load_map, map_entropy
from models.environments.bitmap import MAPS_DIR


def test_hall_entropy_is_papers_map1():
    free = np.zeros((100, 100), dtype=bool)
    free[1:-1, 1:-1] = True
    assert round(map_entropy(free), 4) == 0.2405
    assert map_entropy(Arena(free)) == map_entropy(free)


def test_entropy_of_known_images_exact():
    half = np.zeros((4, 4), dtype=bool)
    half[:2] = True
    assert map_entropy(half) == 1.0
    assert map_entropy(np.ones((3, 3), dtype=bool)) == 0.0
    quarter = np.ones((2, 2), dtype=bool)
    quarter[0, 0] = False
    assert map_entropy(quarter) == pytest.approx(-(0.25 * np.log2(0.25) + 0.75 * np.log2(0.75)))


def test_reconstructed_table1_maps():
    assert len(MAPS) >= 8
    for name in ("hall100", "divided", "complex"):
        assert round(map_entropy(builtin_map(name)), 4) == MAPS[name].paper_entropy
    assert builtin_map("hall100x200").free.shape == (100, 200)


@pytest.mark.parametrize("name", list(MAPS))
def test_builtin_maps_connected_and_start_free(name):
    from scipy import ndimage

    arena = builtin_map(name)
    assert ndimage.label(arena.free)[1] == 1
    assert arena.is_free(np.array([MAPS[name].start]))[0]


@pytest.mark.parametrize("name", list(MAPS))
def test_shipped_png_equals_generated(name):
    assert np.array_equal(load_map(MAPS_DIR / f"{name}.png").free, MAPS[name].build())


def test_load_npy_and_array(tmp_path):
    free = MAPS["rooms4"].build()
    np.save(tmp_path / "m.npy", free[::-1])
    assert np.array_equal(load_map(tmp_path / "m.npy").free, free)
    assert load_map(free).free.shape == free.shape


def test_bad_maps(tmp_path):
    with pytest.raises(MapError, match="no free cell"):
        load_map(np.zeros((5, 5), dtype=bool))
    bad = tmp_path / "bad.png"
    bad.write_text("not an image")
    with pytest.raises(MapError, match="not a readable image"):
        load_map(bad)
    with pytest.raises(MapError, match="does not exist"):
        load_map(tmp_path / "missing.png")
    with pytest.raises(ConfigError, match="map must be one of"):
        load_map("atlantis")
    with pytest.raises(MapError, match="boolean"):
        map_entropy(np.zeros((3, 3)))


def test_complex_map_openings_are_wide_enough():
    """Paper map 4: every door, gap and corridor at least 8 m wide (> sqrt(2) r_u), so the
    wanders' range beams do not turn them back from any opening: a body of radius 3.5 m
    (pixels 4 m or more from every wall) can reach every part of the map."""
    from scipy import ndimage

    from models.environments.bitmap import COMPLEX_MIN_OPENING

    free = MAPS["complex"].build()
    core = ndimage.distance_transform_edt(free) >= COMPLEX_MIN_OPENING / 2
    assert ndimage.label(core)[1] == 1
    assert ndimage.distance_transform_edt(~core)[free].max() <= 6.0
    assert round(map_entropy(free), 4) == 0.4639


def test_map_digest_tells_walls_apart():
    from models.environments import map_digest

    free = MAPS["complex"].build()
    other = free.copy()
    other[50, 50] = not other[50, 50]
    assert map_digest(free) == map_digest(builtin_map("complex")) != map_digest(other)
    assert map_digest(Arena(free, resolution=2.0)) != map_digest(free)
