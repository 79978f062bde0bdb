"""Every key of every model's summary has a documented unit, through one declared hook (the
framework's keys in abm.units.COMMON, a model's in its SUMMARY_UNITS); `abm run` prints them;
the beacon/explorer picture marks the base beacon that ``robots`` counts and ``n_robots`` not.
"""

import numpy as np
import pandas as pd
import pytest

from abm import registry
from abm.contract import check_model
from abm.errors import ContractError
from abm.units import COMMON, Quantity, quantity_of, undocumented
from analysis.cli.run import format_summary, unit_of


@pytest.mark.parametrize("name", registry.model_names())
def test_every_summary_key_of_every_model_has_a_unit(name):
    cls = registry.model_class(name)
    model = cls(seed=1, **dict(cls.QUICK))
    summary = model.run().summary()
    assert undocumented(cls.SUMMARY_UNITS, summary) == []
    for key in summary:
        assert quantity_of(cls.SUMMARY_UNITS, key).description


def test_tangible_pso_deployment_keys_have_units():
    cls = registry.model_class("tangible-pso")
    summary = cls(seed=1, **{**cls.QUICK, "deploy": True}).run().summary()
    assert "deployed_cost" in summary
    assert undocumented(cls.SUMMARY_UNITS, summary) == []


def test_a_key_has_one_unit_across_models():
    seen: dict[str, tuple[str, str]] = {}
    for name in registry.model_names():
        for key, quantity in registry.model_class(name).SUMMARY_UNITS.items():
            assert key not in COMMON, f"{name} redeclares the framework's {key!r}"
            other = seen.setdefault(key, (name, quantity.unit))
            assert other[1] == quantity.unit, f"{key!r}: {other} vs {name} {quantity.unit}"


def test_abm_run_prints_each_models_units():
    assert unit_of("energy_flight") == "J"  # beacon/explorer
    assert unit_of("pheromone_radius") == "m"  # stigmergy
    assert unit_of("envsize") == "m^2"
    assert unit_of("coverage_500") == "%"  # a SugarMap checkpoint, by its pattern
    assert unit_of("coverage_time") == "s"  # the exact key wins over that pattern
    assert unit_of("scout_drive") == "m"  # SI, though the hierarchy's report plots cm
    assert unit_of("bytes") == "byte" and unit_of("entropy") == "bit"
    # names, seeds, flags, counts and plain numbers print bare
    for key in ("end_reason", "seed", "complete", "n_robots", "polarisation"):
        assert unit_of(key) == "", key
    text = format_summary({"n_robots": 20, "robots": 21, "energy_flight": 2.5})
    assert text.splitlines()[2].split()[-1] == "J"
    # a value under 10 keeps three significant digits, a larger one a decimal
    text = format_summary({"mean_flight_speed": 0.6757, "flight_time": 1715.43})
    assert [line.split()[1:] for line in text.splitlines()] == [
        ["0.676", "m/s"],
        ["1,715.4", "s"],
    ]
    # a value the run could not measure is "none", with no unit ("nan %" read as a number)
    text = format_summary({"swap_resolved_pct": float("nan"), "flight_time": float("inf")})
    assert [line.split()[1:] for line in text.splitlines()] == [["none"], ["inf", "s"]]


#: Every unit a summary may use: SI (s, m, m^2, J, W, 1/s, m/s) and the unit-free kinds.
SI = {
    "s",
    "m",
    "m^2",
    "J",
    "W",
    "1/s",
    "m/s",
    "%",
    "1",
    "count",
    "flag",
    "text",
    "id",
    "bit",
    "byte",
}


@pytest.mark.parametrize("name", registry.model_names())
def test_every_declared_unit_is_si(name):
    units = registry.model_class(name).SUMMARY_UNITS
    assert {key: q.unit for key, q in units.items() if q.unit not in SI} == {}


def test_the_contract_refuses_centimetres():
    cls = registry.model_class("flocking")
    for unit in ("cm", "cm^2"):
        bad = type("InCm", (cls,), {"SUMMARY_UNITS": {"updates": Quantity(unit, "x")}})
        with pytest.raises(ContractError, match="SUMMARY_UNITS\\['updates'\\].*one of"):
            check_model(bad)


def test_the_hierarchy_summary_is_in_metres():
    """Areas in m^2 and lengths in m: the queen's area is the 20 m room's 400 m^2 and a
    scout's scan area and drive distance are the sums of its bubbles' pi r^2 and path lengths
    (both in metres inside the model).
    """
    cls = registry.model_class("hierarchy")
    model = cls(seed=1, **dict(cls.QUICK)).run()
    summary = model.summary()
    units = {key: quantity_of(cls.SUMMARY_UNITS, key).unit for key in summary}
    assert {k: u for k, u in units.items() if u not in SI} == {}
    assert units["queen_scan_area"] == "m^2" and units["scout_drive"] == "m"
    assert summary["queen_scan_area"] == pytest.approx(model.arena.width * model.arena.height)
    scouts = model.scouts()
    assert summary["scout_scan_area"] == pytest.approx(np.mean([s.scan_area for s in scouts]))
    assert summary["scout_drive"] == pytest.approx(np.mean([s.drive_distance for s in scouts]))


def test_robots_and_n_robots_are_explained():
    cls = registry.model_class("beacon-explorer")
    assert "base beacon" in cls.SUMMARY_UNITS["robots"].description
    assert "without the base" in cls.SUMMARY_UNITS["n_robots"].description


def test_the_contract_refuses_a_unit_it_does_not_know():
    cls = registry.model_class("flocking")
    bad = type("BadUnits", (cls,), {"SUMMARY_UNITS": {"updates": Quantity("furlong", "x")}})
    with pytest.raises(ContractError, match="SUMMARY_UNITS\\['updates'\\].*one of"):
        check_model(bad)
    worse = type("NotQuantity", (cls,), {"SUMMARY_UNITS": {"updates": "count"}})
    with pytest.raises(ContractError, match="abm.units.Quantity"):
        check_model(worse)


def test_the_picture_marks_the_base_beacon(tmp_path):
    from abm.draw import draw_swarm

    cls = registry.model_class("beacon-explorer")
    model = cls(seed=1, **dict(cls.QUICK)).run(until=20.0)
    (base,) = [layer for layer in model.layers() if layer.label.startswith("base beacon")]
    assert np.allclose(base.points, [model.base.pos])
    view = draw_swarm(model)
    labels = [h.get_label() for h in view.legend_handles()]
    assert "base beacon (robots = n_robots + 1)" in labels
    marked = view.ax.collections
    assert any(np.allclose(c.get_offsets(), [model.base.pos]) for c in marked)


def test_the_hierarchy_claims_quote_square_metres_and_metres():
    """C2 and C6 quote the scouts' means in the summary's units (the report's are cm², cm)."""
    from models.hierarchy.claims import TESTS

    rows = [
        {"W": w, "S": s, "N": 1 + w + w * s, "scout_scan_area": 600.0 / (w * s),
         "scout_drive": 300.0 / (w * s)}
        for w in (2, 3) for s in (2, 3, 4)
    ]  # fmt: skip
    runs = pd.DataFrame(rows)
    area, drive = TESTS["C2"](runs, None), TESTS["C6"](runs, None)
    assert "150.0 m² at N=7 -> 50.0 m² at N=16" in area.ours
    assert "75.0 m at N=7 -> 25.0 m at N=16" in drive.ours
