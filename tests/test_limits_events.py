"""Memory per event is bounded: a crowded run keeps at most ``collision_rows`` collision rows
in its event log (counting every collision all the same), and says where the rows stop.
"""

import tracemalloc

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from abm.clock import Clock
from abm.errors import ConfigError
from abm.params import COLLISION_ROWS
from abm.record import Recorder
from models.beacon_explorer import BeaconExplorerModel

#: A small crowded run: 40 robots launched every 0.5 s into a 5 x 5 cell room (2,137
#: robot-robot contacts in 40 s with seed 11).
CROWD = {"world": "open", "complexity": "low", "n_robots": 40, "launch_period": 0.5,
         "time_limit": 40.0}  # fmt: skip


@pytest.fixture(scope="module")
def every_row():
    return BeaconExplorerModel(seed=11, collision_rows=None, **CROWD).run()


def test_a_crowded_run_keeps_bounded_collision_rows_and_the_right_count(every_row):
    capped = BeaconExplorerModel(seed=11, collision_rows=10, **CROWD).run()
    events, all_events = capped.events(), every_row.events()
    assert (all_events.event == "collision").sum() > 1000
    assert (events.event == "collision").sum() == 10
    assert capped.summary() == every_row.summary()
    assert capped.collisions == every_row.collisions == 2 * (all_events.event == "collision").sum()
    marker = events[events.event == "rows_capped"]
    assert len(marker) == 1 and marker.kind.iloc[0] == "collision" and marker.limit.iloc[0] == 10
    eleventh = all_events[all_events.event == "collision"].time.iloc[10]
    assert marker.time.iloc[0] == eleventh
    assert capped.recorder.dropped == {"collision": (all_events.event == "collision").sum() - 10}
    others = ~all_events.event.isin(["collision", "rows_capped"])
    kept = ~events.event.isin(["collision", "rows_capped"])
    same_columns = events.loc[kept, list(all_events.columns)].reset_index(drop=True)
    assert same_columns.equals(all_events[others].reset_index(drop=True))


def test_collision_rows_zero_logs_none_and_the_default_keeps_today_s_logs(every_row):
    none = BeaconExplorerModel(seed=11, collision_rows=0, **CROWD).run()
    assert not (none.events().event == "collision").any()
    assert none.collisions == every_row.collisions
    default = BeaconExplorerModel(seed=11, **CROWD).run()
    assert default.params.collision_rows == COLLISION_ROWS
    assert default.events().equals(every_row.events())  # fewer than the default's rows


@pytest.mark.parametrize("value", [-1, 2.5, "many"])
def test_a_bad_collision_rows_is_refused_naming_it(value):
    with pytest.raises(ConfigError, match="collision_rows must be"):
        BeaconExplorerModel(seed=1, collision_rows=value)


@settings(max_examples=60, deadline=None)
@given(
    limit=st.one_of(st.none(), st.integers(0, 20)),
    kinds=st.lists(st.sampled_from(["collision", "launch", "attach"]), max_size=60),
)
def test_the_recorder_keeps_at_most_the_limit_and_counts_the_rest(limit, kinds):
    recorder = Recorder(Clock(), ("a",), row_limits={"collision": limit})
    for kind in kinds:
        recorder.log(kind, 1)
    events = recorder.events()
    logged = list(events.event) if len(events) else []
    n = kinds.count("collision")
    kept = n if limit is None else min(n, limit)
    assert logged.count("collision") == kept
    assert recorder.dropped.get("collision", 0) == n - kept
    assert logged.count("rows_capped") == (n > kept)
    assert [k for k in logged if k not in ("collision", "rows_capped")] == [
        k for k in kinds if k != "collision"
    ]


@settings(max_examples=60, deadline=None)
@given(
    steps=st.lists(
        st.tuples(
            st.integers(0, 5),  # robots in the sample (ids 0..n-1, or shuffled)
            st.booleans(),  # shuffle the order of the robots
            st.lists(st.integers(0, 4), max_size=3),  # rows that move
            st.lists(st.integers(0, 4), max_size=3),  # rows that change state or link
        ),
        max_size=12,
    )
)
def test_the_trace_keeps_changes_and_gives_back_every_sample(steps):
    """Samples are stored as the rows that changed; positions() returns every row of every
    sample, as given (a beacon hanging still for 30,000 samples costs one row, not 30,000).
    """
    recorder = Recorder(Clock(), ("a", "b"))
    rng = np.random.default_rng(len(steps))
    expected = []
    xy = rng.uniform(0, 10, (5, 2))
    states = ["a"] * 5
    comm = [False] * 5
    for t, (n, shuffle, moved, flipped) in enumerate(steps):
        for row in moved:
            xy[row] = rng.uniform(0, 10, 2)
        for row in flipped:
            states[row] = "b" if states[row] == "a" else "a"
            comm[row] = not comm[row]
        order = rng.permutation(n) if shuffle else np.arange(n)
        recorder.env._now = float(t)
        recorder.snapshot(order, xy[order], [states[k] for k in order], [comm[k] for k in order])
        expected += [(float(t), int(k), *xy[k], states[k], comm[k]) for k in order]
    got = recorder.positions()
    assert list(got.columns) == ["time", "robot", "x", "y", "state", "comm"]
    assert list(got.itertuples(index=False, name=None)) == expected


def test_still_robots_cost_the_trace_nothing_per_sample():
    """500 robots hanging still for 2,000 samples: the trace grows by the samples, not by
    500 rows each (kept whole, they took about 40 MB).
    """
    recorder = Recorder(Clock(), ("a",))
    robots = np.arange(500)
    xy = np.random.default_rng(1).uniform(0, 10, (500, 2))
    tracemalloc.start()
    before = tracemalloc.get_traced_memory()[0]
    for t in range(2000):
        recorder.env._now = float(t)
        recorder.snapshot(robots, xy, ["a"] * 500, np.zeros(500, dtype=bool))
    grown = tracemalloc.get_traced_memory()[0] - before
    tracemalloc.stop()
    assert grown < 4e6
    assert len(recorder.positions()) == 500 * 2000
