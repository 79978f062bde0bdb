import dataclasses
import time

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import ndimage

from abm.errors import ConfigError
from models.beacon_explorer.published import BRANCHES, BRANCHES_SD
from models.beacon_explorer.published import OBSTACLES as PAPER_OBSTACLES
from models.environments import (
    COMPLEXITIES,
    World,
    branch_count,
    corridor_world,
    grow_corridor,
    make_world,
    mixed_world,
    open_world,
    room_layouts,
)

CASES = [("corridor", c) for c in COMPLEXITIES] + [("open", c) for c in COMPLEXITIES]
CASES += [("mixed", "medium")]
STEPS = ((0, 1), (1, 0), (0, -1), (-1, 0))
SEEDS = st.integers(min_value=0, max_value=2**32 - 1)


# ---------------------------------------------------------------- independent checkers
def n_components(free: np.ndarray) -> int:
    return ndimage.label(free)[1]  # the default structure is 4-connectivity


def has_2x2_block(free: np.ndarray) -> bool:
    return bool((free[:-1, :-1] & free[1:, :-1] & free[:-1, 1:] & free[1:, 1:]).any())


def adjacent_pairs(free: np.ndarray) -> int:
    return int((free[:-1, :] & free[1:, :]).sum() + (free[:, :-1] & free[:, 1:]).sum())


def accidental_corridor_cells(free: np.ndarray) -> np.ndarray:
    """Free cells walled (obstacle or outer wall) both N and S, or both E and W."""
    p = np.pad(free, 1)
    north, south = p[2:, 1:-1], p[:-2, 1:-1]
    east, west = p[1:-1, 2:], p[1:-1, :-2]
    return free & ((~north & ~south) | (~east & ~west))


def grid(cells) -> np.ndarray:
    cells = np.asarray(cells) - np.min(cells, axis=0)
    free = np.zeros(cells.max(axis=0)[::-1] + 3, dtype=bool)
    free[cells[:, 1] + 1, cells[:, 0] + 1] = True
    return free


def same_world(a: World, b: World) -> bool:
    return (
        np.array_equal(a.cells, b.cells)
        and np.array_equal(a.start, b.start)
        and np.array_equal(a.arena.free, b.arena.free)
        and a.branches == b.branches
        and (a.kind, a.complexity) == (b.kind, b.complexity)
    )


# ---------------------------------------------------------------- every world
@pytest.mark.parametrize(("kind", "complexity"), CASES)
@settings(max_examples=40, deadline=None)
@given(seed=SEEDS)
def test_world_invariants(kind, complexity, seed):
    world = make_world(kind, complexity, rng=seed)
    free = world.arena.free
    # Sect. 3.5: 40 corridor cells; a 5 x 5 room with 5 / 7 / 10 obstacle cells; two 3 x 3
    # rooms and 22 corridor cells.
    expected = {"corridor": 40, "open": 25 - PAPER_OBSTACLES[complexity], "mixed": 18 + 22}[kind]
    assert (world.kind, world.complexity) == (kind, complexity)
    assert free.sum() == len(world.cells) == expected
    assert free[world.cells[:, 1], world.cells[:, 0]].all()
    assert n_components(free) == 1
    # A ring of wall all round.
    assert not free[[0, -1], :].any() and not free[:, [0, -1]].any()
    # The start is the centre of a free cell.
    assert world.arena.is_free(world.start[None])[0]
    offset = world.start / world.cell_size - 0.5
    assert np.allclose(offset, np.round(offset))
    assert free[world.start_cell[1], world.start_cell[0]]


@settings(max_examples=60, deadline=None)
@given(seed=SEEDS, complexity=st.sampled_from(COMPLEXITIES))
def test_corridor_is_one_cell_wide_tree(seed, complexity):
    world = corridor_world(complexity, rng=seed)
    free = world.arena.free
    assert not has_2x2_block(free)
    assert adjacent_pairs(free) == len(world.cells) - 1  # connected + n-1 edges: a tree
    assert world.branches == branch_count(world.cells)
    assert world.branches % 2 == 1  # every junction is a T: 1 + 2 * junctions


