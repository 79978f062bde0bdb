"""Statistics on synthetic sweep results with known effects."""

import numpy as np
import pandas as pd
import pytest

from abm.errors import ConfigError
from analysis import stats

PERIODS = (6.0, 8.0, 10.0, 12.0, 18.0, 24.0)
FACTORS = ("launch_period", "complexity")


def synthetic(n: int = 8, seed: int = 0) -> pd.DataFrame:
    """Coverage time grows with the period, energy falls then rises (minimum at 12 s)."""
    rng = np.random.default_rng(seed)
    rows = []
    for complexity, scale in (("low", 1.0), ("high", 2.0)):
        for t in PERIODS:
            for _ in range(n):
                flight = 1000.0 * scale / t + rng.normal(0, 1)
                rows.append(
                    {
                        "complexity": complexity,
                        "launch_period": t,
                        "coverage_time": 10.0 * t + rng.normal(0, 1),
                        "flight_time": flight,
                        "energy_total": 120.0 * flight + rng.normal(0, 1),
                        "collisions": 5.0 * scale + rng.normal(0, 1),
                        "energy_curve": (t - 12.0) ** 2 + rng.normal(0, 0.1),
                        "status": "ok",
                    }
                )
    rows.append({"complexity": "low", "launch_period": 6.0, "status": "failed"})
    return pd.DataFrame(rows)


def test_anova_finds_the_effects_that_exist():
    df = synthetic()
    cov = stats.anova(df, "coverage_time", FACTORS)
    assert cov.loc["launch_period", "PR(>F)"] < 1e-6
    assert cov.loc["complexity", "PR(>F)"] > 0.01
    col = stats.anova(df, "collisions", FACTORS)
    assert col.loc["complexity", "PR(>F)"] < 1e-6
    assert {"launch_period:complexity", "Residual"} <= set(cov.index)
    assert cov.loc["launch_period", "df"] == len(PERIODS) - 1


def test_anova_with_one_complexity_is_one_way():
    df = synthetic()
    table = stats.anova(df[df["complexity"] == "low"], "coverage_time", FACTORS)
    assert list(table.index) == ["launch_period", "Residual"]


def test_percent_change_is_exact():
    df = synthetic()
    table = stats.percent_change(df, "coverage_time", 6.0, 24.0, *FACTORS)
    assert list(table["complexity"]) == ["high", "low"]
    runs = stats.ok_runs(df)
    low = runs[runs["complexity"] == "low"]
    a = low.loc[low["launch_period"] == 6.0, "coverage_time"].mean()
    b = low.loc[low["launch_period"] == 24.0, "coverage_time"].mean()
    got = table.set_index("complexity").loc["low", "change"]
    assert got == pytest.approx(100 * (b - a) / a)
    assert stats.percent_change(df, "coverage_time", 6.0, 30.0, *FACTORS).empty


def test_pearson_of_condition_means():
    result = stats.pearson(synthetic(), "flight_time", "energy_total", FACTORS)
    assert result["n"] == 12 and result["df"] == 10
    assert result["r"] > 0.999


def test_optimal_period_follows_the_weights():
    df = synthetic()
    time_only = stats.optimal_period(df, {"coverage_time": 1.0}, *FACTORS).set_index("complexity")
    assert (time_only["optimal_period"] == 6.0).all()
    convex = stats.optimal_period(df, {"energy_curve": 1.0}, *FACTORS).set_index("complexity")
    assert convex["optimal_period"].to_numpy() == pytest.approx([12.0, 12.0], abs=0.5)
    both = stats.optimal_period(df, {"coverage_time": 1.0, "energy_curve": 1.0}, *FACTORS)
    assert ((both["optimal_period"] > 6.0) & (both["optimal_period"] < 12.0)).all()


@pytest.mark.parametrize("weights", [{"coverage_time": -1.0}, {"coverage_time": 0.0}])
def test_optimal_period_rejects_bad_weights(weights):
    with pytest.raises(ConfigError, match="weight"):
        stats.optimal_period(synthetic(), weights, *FACTORS)


def test_condition_means_are_tidy():
    means = stats.condition_means(synthetic(), ["coverage_time"], FACTORS)
    assert len(means) == 12 and (means["n"] == 8).all()
    assert {"mean", "sem", "metric"} <= set(means.columns)
    with pytest.raises(ConfigError, match="'nope'"):
        stats.condition_means(synthetic(), ["nope"], FACTORS)
