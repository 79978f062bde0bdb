"""Model parameters: one frozen dataclass per model, every field a plain constructor keyword.

A model's ``Params`` subclasses :class:`SwarmParams` and lists every tunable constant with its
unit, default and (in the class docstring's ``Attributes:`` section) what it means, with the
source's symbol and citation. Fields are declared with :func:`param`, which records the accepted
range or choices; :meth:`SwarmParams.__post_init__` checks every field against them once, so a bad
value raises :class:`~abm.errors.ConfigError` naming the parameter, the value and the rule, whoever
passed it (Python, ``mesa.batch_run``, a TOML sweep, a slider or the CLI).

:func:`make_params` is the one place that maps constructor keywords to a validated instance;
:func:`field_help` gives the docstring text of each field (CLI help, reports, sliders).
"""

import dataclasses
import inspect
import re
import types
import typing
from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from abm.errors import ConfigError, check_choice, check_range

__all__ = [
    "COLLISION_ROWS",
    "FAULT_KEYWORDS",
    "FAULT_PARAMS",
    "MAX_FAULT_EVENTS",
    "MAX_PERIODS",
    "LinkFaultParams",
    "RobotFaultParams",
    "SensorFaultParams",
    "SwarmParams",
    "bind_params",
    "check_value",
    "field_help",
    "field_rule",
    "make_params",
    "param",
    "param_fields",
    "plain_value",
    "refuse_fault_keyword",
    "with_faults",
]

_RULE = "abm.rule"

#: Most periods of one repeating process a run may hold (ours). A shorter period is no model
#: anyone means: at ~1e6 SimPy events/s the run would take a quarter of an hour per process at
#: best, and below ``time_limit`` x 2^-52 the clock cannot advance at all (the run never ends).
MAX_PERIODS = 1e9
#: Most events a fault process over the whole network (outages, loss bursts) may be expected to
#: inject in one run (ours): ``rate * time_limit``. Each costs some 7-15 us of simulation
#: (measured on beacon-explorer) plus the model's repair, so this is tens of seconds of work;
#: a larger rate is a storm no study means (``link_outage_rate=1e12`` over 30 s asked for
#: 3e13 outages and ran on without a word).
MAX_FAULT_EVENTS = 1e6
#: Most collision rows a run keeps in its event log by default (ours): about 40 MB of rows.
#: Past it collisions are still counted (the summary's ``collisions``), not logged one by one.
COLLISION_ROWS = 100_000
#: The base fields that are periods whatever a model's own declaration of them says.
_BASE_PERIODS = ("step_duration", "dt", "trace_interval")


def param(
    default: object,
    *,
    low: float | None = None,
    high: float | None = None,
    low_open: bool = False,
    integer: bool = False,
    choices: Sequence | None = None,
    period: bool = False,
    events: bool = False,
    shown: tuple[float, float] | None = None,
) -> object:
    """A dataclass field with a default and the rule its values must follow.

    Args:
        default: the value used when the keyword is not given.
        low: smallest accepted value (None: no lower bound).
        high: largest accepted value (None: no upper bound).
        low_open: exclude ``low`` itself ("must be positive").
        integer: the value must be a whole number.
        choices: the accepted values, for a field that takes one of a few names.
        period: the field is a time period (s) a process waits again and again; it must leave
            at most :data:`MAX_PERIODS` periods in ``time_limit`` (see :class:`SwarmParams`).
        events: the field is the rate (1/s) of a Poisson process of events over the whole run
            (not per robot, where each robot fails once at most); it may be expected to give
            at most :data:`MAX_FAULT_EVENTS` events in ``time_limit``.
        shown: the part of the accepted range a slider offers, ``(low, high)``, for a field
            whose accepted range is unbounded or far wider than anyone explores; None: the
            accepted range itself.

    """
    if shown is not None:
        _check_shown(shown, low, high, low_open)
    rule = {
        "low": low,
        "high": high,
        "low_open": low_open,
        "integer": integer,
        "choices": None if choices is None else tuple(choices),
        "period": period,
        "events": events,
        "shown": None if shown is None else (shown[0], shown[1]),
    }
    return dataclasses.field(default=default, metadata={_RULE: rule})


def _check_shown(
    shown: tuple[float, float], low: float | None, high: float | None, low_open: bool
) -> None:
    """A slider range must lie inside the accepted range: every value it offers is accepted."""
    a, b = shown
    below = low is not None and (a < low or (low_open and a == low))
    if not a < b or below or (high is not None and b > high):
        raise ConfigError(
            f"shown range {shown} must be increasing and inside the accepted range "
            f"[{low}, {high}]" + (" (low excluded)" if low_open else "")
        )


