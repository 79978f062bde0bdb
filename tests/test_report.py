"""Reproduction report: published numbers beside ours, figures, the CLI verb."""

import json

import numpy as np
import pandas as pd

from analysis.cli import main
from analysis.compare import (
    BY_CONSTRUCTION,
    NOT_COMPARABLE,
    NOT_IN_SWEEP,
    compare_published,
    parameter_defaults,
)
from analysis.report import write_report
from models.beacon_explorer.published import PUBLISHED


def corridor_results(n: int = 4) -> pd.DataFrame:
    """Fake corridor runs: 24 s halves flight time and collisions, doubles coverage time."""
    rng = np.random.default_rng(1)
    rows = []
    for level, area in (("low", 80.0), ("medium", 90.0), ("high", 94.0)):
        for t in (6.0, 12.0, 24.0):
            for i in range(n):
                flight = 2000.0 * 6.0 / t + rng.normal(0, 10)
                rows.append(
                    {
                        "run_id": f"{level}-{t:g}-{i}",
                        "seed": i,
                        "world": "corridor",
                        "complexity": level,
                        "launch_period": t,
                        "hover_beacons": False,
                        "coverage_time": 20.0 * t + rng.normal(0, 1),
                        "coverage_area": area + rng.normal(0, 1),
                        "complete": bool(i % 2),
                        "collisions": 60.0 / t,
                        "flight_time": flight,
                        "energy_flight": 120.0 * flight,
                        "energy_beacon": 5.0 * 20 * t,
                        "energy_ground": 0.5 * 20 * t,
                        "energy_total": 120.0 * flight + 110.0 * t,
                        "branches": {"low": 3, "medium": 6, "high": 9}[level],
                        "status": "ok",
                    }
                )
    return pd.DataFrame(rows)


def write_sweep(
    folder,
    df: pd.DataFrame,
    points: list[dict] | None = None,
    *,
    grid: dict | None = None,
    model: str = "beacon-explorer",
    target: str = "models.beacon_explorer.model:BeaconExplorerModel",
) -> None:
    """Fake runs written as the runs of a sweep: each row gets the run id, replication and seed
    the plan gives its parameters (a report refuses run files that are not its sweep's). The
    grid defaults to beacon/explorer's complexity x launch period; with ``points``, the grid is
    the complexity and each row takes the first point it matches.
    """
    from analysis.sweep.seeding import run_id, spawned_seed

    grid = grid or {"complexity": ["low", "medium", "high"], "launch_period": [6.0, 12.0, 24.0]}
    if points:
        del grid["launch_period"]
    (folder / "runs").mkdir(parents=True)
    reps: dict[str, int] = {}
    for _, row in df.iterrows():
        params = {k: next(v for v in values if v == row[k]) for k, values in grid.items()}
        params |= next((p for p in points or [] if all(row[k] == v for k, v in p.items())), {})
        key = json.dumps(params, sort_keys=True)
        rep = reps[key] = reps.get(key, -1) + 1
        rid = run_id(params, rep)
        one = row.to_frame().T.assign(run_id=rid, rep=rep, seed=spawned_seed(1, params, rep)[0])
        one.infer_objects().to_parquet(folder / "runs" / f"{rid}.parquet", index=False)
    manifest = {"name": "fake", "model": model, "seed": 1, "replications": max(reps.values()) + 1,
                "target": target, "grid": grid, "points": points or []}  # fmt: skip
    (folder / "sweep.json").write_text(json.dumps(manifest))


def test_every_published_number_has_a_row():
    table = compare_published(corridor_results(), PUBLISHED)
    assert len(table) == len(PUBLISHED)
    published = set(table["published"])
    for value in ("79.4", "90.1", "94", "38.5", "64.2", "74.3", "-41.5", "-93.9", "+90.5",
                  "-30.8", "99.7", "-29.9", "-16.4", "+149.7", "0.32 -> 0.02", "-15.0",
                  "+44.9", "-34.0", "-86.4", "+70.5", "-25.3", "0.974", "3.6"):  # fmt: skip
        assert value in published, value


def test_ours_beside_published_for_the_same_condition():
    rows = compare_published(corridor_results(), PUBLISHED)
    flight = rows[rows["quantity"].str.startswith("flight time: change 24")]
    corridor = flight[flight["section"] == "corridor"].iloc[0]
    assert float(corridor["ours"].split(";")[0]) == pytest_approx(-75.0, 2.0)
    assert corridor["verdict"] == "holds" and "excludes 0" in corridor["rule"]
    coverage = rows[rows["quantity"].str.startswith("coverage time: change 24")].iloc[0]
    collisions = rows[rows["quantity"].str.startswith("collisions: change 24")].iloc[0]
    assert float(collisions["ours"].split(";")[0]) == pytest_approx(-75.0, 0.01)
    assert float(coverage["ours"].split(";")[0]) > 0 and coverage["verdict"] == "holds"
    area = rows[rows["quantity"].str.startswith("coverage area (%), mean over periods")]
    assert list(area["verdict"]) == ["(reference)", "holds", "holds"]
    r = rows[rows["quantity"].str.startswith("Pearson")].iloc[0]
    # energy is mostly 120 W x flight time: computed and shown, labelled, never "holds"
    assert float(r["ours"].split()[0]) > 0.99 and r["verdict"] == BY_CONSTRUCTION
    assert "constant power" in r["reason"]
    others = rows[rows["section"].isin(["open space", "mixed", "hover vs attach"])]
    assert (others["verdict"] == NOT_COMPARABLE).all()
    assert others["reason"].str.startswith("world is corridor here, ").all()


