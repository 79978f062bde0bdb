"""The SugarMap arenas: the geometries of Fig. 10 as the README's "Choices" read them, the shipped
PNGs, start cells."""

import numpy as np
import pytest
from PIL import Image
from scipy import ndimage

from abm.errors import ConfigError, MapError
from models.sugarmap.arenas import (
    ARENAS,
    CELL,
    MAPS_DIR,
    arena_codes,
    load_arena,
    start_cells,
    write_arena_pngs,
)

NAV, WALL, OBS = 0, 1, 2

#: Our reading (README "Choices": arenas): navigable cells and the start cells of its explorers.
SPEC_TABLE = {
    "open": (1600, [(1, 1), (2, 1), (3, 1), (4, 1)]),
    "circle": (1248, [(17, 1), (18, 1), (19, 1), (20, 1)]),
    "ushape": (1024, [(1, 1), (2, 1), (3, 1), (4, 1)]),
    "serpentine": (1308, [(1, 1), (2, 1), (3, 1), (4, 1)]),
    "corridor": (160, [(19, 1), (20, 1), (21, 1), (22, 1)]),
    "testbed": (60, [(1, 1), (2, 1)]),
    "open10": (400, [(1, 1), (2, 1), (3, 1), (4, 1)]),  # ours (claim C22), not in the paper
}

#: Rows of Appendix A's pictures (north up, so picture line L is y = 41 - L).
APPENDIX_ROWS = {
    "circle": {
        40: "#################........#################",
        29: "###.........oo..............oo.........###",
        28: "##..........oo..............oo..........##",
        21: "#........................................#",
        13: "##..........oo..............oo..........##",
        12: "###.........oo..............oo.........###",
        1: "#################........#################",
    },
    "ushape": {
        40: "#....................################....#",
        5: "#....................################....#",
        4: "#........................................#",
        1: "#........................................#",
    },
    "serpentine": {
        40: "#.........#.........#.........#.........##",
        37: "#.........#.........#.........#.........##",
        36: "#....#....#....#....#....#....#....#....##",
        5: "#....#....#....#....#....#....#....#....##",
        4: "#....#.........#.........#.........#....##",
        1: "#....#.........#.........#.........#....##",
    },
}


def _row(text: str) -> np.ndarray:
    return np.array([{"#": WALL, ".": NAV, "o": OBS}[c] for c in text], dtype=np.int8)


def test_the_arenas_and_their_spec_navigable_counts():
    assert set(ARENAS) == set(SPEC_TABLE)
    for name, (count, _) in SPEC_TABLE.items():
        codes = arena_codes(name)
        assert codes.dtype == np.int8
        assert ARENAS[name].navigable == count
        assert int((codes == NAV).sum()) == count, name
        assert ARENAS[name].name == name
        assert ("Fig. 10" in ARENAS[name].title or "Sect." in ARENAS[name].title) == (
            name != "open10"
        )


@pytest.mark.parametrize("name", list(SPEC_TABLE))
def test_every_arena_is_walled_and_one_connected_space(name):
    codes = arena_codes(name)
    assert (codes[[0, -1], :] == WALL).all() and (codes[:, [0, -1]] == WALL).all()
    assert ndimage.label(codes == NAV)[1] == 1


@pytest.mark.parametrize("name", list(APPENDIX_ROWS))
def test_rows_match_the_appendix_pictures(name):
    codes = arena_codes(name)
    assert codes.shape == (42, 42)
    for y, text in APPENDIX_ROWS[name].items():
        np.testing.assert_array_equal(codes[y], _row(text), err_msg=f"{name} y={y}")


def test_geometry_definitions_of_section_9():
    square = arena_codes("open")
    assert (square[1:41, 1:41] == NAV).all()
    circle = arena_codes("circle")
    assert (circle == OBS).sum() == 16
    for cx in (12, 28):
        for cy in (12, 28):
            assert (circle[cy : cy + 2, cx : cx + 2] == OBS).all()
    assert circle[21, 1] == NAV and circle[1, 1] == WALL  # the disc touches the border mid-side
    u = arena_codes("ushape")
    assert (u[5:41, 21:37] == WALL).all() and (u[1:5, 21:37] == NAV).all()
    serp = arena_codes("serpentine")
    assert (serp[1:37, 5] == WALL).all() and (serp[37:41, 5] == NAV).all()  # gap north
    assert (serp[1:5, 10] == NAV).all() and (serp[5:41, 10] == WALL).all()  # gap south
    assert (serp[:, 40] == WALL).all()
    straight = arena_codes("corridor")
    assert (straight[1:41, 19:23] == NAV).all() and (straight == NAV).sum() == 160
    testbed = arena_codes("testbed")
    assert testbed.shape == (8, 12) and (testbed[1:7, 1:11] == NAV).all()


