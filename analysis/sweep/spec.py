"""What a sweep is: a model, a parameter grid, replications and a seed; read from TOML.

Every grid key is a field of the model's params (so every parameter is sweepable), checked
against its type and range before any run starts; ``seed`` is not a key (per-run seeds are
spawned from the sweep seed). Besides the Cartesian ``grid``, a sweep may list ``points``:
parameter sets taken together (e.g. a 10-node swarm split 2 + 8, 3 + 7, ...); every grid point
is combined with every point. A sweep may instead hold a ``design`` (a Sobol', Morris or Latin
hypercube sample drawn with SALib, :mod:`analysis.sweep.design`): its rows become the points,
and the grid then only fixes settings (one value per key).
"""

import itertools
import json
import math
import re
import tomllib
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from abm.errors import ConfigError, check_seed
from abm.params import check_value, param_fields, refuse_fault_keyword
from abm.registry import model_class, name_of, target_of
from analysis.sweep.design import Design, check_design

__all__ = [
    "MAX_RUNS",
    "NAME_RULE",
    "Sweep",
    "TOML_KEYS",
    "check_int",
    "check_name",
    "load_sweep",
]

#: Keys a sweep file may hold.
TOML_KEYS = (
    "name",
    "description",
    "model",
    "seed",
    "replications",
    "time_series",
    "grid",
    "points",
    "design",
)
_RESERVED = ("seed", "rng")

#: Most runs one sweep may hold (ours): planning takes ~0.1 ms a run, and a study larger than
#: this is clearer as several sweeps (and several folders).
MAX_RUNS = 1_000_000

#: What a sweep name may be: it names a folder under ``out/sweeps/``, so only plain characters
#: and never a path (no ``/``, no ``..``, not empty, not hidden).
NAME_RULE = "1 to 100 characters: ASCII letters, digits, '-', '_' and '.', not starting with '.'"
_NAME = re.compile(r"[A-Za-z0-9_-][A-Za-z0-9_.-]{0,99}")


