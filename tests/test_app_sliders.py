"""The pages' sliders take their bounds from the models' ``Params``, never restated.

Each model's ``app.py`` builds its sliders with :func:`abm.viz.controls.param_slider`; the bounds
must be the range the field declares for a slider (``shown``) or, without one, the range it
accepts; a declared ``shown`` range must lie inside the accepted one.
"""

import importlib
import sys
import types

import pytest
from hypothesis import given
from hypothesis import strategies as st

from abm.errors import ConfigError
from abm.params import field_rule, param, param_fields
from abm.viz.controls import SEEDS

MODELS = ("flocking", "beacon_explorer", "hierarchy", "stigmergy", "sugarmap", "tangible_pso")
SLIDERS = ("SliderInt", "SliderFloat")


def _app(name: str, monkeypatch) -> types.ModuleType:
    """The model's ``app`` module, imported without Solara (the page itself is not built)."""
    page = types.ModuleType("abm.viz.page")
    page.make_page = lambda *args, **kwargs: None
    monkeypatch.setitem(sys.modules, "abm.viz.page", page)
    key = f"models.{name}.app"
    # setitem records the real module (or its absence) for teardown: the stubbed import must
    # not outlive the test, or the live page would find an app without its page
    monkeypatch.setitem(sys.modules, key, types.ModuleType(key))
    del sys.modules[key]
    return importlib.import_module(key)


def _sliders(app: types.ModuleType) -> dict[str, dict]:
    return {
        key: spec
        for key, spec in app.MODEL_PARAMS.items()
        if isinstance(spec, dict) and spec.get("type") in SLIDERS
    }


@pytest.mark.parametrize("name", MODELS)
def test_slider_bounds_are_the_params_ranges(name, monkeypatch):
    app = _app(name, monkeypatch)
    rules = {f.name: field_rule(f) for f in param_fields(app.P)}
    sliders = _sliders(app)
    seed = sliders.pop("seed")
    assert (seed["min"], seed["max"]) == SEEDS
    assert sliders, f"{name}: no slider besides the seed"
    for key, spec in sliders.items():
        rule = rules[key]
        expected = rule.get("shown") or (rule.get("low"), rule.get("high"))
        assert (spec["min"], spec["max"]) == tuple(expected), f"{name}.{key}"


@given(
    low=st.floats(-10, 10),
    width=st.floats(0.1, 10),
    a=st.floats(-30, 30),
    b=st.floats(-30, 30),
    low_open=st.booleans(),
)
def test_a_shown_range_outside_the_accepted_one_is_refused(low, width, a, b, low_open):
    high = low + width
    inside = a < b and (a > low or (a == low and not low_open)) and b <= high
    if inside:
        shown = field_rule(param(a, low=low, high=high, low_open=low_open, shown=(a, b)))["shown"]
        assert shown == (a, b)
    else:
        with pytest.raises(ConfigError, match="shown range"):
            param(a, low=low, high=high, low_open=low_open, shown=(a, b))
