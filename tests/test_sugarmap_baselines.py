"""The baselines of Sect. 4.2: the lattice and bounce random walks, and D-cell OMSTC."""

import numpy as np
import pytest

from abm.errors import ConfigError
from models.sugarmap.arenas import arena_codes, start_cells
from models.sugarmap.baselines import OMSTC, BounceWalk, lattice_turns

D, SPEED, DT = 0.5, 0.35, 1.0


def _room(cols: int, rows: int) -> np.ndarray:
    """A walled room of cols x rows navigable cells (free, row 0 = south)."""
    free = np.zeros((rows + 2, cols + 2), dtype=bool)
    free[1:-1, 1:-1] = True
    return free


class Stepper:
    """Exact kinematics: move ``speed * dt`` along the heading; stay (blocked) if the end point
    is not free. Coverage: the cell of each robot's position at the end of every tick.
    """

    def __init__(self, free, roots):
        self.free = free
        self.pos = (np.array(roots, dtype=float) + 0.5) * D
        self.covered = np.zeros(free.shape, dtype=bool)
        self.bumps: list[tuple[int, tuple[int, int]]] = []
        self.entered: list[list[tuple[int, int]]] = [[] for _ in roots]  # cells new to all
        self._stamp()

    def _cell(self, point):
        return int(point[0] // D), int(point[1] // D)

    def _stamp(self):
        for r, p in enumerate(self.pos):
            ix, iy = self._cell(p)
            if not self.covered[iy, ix]:
                self.entered[r].append((ix, iy))
            self.covered[iy, ix] = True

    def tick(self, omstc):
        """One tick for every robot; False once every robot has stopped."""
        moving = False
        for r in range(len(self.pos)):
            cmd = omstc.command(r, self.pos[r], self.covered, D, SPEED, DT)
            if cmd is None:
                continue
            moving = True
            heading, speed = cmd
            assert 0.0 <= heading < 360.0 and 0.0 < speed <= SPEED
            rad = np.radians(heading)
            end = self.pos[r] + speed * DT * np.array([np.sin(rad), np.cos(rad)])
            ix, iy = self._cell(end)
            inside = 0 <= iy < self.free.shape[0] and 0 <= ix < self.free.shape[1]
            if inside and self.free[iy, ix]:
                self.pos[r] = end
            else:
                self.bumps.append((r, (ix, iy)))
                omstc.blocked(r)
        self._stamp()
        return moving

    def run(self, omstc, ticks):
        """Ticks until every robot stops (or ``ticks``); returns the ticks run."""
        for k in range(1, ticks + 1):
            if not self.tick(omstc):
                return k
        return ticks


# ------------------------------------------------------------------ random walks
def test_lattice_turns_draw_the_four_turns_uniformly():
    turns = lattice_turns(np.random.default_rng(0), 40000)
    assert turns.shape == (40000,)
    values, counts = np.unique(turns, return_counts=True)
    assert set(values) == {0.0, 90.0, -90.0, 180.0}
    np.testing.assert_allclose(counts / 40000, 0.25, atol=0.01)
    assert lattice_turns(np.random.default_rng(0), 0).shape == (0,)


def test_lattice_turns_determinism_and_bad_n():
    a = lattice_turns(np.random.default_rng(3), 50)
    np.testing.assert_array_equal(a, lattice_turns(np.random.default_rng(3), 50))
    assert not np.array_equal(a, lattice_turns(np.random.default_rng(4), 50))
    with pytest.raises(ConfigError, match="^n must"):
        lattice_turns(np.random.default_rng(0), -1)


def test_bounce_walk_starts_north_and_keeps_its_heading_until_blocked():
    rng = np.random.default_rng(1)
    walk = BounceWalk(3, rng)
    for _ in range(10):
        np.testing.assert_array_equal(walk.headings(np.zeros(3, bool), rng), [0.0, 0.0, 0.0])
    bumped = walk.headings(np.array([False, True, False]), rng)
    assert bumped[0] == 0.0 and bumped[2] == 0.0 and 0.0 < bumped[1] < 360.0
    for _ in range(10):
        np.testing.assert_array_equal(walk.headings(np.zeros(3, bool), rng), bumped)
    bumped[0] = 123.0  # a copy: the caller cannot change the walk's state
    assert walk.headings(np.zeros(3, bool), rng)[0] == 0.0


def test_bounce_walk_new_headings_are_uniform_and_seeded():
    def draws(seed):
        rng = np.random.default_rng(seed)
        walk = BounceWalk(1000, rng)
        return np.concatenate([walk.headings(np.ones(1000, bool), rng) for _ in range(10)])

    h = draws(2)
    assert h.min() >= 0.0 and h.max() < 360.0
    counts, _ = np.histogram(h, bins=8, range=(0.0, 360.0))
    np.testing.assert_allclose(counts / len(h), 1 / 8, atol=0.01)
    np.testing.assert_array_equal(h, draws(2))
    assert not np.array_equal(h, draws(3))


def test_bounce_walk_bad_input():
    rng = np.random.default_rng(0)
    with pytest.raises(ConfigError, match="^n must"):
        BounceWalk(0, rng)
    with pytest.raises(ConfigError, match=r"^blocked must have shape \(2,\)"):
        BounceWalk(2, rng).headings(np.zeros(3, bool), rng)


# ------------------------------------------------------------------ OMSTC
def test_dfs_starts_north_at_the_root_and_scans_counter_clockwise_from_the_parent():
    free = _room(6, 6)
    omstc = OMSTC(free, [(3, 3)])
    covered = np.zeros(free.shape, dtype=bool)
    covered[3, 3] = True
    heading, speed = omstc.command(0, np.array([1.75, 1.75]), covered, D, SPEED, DT)
    assert heading == pytest.approx(0.0) and speed == SPEED  # N first at the root
    covered[4, 3] = True  # now standing in (3, 4), entered from the south
    heading, _ = omstc.command(0, np.array([1.75, 2.25]), covered, D, SPEED, DT)
    assert heading == pytest.approx(90.0)  # counter-clockwise after S comes E
    assert omstc.parent[0][(4, 4)] == (3, 4) and omstc.parent[0][(3, 4)] == (3, 3)


def test_closed_loop_motion_toward_the_target_centre_without_overshoot():
    free = _room(4, 4)
    omstc = OMSTC(free, [(2, 2)])
    covered = np.zeros(free.shape, dtype=bool)
    covered[2, 2] = True
    assert omstc.command(0, np.array([1.25, 1.25]), covered, D, SPEED, DT) == (0.0, SPEED)
    position = np.array([1.25, 1.60])  # entered (2, 3) from the south: its child is E, (3, 3)
    covered[3, 2] = True
    heading, speed = omstc.command(0, position, covered, D, SPEED, DT)
    offset = (np.array([3, 3]) + 0.5) * D - position
    assert heading == pytest.approx(np.degrees(np.arctan2(*offset)))  # about 73 deg
    assert speed == SPEED and omstc.target[0] == (3, 3)
    heading, speed = omstc.command(0, np.array([1.45, 1.75]), covered, D, SPEED, DT)
    assert heading == pytest.approx(90.0) and speed == pytest.approx(0.30)  # lands on centre


@pytest.mark.parametrize("n", [1, 2])
def test_a_small_room_is_covered_completely_then_the_robots_stop(n):
    free = _room(7, 5)
    roots = start_cells(free, n)
    stepper = Stepper(free, roots)
    omstc = OMSTC(free, roots)
    ticks = stepper.run(omstc, 400)
    assert ticks < 400 and all(omstc.done)
    np.testing.assert_array_equal(stepper.covered, free)
    for _, cell in stepper.bumps:  # only walls are ever bumped, and each at most once
        assert not free[cell[1], cell[0]]
    assert len(stepper.bumps) == len(set(stepper.bumps))
    assert all(omstc.command(r, stepper.pos[r], stepper.covered, D, SPEED, DT) is None
               for r in range(n))  # fmt: skip


def test_two_robots_share_the_work():
    free = _room(8, 8)
    roots = start_cells(free, 2)
    stepper = Stepper(free, roots)
    stepper.run(OMSTC(free, roots), 600)
    assert stepper.covered[free].all()
    assert min(len(e) for e in stepper.entered) >= 16  # each covers a good share of 64 cells


def test_the_testbed_is_covered_in_a_few_hundred_ticks():
    free = arena_codes("testbed") == 0
    roots = start_cells(free, 2)
    assert roots == [(1, 1), (2, 1)]
    stepper = Stepper(free, roots)
    omstc = OMSTC(free, roots)
    ticks = 0
    while not stepper.covered[free].all() and ticks < 300:
        stepper.tick(omstc)
        ticks += 1
    assert stepper.covered[free].all() and ticks < 200


def test_the_help_step_takes_a_robot_whose_tree_is_done_to_new_ground():
    # A one-cell dead end (1, 1) - (2, 1) - (3, 1) opening onto a room x 4..9, y 1..6.
    free = np.zeros((8, 11), dtype=bool)
    free[1, 1:4] = True
    free[1:7, 4:10] = True
    roots = [(1, 1), (2, 1)]  # robot 0 sits in the dead end behind robot 1
    stepper = Stepper(free, roots)
    omstc = OMSTC(free, roots)
    for _ in range(3):  # robot 0 bumps N, W, S; E is covered: its first tree is its root
        stepper.tick(omstc)
    assert [cell for r, cell in stepper.bumps if r == 0] == [(1, 2), (0, 1), (1, 0)]
    assert omstc.parent[0] == {(1, 1): None}
    stepper.run(omstc, 600)
    assert stepper.covered[free].all() and all(omstc.done)
    assert len(stepper.entered[0]) >= 8  # every one of them found by helping
    roots_of_subtrees = [c for c, p in omstc.parent[0].items() if p is None]
    assert len(roots_of_subtrees) >= 2


def test_robots_keep_out_of_a_cell_another_robot_has_claimed():
    free = _room(6, 6)
    omstc = OMSTC(free, [(3, 3), (3, 3)])  # no collisions: two robots can share a cell
    covered = np.zeros(free.shape, dtype=bool)
    covered[3, 3] = True
    position = np.array([1.75, 1.75])
    assert omstc.command(0, position, covered, D, SPEED, DT)[0] == pytest.approx(0.0)
    assert omstc.command(1, position, covered, D, SPEED, DT)[0] == pytest.approx(270.0)
    assert omstc.target == [(3, 4), (2, 3)]


def test_a_robot_waits_while_the_only_new_cell_is_claimed_then_helps():
    free = _room(4, 1)  # cells (1..4, 1)
    walls = {(x, y) for y, x in zip(*np.nonzero(~free), strict=True)}
    omstc = OMSTC(free, [(1, 1), (2, 1)])
    omstc.obstacles[0] |= walls  # both robots have bumped every wall already
    omstc.obstacles[1] |= walls
    covered = np.zeros(free.shape, dtype=bool)
    covered[1, 1] = covered[1, 2] = True
    assert omstc.command(1, np.array([1.25, 0.75]), covered, D, SPEED, DT)[0] == 90.0
    assert omstc.command(0, np.array([0.75, 0.75]), covered, D, SPEED, DT) is None
    assert omstc.done == [False, False]  # (3, 1) is claimed by robot 1: wait
    covered[1, 3] = True  # robot 1 entered (3, 1): (4, 1) is new ground beyond it
    assert omstc.command(0, np.array([0.75, 0.75]), covered, D, SPEED, DT)[0] == 90.0
    assert omstc.route[0] == [(2, 1), (3, 1)]


def test_with_no_frontier_left_the_robot_stops():
    free = _room(3, 1)  # a 3-cell corridor, already covered: only its walls are unknown
    stepper = Stepper(free, [(1, 1)])
    stepper.covered[free] = True
    omstc = OMSTC(free, [(1, 1)])
    stepper.run(omstc, 100)
    assert omstc.done == [True]
    walls = {(x, y) for x in range(1, 4) for y in (0, 2)} | {(0, 1), (4, 1)}
    assert sorted(cell for _, cell in stepper.bumps) == sorted(walls)  # each bumped once
    assert omstc.command(0, stepper.pos[0], stepper.covered, D, SPEED, DT) is None


def test_a_bumped_cell_is_an_obstacle_to_that_robot_only():
    free = _room(5, 5)
    free[3, 3] = False  # an obstacle
    omstc = OMSTC(free, [(3, 2), (1, 5)])
    covered = np.zeros(free.shape, dtype=bool)
    covered[2, 3] = covered[5, 1] = True
    heading, _ = omstc.command(0, np.array([1.75, 1.25]), covered, D, SPEED, DT)
    assert heading == pytest.approx(0.0) and omstc.target[0] == (3, 3)
    omstc.blocked(0)
    assert omstc.obstacles[0] == {(3, 3)} and omstc.obstacles[1] == set()
    assert omstc.target[0] is None and (3, 3) not in omstc.parent[0]
    heading, _ = omstc.command(0, np.array([1.75, 1.25]), covered, D, SPEED, DT)
    assert heading == pytest.approx(270.0)  # the next one counter-clockwise: W
    assert omstc.target[0] == (2, 2)


def test_an_obstacle_in_the_room_is_bumped_once_and_left_uncovered():
    free = _room(6, 6)
    free[4, 3] = free[4, 4] = False
    roots = start_cells(free, 2)
    stepper = Stepper(free, roots)
    omstc = OMSTC(free, roots)
    stepper.run(omstc, 600)
    np.testing.assert_array_equal(stepper.covered, free)
    for r in range(2):
        assert omstc.obstacles[r] <= {(x, y) for y, x in zip(*np.nonzero(~free), strict=True)}
        hits = [cell for robot, cell in stepper.bumps if robot == r]
        assert len(hits) == len(set(hits))


def test_a_bump_on_the_way_to_a_covered_cell_retries_it():
    free = _room(4, 4)
    omstc = OMSTC(free, [(2, 2)])
    covered = np.zeros(free.shape, dtype=bool)
    covered[2, 2] = True
    assert omstc.command(0, np.array([1.25, 1.25]), covered, D, SPEED, DT)[0] == 0.0
    assert omstc.target[0] == (2, 3)  # a new child, north
    covered[:] = free  # everything covered: the robot in (2, 3) backtracks to (2, 2)
    heading, _ = omstc.command(0, np.array([1.25, 1.75]), covered, D, SPEED, DT)
    assert heading == pytest.approx(180.0) and omstc.target[0] == (2, 2)
    omstc.blocked(0)  # a noise graze: (2, 2) is known free
    assert omstc.target[0] == (2, 2) and omstc.obstacles[0] == set()


def test_a_robot_pushed_off_its_way_hangs_the_new_cell_on_its_last_one():
    free = _room(5, 5)
    omstc = OMSTC(free, [(3, 3)])
    covered = np.zeros(free.shape, dtype=bool)
    covered[3, 3] = True
    omstc.command(0, np.array([1.75, 1.75]), covered, D, SPEED, DT)
    assert omstc.target[0] == (3, 4)
    covered[3, 2] = True  # noise took it west into (2, 3) instead
    omstc.command(0, np.array([1.45, 1.75]), covered, D, SPEED, DT)
    assert omstc.parent[0][(2, 3)] == (3, 3)
    assert omstc.target[0] == (2, 4)  # counter-clockwise after E comes N


def test_same_inputs_same_commands():
    def run():
        free = arena_codes("testbed") == 0
        roots = start_cells(free, 2)
        stepper = Stepper(free, roots)
        omstc = OMSTC(free, roots)
        trace = []
        for _ in range(80):
            stepper.tick(omstc)
            trace.append(stepper.pos.copy())
        return np.array(trace)

    np.testing.assert_array_equal(run(), run())


def test_omstc_bad_input():
    free = _room(3, 3)
    with pytest.raises(ConfigError, match="^free must be a non-empty 2-D array"):
        OMSTC(free[0], [(1, 1)])
    with pytest.raises(ConfigError, match="^roots must list at least one"):
        OMSTC(free, [])
    with pytest.raises(ConfigError, match="^roots must lie in the 5 x 5 cell grid"):
        OMSTC(free, [(1, 1), (5, 1)])
    with pytest.raises(ConfigError, match="^roots must hold cells"):
        OMSTC(free, [(1.5, 1)])
    omstc = OMSTC(free, [(1, 1)])
    with pytest.raises(ConfigError, match=r"^covered must have shape \(5, 5\)"):
        omstc.command(0, np.array([0.75, 0.75]), np.zeros((4, 4), bool), D, SPEED, DT)
