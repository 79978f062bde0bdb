"""The rules abm.verdicts adds for claims of several parts: a linear contrast of group means
(a difference of differences), a larger spread by the Brown-Forsythe test, and one verdict
for a claim whose every part must hold."""

import warnings

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from abm import verdicts
from abm.published import Verdict

samples = st.lists(st.integers(-5000, 5000).map(lambda v: v / 100), min_size=2, max_size=12)


@given(samples, samples, st.sampled_from([-1, 1]))
def test_a_contrast_of_two_groups_is_the_welch_difference(before, after, sign):
    two = verdicts.contrast([before, after], (-1, 1), sign, "after - before")
    welch = verdicts.difference(before, after, sign)
    assert two.holds is welch.holds
    assert two.low == pytest.approx(welch.low, abs=1e-9)
    assert two.high == pytest.approx(welch.high, abs=1e-9)


def test_a_difference_of_differences_needs_its_interval_to_exclude_zero():
    spread = np.linspace(-1.0, 1.0, 8)
    gains = [40 + spread, 60 + spread, 80 + spread, 82 + spread]  # gains 20 then 2
    assert verdicts.contrast(gains, (-1, 1, 1, -1), +1, "gain").holds is True
    noisy = [40 + 30 * spread, 43 + 30 * spread, 80 + 30 * spread, 82 + 30 * spread]
    verdict = verdicts.contrast(noisy, (-1, 1, 1, -1), +1, "gain")
    assert verdict.holds is None and verdict.low < 0 < verdict.high


def test_a_larger_spread_is_judged_by_the_brown_forsythe_p():
    spread = np.linspace(-1.0, 1.0, 10)
    assert verdicts.spread(spread, 10 * spread).holds is True
    assert verdicts.spread(10 * spread, spread).holds is False
    alike = verdicts.spread(spread, 1.2 * spread[::-1])
    assert alike.holds is None and "p = " in alike.why


@given(st.lists(st.sampled_from([True, False, None]), min_size=1, max_size=5))
def test_a_claim_of_several_parts_holds_only_when_every_part_holds(parts):
    judged = verdicts.combine([Verdict("", h, "", f"rule {i}") for i, h in enumerate(parts)],
                              "ours", 10)  # fmt: skip
    if False in parts:
        assert judged.holds is False
    elif None in parts:
        assert judged.holds is None
    else:
        assert judged.holds is True
    assert all(f"rule {i}" in judged.rule for i in range(len(parts)))


def test_agreement_holds_on_one_level_fails_on_a_shift_and_corrects_for_many_checkpoints():
    rng = np.random.default_rng(11)
    same = {f"{t} s": [rng.normal(50, 3, 10) for _ in range(3)] for t in range(20)}
    assert verdicts.agreement(same, "arms").holds is True  # 20 checkpoints: Holm keeps it
    shifted = {"1 s": [rng.normal(50, 3, 10), rng.normal(50, 3, 10), rng.normal(60, 3, 10)]}
    verdict = verdicts.agreement(shifted, "arms")
    assert verdict.holds is False and verdict.low > 0
    assert verdicts.agreement({"1 s": [np.ones(5), np.ones(5)]}, "arms").holds is True
    assert verdicts.agreement({"1 s": [np.ones(1), np.ones(5)]}, "arms").holds is None


def test_coefficient_judges_the_papers_value_and_refuses_collinear_regressors():
    x = np.repeat(np.arange(1.0, 6.0), 4)
    y = 2 * x + np.resize([-0.1, 0.1, -0.05, 0.05], len(x))
    assert verdicts.coefficient(y, {"x": x}, "x", 2.0).holds is True
    verdict = verdicts.coefficient(y, {"x": x}, "x", 1.0)
    assert verdict.holds is False and "differs" in verdict.why
    collinear = verdicts.coefficient(y, {"x": x, "twice x": 2 * x}, "x", 2.0)
    assert collinear.holds is None and "collinear" in collinear.why


def test_no_difference_from_too_few_runs_is_undecided_not_holding():
    rng = np.random.default_rng(3)
    few = {"1 s": [rng.normal(50, 3, 3), rng.normal(50, 3, 3)]}
    assert verdicts.agreement(few, "arms").holds is None
    enough = {"1 s": [rng.normal(50, 3, 5), rng.normal(50, 3, 5)]}
    assert verdicts.agreement(enough, "arms").holds is True
    assert verdicts.level(0.3, -5.0, 5.0, 3, 0.0).holds is None  # inside, but 3 runs
    assert verdicts.level(0.3, -5.0, 5.0, 5, 0.0).holds is True
    assert verdicts.level(9.0, 8.0, 10.0, 3, 0.0).holds is False  # a difference still fails


@given(samples, samples, st.sampled_from([-1, 1]))
def test_every_rule_gives_a_reason_and_no_warning_on_any_sample_even_a_constant_one(a, b, sign):
    pairs = min(len(a), len(b))
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a nan statistic from constant data warns first
        judged = [
            verdicts.difference(a, b, sign),
            verdicts.contrast([a, b], (-1, 1), sign, "b - a"),
            verdicts.spread(a, b),
            verdicts.rank_order(range(len(a)), a, sign),
            verdicts.correlation(a[:pairs], b[:pairs], sign, 10),
            verdicts.band(a, 1.0),
        ]
    for verdict in judged:
        assert "nan" not in verdict.ours + verdict.why
        assert verdict.holds is not None or verdict.why


def test_constant_runs_give_no_interval_test_or_p_value():
    same = [5.0] * 10
    flat = verdicts.band(same, 4.0)
    assert flat.holds is None and "no width" in flat.why  # a t-interval of [5, 5] judges nothing
    assert verdicts.band(same, 4.0, spread=2.0).holds is True  # a band is judged run by run
    assert verdicts.band(same, 8.0, spread=2.0).holds is False
    fixed = verdicts.difference([3.0] * 5, same, +1)
    assert fixed.holds is True and "p =" not in fixed.ours and "no spread" in fixed.ours
    assert verdicts.difference(same, same, +1).holds is None
    assert verdicts.spread(same, [1.0] * 5).holds is None
    ordering = verdicts.rank_order([1, 2, 3, 4, 5], [7.0] * 5, +1)
    assert ordering.holds is None and "every run" in ordering.why
    assert verdicts.correlation([1, 2, 3, 4], [5.0] * 4, +1, 8).holds is None
    x = np.repeat(np.arange(1.0, 6.0), 4)
    exact = verdicts.coefficient(2 * x, {"x": x}, "x", 1.0)  # no residual: no interval
    assert exact.holds is None and "no residual" in exact.why


def test_a_pooled_share_the_same_in_every_run_falls_back_to_wilson_over_the_events():
    none = verdicts.pooled_share([0] * 10, [30] * 10, 80.0)
    assert none.holds is False and "Wilson over the 300 events" in none.ours
    assert none.high == pytest.approx(100 * verdicts._wilson(0.0, 300)[1])
    assert verdicts.pooled_share([0] * 10, [30] * 10, 0.5).holds is True
