"""Large worlds: the generators take a size and keep the paper's rules at every size."""

import numpy as np
import pytest
from scipy import ndimage

from abm.errors import ConfigError
from models.environments import branch_count, make_world, mixed_world, open_world


def free_grid(world):
    return world.arena.free


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("complexity", ["low", "medium", "high"])
def test_large_open_rooms_keep_density_connectivity_and_no_corridor_cells(seed, complexity):
    world = open_world(complexity, seed, room_cells=20)
    free = free_grid(world)[1:-1, 1:-1]  # inside the border ring
    assert free.shape == (20, 20)
    obstacles = {"low": 5, "medium": 7, "high": 10}[complexity]
    assert (~free).sum() == 16 * obstacles  # the paper's density, tile by tile
    assert ndimage.label(free)[1] == 1  # rule (a): one connected free space
    padded = np.pad(free, 1)
    ns_blocked = ~padded[:-2, 1:-1] & ~padded[2:, 1:-1]
    ew_blocked = ~padded[1:-1, :-2] & ~padded[1:-1, 2:]
    assert not (free & (ns_blocked | ew_blocked)).any()  # rule (b): no corridor cell


def test_open_room_side_must_tile_the_paper_room():
    with pytest.raises(ConfigError, match="room_cells"):
        open_world("low", 0, room_cells=12)


@pytest.mark.parametrize("size", [100, 2000])
def test_sized_corridors_and_mixed_worlds_have_the_cells_asked_for(size):
    corridor = make_world("corridor", "high", 3, size=size)
    assert len(corridor.cells) == size
    assert corridor.branches == branch_count(corridor.cells)
    free = free_grid(corridor)
    # one cell wide: no 2 x 2 block of free cells anywhere
    assert not (free[:-1, :-1] & free[1:, :-1] & free[:-1, 1:] & free[1:, 1:]).any()
    mixed = make_world("mixed", "medium", 3, size=size)
    assert abs(len(mixed.cells) - size) <= 0.1 * size
    assert ndimage.label(free_grid(mixed))[1] == 1


def test_large_mixed_world_has_two_square_rooms():
    world = mixed_world(5, room_side=8, corridor_cells=60)
    assert len(world.cells) == 2 * 64 + 60
    free = free_grid(world)
    blocks = ndimage.binary_erosion(free, np.ones((8, 8)), border_value=0)
    assert ndimage.label(blocks)[1] == 2  # each room holds one 8 x 8 block of free cells


def test_sized_open_world_is_near_the_size_asked_for():
    world = make_world("open", "medium", 4, size=1000)
    assert 0.7 * 1000 <= len(world.cells) <= 1.3 * 1000
    with pytest.raises(ConfigError, match="size"):
        make_world("open", "medium", 4, size=3)
