"""Censored summary metrics: the Kaplan-Meier median and which runs a run's end cut short."""

import numpy as np
import pandas as pd
from hypothesis import given, settings
from hypothesis import strategies as st
from statsmodels.duration.survfunc import SurvfuncRight

from abm.published import Censored
from analysis.censoring import censored_mask, km_median, survival

times = st.lists(st.integers(1, 50).map(float), min_size=1, max_size=40)


@given(times)
def test_without_censoring_the_km_median_is_the_lower_sample_median(values):
    ordered = np.sort(values)
    expected = ordered[int(np.ceil(len(ordered) / 2)) - 1]
    assert km_median(values, [True] * len(values)) == expected


@settings(max_examples=60)
@given(times, st.data())
def test_the_km_median_agrees_with_statsmodels(values, data):
    observed = data.draw(st.lists(st.booleans(), min_size=len(values), max_size=len(values)))
    ours = km_median(values, observed)
    if not any(observed):
        assert ours is None
        return
    fit = SurvfuncRight(np.array(values), np.array(observed, dtype=float))
    below = fit.surv_times[fit.surv_prob <= 0.5 + 1e-12]
    assert ours == (float(below[0]) if len(below) else None)


def test_a_median_censored_runs_hide_is_not_reached():
    # 6 of 10 runs cut at 600 s: the survival never falls to one half
    values = [100, 200, 300, 400] + [600] * 6
    assert km_median(values, [True] * 4 + [False] * 6) is None


def test_runs_ended_by_the_time_limit_or_missing_a_bound_metric_are_censored():
    runs = pd.DataFrame(
        {
            "end_reason": ["time limit", "complete", "stalled: 3 explorers", "complete"],
            "coverage_time": [60.0, 40.0, 55.0, 30.0],
            "t50": [np.nan, 20.0, 25.0, np.nan],
            "time": [70.0, 50.0, 60.0, 90.0],
            "t_deploy": [10.0, 10.0, 10.0, 10.0],
        }
    )
    cut = Censored("coverage_time", ends=("time limit", "stalled"))
    assert list(censored_mask(runs, cut)) == [True, False, True, False]
    missing = Censored("t50", ends=(), bound="time", since="t_deploy")
    assert list(censored_mask(runs, missing)) == [True, False, False, True]
    result = survival(runs, missing)
    # the two censored runs count from their coverage clock's end: 60 and 80 s
    assert (result.runs, result.censored, result.bound) == (4, 2, 80.0)
    assert result.median == 25.0 and "2 of 4 runs censored" in result.text()


def test_the_causes_of_censoring_tell_a_time_limit_from_a_target_never_reached():
    # SugarMap's T80: a run that ends at its horizon without 80 % is censored by its own end,
    # and the report said "(time limit)" for it
    from abm.published import Censored
    from analysis.censoring import censoring_causes

    spec = Censored("t80", bound="time")
    ends = ["horizon", "horizon", "horizon", "time limit"]
    runs = pd.DataFrame({"t80": [900.0, np.nan, np.nan, np.nan],
                         "time": [3000.0, 3000.0, 3000.0, 1800.0], "end_reason": ends})  # fmt: skip
    assert (
        censoring_causes(runs, spec) == "1 ended by time limit; 2 never reached it before their end"
    )
    assert censoring_causes(runs.iloc[:3], spec) == "2 never reached it before their end"