def field_rule(f: dataclasses.Field) -> dict:
    """The rule :func:`param` recorded for a field (empty for a plain field)."""
    return dict(f.metadata.get(_RULE, {}))


@dataclasses.dataclass(frozen=True)
class _RunParams:
    """The fields every run has (described in :class:`SwarmParams`); declared apart so they
    come before the fault keywords in every listing.
    """

    time_limit: float = param(3600.0, low=0.0, low_open=True)
    step_duration: float = param(1.0, low=0.0, low_open=True)
    dt: float = param(0.1, low=0.0, low_open=True)
    trace_interval: float | None = param(1.0, low=0.0, low_open=True)
    collision_rows: int | None = param(COLLISION_ROWS, low=0, integer=True)


@dataclasses.dataclass(frozen=True)
class RobotFaultParams:
    """The keywords of "robot" faults (:mod:`abm.faults`), which a model's params get when
    the model declares "robot" in ``SwarmModel.FAULTS``. The defaults inject nothing; the
    shape and states qualify the rate or times (with neither there is no fault to shape).

    Attributes:
        fault_rate: lambda, each robot's failure hazard (1/s): its time to failure is Weibull
            with shape ``fault_shape`` and scale 1/lambda (exponential with mean 1/lambda at
            shape 1), counted only while it is in ``fault_states`` (ours; 0: no random
            failures).
        fault_shape: k, the Weibull shape of the time to failure (1: exponential, a constant
            hazard; > 1: wear-out; < 1: infant mortality) (ours).
        fault_times: simulated times (s) at which one robot, drawn uniformly among those
            in ``fault_states`` that have not failed, fails (ours).
        fault_states: the states in which a robot can fail (empty: any state) (ours).

    """

    fault_rate: float = param(0.0, low=0.0)
    fault_shape: float = param(1.0, low=0.0, low_open=True)
    fault_times: tuple[float, ...] = param(())
    fault_states: tuple[str, ...] = param(())

    def _injects(self) -> bool:
        return self.fault_rate > 0 or bool(self.fault_times)

    def _check_kind(self) -> None:
        for t in self.fault_times:
            if not np.isfinite(t) or t < 0:
                raise ConfigError(
                    f"fault_times must hold finite times >= 0 s, got {self.fault_times!r}"
                )
        bad = [s for s in self.fault_states if not isinstance(s, str) or not s]
        if bad or len(set(self.fault_states)) != len(self.fault_states):
            raise ConfigError(f"fault_states must name distinct states, got {self.fault_states!r}")


@dataclasses.dataclass(frozen=True)
class LinkFaultParams:
    """The keywords of "link" faults (:mod:`abm.faults`), which a model's params get when
    the model declares "link" in ``SwarmModel.FAULTS``. The defaults inject nothing.

    Attributes:
        link_outage_rate: outages per second over the whole comm network: each takes one
            link, drawn uniformly among the links up, down for ``link_outage_duration``
            (ours; 0: none).
        link_outage_duration: how long one link outage lasts (s) (ours).
        loss_burst_rate: message-loss bursts per second: during a burst each transmission is
            lost with probability ``loss_burst_loss`` (ours; 0: none).
        loss_burst_duration: how long one loss burst lasts (s) (ours).
        loss_burst_loss: probability that a transmission sent during a burst is lost (ours).

    """

    link_outage_rate: float = param(0.0, low=0.0, events=True)
    link_outage_duration: float = param(10.0, low=0.0, low_open=True)
    loss_burst_rate: float = param(0.0, low=0.0, events=True)
    loss_burst_duration: float = param(5.0, low=0.0, low_open=True)
    loss_burst_loss: float = param(1.0, low=0.0, high=1.0, low_open=True)

    def _injects(self) -> bool:
        return self.link_outage_rate > 0 or self.loss_burst_rate > 0

    def _check_kind(self) -> None:
        """Each value's range is checked with the other fields."""


@dataclasses.dataclass(frozen=True)
class SensorFaultParams:
    """The keywords of "sensor" faults (:mod:`abm.faults`), which a model's params get when
    the model declares "sensor" in ``SwarmModel.FAULTS``. The defaults inject nothing.

    Attributes:
        sensor_fault_rate: each robot's hazard of a sensor fault (1/s): from then on its
            readings are stuck at the first faulty reading or noisy (ours; 0: none).
        sensor_fault_kind: "stuck" (the reading never changes again) or "noisy" (Gaussian
            noise of sd ``sensor_fault_noise`` added to every reading) (ours).
        sensor_fault_noise: sd of the extra noise of a "noisy" sensor, in the reading's unit
            (m for distance sensors) (ours).

    """

    sensor_fault_rate: float = param(0.0, low=0.0)
    sensor_fault_kind: str = param("stuck", choices=("stuck", "noisy"))
    sensor_fault_noise: float = param(0.5, low=0.0)

    def _injects(self) -> bool:
        return self.sensor_fault_rate > 0

    def _check_kind(self) -> None:
        """Each value's range is checked with the other fields."""


