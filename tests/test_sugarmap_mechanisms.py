"""The candidate mechanisms of SugarMap's Figs. 8, 9 and 11 (issue 30), each a keyword whose
default is the paper's reading: resampling noise (``resample_noise``), what an explorer counts
as covered by itself (``self_cover``), where the anchors land (``anchor_placement``) and
backtracking toward the nearest uncovered cell (``backtrack="frontier"``). Each
acts where it is switched on, and a bad value is refused in one line naming it."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from abm.errors import ConfigError
from models.sugarmap import SugarMapModel
from models.sugarmap.particles import MapGrid, ParticleFilter
from models.sugarmap.planner import CoveragePlanner

GRID = MapGrid.around(10.0, 10.0, 0.5, 4)
START = np.array([[2.25, 2.25]])
TESTBED = {"arena": "testbed", "n_anchors": 5, "n_explorers": 2, "init_cutoff": 60.0}


def _resampled(noise: float, n: int, seed: int) -> np.ndarray:
    """Particle positions after one resampling: all start at START, a signature is stored,
    and the same signature comes back (a match with every delta 0, so uniform weights)."""
    pf = ParticleFilter(START, n, 2, GRID, sig_th=0.5, resample_noise=noise)
    rng = np.random.default_rng(seed)
    signature = np.array([1.0, 2.0])
    assert not pf.correct(rng, 0, signature, 0.0).matched
    assert pf.correct(rng, 0, signature, 1.0).matched
    return pf.pos[0]


@settings(max_examples=20, deadline=None)
@given(st.floats(0.05, 2.0), st.integers(0, 2**32 - 1))
def test_resample_noise_jitters_every_resampled_particle_by_its_sd(noise, seed):
    offsets = _resampled(noise, 4000, seed) - START[0]
    assert np.all(np.hypot(*offsets.T) > 0)  # no particle is left a bare copy
    assert offsets.std(axis=0) == pytest.approx([noise, noise], rel=0.1)
    assert np.abs(offsets.mean(axis=0)).max() < 0.1 * noise


def test_resample_noise_off_leaves_copies():
    assert np.all(_resampled(0.0, 50, 1) == START[0])


def test_self_cover_tree_never_steps_back_onto_its_own_path():
    """A 1 x 4 corridor, nothing covered on the GlobalMap: from (2, 0) after standing in (1, 0)
    the "map" planner may head back west; the "tree" planner only east, to (3, 0)."""
    coverage = np.zeros((1, 4))
    west = {"map": 0, "tree": 0}
    for rule in west:
        for seed in range(100):
            rng = np.random.default_rng(seed)
            planner = CoveragePlanner((1, 0), self_cover=rule)
            planner.decide((1, 0), coverage, 0.0, rng)
            heading = planner.decide((2, 0), coverage, 1.0, rng)
            west[rule] += heading == 270.0
            assert heading in (90.0, 270.0)
    assert west["tree"] == 0
    assert 25 < west["map"] < 75


def test_anchor_placement_spread_lands_every_anchor_at_once_far_apart():
    m = SugarMapModel(arena="open", n_anchors=4, horizon=5.0, anchor_placement="spread", seed=3)
    m.run()
    assert m.t_deploy == 0.0 and not m.cutoff_fired
    pos = m.anchor_pos
    assert m.arena.is_free(pos).all()
    gaps = np.hypot(*(pos[:, None] - pos[None]).transpose(2, 0, 1))
    assert gaps[np.triu_indices(4, 1)].min() > 9.0  # the four corners of the 20 m square
    dispersed = SugarMapModel(arena="open", n_anchors=4, horizon=5.0, seed=3).run()
    assert dispersed.t_deploy > 0.0  # Fig. 3's dispersion takes time


def test_anchor_placement_spread_reaches_the_serpentines_far_lanes():
    """Fig. 3's dispersion leaves every anchor in the serpentine's first lanes (README, Fig. 11);
    "spread" places them across the 20 m square."""
    east = {}
    for rule in ("disperse", "spread"):
        m = SugarMapModel(arena="serpentine", horizon=1.0, anchor_placement=rule, seed=5)
        east[rule] = m.run().anchor_pos[:, 0].max()
    assert east["disperse"] < 6.0 < 15.0 < east["spread"]


#: One non-default value of each mechanism's keyword.
MECHANISMS = [
    ("resample_noise", 0.3),
    ("self_cover", "tree"),
    ("anchor_placement", "spread"),
    ("backtrack", "frontier"),
]


@pytest.mark.parametrize("keyword, value", MECHANISMS)
def test_each_mechanism_changes_a_testbed_run(keyword, value):
    base = SugarMapModel(horizon=60.0, seed=7, **TESTBED).run().samples()
    other = SugarMapModel(horizon=60.0, seed=7, **TESTBED, **{keyword: value}).run()
    assert not base.equals(other.samples())


@pytest.mark.parametrize(
    "keyword, value, rule",
    [
        ("resample_noise", -0.1, r"resample_noise must be in \[0, inf\], got -0.1"),
        ("self_cover", "path", "self_cover must be one of 'map', 'tree', got 'path'"),
        ("anchor_placement", "grid", "anchor_placement must be one of 'disperse', 'spread'"),
        ("backtrack", "bfs", "backtrack must be one of 'soft', 'hard', 'frontier', got 'bfs'"),
    ],
)
def test_bad_values_are_refused_in_one_line(keyword, value, rule):
    with pytest.raises(ConfigError, match=rule) as info:
        SugarMapModel(seed=1, **{keyword: value})
    assert "\n" not in str(info.value)


@pytest.mark.parametrize("keyword, value", MECHANISMS)
def test_baselines_refuse_the_mechanisms(keyword, value):
    with pytest.raises(ConfigError, match=f"{keyword} applies to algorithm='sugarmap' only"):
        SugarMapModel(algorithm="omstc", seed=1, **{keyword: value})


def test_filter_and_planner_refuse_bad_values():
    with pytest.raises(ConfigError, match="resample_noise"):
        ParticleFilter(START, 5, 2, GRID, sig_th=0.5, resample_noise=-1.0)
    with pytest.raises(ConfigError, match="self_cover"):
        CoveragePlanner((0, 0), self_cover="both")
    with pytest.raises(ConfigError, match="backtrack"):
        CoveragePlanner((0, 0), backtrack="bfs")


def _walk_to(planner: CoveragePlanner, cells: list, coverage: np.ndarray, rng) -> float | None:
    """Decide in each of ``cells`` in turn (a path the planner stood in); the last heading."""
    heading = None
    for t, cell in enumerate(cells):
        heading = planner.decide(cell, coverage, float(t), rng)
    return heading


def test_frontier_backtracking_heads_for_what_is_left_not_for_the_tree_parent():
    """A 1 x 6 corridor covered but for its east end; the planner came from the west. Soft
    backtracking favours the tree parent (west); "frontier" always heads east."""
    coverage = np.array([[1.0, 1.0, 1.0, 1.0, 1.0, 0.0]])
    west = {"soft": 0, "frontier": 0}
    for rule in west:
        for seed in range(50):
            planner = CoveragePlanner((1, 0), backtrack=rule)
            heading = _walk_to(planner, [(1, 0), (2, 0)], coverage, np.random.default_rng(seed))
            west[rule] += heading == 270.0
            assert heading in (90.0, 270.0)
    assert west["frontier"] == 0
    assert west["soft"] > 40


def _distance_to_uncovered(coverage: np.ndarray, start: tuple, th: float) -> int | None:
    """Steps of the shortest 4-neighbour path from ``start`` through covered cells to an
    uncovered one (None: none reachable)."""
    rows, cols = coverage.shape
    seen, frontier, d = {start}, [start], 0
    while frontier:
        d += 1
        nxt = []
        for x, y in frontier:
            for n in ((x, y + 1), (x + 1, y), (x, y - 1), (x - 1, y)):
                if n in seen or not (0 <= n[0] < cols and 0 <= n[1] < rows):
                    continue
                if coverage[n[1], n[0]] < th:
                    return d
                seen.add(n)
                nxt.append(n)
        frontier = nxt
    return None


@settings(max_examples=60, deadline=None)
@given(st.integers(2, 8), st.integers(2, 8), st.integers(0, 2**32 - 1))
def test_frontier_step_shortens_the_way_to_the_nearest_uncovered_cell(rows, cols, seed):
    rng = np.random.default_rng(seed)
    coverage = (rng.random((rows, cols)) < 0.8).astype(float)  # 1: covered
    cell = (int(rng.integers(cols)), int(rng.integers(rows)))
    coverage[cell[1], cell[0]] = 1.0  # it stands there
    planner = CoveragePlanner(cell, backtrack="frontier")
    heading = planner.decide(cell, coverage, 0.0, rng)
    far = _distance_to_uncovered(coverage, cell, 0.95)
    if far is None or far == 1:  # nothing left (soft fallback) or an uncovered neighbour
        return
    dx, dy = {0.0: (0, 1), 90.0: (1, 0), 180.0: (0, -1), 270.0: (-1, 0)}[heading]
    step = (cell[0] + dx, cell[1] + dy)
    assert coverage[step[1], step[0]] >= 0.95
    assert _distance_to_uncovered(coverage, step, 0.95) == far - 1


@pytest.mark.parametrize(
    ("keywords", "rule"),
    [
        ({"sigma_m": 0.3}, "sigma_m .* applies to weights='gauss' only, got weights='eq8'"),
        ({"sigma_m": 0.3, "weights": "eq8"}, "applies to weights='gauss' only"),
        ({"horizon": 100.0, "dt": 1000.0}, r"dt \(1000 s\) must not exceed the horizon"),
    ],
)
def test_a_keyword_that_would_change_nothing_or_overrun_the_run_is_refused(keywords, rule):
    # sigma_m without Gaussian weights ran the same run; dt past the horizon ran 2000 s
    with pytest.raises(ConfigError, match=rule):
        SugarMapModel(seed=1, **keywords)
    SugarMapModel(seed=1, weights="gauss", sigma_m=0.3)  # where it applies, it is taken
