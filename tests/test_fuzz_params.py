"""Fuzzing every registered model's parameters: wrong types, NaN, infinities, negative, huge and
tiny numbers, empty strings and tuples. Each case builds the model and runs it for a short
simulated time; it must run, or raise ConfigError naming a parameter it was given.
"""

import math

import numpy as np
import pytest
from fuzzing import case, examples, memory_ceiling
from hypothesis import given
from hypothesis import strategies as st

from abm.errors import ConfigError
from abm.params import field_rule, param_fields
from abm.registry import model_class, model_names

#: Simulated time each accepted case runs (s).
SHORT = 2.0

#: Values of every kind a caller might pass by mistake.
NASTY = st.one_of(
    st.none(),
    st.booleans(),
    st.integers(min_value=-(10**30), max_value=10**30),
    st.integers(min_value=-3, max_value=300),
    st.floats(allow_nan=True, allow_infinity=True),
    st.floats(min_value=-10.0, max_value=1e4),
    st.sampled_from([math.nan, math.inf, -math.inf, 0.0, -0.0, 5e-324, 1e-300, 1e300]),
    st.text(max_size=6),
    st.sampled_from(["", " ", "corridor", "hall100", "nope.png", "x.npy"]),
    st.lists(st.floats(allow_nan=True, allow_infinity=True), max_size=3).map(tuple),
    st.sampled_from([(), [], (1.0,), (5.0, 5.0), (math.nan, 1.0), (-1e9, 1e9), {}]),
)


#: Rates of events over the whole run, from none to a storm (``events=True`` fields).
STORMS = st.sampled_from([0.0, 1e-3, 0.1, 10.0, 1e4, 1e6, 1e12, 1e300])


def _values(field) -> st.SearchStrategy:
    rule = field_rule(field)
    choices = rule.get("choices") or ()
    own = [st.sampled_from(choices)] if choices else []
    if rule.get("events"):
        own.append(STORMS)
    return st.one_of(*own, st.just(field.default), NASTY)


def _kwargs(model: str) -> st.SearchStrategy:
    fields = {f.name: f for f in param_fields(model_class(model).Params)}
    names = st.lists(st.sampled_from(sorted(fields)), min_size=1, max_size=3, unique=True)
    return names.flatmap(lambda keys: st.fixed_dictionaries({k: _values(fields[k]) for k in keys}))


@pytest.fixture(scope="module", autouse=True)
def _ceiling():
    with memory_ceiling():
        yield


def _fuzz(model: str):
    @examples(80)
    @given(kwargs=_kwargs(model), seed=st.integers(0, 2**32 - 1))
    def one(kwargs, seed):
        with case(f"params:{model}", list(kwargs)):
            instance = model_class(model)(seed=seed, **kwargs)
            instance.run(until=min(SHORT, instance.params.time_limit))

    return one


@pytest.mark.parametrize("model", model_names())
def test_fuzzed_parameters_run_or_raise_config_error_naming_them(model):
    _fuzz(model)()


# Regression tests: one per defect the fuzzing found (each raised another exception or hung).
@pytest.mark.parametrize(
    ("model", "kwargs", "match"),
    [
        ("beacon-explorer", {"n_robots": math.nan}, "n_robots must be a number, got NaN"),
        ("sugarmap", {"n_explorers": math.inf}, "n_explorers must be a finite number"),
        ("hierarchy", {"time_limit": math.inf}, "time_limit must be a finite number"),
        ("stigmergy", {"pheromone_radius": -math.inf}, "pheromone_radius must be a finite"),
        ("beacon-explorer", {"sensor_range": 10**400}, "sensor_range must be a finite number"),
        ("beacon-explorer", {"monitor_period": 1e-300}, "monitor_period=1e-300 s repeats"),
        ("stigmergy", {"model_step": 1e-300}, "model_step=1e-300 s repeats"),
        ("stigmergy", {"coverage_interval": 1e-9}, "coverage_interval=1e-09 s repeats"),
        ("sugarmap", {"dt": 1e-300}, "dt=1e-300 s repeats"),
        ("tangible-pso", {"trace_interval": 1e-300}, "trace_interval=1e-300 s repeats"),
        ("beacon-explorer", {"coverage_pixel": 1e-300}, "pixel=1e-300 m splits"),
        ("stigmergy", {"obstacle_beams": 10**18}, r"obstacle_beams must be in \[0, 360\]"),
        ("tangible-pso", {"speed": 5e-324}, r"speed must be in \[0.01, inf\]"),
        ("tangible-pso", {"mav_radius": 4}, r"grown by mav_radius 4 m"),
        ("tangible-pso", {"n_mavs": 8}, r"no feasible start for n_mavs=8 MAVs"),
        (
            "beacon-explorer",
            {"link_outage_rate": 1e12, "time_limit": 30},
            r"link_outage_rate=1000000000000.0 per s asks for 3e\+13 events",
        ),
        ("beacon-explorer", {"loss_burst_rate": 1e300}, r"loss_burst_rate=1e\+300 per s asks"),
        ("tangible-pso", {"fault_rate": 1e12}, r"^fault_rate=1000000000000.0: MAV failures"),
        ("tangible-pso", {"fault_times": (1,)}, r"^fault_times=\(1.0,\): MAV failures"),
        ("beacon-explorer", {"collision_rows": -1}, r"collision_rows must be in \[0, inf\]"),
    ],
)
def test_fuzz_findings_raise_config_error(model, kwargs, match):
    with pytest.raises(ConfigError, match=match):
        model_class(model)(seed=1, **kwargs).run(until=SHORT)


ROOM = np.pad(np.ones((18, 18), dtype=bool), 1)  # a 20 m room with walls


@pytest.mark.parametrize(
    ("model", "kwargs"),
    [
        ("beacon-explorer", {"sensor_range": 1e300}),
        ("stigmergy", {"pheromone_radius": 1e300, "map": ROOM, "start": (5.0, 5.0)}),
    ],
)
def test_a_disc_larger_than_the_world_is_the_world(model, kwargs):
    """A huge sensing or deposit radius is a disc clipped to the grid, not an array too big
    for memory (these raised ValueError: Maximum allowed dimension exceeded)."""
    instance = model_class(model)(seed=1, **kwargs).run(until=SHORT)
    assert instance.time == pytest.approx(SHORT)


def test_a_sensor_that_sees_the_whole_world_covers_it_at_once():
    instance = model_class("stigmergy")(seed=1, detection_range=1e18, map=ROOM, start=(5.0, 5.0))
    instance.run(until=SHORT)
    assert instance.end_reason == "coverage" and instance.summary()["ca"] == 100.0


def test_infinity_is_accepted_where_the_paper_means_it():
    model = model_class("tangible-pso")(seed=1, u_max=math.inf)
    assert model.params.u_max == math.inf
