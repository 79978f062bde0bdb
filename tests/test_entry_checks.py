"""User code is checked where it enters the framework: a model's controller, hooks, docstring
and declared attributes. Each mistake gives one line naming the model, the hook and what was
expected, through the Python API and through ``abm run`` (no traceback), before it can run on
silently or fail deep inside SimPy.

The models here are plugin-like: classes of this test module, named to the CLI as
``"module:Class"`` as an out-of-tree model would be.
"""

import dataclasses

import numpy as np
import pytest
import simpy
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp
from numba import njit
from tiny_model import TinyModel, TinyParams, Walker

from abm import registry
from abm.arena import Arena
from abm.checks import check_control
from abm.contract import check_model
from abm.errors import ContractError, HookError
from abm.params import param
from abm.physics import Physics
from analysis.cli import main

SHORT = ["--time-limit", "30", "--walkers", "2", "--launch-period", "1", "--no-progress"]


# ---------------------------------------------------------------- plugin-like models
class ColumnModel(TinyModel):
    """Walkers whose controller returns velocities of shape (n, 1) (numpy would broadcast)."""

    def control(self, physics):
        desired, done = super().control(physics)
        return desired[:, :1], done


class NaNModel(TinyModel):
    """Walkers whose controller returns NaN velocities once robot 2 flies."""

    def control(self, physics):
        desired, done = super().control(physics)
        desired[physics.ids == 2] = np.nan
        return desired, done


class NoControllerModel(TinyModel):
    """Walkers that forgot to set a flight controller."""

    def __init__(self, *, seed=None, **params):
        super().__init__(seed=seed, **params)
        self.physics.controller = None


class NoDocModel(TinyModel):
    pass


class ListMetricsModel(TinyModel):
    """Walkers whose metrics() puts a list in the summary."""

    def metrics(self):
        return {**super().metrics(), "positions": [1.0, 2.0]}


class ShadowingMetricsModel(TinyModel):
    """Walkers whose metrics() replaces the common summary key "time" with its own value."""

    def metrics(self):
        return {**super().metrics(), "time": 1.0}


class UncalledBehaviourModel(TinyModel):
    """Walkers started with their behaviour function instead of its generator."""

    def _launcher(self):
        yield self.env.timeout(self.params.launch_period)
        walker = Walker(self, self.centre, "walking", "walk")
        walker.start(walker.walk)


class BadLayersModel(TinyModel):
    """Walkers whose layers() returns a bare array instead of Layer objects."""

    def layers(self):
        return [np.zeros((3, 2))]


class BadArrowsModel(TinyModel):
    """Walkers whose arrows() returns one (k, 3) array."""

    ARROWS_LABEL = "heading"

    def arrows(self):
        return np.zeros((4, 3))


def _abm_run(capsys, cls: type, tmp_path) -> str:
    """``abm run module:Class`` with a short set-up: the one line it printed on stderr."""
    code = main(["run", f"{__name__}:{cls.__qualname__}", "--out", str(tmp_path / "run"), *SHORT])
    err = capsys.readouterr().err
    assert code == 2
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1, err
    return err.strip()


# ---------------------------------------------------------------- 1. controller outputs
def test_velocities_of_the_wrong_shape_are_refused_not_broadcast(capsys, tmp_path):
    expected = (
        r"ColumnModel\.control\(physics\) returned desired velocities as an array of shape "
        r"\(1, 1\).*expected a float array of shape \(1, 2\)"
    )
    with pytest.raises(HookError, match=expected) as caught:
        ColumnModel(seed=1, **_short()).run()
    assert "\n" not in str(caught.value)
    line = _abm_run(capsys, ColumnModel, tmp_path)
    assert line.startswith("abm run: error: ColumnModel.control(physics) returned desired")
    assert not (tmp_path / "run").exists()  # the folder made for the run is gone with it


def test_non_finite_velocities_are_refused_naming_the_robot(capsys, tmp_path):
    expected = (
        r"NaNModel\.control\(physics\) returned non-finite desired velocities for 1 of \d "
        r"flyers \(first: robot 2, \[nan, nan\]\)"
    )
    with pytest.raises(HookError, match=expected):
        NaNModel(seed=1, **_short()).run()
    assert "NaNModel.control(physics) returned non-finite" in _abm_run(capsys, NaNModel, tmp_path)


class _Returns:
    """A controller that returns ``value`` every tick."""

    def __init__(self, value: object) -> None:
        self.value = value

    def control(self, physics):
        return self.value


def _physics(n: int, controller: object) -> Physics:
    free = np.zeros((12, 12), dtype=bool)
    free[1:-1, 1:-1] = True
    physics = Physics(simpy.Environment(), Arena(free, 1.0), np.random.default_rng(0), controller)
    physics.fly_many(range(n), np.column_stack([np.linspace(2, 9, n), np.full(n, 5.0)]))
    return physics