@settings(max_examples=60, deadline=None)
@given(seed=SEEDS, complexity=st.sampled_from(COMPLEXITIES))
def test_open_room_has_no_accidental_corridor(seed, complexity):
    world = open_world(complexity, rng=seed)
    assert world.branches is None
    assert world.arena.free.shape == (7, 7)  # the 5 x 5 room and its wall, always whole
    assert not accidental_corridor_cells(world.arena.free).any()


@settings(max_examples=60, deadline=None)
@given(seed=SEEDS)
def test_mixed_world_two_rooms_joined_by_corridors(seed):
    world = mixed_world(rng=seed)
    free = world.arena.free
    # Room cells are exactly the cells of some 2 x 2 free block (corridors have none).
    block = free[:-1, :-1] & free[1:, :-1] & free[:-1, 1:] & free[1:, 1:]
    room = np.zeros_like(free)
    for dy in (0, 1):
        for dx in (0, 1):
            room[dy : dy + block.shape[0], dx : dx + block.shape[1]] |= block
    labels, n = ndimage.label(room)
    assert n == 2
    for k in (1, 2):
        iy, ix = np.nonzero(labels == k)
        assert len(ix) == 9 and np.ptp(ix) == 2 and np.ptp(iy) == 2
    corridor = free & ~room
    assert corridor.sum() == 22
    assert adjacent_pairs(corridor) == 21  # the corridor cells form one tree
    # Exactly one corridor-room contact per room: the doorways.
    contacts = adjacent_pairs(free) - adjacent_pairs(room) - adjacent_pairs(corridor)
    assert contacts == 2
    iy, ix = np.nonzero(corridor)
    assert world.branches == branch_count(np.column_stack([ix, iy]))


# ---------------------------------------------------------------- calibration
@pytest.mark.parametrize("complexity", COMPLEXITIES)
def test_corridor_branch_counts_match_paper(complexity):
    rng = np.random.default_rng(12345)
    counts = np.array([corridor_world(complexity, rng).branches for _ in range(300)])
    mean, sd = counts.mean(), counts.std()
    paper_mean, paper_sd = BRANCHES[complexity], BRANCHES_SD[complexity]
    print(f"{complexity}: mean {mean:.2f} (paper {paper_mean}), sd {sd:.2f} (paper {paper_sd})")
    assert abs(mean - paper_mean) <= 0.15 * paper_mean
    assert abs(sd - paper_sd) <= 0.35 * paper_sd


def test_room_layout_counts_and_rule():
    # Exhaustive counts, checked once by brute force over all C(25, k) placements.
    assert [len(room_layouts(5, k)) for k in (5, 7, 10)] == [405, 774, 730]
    rng = np.random.default_rng(7)
    for k in (5, 7, 10):
        valid = set(room_layouts(5, k).tolist())
        for _ in range(3000):
            free = np.ones(25, dtype=bool)
            free[rng.choice(25, size=k, replace=False)] = False
            free = free.reshape(5, 5)
            ok = n_components(free) == 1 and not accidental_corridor_cells(free).any()
            mask = int((free.ravel().astype(np.int64) << np.arange(25)).sum())
            assert ok == (mask in valid)


def test_corridor_generation_is_fast():
    rng = np.random.default_rng(3)
    began = time.perf_counter()
    for _ in range(100):
        corridor_world("high", rng)
    assert (time.perf_counter() - began) / 100 < 0.010


# ---------------------------------------------------------------- branch_count
@pytest.mark.parametrize(
    ("cells", "branches"),
    [
        ([], 0),
        ([(0, 0)], 1),
        ([(0, 0), (1, 0), (2, 0)], 1),  # straight
        ([(0, 0), (1, 0), (1, 1), (1, 2)], 1),  # a turn is not a branch
        ([(0, 0), (1, 0), (2, 0), (1, 1)], 3),  # T
        ([(1, 0), (0, 1), (1, 1), (2, 1), (1, 2)], 4),  # cross
        ([(0, 0), (0, 1), (0, 2), (1, 1), (2, 1), (2, 0), (2, 2)], 5),  # H
        ([(x, y) for x in range(3) for y in range(3) if (x, y) != (1, 1)], 1),  # a loop
        ([(0, 0), (1, 0), (5, 5)], 2),  # two pieces
    ],
)
def test_branch_count(cells, branches):
    assert branch_count(cells) == branches
    assert branch_count(np.array(cells, dtype=int).reshape(-1, 2)) == branches


