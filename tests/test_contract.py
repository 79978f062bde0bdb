"""The model contract: every registered model, and a model defined only in the tests, gets
every tool (construction, a run, mesa.batch_run, abm run, abm sweep + abm report, abm render,
abm fit, the viz page) without a line of abm/ or analysis/ written for it."""

import dataclasses
import inspect

import mesa
import numpy as np
import pandas as pd
import pytest

from abm import registry
from abm.contract import check_model
from abm.errors import ConfigError, ContractError
from abm.model import SwarmModel
from abm.params import SwarmParams, field_help, param
from analysis.cli import main
from analysis.run_folder import load_run

#: A short run of every model (s of simulated time): stigmergy launches its first wanders.
SHORT = 120.0
#: Every model of the registry (a new model is tested here as soon as it is registered), and
#: the tiny one of the tests.
ALL = sorted({*registry.model_names(), "tiny"})


@pytest.fixture(params=ALL)
def name(request, tiny_package) -> str:
    """Each model name; "tiny" comes from an entry point of a package made in the test."""
    return request.param


def _quick(name: str) -> dict:
    """The keywords of a short run of the model: its QUICK set-up, stopped at SHORT."""
    return {**registry.model_class(name).QUICK, "time_limit": SHORT}


def _flags(name: str) -> list[str]:
    """The same as ``abm run`` flags."""
    pairs = [(f"--{k.replace('_', '-')}", str(v)) for k, v in _quick(name).items()]
    return [word for pair in pairs for word in pair]


def _sets(name: str) -> list[str]:
    """The same as ``abm fit --set`` words."""
    return [word for k, v in _quick(name).items() for word in ("--set", f"{k}={v}")]


def _wrote(out: str) -> list:
    from pathlib import Path

    return [Path(line[6:].strip()) for line in out.splitlines() if line.startswith("wrote ")]


def test_the_registry_lists_the_models_and_the_tiny_one_comes_from_an_entry_point(tiny_package):
    assert {"beacon-explorer", "stigmergy", "tiny"} <= set(registry.model_names())
    import tiny_model

    assert registry.model_class("tiny") is tiny_model.TinyModel
    assert registry.name_of(tiny_model.TinyModel) == "tiny"


def test_each_model_keeps_the_contract(name):
    cls = registry.model_class(name)
    check_model(cls)
    fields = [f.name for f in dataclasses.fields(cls.Params)]
    signature = inspect.signature(cls)
    assert list(signature.parameters) == ["seed", *fields]  # every field is a keyword
    helps = field_help(cls.Params)
    assert all(helps[f] for f in fields)


def test_each_model_runs_with_defaults_and_has_the_common_summary(name):
    cls = registry.model_class(name)
    model = cls(seed=3, **_quick(name))
    assert model.time == 0.0
    model.run()
    summary = model.summary()
    assert {"time", "end_reason"} <= set(summary)
    assert summary["time"] == model.time <= SHORT
    if cls.CONTACTS:  # else no collision counts (test_collision_counts_are_in_a_summary...)
        assert summary["collisions"] == summary["wall_collisions"] + summary["robot_collisions"]
    assert ("coverage_area" in summary) == (model.coverage is not None)
    assert ("energy_total" in summary) == model.ledger.has_powers
    if model.coverage is not None:
        assert 0 < summary["coverage_area"] <= 100
    counts = model.state_counts()
    assert list(counts.columns) == ["time", *model.STATES]
    assert counts["time"].is_monotonic_increasing
    again = cls(seed=3, **_quick(name)).run()
    pd.testing.assert_frame_equal(model.events(), again.events())


def test_each_model_decides_the_same_without_its_position_trace(name):
    """A sweep runs models without the position trace (``analysis.runner.run_one``): it must
    change no event, count or summary value, only what ``abm render`` would draw.
    """
    cls = registry.model_class(name)
    traced = cls(seed=5, **{**_quick(name), "trace_interval": 0.5}).run()
    plain = cls(seed=5, **{**_quick(name), "trace_interval": None}).run()
    assert not traced.positions().empty and plain.positions().empty
    pd.testing.assert_frame_equal(traced.events(), plain.events())
    pd.testing.assert_frame_equal(traced.state_counts(), plain.state_counts())
    assert repr(traced.summary()) == repr(plain.summary())


