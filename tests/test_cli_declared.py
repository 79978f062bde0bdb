"""`abm run MODEL --help` and the parameter check read a model's ``Params`` from its source
(:mod:`abm.declared`) and get exactly what the model class has: the same fields, rules, help,
names, fault keywords and description, so the same values are refused with the same words.
A model of any other shape (a plugin with its params in its model module, a computed
``FAULTS``, ...) is imported as before and answers the same.
"""

import dataclasses
import itertools
import sys
from functools import cache
from importlib.metadata import entry_points
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from abm import registry
from abm.contract import description
from abm.declared import Declared, declared_params
from abm.errors import ABMError, ContractError
from abm.params import FAULT_KEYWORDS, FAULT_PARAMS, field_help, make_params
from analysis.cli import main
from analysis.cli.run import model_parser

#: The project's own models: name -> "module:Class".
PROJECT = {
    ep.name: ep.value
    for ep in entry_points(group=registry.ENTRY_POINT_GROUP)
    if ep.value.startswith("models.")
}


@cache
def _read(target: str) -> Declared | None:
    return declared_params(target)


def _shape(found: Declared) -> dict:
    """Everything of a model's Params and description the CLI and the checks read."""
    params = found.params
    return {
        "names": (params.__name__, params.__qualname__, params.__module__),
        "owner": (params.fault_owner, params.fault_kinds_declared),
        "fields": [
            (f.name, f.type, repr(f.default), dict(f.metadata)) for f in dataclasses.fields(params)
        ],
        "help": field_help(params),
        "description": found.description,
    }


def _of_class(name: str) -> Declared:
    cls = registry.model_class(name)
    return Declared(cls.Params, description(cls))


# ------------------------------------------------------------------- the project's models
@pytest.mark.parametrize("name", sorted(PROJECT))
def test_every_project_model_is_read_from_source_as_its_class_has_it(name):
    """Each model of the project is read without importing it, and what is read is what the
    imported class has; ``abm run NAME --help`` prints the same text from either.
    """
    found = _read(PROJECT[name])
    assert found is not None, f"{name}: its source is not read (the class is imported)"
    cls = _of_class(name)
    assert _shape(found) == _shape(cls)
    assert (
        model_parser(name, found.params, found.description).format_help()
        == model_parser(name, cls.params, cls.description).format_help()
    )


def _verdict(params_cls: type, given: dict) -> tuple:
    """What making params from ``given`` gives: the plain values, or the error and its words."""
    try:
        return ("made", make_params(params_cls, given).plain())
    except ABMError as exc:
        return (type(exc).__name__, str(exc))


_VALUES = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(-(10**6), 10**6),
    st.floats(allow_nan=True, allow_infinity=True),
    st.sampled_from(["", "none", "corridor", "open", "high", "stuck", "hall100", "x"]),
    st.lists(st.floats(-10, 10), max_size=3),
)


@settings(max_examples=150, deadline=None)
@given(data=st.data())
def test_the_same_values_are_accepted_or_refused_with_the_same_words(data):
    """Any value for any field (or a fault keyword, or an unknown name) gets the same verdict
    from the Params read from source as from the class's: the same values, or the same error
    in the same words.
    """
    name = data.draw(st.sampled_from(sorted(PROJECT)), label="model")
    found, cls = _read(PROJECT[name]), registry.model_class(name)
    fields = [f.name for f in dataclasses.fields(cls.Params)]
    keys = data.draw(
        st.lists(st.sampled_from([*fields, *FAULT_KEYWORDS, "no_such_field"]), max_size=3),
        label="keywords",
    )
    given = {key: data.draw(_VALUES, label=key) for key in keys}
    assert _verdict(found.params, given) == _verdict(cls.Params, given)


# ------------------------------------------------------------------- plugin models
_PARAMS = '''
from dataclasses import dataclass

from abm.params import SwarmParams, param


@dataclass(frozen=True)
class PlugParams(SwarmParams):
    """A plugin's parameters.

    Attributes:
        speed: how fast a robot flies (m/s).

    """

    speed: float = param(1.0, low=0.0, low_open=True)
'''

_MODEL = '''
"""A plugin's model."""

import numpy as np

from abm.arena import Arena
from abm.model import SwarmModel
{imports}

{before}
class Model({base}):
    {doc}

{body}
    STATES = ("idle",)

    def __init__(self, *, seed=None, **params):
        free = np.ones((4, 4), dtype=bool)
        super().__init__(self.make_params(**params), Arena(free, 1.0), seed=seed)
{after}
'''

_counter = itertools.count()


