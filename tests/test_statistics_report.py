"""The report's statistics: refusals instead of meaningless tables, no warning on the terminal,
statistics.csv beside the HTML with the same numbers, Holm-adjusted p-values, bootstrap
intervals, and figures for a custom grid the paper never ran.
"""

import warnings
from html.parser import HTMLParser

import numpy as np
import pandas as pd
import pytest
from test_report import corridor_results, write_sweep

from analysis.cli import main
from analysis.report import write_report
from analysis.statistics_table import holm
from models.beacon_explorer.published import REPORT


class _Tables(HTMLParser):
    """Each ``<h4>`` heading of the page with the rows of the table under it."""

    def __init__(self) -> None:
        super().__init__()
        self.tables: dict[str, list[list[str]]] = {}
        self._heading: str | None = None
        self._text: list[str] | None = None
        self._row: list[str] | None = None

    def handle_starttag(self, tag, attrs):
        if tag in ("h4", "td", "th"):
            self._text = []
        elif tag == "tr":
            self._row = []

    def handle_endtag(self, tag):
        if tag == "h4":
            self._heading = "".join(self._text).strip()
        elif tag in ("td", "th") and self._row is not None:
            self._row.append("".join(self._text).strip())
        elif tag == "tr" and self._heading is not None:
            self.tables.setdefault(self._heading, []).append(self._row)
        if tag in ("h4", "td", "th"):
            self._text = None

    def handle_data(self, data):
        if self._text is not None:
            self._text.append(data)


def _sweep(folder, runs: pd.DataFrame, manifest: dict) -> None:
    """Fake runs written as the runs of a sweep of ``manifest``'s model and grid."""
    write_sweep(folder, runs, grid=dict(manifest["grid"]), model=manifest["model"],
                target=manifest["target"])  # fmt: skip


