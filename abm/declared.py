"""A model's parameters read from its source, without importing the model's module.

``abm run MODEL --help`` and a refused parameter need a model's ``Params`` (with the fault
keywords of the kinds it declares) and the first line of its docstring, and nothing a run
needs. Importing the model class costs most of a second (Mesa, which imports pandas,
scipy.spatial and networkx, and numba); the module its ``Params`` comes from costs a few
hundredths. So the registry asks :func:`declared_params` first. It parses, without running
them, the module an entry point names and the module that defines the class; when the class
declares what is needed in the plain way every model of this project does, it runs only the
module ``Params`` is imported from and builds the very class the model's definition makes
(:func:`abm.params.bind_params`, which ``SwarmModel.__init_subclass__`` calls too).

The plain way, as written in a model's ``model.py``::

    from abm.model import SwarmModel
    from my_package.params import MyParams

    class MyModel(SwarmModel):
        \"\"\"What the model is (its first line is the model's description).\"\"\"

        Params = MyParams
        FAULTS = frozenset({"robot"})  # or no FAULTS: no fault kinds

with the class bound once at the top level of its module (by its ``class`` statement, or in a
package's ``__init__.py`` by ``from ... import MyModel``) and changed nowhere after. Anything
else (a computed ``FAULTS``, ``Params`` defined in the model's own module or nested in the
class, a decorator, a base other than ``SwarmModel``, no docstring) gets None, and the
registry imports the class instead: slower, never different.
"""

import ast
import dataclasses
import importlib.util
import sys

from abm.errors import ConfigError
from abm.params import FAULT_PARAMS, SwarmParams, bind_params
from abm.targets import source_of

__all__ = ["Declared", "declared_params"]

#: Class attributes whose every binding in the class body must be the plain one read here.
_READ = ("Params", "FAULTS", "__doc__", "__module__", "__qualname__")
#: How many ``from ... import Class`` re-exports are followed to the ``class`` statement.
_MAX_HOPS = 4


@dataclasses.dataclass(frozen=True)
class Declared:
    """What ``abm run MODEL --help`` and the parameter check need of a model.

    Attributes:
        params: the model class's ``Params`` (its dataclass with the fault keywords of the
            kinds it declares).
        description: the first line of the model class's docstring.

    """

    params: type[SwarmParams]
    description: str


def declared_params(target: str) -> Declared | None:
    """A model's :class:`Declared`, from the source of ``target`` (``"module:Class"``) and the
    module its ``Params`` is imported from, or None where the source is not the plain shape
    (then the class itself must be imported to know).

    The model's own module is not imported, nor is any package on the way to it.
    """
    module, _, attr = target.partition(":")
    if not module or not attr.isidentifier():
        return None
    found = _class_statement(module, attr)
    if found is None:
        return None
    home, package, tree, node = found
    doc = ast.get_docstring(node)
    description = doc.splitlines()[0].strip() if doc else ""
    if not description or not _plain_class(tree, node):
        return None  # no docstring: the class itself raises the contract's ContractError
    faults = _faults(tree, node)
    params = _params_class(home, package, tree, node)
    if faults is None or params is None:
        return None
    return Declared(bind_params(params, faults, home, node.name), description)


def _class_statement(module: str, name: str) -> tuple[str, str, ast.Module, ast.ClassDef] | None:
    """The module that defines class ``name`` (following re-exports such as a package's
    ``from .model import Model``), its package, its parsed source and the ``class`` statement.
    """
    for _ in range(_MAX_HOPS):
        parsed = _parse(module)
        if parsed is None:
            return None
        package, tree = parsed
        binding = _sole(tree, name)
        if binding is None or _changed(tree, name):
            return None
        if isinstance(binding, ast.ClassDef):
            return module, package, tree, binding
        module, name = _absolute(binding, package), _imported_name(binding, name)
        if module is None:
            return None
    return None


