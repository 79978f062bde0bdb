"""The reproduction benchmark times each model's figure set: the sweeps its README's
reproduction commands run. These tests keep the two in step and check its refusal of a folder
that already holds runs (the runner would skip them and the time would be too short)."""

import sys
from importlib.metadata import entry_points
from pathlib import Path

import pytest

from abm.registry import target_of
from analysis.sweep.spec import load_sweep
from tests.scripts import load_benchmark

ROOT = Path(__file__).resolve().parents[1]


bench = load_benchmark("bench_reproductions")


def test_every_model_with_paper_figures_has_a_figure_set():
    # the project's own models (other tests register more at run time); flocking is the
    # public benchmark model: speed, not a paper's figures
    entries = entry_points(group="swarm_abm.models")
    ours = {entry.name for entry in entries if entry.value.startswith("models.")}
    assert set(bench.FIGURE_SETS) == ours - {"flocking"}


@pytest.mark.parametrize("model", sorted(bench.FIGURE_SETS))
def test_a_figure_set_is_sweeps_of_its_model_that_its_readme_runs(model):
    readme = (ROOT / "models" / model.replace("-", "_") / "README.md").read_text()
    for group in bench.FIGURE_SETS[model]:
        for name in group:
            sweep = load_sweep(ROOT / "experiments" / f"{name}.toml")
            assert sweep.target == target_of(model)
            assert f"experiments/{name}.toml" in readme
    if model in bench.FITS:
        assert f"abm fit {model} --read" in readme


def test_a_folder_that_already_holds_runs_is_refused_before_any_run(tmp_path, monkeypatch, capsys):
    (tmp_path / "sugarmap" / "sugarmap_fig5").mkdir(parents=True)
    argv = ["bench_reproductions.py", "--models", "sugarmap", "--out", str(tmp_path)]
    monkeypatch.setattr(sys, "argv", argv)
    with pytest.raises(SystemExit) as stop:
        bench.main()
    assert stop.value.code == 2
    err = capsys.readouterr().err.strip().splitlines()[-1]
    assert "already holds runs of sugarmap" in err and "fresh --out" in err


@pytest.mark.parametrize(
    ("flags", "says"),
    [(["--workers", "0"], "--workers must be 1 or more processes, got 0"),
     (["--replications", "-1"], "--replications must be 1 or more, got -1")],
)  # fmt: skip
def test_bad_counts_are_refused_in_one_line(flags, says, tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(sys, "argv", ["bench_reproductions.py", "--out", str(tmp_path), *flags])
    with pytest.raises(SystemExit) as stop:
        bench.main()
    assert stop.value.code == 2 and says in capsys.readouterr().err
    assert not any(tmp_path.iterdir())  # nothing was run
