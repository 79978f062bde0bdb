"""The coverage path planner of Fig. 4 (Sect. 3.2) on hand-made GlobalMaps."""

import numpy as np
import pytest

from abm.errors import ConfigError
from models.sugarmap.planner import HEADINGS, CoveragePlanner, heading_to

N, E, S, W = 0.0, 90.0, 180.0, 270.0
STEP = {heading: step for step, heading in HEADINGS.items()}


def _rng(seed: int = 0) -> np.random.Generator:
    return np.random.default_rng(seed)


def _step(cell, heading):
    dx, dy = STEP[heading]
    return cell[0] + dx, cell[1] + dy


def _frequencies(make, cell, grid, draws=20000, seed=1):
    """How often each heading is chosen by a fresh planner from ``cell``."""
    rng = _rng(seed)
    counts: dict[float, int] = {}
    for _ in range(draws):
        heading = make().decide(cell, grid, 0.0, rng)
        counts[heading] = counts.get(heading, 0) + 1
    return {h: c / draws for h, c in counts.items()}


def _walk_the_grid(planner, free, rng, ticks=2000):
    """An idealised explorer: enters its target in one tick, bumps into walls, and marks the
    GlobalMap 1 where it stands (binary coverage). Returns the visited cells and the GlobalMap.
    """
    cell = planner.root
    grid = np.zeros(free.shape)
    grid[cell[1], cell[0]] = 1.0
    visits = [cell]
    for t in range(ticks):
        heading = planner.decide(cell, grid, float(t), rng)
        if heading is None:
            break
        nxt = _step(cell, heading)
        if free[nxt[1], nxt[0]]:
            cell = nxt
            grid[cell[1], cell[0]] = 1.0
            visits.append(cell)
        else:
            planner.blocked(float(t))
    return visits, grid


def test_headings_follow_the_compass_convention():
    assert heading_to((3, 3), (3, 4)) == N
    assert heading_to((3, 3), (4, 3)) == E
    assert heading_to((3, 3), (3, 2)) == S
    assert heading_to((3, 3), (2, 3)) == W
    with pytest.raises(ConfigError, match="target must be 4-adjacent"):
        heading_to((3, 3), (4, 4))


@pytest.mark.parametrize("backtrack", ["soft", "hard"])
def test_a_single_uncovered_neighbour_is_always_chosen(backtrack):
    grid = np.ones((10, 10))
    grid[5, 6] = 0.9  # east of (5, 5), below COVER_TH
    rng = _rng()
    for _ in range(200):
        planner = CoveragePlanner((5, 5), backtrack=backtrack, beta=5.0)
        assert planner.decide((5, 5), grid, 0.0, rng) == E
        assert planner.target == (6, 5) and planner.tree_parent[(6, 5)] == (5, 5)


def test_a_cell_at_cover_th_counts_as_covered():
    grid = np.ones((10, 10))
    grid[6, 5] = 0.95  # north: covered exactly at the threshold
    grid[5, 4] = 0.9499  # west: not covered
    planner = CoveragePlanner((5, 5), backtrack="hard")
    assert planner.decide((5, 5), grid, 0.0, _rng()) == W


def test_choice_probabilities_follow_one_minus_g():
    grid = np.ones((10, 10))
    g = {N: 0.0, E: 0.5, S: 0.9}  # W stays covered (G = 1)
    for heading, value in g.items():
        x, y = _step((5, 5), heading)
        grid[y, x] = value
    freq = _frequencies(lambda: CoveragePlanner((5, 5)), (5, 5), grid)
    weights = {h: 1.0 - v + 1e-3 for h, v in g.items()}
    total = sum(weights.values())
    assert set(freq) == set(g)
    for heading, w in weights.items():
        assert freq[heading] == pytest.approx(w / total, abs=0.015)


def test_choice_probabilities_follow_the_inverse_reading():
    grid = np.ones((10, 10))
    g = {N: 0.2, E: 0.4, S: 0.8}
    for heading, value in g.items():
        x, y = _step((5, 5), heading)
        grid[y, x] = value
    freq = _frequencies(lambda: CoveragePlanner((5, 5), pick="inverse"), (5, 5), grid)
    weights = {h: 1.0 / (v + 1e-3) for h, v in g.items()}
    total = sum(weights.values())
    for heading, w in weights.items():
        assert freq[heading] == pytest.approx(w / total, abs=0.015)


def _planner_one_step_north(**kwargs):
    """A planner whose explorer went from the root (5, 5) to (5, 6): (5, 5) is its parent."""
    planner = CoveragePlanner((5, 5), **kwargs)
    grid = np.ones((10, 10))
    grid[6, 5] = 0.0
    assert planner.decide((5, 5), grid, 0.0, _rng()) == N
    return planner


