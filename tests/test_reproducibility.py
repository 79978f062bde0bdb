"""The same seed decides the same on a plainer CPU: the reproducibility guarantee across machines.

One machine imitates a plainer one: ``NPY_DISABLE_CPU_FEATURES`` limits numpy's dispatch to
its baseline (X86_V2 on x86-64: no AVX2, no AVX-512), ``NUMBA_CPU_NAME=generic`` compiles the
kernels for a generic CPU (into a fresh cache, so no code built for this CPU is reused),
``GLIBC_TUNABLES=glibc.cpu.hwcaps=-AVX2,-FMA`` makes the C library take its code for CPUs
without FMA, and ``OPENBLAS_CORETYPE=Prescott`` gives BLAS its oldest x86-64 kernels. Runs there
are compared with runs here under the guarantee of ``docs/reproducibility.md``: the same
decision digests, floats within ``RTOL``. Before the decision paths used ``abm.portable``, an
AVX-512 machine and an AVX2 one disagreed on ``st-hall100-fast-4`` (issue 26), and so did these
tests on an AVX-512 machine; without FMA in the C library two beacon/explorer cases decided
differently (``be-open-crowd-11``: 17,941 events instead of 10,970).
"""

import importlib.util
import json
import math
import os
import platform
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from numpy._core import _multiarray_umath as umath

from abm import portable
from abm.comms import Shadowing
from abm.kinematics import heading_vectors
from abm.pheromone import PheromoneField
from abm.sensors import relative_positions
from models.stigmergy.wander import radio_margin
from models.sugarmap.particles import _gauss_weights

ROOT = Path(__file__).resolve().parent.parent
_spec = importlib.util.spec_from_file_location(
    "event_digests", ROOT / "scripts" / "event_digests.py"
)
event_digests = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(event_digests)

#: The dispatched numpy features this CPU has: disabling them all leaves numpy's baseline.
DISPATCHED = [f for f in umath.__cpu_dispatch__ if umath.__cpu_features__.get(f)]


def plain_env(numba_cache: Path | None) -> dict[str, str]:
    """The environment of a plainer CPU: numpy's baseline, the C library's and BLAS's code for
    CPUs without FMA and AVX2 (on x86-64), and (given a fresh cache folder) numba compiling for
    a generic CPU.
    """
    env = {**os.environ, "NPY_DISABLE_CPU_FEATURES": " ".join(DISPATCHED)}
    if platform.machine().lower() in ("x86_64", "amd64"):
        env |= {"GLIBC_TUNABLES": "glibc.cpu.hwcaps=-AVX2,-FMA", "OPENBLAS_CORETYPE": "Prescott"}
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT), env.get("PYTHONPATH")]))
    if numba_cache is not None:
        env |= {"NUMBA_CPU_NAME": "generic", "NUMBA_CACHE_DIR": str(numba_cache)}
    return env


# ---------------------------------------------------------------- the decision functions
def decision_values() -> dict[str, np.ndarray]:
    """Values the models decide on, from every computation that used numpy's dispatched
    ufuncs or the C library's transcendental functions: the pheromone field's decay and f1
    weights, link margins and probabilities, the particle filter's Gaussian weights, measured
    relative positions, compass heading vectors, and the portable functions themselves.
    """
    rng = np.random.default_rng(26)
    field = PheromoneField((60, 80), decay=0.0123)
    points = rng.uniform(5.0, 55.0, size=(40, 2))
    for k in range(12):
        field.deposit(points[3 * k : 3 * k + 3], 6.0, 1.0, time=0.5 * k)
    beacons = rng.uniform(0.0, 60.0, size=(7, 2))
    distance = rng.uniform(0.1, 40.0, 500)
    angles = rng.uniform(-10.0, 10.0, 500)
    return {
        "pheromone": field.values.copy(),
        "f1": field.lower_direction(points, 20.0),
        "radio": radio_margin(points, beacons, np.zeros((40, 7)), 10.0, 2.7, 3.0),
        "shadowing": Shadowing(exponent=3.0, sd=4.0).probability(distance, 10.0),
        "gauss": _gauss_weights(distance, 7.0),
        "relative": relative_positions(points - points[::-1], rng, 0.05, 0.1, 5.0),
        "headings": heading_vectors(rng.uniform(-720.0, 720.0, 500)),
        "trig": np.stack(
            [portable.sin(angles), portable.cos(angles), portable.tan(angles)]
            + [portable.arctan2(angles, distance), portable.exp(-distance / 7.0)]
            + [portable.power(distance, -3.0), portable.log10(distance)]
        ),
    }


_VALUES_SCRIPT = """
import sys
import numpy as np
sys.path.insert(0, sys.argv[1])
from test_reproducibility import decision_values
np.savez(sys.argv[2], **decision_values())
"""


def test_decision_values_are_the_same_bits_on_a_plain_cpu(tmp_path):
    out = tmp_path / "plain.npz"
    subprocess.run(
        [sys.executable, "-c", _VALUES_SCRIPT, str(ROOT / "tests"), str(out)],
        env=plain_env(None),
        check=True,
        timeout=120,
    )
    here = decision_values()
    with np.load(out) as plain:
        assert sorted(plain.files) == sorted(here)
        for key, values in here.items():
            assert np.array_equal(plain[key], values, equal_nan=True), key


def _ulps(got: np.ndarray, want: list[float]) -> np.ndarray:
    """Distance of each value from the C library's, in units of the last place."""
    want = np.array(want)
    return np.abs(got - want) / np.spacing(np.maximum(np.abs(want), 1e-300))


