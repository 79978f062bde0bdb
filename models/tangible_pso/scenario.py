"""The surveillance scenarios: operational area, depot, no-fly zones and the AoI map.

A scenario is a small TOML file (``scenarios/<name>.toml``, or any path): ``size`` (m), ``depot``
(x, y in m), ``a_max`` (A_max), ``[[zones]]`` with polygon ``vertices`` (m) and either
``[[aoi]]`` discs (``centre``, ``radius`` in m, ``value``) or a full ``aoi_map`` (rows of A,
row 0 south, 1 m cells). The paper publishes no geometry; the shipped maps are our
readings of Table 1 (README "What we had to choose": maps) ("nofly") and Fig. 9 ("open").
"""

import tomllib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from abm.arena import Arena
from abm.errors import ConfigError
from abm.polygons import as_polygon, inside_any

__all__ = ["SCENARIOS", "Scenario", "load_scenario"]

_HERE = Path(__file__).parent / "scenarios"
#: The built-in scenarios by name.
SCENARIOS = tuple(sorted(p.stem for p in _HERE.glob("*.toml")))


@dataclass(frozen=True, eq=False)
class Scenario:
    """One surveillance task.

    Attributes:
        name: label for reports.
        size: (width, height) of the operational area (m).
        depot: where the swarm starts (x, y, m).
        zones: no-fly zones, polygons of (x, y) vertices (m).
        aoi: the AoI map A, ``(rows, cols)``, 1 m cells, row 0 south, values in [0, a_max].
        a_max: A_max, the highest priority.

    """

    name: str
    size: tuple[float, float]
    depot: np.ndarray
    zones: tuple[np.ndarray, ...]
    aoi: np.ndarray
    a_max: float

    @classmethod
    def from_dict(cls, data: dict, where: str = "scenario") -> "Scenario":
        """Build and check a scenario from plain data (a parsed TOML file)."""
        try:
            width, height = (float(v) for v in data["size"])
            depot = np.asarray(data["depot"], dtype=float).reshape(2)
        except (KeyError, TypeError, ValueError) as err:
            raise ConfigError(
                f"{where}: needs size = [w, h] and depot = [x, y] (m): {err}"
            ) from err
        if width <= 0 or height <= 0:
            raise ConfigError(f"{where}: size must be positive, got {[width, height]}")
        a_max = float(data.get("a_max", 1.0))
        if a_max <= 0:
            raise ConfigError(f"{where}: a_max must be positive, got {a_max}")
        zones = tuple(
            as_polygon(z.get("vertices"), f"{where}: zone {i}")
            for i, z in enumerate(data.get("zones", []))
        )
        cols, rows = int(np.ceil(width)), int(np.ceil(height))
        if "aoi_map" in data:
            aoi = np.asarray(data["aoi_map"], dtype=float)
            if aoi.shape != (rows, cols):
                raise ConfigError(
                    f"{where}: aoi_map must be {rows} x {cols} cells, got {aoi.shape}"
                )
        else:
            aoi = np.zeros((rows, cols))
            cy, cx = np.mgrid[0:rows, 0:cols] + 0.5
            for disc in data.get("aoi", []):
                (x, y), r = disc["centre"], float(disc["radius"])
                value = float(disc.get("value", a_max))
                inside = (cx - x) ** 2 + (cy - y) ** 2 <= r * r
                aoi[inside] = np.maximum(aoi[inside], value) if value >= 0 else value
        if (aoi < 0).any() or (aoi > a_max).any() or not np.isfinite(aoi).all():
            bad = aoi[(aoi < 0) | (aoi > a_max) | ~np.isfinite(aoi)][0]
            raise ConfigError(
                f"{where}: AoI values must lie in [0, a_max = {a_max:g}], got {bad:g}"
            )
        return cls(str(data.get("name", where)), (width, height), depot, zones, aoi, a_max)

    def check_depot(self, depot: np.ndarray, name: str = "depot") -> None:
        """ConfigError naming ``name`` unless the depot lies in the area and outside every zone."""
        x, y = depot
        if not (0 <= x <= self.size[0] and 0 <= y <= self.size[1]):
            raise ConfigError(
                f"{name} {tuple(depot.tolist())} must lie in the operational area "
                f"[0, {self.size[0]:g}] x [0, {self.size[1]:g}] m"
            )
        if inside_any(depot[None], self.zones)[0]:
            raise ConfigError(f"{name} {tuple(depot.tolist())} lies inside a no-fly zone")

    def arena(self, resolution: float = 0.5) -> Arena:
        """The area as the framework's grid arena: cells whose centre is in a zone are walls."""
        cols = int(np.ceil(self.size[0] / resolution))
        rows = int(np.ceil(self.size[1] / resolution))
        centres = (np.stack(np.mgrid[0:rows, 0:cols][::-1], axis=-1) + 0.5) * resolution
        free = ~inside_any(centres, self.zones)
        return Arena(free, resolution, name=self.name)


def load_scenario(name: str) -> Scenario:
    """A built-in scenario by name, or a TOML file by path.

    Raises:
        ConfigError: naming ``scenario`` when the name is unknown or the file is bad.

    """
    path = _HERE / f"{name}.toml" if name in SCENARIOS else Path(name)
    if not path.is_file():
        raise ConfigError(
            f"scenario {name!r} is neither a built-in scenario {SCENARIOS} nor a TOML file"
        )
    try:
        data = tomllib.loads(path.read_text())
    except tomllib.TOMLDecodeError as err:
        raise ConfigError(f"scenario {name!r}: not valid TOML: {err}") from err
    return Scenario.from_dict(data, f"scenario {name!r}")