@pytest.mark.parametrize("beta", [0.0, 1.0, 3.0])
def test_soft_backtracking_favours_the_tree_parent_by_beta(beta):
    grid = np.full((10, 10), 0.96)  # every neighbour covered (>= COVER_TH)
    freq = _frequencies(lambda: _planner_one_step_north(beta=beta), (5, 6), grid, draws=12000)
    w = 1.0 - 0.96 + 1e-3
    expected_parent = (w + beta) / (4 * w + beta)
    assert freq[S] == pytest.approx(expected_parent, abs=0.015)
    for other in (N, E, W):
        assert freq[other] == pytest.approx(w / (4 * w + beta), abs=0.015)


def test_soft_backtracking_never_idles():
    planner = CoveragePlanner((5, 5))
    grid = np.ones((10, 10))
    rng = _rng()
    for t in range(50):
        assert planner.decide((5, 5), grid, float(t), rng) is not None
        planner.target = None  # as if the explorer had moved and come back
    assert not planner.idle


def test_hard_backtracking_returns_to_the_root_then_idles():
    planner = CoveragePlanner((2, 2), backtrack="hard")
    grid = np.ones((8, 8))
    rng = _rng()
    path = [(2, 2), (2, 3), (3, 3), (3, 4)]  # walk away with one uncovered cell at a time
    for cell, nxt in zip(path, path[1:], strict=False):
        grid[nxt[1], nxt[0]] = 0.0
        assert planner.decide(cell, grid, 0.0, rng) == heading_to(cell, nxt)
        grid[nxt[1], nxt[0]] = 1.0
    cell = path[-1]
    back = []
    while (heading := planner.decide(cell, grid, 1.0, rng)) is not None:
        cell = _step(cell, heading)
        back.append(cell)
        assert len(back) < 10
    assert back == [(3, 3), (2, 3), (2, 2)]  # the tree edges, reversed
    assert planner.idle
    for t in range(2, 5):  # the exit condition is re-checked every tick
        assert planner.decide(cell, grid, float(t), rng) is None and planner.idle
    grid[1, 2] = 0.5  # a cell next to the root drops below COVER_TH
    assert planner.decide(cell, grid, 5.0, rng) == S
    assert not planner.idle


def test_hard_backtracking_escapes_at_random_off_the_tree():
    planner = CoveragePlanner((0, 0), backtrack="hard")
    grid = np.ones((10, 10))
    rng = _rng()
    far = (6, 6)  # reached by a jump of the pose estimate: no tree parent
    headings = set()
    for _ in range(200):
        headings.add(planner.decide(far, grid, 0.0, rng))
        assert planner.tree_parent[far] is None and not planner.idle
        planner.target = None
    assert headings == {N, E, S, W}


@pytest.mark.parametrize("backtrack", ["soft", "hard"])
def test_dfs_covers_a_room_with_an_obstacle(backtrack):
    free = np.zeros((8, 9), dtype=bool)
    free[1:7, 1:8] = True
    free[3, 4] = False  # an obstacle in the middle
    planner = CoveragePlanner((1, 1), backtrack=backtrack, blocked_ttl=1e9)
    visits, grid = _walk_the_grid(planner, free, _rng(3))
    assert (grid[free] == 1).all()
    assert grid[3, 4] == 0
    if backtrack == "hard":
        assert visits[-1] == (1, 1) and planner.idle


def test_blocked_target_is_avoided_until_the_ttl_passes():
    grid = np.ones((10, 10))
    grid[6, 5] = 0.0  # north of (5, 5) is the only uncovered neighbour
    planner = CoveragePlanner((5, 5), blocked_ttl=30.0)
    rng = _rng()
    assert planner.decide((5, 5), grid, 0.0, rng) == N
    planner.blocked(0.0)
    assert planner.target is None and planner.blocked_at == {(5, 6): 0.0}
    for t in range(1, 30):  # soft backtracking among the others, never north
        heading = planner.decide((5, 5), grid, float(t), rng)
        assert heading in (E, S, W)
        planner.target = None
    assert planner.decide((5, 5), grid, 30.0, rng) == N  # the mark has expired
    assert planner.blocked_at == {}


