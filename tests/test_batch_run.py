"""mesa.batch_run drives BeaconExplorerModel unchanged (Mesa passes ``seed=`` per run)."""

import mesa
import pandas as pd

from models.beacon_explorer import BeaconExplorerModel


def _batch(**kwargs) -> pd.DataFrame:
    rows = mesa.batch_run(
        BeaconExplorerModel,
        parameters={
            "world": "corridor",
            "complexity": ["low", "high"],
            "time_limit": 60.0,
            "launch_period": 6.0,
        },  # fmt: skip
        number_processes=1,
        max_steps=20,
        display_progress=False,
        **kwargs,
    )
    return pd.DataFrame(rows)


def test_batch_run_gives_one_row_per_run_with_seed_and_reporters():
    df = _batch(rng=[1, 2])
    assert len(df) == 4
    assert sorted(df["seed"]) == [1, 1, 2, 2]
    assert {"ground", "explorer", "beacon", "coverage", "energy", "complexity"} <= set(df.columns)
    assert (df["Step"] == 20).all()
    assert (df[["ground", "explorer", "beacon"]].sum(axis=1) == 21).all()  # 20 robots + base


def test_batch_run_same_seed_same_rows():
    a = _batch(rng=[3]).drop(columns="RunId")
    b = _batch(rng=[3]).drop(columns="RunId")
    pd.testing.assert_frame_equal(a, b)


def test_step_counts_steps_and_time_is_its_own_column():
    """Stigmergy's step is 0.5 s: Step is still Mesa's step count, time the simulated seconds."""
    from models.stigmergy import StigmergyModel

    rows = mesa.batch_run(
        StigmergyModel,
        parameters={"time_limit": 60.0},
        number_processes=1,
        max_steps=6,
        data_collection_period=1,
        display_progress=False,
        rng=[1],
    )
    df = pd.DataFrame(rows)
    assert list(df["Step"]) == [1, 2, 3, 4, 5, 6]
    assert list(df["time"]) == [0.5, 1.0, 1.5, 2.0, 2.5, 3.0]