@dataclass(frozen=True)
class Sweep:
    """What to run: a model, a parameter grid, replications and the sweep seed.

    Attributes:
        model: a registered model name, ``"module:Class"`` or a model class.
        grid: parameter -> list of values (a scalar means one value).
        replications: runs per grid point.
        points: parameter sets taken together, each combined with every grid point.
        seed: the sweep seed; per-run seeds are spawned from it.
        name: the sweep's name, a plain folder name (:data:`NAME_RULE`); the default output
            folder is ``out/sweeps/<name>``.
        time_series: also keep each run's state counts over time.
        description: free text, shown in reports.
        design: a sensitivity design (a ``[design]`` table or a :class:`Design`); its sample
            rows become the points (``points`` must then be empty, and every grid key take
            one value).

    """

    model: str | type
    grid: Mapping[str, Sequence]
    replications: int = 1
    seed: int = 0
    name: str = "sweep"
    time_series: bool = False
    description: str = ""
    points: Sequence[Mapping[str, object]] = ()
    design: Design | Mapping | None = None
    model_cls: type = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        check_name(self.name)
        cls = model_class(self.model)  # a "module:Class" is checked before it is imported
        object.__setattr__(self, "model_cls", cls)
        check_int("replications", self.replications, 1)
        check_seed(self.seed, allow_none=False)
        if not isinstance(self.time_series, bool):
            raise ConfigError(f"time_series must be true or false, got {self.time_series!r}")
        if self.design is not None:
            self._sample_design(cls)
        points = check_points(cls, self.points, self.grid)
        object.__setattr__(self, "points", points)
        object.__setattr__(self, "grid", check_grid(cls, self.grid, allow_empty=bool(points)))
        if self.n_runs > MAX_RUNS:
            raise ConfigError(
                f"the sweep has {self.n_runs:.3g} runs (grid points x points x replications); "
                f"at most {MAX_RUNS:.0e} in one sweep: split it into several"
            )

    def _sample_design(self, cls: type) -> None:
        """Check the design and make its sample rows the sweep's points (repeated rows once)."""
        if self.points:
            raise ConfigError("a sweep with a [design] takes no [[points]]: the design gives them")
        if not isinstance(self.grid, Mapping):
            raise ConfigError(f"grid must be a table ([grid]), got {self.grid!r}")
        for key, values in self.grid.items():
            if not isinstance(values, str) and isinstance(values, Sequence) and len(values) != 1:
                raise ConfigError(
                    f"grid key {key!r} takes {len(values)} values; with a [design] every grid "
                    "key takes one value (a fixed setting): vary it in the design instead"
                )
        design = check_design(cls, self.design, self.seed, fixed=self.grid)
        unique = {json.dumps(row, sort_keys=True): row for row in design.rows()}
        object.__setattr__(self, "design", design)
        object.__setattr__(self, "points", tuple(unique.values()))

    @property
    def target(self) -> str:
        """``"module:Class"`` of the model (what worker processes import)."""
        return target_of(self.model_cls)

    @property
    def n_runs(self) -> int:
        """Grid points times replications."""
        grid = math.prod(len(v) for v in self.grid.values())
        return grid * max(len(self.points), 1) * self.replications

    @property
    def n_points(self) -> int:
        """Distinct parameter sets (grid points x points)."""
        return self.n_runs // self.replications

    def conditions(self) -> list[dict]:
        """Every grid point as a dict of constructor keywords, in grid order."""
        return list(self.iter_conditions())

    def iter_conditions(self) -> Iterator[dict]:
        """The grid points one at a time, in grid order (a 1e6-point grid is never held in
        memory: the first run starts while the rest are still unplanned).
        """
        keys = list(self.grid)
        for vals in itertools.product(*self.grid.values()):
            g = dict(zip(keys, vals, strict=True))
            for p in self.points or [{}]:
                yield {**g, **p}

    def manifest(self) -> dict:
        """A JSON-able description (written as ``sweep.json`` beside the runs)."""
        model = self.model if isinstance(self.model, str) else name_of(self.model_cls)
        return {
            "name": self.name,
            "description": self.description,
            "model": model or self.target,
            "target": self.target,
            "seed": self.seed,
            "replications": self.replications,
            "time_series": self.time_series,
            "grid": {k: list(v) for k, v in self.grid.items()},
            "points": [dict(p) for p in self.points],
            **({"design": self.design.manifest()} if self.design is not None else {}),
            # the unit of each summary key, so runs made in other units are never mixed
            "units": summary_units(self.model_cls),
        }


def summary_units(cls: type) -> dict[str, str]:
    """The unit symbol of each summary key a model documents (its ``SUMMARY_UNITS`` and the
    framework's common keys), as ``sweep.json`` records them.
    """
    from abm.units import quantity_of

    declared = getattr(cls, "SUMMARY_UNITS", {}) or {}
    keys = {*declared, "time", "coverage_area", "energy_total"}
    units = {k: quantity_of(declared, k) for k in sorted(keys)}
    return {k: q.unit for k, q in units.items() if q is not None}


def check_name(name: object) -> None:
    """Raise ConfigError unless ``name`` is a plain sweep name (see :data:`NAME_RULE`).

    A name becomes the folder ``out/sweeps/<name>``: ``"/tmp/x"``, ``"../../x"`` or ``""``
    would write outside it (or into ``out/sweeps`` itself), so anything but a plain name is
    refused before any folder is made.
    """
    if not isinstance(name, str) or not _NAME.fullmatch(name):
        raise ConfigError(f"name must be {NAME_RULE}; got {name!r}")


def check_int(name: str, value, low: int) -> None:
    """Raise ConfigError unless ``value`` is an integer >= ``low``."""
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < low:
        raise ConfigError(f"{name} must be an integer >= {low}, got {value!r}")


def check_points(model_cls: type, points: Sequence, grid: Mapping) -> tuple[dict, ...]:
    """Every point a table of parameters the model accepts, none also a grid key."""
    if isinstance(points, Mapping) or not isinstance(points, Sequence):
        raise ConfigError(f"points must be a list of tables ([[points]]), got {points!r}")
    checked = []
    for k, point in enumerate(points):
        if not isinstance(point, Mapping) or not point:
            raise ConfigError(f"points[{k}] must be a non-empty table, got {point!r}")
        shared = sorted(set(point) & set(grid))
        if shared:
            raise ConfigError(f"points[{k}] sets {shared[0]!r}, which the grid varies already")
        one = check_grid(model_cls, {key: [value] for key, value in point.items()})
        checked.append({key: values[0] for key, values in one.items()})
    return tuple(checked)


