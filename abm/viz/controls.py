"""Inputs and live series of a model's page, derived from the model contract (no Solara here).

:func:`default_controls` turns a model's ``Params`` into SolaraViz input specs: a checkbox for
a True/False parameter, a select for one with choices, a slider for a number with its
accepted range. A model's ``app.py`` may pick and label its own instead.
"""

import dataclasses
from collections.abc import Mapping

from abm.params import SwarmParams, field_help, field_rule, param_fields

__all__ = ["default_controls", "default_series", "initial_kwargs", "slider"]

#: Parameters of every model (the framework's) that a page leaves at their defaults.
_FRAMEWORK = {f.name for f in dataclasses.fields(SwarmParams)}


def slider(label: str, value: float, low: float, high: float, step: float) -> dict:
    """A SolaraViz slider spec: an integer slider for an int ``value``, else a float slider."""
    kind = "SliderInt" if isinstance(value, int) and not isinstance(value, bool) else "SliderFloat"
    return {"type": kind, "label": label, "value": value, "min": low, "max": high, "step": step}


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
    controls["seed"] = slider("seed", seed, 0, 100, 1)
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
        low = rule.get("low")
        high = rule.get("high")
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