#: Each fault kind (``SwarmModel.FAULTS``) and the dataclass of its keywords.
FAULT_PARAMS: dict[str, type] = {
    "robot": RobotFaultParams,
    "link": LinkFaultParams,
    "sensor": SensorFaultParams,
}

#: Every fault keyword and its kind, in declaration order.
FAULT_KEYWORDS: dict[str, str] = {
    f.name: kind for kind, cls in FAULT_PARAMS.items() for f in dataclasses.fields(cls)
}


@dataclasses.dataclass(frozen=True)
class SwarmParams(_RunParams):
    """What every swarm model has, with neutral defaults (a model overrides what it needs):
    the run's clock settings below. The fault keywords of the kinds a model declares
    (:data:`FAULT_PARAMS`) are added by :func:`with_faults` when the model class is defined.

    Attributes:
        time_limit: the run ends at this simulated time at the latest (s).
        step_duration: simulated time one Mesa ``step()`` advances (s).
        dt: physics tick: flying robots move and their controller runs once per tick (s).
        trace_interval: how often robot positions are sampled for rendering (s); None: never
            (faster).
        collision_rows: most collisions logged one per row in the event log (ours; default
            100,000); later ones are counted in the summary's ``collisions`` but not logged,
            and a ``rows_capped`` event marks where the rows stop. None: log every one (a
            crowded run can log tens of millions); 0: none.

    """

    def __post_init__(self) -> None:
        for f in dataclasses.fields(self):
            value = _checked(f, getattr(self, f.name))
            object.__setattr__(self, f.name, value)
        for mixin in FAULT_PARAMS.values():
            if isinstance(self, mixin):
                mixin._check_kind(self)
        self._check_periods()

    @property
    def fault_kinds(self) -> frozenset[str]:
        """The kinds of fault these params inject: "robot", "link" and/or "sensor"."""
        return frozenset(
            kind
            for kind, mixin in FAULT_PARAMS.items()
            if isinstance(self, mixin) and mixin._injects(self)
        )

    def _check_periods(self) -> None:
        """Every period (``dt``, ``step_duration``, ``trace_interval`` and the fields declared
        with ``period=True``) leaves at most :data:`MAX_PERIODS` periods in ``time_limit``.
        """
        for f in dataclasses.fields(self):
            if field_rule(f).get("events"):
                self._check_events(f.name, getattr(self, f.name))
            if not (field_rule(f).get("period") or f.name in _BASE_PERIODS):
                continue
            value = getattr(self, f.name)
            if value is not None and value * MAX_PERIODS < self.time_limit:
                raise ConfigError(
                    f"{f.name}={value!r} s repeats more than {MAX_PERIODS:.0e} times in "
                    f"time_limit={self.time_limit!r} s (the run would never end in practice): "
                    f"{f.name} must be >= time_limit / {MAX_PERIODS:.0e}"
                )

    def _check_events(self, name: str, rate: float) -> None:
        """A rate of events over the whole run gives at most :data:`MAX_FAULT_EVENTS` of them
        in ``time_limit`` on average.
        """
        if rate * self.time_limit > MAX_FAULT_EVENTS:
            raise ConfigError(
                f"{name}={rate!r} per s asks for {rate * self.time_limit:.3g} events in "
                f"time_limit={self.time_limit!r} s, more than the {MAX_FAULT_EVENTS:.0e} a run "
                f"may hold (each costs simulation work): {name} must be <= "
                f"{MAX_FAULT_EVENTS / self.time_limit:.6g} here"
            )

    def replace(self, **changes: object) -> "SwarmParams":
        """A copy with some fields changed (validated like a new instance)."""
        return make_params(type(self), changes, base=self)

    def as_dict(self) -> dict:
        """Field name -> value (values as given: a map may be an array or an Arena)."""
        return {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}

    def plain(self) -> dict:
        """Field name -> a JSON-friendly value (others, such as arrays, as their repr)."""
        return {name: plain_value(value) for name, value in self.as_dict().items()}