def test_codes_are_fresh_copies():
    arena_codes("open")[5, 5] = WALL
    assert arena_codes("open")[5, 5] == NAV


@pytest.mark.parametrize("name", list(SPEC_TABLE))
def test_load_arena_round_trips_the_shipped_png(name):
    arena = load_arena(name)
    np.testing.assert_array_equal(arena.free, arena_codes(name) == NAV)
    assert arena.resolution == CELL and arena.name == name
    assert arena.free_area == pytest.approx(SPEC_TABLE[name][0] * CELL**2)


def test_shipped_pngs_are_what_write_arena_pngs_writes(tmp_path):
    paths = write_arena_pngs(tmp_path)
    assert [p.name for p in paths] == [f"{n}.png" for n in ARENAS]
    for path in paths:
        fresh = np.asarray(Image.open(path))
        np.testing.assert_array_equal(fresh, np.asarray(Image.open(MAPS_DIR / path.name)))


def test_png_grey_levels_north_up_and_obstacles_impassable(tmp_path):
    write_arena_pngs(tmp_path)
    grey = np.asarray(Image.open(tmp_path / "circle.png").convert("L"))[::-1]  # row 0 = south
    codes = arena_codes("circle")
    assert (grey[codes == NAV] == 255).all() and (grey[codes == WALL] == 0).all()
    obstacle = np.unique(grey[codes == OBS])
    assert len(obstacle) == 1 and 0 < obstacle[0] < 128
    u = np.asarray(Image.open(tmp_path / "ushape.png").convert("L"))
    assert (u[-5, 21:37] == 255).all() and (u[1, 21:37] == 0).all()  # the U's base is south


def test_load_a_users_bitmap(tmp_path):
    image = np.zeros((4, 6), dtype=np.uint8)
    image[1:3, 1:5] = 255
    image[1, 2] = 60  # dark grey: impassable
    path = tmp_path / "room.png"
    Image.fromarray(image).save(path)
    arena = load_arena(path, cell=0.25)
    assert arena.resolution == 0.25 and arena.name == "room"
    assert arena.free.sum() == 7 and not arena.free[2, 2] and arena.free[1, 2]
    assert load_arena(str(path)).resolution == CELL


def test_load_arena_bad_input(tmp_path):
    with pytest.raises(ConfigError, match="arena must be one of 'open'.*got 'moon'"):
        load_arena("moon")
    with pytest.raises(ConfigError, match="existing bitmap file"):
        load_arena(tmp_path / "missing.png")
    with pytest.raises(ConfigError, match="cell must be"):
        load_arena("open", cell=0.0)
    broken = tmp_path / "broken.png"
    broken.write_text("not an image")
    with pytest.raises(MapError, match="not a readable image"):
        load_arena(broken)
    with pytest.raises(ConfigError, match="arena must be one of"):
        arena_codes("moon")


@pytest.mark.parametrize("name", list(SPEC_TABLE))
def test_start_cells_of_the_spec_table(name):
    expected = SPEC_TABLE[name][1]
    assert start_cells(arena_codes(name) == NAV, len(expected)) == expected
    assert start_cells(load_arena(name).free, len(expected)) == expected


def test_start_cells_continue_along_the_row_then_go_up():
    free = arena_codes("open") == NAV
    cells = start_cells(free, 43)
    assert cells[:40] == [(x, 1) for x in range(1, 41)]
    assert cells[40:] == [(1, 2), (2, 2), (3, 2)]
    serp = start_cells(arena_codes("serpentine") == NAV, 6)
    assert serp == [(1, 1), (2, 1), (3, 1), (4, 1), (6, 1), (7, 1)]  # the literal rule
    assert all((arena_codes("serpentine") == NAV)[y, x] for x, y in serp)


def test_start_cells_bad_input():
    free = arena_codes("testbed") == NAV
    with pytest.raises(ConfigError, match="n must be at most the 60 free cells, got 61"):
        start_cells(free, 61)
    with pytest.raises(ConfigError, match="n must be"):
        start_cells(free, 0)
    with pytest.raises(ConfigError, match="n must be an integer"):
        start_cells(free, 1.5)
    with pytest.raises(ConfigError, match="free must be a 2-D boolean array"):
        start_cells(free.astype(int), 2)
    with pytest.raises(ConfigError, match="free must be a 2-D boolean array"):
        start_cells(free[0], 2)
