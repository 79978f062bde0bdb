"""The scale benchmark's own logic: a run stopped at the wall budget is marked as such, and the
table's note on cut rows is printed only when a row was cut.
"""

import sys

import pytest

from tests.scripts import load_benchmark

bench = load_benchmark("bench_scale")


def test_a_run_stopped_at_the_wall_budget_is_marked_cut_with_the_time_it_reached():
    _, duration = bench.beacon_explorer_case(20)
    row = bench.time_run("beacon-explorer", 20, seed=1, budget=0.0, chunk=5.0)
    assert row["truncated"]
    assert row["simulated"] == 5.0 < duration
    assert bench.cut(row) == "*"


def test_a_run_that_reaches_its_duration_is_not_marked_cut():
    _, duration = bench.beacon_explorer_case(20)
    row = bench.time_run("beacon-explorer", 20, seed=1, budget=600.0, chunk=60.0)
    assert (row["truncated"], row["simulated"], bench.cut(row)) == (False, duration, " ")


def test_a_run_the_model_ends_early_is_not_marked_cut():
    # 5 robots all become beacons and the model stops itself (seed 1: at 39 s of 75)
    _, duration = bench.beacon_explorer_case(5)
    row = bench.time_run("beacon-explorer", 5, seed=1, budget=600.0, chunk=60.0)
    assert row["simulated"] < duration and row["end"].startswith("stuck")
    assert (row["truncated"], bench.cut(row)) == (False, " ")


@pytest.mark.parametrize("cut_rows", [(), (1,), (0, 1)])
def test_the_note_on_cut_rows_is_printed_only_when_a_row_was_cut(monkeypatch, capsys, cut_rows):
    rows = [{"truncated": k in cut_rows} for k in range(2)]
    monkeypatch.setattr(bench, "print_rows", lambda name, sizes, args: rows)
    monkeypatch.setattr(sys, "argv", ["bench_scale.py", "--models", "beacon-explorer"])
    bench.main()
    assert ("stopped at the wall budget" in capsys.readouterr().out) == bool(cut_rows)
