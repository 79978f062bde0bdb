"""The ordering rule's p (abm.verdicts.spearman): a permutation p, exact up to 8 runs, so a
handful of tied runs (a 0/1 outcome at three levels of a factor) cannot decide an ordering
that the t approximation would call significant."""

from math import comb

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from abm import verdicts


def test_six_tied_runs_with_the_t_approximations_p_0_047_are_undecided():
    # Table 1's deadlocks without motion planning on 2 runs per k: True True / True False /
    # False False; scipy's t approximation gives p = 0.047, all 720 pairings give 0.2
    neighbours, deadlock = [0, 0, 1, 1, 2, 2], [1, 1, 1, 0, 0, 0]
    rho, p, exact = verdicts.spearman(neighbours, deadlock)
    assert exact and rho == pytest.approx(-0.8165, abs=1e-4) and p == pytest.approx(0.2)
    verdict = verdicts.rank_order(neighbours, deadlock, +1)
    assert verdict.holds is None and "p = 0.2" in verdict.ours


def test_five_untied_runs_in_order_have_the_exact_p_of_2_in_120():
    # only the order itself and its reverse are as extreme as rho = 1
    rho, p, exact = verdicts.spearman([1, 2, 3, 4, 5], [10, 20, 30, 40, 50])
    assert (rho, exact) == (pytest.approx(1.0), True) and p == pytest.approx(2 / 120)


def _tied(counts: tuple[int, ...]) -> np.ndarray:
    """A 0/1 outcome for 10 runs at each level: ``counts[i]`` ones at level i."""
    return np.concatenate([np.r_[np.ones(k), np.zeros(10 - k)] for k in counts])


def _hypergeometric_p(counts: tuple[int, ...]) -> float:
    """The exact two-sided p of a 0/1 outcome at three levels of 10 runs: rho depends only on
    how many ones each level holds, whose law under no correlation is multivariate
    hypergeometric (computed here without shuffling anything).
    """
    levels, ones = np.repeat([0, 1, 2], 10), sum(counts)
    observed = abs(verdicts.spearman(levels, _tied(counts))[0])
    p = 0.0
    for a in range(11):
        for b in range(11):
            c = ones - a - b
            if (
                0 <= c <= 10
                and abs(verdicts.spearman(levels, _tied((a, b, c)))[0]) >= observed - 1e-12
            ):
                p += comb(10, a) * comb(10, b) * comb(10, c) / comb(30, ones)
    return p


@pytest.mark.parametrize("counts", [(1, 2, 5), (3, 5, 8)])
def test_thirty_tied_runs_get_the_exact_p_within_the_shuffles_error(counts):
    # (1, 2, 5): the t approximation says 0.045, the exact p is 0.079: not an ordering
    levels = np.repeat([0, 1, 2], 10)
    _, p, exact = verdicts.spearman(levels, _tied(counts))
    truth = _hypergeometric_p(counts)
    assert not exact
    assert abs(p - truth) < 4 * np.sqrt(truth * (1 - truth) / verdicts.SHUFFLES)
    assert (p < verdicts.ALPHA) == (truth < verdicts.ALPHA)


def test_a_strong_ordering_over_many_runs_says_its_p_is_at_the_shuffles_floor():
    x = np.arange(300) % 3
    verdict = verdicts.rank_order(x, x + np.random.default_rng(0).normal(0, 1, 300), +1)
    assert verdict.holds is True and "p <= 0.0001" in verdict.ours


values = st.lists(st.integers(0, 4), min_size=3, max_size=40)


@given(values, st.data())
def test_the_p_is_seeded_and_blind_to_the_scale_and_the_sign_of_the_values(x, data):
    y = data.draw(st.lists(st.integers(0, 4), min_size=len(x), max_size=len(x)))
    if len(set(x)) < 2 or len(set(y)) < 2:
        return
    rho, p, _ = verdicts.spearman(x, y)
    assert 0.0 < p <= 1.0
    assert verdicts.spearman(x, y) == (rho, p, _)
    stretched = verdicts.spearman([3 * v + 1 for v in x], [v**3 for v in y])
    assert stretched[0] == pytest.approx(rho) and stretched[1] == pytest.approx(p)
    flipped = verdicts.spearman(x, [-v for v in y])
    assert flipped[0] == pytest.approx(-rho) and flipped[1] == pytest.approx(p)


def test_a_variable_of_one_value_has_no_rho():
    from abm.errors import ConfigError

    with pytest.raises(ConfigError, match="two values or more"):
        verdicts.spearman([1, 2, 3], [5, 5, 5])
