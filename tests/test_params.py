"""Parameters: every field validated once (type and range), help text from the docstring, one
place that maps keywords; the CLI's flags and the contract rest on them."""

import dataclasses

import pytest

from abm.errors import ConfigError
from abm.params import SwarmParams, check_value, field_help, make_params, param
from models.beacon_explorer.params import BeaconExplorerParams
from models.stigmergy.params import StigmergyParams


@dataclasses.dataclass(frozen=True)
class Demo(SwarmParams):
    """A demo.

    Attributes:
        speed: how fast (m/s); it may
            span lines.
        count: how many.
        name: a choice.
        point: where (m).
        flag: on or off.

    """

    speed: float = param(1.0, low=0.0, high=5.0, low_open=True)
    count: int | None = param(None, low=1, integer=True)
    name: str = param("a", choices=("a", "b"))
    point: tuple[float, float] | None = None
    flag: bool = False


def test_values_are_checked_and_normalised():
    p = Demo(speed=2, count=3, point=[1, 2])
    assert p.speed == 2.0 and isinstance(p.speed, float)
    assert p.point == (1.0, 2.0) and p.count == 3
    for kwargs, match in [
        ({"speed": 0}, r"speed must be in \(0, 5\]"),
        ({"speed": "fast"}, "speed must be a number"),
        ({"count": 0}, r"count must be in \[1"),
        ({"count": 1.5}, "count must be an integer"),
        ({"name": "c"}, "name must be one of 'a', 'b'"),
        ({"point": (1.0,)}, "point must have 2 values"),
        ({"flag": 1}, "flag must be True or False"),
        ({"time_limit": -1.0}, r"time_limit must be in \(0"),
        ({"trace_interval": 0.0}, r"trace_interval must be in \(0"),
    ]:
        with pytest.raises(ConfigError, match=match):
            Demo(**kwargs)


def test_unknown_keywords_name_the_accepted_ones_and_a_close_match():
    with pytest.raises(ConfigError, match=r"unknown parameter 'sped' \(did you mean 'speed'\?\)"):
        make_params(Demo, {"sped": 1.0})
    with pytest.raises(ConfigError, match="Demo accepts: time_limit, .*, flag"):
        make_params(Demo, {"x": 1})
    assert check_value(Demo, "speed", 3) == 3.0
    with pytest.raises(ConfigError, match="unknown parameter 'nope'"):
        check_value(Demo, "nope", 1)


def test_help_comes_from_the_attributes_section_of_the_class_and_its_bases():
    helps = field_help(Demo)
    assert helps["speed"] == "how fast (m/s); it may span lines."
    assert helps["time_limit"].startswith("the run ends at this simulated time")
    assert set(helps) >= {f.name for f in dataclasses.fields(Demo)}


def test_replace_validates_and_plain_is_json_friendly():
    p = Demo().replace(speed=4.0)
    assert p.speed == 4.0
    with pytest.raises(ConfigError, match="speed"):
        p.replace(speed=9.0)
    assert Demo(point=(1, 2)).plain()["point"] == [1.0, 2.0]


@pytest.mark.parametrize("params_cls", [BeaconExplorerParams, StigmergyParams])
def test_every_model_parameter_is_described(params_cls):
    helps = field_help(params_cls)
    for f in dataclasses.fields(params_cls):
        assert len(helps[f.name]) > 10, f.name
