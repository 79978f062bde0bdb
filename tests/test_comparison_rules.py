"""The verdict rules of abm.verdicts: a two-sided band for a level, an interval that excludes
zero for a direction, a test with its p for an ordering."""

import numpy as np
import pandas as pd
import pytest
from hypothesis import given
from hypothesis import strategies as st

from abm import verdicts
from abm.errors import ConfigError
from abm.published import Published

levels = st.floats(0.0, 100.0, allow_nan=False)


@given(levels, levels, st.floats(0.5, 20.0))
def test_a_band_is_two_sided(ours, paper, spread):
    values = ours + np.array([-0.1, 0.0, 0.1])
    verdict = verdicts.band(values, paper, spread)
    low, high = verdict.low, verdict.high
    if paper - spread <= low and high <= paper + spread:
        assert verdict.holds is True
    elif high < paper - spread or low > paper + spread:
        assert verdict.holds is False
        assert "differs from the published" in verdict.why
    else:
        assert verdict.holds is None
    # a level far above the band fails as surely as one far below it
    above = verdicts.band(paper + spread + 5 + values - ours, paper, spread)
    below = verdicts.band(paper - spread - 5 + values - ours, paper, spread)
    assert above.holds is False and below.holds is False


def test_without_a_spread_the_papers_value_must_lie_in_our_interval():
    values = np.array([70.0, 74.0, 78.0, 72.0, 76.0])
    assert verdicts.band(values, 74.0).holds is True
    far = verdicts.band(values, 96.8)
    assert far.holds is False and "by -22.8" in far.why


@given(st.floats(-50, 50), st.sampled_from([-1, 1]))
def test_a_direction_holds_only_when_the_interval_excludes_zero_on_its_side(shift, sign):
    noise = np.array([-1.0, 0.0, 1.0, 0.5, -0.5])
    verdict = verdicts.difference(noise, noise + shift, sign)
    if verdict.low > 0 or verdict.high < 0:
        assert verdict.holds is bool(np.sign(verdict.mean) == sign)
        assert verdict.holds or verdict.why == "the interval excludes 0 on the other side"
    else:
        assert verdict.holds is None and verdict.why == "the interval includes 0"


def test_an_ordering_needs_p_below_0_05():
    anchors = np.repeat([2, 4, 6, 8, 10], 4)
    rising = verdicts.rank_order(anchors, anchors * 2.0, +1)
    assert rising.holds is True and "p < 0.05" in rising.rule
    assert verdicts.rank_order(anchors, -anchors * 2.0, +1).holds is False
    flat = verdicts.rank_order(anchors, np.tile([1.0, 3.0, 2.0, 0.0], 5), +1)
    assert flat.holds is None


def test_a_pooled_share_treats_runs_as_clusters():
    hits, totals = np.array([70, 80, 72, 78]), np.full(4, 100)
    verdict = verdicts.pooled_share(hits, totals, 96.8)
    assert verdict.mean == pytest.approx(75.0) and verdict.holds is False
    assert verdict.low < 75.0 < verdict.high and verdict.runs == 4


def test_a_claim_built_from_a_level_record_uses_its_band():
    record = Published("s", "q", {"arena": "a"}, 85.0, "level", "m", "band", spread=10.0)
    runs = pd.DataFrame({"arena": ["a"] * 5 + ["b"] * 5, "m": [96.0] * 5 + [85.0] * 5})
    verdict = verdicts.level_test(record)(runs, None)
    assert verdict.holds is False and verdict.runs == 5  # only the arena-a runs
    with pytest.raises(ConfigError, match="'band' level"):
        verdicts.level_test(Published("s", "q", {}, 1.0, "ordering", "m", "rises"))


def test_records_declare_their_kind_and_measure():
    with pytest.raises(ConfigError, match="kind must be one of"):
        Published("s", "q", {}, 1.0, "change", "m", "same sign")
    with pytest.raises(ConfigError, match="measure of a 'direction' record"):
        Published("s", "q", {}, 1.0, "direction", "m", "same sign", factor="f")
    with pytest.raises(ConfigError, match="why it has no verdict"):
        Published("s", "q", {}, 1.0, "level", "m", "shown")


def test_a_share_of_none_or_all_has_an_exact_wilson_bound():
    """A share of 0 printed its Wilson lower bound as 1.7e-16; the bound is exactly 0 (1)."""
    from abm.verdicts import interval

    for n in range(2, 300, 7):
        assert interval([0.0] * n, share=True)[1] == 0.0
        assert interval([1.0] * n, share=True)[2] == 1.0
