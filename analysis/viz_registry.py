"""Which models have a SolaraViz page, with their sliders and live plots.

Adding a model is one entry in :data:`REGISTRY`. This module is also the Solara app that
``abm viz`` serves: Solara asks it for ``Page``, built for the model named in the environment
variable ``ABM_VIZ_MODEL`` (see :func:`__getattr__`), so importing it needs no Solara.
"""

import importlib
import os
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cache

from abm.errors import ConfigError

__all__ = ["REGISTRY", "VizEntry", "entry", "page"]

#: Environment variable naming the model the Solara app shows.
ENV_VAR = "ABM_VIZ_MODEL"


def _slider(label: str, value, low, high, step) -> dict:
    kind = "SliderFloat" if isinstance(value, float) else "SliderInt"
    return {"type": kind, "label": label, "value": value, "min": low, "max": high, "step": step}


def _select(label: str, value: str, values: list[str]) -> dict:
    return {"type": "Select", "label": label, "value": value, "values": values}


def _checkbox(label: str, value: bool) -> dict:
    return {"type": "Checkbox", "label": label, "value": value}


@dataclass(frozen=True)
class VizEntry:
    """One model's page.

    Attributes:
        name: the CLI name (``abm viz NAME``).
        target: ``"module:Class"`` of the SwarmModel subclass.
        params: SolaraViz model parameters (sliders, selects, fixed values).
        series: DataCollector column -> axis label with unit, plotted live.
        coverage: ``f(model) -> (covered raster, pixel m) | None`` when the model keeps its
            covered area elsewhere than a ``coverage`` CoverageRaster.

    """

    name: str
    target: str
    params: dict
    series: dict = field(default_factory=dict)
    coverage: Callable | None = None

    def model_class(self) -> type:
        """Import and return the model class."""
        module, _, attr = self.target.partition(":")
        return getattr(importlib.import_module(module), attr)


REGISTRY: dict[str, VizEntry] = {
    "beacon-explorer": VizEntry(
        name="beacon-explorer",
        target="models.beacon_explorer:BeaconExplorerModel",
        params={
            "world": _select("world", "corridor", ["corridor", "open", "mixed"]),
            "complexity": _select("complexity", "high", ["low", "medium", "high"]),
            "launch_period": _slider("launch period t (s)", 6.0, 1.0, 30.0, 1.0),
            "n_robots": _slider("robots", 20, 2, 40, 1),
            "max_speed": _slider("explorer speed (m/s)", 1.0, 0.2, 2.0, 0.1),
            "hover_beacons": _checkbox("beacons hover (no ceiling)", False),
            "seed": _slider("seed", 1, 0, 100, 1),
        },
        series={"coverage": "coverage (% of free area)", "energy": "energy used (J)"},
    ),
    "stigmergy": VizEntry(
        name="stigmergy",
        target="models.stigmergy:StigmergyModel",
        params={
            "map": _select(
                "map",
                "hall100",
                [
                    "hall100",
                    "hall100x200",
                    "divided",
                    "complex",
                    "rooms4",
                    "serpentine",
                    "pillars",
                    "lshape",
                    "wide",
                ],
            ),
            "pheromone_radius": _slider("pheromone radius C_rb (m)", 20.0, 5.0, 60.0, 5.0),
            "launch_rate": _slider("launch rate eta (robots per 0.5 s)", 0.01, 0.005, 0.1, 0.005),
            "max_speed": _slider("UAV speed (m/s)", 2.0, 0.5, 5.0, 0.5),
            "seed": _slider("seed", 1, 0, 100, 1),
        },
        series={"ca": "area seen ca (fraction of free area)"},
        coverage=lambda model: (model.seen, model.arena.resolution),
    ),
}


def entry(name: str) -> VizEntry:
    """The registry entry of a model, or a ConfigError listing the known names."""
    if name not in REGISTRY:
        known = ", ".join(sorted(REGISTRY))
        raise ConfigError(f"no viz page for model {name!r}; known models: {known}")
    return REGISTRY[name]


@cache
def page(name: str):
    """The Solara ``Page`` component of a registered model (needs the viz extra)."""
    from abm.viz.page import make_page

    spec = entry(name)
    extra = {} if spec.coverage is None else {"coverage": spec.coverage}
    return make_page(spec.model_class(), spec.params, name=spec.name, series=spec.series, **extra)


def __getattr__(name: str):
    if name == "Page":
        return page(os.environ.get(ENV_VAR, "beacon-explorer"))
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
