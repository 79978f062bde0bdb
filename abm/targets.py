"""Checking a ``"module:Class"`` model target before anything is imported.

A model may be named ``"module:Class"`` instead of by its registered name (``abm run``, a
sweep file, a sweep folder's ``sweep.json``). Importing a module runs its code, so a typo or a
hostile file (``model = "this:X"`` prints the Zen of Python; ``"antigravity:X"`` opens a
browser) must be refused before the import. The rule:

* a registered model name is trusted (the user installed it);
* a module already imported has already run: only the class is checked (after import);
* any other module is located on ``sys.path`` *without importing it or its packages*, its
  source is read and parsed, and it is imported only if its top level binds ``Class`` by a
  ``class`` statement or an ``import`` (as a package's ``__init__.py`` re-exports its model).
  Modules without Python source (extensions, missing files) are refused.

After the import, :func:`abm.registry.model_class` checks that the class is a SwarmModel
keeping the model contract. This is a check against accidents, not a sandbox: a module that
does define a class of that name runs when imported, as any model's module does.
"""

import ast
import importlib.machinery
import importlib.util
import sys
from pathlib import Path

from abm.errors import ConfigError
from abm.registry import model_names

__all__ = ["check_target", "source_of"]

_RULE = "a 'module:Class' model names a class defined or imported at the top level of its module"


def check_target(model: str) -> None:
    """Raise ConfigError unless ``model`` (a name or ``"module:Class"``) is safe to import.

    Args:
        model: a model as a user gave it (a registered name or ``"module:Class"``).

    """
    if ":" not in model or model in model_names():
        return  # a registered name, or an unknown one model_class refuses without importing
    module, _, attr = model.partition(":")
    if not module or not attr or not all(p.isidentifier() for p in module.split(".")):
        raise ConfigError(f"model {model!r}: not a 'package.module:Class' target")
    if module in sys.modules:
        return
    source = source_of(module, model)
    name = attr.split(".")[0]
    try:
        tree = ast.parse(source.read_bytes(), filename=str(source))
    except (SyntaxError, ValueError, OSError) as exc:
        raise ConfigError(f"model {model!r}: cannot read {source} ({exc})") from exc
    if name not in _top_level_names(tree.body):
        raise ConfigError(
            f"model {model!r}: {source} has no class {name!r} at its top level, so it was not "
            f"imported; {_RULE}"
        )


def source_of(module: str, model: str) -> Path:
    """The ``.py`` file of ``module``, found without importing it or its parent packages.

    Raises:
        ConfigError: no such module, or one without Python source; naming ``model`` (the
            model as the user gave it).

    """
    path = None  # None: sys.path
    spec = None
    parts = module.split(".")
    for k in range(len(parts)):
        dotted = ".".join(parts[: k + 1])
        loaded = sys.modules.get(dotted)
        if loaded is not None and k < len(parts) - 1:
            path = list(getattr(loaded, "__path__", []))
            continue
        if k == 0:  # every finder (an editable install has its own); finding imports nothing
            spec = importlib.util.find_spec(dotted)
        else:
            spec = importlib.machinery.PathFinder.find_spec(dotted, path)
        if spec is None:
            raise ConfigError(f"model {model!r}: no module {dotted!r} on the Python path")
        path = list(spec.submodule_search_locations or [])
    origin = spec.origin if spec is not None else None
    if not origin or not origin.endswith(".py"):
        raise ConfigError(f"model {model!r}: {module!r} is not a Python source module; {_RULE}")
    return Path(origin)


def _top_level_names(body: list[ast.stmt]) -> set[str]:
    """Names bound at a module's top level by ``class`` and ``import`` statements (also
    inside top-level ``if``/``try`` blocks, as conditional imports are written).
    """
    names: set[str] = set()
    for node in body:
        if isinstance(node, ast.ClassDef):
            names.add(node.name)
        elif isinstance(node, ast.Import | ast.ImportFrom):
            names.update((a.asname or a.name).split(".")[0] for a in node.names)
        elif isinstance(node, ast.If):
            names |= _top_level_names(node.body) | _top_level_names(node.orelse)
        elif isinstance(node, ast.Try):
            for block in (node.body, node.orelse, node.finalbody, *(h.body for h in node.handlers)):
                names |= _top_level_names(block)
    return names
