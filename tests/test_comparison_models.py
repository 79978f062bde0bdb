"""Every model's README sweep, made tiny (short time limits, small grids), gives a report whose
comparison.csv holds every published number and every claim, each the same row as the HTML's;
runs all cut by the time limit give censored rows, and settings that are not the paper's give
"not comparable" rows."""

import re

import pytest

from abm.registry import model_class
from analysis.compare import NOT_IN_SWEEP
from analysis.report import write_report
from analysis.sweep import run_sweep
from tests.test_comparison import JUDGED, check_csv_against_html

#: model -> (grid, replications): each model's README sweep, cut down to seconds.
TINY = {
    "beacon-explorer": ({"world": ["corridor"], "complexity": ["high"],
                         "launch_period": [6.0, 24.0], "time_limit": [60.0]}, 2),
    "stigmergy": ({"map": ["hall100"], "pheromone_radius": [20.0, 30.0],
                   "time_limit": [120.0]}, 2),
    "sugarmap": ({"arena": ["testbed"], "n_anchors": [5], "n_explorers": [2],
                  "horizon": [180.0], "init_cutoff": [60.0]}, 2),
    "hierarchy": ({"workers": [2, 3], "scouts_per_worker": [2], "world_size": [6.0],
                   "worker_spacing": [1.6]}, 1),
    "tangible-pso": ({"particles": [10], "iterations": [10], "neighbours": [0, 1],
                      "motion_planning": [False, True]}, 1),
    "flocking": ({"visual_distance": [3.0, 5.0], "birds": [50], "steps": [20]}, 1),
}  # fmt: skip


@pytest.mark.slow
@pytest.mark.parametrize("model", sorted(TINY))
def test_comparison_csv_of_a_tiny_readme_sweep_matches_the_report(tmp_path, model):
    grid, replications = TINY[model]
    folder = tmp_path / model
    run_sweep(model, grid, replications, 27, folder, "serial", time_series=True, progress=False)
    html = write_report(folder).read_text()
    table = check_csv_against_html(folder, html)
    cls = model_class(model)
    assert len(table) == len(cls.PUBLISHED) + len(cls.CLAIMS)
    published = table.iloc[: len(cls.PUBLISHED)]
    claims = table.iloc[len(cls.PUBLISHED) :]
    if (claims["verdict"] == NOT_IN_SWEEP).any():  # folded below the claims these runs judge
        absent = int((claims["verdict"] == NOT_IN_SWEEP).sum())
        summary = re.search(rf"{absent} claims? {NOT_IN_SWEEP}", html).start()
        assert summary < html.rindex('<table class="claims">')  # the folded table follows
        if absent < len(claims):  # the judged claims come first
            assert html.index('<table class="claims">') < summary
    if model == "beacon-explorer":  # every run ends at the 60 s limit
        coverage = published[published["claim or metric"].str.contains("coverage time")]
        judged = coverage[coverage["verdict"].isin(JUDGED)]
        assert judged.empty, judged
        assert (coverage["verdict"] == "censored").any()
    if model == "stigmergy":  # Table 1 ran to 15000 s; these runs to 120 s
        assert not set(published["verdict"]) & JUDGED
        assert published["reason"].str.contains("time limit is 120 here, 15000 in the paper").any()
    if model == "tangible-pso":  # Table 1: 40 particles x 70 iterations
        assert set(published["verdict"]) == {"not comparable"}
        assert set(published["reason"]) == {"particles is 10 here, 40 in the paper"}
    if model == "sugarmap":  # the testbed record and C18: one rule, one verdict
        c18 = table[table["claim or metric"].str.startswith("C18:")]["verdict"].iloc[0]
        assert published["verdict"].iloc[0] == c18