@st.composite
def _bad_outputs(draw, n: int) -> object:
    """A controller's return value for n flyers that breaks exactly one documented rule."""
    good_desired = np.zeros((n, 2))
    good_done = np.zeros(n, dtype=bool)
    kind = draw(st.sampled_from(["shape", "dtype", "finite", "done", "not a pair"]))
    if kind == "shape":
        shape = draw(
            hnp.array_shapes(min_dims=0, max_dims=3, max_side=4).filter(lambda s: s != (n, 2))
        )
        return draw(hnp.arrays(np.float64, shape, elements=st.floats(-1, 1))), good_done
    if kind == "dtype":
        dtype = draw(st.sampled_from([np.int64, np.int32, np.bool_, np.complex128, object]))
        return np.zeros((n, 2), dtype=dtype), good_done
    if kind == "finite":
        dtype = draw(st.sampled_from([np.float64, np.float32, np.float16]))
        desired = draw(hnp.arrays(dtype, (n, 2), elements=st.floats(-1, 1, width=16)))
        row, col = draw(st.integers(0, n - 1)), draw(st.integers(0, 1))
        desired[row, col] = draw(st.sampled_from([np.nan, np.inf, -np.inf]))
        return desired, good_done
    if kind == "done":
        done = draw(
            st.sampled_from(
                [
                    np.zeros(n, dtype=np.int64),  # indexes rows 0 instead of masking
                    np.zeros((n, 1), dtype=bool),
                    np.zeros(n + 1, dtype=bool),
                    [False] * n,
                    None,
                ]
            )
        )
        return good_desired, done
    return draw(
        st.sampled_from(
            [None, good_desired, [good_desired, good_done], (good_desired, good_done, good_done)]
        )
    )


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.data_too_large])
@given(data=st.data(), n=st.integers(1, 5))
def test_any_bad_controller_output_is_one_line_naming_the_hook_and_nothing_moves(data, n):
    value = data.draw(_bad_outputs(n))
    physics = _physics(n, _Returns(value))
    before = physics.pos.copy()
    with pytest.raises(HookError) as caught:
        physics.tick()
    message = str(caught.value)
    assert message.startswith("_Returns.control(physics) returned ")
    assert "expected" in message and "\n" not in message
    np.testing.assert_array_equal(physics.pos, before)  # no motion from a refused output


@settings(max_examples=60, deadline=None)
@given(
    n=st.integers(0, 6),
    dtype=st.sampled_from([np.float64, np.float32, np.float16]),
    fortran=st.booleans(),
    data=st.data(),
)
def test_any_output_of_the_documented_kind_is_accepted(n, dtype, fortran, data):
    desired = data.draw(hnp.arrays(dtype, (n, 2), elements=st.floats(-2, 2, width=16)))
    if fortran:  # a column-major view (e.g. a transposed (2, n) array) is fine too
        desired = np.asfortranarray(desired)
    done = data.draw(hnp.arrays(np.bool_, (n,)))
    checked = check_control((desired, done), np.arange(n), "M", object())
    assert checked[0] is desired and checked[1] is done  # passed on as they are


@settings(max_examples=40, deadline=None)
@given(n=st.integers(1, 6), row=st.integers(0, 5), bad=st.sampled_from([np.nan, np.inf, -np.inf]))
def test_velocities_made_by_a_compiled_kernel_are_checked_like_numpys(n, row, bad):
    """A controller's kernel returns float64 arrays whose dtype object is numba's, not numpy's
    singleton: they are accepted when finite and refused with a non-finite entry."""
    desired, done = _kernel_output(n, row % n, 0.5)
    assert check_control((desired, done), np.arange(n), "M", object())[0] is desired
    desired, done = _kernel_output(n, row % n, bad)
    with pytest.raises(HookError, match=f"non-finite desired velocities for 1 of {n} flyers"):
        check_control((desired, done), np.arange(n), "M", object())


@njit(cache=True)
def _kernel_output(n: int, row: int, value: float) -> tuple[np.ndarray, np.ndarray]:
    """Zero velocities but ``value`` in one entry of ``row``, and no flyer done."""
    desired = np.zeros((n, 2))
    desired[row, 1] = value
    return desired, np.zeros(n, dtype=np.bool_)


# ---------------------------------------------------------------- 2. docstring, attributes
def test_a_model_without_a_docstring_is_one_line_not_an_index_error(capsys, tmp_path):
    with pytest.raises(ContractError, match="NoDocModel has no docstring: .*first line"):
        registry.register("no-doc", NoDocModel)
    assert "no-doc" not in registry.model_names()
    line = _abm_run(capsys, NoDocModel, tmp_path)
    assert line.startswith("abm run: error: NoDocModel has no docstring")


def _model_with(**attributes) -> type:
    """A TinyModel subclass with a docstring and ``attributes`` (one contract point broken)."""
    return type("Broken", (TinyModel,), {"__doc__": "A broken walker model.", **attributes})