def _report_quietly(folder, capsys) -> str:
    """``abm report`` with every warning recorded: none may be raised, none printed."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        assert main(["report", str(folder)]) == 0
    printed = capsys.readouterr()
    assert [str(w.message) for w in caught] == []
    assert printed.err == ""
    return (folder / "report.html").read_text()


#: The rest of a hierarchy run's summary (one real run's values), for the claims' checks.
HIERARCHY_REST = {
    "wall_collisions": 0, "robot_collisions": 0, "queen_scan_area": 36.0,
    "queen_iterations": 7, "worker_iterations": 25.5, "known_free_fraction": 0.999,
    "wave_order_violations": 0, "robot_proximity_events": 0, "sibling_proximity_events": 0,
    "path_cells_blocked": 0, "stalled_moves": 0, "workers_failed": 0, "reattached": 0,
    "messages": 4341, "messages_task": 4329, "messages_startup": 12, "bytes": 34886,
    "max_node_load": 2526, "queen_load": 79, "worker_load_max": 2526, "scout_load_max": 1545,
    "msg_REQUEST_INFO": 6, "msg_INFO": 6, "msg_MOVE": 101, "msg_ARRIVED": 101, "msg_SCAN": 107,
    "msg_POINT": 3886, "msg_SCAN_COMPLETE": 107, "msg_MAP_REPORT": 13, "msg_MAP_DOWN": 13,
    "msg_START": 1, "msg_ASSIGN": 0, "msg_LOS_HINT": 0,
}  # fmt: skip


def hierarchy_runs() -> pd.DataFrame:
    """A W x S grid of the hierarchy: its layout draws against N = 1 + W + W S, hue W."""
    rng = np.random.default_rng(3)
    rows = []
    for w in (2, 3):
        for s in (2, 3):
            for rep in range(2):
                rows.append(
                    {"run_id": f"{w}-{s}-{rep}", "rep": rep, "seed": rep, "workers": w,
                     "scouts_per_worker": s, "time": 300.0 + rng.normal(0, 9),
                     "end_reason": "cannot_complete", "collisions": 0, "topology": "hst",
                     "complete": 0.0, "N": 1 + w + w * s,
                     "W": w, "S": s, "scout_scan_area": 20.0 + rng.normal(0, 1.0),
                     "worker_scan_area": 60.0 + rng.normal(0, 1.0),
                     "scout_drive": 25.0 + rng.normal(0, 0.9),
                     "worker_drive": 14.0 + rng.normal(0, 0.9), "status": "ok",
                     "links": w + w * s, "scouts": w * s, **HIERARCHY_REST}
                )  # fmt: skip
    return pd.DataFrame(rows)


HIERARCHY = {"name": "hier_tiny", "model": "hierarchy", "seed": 3, "replications": 2,
             "target": "models.hierarchy.model:HierarchyModel",
             "grid": {"workers": [2, 3], "scouts_per_worker": [2, 3]}}  # fmt: skip


def test_the_hierarchy_is_tested_over_its_swept_w_and_s_not_its_collinear_n(tmp_path, capsys):
    # N x W (drawn) and W x S (swept) split the runs into the same conditions: one test,
    # over the crossed keys the grid swept (N x W would be refused: W is fixed by N)
    _sweep(tmp_path, hierarchy_runs(), HIERARCHY)
    page = _report_quietly(tmp_path, capsys)
    assert "not computed: W is fixed by N" not in page
    stats = pd.read_csv(tmp_path / "statistics.csv")
    assert set(stats["factors"].dropna()) == {"workers x scouts_per_worker"}
    swept = stats[stats["factors"] == "workers x scouts_per_worker"]
    assert swept["computed"].all() and swept["metric"].nunique() == 4
    assert "Scout drive distance (m)</h4>" in page


@pytest.mark.slow
def test_abm_report_of_a_real_hierarchy_tiny_sweep_prints_no_warning(tmp_path, capsys):
    spec = tmp_path / "tiny.toml"
    spec.write_text(
        'name = "hier_tiny"\nmodel = "hierarchy"\nseed = 3\nreplications = 2\n[grid]\n'
        "workers = [2, 3]\nscouts_per_worker = [2, 3]\nworld_size = [6.0]\n"
        "worker_spacing = [1.6]\n"
    )
    assert main(["sweep", str(spec), "--out", str(tmp_path / "s"), "--executor", "serial"]) == 0
    capsys.readouterr()
    page = _report_quietly(tmp_path / "s", capsys)
    assert "not computed: W is fixed by N" not in page  # tested over W x S alone
    stats = pd.read_csv(tmp_path / "s" / "statistics.csv")
    assert set(stats.loc[stats["test"] == "ANOVA", "factors"].dropna()) == {
        "workers x scouts_per_worker"
    }


#: statistics.csv's columns and the page's headings of the same numbers.
SHOWN_AS = (("p", "PR(>F)"), ("p_holm", "p (Holm)"), ("effect_value", "eta_sq"),
            ("ci_low", "eta_sq 2.5 %"), ("ci_high", "eta_sq 97.5 %"))  # fmt: skip


def test_statistics_csv_holds_what_the_page_shows(tmp_path):
    write_sweep(tmp_path, corridor_results())
    page = write_report(tmp_path).read_text()
    stats = pd.read_csv(tmp_path / "statistics.csv")
    tables = _Tables()
    tables.feed(page)
    computed = stats[stats["computed"] & (stats["test"] == "ANOVA")]
    assert set(computed["metric"]) == {"coverage_time", "flight_time", "energy_total"}
    refused = stats[~stats["computed"]].set_index("metric")["reason"]
    assert refused["collisions"].startswith("collisions does not vary within any condition")
    assert f"not computed: {refused['collisions']}" in page
    shown = 0
    for metric, rows in computed.groupby("metric"):
        head, *body = tables.tables[REPORT.labels[metric].replace("(kJ)", "(J)")]
        assert head == ["source", "df", "sum_sq", "F", "PR(>F)", "p (Holm)", "eta_sq",
                        "eta_sq 2.5 %", "eta_sq 97.5 %"]  # fmt: skip
        by_source = {cells[0]: dict(zip(head, cells, strict=True)) for cells in body}
        for row in rows.to_dict("records"):
            cells = by_source[row["source"]]
            for column, shown_as in SHOWN_AS:
                if pd.isna(row[column]):
                    assert cells[shown_as] == "\u2013"
                else:
                    assert float(cells[shown_as].replace(",", "")) == pytest.approx(
                        row[column], rel=5e-3
                    )
                    shown += 1
    assert shown > 20
    # Holm over every p-value of the page, and the page says how many there are
    tested = stats["p"].notna()
    assert stats.loc[tested, "p_holm"].to_numpy() == pytest.approx(holm(stats.loc[tested, "p"]))
    assert f"{int(tested.sum())} tests on this page" in page
    # the condition means are in J where the figures draw kJ, and the page says so
    assert "energy_total: Total swarm energy (J)" in page
    # the effect sizes' intervals come from the sweep's seed: the same report, the same numbers
    write_report(tmp_path)
    pd.testing.assert_frame_equal(stats, pd.read_csv(tmp_path / "statistics.csv"))


def sugarmap_cut_runs() -> pd.DataFrame:
    """A custom SugarMap grid (n_anchors 2 and 6) whose runs ended before deployment did: none
    of the paper's coverage metrics exist, the common summary keys do.
    """
    rng = np.random.default_rng(5)
    rows = [
        {"run_id": f"{a}-{rep}", "rep": rep, "seed": rep, "n_anchors": a, "arena": "testbed",
         "time_limit": 20.0, "time": 20.0, "end_reason": "time limit",
         "collisions": int(rng.integers(0, 6)), "coverage_area": 30.0 / a + rng.normal(0, 2),
         "algorithm": "sugarmap", "n_explorers": 2, "noise_scale": 1.0,
         "heading_model": "literal", "n_particles": 10, "cutoff_fired": False, "status": "ok"}
        for a in (2, 6)
        for rep in range(3)
    ]  # fmt: skip
    return pd.DataFrame(rows)


def test_a_custom_sugarmap_grid_gets_figures_and_statistics(tmp_path, capsys):
    manifest = {"name": "sugar_cut", "model": "sugarmap", "seed": 5, "replications": 3,
                "target": "models.sugarmap.model:SugarMapModel",
                "grid": {"n_anchors": [2, 6], "time_limit": [20.0]}}  # fmt: skip
    _sweep(tmp_path, sugarmap_cut_runs(), manifest)
    page = _report_quietly(tmp_path, capsys)
    assert (tmp_path / "figures" / "metrics.png").is_file()
    assert "not computed: time is constant (20 in every run)" in page
    stats = pd.read_csv(tmp_path / "statistics.csv")
    tested = stats[stats["computed"] & (stats["source"] == "n_anchors")]
    assert set(tested["metric"]) == {"coverage_area", "collisions"}


@pytest.mark.parametrize("complexities", [["low"], ["low", "medium", "high"]])
def test_the_stacked_energy_legend_is_not_cut(complexities):
    """One panel is narrower than three labels side by side ("Ground energ" was cut off)."""
    from dataclasses import replace

    from analysis.figures import stacked_bars

    runs = corridor_results()
    runs = runs[runs["complexity"].isin(complexities)]
    fig = stacked_bars(runs, replace(REPORT, hue=None if len(complexities) == 1 else "complexity"))
    fig.canvas.draw()
    (legend,) = fig.legends
    assert [t.get_text() for t in legend.get_texts()] == [
        "Flight energy", "Beacon energy", "Ground energy"]  # fmt: skip
    page = fig.bbox
    for text in [*legend.get_texts(), legend.get_title()]:
        box = text.get_window_extent()
        assert page.x0 <= box.x0 and box.x1 <= page.x1 and page.y0 <= box.y0, text.get_text()
    for ax in fig.axes:  # the panels stay above the legend
        assert ax.get_tightbbox().y0 >= legend.get_window_extent().y1 - 1


def test_a_custom_grid_of_names_is_drawn_and_tested_against_them(tmp_path, capsys):
    """A grid of arenas only: the swept key is not a number and not the layout's x."""
    runs = sugarmap_cut_runs()
    runs["arena"] = runs["n_anchors"].map({2: "testbed", 6: "open"})
    runs["n_anchors"] = 5
    manifest = {"name": "arenas", "model": "sugarmap", "seed": 5, "replications": 3,
                "target": "models.sugarmap.model:SugarMapModel",
                "grid": {"arena": ["testbed", "open"], "time_limit": [20.0]}}  # fmt: skip
    _sweep(tmp_path, runs, manifest)
    page = _report_quietly(tmp_path, capsys)
    assert (tmp_path / "figures" / "metrics.png").is_file()
    assert "against arena" in page
    stats = pd.read_csv(tmp_path / "statistics.csv")
    assert set(stats.loc[stats["source"] == "arena", "metric"]) == {"coverage_area", "collisions"}
    assert "<h4>coverage area (%)</h4>" in page  # its unit, from the model's declaration


