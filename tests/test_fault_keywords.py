"""Fault keywords exist only for the fault kinds a model declares (``SwarmModel.FAULTS``):
a model that handles none has none, and a keyword of another kind is refused in one line
naming the model and the kinds it handles, wherever it is given (Python, abm run, a sweep).
"""

import dataclasses
import inspect
import pickle

import pytest

from abm import registry
from abm.errors import ConfigError
from abm.model import SwarmModel
from abm.params import FAULT_KEYWORDS, FAULT_PARAMS, SwarmParams, param
from analysis.cli import main


@pytest.mark.parametrize("name", registry.model_names())
def test_a_models_keywords_are_its_fields_and_the_faults_it_declares(name):
    cls = registry.model_class(name)
    keywords = set(inspect.signature(cls).parameters) - {"seed"}
    declared = {f.name for kind in cls.FAULTS for f in dataclasses.fields(FAULT_PARAMS[kind])}
    assert keywords & FAULT_KEYWORDS.keys() == declared
    # the params of a run cross process boundaries in sweeps: they pickle as the model's own
    params = cls.make_params(**cls.QUICK)
    assert pickle.loads(pickle.dumps(params)) == params


def test_a_model_without_faults_has_no_fault_keyword_and_refuses_them():
    @dataclasses.dataclass(frozen=True)
    class EightParams(SwarmParams):
        """Eight fields of its own.

        Attributes:
            a: one.
            b: two.
            c: three.
            d: four.
            e: five.
            f: six.
            g: seven.
            h: eight.

        """

        a: float = param(1.0)
        b: float = param(1.0)
        c: float = param(1.0)
        d: float = param(1.0)
        e: float = param(1.0)
        f: float = param(1.0)
        g: float = param(1.0)
        h: float = param(1.0)

    class Eight(SwarmModel):
        Params = EightParams
        STATES = ("idle",)

    own = {f.name for f in dataclasses.fields(SwarmParams)} | set("abcdefgh")
    assert {f.name for f in dataclasses.fields(Eight.Params)} == own  # 8 + the run's, no faults
    with pytest.raises(ConfigError, match=r"^fault_rate=0.1: Eight does not handle robot "
                                          r"faults \(it handles: none\)"):  # fmt: skip
        Eight.make_params(fault_rate=0.1)

    class Linked(Eight):
        FAULTS = frozenset({"link"})

    assert {f.name for f in dataclasses.fields(Linked.Params)} - own == {
        f.name for f in dataclasses.fields(FAULT_PARAMS["link"])
    }
    assert Linked.make_params(link_outage_rate=0.5).fault_kinds == {"link"}


def test_abm_run_and_sweep_refuse_an_unsupported_kind_in_one_line(tmp_path, capsys):
    assert main(["run", "flocking", "--fault-rate", "0.1", "--time-limit", "5"]) == 2
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert "FlockingModel does not handle robot faults (it handles: none)" in line
    sweep = tmp_path / "s.toml"
    sweep.write_text('model = "stigmergy"\n[grid]\nlink_outage_rate = [0.0, 0.1]\n')
    assert main(["sweep", str(sweep), "--out", str(tmp_path / "out")]) == 2
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert "StigmergyModel does not handle link faults (it handles: robot)" in line
    assert not (tmp_path / "out").exists()
