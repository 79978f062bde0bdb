"""Checks of what a model's own code hands the framework, made where the framework takes it.

A model plugs into the framework through hooks: the flight controller's
``control(physics)``, :meth:`~abm.model.SwarmModel.metrics`, ``layers()``, ``arrows()``,
``reporters()``. Left unchecked, a wrong return value runs on silently (velocities of shape
``(n, 1)`` broadcast into wrong motion) or fails far from its cause (a ``None`` controller
inside SimPy). Each function here takes one hook's return value and either gives it back or
raises :class:`~abm.errors.HookError`: one line naming the model, the hook, what it returned
and what is expected, which the CLI prints without a traceback.

The controller's check runs on every physics tick, so it costs a few attribute reads and one
pass over the velocities (compiled for float64, :func:`_all_finite`; ``np.isfinite(...).all()``
for other float dtypes): under a microsecond per tick (0.7-0.8 us measured on a 2-core
machine, a few percent of a tick of a few flyers); the details of a bad value are worked out
only once it has been found bad.
"""

import math
from collections.abc import Callable, Mapping, Sequence
from numbers import Number

import numpy as np
from numba import njit

from abm.errors import HookError
from abm.styles import Layer

__all__ = [
    "arrows_of",
    "check_arrows",
    "check_control",
    "check_controller",
    "check_layers",
    "check_metrics",
    "check_reporters",
    "hook_name",
    "layers_of",
]


def hook_name(owner: str, obj: object, method: str) -> str:
    """How a message names a hook: ``Model.method`` when the model itself provides it, else
    ``Model: Helper.method`` (a controller object of the model's, for instance); ``method``
    with its arguments, e.g. ``"control(physics)"``.
    """
    provider = type(obj).__qualname__
    if not owner or provider == owner:
        return f"{provider}.{method}"
    return f"{owner}: {provider}.{method}"


def check_controller(controller: object, owner: str) -> None:
    """Raise HookError unless ``controller`` has a callable ``control(physics)``.

    Args:
        controller: what the model set as ``physics.controller``.
        owner: the model's class name, for the message.

    """
    if callable(getattr(controller, "control", None)):
        return
    got = "is None" if controller is None else f"is a {type(controller).__qualname__}"
    raise HookError(
        f"{owner or 'the physics'} has no flight controller: physics.controller {got}, which has "
        "no control(physics) method; set self.physics.controller to an object whose "
        "control(physics) returns (desired velocities (n, 2), done mask (n,)) in the model's "
        "__init__ (or pass controller= to SwarmModel.__init__), or pass physics=False if the "
        "model's robots never fly"
    )


def check_control(
    result: object, ids: np.ndarray, owner: str, controller: object
) -> tuple[np.ndarray, np.ndarray]:
    """The controller's ``(desired, done)`` for the flyers ``ids``, once checked.

    Expected: a tuple of ``desired``, a real floating-point array of shape ``(n, 2)`` (each
    flyer's desired velocity, m/s, in the rows of ``physics.ids``) whose every entry is finite,
    and ``done``, a boolean array of shape ``(n,)``. Nothing is converted: an integer or
    complex array, a list, or a ``(n, 1)`` column that numpy would broadcast are refused.

    Args:
        result: what ``control(physics)`` returned.
        ids: the flyers' robot ids (``physics.ids``), n of them.
        owner: the model's class name, for the message.
        controller: the object whose ``control`` returned ``result``, for the message.

    Raises:
        HookError: naming the hook, what it returned and what is expected.

    """
    n = len(ids)
    if type(result) is tuple and len(result) == 2:
        desired, done = result
        if (
            isinstance(desired, np.ndarray)
            and isinstance(done, np.ndarray)
            and desired.shape == (n, 2)
            and done.shape == (n,)
            and desired.dtype.kind == "f"
            and done.dtype.kind == "b"
            and (_all_finite(desired) if desired.dtype == _FLOAT64 else np.isfinite(desired).all())
        ):
            return desired, done
    hook = hook_name(owner, controller, "control(physics)")
    raise HookError(f"{hook} returned {_what_is_wrong(result, ids)}")


#: Compared with ``==``: an array a compiled kernel returns has a float64 dtype object of its
#: own (numba's), not numpy's singleton, which ``is`` would miss.
_FLOAT64 = np.dtype(np.float64)


@njit(cache=True)
def _all_finite(values: np.ndarray) -> bool:
    """Whether every entry of an ``(n, 2)`` float64 array is finite: ``np.isfinite(v).all()``
    without its temporary array and second call (a third of the cost for a few flyers).
    """
    for k in range(values.shape[0]):
        if not (math.isfinite(values[k, 0]) and math.isfinite(values[k, 1])):
            return False
    return True


def _what_is_wrong(result: object, ids: np.ndarray) -> str:
    """The first problem of a controller's bad return value, and what was expected."""
    n = len(ids)
    pair = f"a tuple (desired velocities, done mask) for the {n} flyers"
    if type(result) is not tuple or len(result) != 2:
        return f"{_shown(result)}; expected {pair}"
    desired, done = result
    if not (isinstance(desired, np.ndarray) and desired.shape == (n, 2)):
        return (
            f"desired velocities as {_shown(desired)}; expected a float array of shape ({n}, 2): "
            "one (vx, vy) row (m/s) per flyer, in the order of physics.ids"
        )
    if desired.dtype.kind != "f":
        return (
            f"desired velocities of dtype {desired.dtype}; expected a real floating-point array "
            f"(float64) of shape ({n}, 2)"
        )
    if not (isinstance(done, np.ndarray) and done.shape == (n,) and done.dtype.kind == "b"):
        return (
            f"a done mask as {_shown(done)}; expected a bool array of shape ({n},): True for "
            "each flyer whose flight ends now"
        )
    bad = np.flatnonzero(~np.isfinite(desired).all(axis=1))
    row = int(bad[0])
    return (
        f"non-finite desired velocities for {len(bad)} of {n} flyers (first: robot "
        f"{int(ids[row])}, {desired[row].tolist()}); expected finite numbers (m/s)"
    )


