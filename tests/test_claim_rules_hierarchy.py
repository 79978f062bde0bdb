"""The hierarchy's claims C1, C2, C4, C6, C7 and C14 are judged by a stated rule with an
interval or a test: on made-up runs each holds when the effect is clear, does not hold when it
is reversed, and is undecided when the runs' spread leaves it within noise (the former rules
on condition means, a minimum or a ratio decided those runs)."""

import numpy as np
import pandas as pd
import pytest

from models.hierarchy.claims import TESTS

#: Configurations (W workers, S scouts per worker): N = 1 + W + W S robots.
GRID = [(w, s) for w in (2, 3, 4, 5) for s in (1, 2, 3, 4)]
#: Per-run offsets within a configuration (4 runs): mean 0.
OFFSETS = np.array([-1.0, -0.33, 0.33, 1.0])


def _runs(column: str, level, jitter: float, **fixed) -> pd.DataFrame:
    """Four runs per configuration; ``column`` is level(N) plus jitter x a standard normal
    (fixed seed: the same made-up runs every time)."""
    rng = np.random.default_rng(5)
    rows = []
    for w, s in GRID:
        n = 1 + w + w * s
        for _ in OFFSETS:
            rows.append({
                "W": w, "S": s, "N": n, "topology": "hst", "wave_generator": True,
                "scout_scan_area": 100.0 / n, "worker_scan_area": 50.0 / n,
                "scout_drive": 100.0 / n, "worker_drive": 20.0 / n**0.1,
                "end_reason": "complete", "complete": True, "known_free_fraction": 1.0,
                "completion_time": 1000.0,
                **fixed, column: level(n) + jitter * rng.standard_normal(),
            })  # fmt: skip
    return pd.DataFrame(rows)


@pytest.mark.parametrize(
    ("mean", "jitter", "holds"), [(0.9999, 0.0001, True), (0.99, 0.001, False),
                                  (0.999, 0.002, None)]
)  # fmt: skip
def test_c1_judges_the_mean_share_known_against_a_band_not_the_minimum(mean, jitter, holds):
    runs = _runs("known_free_fraction", lambda n: mean, jitter)
    verdict = TESTS["C1"](runs, None)
    assert verdict.holds is holds and "two-sided band 100 +- 0.1" in verdict.rule
    # "for every configuration": the value says over how many of the report's 42
    configs = len(runs.groupby(["W", "S"]))
    assert f"over {configs} configurations (W, S) of the report's 42" in verdict.ours


@pytest.mark.parametrize("claim", ["C2", "C6", "C9"])
@pytest.mark.parametrize(("slope", "jitter", "holds"), [(-1.0, 1.0, True), (1.0, 1.0, False),
                                                        (-0.05, 30.0, None)])  # fmt: skip
def test_c2_c6_c9_the_fall_with_n_is_an_ordering_over_the_runs_with_its_p(
    claim, slope, jitter, holds
):
    metric = {"C2": "scout_scan_area", "C6": "scout_drive", "C9": "completion_time"}[claim]
    verdict = TESTS[claim](_runs(metric, lambda n: 100 + slope * n, jitter), None)
    assert verdict.holds is holds and "Spearman" in verdict.rule


@pytest.mark.parametrize(("scatter", "holds"), [(1.0, True), (0.1, None), (0.005, False)])
def test_c4_the_workers_more_sporadic_curve_needs_a_spread_test(scatter, holds):
    # the means fall with N and wander about their trend: workers by scatter, scouts by 0.1
    runs = _runs("worker_scan_area", lambda n: 50.0 / n * np.exp(scatter * np.sin(1.3 * n)), 0.0)
    runs["scout_scan_area"] = 100.0 / runs["N"] * np.exp(0.1 * np.sin(runs["N"]))
    verdict = TESTS["C4"](runs, None)
    assert verdict.holds is holds and "Brown-Forsythe" in verdict.rule
    runs["worker_scan_area"] = 50.0 * runs["N"] * np.exp(np.sin(1.3 * runs["N"]))  # rises
    assert TESTS["C4"](runs, None).holds is False


@pytest.mark.parametrize(("power", "jitter", "holds"), [(0.1, 0.2, True), (1.5, 0.2, False),
                                                        (0.9, 40.0, None)])  # fmt: skip
def test_c7_the_slighter_fall_of_level_1_is_a_difference_of_slopes(power, jitter, holds):
    runs = _runs("worker_drive", lambda n: 100.0 / n**power, 0.0)
    runs["worker_drive"] *= np.exp(jitter / 100 * np.tile(OFFSETS, len(GRID)))
    runs["scout_drive"] = (
        100.0 / runs["N"] * np.exp(jitter / 100 * np.tile(OFFSETS[::-1], len(GRID)))
    )
    verdict = TESTS["C7"](runs, None)
    assert verdict.holds is holds and verdict.low is not None


@pytest.mark.parametrize(("flat", "jitter", "holds"), [(500.0, 10.0, True), (50.0, 10.0, False),
                                                       (105.0, 50.0, None)])  # fmt: skip