def _plain_class(tree: ast.Module, node: ast.ClassDef) -> bool:
    """The class is ``class Name(SwarmModel):`` with ``SwarmModel`` imported from
    ``abm.model``, no decorator and no class keyword (a metaclass could change anything).
    """
    if node.decorator_list or node.keywords or len(node.bases) != 1:
        return False
    base = node.bases[0]
    if not isinstance(base, ast.Name):
        return False
    binding = _sole(tree, base.id)
    return (
        isinstance(binding, ast.ImportFrom)
        and binding.level == 0
        and binding.module == "abm.model"
        and _imported_name(binding, base.id) == "SwarmModel"
    )


def _faults(tree: ast.Module, node: ast.ClassDef) -> frozenset[str] | None:
    """``FAULTS`` as the class body writes it: absent (none), ``frozenset()`` or
    ``frozenset({"robot", ...})`` of known kinds; None for anything else.
    """
    value = _class_value(node, "FAULTS")
    if value is _ABSENT:
        return frozenset()
    if not (
        isinstance(value, ast.Call)
        and isinstance(value.func, ast.Name)
        and value.func.id == "frozenset"
        and not _bindings(tree, "frozenset")
        and not value.keywords
        and len(value.args) <= 1
    ):
        return None
    if not value.args:
        return frozenset()
    items = value.args[0]
    if not isinstance(items, ast.Set | ast.Tuple | ast.List):
        return None
    kinds = [e.value for e in items.elts if isinstance(e, ast.Constant)]
    if len(kinds) != len(items.elts) or not all(k in FAULT_PARAMS for k in kinds):
        return None  # the class itself says what is wrong (the contract's ContractError)
    return frozenset(kinds)


def _params_class(home: str, package: str, tree: ast.Module, node: ast.ClassDef) -> type | None:
    """The class ``Params = Name`` names, loaded from the module ``Name`` is imported from
    (not the model's own); :class:`~abm.params.SwarmParams` when the class sets no Params.
    """
    value = _class_value(node, "Params")
    if value is _ABSENT:
        return SwarmParams
    if not isinstance(value, ast.Name):
        return None
    binding = _sole(tree, value.id)
    if not isinstance(binding, ast.ImportFrom):
        return None
    module = _absolute(binding, package)
    if module is None or module == home:
        return None
    loaded = _load(module)
    cls = getattr(loaded, _imported_name(binding, value.id), None) if loaded else None
    if not (
        isinstance(cls, type)
        and issubclass(cls, SwarmParams)
        and dataclasses.is_dataclass(cls)
        and cls.__dataclass_params__.frozen
    ):
        return None  # the class itself says what is wrong (the contract's ContractError)
    return cls


def _load(module: str) -> object | None:
    """``module`` run from its source file without importing its packages (an imported one
    as it is), or None where it cannot be found or fails to run (importing the model then
    shows the failure as it is).

    The module is not entered in ``sys.modules``: importing the model later runs the file
    again under its package, so nothing of this load stays visible to it.
    """
    if module in sys.modules:
        return sys.modules[module]
    try:
        path = source_of(module, module)
    except ConfigError:
        return None
    spec = importlib.util.spec_from_file_location(module, path)
    if spec is None or spec.loader is None:
        return None
    loaded = importlib.util.module_from_spec(spec)
    try:
        spec.loader.exec_module(loaded)
    except Exception:  # noqa: BLE001 - the model's own import shows any failure as it is
        return None
    return loaded


# ------------------------------------------------------------------------- reading source
#: A class body that does not bind the name asked for.
_ABSENT = object()


def _parse(module: str) -> tuple[str, ast.Module] | None:
    """The package ``module`` belongs to (itself for a package) and its parsed source, found
    without importing it or its packages.
    """
    try:
        path = source_of(module, module)
        tree = ast.parse(path.read_bytes(), filename=str(path))
    except (ConfigError, SyntaxError, ValueError, OSError):
        return None
    return (module if path.name == "__init__.py" else module.rpartition(".")[0]), tree