def test_each_model_runs_under_mesa_batch_run(name):
    cls = registry.model_class(name)
    rows = pd.DataFrame(
        mesa.batch_run(
            cls,
            parameters=_quick(name),
            rng=[1, 2],
            max_steps=8,
            number_processes=1,
            display_progress=False,
        )  # fmt: skip
    )
    assert len(rows) == 2 and sorted(rows["seed"]) == [1, 2]
    assert set(cls.STATES) <= set(rows.columns)
    model = cls(seed=1, **_quick(name))
    for _ in range(8):
        model.step()
    assert model.time == pytest.approx(8 * model.step_duration)


def test_abm_run_then_render_shows_coverage_where_the_model_covers(name, tmp_path, capsys):
    out = tmp_path / "run"
    assert main(["run", name, *_flags(name), "--seed", "2", "--out", str(out)]) == 0
    assert all(p.exists() for p in _wrote(capsys.readouterr().out))
    run = load_run(out)
    covers = registry.model_class(name)(seed=2, **_quick(name)).coverage is not None
    assert (run.first_covered is not None) == covers
    assert main(["render", str(out), "--times", str(run.end_time), "--no-gif"]) == 0
    (png,) = _wrote(capsys.readouterr().out)
    image = np.asarray(__import__("PIL.Image", fromlist=["Image"]).open(png).convert("RGB"))
    alpha = 0.75  # the covered-area colour as the scene draws it over the white floor
    green = alpha * np.array([0x9B, 0xE3, 0xA4]) + (1 - alpha) * 255
    covered_pixels = int((np.abs(image.astype(int) - green).max(axis=-1) < 6).sum())
    assert (covered_pixels > 1000) == covers, covered_pixels
    for style in run.styles.values():  # every state is drawn in its declared colour
        colour = np.array([int(style.colour[i : i + 2], 16) for i in (1, 3, 5)])
        assert (np.abs(image.astype(int) - colour).max(axis=-1) < 30).any()


def test_abm_sweep_and_report(name, tmp_path, capsys):
    sweep = tmp_path / f"{name}.toml"
    grid = "".join(f"{k} = [{v!r}]\n" for k, v in _quick(name).items()).replace("'", '"')
    sweep.write_text(f'model = "{name}"\nseed = 1\nreplications = 2\n[grid]\n{grid}')
    out = tmp_path / "sweep"
    assert main(["sweep", str(sweep), "--executor", "serial", "--out", str(out)]) == 0
    capsys.readouterr()
    assert main(["report", str(out)]) == 0
    assert all(p.exists() for p in _wrote(capsys.readouterr().out))
    html = (out / "report.html").read_text()
    published = registry.model_class(name).PUBLISHED
    assert ("Published numbers beside ours" in html) == bool(published)
    assert "runs finished / failed" in html and "2 / 0" in html


