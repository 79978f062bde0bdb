"""`abm --help`, `abm run MODEL --help` and a bad parameter answer at once: they load no
simulation code, not even the model's own module.

A wall-clock limit would be flaky on a shared machine, so the tests assert what makes those
paths fast instead, in a fresh interpreter that has asked for the help and refused bad
parameters of every model of the project: none of the libraries a run needs (Mesa, pandas,
networkx, numba, SimPy, matplotlib, scipy.spatial) is imported, no part of ``abm`` that only a
run needs, and no model's package (``abm.declared`` reads the model's ``Params`` from its
source and its params module). Each of these costs a tenth of a second or more per command
(``benchmarks/bench_cli.py`` times the commands themselves).
"""

import json
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: Modules (and their submodules) only a run needs: none may be imported to answer help or
#: refuse a parameter.
RUN_ONLY = (
    "mesa",
    "pandas",
    "networkx",
    "numba",
    "simpy",
    "matplotlib",
    "scipy.spatial",
    "abm.model",
    "abm.robot",
    "abm.gridkernels",
    "abm.portable",
    "abm.draw",
    "abm.png_process",
    "analysis.run_folder",
)

#: Each bad input of ``abm run MODEL ...`` the probe gives every model: every one is refused
#: in one line with exit code 2 before anything a run needs is imported.
BAD = {
    "a value out of range": ["--trace-interval", "-1"],
    "a value that is no number": ["--time-limit", "soon"],
    "an unknown flag": ["--no-such-parameter", "1"],
    "a rule between fields": ["--dt", "1e-12"],
    "a fault keyword refused (range or kind)": ["--link-outage-rate", "-1"],
    "a bad seed": ["--seed", "-1"],
}

#: Runs in a fresh interpreter; prints exit codes, error lines and what was left loaded.
PROBE = r"""
import contextlib, io, json, sys
from importlib.metadata import entry_points

from abm.registry import ENTRY_POINT_GROUP
from analysis.cli import main

bad = json.loads(sys.argv[1])
run_only = json.loads(sys.argv[2])
names = sorted(ep.name for ep in entry_points(group=ENTRY_POINT_GROUP)
               if ep.value.startswith("models."))
seen = {}

def ask(label, argv):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main(argv)
        except SystemExit as exc:
            code = exc.code
    seen[label] = {"code": code, "out": out.getvalue(), "err": err.getvalue().splitlines()}

ask("abm --help", ["--help"])
ask("abm run no-such-model", ["run", "no-such-model"])
for name in names:
    ask(f"{name} --help", ["run", name, "--help"])
    for what, argv in bad.items():
        ask(f"{name}: {what}", ["run", name, *argv])
loaded = sorted(m for m in sys.modules if m in run_only
                or any(m.startswith(r + ".") for r in run_only))
packages = sorted({m.split(".")[1] for m in sys.modules if m.startswith("models.")})
print(json.dumps({"names": names, "seen": seen, "loaded": loaded, "packages": packages}))
"""


def _probe() -> dict:
    out = subprocess.run(
        [sys.executable, "-c", PROBE, json.dumps(BAD), json.dumps(RUN_ONLY)],
        cwd=ROOT,
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    return json.loads(out.strip().splitlines()[-1])


def test_help_and_bad_parameters_load_no_simulation_code_and_no_model():
    """Every model's ``--help`` exits 0 naming the model's flags, and each bad input of
    :data:`BAD` exits 2 with one line naming what was wrong, having imported nothing of
    :data:`RUN_ONLY` and no model's package (``models.environments``, which beacon/explorer's
    params name, aside).
    """
    seen = _probe()
    assert seen["names"], "no model registered"
    results = seen["seen"]
    assert results["abm --help"]["code"] == 0 and "run" in results["abm --help"]["out"]
    unknown = results["abm run no-such-model"]
    assert unknown["code"] == 2 and "unknown model 'no-such-model'" in unknown["err"][0]
    for name in seen["names"]:
        helped = results[f"{name} --help"]
        assert helped["code"] == 0 and helped["out"].startswith(f"usage: abm run {name} ")
        assert "--time-limit" in helped["out"] and "--trace-interval" in helped["out"]
        for what, argv in BAD.items():
            refused = results[f"{name}: {what}"]
            assert refused["code"] == 2, (name, what, refused)
            assert len(refused["err"]) == 1, (name, what, refused["err"])
            assert refused["err"][0].startswith(("abm run: error: ", "abm: error: "))
            line, field = refused["err"][0], argv[0][2:].replace("-", "_")
            assert argv[0] in line or field in line, (name, line)
    assert seen["loaded"] == []
    assert set(seen["packages"]) <= {"environments"}, seen["packages"]


def test_a_model_loads_no_other_model():
    """``abm run MODEL`` up to its parameter check imports that model's package only, not
    every model registered before it in sorted order (the run's name is looked up without
    importing the others).
    """
    probe = r"""
import contextlib, io, json, sys
from importlib.metadata import entry_points

from abm.registry import ENTRY_POINT_GROUP, model_class
from analysis.cli import main

# the last of the project's own models, read without importing any (a test run may have
# installed a plugin model of its own beside them)
last = sorted(ep.name for ep in entry_points(group=ENTRY_POINT_GROUP)
              if ep.value.startswith("models."))[-1]
with contextlib.redirect_stderr(io.StringIO()):
    code = main(["run", last, "--trace-interval", "-1"])
target = model_class(last).__module__.split(".")[:2]
loaded = sorted({m.split(".")[1] for m in sys.modules if m.startswith("models.")})
print(json.dumps({"code": code, "target": target[1], "loaded": loaded}))
"""
    out = subprocess.run(
        [sys.executable, "-c", probe], cwd=ROOT, capture_output=True, text=True, check=True
    ).stdout
    seen = json.loads(out.strip().splitlines()[-1])
    assert seen["code"] == 2
    assert seen["target"] in seen["loaded"]
    assert set(seen["loaded"]) - {seen["target"]} <= {"environments"}, seen["loaded"]
