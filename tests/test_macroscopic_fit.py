"""Rates fitted from the log recover the known rates of a test model (analysis.macroscopic)."""

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from rates_model import RatesModel

from abm.errors import ConfigError
from analysis.macroscopic import collect_runs, exposure_table, fit_hazard, fit_rates

#: Two-sided 99.9 % normal quantile: three coefficients per example, four examples, so a
#: correct estimator fails the recovery test with probability about 1 % (Bonferroni).
Z999 = 3.2905
Z99 = 2.5758  # two-sided 99 % normal quantile


def _pooled(logs):
    return pd.concat([exposure_table(log, 5.0) for log in logs], ignore_index=True)


@settings(max_examples=4, deadline=None, derandomize=True)
@given(
    rate_ab=st.floats(0.02, 0.1),
    contact=st.floats(0.001, 0.004),
    seed=st.integers(0, 10_000),
)
def test_fit_recovers_constant_and_mass_action_rates_within_their_intervals(rate_ab, contact, seed):
    """A -> B at rate_ab and B -> C at contact * n_A: the Poisson GLMs with robot-time as
    exposure put the true coefficients inside their 99.9 % intervals."""
    params = {"rate_ab": rate_ab, "contact": contact}
    logs = collect_runs(RatesModel, range(seed, seed + 6), params)
    rows = _pooled(logs)
    horizon = max(log.end for log in logs)
    ab = fit_hazard(rows[rows["state"] == "A"], "A", "B", "constant", horizon)
    assert abs(ab.params[0] - np.log(rate_ab)) <= Z999 * ab.bse[0]
    bc = fit_hazard(rows[rows["state"] == "B"], "B", "C", "counts:A", horizon)
    truth = np.array([np.log(contact), 1.0])
    assert np.all(np.abs(bc.params - truth) <= Z999 * bc.bse), (bc.params, bc.bse, truth)


def test_held_out_likelihood_chooses_the_count_dependent_family():
    """B -> C depends on the count of A: held-out likelihood picks counts:A over constant,
    time, piecewise and the other count; the interval of its exponent holds 1."""
    logs = collect_runs(RatesModel, range(100, 108))
    model = fit_rates(logs)
    chosen = {(h.source, h.target): h for h in model.hazards}
    assert set(chosen) == {("A", "B"), ("B", "C")}
    bc = chosen[("B", "C")]
    assert bc.family == "counts:A"
    assert abs(bc.params[1] - 1.0) <= Z99 * bc.bse[1]
    table = model.table()
    assert {"estimate", "se", "low", "high"} <= set(table.columns)


def test_fit_needs_two_runs_and_a_known_launch_mode():
    logs = collect_runs(RatesModel, [1, 2])
    with pytest.raises(ConfigError, match="at least 2 runs"):
        fit_rates(logs[:1])
    with pytest.raises(ConfigError, match="launches must be one of"):
        fit_rates(logs, launches="sometimes")
    with pytest.raises(ConfigError, match="bin_width must be in"):
        fit_rates(logs, bin_width=-1.0)
