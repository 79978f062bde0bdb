"""Inputs and live series of a model's page, derived from the model contract (no Solara here).

:func:`default_controls` turns a model's ``Params`` into SolaraViz input specs: a checkbox for
a True/False parameter, a select for one with choices, a slider for a number with its
accepted range. A model's ``app.py`` may pick and label its own instead, with
:func:`param_slider`, whose bounds also come from ``Params`` (the range a field declares as
``shown``, else the range it accepts), so a page never restates them.
"""

import dataclasses
from collections.abc import Mapping

from abm.errors import ConfigError
from abm.params import SwarmParams, field_help, field_rule, param_fields

__all__ = [
    "default_controls",
    "default_series",
    "initial_kwargs",
    "param_slider",
    "seed_slider",
    "slider",
    "slider_bounds",
]

#: Parameters of every model (the framework's) that a page leaves at their defaults.
_FRAMEWORK = {f.name for f in dataclasses.fields(SwarmParams)}

#: The seeds a page offers: any seed is accepted, a hundred are plenty to look at.
SEEDS = (0, 100)


def slider(label: str, value: float, low: float, high: float, step: float) -> dict:
    """A SolaraViz slider spec: an integer slider for an int ``value``, else a float slider."""
    kind = "SliderInt" if isinstance(value, int) and not isinstance(value, bool) else "SliderFloat"
    return {"type": kind, "label": label, "value": value, "min": low, "max": high, "step": step}


def slider_bounds(params_cls: type[SwarmParams], name: str) -> tuple[float, float]:
    """``(low, high)`` of a slider for field ``name``: its ``shown`` range, else its accepted one.

    Raises ConfigError when the field declares neither a ``shown`` range nor a finite accepted
    range (with an open low end, 0 itself is not accepted, so that needs ``shown`` too).
    """
    fields = {f.name: f for f in param_fields(params_cls)}
    if name not in fields:
        raise ConfigError(f"{params_cls.__name__} has no parameter {name!r} for a slider")
    rule = field_rule(fields[name])
    if rule.get("shown") is not None:
        return rule["shown"]
    low, high = rule.get("low"), rule.get("high")
    if low is None or high is None or rule.get("low_open"):
        raise ConfigError(
            f"{params_cls.__name__}.{name} declares no slider range: give param(..., shown=(low,"
            f" high)) inside its accepted range [{low}, {high}]"
        )
    return low, high


def param_slider(
    params_cls: type[SwarmParams],
    name: str,
    label: str,
    value: float | None = None,
    step: float | None = None,
) -> dict:
    """A slider for field ``name`` with its bounds from ``params_cls`` (:func:`slider_bounds`).

    Args:
        params_cls: the model's ``Params``.
        name: the field.
        label: the slider's text.
        value: the page's starting value; None: the field's default.
        step: the slider's step; None: 1 for an integer field, else a round fiftieth of the range.

    """
    low, high = slider_bounds(params_cls, name)
    f = next(f for f in param_fields(params_cls) if f.name == name)
    value = f.default if value is None else value
    if isinstance(value, int) and not isinstance(value, bool):
        return slider(label, value, int(low), int(high), 1 if step is None else step)
    if step is None:
        step = float(f"{(high - low) / 50:.1g}") or (high - low) / 50
    return slider(label, float(value), float(low), float(high), step)


def seed_slider(value: int = 1) -> dict:
    """The seed slider every page shows (:data:`SEEDS`)."""
    return slider("seed", value, *SEEDS, 1)


def default_controls(model_class: type, seed: int = 1) -> dict:
    """An input for each of the model's own simple parameters, plus a seed slider.

    Parameters without a default value of a simple kind (None, arrays, objects) keep their
    default and get no input.
    """
    helps = field_help(model_class.Params)
    controls: dict[str, object] = {}
    for f in param_fields(model_class.Params):
        if f.name in _FRAMEWORK:
            continue
        spec = _control(f, helps.get(f.name, f.name))
        if spec is not None:
            controls[f.name] = spec
    controls["seed"] = seed_slider(seed)
    return controls


def _control(f: dataclasses.Field, text: str) -> dict | None:
    label = _label(f.name, text)
    value = f.default
    rule = field_rule(f)
    if isinstance(value, bool):
        return {"type": "Checkbox", "label": label, "value": value}
    if rule.get("choices") and isinstance(value, str):
        return {"type": "Select", "label": label, "value": value, "values": list(rule["choices"])}
    if isinstance(value, int | float):
        low, high = rule.get("shown") or (rule.get("low"), rule.get("high"))
        low = 0 if low is None else low
        if high is None:
            high = max(4 * abs(value), low + 1)
        if isinstance(value, int) or rule.get("integer"):
            return slider(label, int(value), int(low), int(high), 1)
        step = float(f"{(high - low) / 50:.1g}") or (high - low) / 50
        return slider(label, float(value), float(low), float(high), step)
    return None


def _label(name: str, text: str) -> str:
    """``name`` and the unit its help text ends with, e.g. ``launch_period (s)``."""
    unit = text.rsplit("(", 1)[-1].split(")")[0] if text.rstrip(".").endswith(")") else ""
    unit = unit.split(";")[0].strip()
    return f"{name} ({unit})" if unit and len(unit) <= 8 else name


def default_series(model) -> dict[str, str]:
    """DataCollector column -> axis label: coverage and energy when the model has them."""
    series = {}
    if model.coverage is not None:
        series["coverage"] = "coverage (% of free area)"
    if model.ledger.has_powers:
        series["energy"] = "energy used (J)"
    return series


def initial_kwargs(model_params: Mapping[str, object]) -> dict:
    """Constructor keyword arguments from SolaraViz ``model_params`` (inputs give their value)."""
    return {
        key: spec["value"] if isinstance(spec, dict) and "type" in spec else spec
        for key, spec in model_params.items()
    }
