"""The published effects of the inter-launch period (Stirling et al. 2010, Sect. 4), over 30
seeds per condition: the direction of each, and at least a quarter of its published size.

The paper's numbers come from the model's published.py (high-complexity corridors, 24 s vs
6 s; hovering vs attached beacons in mixed worlds). What this suite measured last is printed
with ``pytest -s``; the full-size reproduction (100 trials per condition) is in the README.
"""

from functools import partial

import pandas as pd
import pytest

from abm.pools import process_pool
from analysis.runner import run_model
from models.beacon_explorer.published import CORRIDOR_24_VS_6, HOVER_RATIO

#: Statistical checks over 80 beacon/explorer runs: the full tier (`make test-all`).
pytestmark = pytest.mark.slow

SEEDS = range(1, 31)


def summary(kwargs: dict) -> dict:
    """The run's parameters beside its summary (a summary holds no parameter copies)."""
    params = {"trace_interval": None, **kwargs}
    seed = params.pop("seed")
    return {**kwargs, **run_model("beacon-explorer", params, seed).summary}


def run_many(jobs: list[dict]) -> pd.DataFrame:
    with process_pool(2) as pool:
        return pd.DataFrame(list(pool.map(partial(summary), jobs, chunksize=3)))


@pytest.fixture(scope="module")
def periods() -> pd.DataFrame:
    jobs = [
        {"world": "corridor", "complexity": "high", "launch_period": p, "seed": s}
        for p in (6.0, 24.0)
        for s in SEEDS
    ]
    return run_many(jobs)


def change(runs: pd.DataFrame, metric: str) -> float:
    means = runs.groupby("launch_period")[metric].mean()
    return 100.0 * (means[24.0] / means[6.0] - 1.0)


@pytest.mark.parametrize("metric", sorted(CORRIDOR_24_VS_6))
def test_a_longer_period_changes_each_metric_as_published(periods, metric):
    """Flight time, collisions and energy fall, coverage time rises (24 s vs 6 s)."""
    paper = CORRIDOR_24_VS_6[metric]
    ours = change(periods, metric)
    print(f"{metric}: ours {ours:+.1f} %, paper {paper:+.1f} %")
    assert ours * paper > 0, (metric, ours, paper)  # the same direction
    assert abs(ours) > abs(paper) / 4, (metric, ours, paper)  # and a size of the same order


def test_every_run_ends_by_itself(periods):
    # no run may need the time limit: pile-ups of explorers once did
    assert (periods["end_reason"] != "time limit").all()
    assert len(periods) == 2 * len(SEEDS)


def test_hovering_beacons_cost_about_the_published_factor():
    jobs = [
        {"world": "mixed", "launch_period": 6.0, "seed": s, "hover_beacons": h}
        for h in (False, True)
        for s in range(1, 11)
    ]
    energy = run_many(jobs).groupby("hover_beacons")["energy_total"].mean()
    ratio = energy[True] / energy[False]
    print(f"hover / attached energy: ours {ratio:.2f}x, paper {HOVER_RATIO}x")
    assert HOVER_RATIO / 1.5 < ratio < HOVER_RATIO * 1.5
