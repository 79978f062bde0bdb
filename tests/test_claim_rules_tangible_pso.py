"""Tangible PSO's C5 ("the best swarm splits into two groups", read as at least half the runs)
is judged by the Wilson 95 % interval of the share of runs that split, not the bare share: a
share just above one half from few runs is undecided."""

import pandas as pd
import pytest

from models.tangible_pso.claims import TESTS


@pytest.mark.parametrize(
    ("split", "runs", "holds"),
    [(70, 100, True), (30, 100, False), (11, 20, None), (10, 20, None)],
)
def test_c5_the_share_of_split_runs_is_judged_by_its_wilson_interval(split, runs, holds):
    rows = pd.DataFrame({"scenario": "open", "n_mavs": 6, "neighbours": 2,
                         "groups": [2] * split + [1] * (runs - split),
                         "best_iteration": 10})  # fmt: skip
    verdict = TESTS["C5"](rows, None)
    assert verdict.holds is holds and "Wilson 95 % interval" in verdict.rule
    assert verdict.low <= 100 * split / runs <= verdict.high