@pytest.mark.parametrize(
    ("attributes", "expected"),
    [
        ({"STATE_STYLES": ["walking"]}, r"Broken\.STATE_STYLES must be a dict state"),
        ({"SUMMARY_UNITS": ("resting",)}, r"Broken\.SUMMARY_UNITS must be a dict summary key"),
        ({"QUICK": "walkers=2"}, r"Broken\.QUICK must be a dict parameter -> value"),
        ({"PUBLISHED": None}, r"Broken\.PUBLISHED must be a tuple or list"),
        ({"CENSORED": 3}, r"Broken\.CENSORED must be a tuple or list"),
    ],
)
def test_ill_formed_declared_attributes_are_named(attributes, expected):
    with pytest.raises(ContractError, match=expected):
        check_model(_model_with(**attributes))


def test_params_whose_defaults_are_refused_or_missing_are_named():
    @dataclasses.dataclass(frozen=True)
    class BadDefault(TinyParams):
        """Walkers at a negative speed.

        Attributes:
            speed: walking speed (m/s).

        """

        speed: float = param(-0.5, low=0.0, low_open=True)

    with pytest.raises(ContractError, match=r"the defaults of Broken\.Params are refused: speed"):
        check_model(_model_with(Params=BadDefault))

    @dataclasses.dataclass(frozen=True, kw_only=True)
    class NoDefault(TinyParams):
        """Walkers that must be told their colour.

        Attributes:
            colour: their colour.

        """

        colour: str

    with pytest.raises(ContractError, match=r"Broken\.Params gives no default to colour"):
        check_model(_model_with(Params=NoDefault))


# ---------------------------------------------------------------- 3. a missing controller
def test_a_missing_controller_is_named_before_the_run_starts(capsys, tmp_path):
    model = NoControllerModel(seed=1, **_short())
    expected = (
        "NoControllerModel has no flight controller: physics.controller is None.*set "
        "self.physics.controller"
    )
    with pytest.raises(HookError, match=expected):
        model.run()
    assert model.time == 0.0  # refused before simulated time moved
    with pytest.raises(HookError, match="NoControllerModel has no flight controller"):
        NoControllerModel(seed=1, **_short()).step()
    line = _abm_run(capsys, NoControllerModel, tmp_path)
    assert line.startswith("abm run: error: NoControllerModel has no flight controller")


def test_a_sweep_of_a_model_without_controller_stops_before_any_run(tmp_path):
    from analysis.sweep import run_sweep

    with pytest.raises(HookError, match=r"grid point \(time_limit=30.0\): NoControllerModel has"):
        run_sweep(NoControllerModel, {"time_limit": [30.0]}, 2, 0, tmp_path / "s", "serial")
    assert not list(tmp_path.rglob("*.parquet"))  # no run was recorded as a failure


def test_a_controller_without_control_is_refused_at_take_off():
    with pytest.raises(HookError, match="has no flight controller: physics.controller is a str"):
        _physics(2, "pilot")


# ---------------------------------------------------------------- other hooks
def test_metrics_that_no_summary_table_can_hold_are_named(capsys, tmp_path):
    model = ListMetricsModel(seed=1, **_short()).run()
    expected = r"ListMetricsModel\.metrics\(\) returned 'positions' as a list; expected one number"
    with pytest.raises(HookError, match=expected):
        model.summary()
    assert "ListMetricsModel.metrics() returned 'positions'" in _abm_run(
        capsys, ListMetricsModel, tmp_path
    )


def test_metrics_may_not_replace_a_common_summary_key():
    model = ShadowingMetricsModel(seed=1, **_short()).run()
    with pytest.raises(HookError, match=r"ShadowingMetricsModel\.metrics\(\) returned 'time', a"):
        model.summary()


def test_a_behaviour_that_is_not_a_generator_is_named(capsys, tmp_path):
    expected = (
        r"UncalledBehaviourModel: robot\.start\(\) got the function Walker\.walk \(not "
        r"called\); expected a generator"
    )
    with pytest.raises(HookError, match=expected):
        UncalledBehaviourModel(seed=1, **_short()).run()
    line = _abm_run(capsys, UncalledBehaviourModel, tmp_path)
    assert line.startswith("abm run: error: UncalledBehaviourModel: robot.start() got")


def test_layers_that_are_not_layers_are_named_and_leave_no_files(capsys, tmp_path):
    line = _abm_run(capsys, BadLayersModel, tmp_path)
    assert "BadLayersModel.layers()[0] is an array of shape (3, 2)" in line
    assert "expected an abm.styles.Layer" in line
    assert not list(tmp_path.iterdir())  # neither the run folder nor a half-written one


def test_arrows_of_the_wrong_shape_are_named(capsys, tmp_path):
    from abm.scene import scene_of

    model = BadArrowsModel(seed=1, **_short()).run()
    expected = (
        r"BadArrowsModel\.arrows\(\) returned an array of shape \(4, 3\).*; expected None or "
        r"\(points, vectors\)"
    )
    with pytest.raises(HookError, match=expected):
        scene_of(model)


def test_reporters_must_be_callables():
    model = _model_with(reporters=lambda self: {"walking": 3})(seed=1, **_short())
    with pytest.raises(HookError, match=r"Broken\.reporters\(\) returned 'walking': an? int"):
        model.step()


def _short() -> dict:
    return {"time_limit": 30.0, "walkers": 2, "launch_period": 1.0}
