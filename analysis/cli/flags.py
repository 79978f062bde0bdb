"""Command-line flags generated from a model's params dataclass (one flag per field).

``--launch-period 6`` sets ``launch_period``; a True/False field gets ``--hover-beacons`` /
``--no-hover-beacons``; a field that may be None accepts ``none``; a point takes two numbers.
The help text of each flag is the field's docstring text, and only the flags given are passed
to the model (its own defaults apply to the rest).
"""

import argparse
import dataclasses
import types
import typing

from abm.params import FAULT_KEYWORDS, field_help, field_rule, param_fields, refuse_fault_keyword

__all__ = ["add_param_flags", "flag_name", "given_params", "parse_assignment", "seed_argument"]

_DEST = "param__"


def flag_name(field_name: str) -> str:
    """``launch_period`` -> ``--launch-period``."""
    return "--" + field_name.replace("_", "-")


def add_param_flags(parser: argparse.ArgumentParser, params_cls: type) -> None:
    """One flag per field of ``params_cls``, grouped under "model parameters"."""
    helps = field_help(params_cls)
    group = parser.add_argument_group(
        "model parameters", f"every field of {params_cls.__name__}; defaults in brackets"
    )
    for f in param_fields(params_cls):
        kwargs = _flag(f)
        text = helps.get(f.name, "").replace("``", "").replace("%", "%%")
        default = f.default if f.default is not dataclasses.MISSING else None
        kwargs["help"] = f"{text} [{_shown(default)}]"
        group.add_argument(
            flag_name(f.name), dest=_DEST + f.name, default=argparse.SUPPRESS, **kwargs
        )
    fields = {f.name for f in param_fields(params_cls)}
    for name in FAULT_KEYWORDS.keys() - fields:  # kinds the model does not handle: one line
        parser.add_argument(flag_name(name), nargs="*", help=argparse.SUPPRESS,
                            action=_Refused, params_cls=params_cls)  # fmt: skip


class _Refused(argparse.Action):
    """A fault keyword of a kind the model does not handle: refused naming the kinds it does."""

    def __init__(self, *args, params_cls: type, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        self.params_cls = params_cls

    def __call__(self, parser, namespace, values, option_string=None) -> None:
        refuse_fault_keyword(self.params_cls, self.dest, " ".join(values) or None)


def given_params(args: argparse.Namespace) -> dict:
    """The model parameters the user gave, by field name ("none" given as None)."""
    return {
        k[len(_DEST) :]: None if v == "none" else v
        for k, v in vars(args).items()
        if k.startswith(_DEST)
    }


def _flag(f: dataclasses.Field) -> dict:
    args = typing.get_args(f.type) if _is_union(f.type) else (f.type,)
    optional = type(None) in args
    kinds = [a for a in args if a is not type(None)]
    rule = field_rule(f)
    if kinds == [bool]:
        return {"action": argparse.BooleanOptionalAction}
    tuple_args = next((typing.get_args(k) for k in kinds if typing.get_origin(k) is tuple), None)
    if tuple_args:
        item = tuple_args[0] if tuple_args[0] in (int, float) else str
        nargs = "*" if Ellipsis in tuple_args else len(tuple_args)
        return {"nargs": nargs, "type": _maybe_none(item, optional), "metavar": "V"}
    if float in kinds and len(kinds) == 1:
        return {"type": _maybe_none(float, optional), "metavar": "X"}
    if int in kinds and len(kinds) == 1:
        return {"type": _maybe_none(int, optional), "metavar": "N"}
    if rule.get("choices"):
        return {"choices": [*rule["choices"], *(["none"] if optional else [])]}
    return {"type": _maybe_none(str, optional), "metavar": "VALUE"}


def _is_union(annotation) -> bool:
    return typing.get_origin(annotation) in (typing.Union, types.UnionType)


def _maybe_none(convert, optional: bool):
    def parse(text: str):
        if optional and text.lower() == "none":
            return None
        return convert(text)

    parse.__name__ = convert.__name__  # argparse names the type in its errors
    return parse


def _shown(value) -> str:
    return "none" if value is None else f"{value:g}" if isinstance(value, float) else str(value)


def parse_assignment(params_cls: type, text: str, many: bool = False) -> tuple[str, list]:
    """``"name=v1,v2"`` -> ``("name", [v1, v2])`` with each value of the field's type.

    With ``many`` False the text holds one value; it comes back as a one-item list either way,
    as a sweep grid wants. True/False fields take true/false (yes/no, 1/0); "none" is None
    where a field allows it; a point is ``x,y`` (with ``many``, points are separated by ``;``).

    Raises:
        ConfigError: no ``=``, an unknown field or a value the field does not accept.

    """
    from abm.errors import ConfigError
    from abm.params import check_value

    name, sep, values = text.partition("=")
    name = name.strip().replace("-", "_")
    if not sep or not name:
        raise ConfigError(f"expected NAME=VALUE, got {text!r}")
    fields = {f.name: f for f in param_fields(params_cls)}
    if name not in fields:
        raise ConfigError(
            f"unknown parameter {name!r}; {params_cls.__name__} accepts: " + ", ".join(fields)
        )
    flag = _flag(fields[name])
    point = "nargs" in flag
    if not many:
        items = [values]
    else:
        items = values.split(";" if point else ",")
    return name, [_one(params_cls, name, flag, item.strip(), check_value) for item in items]


def _one(params_cls, name: str, flag: dict, text: str, check_value):
    from abm.errors import ConfigError

    if text.lower() == "none":
        return check_value(params_cls, name, None)
    if flag.get("action") is argparse.BooleanOptionalAction:
        truth = {"true": True, "yes": True, "1": True, "false": False, "no": False, "0": False}
        if text.lower() not in truth:
            raise ConfigError(f"{name} takes true or false, got {text!r}")
        return check_value(params_cls, name, truth[text.lower()])
    parts = text.split(",") if "nargs" in flag else [text]
    convert = flag.get("type", str)
    try:
        parsed = [convert(part.strip()) for part in parts]
    except ValueError as exc:
        raise ConfigError(f"{name}: cannot read {text!r} ({exc})") from exc
    value = parsed if "nargs" in flag else parsed[0]
    if "choices" in flag and value not in flag["choices"]:
        choices = ", ".join(repr(c) for c in flag["choices"])
        raise ConfigError(f"{name} must be one of {choices}, got {value!r}")
    return check_value(params_cls, name, value)


def seed_argument(text: str) -> int:
    """An argparse ``type`` for every verb's ``--seed``: one integer in [0, 2**63 - 1]
    (:func:`abm.errors.parse_seed`), refused in one line before any work starts.
    """
    from abm.errors import ConfigError, parse_seed

    try:
        return parse_seed(text)
    except ConfigError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None
