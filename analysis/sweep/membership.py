"""Does a run's row belong to a sweep's plan? Answered per row, without listing the plan.

A sweep folder's plan is what its ``sweep.json`` records: the grid (every value each key took
in any sweep run there), the points, the replications and the sweep seed. A row belongs when
its parameters are plan values, its ``run_id`` is the one :func:`~analysis.sweep.seeding.run_id`
gives those parameters and its replication, and its ``seed`` is the one
:func:`~analysis.sweep.seeding.spawned_seed` gives them (in a design sweep, the
:func:`~analysis.sweep.seeding.common_seed` of its replication). Listing a 1e6-run plan takes
minutes; matching a row takes ~0.1 ms.
"""

import json
from collections.abc import Mapping

import numpy as np

from analysis.sweep.integrity import CorruptResultError
from analysis.sweep.seeding import common_seed, run_id, spawned_seed
from analysis.sweep.spec import Sweep

__all__ = ["PlanIndex"]

_NONE = object()


class PlanIndex:
    """The runs of a plan, as read from a sweep manifest (``sweep.json``)."""

    def __init__(self, manifest: Mapping) -> None:
        manifest = json.loads(json.dumps(dict(manifest), default=str))  # values as stored
        self.grid: dict[str, list] = dict(manifest.get("grid") or {})
        self.points: list[dict] = list(manifest.get("points") or [])
        self.replications = int(manifest.get("replications", 1))
        self.seed = int(manifest.get("seed", 0))
        self.common = bool(manifest.get("design"))  # a design's runs share seeds per rep
        self._index = _index_points(self.points)

    @classmethod
    def of(cls, sweep: Sweep) -> "PlanIndex":
        """The plan of one sweep (not of the folder it writes into)."""
        return cls(sweep.manifest())

    def match(self, row: Mapping, rid: str) -> tuple[dict, int]:
        """The plan's parameters and replication of the run ``rid`` whose row is ``row``.

        Raises:
            CorruptResultError: ``wrong-params`` (a parameter the plan does not have),
                ``not-in-plan`` (the plan gives these parameters another run id, or the
                replication is out of range) or ``wrong-seed``.

        """
        rep = _plain(row.get("rep"))
        if isinstance(rep, bool) or not isinstance(rep, int) or not 0 <= rep < self.replications:
            raise CorruptResultError(
                "not-in-plan", f"replication {rep!r}, the plan has 0 to {self.replications - 1}"
            )
        params = self._params(row)
        for point in self._points(row):
            full = {**params, **point}
            if run_id(full, rep) == rid:
                break
        else:
            raise CorruptResultError(
                "not-in-plan",
                f"the plan gives its parameters (replication {rep}) run id "
                f"{run_id({**params, **self._points(row)[0]}, rep)}, not {rid}",
            )
        if self.common:
            seed = common_seed(self.seed, rep)[0]
        else:
            seed = spawned_seed(self.seed, full, rep)[0]
        if _plain(row.get("seed")) != seed:
            raise CorruptResultError(
                "wrong-seed", f"seed {_plain(row.get('seed'))!r}, the plan gives run {rid} {seed}"
            )
        return full, rep

    def holds(self, params: Mapping, rep: int) -> bool:
        """True when this plan has the run (``params``, ``rep``) (exactly these keys)."""
        if rep >= self.replications:
            return False
        keys = set(params)
        points = self._holding(params) if self.points else [{}]
        return any(keys == set(self.grid) | set(point) for point in points) and all(
            any(_same(params[k], v) for v in vs) for k, vs in self.grid.items()
        )

    def _params(self, row: Mapping) -> dict:
        params = {}
        for key, values in self.grid.items():
            value = row.get(key, _NONE)
            hit = next((v for v in values if _same(value, v)), _NONE)
            if hit is _NONE:
                shown = "no such column" if value is _NONE else f"{_plain(value)!r}"
                raise CorruptResultError(
                    "wrong-params", f"{key} {shown}, the plan has {key} in {values!r}"
                )
            params[key] = hit
        return params

    def _points(self, row: Mapping) -> list[dict]:
        if not self.points:
            return [{}]
        hits = self._holding(row)
        if not hits:
            raise CorruptResultError("wrong-params", "its parameters are none of the plan's points")
        return hits

    def _holding(self, row: Mapping) -> list[dict]:
        """The plan's points whose every value ``row`` holds (by :func:`_same`), in plan order:
        looked up by key (a design's 24,000 points against 24,000 run files on a restart), or
        compared one by one where a value cannot be a key.
        """
        if self._index is None:
            return [p for p in self.points if _holds(row, p)]
        found = []
        for keys, table in self._index.items():
            try:
                found += table.get(tuple(_key(row.get(k, _NONE)) for k in keys), [])
            except TypeError:  # the row's value cannot be a key (and so is no point's)
                continue
        return [p for _, p in sorted(found, key=lambda hit: hit[0])]


def _holds(row: Mapping, point: Mapping) -> bool:
    """Whether ``row`` holds every value of ``point``."""
    return all(_same(row.get(k, _NONE), v) for k, v in point.items())


def _index_points(points: list[dict]) -> dict | None:
    """The points by their keys, then by :func:`_key` of their values: ``{keys: {values:
    [(position, point), ...]}}``; None if some value cannot be a key.
    """
    index: dict[tuple, dict[tuple, list]] = {}
    for position, point in enumerate(points):
        keys = tuple(sorted(point))
        try:
            values = tuple(_key(point[k]) for k in keys)
            index.setdefault(keys, {}).setdefault(values, []).append((position, point))
        except TypeError:
            return None
    return index


def _key(value: object) -> object:
    """A dict key for ``value`` such that two values have equal keys exactly when
    :func:`_same` calls them equal (a missing column, ``_NONE``, equals nothing, itself too:
    no point holds it).
    """
    if value is _NONE:
        return _NONE
    value = _plain(value)
    if isinstance(value, list):
        return ("list", *(_key(v) for v in value))
    if isinstance(value, bool):
        return ("bool", value)
    if _missing(value):
        return ("missing",)
    hash(value)  # TypeError for a value that cannot be a key
    return value


def _plain(value: object) -> object:
    """A value read back from Parquet as the plain Python value the plan holds."""
    if isinstance(value, np.ndarray):
        return [_plain(v) for v in value.tolist()]
    if isinstance(value, list | tuple):
        return [_plain(v) for v in value]
    if isinstance(value, np.generic):
        return value.item()
    return value


def _same(a: object, b: object) -> bool:
    """Equal as parameter values: numbers by value (never a bool for a number), lists
    element by element, a missing value (None or NaN) only for a missing value.
    """
    if a is _NONE or b is _NONE:
        return False
    a, b = _plain(a), _plain(b)
    if isinstance(a, list) or isinstance(b, list):
        return (
            isinstance(a, list)
            and isinstance(b, list)
            and len(a) == len(b)
            and all(_same(x, y) for x, y in zip(a, b, strict=True))
        )
    if isinstance(a, bool) or isinstance(b, bool):
        return type(a) is type(b) and a == b
    if _missing(a) or _missing(b):
        return _missing(a) and _missing(b)
    return a == b


def _missing(value: object) -> bool:
    return value is None or (isinstance(value, float) and value != value)
