"""Statistics on synthetic sweep results with known effects."""

import warnings

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

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
    cov = stats.anova(df, "coverage_time", FACTORS).table
    assert cov.loc["launch_period", "PR(>F)"] < 1e-6
    assert cov.loc["complexity", "PR(>F)"] > 0.01
    col = stats.anova(df, "collisions", FACTORS).table
    assert col.loc["complexity", "PR(>F)"] < 1e-6
    assert {"launch_period:complexity", "Residual"} <= set(cov.index)
    assert cov.loc["launch_period", "df"] == len(PERIODS) - 1


def test_anova_with_one_complexity_is_one_way():
    df = synthetic()
    result = stats.anova(df[df["complexity"] == "low"], "coverage_time", FACTORS)
    assert list(result.table.index) == ["launch_period", "Residual"]
    assert result.notes == ("complexity has one level in these runs: left out",)


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


# ------------------------------------------------------------------ refusals
def _quiet_anova(df: pd.DataFrame, metric: str, factors) -> stats.Anova:
    """stats.anova with every warning an error: none may reach the terminal."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        return stats.anova(df, metric, factors, resamples=50)


def test_a_constant_response_is_not_analysed():
    df = synthetic().assign(coverage_time=120.0)  # beacon/explorer's cut runs: 120 s in each
    result = _quiet_anova(df, "coverage_time", FACTORS)
    assert result.table is None
    assert result.reason == "coverage_time is constant (120 in every run)"


def test_a_response_constant_within_conditions_is_not_analysed():
    # stigmergy's final beacons: a fixed number per condition, F a ratio to zero
    df = synthetic()
    df["beacons"] = df["launch_period"] * 2.0
    result = _quiet_anova(df, "beacons", FACTORS)
    assert result.table is None
    assert "does not vary within any condition" in result.reason


def hierarchy_runs(n: int = 3) -> pd.DataFrame:
    """Runs of a W x S grid with the robot total N = 1 + W + W S, which fixes W."""
    rng = np.random.default_rng(2)
    rows = [
        {"W": w, "S": s, "N": 1 + w + w * s, "scout_drive": 100.0 * s + rng.normal(0, 5)}
        for w in (2, 3)
        for s in (2, 3)
        for _ in range(n)
    ]
    return pd.DataFrame(rows)


def test_collinear_factors_are_not_analysed():
    result = _quiet_anova(hierarchy_runs(), "scout_drive", ["N", "W"])
    assert result.table is None
    assert result.reason.startswith("W is fixed by N")
    assert "full rank" in result.reason


def test_a_grid_with_missing_combinations_is_not_analysed():
    df = synthetic()
    df = df[~((df["complexity"] == "high") & (df["launch_period"] == 6.0))]
    result = _quiet_anova(df, "coverage_time", FACTORS)
    assert result.table is None
    assert result.reason.startswith("only 11 of the 12 combinations of launch_period x complexity")


def test_one_run_per_condition_is_not_analysed():
    df = synthetic().drop_duplicates(["launch_period", "complexity", "status"])
    result = _quiet_anova(df, "coverage_time", FACTORS)
    assert result.table is None and "no residual degrees of freedom" in result.reason


@settings(max_examples=25, deadline=None)
@given(
    sizes=st.lists(st.integers(2, 5), min_size=6, max_size=6),
    seed=st.integers(0, 2**16),
)
def test_type2_sums_are_statsmodels_own(sizes, seed):
    """The bootstrap's fast sums of squares equal statsmodels' type-II table (unbalanced)."""
    from statsmodels.formula.api import ols
    from statsmodels.stats.anova import anova_lm

    from analysis.anova import type2_sums

    rng = np.random.default_rng(seed)
    cells = [(a, b) for a in range(3) for b in range(2)]
    a = np.repeat([c[0] for c in cells], sizes)
    b = np.repeat([c[1] for c in cells], sizes)
    y = a * 1.5 + b * rng.normal() + rng.normal(size=len(a))
    ours = type2_sums(y, [a, b], [(0,), (1,), (0, 1)])
    data = pd.DataFrame({"y": y, "a": a, "b": b})
    theirs = anova_lm(ols("y ~ C(a) * C(b)", data).fit(), typ=2)["sum_sq"]
    assert ours[(0,)] == pytest.approx(theirs["C(a)"], rel=1e-7, abs=1e-9)
    assert ours[(1,)] == pytest.approx(theirs["C(b)"], rel=1e-7, abs=1e-9)
    assert ours[(0, 1)] == pytest.approx(theirs["C(a):C(b)"], rel=1e-7, abs=1e-9)
    assert ours["Residual"] == pytest.approx(theirs["Residual"], rel=1e-7, abs=1e-9)


def test_effect_intervals_are_seeded_and_hold_the_estimate():
    df = synthetic()
    a = stats.anova(df, "collisions", FACTORS, seed=4).table
    b = stats.anova(df, "collisions", FACTORS, seed=4).table
    c = stats.anova(df, "collisions", FACTORS, seed=5).table
    pd.testing.assert_frame_equal(a, b)
    assert not np.allclose(a["eta_sq_low"].dropna(), c["eta_sq_low"].dropna())
    effects = a.drop(index="Residual")
    assert (effects["eta_sq_low"] <= effects["eta_sq_high"]).all()
    strong = effects.loc["complexity"]
    assert strong["eta_sq_low"] <= strong["eta_sq"] <= strong["eta_sq_high"]


def test_pearson_refuses_too_few_conditions_and_has_an_interval():
    df = synthetic()
    few = stats.pearson(df[df["launch_period"] <= 6.0], "flight_time", "energy_total", FACTORS)
    assert np.isnan(few["r"]) and few["reason"] == "2 conditions: r needs at least 3"
    full = stats.pearson(df, "flight_time", "energy_total", FACTORS, seed=1)
    assert full["reason"] is None
    assert full["r_low"] <= full["r"] <= full["r_high"]


@settings(max_examples=50, deadline=None)
@given(st.lists(st.floats(0.0, 1.0), min_size=1, max_size=12))
def test_holm_is_statsmodels_holm(p):
    from statsmodels.stats.multitest import multipletests

    from analysis.statistics_table import holm

    expected = multipletests(p, method="holm")[1]
    assert holm(p) == pytest.approx(expected)
    with_gap = holm([*p, float("nan")])
    assert np.isnan(with_gap[-1]) and with_gap[:-1] == pytest.approx(expected)


@pytest.mark.parametrize(("runs", "interval"), [(2, False), (4, False), (5, True)])
def test_eta_sq_gets_a_bootstrap_interval_only_from_five_runs_a_condition(runs, interval):
    rng = np.random.default_rng(7)
    df = pd.DataFrame(
        [{"a": a, "b": b, "y": 10.0 * a + b + rng.normal()} for a in range(3) for b in range(2)
         for _ in range(runs)]
    )  # fmt: skip
    result = stats.anova(df, "y", ["a", "b"], resamples=200)
    low, high = result.table.loc["a", "eta_sq_low"], result.table.loc["a", "eta_sq_high"]
    assert bool(np.isfinite(low) and low < result.table.loc["a", "eta_sq"] < high) is interval
    assert any("no bootstrap interval" in note for note in result.notes) is not interval
