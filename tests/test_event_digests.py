"""Seeded runs of every model keep the reproducibility guarantee against what is on file.

The guarantee (``docs/reproducibility.md``): the same decisions (events, labels, order,
counts), floats equal within ``RTOL``. ``tests/data/event_digests.json`` holds each quick
case's decision digests and ``tests/data/event_digests_floats.npz`` its floats, written by
``scripts/event_digests.py --write``; a branch that changes a model's behaviour on purpose
regenerates them (see the script's docstring). The last tests change a model on purpose and
check the comparison notices.
"""

import importlib.util
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from hypothesis import given
from hypothesis import strategies as st

_SCRIPT = Path(__file__).resolve().parent.parent / "scripts" / "event_digests.py"
_spec = importlib.util.spec_from_file_location("event_digests", _SCRIPT)
event_digests = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(event_digests)

RTOL = event_digests.RTOL


@pytest.fixture(scope="module")
def on_file():
    return event_digests.stored(), event_digests.load_floats()


@pytest.mark.parametrize("case", event_digests.QUICK)
def test_seeded_run_matches_stored_digest(case, on_file):
    result = event_digests.outcome(case, *on_file)
    assert result.same, "\n".join(result.problems)


def test_paper_default_worlds_match_stored_digest():
    want = event_digests.stored().get(event_digests.WORLDS)
    assert want is not None
    assert event_digests.world_digest() == want


# ---------------------------------------------------------------- the comparison itself
finite = st.floats(-1e6, 1e6, allow_nan=False)


@given(st.lists(finite, min_size=1, max_size=30), st.floats(-0.5, 0.5))
def test_floats_within_the_tolerance_agree(values, fraction):
    a = np.array(values)
    b = a + fraction * RTOL * np.maximum(1.0, np.abs(a))
    assert event_digests.compare({"events/x": b}, {"events/x": a}) == []


@given(st.lists(finite, min_size=1, max_size=30), st.data())
def test_a_float_beyond_the_tolerance_is_reported(values, data):
    a = np.array(values)
    row = data.draw(st.integers(0, len(a) - 1))
    b = a.copy()
    b[row] += 3 * RTOL * max(1.0, abs(a[row]))
    problems = event_digests.compare({"events/x": b}, {"events/x": a})
    assert len(problems) == 1 and problems[0].startswith("events/x: 1 of")


def test_decisions_keep_labels_and_gaps_but_not_float_values():
    frame = pd.DataFrame(
        {"time": [0.5, 1.0], "event": ["launch", "land"], "x": [np.nan, 2.25], "hit": [True, 0.1]}
    )
    text, floats = event_digests.split(frame)
    moved = frame.assign(x=[np.nan, 2.25 + 1e-3], hit=[True, 0.2])
    assert event_digests.split(moved)[0] == text  # float values: compared by tolerance
    assert event_digests.compare(event_digests.split(moved)[1], floats) != []
    assert event_digests.split(frame.assign(event=["launch", "fail"]))[0] != text
    assert event_digests.split(frame.assign(x=[1.0, 2.25]))[0] != text  # a value appeared
    assert event_digests.split(frame.iloc[::-1].reset_index(drop=True))[0] != text  # order


# ---------------------------------------------------------------- behaviour changed on purpose
def test_a_launch_period_a_millionth_longer_is_caught(monkeypatch, on_file):
    """Launching every 6.000006 s instead of the paper's 6 s: launches now fall just after
    the physics ticks they coincided with, the runs part ways, and the check says so.
    """
    from models.beacon_explorer.params import BeaconExplorerParams

    case = "be-open-high-5"
    name, kwargs = event_digests.CASES[case]
    period = BeaconExplorerParams().launch_period * (1 + 1e-6)
    monkeypatch.setitem(event_digests.CASES, case, (name, {**kwargs, "launch_period": period}))
    problems = event_digests.outcome(case, *on_file).problems
    assert any(p.startswith("events:") for p in problems), problems
    assert any(p.startswith("events/time") for p in problems), problems


def test_a_changed_rule_is_caught(monkeypatch, on_file):
    """Wanders that land when the nearest beacon is 1 % nearer than the paper's l_i: other
    decisions, and the decision digest says so.
    """
    from models.stigmergy import wander

    nearest = wander.nearest_distance
    monkeypatch.setattr(wander, "nearest_distance", lambda p, t: 1.01 * nearest(p, t))
    problems = event_digests.outcome("st-hall100-fast-4", *on_file).problems
    assert any(p.startswith("events:") for p in problems), problems
