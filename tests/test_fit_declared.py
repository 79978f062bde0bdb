"""``abm fit`` asks, models declare: the recurrence's inputs are read from each run's own
parameters (no model copies its parameters into its summary for the fit), and what the fit
prints speaks the model's states and rate names, not stigmergy's w, b, a0 and alpha6.
"""

import pandas as pd
import pytest

from abm import registry
from abm.published import MacroSpec
from analysis.fit import analyse, read_runs, speak, spoken, with_parameters
from analysis.sweep import run_sweep


def test_the_fit_reads_the_runs_parameters_not_their_summaries(tiny_package, tmp_path):
    """The tiny model's summary holds no parameter; its MACRO names two (the launch period,
    set by the sweep, and the walkers, left at the default); the fit reads both per run.
    """
    cls = registry.model_class("tiny")
    summary = cls(seed=1, time_limit=30.0).run().summary()
    assert {"launch_period", "walkers"}.isdisjoint(summary)
    grid = {"launch_period": [2.0, 4.0], "time_limit": [40.0]}
    run_sweep(cls, grid, 2, 1, tmp_path, "serial", time_series=True, progress=False)
    summaries, counts, conditions = read_runs(tmp_path)
    assert conditions == ["launch_period"]
    assert sorted(summaries["launch_period"]) == [2.0, 2.0, 4.0, 4.0]
    assert (summaries["walkers"] == cls.Params().walkers).all()  # the default, never swept
    fits = analyse(summaries, counts, cls.MACRO, conditions)["fits"]
    # alpha5 = step / launch period: one arrival per launch period
    assert dict(zip(fits["launch_period"], fits["alpha5"], strict=True)) == {2.0: 0.5, 4.0: 0.25}


def test_a_parameter_the_params_derive_is_read_as_the_run_had_it():
    """Stigmergy's launch period is a property of its params (model step / launch rate)."""
    cls = registry.model_class("stigmergy")
    runs = pd.DataFrame({"run_id": ["a", "b", "c"], "launch_rate": [0.02, 0.05, float("nan")]})
    got = with_parameters(runs, cls, ["launch_rate"])
    step = cls.Params().model_step
    default = cls.Params().launch_period
    assert list(got["launch_period"]) == pytest.approx([step / 0.02, step / 0.05, default])
    assert list(got["pheromone_radius"]) == [cls.Params().pheromone_radius] * 3


def test_a_name_that_is_neither_parameter_nor_summary_key_is_refused():
    spec = MacroSpec("wander", "beacon", arrival_period="nowhere")
    runs = pd.DataFrame({"run_id": ["a"], "time": [1.0]})
    counts = pd.DataFrame({"run_id": ["a"] * 3, "time": [0.0, 1.0, 2.0], "wander": [0, 1, 1],
                           "beacon": [0, 0, 1]})  # fmt: skip
    with pytest.raises(Exception, match="'nowhere', which is neither a parameter"):
        analyse(runs, counts, spec, [])


def test_fit_columns_speak_each_models_states_and_rates():
    explorer = registry.model_class("beacon-explorer").MACRO
    assert spoken("rmsd_w_fit", explorer) == "rmsd_explorer_fit"
    assert spoken("a0_se", explorer) == "beacon_share_0_se"
    assert spoken("paper rmsd_b", explorer) == "paper rmsd_beacon"
    # the paper's own symbols where the model declares them, and words that merely contain
    # a symbol's letters are left alone
    stigmergy = registry.model_class("stigmergy").MACRO
    table = pd.DataFrame(columns=["condition", "runs", "w_hat", "alpha6", "alpha6_reg", "t"])
    assert list(speak(table, stigmergy).columns) == [
        "condition", "runs", "wander_hat", "alpha6", "alpha6_reg", "t"
    ]  # fmt: skip
    named = MacroSpec("walking", "resting", rates={"alpha6": "slowing"})
    assert spoken("rmsd_w_reg_alpha6", named) == "rmsd_walking_reg_slowing"


def test_the_contract_refuses_a_rate_the_recurrence_does_not_have():
    from abm.contract import check_model
    from abm.errors import ContractError

    cls = registry.model_class("stigmergy")
    spec = MacroSpec("wander", "beacon", rates={"alpha7": "x"})
    with pytest.raises(ContractError, match=r"MACRO.rates names \['alpha7'\]"):
        check_model(type("Odd", (cls,), {"MACRO": spec}))