@given(st.lists(st.floats(-1e4, 1e4), min_size=1, max_size=20))
def test_sine_and_cosine_within_one_ulp_of_the_c_library(values):
    x = np.array(values)
    assert _ulps(portable.sin(x), [math.sin(v) for v in x]).max() <= 1.0
    assert _ulps(portable.cos(x), [math.cos(v) for v in x]).max() <= 1.0
    assert _ulps(portable.tan(x), [math.tan(v) for v in x]).max() <= 3.0


@given(st.lists(st.floats(-745.0, 709.0), min_size=1, max_size=20))
def test_exp_within_one_ulp_of_the_c_library(values):
    x = np.array(values)
    assert _ulps(portable.exp(x), [math.exp(v) for v in x]).max() <= 1.0


finite = st.floats(allow_nan=False, allow_infinity=False)


@given(st.lists(st.tuples(finite, finite), min_size=1, max_size=20))
def test_arctan2_within_one_ulp_of_the_c_library(pairs):
    y, x = np.array(pairs).T
    got = portable.arctan2(y, x)
    assert _ulps(got, [math.atan2(a, b) for a, b in pairs]).max() <= 1.0
    assert (np.signbit(got) == np.signbit([math.atan2(a, b) for a, b in pairs])).all()


@given(st.lists(st.floats(1e-300, 1e300), min_size=1, max_size=20), st.floats(-3.0, 3.0))
def test_logarithm_and_power_near_the_c_library(values, y):
    x = np.array(values)
    assert _ulps(portable.log10(x), [math.log10(v) for v in x]).max() <= 2.0
    x = x[np.abs(y * np.log(x)) < 700]  # results within the double range
    bound = 4.0 + 4.0 * np.abs(y * np.log(x))  # exp(y log x): log's error times |y ln x|
    assert (_ulps(portable.power(x, y), [math.pow(v, y) for v in x]) <= bound).all()


@pytest.mark.parametrize(
    ("x", "y", "want"),
    [(1e100, 3.0, 1e300), (1e60, 5.0, 1e300), (1e-100, -3.0, 1e300), (1e-60, 5.0, 1e-300)],
)
def test_power_by_squaring_flags_nothing_when_the_result_is_in_range(x, y, want):
    """Squaring stops at y's last bit: one square more (x**4 for y = 3) would overflow or
    underflow and set the flag numpy reports as a warning, for a result that is fine."""
    with np.errstate(over="raise", under="raise"):
        got = portable.power(np.array([x]), y)[0]
    assert got == pytest.approx(want, rel=1e-14)


def test_special_values_follow_the_c_conventions():
    specials = [0.0, -0.0, 1.0, -1.0, math.inf, -math.inf]
    for a in specials:
        for b in specials:
            got, want = portable.arctan2(a, b), math.atan2(a, b)
            assert np.float64(got).tobytes() == np.float64(want).tobytes(), (a, b)
    assert np.isnan(portable.sin(2 * portable.PORTABLE_RANGE))  # NaN, not a machine's guess
    assert portable.exp(-math.inf) == 0.0 and portable.exp(math.inf) == math.inf
    assert portable.log10(0.0) == -math.inf and np.isnan(portable.log10(-1.0))
    assert portable.power(-2.0, 3.0) == -8.0 and np.isnan(portable.power(-2.0, 0.5))


# ---------------------------------------------------------------- whole runs
_RUNS_SCRIPT = """
import importlib.util, json, sys
import numpy as np
spec = importlib.util.spec_from_file_location("event_digests", sys.argv[1])
event_digests = importlib.util.module_from_spec(spec)
spec.loader.exec_module(event_digests)
out = {}
for case in sys.argv[3:]:
    name, kwargs = event_digests.CASES[case]
    digests, floats = event_digests.fingerprint(case)
    out[case + "/digests"] = np.array(json.dumps(digests))
    out |= {f"{case}/{key}": values for key, values in floats.items()}
np.savez(sys.argv[2], **out)
"""


def _plain_runs(cases: list[str], tmp_path: Path, numba_cache: Path | None) -> dict:
    out = tmp_path / "plain-runs.npz"
    script = str(ROOT / "scripts" / "event_digests.py")
    subprocess.run(
        [sys.executable, "-c", _RUNS_SCRIPT, script, str(out), *cases],
        env=plain_env(numba_cache),
        check=True,
        timeout=1800,
    )
    with np.load(out) as data:
        return {key: data[key] for key in data.files}


def _check_against_here(cases: list[str], plain: dict) -> list[str]:
    problems = []
    for case in cases:
        digests, floats = event_digests.fingerprint(case)
        prefix = f"{case}/"
        theirs = {k[len(prefix) :]: v for k, v in plain.items() if k.startswith(prefix)}
        if str(theirs.pop("digests")) != json.dumps(digests):
            problems.append(f"{case}: decisions differ")
        problems += [f"{case}: {p}" for p in event_digests.compare(theirs, floats)]
    return problems


def test_stigmergy_case_decides_the_same_on_a_plain_cpu(tmp_path):
    """The case issue 26 saw differ (an AVX2 machine against an AVX-512 one), with numba's
    cache as it is (compiling for a generic CPU takes minutes): the quick tier's run check.
    """
    cases = ["st-hall100-fast-4"]
    assert _check_against_here(cases, _plain_runs(cases, tmp_path, None)) == []


@pytest.mark.slow
def test_quick_cases_decide_the_same_on_a_plain_cpu(tmp_path):
    """Every quick case on the plain CPU, numba compiled for a generic CPU too."""
    cases = list(event_digests.QUICK)
    plain = _plain_runs(cases, tmp_path, tmp_path / "numba-cache")
    assert _check_against_here(cases, plain) == []