def _absolute(binding: ast.ImportFrom, package: str) -> str | None:
    """The absolute name of the module a ``from ... import`` in ``package`` reads from."""
    if binding.level == 0:
        return binding.module
    parts = package.split(".") if package else []
    keep = len(parts) - (binding.level - 1)
    if keep < 1:
        return None
    base = ".".join(parts[:keep])
    return f"{base}.{binding.module}" if binding.module else base


def _imported_name(binding: ast.ImportFrom, local: str) -> str:
    """The name a ``from ... import`` binds as ``local`` had in its module."""
    return next(a.name for a in binding.names if (a.asname or a.name) == local)


def _class_value(node: ast.ClassDef, name: str) -> object:
    """The expression the class body assigns to ``name`` (``name = value`` or ``name: T =
    value``); :data:`_ABSENT` when the body binds no such name; None when it binds it, or
    any of :data:`_READ`, in any other way or more than once.
    """
    assigned: list[tuple[str, ast.expr]] = []
    for stmt in node.body:
        if not _binds(stmt) & set(_READ):
            continue
        if isinstance(stmt, ast.Assign) and len(stmt.targets) == 1:
            target = stmt.targets[0]
        elif isinstance(stmt, ast.AnnAssign) and stmt.value is not None:
            target = stmt.target
        else:
            return None
        if not (isinstance(target, ast.Name) and target.id in ("Params", "FAULTS")):
            return None
        assigned.append((target.id, stmt.value))
    values = [value for key, value in assigned if key == name]
    if not values:
        return _ABSENT
    return values[0] if len(values) == 1 else None


def _bindings(tree: ast.Module, name: str) -> list[ast.stmt]:
    """The top-level statements of a module that bind ``name`` anywhere inside them (a star
    import binds every name).
    """
    return [stmt for stmt in tree.body if {name, "*"} & _binds(stmt)]


def _sole(tree: ast.Module, name: str) -> ast.ClassDef | ast.ImportFrom | None:
    """The one statement that binds ``name`` in a module, when it is a top-level ``class``
    statement or ``from ... import``; else None (unbound, bound more than once or otherwise,
    any of which could make it something else).
    """
    found = _bindings(tree, name)
    if len(found) != 1:
        return None
    stmt = found[0]
    if isinstance(stmt, ast.ImportFrom) and stmt.names[0].name != "*":
        return stmt
    if isinstance(stmt, ast.ClassDef) and stmt.name == name:
        inside = set().union(*(_binds(s) for s in stmt.body))
        return None if name in inside else stmt
    return None


def _changed(tree: ast.Module, name: str) -> bool:
    """True when anything in the module sets or deletes an attribute of ``name``
    (``Model.FAULTS = ...``, ``setattr(Model, ...)``).
    """
    for node in ast.walk(tree):
        if (
            isinstance(node, ast.Attribute)
            and isinstance(node.ctx, ast.Store | ast.Del)
            and isinstance(node.value, ast.Name)
            and node.value.id == name
        ):
            return True
        if (
            isinstance(node, ast.Call)
            and isinstance(node.func, ast.Name)
            and node.func.id in ("setattr", "delattr")
            and node.args
            and isinstance(node.args[0], ast.Name)
            and node.args[0].id == name
        ):
            return True
    return False


def _binds(node: ast.AST) -> set[str]:
    """Every name bound anywhere inside ``node``, nested scopes included (more than the
    scope of ``node`` binds: a safe over-estimate), ``"*"`` for a star import.
    """
    names: set[str] = set()
    for child in ast.walk(node):
        if isinstance(child, ast.ClassDef | ast.FunctionDef | ast.AsyncFunctionDef):
            names.add(child.name)
        elif isinstance(child, ast.alias):
            names.add((child.asname or child.name).split(".")[0])
        elif isinstance(child, ast.Name) and isinstance(child.ctx, ast.Store | ast.Del):
            names.add(child.id)
        elif isinstance(child, ast.Global | ast.Nonlocal):
            names.update(child.names)
        elif isinstance(child, ast.ExceptHandler | ast.MatchAs | ast.MatchStar) and child.name:
            names.add(child.name)
        elif isinstance(child, ast.MatchMapping) and child.rest:
            names.add(child.rest)
    return names
