"""The sensor models with the constants of Stirling et al. (2010) (the beacon/explorer params):
noise of the stated size, no reading past range."""

import numpy as np

from abm.arena import Arena
from abm.sensors import distance_sensors, relative_positions
from models.beacon_explorer.params import DEFAULTS as P


def test_relative_positioning_has_the_published_noise_at_3_m():
    rng = np.random.default_rng(1)
    truth = np.tile([[0.0, 3.0]], (20_000, 1))  # a neighbour 3 m to the North
    measured = relative_positions(truth, rng, P.range_noise, P.bearing_noise, P.reference_range)
    r = np.hypot(measured[:, 0], measured[:, 1])
    bearing = np.degrees(np.arctan2(measured[:, 1], measured[:, 0]))
    assert abs(r.mean() - 3.0) < 0.01 and abs(r.std() - 0.17) < 0.01
    assert abs(bearing.mean() - 90.0) < 0.2 and abs(bearing.std() - 6.1) < 0.2
    # Range noise grows with range: at 1.5 m it is half as large.
    near = np.hypot(
        *relative_positions(truth / 2, rng, P.range_noise, P.bearing_noise, P.reference_range).T
    )
    assert abs(near.std() - 0.085) < 0.006


def test_distance_sensors_are_noisy_within_range_and_read_max_range_beyond():
    free = np.ones((10, 40), dtype=bool)
    arena = Arena(free, 1.0)
    point = np.array([[2.5, 5.0]])  # 2.5 m from the west edge, far from the others
    points = np.repeat(point, 20_000, axis=0)
    readings = distance_sensors(
        arena, points, np.random.default_rng(2), P.sensor_range, P.sensor_noise
    )
    north, east, south, west = readings.T
    assert abs(west.mean() - 2.5) < 0.002 and abs(west.std() - 0.05) < 0.002
    assert (east == 3.5).all() and (north == 3.5).all() and (south == 3.5).all()
