"""From the event log to the state machine (analysis.macroscopic.logs, .graph, .design)."""

import numpy as np
import pandas as pd
import pytest
from rates_model import RatesModel

from abm.errors import ConfigError
from analysis.macroscopic import (
    LAUNCH,
    REMOVED,
    RunLog,
    check_states,
    collect_runs,
    exposure_table,
    sinks,
    sources,
    state_graph,
    transitions,
)


def _log(rows, end=10.0, states=("A", "B", "C")) -> RunLog:
    changes = pd.DataFrame(rows, columns=["time", "robot", "state", "launch"])
    return RunLog(run=0, states=states, changes=changes, end=end)


def test_a_one_state_model_is_refused_with_what_to_count_instead():
    with pytest.raises(ConfigError, match="1 state .flying.*count something that changes"):
        collect_runs("flocking", [1])
    with pytest.raises(ConfigError, match="needs robots that change state"):
        check_states(("flying",), "FlockingModel")


def test_changes_at_one_instant_merge_and_launches_and_removals_are_kept():
    log = _log(
        [
            (0.0, 1, "A", False),
            (2.0, 1, "B", False),  # B then C at t = 2: one change A -> C
            (2.0, 1, "C", False),
            (0.0, 2, "A", False),
            (3.0, 2, "B", True),  # logged as a launch: a known schedule
            (5.0, 2, REMOVED, False),
        ]
    )
    moves = transitions(log)
    got = list(moves[["robot", "source", "target", "launch"]].itertuples(index=False))
    assert [tuple(g) for g in got] == [
        (1, LAUNCH, "A", False),
        (2, LAUNCH, "A", False),
        (1, "A", "C", False),
        (2, "A", "B", True),
        (2, "B", REMOVED, False),
    ]
    np.testing.assert_allclose(moves["dwell"].dropna(), [2.0, 3.0, 2.0])


def test_exposure_table_counts_robot_time_and_hazard_transitions_only():
    log = _log(
        [
            (0.0, 1, "A", False),
            (2.0, 1, "C", False),
            (0.0, 2, "A", False),
            (3.0, 2, "B", True),
            (5.0, 2, REMOVED, False),
        ]  # fmt: skip
    )
    table = exposure_table(log, 10.0)
    in_a = table[table["state"] == "A"]
    assert in_a["exposure"].sum() == pytest.approx(2.0 + 3.0)
    assert in_a["to:C"].sum() == 1 and in_a["to:B"].sum() == 0  # the launch is no hazard
    in_b = table[table["state"] == "B"]
    assert in_b["exposure"].sum() == pytest.approx(2.0) and in_b[f"to:{REMOVED}"].sum() == 1


def test_state_graph_of_the_test_model():
    """Edges A -> B and B -> C with their counts; crude rates near the known ones; launch is
    the source and C the sink."""
    logs = collect_runs(RatesModel, range(10, 14), {"contact": 0.002, "rate_ab": 0.05})
    graph = state_graph(logs)
    assert set(graph.edges) == {(LAUNCH, "A"), ("A", "B"), ("B", "C")}
    assert graph.edges[LAUNCH, "A"]["count"] == 4 * 30
    assert graph.edges["A", "B"]["count"] == 4 * 30
    assert graph.edges["A", "B"]["rate"] == pytest.approx(0.05, rel=0.25)
    assert graph.nodes["A"]["robot_time"] == pytest.approx(graph.edges["A", "B"]["exposure"])
    assert sources(graph) == ["A"]
    assert sinks(graph) == ["C"]
