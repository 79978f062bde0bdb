"""Runs made in other units are never pooled: a sweep records the unit of each summary key in
its sweep.json, a resume under code whose units differ is refused, and a report over sweeps
whose units differ (or were not recorded) stops in one line instead of mixing cm^2 with m^2."""

from types import SimpleNamespace

import pytest

from abm.errors import ABMError
from analysis.report import _check_units
from analysis.sweep.spec import load_sweep, summary_units
from models.hierarchy import HierarchyModel


def _sweep(name, units):
    manifest = {"name": name} if units is None else {"name": name, "units": units}
    return SimpleNamespace(name=name, manifest=manifest)


def test_a_sweep_records_the_models_units():
    units = summary_units(HierarchyModel)
    assert units["scout_scan_area"] == "m^2" and units["time"] == "s"


def test_a_sweep_file_plans_its_units(tmp_path):
    path = tmp_path / "h.toml"
    path.write_text('model = "hierarchy"\nseed = 1\n[grid]\nworkers = [2]\n')
    assert load_sweep(path).manifest()["units"] == summary_units(HierarchyModel)


def test_sweeps_in_different_units_or_without_units_are_not_pooled():
    today = summary_units(HierarchyModel)
    older = {**today, "scout_scan_area": "cm^2"}
    _check_units([_sweep("a", today), _sweep("b", dict(today))])  # same units: pooled
    _check_units([_sweep("old", None)])  # alone: reported as it is
    with pytest.raises(ABMError, match=r"scout_scan_area \(m\^2 vs cm\^2\)"):
        _check_units([_sweep("a", today), _sweep("b", older)])
    with pytest.raises(ABMError, match="old: made by code that recorded no units"):
        _check_units([_sweep("a", today), _sweep("old", None)])


def test_a_resume_under_code_whose_units_differ_is_refused(tmp_path, capsys):
    import json

    from analysis.cli import main

    path = tmp_path / "s.toml"
    path.write_text(
        'model = "tests.tiny_model:TinyModel"\nseed = 1\nreplications = 1\n'
        "[grid]\ntime_limit = [5.0]\n"
    )
    out = tmp_path / "sweep"
    assert main(["sweep", str(path), "--executor", "serial", "--out", str(out)]) == 0
    manifest = json.loads((out / "sweep.json").read_text())
    manifest["units"]["time"] = "min"  # as if an older code had stored minutes
    (out / "sweep.json").write_text(json.dumps(manifest))
    capsys.readouterr()
    assert main(["sweep", str(path), "--executor", "serial", "--out", str(out)]) != 0
    assert "summary units differ from today's code's (time)" in capsys.readouterr().err