def test_c14_hst_sends_fewer_by_the_welch_interval_at_every_size(flat, jitter, holds):
    rows = []
    for w, s in ((2, 2), (2, 4), (4, 4)):
        for topology, level in (("hst", 100.0), ("fc", flat), ("ring", flat)):
            for offset in OFFSETS:
                rows.append(
                    {
                        "W": w,
                        "S": s,
                        "N": 1 + w + w * s,
                        "topology": topology,
                        "scout_scan_area": 1.0,
                        "messages_task": level + jitter * offset,
                    }
                )
    verdict = TESTS["C14"](pd.DataFrame(rows), None)
    assert verdict.holds is holds and "Welch 95 % interval" in verdict.rule


@pytest.mark.parametrize(("per_worker", "jitter", "holds"), [(0.0, 0.05, True),
                                                             (0.1, 0.05, False)])  # fmt: skip
def test_c3_no_effect_of_w_is_the_level_rule_on_its_coefficient(per_worker, jitter, holds):
    runs = _runs("scout_scan_area", lambda n: 100.0 / n, 0.0)
    runs["scout_scan_area"] *= np.exp(
        per_worker * runs["W"] + jitter * np.resize(OFFSETS, len(runs))
    )
    verdict = TESTS["C3"](runs, None)
    assert verdict.holds is holds and "0 inside" in verdict.rule


@pytest.mark.parametrize(("increase", "jitter", "holds"), [
    (0.0, 1.0, True), (6.0, 1.0, False), (2.0, 0.1, False), (1.0, 20.0, True)])  # fmt: skip
def test_c8_almost_no_increase_is_the_level_rule_on_the_difference(increase, jitter, holds):
    # an increase of 2 of 11 passed the former ratio threshold (1.18 <= 1.25)
    rows = []
    for w in (2, 7):
        for s in (2, 4):
            for offset in OFFSETS:
                rows.append(
                    {
                        "W": w,
                        "S": s,
                        "N": 1 + w + w * s,
                        "topology": "hst",
                        "wave_generator": True,
                        "scout_scan_area": 1.0,
                        "queen_iterations": 11 + (w == 7) * increase + jitter * offset,
                    }
                )
    verdict = TESTS["C8"](pd.DataFrame(rows), None)
    assert verdict.holds is holds and "W=7 - W=2" in verdict.rule


@pytest.mark.parametrize(("with_waves", "without", "holds"), [
    (0, 5, True), (2, 5, False), (2, None, False), (0, 0, None), (0, None, None)])  # fmt: skip
def test_c12_safe_motion_needs_no_event_with_waves_and_a_control_that_shows_some(
    with_waves, without, holds
):
    rows = []
    for waves, events in ((True, with_waves), (False, without)):
        for _ in range(4 if events is not None else 0):  # None: no control runs
            rows.append(
                {
                    "W": 2,
                    "S": 4,
                    "N": 11,
                    "wave_generator": waves,
                    "scout_scan_area": 1.0,
                    "wave_order_violations": events,
                    "robot_proximity_events": events,
                    "sibling_proximity_events": 0,
                    "robot_collisions": 0,
                }
            )
    assert TESTS["C12"](pd.DataFrame(rows), None).holds is holds


def test_c8_no_increase_from_three_runs_per_arm_is_undecided():
    rows = [{"W": w, "S": 4, "N": 1 + w + 4 * w, "topology": "hst", "wave_generator": True,
             "scout_scan_area": 1.0, "queen_iterations": 11 + (w == 7) * 4 + offset}
            for w in (2, 7) for offset in (-5.0, 0.0, 5.0)]  # fmt: skip
    assert TESTS["C8"](pd.DataFrame(rows), None).holds is None


@pytest.mark.parametrize(("together", "staggered", "holds"), [(0, 3, True), (3, 0, False)])
def test_c12_judges_the_reports_transits_and_shows_staggered_ones_apart(together, staggered, holds):
    rows = [
        {"W": 2, "S": 4, "N": 11, "wave_generator": waves, "subtree_transits": transits,
         "scout_scan_area": 1.0, "completion_time": 1000.0 + 500.0 * (transits == "staggered"),
         "wave_order_violations": events, "robot_proximity_events": events,
         "sibling_proximity_events": 0, "robot_collisions": 2 * events}
        for waves, transits, events in ((True, "together", together), (False, "together", 5),
                                        (True, "staggered", staggered))
        for _ in range(4)
    ]  # fmt: skip
    verdict = TESTS["C12"](pd.DataFrame(rows), None)
    assert verdict.holds is holds and verdict.runs == 4
    assert f"staggered by the queen (ours, not judged; 4 runs): {staggered:.1f} wave-order" in (
        verdict.ours
    )
    assert "completion 1,500 s against 1,000 s" in verdict.ours


def test_the_other_claims_leave_out_staggered_runs():
    rows = [{"W": w, "S": 4, "N": 1 + w + 4 * w, "topology": "hst", "wave_generator": True,
             "subtree_transits": transits, "scout_scan_area": 1.0,
             "queen_iterations": 11 + (w == 7) * 30 * (transits == "staggered") + offset}
            for w in (2, 7) for offset in (-0.5, 0.0, 0.5) for _ in range(4)
            for transits in ("together", "staggered")]  # fmt: skip
    verdict = TESTS["C8"](pd.DataFrame(rows), None)
    assert verdict.holds is True and verdict.runs == 24
