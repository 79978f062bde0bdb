"""The model contract, checked: what a class must declare before any tool will run it.

:func:`check_model` is called by the registry whenever a model is registered or resolved, so
a broken model fails with one clear :class:`~abm.errors.ContractError` naming what is missing,
not with an attribute error deep inside a report. ``docs/adding-a-model.md`` explains each
point.
"""

import dataclasses
import inspect
from collections.abc import Mapping, Sequence
from functools import cache

from abm.errors import ConfigError, ContractError
from abm.faults import FAULT_KINDS
from abm.params import SwarmParams, field_help
from abm.published import Censored, Claim, MacroSpec, Published, ReportLayout
from abm.styles import StateStyle
from abm.units import UNITS, Quantity

__all__ = ["check_model", "description"]


def check_model(cls: type) -> None:
    """Raise ContractError unless ``cls`` keeps the model contract.

    The contract: a :class:`~abm.model.SwarmModel` subclass; ``Params`` a frozen dataclass
    subclassing :class:`~abm.params.SwarmParams` whose every field has a default and is
    described in the docstring's ``Attributes:`` section, and whose defaults are valid; a
    constructor taking only ``seed`` and the params' fields as keywords; ``STATES`` a
    non-empty tuple of names; ``STATE_STYLES``, ``MACRO``, ``PUBLISHED``, ``CLAIMS``,
    ``CENSORED``, ``CUT_ENDS``, ``CONTACTS``, ``REPORT``, ``APP``, ``QUICK``, ``FAULTS`` and
    ``SUMMARY_UNITS`` of the documented types; every setting a published number's or a
    claim's condition names is a parameter; a docstring of the class's own (see
    :func:`description`).
    """
    _check(cls)


@cache
def _check(cls: type) -> None:
    from abm.model import SwarmModel

    name = getattr(cls, "__qualname__", repr(cls))
    if not (isinstance(cls, type) and issubclass(cls, SwarmModel)):
        raise ContractError(f"{name} is not a subclass of abm.model.SwarmModel")
    params = cls.Params
    if not (
        isinstance(params, type)
        and issubclass(params, SwarmParams)
        and dataclasses.is_dataclass(params)
        and params.__dataclass_params__.frozen
    ):
        raise ContractError(f"{name}.Params must be a frozen dataclass subclassing SwarmParams")
    no_default = [
        f.name
        for f in dataclasses.fields(params)
        if f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING
    ]
    if no_default:
        raise ContractError(
            f"{params.__qualname__} gives no default to {', '.join(no_default)}: every field "
            f"needs one (a run of {name} with no flags uses them all)"
        )
    try:
        params()
    except ConfigError as exc:
        raise ContractError(
            f"{name}: the defaults of {params.__qualname__} are refused: {exc}"
        ) from exc
    helps = field_help(params)
    missing = [f.name for f in dataclasses.fields(params) if f.name not in helps]
    if missing:
        raise ContractError(
            f"{params.__qualname__} does not describe {', '.join(missing)} in its docstring's "
            "Attributes: section (the CLI's help and the reports read it)"
        )
    _check_constructor(cls, name)
    states = cls.STATES
    if not (isinstance(states, tuple) and states and all(isinstance(s, str) for s in states)):
        raise ContractError(f"{name}.STATES must be a non-empty tuple of state names")
    _check_kinds(cls, name)
    for state, style in cls.STATE_STYLES.items():
        if not isinstance(style, StateStyle):
            raise ContractError(f"{name}.STATE_STYLES[{state!r}] must be an abm.styles.StateStyle")
    macro = cls.MACRO
    if macro is not None:
        if not isinstance(macro, MacroSpec):
            raise ContractError(f"{name}.MACRO must be an abm.published.MacroSpec or None")
        if not {macro.moving, macro.settled} <= set(states) or macro.moving == macro.settled:
            raise ContractError(
                f"{name}.MACRO must count two different states of STATES {states}, "
                f"got {macro.moving!r} and {macro.settled!r}"
            )
        unknown = sorted(set(macro.rates) - {"a0", "alpha6", "alpha5"})
        if unknown:
            raise ContractError(
                f"{name}.MACRO.rates names {unknown}; the recurrence's rates are a0, alpha6 "
                "and alpha5"
            )
    if not all(isinstance(p, Published) for p in cls.PUBLISHED):
        raise ContractError(f"{name}.PUBLISHED must hold abm.published.Published records")
    if not all(isinstance(c, Claim) for c in cls.CLAIMS):
        raise ContractError(f"{name}.CLAIMS must hold abm.published.Claim records")
    if not all(isinstance(c, Censored) for c in cls.CENSORED):
        raise ContractError(f"{name}.CENSORED must hold abm.published.Censored records")
    if not (isinstance(cls.CUT_ENDS, tuple) and all(isinstance(e, str) for e in cls.CUT_ENDS)):
        raise ContractError(f"{name}.CUT_ENDS must be a tuple of end_reason prefixes (str)")
    if not isinstance(cls.CONTACTS, bool):
        raise ContractError(f"{name}.CONTACTS must be True or False")
    fields = {f.name for f in dataclasses.fields(cls.Params)}
    for record in (*cls.PUBLISHED, *cls.CLAIMS):
        unknown = sorted(set(record.condition) - fields)
        if unknown:
            raise ContractError(
                f"{name}: the condition of {getattr(record, 'id', record.quantity)!r} names "
                f"{unknown}, which are not parameters of {cls.Params.__name__}"
            )
    if cls.REPORT is not None and not isinstance(cls.REPORT, ReportLayout):
        raise ContractError(f"{name}.REPORT must be an abm.published.ReportLayout or None")
    if cls.APP is not None and not isinstance(cls.APP, str):
        raise ContractError(f"{name}.APP must be a module name (str) or None")
    if not (isinstance(cls.FAULTS, frozenset) and cls.FAULTS <= FAULT_KINDS):
        raise ContractError(
            f"{name}.FAULTS must be a frozenset of fault kinds among "
            f"{', '.join(sorted(FAULT_KINDS))}, got {cls.FAULTS!r}"
        )
    units = cls.SUMMARY_UNITS
    for key, quantity in units.items():
        if not (isinstance(quantity, Quantity) and quantity.unit in UNITS):
            raise ContractError(
                f"{name}.SUMMARY_UNITS[{key!r}] must be an abm.units.Quantity whose unit is one "
                f"of {', '.join(sorted(UNITS))}, got {quantity!r}"
            )
    unknown = set(cls.QUICK) - {f.name for f in dataclasses.fields(cls.Params)}
    if unknown:
        raise ContractError(f"{name}.QUICK names no parameter: {', '.join(sorted(unknown))}")
    description(cls)