def _shown(value: object) -> str:
    """A short description of a value: its type, and its shape and dtype for an array."""
    if isinstance(value, np.ndarray):
        return f"an array of shape {value.shape} and dtype {value.dtype}"
    if isinstance(value, tuple):
        return f"a tuple of {len(value)}"
    return "None" if value is None else f"a {type(value).__qualname__}"


#: Types a summary value may have: it becomes one cell of a Parquet table and of a report.
_SCALARS = (Number, str, np.generic)


def check_metrics(metrics: object, hook: str, common: Sequence[str] = ()) -> Mapping[str, object]:
    """A model's ``metrics()``, once checked: a mapping of str keys, none of them one of the
    ``common`` summary keys (whose meaning the framework fixes, :data:`abm.units.COMMON`), to
    single values (numbers, true/false, text or None), each one cell of the run's summary row.

    Raises:
        HookError: naming the hook and the first key or value that is not of that kind.

    """
    if not isinstance(metrics, Mapping):
        raise HookError(f"{hook} returned {_shown(metrics)}; expected a dict of summary keys")
    for key, value in metrics.items():
        if not isinstance(key, str):
            raise HookError(f"{hook} returned the key {key!r}; expected str keys")
        if key in common:
            raise HookError(
                f"{hook} returned {key!r}, a key of the common summary ({', '.join(common)}) "
                "that the framework fills in; give the model's own value another name"
            )
        if not (value is None or isinstance(value, _SCALARS)):
            raise HookError(
                f"{hook} returned {key!r} as {_shown(value)}; expected one number, true/false, "
                "text or None per key (a summary value is one cell of the run's table)"
            )
    return metrics


def check_layers(layers: object, hook: str) -> list[Layer]:
    """A model's ``layers()``, once checked: a sequence of :class:`~abm.styles.Layer` whose
    points are ``(k, 2)`` and whose raster is 2-D.

    Raises:
        HookError: naming the hook and the first item that is not such a layer.

    """
    if not isinstance(layers, Sequence):
        raise HookError(f"{hook} returned {_shown(layers)}; expected a list of abm.styles.Layer")
    for i, layer in enumerate(layers):
        if not isinstance(layer, Layer):
            raise HookError(f"{hook}[{i}] is {_shown(layer)}; expected an abm.styles.Layer")
        points, raster = layer.points, layer.raster
        if points is not None and np.shape(points)[1:] != (2,):
            raise HookError(
                f"{hook}[{i}] ({layer.label!r}) has points of shape {np.shape(points)}; "
                "expected (k, 2) positions (m)"
            )
        if raster is not None and np.ndim(raster) != 2:
            raise HookError(
                f"{hook}[{i}] ({layer.label!r}) has a raster of shape {np.shape(raster)}; "
                "expected (rows, cols)"
            )
    return list(layers)


def check_arrows(arrows: object, hook: str) -> tuple[np.ndarray, np.ndarray] | None:
    """A model's ``arrows()``, once checked: None, or ``(points, vectors)`` of the same shape
    ``(k, 2)`` (m).

    Raises:
        HookError: naming the hook, what it returned and what is expected.

    """
    if arrows is None:
        return None
    if type(arrows) is tuple and len(arrows) == 2:
        points, vectors = (np.asarray(a) for a in arrows)
        if points.ndim == 2 and points.shape[1:] == (2,) and vectors.shape == points.shape:
            return points, vectors
        got = f"points of shape {points.shape} and vectors of shape {vectors.shape}"
    else:
        got = _shown(arrows)
    raise HookError(f"{hook} returned {got}; expected None or (points, vectors), both (k, 2) (m)")


def check_reporters(reporters: object, hook: str) -> dict[str, Callable]:
    """A model's ``reporters()``, once checked: a dict of column names to callables
    ``f(model)`` (Mesa's DataCollector model reporters).

    Raises:
        HookError: naming the hook and the first entry that is not such a pair.

    """
    if not isinstance(reporters, Mapping):
        raise HookError(f"{hook} returned {_shown(reporters)}; expected a dict of name -> f(model)")
    for key, reporter in reporters.items():
        if not (isinstance(key, str) and callable(reporter)):
            raise HookError(
                f"{hook} returned {key!r}: {_shown(reporter)}; expected str names of callables "
                "f(model)"
            )
    return dict(reporters)


def layers_of(model: object) -> list[Layer]:
    """``model.layers()``, checked (:func:`check_layers`): what the live page, the PNGs and
    the run folder draw and keep.
    """
    return check_layers(model.layers(), f"{type(model).__qualname__}.layers()")


def arrows_of(model: object) -> tuple[np.ndarray, np.ndarray] | None:
    """``model.arrows()``, checked (:func:`check_arrows`)."""
    return check_arrows(model.arrows(), f"{type(model).__qualname__}.arrows()")