@pytest.fixture(scope="module")
def plugins(tmp_path_factory):
    """Write plugin packages into a folder on ``sys.path``; register each under a name."""
    folder = tmp_path_factory.mktemp("plugins")
    sys.path.insert(0, str(folder))
    made: list[str] = []

    def write(
        model: dict, params: str = _PARAMS, init: str | None = None, via_package=True
    ) -> tuple[str, str]:
        package = f"plug_{next(_counter)}"
        root = folder / package
        root.mkdir()
        fields = {"imports": "", "before": "", "base": "SwarmModel", "body": "", "after": ""}
        fields |= model
        if init is None:
            init = '"""A plugin."""\n\nfrom PACKAGE.model import Model\n'
        for file, text in (("model.py", _MODEL.format(**fields)), ("params.py", params),
                           ("__init__.py", init)):  # fmt: skip
            (root / file).write_text(text.replace("PACKAGE", package))
        target = f"{package}:Model" if via_package else f"{package}.model:Model"
        name = package.replace("_", "-")
        registry.register(name, target)
        made.append(name)
        return name, target

    yield write
    for name in made:
        registry.unregister(name)
    for module in [m for m in sys.modules if m.startswith("plug_")]:
        del sys.modules[module]
    sys.path.remove(str(folder))


def _faults_line(kinds: list[str] | None, style: str) -> str:
    if kinds is None:
        return ""
    if not kinds:
        return "    FAULTS = frozenset()\n"
    items = ", ".join(repr(k) for k in kinds)
    literal = {"set": f"{{{items}}}", "tuple": f"({items},)", "list": f"[{items}]"}[style]
    return f"    FAULTS = frozenset({literal})\n"


_DOCS = st.text(
    st.characters(codec="utf-8", exclude_categories=("Cs", "Cc")), min_size=1, max_size=30
).filter(lambda text: text.strip())