def test_blocked_under_hard_backtracking_and_all_neighbours_blocked():
    grid = np.zeros((10, 10))
    planner = CoveragePlanner((5, 5), backtrack="hard")
    rng = _rng()
    for t in range(4):
        heading = planner.decide((5, 5), grid, float(t), rng)
        assert _step((5, 5), heading) not in planner.blocked_at
        planner.blocked(float(t))
    assert len(planner.blocked_at) == 4
    assert planner.decide((5, 5), grid, 4.0, rng) is None  # at the root: the exit condition
    assert planner.idle
    soft = CoveragePlanner((1, 1))
    soft.blocked_at = {(1, 2): 0.0, (2, 1): 0.0, (1, 0): 0.0, (0, 1): 0.0}
    assert soft.decide((1, 1), grid, 1.0, rng) is None and not soft.idle  # hovers
    assert soft.decide((1, 1), grid, 31.0, rng) is not None


@pytest.mark.parametrize("backtrack", ["soft", "hard"])
def test_neighbours_outside_the_grid_are_never_chosen(backtrack):
    rng = _rng()
    for grid in (np.zeros((6, 6)), np.ones((6, 6))):
        for corner, allowed in (((0, 0), {N, E}), ((5, 5), {S, W}), ((0, 5), {S, E})):
            for _ in range(100):
                planner = CoveragePlanner((3, 3), backtrack=backtrack)
                heading = planner.decide(corner, grid, 0.0, rng)
                assert heading in allowed


def test_the_target_is_held_until_entered_or_no_longer_adjacent():
    grid = np.zeros((10, 10))
    planner = CoveragePlanner((5, 5))
    rng = _rng(7)
    first = planner.decide((5, 5), grid, 0.0, rng)
    target = _step((5, 5), first)
    changed = np.zeros((10, 10))
    changed[target[1], target[0]] = 1.0  # the target is now covered: still held
    for t in range(1, 5):
        assert planner.decide((5, 5), changed, float(t), rng) == first
    assert planner.target == target
    grid[target[1], target[0]] = 1.0
    nxt = planner.decide(target, grid, 5.0, rng)  # entered: a new target from there
    assert nxt is not None and planner.target != target and planner.prev_cell == target
    held = planner.target
    planner.decide((0, 9), grid, 6.0, rng)  # the pose jumped: the old target is dropped
    assert planner.target != held and planner.tree_parent[(0, 9)] is None


def test_tree_parent_is_the_previous_cell_when_adjacent():
    grid = np.zeros((10, 10))
    planner = CoveragePlanner((5, 5))
    rng = _rng()
    planner.decide((5, 5), grid, 0.0, rng)
    planner.target = None
    planner.decide((5, 6), grid, 1.0, rng)  # not chosen as a child, but entered from (5, 5)
    assert planner.tree_parent[(5, 6)] == (5, 5)
    assert (5, 5) not in planner.tree_parent  # the root has no parent


def test_same_seed_same_decisions():
    def run(seed):
        planner = CoveragePlanner((4, 4))
        rng = _rng(seed)
        grids = np.random.default_rng(99).random((60, 9, 9))
        cell, out = (4, 4), []
        for t, grid in enumerate(grids):
            heading = planner.decide(cell, grid, float(t), rng)
            out.append(heading)
            if t % 2:
                cell = _step(cell, heading)
            if t % 7 == 0:
                planner.blocked(float(t))
        return out

    assert run(5) == run(5)
    assert run(5) != run(6)


@pytest.mark.parametrize(
    ("kwargs", "name"),
    [
        ({"cover_th": 0.0}, "cover_th"),
        ({"cover_th": 1.5}, "cover_th"),
        ({"backtrack": "dfs"}, "backtrack"),
        ({"beta": -1.0}, "beta"),
        ({"blocked_ttl": 0.0}, "blocked_ttl"),
        ({"pick": "max"}, "pick"),
        ({"eps": 0.0}, "eps"),
        ({"eps": "small"}, "eps"),
    ],
)
def test_bad_parameters_name_themselves(kwargs, name):
    with pytest.raises(ConfigError, match=f"^{name} must"):
        CoveragePlanner((1, 1), **kwargs)


def test_bad_cells_and_maps():
    for root in [(1.5, 2), "ab", (1, 2, 3), None]:
        with pytest.raises(ConfigError, match="^root must be a cell"):
            CoveragePlanner(root)
    planner = CoveragePlanner((1, 1))
    with pytest.raises(ConfigError, match="^coverage must be a 2-D array"):
        planner.decide((1, 1), np.zeros(9), 0.0, _rng())
    with pytest.raises(ConfigError, match="^cell must be a cell"):
        planner.decide((1.2, 1), np.zeros((3, 3)), 0.0, _rng())
    with pytest.raises(ConfigError, match=r"^coverage must hold probabilities in \[0, 1\]"):
        planner.decide((1, 1), np.full((3, 3), 1.5), 0.0, _rng())
