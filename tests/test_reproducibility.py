"""The same seed decides the same on a plainer CPU: the reproducibility guarantee across machines.

One machine imitates a plainer one: ``NPY_DISABLE_CPU_FEATURES`` limits numpy's dispatch to
its baseline (X86_V2 on x86-64: no AVX2, no AVX-512) and ``NUMBA_CPU_NAME=generic`` compiles
the kernels for a generic CPU (into a fresh cache, so no code built for this CPU is reused).
Runs there are compared with runs here under the guarantee of ``docs/reproducibility.md``:
the same decision digests, floats within ``RTOL``. Before the decision paths left numpy's
dispatched ufuncs (``abm.portable``), an AVX-512 machine and an AVX2 one disagreed on
``st-hall100-fast-4`` (issue 26), and so did these tests on an AVX-512 machine.
"""

import importlib.util
import json
import math
import os
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
from abm.pheromone import PheromoneField
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
    """The environment of a plainer CPU: numpy's baseline, and (given a fresh cache folder)
    numba compiling for a generic CPU.
    """
    env = {**os.environ, "NPY_DISABLE_CPU_FEATURES": " ".join(DISPATCHED)}
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT), env.get("PYTHONPATH")]))
    if numba_cache is not None:
        env |= {"NUMBA_CPU_NAME": "generic", "NUMBA_CACHE_DIR": str(numba_cache)}
    return env


# ---------------------------------------------------------------- the decision functions
def decision_values() -> dict[str, np.ndarray]:
    """Values the models decide on, from every computation that used numpy's dispatched
    ufuncs: the pheromone field's decay and f1 weights, link margins and probabilities, the
    particle filter's Gaussian weights.
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


def test_decision_values_are_the_same_bits_with_numpy_at_its_baseline(tmp_path):
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


finite = st.floats(-700.0, 700.0, allow_nan=False)


@given(st.lists(finite, min_size=1, max_size=20))
def test_portable_functions_return_the_c_library_values(values):
    x = np.array(values)
    positive = np.abs(x) + 1e-3
    pairs = [
        (portable.exp(x), [math.exp(v) for v in x]),
        (portable.sin(x), [math.sin(v) for v in x]),
        (portable.cos(x), [math.cos(v) for v in x]),
        (portable.tan(x), [math.tan(v) for v in x]),
        (portable.arctan2(x, x[::-1]), [math.atan2(a, b) for a, b in zip(x, x[::-1], strict=True)]),
        (portable.log10(positive), [math.log10(v) for v in positive]),
        (portable.power(positive, -1.5), [math.pow(v, -1.5) for v in positive]),
    ]
    for got, want in pairs:
        assert got.tobytes() == np.array(want).tobytes()


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


def test_stigmergy_case_decides_the_same_with_numpy_at_its_baseline(tmp_path):
    """The case issue 26 saw differ (an AVX2 machine against an AVX-512 one), numba's cache
    as it is: the quick tier's run-level check.
    """
    cases = ["st-hall100-fast-4"]
    assert _check_against_here(cases, _plain_runs(cases, tmp_path, None)) == []


@pytest.mark.slow
def test_quick_cases_decide_the_same_on_a_plain_cpu(tmp_path):
    """Every quick case with numpy at its baseline and numba compiled for a generic CPU."""
    cases = list(event_digests.QUICK)
    plain = _plain_runs(cases, tmp_path, tmp_path / "numba-cache")
    assert _check_against_here(cases, plain) == []