@settings(
    max_examples=25, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(
    kinds=st.none() | st.lists(st.sampled_from(sorted(FAULT_PARAMS)), unique=True),
    style=st.sampled_from(["set", "tuple", "list"]),
    relative=st.booleans(),
    own_params=st.booleans(),
    via_package=st.booleans(),
    doc=_DOCS,
)
def test_a_plain_plugin_is_read_without_importing_its_model(
    plugins, kinds, style, relative, own_params, via_package, doc
):
    """A plugin declaring its Params (imported from its params module, absolutely or
    relatively, or not at all), its FAULTS (absent, empty or any kinds, as a set, tuple or
    list) and a docstring plainly is read without importing its package or model module,
    and exactly as its class has them.
    """
    source = (
        "from .params import PlugParams" if relative else "from PACKAGE.params import PlugParams"
    )
    model = {
        "imports": source if own_params else "",
        "doc": repr(doc),
        "body": ("    Params = PlugParams\n" if own_params else "") + _faults_line(kinds, style),
    }
    name, target = plugins(model, via_package=via_package)
    package = target.partition(".")[0].partition(":")[0]
    found = registry.declared(name)
    assert package not in sys.modules and f"{package}.model" not in sys.modules
    assert _shape(found) == _shape(_of_class(name))


_NESTED = """
    @dataclass(frozen=True)
    class Params(SwarmParams):
        \"\"\"Nested.

        Attributes:
            speed: how fast a robot flies (m/s).

        \"\"\"

        speed: float = param(1.0)
"""

_BASE = """
class Base(SwarmModel):
    \"\"\"A base model with robot faults.\"\"\"

    Params = PlugParams
    FAULTS = frozenset({"robot"})
    STATES = ("idle",)

    def __init__(self, *, seed=None, **params):
        free = np.ones((4, 4), dtype=bool)
        super().__init__(self.make_params(**params), Arena(free, 1.0), seed=seed)

"""

_IMPORT = "from PACKAGE.params import PlugParams"
_DATACLASS = "from dataclasses import dataclass\n\nfrom abm.params import SwarmParams, param"

#: Models of other shapes: each is imported to know its Params, and answers as its class.
OTHER_SHAPES = {
    "Params defined in the model's module": {
        "imports": _DATACLASS,
        "before": _PARAMS.split("\n", 5)[5].replace("PlugParams", "OwnParams"),
        "body": "    Params = OwnParams\n",
    },
    "Params as a class nested in the model": {"imports": _DATACLASS, "body": _NESTED},
    "a computed FAULTS": {
        "imports": _IMPORT,
        "before": 'KINDS = ("robot",)\n',
        "body": "    Params = PlugParams\n    FAULTS = frozenset(KINDS)\n",
    },
    "a decorator": {
        "imports": _IMPORT,
        "before": "def keep(cls):\n    return cls\n\n\n@keep",
        "body": "    Params = PlugParams\n",
    },
    "another model as the base": {"imports": _IMPORT, "before": _BASE, "base": "Base"},
    "a class keyword": {"imports": _IMPORT, "base": "SwarmModel, **{}"},
    "FAULTS changed after the class": {
        "imports": _IMPORT,
        "body": "    Params = PlugParams\n",
        "after": 'Model.FAULTS = frozenset({"robot"})\n',
    },
    "Params imported in a try block": {
        "imports": f"try:\n    {_IMPORT}\nexcept ImportError:\n    raise",
        "body": "    Params = PlugParams\n",
    },
    "a star import": {
        "imports": "from PACKAGE.params import *  # noqa: F403",
        "body": "    Params = PlugParams\n",
    },
}


@pytest.mark.parametrize("shape", sorted(OTHER_SHAPES))
def test_a_model_of_another_shape_is_imported_and_answers_as_its_class(plugins, shape):
    """A plugin that does not declare its Params and FAULTS plainly (its params in its model
    module, say) is not read from source: its class is imported, and ``abm run`` works.
    """
    name, target = plugins({"doc": repr("A plugin of another shape."), **OTHER_SHAPES[shape]})
    assert declared_params(target) is None
    assert _shape(registry.declared(name)) == _shape(_of_class(name))


def test_a_model_without_a_docstring_is_refused_as_before(plugins):
    """No docstring: no description to read, so the class is imported and the contract
    refuses it, naming what is missing, as ``model_class`` does.
    """
    name, target = plugins({"imports": _IMPORT, "doc": "", "body": "    Params = PlugParams\n"})
    assert declared_params(target) is None
    with pytest.raises(ContractError, match="has no docstring"):
        registry.declared(name)


def test_a_params_module_that_fails_fails_as_the_models_import_does(plugins):
    """A params module that raises is not hidden by the reading from source: the class is
    imported, which raises the same error as it always did.
    """
    broken = _PARAMS + '\nraise RuntimeError("this params module is broken")\n'
    model = {"imports": _IMPORT, "doc": '"A model."', "body": "    Params = PlugParams\n"}
    name, target = plugins(model, params=broken)
    assert declared_params(target) is None
    with pytest.raises(RuntimeError, match="this params module is broken"):
        registry.declared(name)


def test_registering_a_name_again_forgets_what_was_read_for_it(plugins):
    """``register`` of a name already read answers with the new model's Params."""
    robot = {"imports": _IMPORT, "doc": '"Robot faults."', "body": _faults_line(["robot"], "set")}
    name, _ = plugins(robot)
    assert registry.declared(name).params.fault_kinds_declared == {"robot"}
    _, other = plugins({"imports": _IMPORT, "doc": '"No faults."'})
    registry.register(name, other)
    assert registry.declared(name).params.fault_kinds_declared == frozenset()
    assert registry.declared(name).description == "No faults."


@pytest.mark.parametrize("shape", ["plain", "Params defined in the model's module"])
def test_abm_run_of_a_plugin_answers_help_and_refuses_a_bad_value_in_one_line(
    plugins, shape, capsys
):
    """``abm run`` of a plugin, read from source or imported, prints its flags and refuses a
    bad value in one line naming the parameter and the rule.
    """
    plain = {"imports": _IMPORT, "body": "    Params = PlugParams\n"}
    model = plain if shape == "plain" else OTHER_SHAPES[shape]
    name, _ = plugins({"doc": '"A plugin."', **model})
    with pytest.raises(SystemExit) as done:
        main(["run", name, "--help"])
    assert done.value.code == 0
    out = capsys.readouterr().out
    assert out.startswith(f"usage: abm run {name} ") and "A plugin." in out and "--speed" in out
    assert main(["run", name, "--speed", "-1"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ["abm run: error: speed must be in (0, inf], got -1.0"]


def test_a_model_read_from_source_that_breaks_the_contract_is_refused_before_any_work(
    plugins, tmp_path, monkeypatch, capsys
):
    """Reading a model from source checks only what help and the parameters need; the rest
    of the contract is checked when the class is imported, still before the run: a run of a
    plain-shaped model whose STATES is no tuple is refused in one line, and no run folder is
    made.
    """
    model = {"imports": _IMPORT, "doc": '"A broken model."', "body": "    Params = PlugParams\n"}
    name, target = plugins(model)
    package = target.partition(":")[0]
    folder = next(Path(p) for p in sys.path if (Path(p) / package).is_dir())
    path = folder / package / "model.py"
    path.write_text(path.read_text().replace('STATES = ("idle",)', 'STATES = "idle"'))
    assert declared_params(target) is not None
    monkeypatch.chdir(tmp_path)
    assert main(["run", name, "--speed", "2"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "STATES must be a non-empty tuple of state names" in err[0]
    assert not (tmp_path / "out").exists()
