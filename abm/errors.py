"""The project's exception types.

Every public constructor validates its input and raises one of these with the name of the bad
parameter, the value it got and the rule it broke, so a user can fix the call without reading
the source.
"""

import math
import sys

import numpy as np

__all__ = [
    "ABMError",
    "ConfigError",
    "ContractError",
    "HookError",
    "LinkError",
    "MapError",
    "OutputError",
    "SEED_MAX",
    "check_choice",
    "check_range",
    "check_seed",
    "parse_seed",
]

#: Largest seed accepted: seeds are stored as 64-bit signed integers (Parquet ``int64``
#: columns of sweeps, ``run.json``), so every seed a run accepts can be written with its results.
SEED_MAX = 2**63 - 1


class ABMError(Exception):
    """Base class of every error this project raises on purpose."""


class ConfigError(ABMError, ValueError):
    """A parameter is outside the range or set of values it accepts."""


class MapError(ABMError, ValueError):
    """A map (cell list, bitmap file or array) cannot be turned into an arena."""


class OutputError(ABMError, OSError):
    """A file or folder could not be written or read where the user pointed (full disk,
    read-only folder, a file where a folder was expected, a folder another sweep holds).

    The message names the path and what to do; whatever was finished before stays on disk.
    """


class LinkError(ABMError, ValueError):
    """A message was sent over a pair of nodes the comm network's link policy forbids."""


class ContractError(ABMError, TypeError):
    """A model class does not keep the model contract (see ``docs/adding-a-model.md``)."""


class HookError(ConfigError):
    """A model's own code handed the framework something it cannot use: a hook the framework
    calls (the flight controller's ``control``, ``metrics()``, ``layers()``, ``arrows()``, ...)
    returned the wrong type, shape or dtype, or a non-finite number, or a hook the model needs
    is missing. The message names the model, the hook, what it returned and what is expected
    (see :mod:`abm.checks`).
    """


def check_range(
    name: str,
    value: float,
    low: float | None = None,
    high: float | None = None,
    *,
    low_open: bool = False,
    integer: bool = False,
) -> None:
    """Raise ConfigError unless ``low <= value <= high`` (``low < value`` when ``low_open``).

    Infinity (and an integer too large for a float) is refused unless ``high`` is ``math.inf``
    itself: an unbounded parameter still takes finite values only.

    Args:
        name: the parameter's name as the user typed it.
        value: the value received.
        low: smallest accepted value, or None for no lower bound.
        high: largest accepted value, or None for no upper bound (finite values); ``math.inf``
            to accept infinity too.
        low_open: exclude ``low`` itself (for "must be positive").
        integer: the value must also be an integer.

    """
    if isinstance(value, bool) or not isinstance(value, int | float):
        kind = "an integer" if integer else "a number"
        raise ConfigError(f"{name} must be {kind}, got {value!r}")
    if value != value:  # NaN
        raise ConfigError(f"{name} must be a number, got NaN")
    if not _finite(value) and not (value > 0 and high == math.inf):
        raise ConfigError(f"{name} must be a finite number, got {value!r}")
    if integer and int(value) != value:
        raise ConfigError(f"{name} must be an integer, got {value!r}")
    too_low = low is not None and (value <= low if low_open else value < low)
    too_high = high is not None and value > high
    if too_low or too_high:
        lo = "-inf" if low is None else f"{low:g}"
        hi = "inf" if high is None else f"{high:g}"
        bracket = "(" if low_open else "["
        raise ConfigError(f"{name} must be in {bracket}{lo}, {hi}], got {value!r}")


def _finite(value: int | float) -> bool:
    """True for a finite float or an integer a float can hold."""
    if isinstance(value, int):
        return abs(value) <= sys.float_info.max
    return math.isfinite(value)


def check_choice(name: str, value: object, choices: tuple) -> None:
    """Raise ConfigError unless ``value`` is one of ``choices``."""
    if value not in choices:
        options = ", ".join(repr(c) for c in choices)
        raise ConfigError(f"{name} must be one of {options}, got {value!r}")


def check_seed(value: object, name: str = "seed", *, allow_none: bool = True) -> int | None:
    """Return ``value`` as a plain int (or None) when it is a seed a run accepts, else raise.

    A seed is an integer in ``[0, 2**63 - 1]`` (or None, fresh entropy, where ``allow_none``):
    numpy's ``SeedSequence`` takes any non-negative integer, but a run's seed is stored beside
    its results as a 64-bit integer, so a larger one would fail only once the run is over.
    This is the one check model constructors and ``abm run`` (through :func:`parse_seed`) use.

    Raises:
        ConfigError: naming ``name``, the value and the accepted range.

    """
    if value is None and allow_none:
        return None
    if (
        isinstance(value, bool)
        or not isinstance(value, int | np.integer)
        or not 0 <= value <= SEED_MAX
    ):
        rule = f"{name} must be an integer in [0, 2**63 - 1]" + (" or None" if allow_none else "")
        raise ConfigError(f"{rule}, got {_shown(value)}")
    return int(value)


def parse_seed(text: str, name: str = "seed") -> int:
    """A seed given as text (a command line's): a decimal integer that :func:`check_seed`
    accepts.

    Raises:
        ConfigError: the text is not a decimal integer, or the integer is out of range.

    """
    try:
        value = int(text.strip(), 10)
    except ValueError:
        rule = f"{name} must be an integer in [0, 2**63 - 1]"
        raise ConfigError(f"{rule}, got {_shown(text)}") from None
    return check_seed(value, name, allow_none=False)


def _shown(value: object) -> str:
    """``repr(value)``, shortened to one readable line for an error message."""
    text = repr(value)
    return text if len(text) <= 40 else f"{text[:20]}...{text[-12:]} ({len(text)} characters)"
