"""The claim tests of models/sugarmap/claims.py decide the report's verdicts: on made-up runs
they must say "holds" when the published effect is there and "does not hold" when it is
reversed, and stay silent (None) when the runs lack the claim's set-up."""

import numpy as np
import pandas as pd
import pytest
from scipy import stats as sps

from analysis.compare import compare_published, judge_claims, parameter_defaults
from models.sugarmap import SugarMapModel
from models.sugarmap.published import CLAIMS, PUBLISHED

#: Claim id -> its test, as the report runs it.
TESTS = {claim.id: claim.test for claim in CLAIMS if claim.test is not None}

CHECKPOINTS = (250, 500, 1000, 1500, 2000, 3000)
REFERENCE = {"arena": "open", "n_explorers": 4, "noise_scale": 1.0, "heading_model": "literal"}


def _runs(algorithm: str, level: float, n: int = 10, **setup) -> pd.DataFrame:
    """n runs whose coverage at every checkpoint is ``level`` x tau / 3000 plus noise."""
    rng = np.random.default_rng(int(level))  # fixed: the same made-up runs every time
    sugarmap = algorithm == "sugarmap"
    rows = []
    for _ in range(n):
        row = {
            **REFERENCE,
            "algorithm": algorithm,
            "n_anchors": 6 if sugarmap else 0,
            "n_particles": 10 if sugarmap else 0,
            "random_walk": "lattice" if algorithm == "random_walk" else None,
            **setup,
        }
        for tau in CHECKPOINTS:
            row[f"coverage_{tau}"] = min(100.0, level * tau / 3000 + rng.normal(0, 1))
        for target in (50, 80, 90):
            row[f"t{target}"] = 3000 * target / level if level > target else np.nan
        rows.append(row)
    return pd.DataFrame(rows)


def _verdict(claim: str, runs: pd.DataFrame):
    return TESTS[claim](runs, None)


@pytest.mark.parametrize(("sugarmap", "walk", "holds"), [(90, 40, True), (40, 90, False)])
def test_c01_follows_the_order_of_sugarmap_and_the_random_walk(sugarmap, walk, holds):
    runs = pd.concat([_runs("sugarmap", sugarmap), _runs("random_walk", walk)])
    assert _verdict("C01", runs).holds is holds


@pytest.mark.parametrize(("omstc", "holds"), [(300, True), (50, False)])
def test_c02_needs_omstc_at_least_as_fast_as_sugarmap(omstc, holds):
    runs = pd.concat([_runs("sugarmap", 90), _runs("omstc", omstc)])
    assert _verdict("C02", runs).holds is holds


@pytest.mark.parametrize(
    ("coverage", "jitter", "verdict"),
    [
        (85.0, 2.0, "holds"),
        (93.0, 2.0, "holds"),
        (60.0, 2.0, "does not hold"),
        (97.0, 1.0, "does not hold"),  # above the band: the one-sided ">= 75 %" passed it
        (76.0, 8.0, "undecided"),  # the interval crosses the band's lower edge
    ],
)
def test_c18_and_the_testbed_number_share_one_two_sided_band(coverage, jitter, verdict):
    rows = _runs("sugarmap", 90, arena="testbed", n_anchors=5, n_explorers=2)
    rows["coverage_180"] = coverage + np.linspace(-jitter, jitter, len(rows))
    rows["status"] = "ok"
    claim = next(c for c in CLAIMS if c.id == "C18")
    judged = judge_claims(rows, None, [claim], parameter_defaults(SugarMapModel))[0]
    published = compare_published(rows, PUBLISHED, parameter_defaults(SugarMapModel)).iloc[0]
    assert judged["verdict"] == published["verdict"] == verdict
    assert judged["rule"] == published["rule"] and "two-sided band 85 +- 10" in judged["rule"]


def test_c05_needs_the_ordering_test_not_only_a_positive_rho():
    # coverage rising weakly with the anchors: rho +0.24, one-sided p 0.045, two-sided 0.089
    runs = pd.concat([_runs("sugarmap", 90, n_anchors=a) for a in (2, 4, 6, 8, 10)],
                     ignore_index=True)  # fmt: skip
    noise = np.random.default_rng(4).normal(0, 6, len(runs))
    for tau in CHECKPOINTS:
        runs[f"coverage_{tau}"] = 40 + 0.5 * runs["n_anchors"] + noise + tau / 1000
    rho = sps.spearmanr(runs["n_anchors"], runs["coverage_1000"])
    assert 0.2 < rho.statistic < 0.3 and 0.05 < rho.pvalue < 0.1
    verdict = _verdict("C05", runs)
    assert verdict.holds is None and "p < 0.05" in verdict.rule
    for tau in CHECKPOINTS:  # a clear rise
        runs[f"coverage_{tau}"] = 40 + 5 * runs["n_anchors"] + noise / 3
    assert _verdict("C05", runs).holds is True


def test_c08_needs_coverage_rising_with_every_explorer():
    rising = pd.concat([_runs("sugarmap", 20 * n, n_explorers=n) for n in (1, 2, 4)])
    assert _verdict("C08", rising).holds
    falling = pd.concat([_runs("sugarmap", 100 - 20 * n, n_explorers=n) for n in (1, 2, 4)])
    assert not _verdict("C08", falling).holds


def test_a_claim_without_its_set_up_in_the_runs_gives_no_verdict():
    only_sugarmap = _runs("sugarmap", 90)
    for claim in ("C01", "C02", "C08", "C14", "C17", "C18"):
        assert _verdict(claim, only_sugarmap) is None


@pytest.mark.parametrize(("big", "small", "holds"), [(3.0, 2.0, True), (2.0, 3.0, False)])
def test_c22_needs_the_larger_advantage_in_the_larger_place(big, small, holds):
    parts = []
    for arena, ratio in (("open", big), ("open10", small)):
        for n, extra in ((2, 1.0), (4, 0.0)):  # fewer nodes: a larger advantage in both
            parts.append(_runs("sugarmap", 30 * (ratio + extra), arena=arena, n_explorers=n))
            parts.append(_runs("random_walk", 30, arena=arena, n_explorers=n))
    assert _verdict("C22", pd.concat(parts)).holds is holds


def test_c17_ignores_runs_of_other_arenas_that_stop_earlier():
    geometries = pd.concat(
        [_runs("sugarmap", level, arena=a) for a, level in (("circle", 85), ("ushape", 86),
                                                             ("serpentine", 160))]
    )  # fmt: skip
    short = _runs("sugarmap", 90, arena="open10")
    short[[f"coverage_{t}" for t in (1000, 1500, 2000, 3000)]] = np.nan  # stopped at 500 s
    alone, mixed = _verdict("C17", geometries), _verdict("C17", pd.concat([geometries, short]))
    assert alone.holds is False and mixed.ours == alone.ours


def test_c17_leaves_a_censored_t80_unjudged_and_judges_the_curves():
    geometries = pd.concat(
        [_runs("sugarmap", level, arena=a) for a, level in (("circle", 85), ("ushape", 86),
                                                             ("serpentine", 70))]
    )  # fmt: skip
    verdict = _verdict("C17", geometries)
    assert verdict.censored == pytest.approx(1 / 3) and "T80 censored" in verdict.why
    assert verdict.holds is False  # the serpentine's curve lies 15 points below the others'
