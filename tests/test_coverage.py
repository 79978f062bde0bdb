"""Coverage rasters (abm.coverage): what a sensor sees, checked against brute force; when each
pixel was first covered; the two disc conventions."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from abm.arena import Arena
from abm.coverage import CoverageRaster
from abm.disc_cells import disc_offsets
from abm.errors import ConfigError
from models.environments import builtin_map


def _brute_force(arena, raster, points):
    """Free fine pixels whose centre lies within the radius of a point, seen from it."""
    rows, cols = raster.free.shape
    iy, ix = np.mgrid[0:rows, 0:cols]
    centres = (np.stack([ix.ravel(), iy.ravel()], axis=1) + 0.5) * raster.pixel
    seen = set()
    for p in points:
        near = (np.hypot(*(centres - p).T) <= raster.radius) & raster.free.ravel()
        idx = np.nonzero(near)[0]
        los = arena.line_of_sight(np.repeat(p[None], len(idx), axis=0), centres[idx])
        seen |= set(idx[los].tolist())
    return seen


def test_cell_disc_is_the_disc_cells_in_line_of_sight():
    arena = builtin_map("divided")
    raster = CoverageRaster(arena, 10.0, around="cell")
    dy, dx = disc_offsets(10.0)
    rng = np.random.default_rng(1)
    points = rng.uniform(40, 60, (6, 2))
    points = points[arena.is_free(points)]
    want = set()
    for p in points:
        ix, iy = int(p[0]), int(p[1])
        tx, ty = ix + dx, iy + dy
        ok = arena.free[ty, tx]
        ends = (np.stack([tx[ok], ty[ok]], axis=1) + 0.5) * arena.resolution
        los = arena.line_of_sight(np.repeat(p[None], ok.sum(), axis=0), ends)
        want |= set((ty[ok][los] * arena.cols + tx[ok][los]).tolist())
    assert set(raster.visible(points).tolist()) == want
    skip = np.zeros_like(arena.free)
    skip.ravel()[sorted(want)[:50]] = True
    assert set(raster.visible(points, skip=skip).tolist()) == want - set(sorted(want)[:50])


@settings(max_examples=25, deadline=None)
@given(
    st.lists(st.tuples(st.floats(0.3, 11.7), st.floats(0.3, 8.7)), min_size=1, max_size=4),
    st.floats(0.5, 4.0),
    st.sampled_from([1.0, 0.5, 0.25]),
)
def test_point_disc_matches_brute_force_around_walls(points, radius, pixel):
    free = np.ones((9, 12), dtype=bool)
    free[2:7, 6] = False  # a wall with gaps at both ends
    free[4, 2] = False  # a pillar
    arena = Arena(free, 1.0)
    points = np.array(points)
    points = points[arena.is_free(points)]
    raster = CoverageRaster(arena, radius, pixel)
    assert set(raster.visible(points).tolist()) == _brute_force(arena, raster, points)


def test_without_line_of_sight_the_sensor_sees_through_walls():
    free = np.ones((20, 20), dtype=bool)
    free[:, 10] = False
    arena = Arena(free)
    blind = CoverageRaster(arena, 5.0, around="cell").visible([[8.5, 10.5]])
    through = CoverageRaster(arena, 5.0, around="cell", line_of_sight=False).visible([[8.5, 10.5]])
    assert np.all(blind % 20 < 10)
    assert np.any(through % 20 > 10)


@settings(max_examples=25, deadline=None)
@given(st.lists(st.tuples(st.floats(0.5, 19.5), st.floats(0.5, 9.5)), min_size=1, max_size=8))
def test_first_covered_is_the_earliest_stamp_and_fraction_counts_pixels(points):
    free = np.ones((10, 20), dtype=bool)
    free[3:, 12] = False
    arena = Arena(free, 1.0)
    raster = CoverageRaster(arena, 3.0, pixel=0.5)
    first = {}
    for time, p in enumerate(points):
        p = np.array([p])
        if not arena.is_free(p)[0]:
            continue
        new_area = raster.stamp(p, float(time))
        seen = raster.visible(p)
        assert new_area == pytest.approx(len(set(seen.tolist()) - set(first)) * 0.25)
        for cell in seen.tolist():
            first.setdefault(cell, float(time))
    got = raster.first_covered.ravel()
    assert {i: got[i] for i in np.nonzero(np.isfinite(got))[0].tolist()} == first
    assert raster.fraction == pytest.approx(raster.covered.sum() / raster.free.sum())
    assert raster.area == pytest.approx(raster.covered.sum() * 0.25)
    for t in range(len(points)):
        assert np.array_equal(raster.covered_at(t), raster.first_covered <= t)


def test_bad_settings_are_config_errors():
    arena = Arena(np.ones((4, 4), dtype=bool))
    with pytest.raises(ConfigError, match="radius"):
        CoverageRaster(arena, 0.0)
    with pytest.raises(ConfigError, match="around must be one of"):
        CoverageRaster(arena, 1.0, around="corner")
    with pytest.raises(ConfigError, match="pixel"):
        CoverageRaster(arena, 1.0, pixel=-1.0)
