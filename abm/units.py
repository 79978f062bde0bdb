"""The unit and meaning of every key of a run's summary.

The framework's own keys (:meth:`abm.model.SwarmModel.common_summary`) are documented once,
here, in :data:`COMMON`; each model declares its own keys in its ``SUMMARY_UNITS`` (a mapping
of key, or ``fnmatch`` pattern such as ``"coverage_*"``, to a :class:`Quantity`), checked by
the model contract. ``abm run`` prints the units beside the values; reports label axes with
them.

Units are SI (s, m, m^2, J, W, m/s), also where a source publishes its numbers in other units
(the model's documentation then gives the conversion); besides those:

* ``%``: percent; ``1``: a dimensionless number (a ratio, a share in [0, 1], a score);
* ``count``: a number of things (the description says of what);
* ``flag``: true or false (1.0 or 0.0 when averaged); ``text``: a name or label; ``id``: an
  identifier (a seed);
* ``bit``: information (log2); ``byte``: message size.
"""

from collections.abc import Mapping
from dataclasses import dataclass
from fnmatch import fnmatchcase

__all__ = ["COMMON", "UNITS", "Quantity", "declare", "quantity_of", "undocumented", "unit_of"]

#: The unit symbols a summary key may have.
UNITS = frozenset(
    {"s", "m", "m^2", "J", "W", "1/s", "m/s",
     "%", "1", "count", "flag", "text", "id", "bit", "byte"}
)  # fmt: skip


@dataclass(frozen=True)
class Quantity:
    """The unit and meaning of one summary key.

    Attributes:
        unit: one of :data:`UNITS`.
        description: what the number is, in a phrase (with the source's symbol where it has one).

    """

    unit: str
    description: str


#: The keys every model's summary has (or has when it covers, has energy, or its robots fail).
COMMON: Mapping[str, Quantity] = {
    "time": Quantity("s", "simulated time when the run ended"),
    "end_reason": Quantity("text", "why the run ended (the first reason wins)"),
    "collisions": Quantity("count", "wall contacts plus two per robot-robot contact"),
    "wall_collisions": Quantity("count", "contacts of a robot with a wall"),
    "robot_collisions": Quantity("count", "robot-robot contacts, two per contact"),
    "coverage_area": Quantity("%", "share of the free area ever covered"),
    "energy_total": Quantity("J", "energy drawn by the whole swarm"),
    "failed": Quantity("count", "robots failed (abm.faults)"),
    "faults_skipped": Quantity(
        "count", "scheduled faults (fault_times) that found no robot to fail (abm.faults)"
    ),
}


#: Every model class's declared units, in the order the classes were defined (see declare).
_DECLARED: list[Mapping[str, Quantity]] = []


def declare(units: Mapping[str, Quantity]) -> None:
    """Record a model class's ``SUMMARY_UNITS`` (called as each SwarmModel subclass is
    defined), so a key's unit can be found from the key alone (``abm run`` prints a summary
    dict that does not name its model).
    """
    _DECLARED.append(units)


def quantity_of(declared: Mapping[str, Quantity] | None, key: str) -> Quantity | None:
    """The quantity of ``key``: the framework's, else the model's exact key, else the first
    of the model's patterns that matches it; None when nothing documents it.

    Args:
        declared: the model's ``SUMMARY_UNITS``; None: those of every model class defined so
            far (exact keys first, then patterns; the contract keeps a key's unit one across
            models).
        key: a summary key.

    """
    if key in COMMON:
        return COMMON[key]
    tables = _DECLARED if declared is None else [declared]
    for table in tables:
        if key in table:
            return table[key]
    for table in tables:
        for pattern, quantity in table.items():
            if fnmatchcase(key, pattern):
                return quantity
    return None


def unit_of(key: str, declared: Mapping[str, Quantity] | None = None) -> str:
    """The unit symbol of ``key`` ("" when nothing documents it); ``declared`` as in
    :func:`quantity_of`.
    """
    quantity = quantity_of(declared, key)
    return "" if quantity is None else quantity.unit


def undocumented(declared: Mapping[str, Quantity], keys: object) -> list[str]:
    """The keys of a summary that neither the framework nor the model documents."""
    return [k for k in keys if quantity_of(declared, k) is None]
