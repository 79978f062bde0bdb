"""The explorers' odometry in the summary: ``flight_distance`` and ``mean_flight_speed``, the
metric that tells flight speeds apart in a calibration (docs/calibration.md)."""

import numpy as np

from analysis.runner import run_model


def test_mean_flight_speed_stays_under_the_cap_and_rises_with_it():
    """Without body noise a flyer never moves faster than ``max_speed``, so the mean speed is
    at most the cap; raising the cap raises it (the explorers cruise at the cap in corridors)."""
    speeds = []
    for cap in (0.4, 1.2):
        summary = run_model(
            "beacon-explorer",
            {"max_speed": cap, "body_noise": 0.0, "n_robots": 8, "time_limit": 300.0},
            seed=27,
        ).summary
        assert summary["flight_distance"] > 0
        assert 0 < summary["mean_flight_speed"] <= cap + 1e-9
        assert np.isclose(
            summary["mean_flight_speed"], summary["flight_distance"] / summary["flight_time"]
        )
        speeds.append(summary["mean_flight_speed"])
    assert speeds[1] > 1.3 * speeds[0]
