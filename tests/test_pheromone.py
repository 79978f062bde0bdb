import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from abm.disc_cells import disc_offsets
from abm.errors import ConfigError
from abm.pheromone import PheromoneField


def test_disc_offsets_count_matches_area():
    dy, dx = disc_offsets(10.0)
    assert len(dy) == 317  # lattice points in a radius-10 disc
    assert np.all(np.hypot(dx, dy) <= 10.0)


def test_deposit_adds_intensity_on_disc_only_in_mask():
    mask = np.ones((30, 30), dtype=bool)
    mask[:, 15] = False
    f = PheromoneField((30, 30), mask=mask)
    f.deposit([[15.5, 15.5]], 3.0, 2.0)
    assert f.values[15, 15] == 0.0  # masked column
    assert f.values[15, 14] == 2.0
    assert f.total() == pytest.approx(2.0 * (29 - 7))


@given(st.floats(0.0, 0.01), st.lists(st.floats(0.0, 500.0), min_size=1, max_size=5))
@settings(max_examples=30, deadline=None)
def test_decay_matches_closed_form(rate, gaps):
    f = PheromoneField((10, 10), decay=rate)
    f.deposit([[5.0, 5.0]], 0.0, 1.0, time=0.0)
    t = 0.0
    for g in gaps:
        t += g
        f.advance(t)
    assert f.value_at([[5.0, 5.0]])[0] == pytest.approx(np.exp(-rate * t), rel=1e-9)


def test_deposits_at_different_times_decay_independently():
    f = PheromoneField((10, 10), decay=0.01)
    f.deposit([[5.0, 5.0]], 0.0, 1.0, time=0.0)
    f.deposit([[5.0, 5.0]], 0.0, 3.0, time=100.0)
    f.advance(250.0)
    expected = np.exp(-0.01 * 250) + 3 * np.exp(-0.01 * 150)
    assert f.value_at([[5.0, 5.0]])[0] == pytest.approx(expected)


def test_lower_direction_points_away_from_pheromone():
    f = PheromoneField((50, 50))
    f.deposit([[35.5, 25.5], [25.5, 40.5]], 4.0, 1.0)
    v = f.lower_direction([[25.5, 25.5], [25.5, 25.5]], 20.0)
    assert v[0, 0] < 0 and v[0, 1] < 0  # away from east and north deposits
    assert np.allclose(v[0], v[1])
    empty = PheromoneField((50, 50)).lower_direction([[10.0, 10.0]], 5.0)
    assert np.all(empty == 0)


def test_lower_direction_vectorised_equals_loop():
    rng = np.random.default_rng(3)
    f = PheromoneField((40, 60))
    f.deposit(rng.uniform(0, 40, (20, 2)), 5.0, rng.uniform(0, 1, 20))
    pts = rng.uniform(0, 40, (7, 2))
    together = f.lower_direction(pts, 8.0)
    single = np.vstack([f.lower_direction(p[None], 8.0) for p in pts])
    assert np.allclose(together, single)


def _brute_f1(f, mask, point, radius, falloff, relative):
    ix, iy = int(point[0]), int(point[1])
    here = f.values[iy, ix] if relative else 0.0
    total = np.zeros(2)
    r = int(radius)
    for dy in range(-r, r + 1):
        for dx in range(-r, r + 1):
            d = np.hypot(dx, dy)
            cx, cy = ix + dx, iy + dy
            if d == 0 or d > radius or not (0 <= cx < f.cols and 0 <= cy < f.rows):
                continue
            if relative and not mask[cy, cx]:
                continue
            total += np.array([dx, dy]) / d ** (1 + falloff) * (f.values[cy, cx] - here)
    return -total


@pytest.mark.parametrize("relative", [True, False])
@pytest.mark.parametrize("falloff", [1.0, 2.0])
def test_lower_direction_matches_the_sum_over_the_disc(relative, falloff):
    rng = np.random.default_rng(0)
    mask = np.ones((40, 60), dtype=bool)
    mask[10:30, 20] = False
    mask[:, :3] = False
    f = PheromoneField((40, 60), mask=mask)
    f.deposit(rng.uniform(0, 40, (30, 2)), 6.0, rng.uniform(0, 1, 30))
    pts = rng.uniform(0, 40, (9, 2))
    got = f.lower_direction(pts, 8.0, falloff=falloff, relative=relative)
    want = np.array([_brute_f1(f, mask, p, 8.0, falloff, relative) for p in pts])
    assert np.allclose(got, want, atol=1e-12)


def test_relative_reading_is_not_pulled_into_walls():
    """An even field inside a walled box: the absolute sum points at the nearest wall (the
    cut-away part of the disc reads as empty), the relative reading does not."""
    free = np.pad(np.ones((28, 28), dtype=bool), 1)
    f = PheromoneField((30, 30), mask=free)
    f.deposit([[15.0, 15.0]], 40.0, 1.0)
    near_west_wall = [[3.5, 15.5]]
    assert f.lower_direction(near_west_wall, 10.0, relative=False)[0, 0] < -1.0
    assert np.allclose(f.lower_direction(near_west_wall, 10.0), 0.0)


def test_line_of_sight_deposit_and_reading_stop_at_walls():
    mask = np.ones((30, 30), dtype=bool)
    mask[:, 15] = False
    f = PheromoneField((30, 30), mask=mask)
    f.deposit([[12.5, 15.5]], 8.0, 1.0, line_of_sight=True)
    assert f.values[15, 12 + 5] == 0.0  # behind the wall
    assert f.values[15, 12 - 5] == 1.0
    g = PheromoneField((30, 30), mask=mask)
    g.deposit([[12.5, 15.5]], 8.0, 1.0)
    assert g.values[15, 12 + 5] == 1.0  # the plain disc goes through
    h = PheromoneField((30, 30), mask=mask)
    h.deposit([[20.5, 15.5]], 3.0, 5.0)  # behind the wall
    assert h.lower_direction([[12.5, 15.5]], 10.0)[0, 0] < 0  # pushed away from it
    assert np.allclose(h.lower_direction([[12.5, 15.5]], 10.0, line_of_sight=True), 0.0)


def test_bad_input():
    with pytest.raises(ConfigError, match="decay"):
        PheromoneField((5, 5), decay=-1)
    with pytest.raises(ConfigError, match="shape"):
        PheromoneField((0, 5))
    f = PheromoneField((5, 5))
    f.advance(10)
    with pytest.raises(ConfigError, match="backwards"):
        f.advance(5)
