import numpy as np
import pytest

from abm.disc_cells import disc_offsets
from abm.disc_sight import disc_parents, disc_visibility, visible_rows
from abm.errors import ConfigError
from models.environments import builtin_map


def _exact(arena, cell, dy, dx):
    """Centre-to-centre line of sight from a cell to the free cells at the offsets."""
    ix, iy = cell
    tx, ty = ix + dx, iy + dy
    inside = (tx >= 0) & (tx < arena.cols) & (ty >= 0) & (ty < arena.rows)
    out = np.zeros(len(dy), dtype=bool)
    ok = inside.copy()
    ok[inside] = arena.free[ty[inside], tx[inside]]
    start = np.repeat([[ix + 0.5, iy + 0.5]], ok.sum(), axis=0) * arena.resolution
    ends = (np.stack([tx[ok], ty[ok]], axis=1) + 0.5) * arena.resolution
    out[ok] = arena.line_of_sight(start, ends)
    return out


def test_parents_step_one_cell_towards_the_origin():
    dy, dx = disc_offsets(12.0)
    parents = disc_parents(dy, dx)
    root = np.nonzero((dy == 0) & (dx == 0))[0][0]
    assert parents[root] == -1
    others = parents >= 0
    cheb = np.maximum(np.abs(dy), np.abs(dx))
    assert np.all(cheb[parents[others]] == cheb[others] - 1)
    assert np.all(np.abs(dy[parents[others]] - dy[others]) <= 1)
    assert np.all(np.abs(dx[parents[others]] - dx[others]) <= 1)
    with pytest.raises(ConfigError, match="include"):
        disc_parents(np.array([1]), np.array([0]))


def test_open_room_sees_every_free_cell_of_the_disc():
    free = np.pad(np.ones((30, 30), dtype=bool), 1)
    dy, dx = disc_offsets(8.0)
    table = disc_visibility(free, dy, dx)
    cell = 16 * 32 + 16
    seen = visible_rows(table, np.array([cell]), len(dy))[0]
    assert seen.all()
    corner = 1 * 32 + 1  # next to two walls: only the quarter disc inside is free
    seen = visible_rows(table, np.array([corner]), len(dy))[0]
    assert np.array_equal(seen, (dy >= 0) & (dx >= 0))
    wall = visible_rows(table, np.array([0]), len(dy))[0]
    assert not wall.any()


def test_a_wall_hides_what_is_behind_it_and_a_door_shows_it():
    arena = builtin_map("divided")  # wall at x = 50 with a door at y = 45..49
    dy, dx = disc_offsets(10.0)
    table = disc_visibility(arena.free, dy, dx)
    k_east = np.nonzero((dy == 0) & (dx == 6))[0][0]
    facing_wall = 20 * arena.cols + 46
    facing_door = 47 * arena.cols + 46
    assert not visible_rows(table, np.array([facing_wall]), len(dy))[0, k_east]
    assert visible_rows(table, np.array([facing_door]), len(dy))[0, k_east]


def test_table_agrees_with_exact_line_of_sight_on_the_complex_map():
    arena = builtin_map("complex")
    dy, dx = disc_offsets(10.0)
    table = disc_visibility(arena.free, dy, dx)
    rng = np.random.default_rng(0)
    iy, ix = np.nonzero(arena.free)
    agree = total = 0
    for c in rng.choice(len(ix), 40, replace=False):
        got = visible_rows(table, np.array([iy[c] * arena.cols + ix[c]]), len(dy))[0]
        want = _exact(arena, (ix[c], iy[c]), dy, dx)
        assert not (got & ~arena.free[np.clip(iy[c] + dy, 0, 99), np.clip(ix[c] + dx, 0, 99)]).any()
        agree += int((got == want).sum())
        total += len(dy)
    assert agree / total > 0.97  # digital lines vs exact rays differ only at grazing angles
