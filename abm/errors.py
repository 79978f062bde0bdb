"""The project's exception types.

Every public constructor validates its input and raises one of these with the name of the bad
parameter, the value it got and the rule it broke, so a user can fix the call without reading
the source.
"""

import math
import sys

__all__ = [
    "ABMError",
    "ConfigError",
    "ContractError",
    "LinkError",
    "MapError",
    "OutputError",
    "check_choice",
    "check_range",
]


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
