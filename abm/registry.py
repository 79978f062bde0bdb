"""The one registry of models that every tool reads (run, sweep, report, render, viz, fit).

Models come from the Python entry-point group ``swarm_abm.models`` (name = ``module:Class``),
so a package of your own adds a model by declaring, in its ``pyproject.toml``::

    [project.entry-points."swarm_abm.models"]
    my-model = "my_package.model:MyModel"

or, at run time, with :func:`register`. Classes are imported only when first asked for. A
``"module:Class"`` string is accepted wherever a name is, so a model that is not registered
still works in sweep files and worker processes.

:func:`declared` answers what ``abm run MODEL --help`` and the parameter check need (the
model's ``Params`` and description) from the model's source and its params module, without
importing the model's module where its source declares them plainly (:mod:`abm.declared`).
"""

import importlib
import sys
from importlib.metadata import entry_points
from typing import TYPE_CHECKING

from abm.errors import ConfigError, ContractError

if TYPE_CHECKING:
    from abm.declared import Declared

__all__ = [
    "ENTRY_POINT_GROUP",
    "declared",
    "model_class",
    "model_names",
    "name_of",
    "refresh",
    "register",
    "target_of",
    "unregister",
]

#: The entry-point group models are registered in.
ENTRY_POINT_GROUP = "swarm_abm.models"

_targets: dict[str, str] = {}  # name -> "module:Class"
_classes: dict[str, type] = {}  # name -> class, once imported or registered as a class
_registered: set[str] = set()  # names given to register() (they win over entry points)
_declared: dict[str, "Declared"] = {}  # name -> Params and description, read without the class
_loaded = False


def _discover() -> None:
    global _loaded
    if _loaded:
        return
    for ep in entry_points(group=ENTRY_POINT_GROUP):
        if ep.name not in _registered:
            _targets[ep.name] = ep.value
    _loaded = True


def refresh() -> None:
    """Read the entry points again (after installing a package that adds a model)."""
    global _loaded
    for name in [n for n in _targets if n not in _registered]:
        _targets.pop(name)
        _classes.pop(name, None)
        _declared.pop(name, None)
    _loaded = False
    _discover()


def register(name: str, model: type | str) -> None:
    """Make ``model`` (a SwarmModel subclass or ``"module:Class"``) known as ``name``.

    Raises:
        ContractError: a class that does not keep the model contract (see
            :func:`abm.contract.check_model`).
        ConfigError: a malformed name or target.

    """
    if not isinstance(name, str) or not name or name != name.strip():
        raise ConfigError(f"a model name must be a non-empty string, got {name!r}")
    _discover()
    _declared.pop(name, None)
    if isinstance(model, str):
        _check_target(model)
        _targets[name] = model
        _classes.pop(name, None)
    else:
        from abm.contract import check_model

        check_model(model)
        _targets[name] = f"{model.__module__}:{model.__qualname__}"
        _classes[name] = model
    _registered.add(name)


def unregister(name: str) -> None:
    """Forget a model registered with :func:`register` (an entry point of that name comes back
    with :func:`refresh`).
    """
    _targets.pop(name, None)
    _classes.pop(name, None)
    _declared.pop(name, None)
    _registered.discard(name)


def model_names() -> list[str]:
    """Every registered model name, sorted."""
    _discover()
    return sorted(_targets)


def model_class(model: str | type) -> type:
    """The model class for a registered name, a ``"module:Class"`` string, or a class.

    Raises:
        ConfigError: an unknown name (the message lists the known ones) or a target that cannot
            be imported.
        ContractError: the class does not keep the model contract.

    """
    if isinstance(model, type):
        from abm.contract import check_model

        check_model(model)
        return model
    if not isinstance(model, str):
        raise ConfigError(f"model must be a model name or class, got {model!r}")
    _discover()
    if model in _classes:
        return _classes[model]
    target = _targets.get(model, model)
    if ":" not in target:
        known = ", ".join(repr(n) for n in model_names())
        raise ConfigError(f"unknown model {model!r}; known models: {known} (or 'module:Class')")
    if model not in _targets:
        from abm.targets import check_target

        check_target(target)  # a user's "module:Class": not imported unless it defines Class
    cls = _import(target, model)
    from abm.contract import check_model  # Mesa: imported once there is a class to check

    check_model(cls)
    if model in _targets:
        _classes[model] = cls
    return cls


def declared(model: str) -> "Declared":
    """The ``Params`` (with its fault keywords) and the description of a model, as
    :func:`model_class` would give them (``cls.Params``, the first line of its docstring).

    For a registered name whose class is not imported yet, they are read from the model's
    source and the module its ``Params`` comes from, without importing the model's module or
    its package (:func:`abm.declared.declared_params`): ``abm run MODEL --help`` and a refused
    parameter then load no simulation code. Where the source does not declare them plainly (a
    model of another shape, a ``"module:Class"`` target), the class is imported.

    Raises:
        ConfigError: as :func:`model_class`.
        ContractError: as :func:`model_class`, where the class is imported.

    """
    from abm.declared import Declared, declared_params

    _discover()
    if isinstance(model, str) and model in _targets and model not in _classes:
        target = _targets[model]
        if model not in _declared and target.partition(":")[0] not in sys.modules:
            found = declared_params(target)
            if found is not None:
                _declared[model] = found
        if model in _declared:
            return _declared[model]
    cls = model_class(model)  # an unknown name is refused here, before Mesa is imported
    from abm.contract import description

    return Declared(cls.Params, description(cls))


def name_of(model: type) -> str | None:
    """The registered name of a model class (None if it is not registered).

    A name already looked up as this class is answered without importing anything (so
    ``abm run tangible-pso`` does not import every model listed before it); otherwise
    registered targets are imported as needed to compare classes (an entry point may name the
    class through its package, ``models.x:Model``, or its module, ``models.x.model:Model``).
    Where several names register one class, the first in sorted order among those looked up
    is the answer.
    """
    _discover()
    known = sorted(name for name, cls in _classes.items() if cls is model)
    if known:
        return known[0]
    for name in sorted(_targets):
        try:
            if model_class(name) is model:
                return name
        except (ConfigError, ContractError):
            continue  # a broken registration elsewhere is not this model's name
    return None


def target_of(model: str | type) -> str:
    """``"module:Class"`` of a model (what worker processes import)."""
    cls = model_class(model)
    return f"{cls.__module__}:{cls.__qualname__}"


def _check_target(target: str) -> None:
    module, _, attr = target.partition(":")
    if not module or not attr:
        raise ConfigError(f"a model target must look like 'package.module:Class', got {target!r}")


def _import(target: str, name: str) -> type:
    _check_target(target)
    module, _, attr = target.partition(":")
    try:
        obj = importlib.import_module(module)
        for part in attr.split("."):
            obj = getattr(obj, part)
    except (ImportError, AttributeError) as exc:
        raise ConfigError(f"model {name!r}: cannot import {target!r} ({exc})") from exc
    if not isinstance(obj, type):
        raise ContractError(f"model {name!r}: {target!r} is not a class")
    return obj