def check_grid(model_cls: type, grid: Mapping, allow_empty: bool = False) -> dict[str, tuple]:
    """Every key a field of the model's params, every value one that field accepts."""
    if not isinstance(grid, Mapping) or (not grid and not allow_empty):
        raise ConfigError("grid is empty: give at least one parameter and its values")
    accepted = [f.name for f in param_fields(model_cls.Params)]
    checked = {}
    for key, values in grid.items():
        if key in _RESERVED:
            raise ConfigError(
                f"grid key {key!r} is not allowed: per-run seeds are spawned from the sweep seed"
            )
        refuse_fault_keyword(model_cls.Params, key)
        if key not in accepted:
            raise ConfigError(
                f"grid key {key!r} is not a parameter of {model_cls.__name__}; "
                f"accepted: {', '.join(accepted)}"
            )
        if isinstance(values, str) or not isinstance(values, Sequence):
            values = [values]
        if len(values) == 0:
            raise ConfigError(f"grid key {key!r} has an empty list of values")
        clean = []
        for value in values:
            try:
                clean.append(check_value(model_cls.Params, key, value))
            except ConfigError as exc:
                raise ConfigError(f"grid key {key!r}: {exc}") from exc
        if len(set(map(repr, clean))) != len(clean):
            raise ConfigError(f"grid key {key!r} repeats a value: {list(values)!r}")
        checked[key] = tuple(clean)
    return checked


def load_sweep(path: str | Path, replications: int | None = None, seed: int | None = None) -> Sweep:
    """Read and validate a sweep file (TOML); ``replications`` and ``seed`` override the file's
    values.

    An overridden seed is the sweep seed as if the file had said it (the same plan, the same
    ``sweep.json``): a sweep re-measured on a fresh seed needs no edited copy of the file, and a
    folder holding another seed's runs is refused as for any other change of plan.

    The file (UTF-8, as TOML requires) holds ``model``, ``seed``, ``replications``, optional
    ``name`` (default: the file's stem), ``description`` and ``time_series``, and a ``[grid]``
    table of parameter -> list of values. Everything is checked here, before any folder is
    made or any run starts; a ``"module:Class"`` model before its module is imported
    (:mod:`analysis.sweep.targets`).
    """
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"no sweep file {str(path)!r}")
    raw = path.read_bytes()
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ConfigError(
            f"{path}: not UTF-8 text (byte {raw[exc.start]:#04x} at offset {exc.start}); "
            "save the file as UTF-8 (TOML files are UTF-8)"
        ) from exc
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{path}: not valid TOML ({exc})") from exc
    unknown = [k for k in data if k not in TOML_KEYS]
    if unknown:
        raise ConfigError(
            f"{path}: unknown key {unknown[0]!r}; accepted keys: {', '.join(TOML_KEYS)}"
        )
    if "model" not in data:
        raise ConfigError(f"{path}: missing key 'model'")
    if "grid" not in data and "points" not in data and "design" not in data:
        raise ConfigError(f"{path}: missing key 'grid' (or 'points', or 'design')")
    data.setdefault("grid", {})
    if not isinstance(data["grid"], dict):
        raise ConfigError(f"{path}: 'grid' must be a table ([grid]), got {data['grid']!r}")
    try:
        return Sweep(
            model=data["model"],
            grid=data["grid"],
            replications=data.get("replications", 1) if replications is None else replications,
            seed=data.get("seed", 0) if seed is None else seed,
            name=data["name"] if "name" in data else _default_name(path),
            time_series=data.get("time_series", False),
            description=data.get("description", ""),
            points=data.get("points", ()),
            design=data.get("design"),
        )
    except ConfigError as exc:
        raise ConfigError(f"{path}: {exc}") from exc


def _default_name(path: Path) -> str:
    """The file's stem as the sweep's name; a stem that is not a plain name is refused with a
    hint to set ``name`` in the file.
    """
    try:
        check_name(path.stem)
    except ConfigError as exc:
        raise ConfigError(f'{exc} (the file\'s name; set name = "..." in the file)') from exc
    return path.stem