def with_faults(params_cls: type[SwarmParams], kinds: frozenset[str], owner: str) -> type:
    """``params_cls`` with the fault keywords of ``kinds`` (and only those) as fields.

    The model class calls it once when it is defined (``SwarmModel.__init_subclass__``): a
    model that declares no fault kind has no fault keyword. The class keeps the base's name,
    and records ``owner`` (the model) and its kinds, for :func:`refuse_fault_keyword`.

    Args:
        params_cls: the model's params dataclass (or one this function made).
        kinds: the fault kinds the model declares.
        owner: the model class's name.

    """
    base = vars(params_cls).get("_fault_base", params_cls)
    mixins = [FAULT_PARAMS[k] for k in FAULT_PARAMS if k in kinds]
    made = dataclasses.make_dataclass(
        base.__name__, [], bases=(*reversed(mixins), base), frozen=True
    )
    made.__doc__ = base.__doc__
    made.__module__ = base.__module__
    made._fault_base = base
    made.fault_owner = owner
    made.fault_kinds_declared = frozenset(kinds)
    return made


def bind_params(
    params_cls: type[SwarmParams], kinds: frozenset[str], module: str, qualname: str
) -> type:
    """What a model class's ``Params`` becomes when the class is defined: ``params_cls`` with
    the fault keywords of ``kinds`` (:func:`with_faults`), named as the class's attribute
    (``module``, ``<qualname>.Params``).

    ``SwarmModel.__init_subclass__`` calls it, and :mod:`abm.declared` calls it from the
    model's source alone, so both build the same class.

    Args:
        params_cls: the dataclass the model class names as its ``Params``.
        kinds: the fault kinds the model declares (``FAULTS``).
        module: the module the model class is defined in.
        qualname: the model class's qualified name.

    """
    made = with_faults(params_cls, kinds, qualname.rpartition(".")[2])
    made.__module__, made.__qualname__ = module, f"{qualname}.Params"
    return made


def refuse_fault_keyword(params_cls: type, name: str, value: object = None) -> None:
    """Raise ConfigError when ``name`` is a fault keyword ``params_cls`` lacks: one line
    naming the keyword, the model and the fault kinds it handles.
    """
    kind = FAULT_KEYWORDS.get(name)
    fields = {f.name for f in dataclasses.fields(params_cls)}
    if kind is None or name in fields:
        return
    owner = getattr(params_cls, "fault_owner", params_cls.__name__)
    handled = ", ".join(sorted(getattr(params_cls, "fault_kinds_declared", ()))) or "none"
    given = name if value is None else f"{name}={value!r}"
    raise ConfigError(
        f"{given}: {owner} does not handle {kind} faults (it handles: {handled}); "
        f"its fault keywords are those of the kinds it handles"
    )


def param_fields(params_cls: type[SwarmParams]) -> list[dataclasses.Field]:
    """The fields of a params dataclass, in declaration order (base fields first)."""
    return list(dataclasses.fields(params_cls))


def make_params(
    params_cls: type[SwarmParams], kwargs: Mapping[str, object], base: SwarmParams | None = None
) -> SwarmParams:
    """Validated ``params_cls`` from constructor keywords (unknown names are a ConfigError).

    Args:
        params_cls: the model's params dataclass.
        kwargs: keyword -> value; missing fields take ``base``'s value or the default.
        base: an instance to start from.

    """
    names = [f.name for f in dataclasses.fields(params_cls)]
    unknown = [k for k in kwargs if k not in names]
    for name in unknown:
        refuse_fault_keyword(params_cls, name, kwargs[name])
    if unknown:
        close = _close_names(unknown[0], names)
        hint = f" (did you mean {close}?)" if close else ""
        raise ConfigError(
            f"unknown parameter {unknown[0]!r}{hint}; {params_cls.__name__} accepts: "
            + ", ".join(names)
        )
    if base is not None:
        kwargs = {**base.as_dict(), **kwargs}
    return params_cls(**kwargs)


def _close_names(name: str, names: Sequence[str]) -> str:
    import difflib

    return " or ".join(repr(n) for n in difflib.get_close_matches(name, names, n=2))


def field_help(params_cls: type) -> dict[str, str]:
    """Field name -> its text in the ``Attributes:`` sections of the class and its bases."""
    out: dict[str, str] = {}
    for cls in reversed(params_cls.__mro__):
        out.update(_attributes_section(inspect.getdoc(cls) or ""))
    return out