def test_a_warning_while_drawing_or_testing_becomes_a_note_of_the_page(
    tmp_path, capsys, monkeypatch
):
    import analysis.report

    def warning_anova(*args, **kwargs):
        np.log(np.zeros(1))  # numpy: divide by zero
        warnings.warn("covariance of constraints does not have full rank", stacklevel=2)
        return original(*args, **kwargs)

    original = analysis.report.stats.anova
    monkeypatch.setattr(analysis.report.stats, "anova", warning_anova)
    write_sweep(tmp_path, corridor_results())
    page = _report_quietly(tmp_path, capsys)
    assert "UserWarning: covariance of constraints does not have full rank" in page
    assert page.count("covariance of constraints") == 1  # each once
    assert "RuntimeWarning: divide by zero encountered in log" in page


def test_an_anova_over_factors_that_split_the_runs_alike_is_one_test_named_by_the_sweep():
    # a star arm against the hierarchy at W = S = 2: N (5 or 7) follows the topology, so
    # "over N" and "over topology" were the same F test, and Holm counted it twice
    from abm.published import ReportLayout
    from analysis.report import _anova

    rng = np.random.default_rng(3)
    runs = pd.DataFrame(
        {"topology": ["star"] * 6 + ["hst"] * 6, "N": [5] * 6 + [7] * 6,
         "scout_drive": np.r_[rng.normal(80, 2, 6), rng.normal(60, 2, 6)]}
    )  # fmt: skip
    layout = ReportLayout(x="N", metrics=("scout_drive",))
    tests = _anova(runs, layout, seed=1, conditions=["topology"])
    assert [t.factors for t in tests] == [("topology",)]
    # where the sweep's factors split the runs otherwise, both tests stay
    runs["topology"] = ["star", "hst"] * 6
    assert [t.factors for t in _anova(runs, layout, 1, ["topology"])] == [("N",), ("topology",)]