def description(cls: type) -> str:
    """The first line of a model class's own docstring: what ``abm run MODEL --help`` says
    the model is.

    A docstring is required, not inherited: a subclass without one would otherwise be
    described by its base's text (``SwarmModel``'s "Base class of every swarm model").

    Raises:
        ContractError: the class has no docstring of its own, or an empty one.

    """
    name = getattr(cls, "__qualname__", repr(cls))
    doc = cls.__dict__.get("__doc__")
    lines = inspect.cleandoc(doc).splitlines() if isinstance(doc, str) else []
    if not lines or not lines[0].strip():
        raise ContractError(
            f"{name} has no docstring: a model class needs one of its own whose first line "
            "says what the model is (abm run MODEL --help shows it)"
        )
    return lines[0].strip()


#: Declared class attributes the contract iterates, and the kind of value each must be.
_KINDS = {
    "STATE_STYLES": (Mapping, "a dict state -> abm.styles.StateStyle"),
    "SUMMARY_UNITS": (Mapping, "a dict summary key -> abm.units.Quantity"),
    "QUICK": (Mapping, "a dict parameter -> value"),
    "PUBLISHED": (Sequence, "a tuple or list of abm.published.Published"),
    "CLAIMS": (Sequence, "a tuple or list of abm.published.Claim"),
    "CENSORED": (Sequence, "a tuple or list of abm.published.Censored"),
}


def _check_kinds(cls: type, name: str) -> None:
    """Each attribute of :data:`_KINDS` is of its kind, so the checks after can read it."""
    for attr, (kind, expected) in _KINDS.items():
        value = getattr(cls, attr)
        if not isinstance(value, kind) or isinstance(value, str):
            raise ContractError(
                f"{name}.{attr} must be {expected}, got a {type(value).__qualname__}"
            )


def _check_constructor(cls: type, name: str) -> None:
    signature = inspect.signature(cls.__init__)
    kinds = {p.kind for p in signature.parameters.values()}
    if "seed" not in signature.parameters or inspect.Parameter.VAR_KEYWORD not in kinds:
        raise ContractError(
            f"{name}.__init__ must be (self, *, seed=None, **params): every field of "
            f"{cls.Params.__qualname__} is a keyword of the constructor"
        )
    extra = [
        p.name
        for p in signature.parameters.values()
        if p.name not in ("self", "seed") and p.kind is not inspect.Parameter.VAR_KEYWORD
    ]
    if extra:
        raise ContractError(
            f"{name}.__init__ takes {', '.join(extra)} besides seed and the params' fields; "
            f"make them fields of {cls.Params.__qualname__}"
        )