def test_abm_fit_of_each_model_that_counts_two_states(name, tmp_path, capsys):
    cls = registry.model_class(name)
    out = tmp_path / "fit"
    args = ["fit", name, *_sets(name), "--runs", "2", "--workers", "1"]
    if len(cls.STATES) < 2:  # nothing changes state: refused before any run, naming why
        assert main([*args, "--out", str(out)]) != 0
        assert "a macroscopic model needs robots that change state" in capsys.readouterr().err
        assert not out.exists()
        return
    if cls.MACRO is None:  # rate equations from the model's own event log
        assert main([*args, "--held", "1", "--out", str(out)]) == 0
        printed = capsys.readouterr().out
        rates = pd.read_csv(out / "rates.csv")
        fit = pd.read_csv(out / "fit.csv")
        assert set(rates["source"]) <= {*cls.STATES, "(launch)"}  # the model's own states
        assert list(fit["state"]) == list(cls.STATES)
        # a state no run occupies is left unchecked (NaN), the others are shares of N
        assert fit.loc[fit["occupied"], "rmsd"].between(0, 1).all()
        assert fit.loc[~fit["occupied"], "rmsd"].isna().all()
        assert (out / "curves.png").is_file() and "held-out seeds" in printed
        page = (out / "rates_report.html").read_text()
        assert "The state graph" in page and all(state in page for state in cls.STATES)
        return
    assert main([*args, "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert (out / "fit_report.html").is_file()
    # the columns speak the model's states and rate names, not stigmergy's w, b, a0, alpha6
    spec, header = cls.MACRO, printed.splitlines()[0].split()
    named = spec.names()
    assert {spec.moving, spec.settled, f"rmsd_{spec.moving}_fit", named["a0"]} <= set(header)
    assert not {"w", "b"} & set(header)
    # the rate equations from the event log beside the recurrence: the same runs, same RMSD
    assert f"rmsd_{spec.moving}_rates" in header and "rate equations from the event log" in printed
    assert ("alpha6" in header) == (named["alpha6"] == "alpha6")


def test_each_model_has_a_page(name):
    pytest.importorskip("solara", reason="the viz extra is not installed")
    from abm.viz.app import page_of

    assert callable(page_of(name))


# ---------------------------------------------------------------- what the contract refuses
def test_a_class_that_breaks_the_contract_is_refused_with_a_reason():
    @dataclasses.dataclass(frozen=True)
    class Undocumented(SwarmParams):
        """No Attributes section."""

        speed: float = param(1.0)

    class NoDocs(SwarmModel):
        Params = Undocumented
        STATES = ("a",)

        def __init__(self, *, seed=None, **params):
            super().__init__(self.make_params(**params), None, seed=seed)

    with pytest.raises(ContractError, match="does not describe speed"):
        registry.register("no-docs", NoDocs)

    class Positional(SwarmModel):
        STATES = ("a",)

        def __init__(self, world, seed=None):
            pass

    with pytest.raises(ContractError, match="must be \\(self, \\*, seed=None, \\*\\*params\\)"):
        check_model(Positional)
    with pytest.raises(ContractError, match="not a subclass"):
        check_model(dict)
    assert "no-docs" not in registry.model_names()


def test_unknown_names_and_targets_are_clear_errors():
    with pytest.raises(ConfigError, match="unknown model 'ants'; known models: .*beacon"):
        registry.model_class("ants")
    with pytest.raises(
        ConfigError, match="'nowhere:Model': no module 'nowhere' on the Python path"
    ):
        registry.model_class("nowhere:Model")
    with pytest.raises(ConfigError, match="package.module:Class"):
        registry.register("x", "not-a-target")


@pytest.mark.parametrize(
    "model", [n for n in registry.model_names() if registry.model_class(n).CUT_ENDS]
)
def test_a_run_the_time_limit_stops_ends_as_the_models_cut_ends_say(model):
    # the report refuses runs whose end_reason starts with one of CUT_ENDS; a model whose
    # time limit wrote another reason would have its cut runs judged as finished
    cls = registry.model_class(model)
    run = cls(seed=1, **{**cls.QUICK, "time_limit": 1.0})
    run.run()
    assert run.summary()["end_reason"].startswith(cls.CUT_ENDS)
    assert not "complete".startswith(cls.CUT_ENDS) and not "horizon".startswith(cls.CUT_ENDS)


def test_cut_ends_must_be_a_tuple_of_end_reasons():
    class Cut(SwarmModel):
        """A model whose CUT_ENDS is a bare string."""

        STATES = ("idle",)
        CUT_ENDS = "time limit"

        def __init__(self, *, seed=None, **params):
            super().__init__(self.make_params(**params), None, seed=seed)

    with pytest.raises(ContractError, match="CUT_ENDS must be a tuple"):
        check_model(Cut)


@pytest.mark.parametrize("model", registry.model_names())
def test_collision_counts_are_in_a_summary_only_where_robots_can_touch(model):
    # flocking's birds and tangible PSO's MAVs never touch: "collisions 0" would read as a
    # measurement, and collision_rows as a setting that acts
    cls = registry.model_class(model)
    summary = cls(seed=1, **_quick(model)).summary()
    keys = {"collisions", "wall_collisions", "robot_collisions"}
    assert (keys <= set(summary)) is cls.CONTACTS
    assert not (keys & set(summary)) or cls.CONTACTS
    if not cls.CONTACTS:
        with pytest.raises(ConfigError, match="collision_rows: .* never touch"):
            cls(seed=1, collision_rows=0)