def test_grow_corridor_keeps_off_blocked_cells():
    blocked = frozenset((x, y) for x in range(3) for y in range(3))
    cells = grow_corridor(
        30, np.random.default_rng(4), root=(1, 3), heading=(0, 1), blocked=blocked
    )
    assert cells[0] == (1, 3) and len(set(cells)) == 30 and not blocked & set(cells)
    touching = [c for c in cells if any((c[0] + dx, c[1] + dy) in blocked for dx, dy in STEPS)]
    assert touching == [(1, 3)]
    assert adjacent_pairs(grid(cells)) == 29


def test_branch_count_of_grid_helper_shapes():
    cells = [(0, y) for y in range(5)] + [(x, 2) for x in range(1, 4)]  # a T lying down
    assert branch_count(cells) == 3
    assert not has_2x2_block(grid(cells))


# ---------------------------------------------------------------- seeds
@pytest.mark.parametrize(("kind", "complexity"), CASES)
def test_same_seed_same_world(kind, complexity):
    a = make_world(kind, complexity, rng=42)
    b = make_world(kind, complexity, rng=42)
    c = make_world(kind, complexity, rng=np.random.default_rng(42))
    assert same_world(a, b) and same_world(a, c)


@pytest.mark.parametrize(("kind", "complexity"), CASES)
def test_different_seeds_different_worlds(kind, complexity):
    worlds = [make_world(kind, complexity, rng=seed) for seed in range(20)]
    distinct = {(w.cells.tobytes(), w.start.tobytes()) for w in worlds}
    assert len(distinct) >= 18


def test_one_generator_draws_a_sequence_of_different_worlds():
    rng = np.random.default_rng(0)
    a, b = corridor_world(rng=rng), corridor_world(rng=rng)
    assert not same_world(a, b)


def test_cell_size_scales_the_world():
    a = make_world("mixed", rng=5)
    b = make_world("mixed", rng=5, cell_size=1.5)
    assert np.array_equal(a.cells, b.cells)
    assert b.arena.resolution == 1.5 and np.allclose(b.start * 2, a.start)
    assert a.free_area == 40 * 9.0


def test_world_is_read_only():
    world = corridor_world(rng=1)
    with pytest.raises(ValueError):
        world.cells[0, 0] = 99
    with pytest.raises(dataclasses.FrozenInstanceError):
        world.kind = "open"
    assert "corridor" in repr(world)


# ---------------------------------------------------------------- bad input
@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda: make_world("maze"), "kind"),
        (lambda: make_world("corridor", "extreme"), "complexity"),
        (lambda: make_world("mixed", "high"), "complexity"),
        (lambda: corridor_world("hard"), "complexity"),
        (lambda: open_world("hard"), "complexity"),
        (lambda: corridor_world(n_cells=1), "n_cells"),
        (lambda: corridor_world(n_cells=2.5), "n_cells"),
        (lambda: corridor_world(cell_size=0.0), "cell_size"),
        (lambda: open_world(cell_size=-3.0), "cell_size"),
        (lambda: mixed_world(cell_size="3"), "cell_size"),
        (lambda: make_world("open", rng="seed"), "rng"),
        (lambda: make_world("corridor", rng=-1), "rng"),
        (lambda: mixed_world(rng=1.5), "rng"),
        (lambda: room_layouts(5, 25), "n_obstacles"),
        (lambda: grow_corridor(0, np.random.default_rng()), "n_cells"),
        (lambda: grow_corridor(5, np.random.default_rng(), "huge"), "complexity"),
        (lambda: grow_corridor(5, np.random.default_rng(), heading=(1, 1)), "heading"),
    ],
)
def test_bad_input_raises_config_error(call, match):
    with pytest.raises(ConfigError, match=match):
        call()