def pytest_approx(value, tol):
    import pytest

    return pytest.approx(value, abs=tol)


def test_report_is_self_contained_html(tmp_path):
    folder = tmp_path / "fake"
    write_sweep(folder, corridor_results())
    path = write_report(folder)
    text = path.read_text()
    assert path == folder / "report.html"
    assert text.count("data:image/png;base64,") == 2  # metric panels + energy components
    assert "Two-way ANOVA" in text and NOT_IN_SWEEP in text and "0.974" in text
    assert "Optimal launch_period" in text and "Percent changes" in text
    assert 'src="http' not in text and "<script" not in text
    assert (folder / "figures" / "metrics.png").is_file()
    assert (folder / "figures" / "stacked.png").is_file()
    elsewhere = write_report(folder, tmp_path / "not" / "yet" / "there.html")  # made as needed
    assert elsewhere.is_file() and (elsewhere.parent / "comparison.csv").is_file()


def test_a_stigmergy_sweep_is_compared_with_table_1(tmp_path):
    """Table 1's trends as records: beacons fall with the radius on map 1 (233.4, 27.8, 12.8,
    8.2); fake runs that fall agree, the missing 10 m condition reads as not comparable."""
    from models.stigmergy import StigmergyModel
    from models.stigmergy.published import PUBLISHED as TABLE1_RECORDS

    rows = []
    for radius, beacons in ((20.0, 30.0), (30.0, 13.0), (40.0, 9.0)):
        for i in range(3):
            rows.append({"run_id": f"{radius}-{i}", "map": "hall100", "pheromone_radius": radius,
                         "beacon": beacons + i, "wander": 2.0, "time": 1000.0 - radius * 5,
                         "cb": 10.0, "status": "ok"})  # fmt: skip
    defaults = parameter_defaults(StigmergyModel)
    table = compare_published(pd.DataFrame(rows), TABLE1_RECORDS, defaults)
    beacons = table[
        (table["section"] == "map 1 (hall100)") & (table["quantity"] == "final beacons b")
    ]
    assert list(beacons["verdict"]) == [NOT_COMPARABLE, "(reference)", "holds", "holds"]
    assert beacons["reason"].iloc[0] == "pheromone radius is 20, 30, 40 here, 10 in the paper"
    assert list(beacons["published"]) == ["233.4", "27.8", "12.8", "8.2"]


def test_cli_report_prints_where_it_wrote(tmp_path, capsys):
    folder = tmp_path / "fake"
    write_sweep(folder, corridor_results(n=2))
    assert main(["report", str(folder)]) == 0
    assert f"wrote {folder / 'report.html'}" in capsys.readouterr().out
    assert main(["report", str(tmp_path / "nothing")]) == 2
    assert "not a sweep folder" in capsys.readouterr().err


def test_report_out_is_checked_before_the_work(tmp_path, capsys):
    """``--out`` naming a folder is refused at once; a file in a folder not made yet gets its
    folder (the report wrote for 10 s, then failed with "Cannot save file into a non-existent
    directory"), with the tables beside it.
    """
    folder = tmp_path / "fake"
    write_sweep(folder, corridor_results(n=2))
    assert main(["report", str(folder), "--out", str(tmp_path)]) == 2
    assert f"--out {tmp_path} is a folder" in capsys.readouterr().err
    target = tmp_path / "new" / "deeper" / "r.html"
    assert main(["report", str(folder), "--out", str(target)]) == 0
    out = capsys.readouterr().out
    for written in (target, target.parent / "comparison.csv", target.parent / "statistics.csv"):
        assert written.exists() and f"wrote {written}" in out


def test_a_points_only_key_is_a_condition_of_its_own_in_the_means(tmp_path):
    # a sweep whose [[points]] set hover_beacons on some runs only: those runs, and the others
    # (where the key is unset), each get their own row instead of being averaged together
    df = corridor_results()
    df = df[df["complexity"] == "high"].copy()
    df["hover_beacons"] = np.where(df["launch_period"] == 6.0, True, None)
    df.loc[df["hover_beacons"].notna(), "energy_total"] = 1e9
    folder = tmp_path / "points"
    write_sweep(folder, df, [{"hover_beacons": True, "launch_period": 6.0},
                             {"launch_period": 12.0}, {"launch_period": 24.0}])  # fmt: skip
    text = write_report(folder).read_text()
    assert "(hover_beacons=True, launch_period=6.0)" in text  # the set-up line names the points
    assert "(default)" in text and "1e+09" in text  # their means are not mixed with the rest


def test_a_list_valued_points_key_is_a_condition_of_its_own(tmp_path):
    # fault_states set on some [[points]] only comes back from Parquet as arrays: the report
    # groups by its text instead of failing on an unhashable value
    df = corridor_results()
    df = df[df["complexity"] == "high"].copy()
    on = df["launch_period"] == 6.0
    df["fault_states"] = [["beacon"] if flag else None for flag in on]
    df.loc[on, "energy_total"] = 1e9
    folder = tmp_path / "lists"
    write_sweep(folder, df, [{"fault_states": ["beacon"], "launch_period": 6.0},
                             {"launch_period": 12.0}, {"launch_period": 24.0}])  # fmt: skip
    text = write_report(folder).read_text()
    assert "[&#39;beacon&#39;]" in text or "['beacon']" in text
    assert "(default)" in text and "1e+09" in text
