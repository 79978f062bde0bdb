"""The perfect-DFS bounds of corridor worlds, the failure classifier, and the taken-spot hold."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from abm.arena import Arena
from abm.errors import ConfigError
from models.beacon_explorer import BeaconExplorerModel
from models.beacon_explorer.diagnose import CAUSES, cell_depths, classify, paper_dfs_completes
from models.environments import World, make_world


def cell_world(cells: list[tuple[int, int]], start: tuple[int, int]) -> World:
    arena = Arena.from_cells(cells, cell_size=3.0)
    base = (np.asarray(start, dtype=float) + 0.5) * 3.0
    return World(arena, base, "bitmap", "high", np.array(cells), None)


def t_world(stem: int, north: int, east: int) -> World:
    """A stem running north from the base to a junction, branches north and east from it."""
    cells = [(1, 1 + i) for i in range(stem + 1 + north)]
    top = 1 + stem
    cells += [(2 + i, top) for i in range(east)]
    return cell_world(cells, (1, 1))


@pytest.mark.parametrize("length", [5, 12])
def test_a_straight_corridor_from_its_end_needs_one_explorer_per_cell(length):
    world = cell_world([(1, 1 + i) for i in range(length + 1)], (1, 1))
    assert max(cell_depths(world).values()) == length
    assert paper_dfs_completes(world, length)
    assert not paper_dfs_completes(world, length - 1)


def test_a_junction_keeps_a_stub_beacon_in_the_branch_it_searches_last():
    """The flowchart fills every empty direction of a junction before passing explorers on, so
    the branch searched first (north, clockwise) needs one explorer more than its depth."""
    world = t_world(stem=4, north=6, east=3)  # deepest cell: 4 + 6 = 10 from the base
    assert max(cell_depths(world).values()) == 10
    assert not paper_dfs_completes(world, 10)  # the path bound (10 <= 10) would allow it
    assert paper_dfs_completes(world, 11)
    # East searched last: its own depth (4 + 3) plus nothing pending is within 10 anyway.
    assert paper_dfs_completes(t_world(stem=4, north=3, east=6), 10)


@settings(max_examples=15, deadline=None)
@given(st.integers(0, 10_000), st.sampled_from(["low", "medium", "high"]), st.integers(5, 40))
def test_the_paper_dfs_bound_is_within_the_path_bound_and_monotone(seed, level, n):
    world = make_world("corridor", level, np.random.default_rng(seed))
    deepest = max(cell_depths(world).values())
    if paper_dfs_completes(world, n):
        assert deepest <= n
        assert paper_dfs_completes(world, n + 1)
    assert paper_dfs_completes(world, len(world.cells))


@pytest.fixture(scope="module")
def overfilled_runs():
    """A high-complexity corridor at 6 s where two explorers committed to one junction spot and
    the second followed the newcomer into the side branch (found by the diagnosis sweep)."""
    kwargs = {"world": "corridor", "complexity": "high", "launch_period": 6.0}
    runs = {}
    for hold in (None, 1.0):
        model = BeaconExplorerModel(seed=900002, trace_interval=None, taken_hold=hold, **kwargs)
        model.run()
        runs[hold] = model
    return runs


def test_a_completable_corridor_lost_to_side_branch_over_filling(overfilled_runs):
    plain = classify(overfilled_runs[None])
    assert plain.completable and plain.path_bound
    assert not plain.complete
    assert plain.cause == "side branch over-filled" and plain.cause in CAUSES
    assert plain.extra_in_side >= 2
    assert plain.stranded == 0 and plain.shared_cells == 0


def test_an_explorer_whose_spot_is_taken_follows_its_junction_not_the_newcomer(overfilled_runs):
    held = classify(overfilled_runs[1.0])
    assert held.complete and held.cause == ""
    assert overfilled_runs[1.0].end_reason == "complete"


def test_taken_hold_is_validated():
    with pytest.raises(ConfigError, match="taken_hold"):
        BeaconExplorerModel(taken_hold=0.0)