def _attributes_section(doc: str) -> dict[str, str]:
    """Parse a Google-style ``Attributes:`` section: ``name: text`` with indented follow-ons."""
    out: dict[str, str] = {}
    lines = doc.splitlines()
    try:
        start = next(i for i, line in enumerate(lines) if line.strip() == "Attributes:")
    except StopIteration:
        return out
    indent = None
    current = None
    for line in lines[start + 1 :]:
        if not line.strip():
            continue
        depth = len(line) - len(line.lstrip())
        if indent is None:
            indent = depth
        if depth < indent:
            break
        match = re.match(r"(\w+)(?: \(.*?\))?: (.*)", line.strip())
        if depth == indent and match:
            current = match.group(1)
            out[current] = match.group(2)
        elif current is not None:
            out[current] += " " + line.strip()
    return out


def plain_value(value: object) -> object:
    """``value`` as JSON-friendly data: numbers, strings, bools, None, lists; else its repr."""
    if isinstance(value, np.generic):
        value = value.item()
    if value is None or isinstance(value, bool | int | float | str):
        return value
    if isinstance(value, Path):
        return str(value)
    if isinstance(value, tuple | list) and all(
        isinstance(v, bool | int | float | str | np.generic) for v in value
    ):
        return [plain_value(v) for v in value]
    return repr(value)


def check_value(params_cls: type[SwarmParams], name: str, value: object) -> object:
    """``value`` checked against one field's type and rule (normalised: ints become floats
    for float fields, lists tuples); cross-field rules are checked when the params are built.

    Raises:
        ConfigError: an unknown field (the message lists them) or a value it does not accept.

    """
    fields = {f.name: f for f in dataclasses.fields(params_cls)}
    refuse_fault_keyword(params_cls, name, value)
    if name not in fields:
        raise ConfigError(
            f"unknown parameter {name!r}; {params_cls.__name__} accepts: " + ", ".join(fields)
        )
    return _checked(fields[name], value)


# ---------------------------------------------------------------------- checking one field
def _checked(f: dataclasses.Field, value: object) -> object:
    """``value`` after the field's type and rule checks (ints become floats for float fields)."""
    kinds = _kinds(f.type)
    if isinstance(value, np.generic):
        value = value.item()
    if value is None:
        if type(None) in kinds or not kinds:
            return None
        raise ConfigError(f"{f.name} must be {_describe(kinds)}, got None")
    rule = field_rule(f)
    if float in kinds and _is_number(value) and int not in kinds:
        check_range(f.name, value, rule.get("low"), rule.get("high"), low_open=rule["low_open"])
        return float(value)
    if int in kinds and _is_number(value):
        check_range(
            f.name,
            value,
            rule.get("low"),
            rule.get("high"),
            low_open=rule["low_open"],
            integer=True,
        )
        return int(value)
    if bool in kinds and isinstance(value, bool | np.bool_):
        return bool(value)
    if rule.get("choices") is not None and isinstance(value, str):
        check_choice(f.name, value, rule["choices"])
        return value
    if tuple in kinds and isinstance(value, tuple | list | np.ndarray):
        return _checked_tuple(f, value)
    if any(isinstance(value, k) for k in kinds if k not in (float, int, bool, tuple)):
        return value
    if not kinds:
        return value
    raise ConfigError(f"{f.name} must be {_describe(kinds)}, got {value!r}")


def _checked_tuple(f: dataclasses.Field, value) -> tuple:
    args = _tuple_args(f.type)
    items = tuple(np.asarray(value).ravel().tolist())
    if args and Ellipsis not in args and len(items) != len(args):
        raise ConfigError(f"{f.name} must have {len(args)} values, got {value!r}")
    if float in args and not all(_is_number(v) for v in items):
        raise ConfigError(f"{f.name} must hold numbers, got {value!r}")
    return tuple(float(v) for v in items) if float in args else items


def _tuple_args(annotation) -> tuple:
    for kind in _union_args(annotation):
        if typing.get_origin(kind) is tuple:
            return typing.get_args(kind)
    return ()


def _union_args(annotation) -> tuple:
    if typing.get_origin(annotation) in (typing.Union, types.UnionType):
        return typing.get_args(annotation)
    return (annotation,)


def _kinds(annotation) -> tuple[type, ...]:
    """The plain types a field annotation admits (``tuple[float, float]`` -> ``tuple``)."""
    out = []
    for kind in _union_args(annotation):
        origin = typing.get_origin(kind)
        if origin is not None:
            out.append(origin)
        elif isinstance(kind, type):
            out.append(kind)
    return tuple(out)


def _is_number(value) -> bool:
    return isinstance(value, int | float | np.integer | np.floating) and not isinstance(
        value, bool | np.bool_
    )


def _describe(kinds: tuple[type, ...]) -> str:
    names = {
        float: "a number",
        int: "an integer",
        bool: "True or False",
        str: "a string",
        tuple: "a list of values",
        type(None): "None",
    }
    return " or ".join(names.get(k, k.__name__) for k in kinds)
