"""`abm run MODEL --help` and a bad parameter answer at once: they load nothing only a run needs.

A wall-clock limit would be flaky on a shared machine, so the test asserts what makes those
paths fast instead, in a fresh interpreter that has asked every registered model for its help
and refused a bad parameter of each: no plotting library and no run-folder writer is imported,
no numba kernel of the project is compiled or loaded from numba's cache, and none of
``abm.portable``'s ufuncs is built. Any of these at import time costs a tenth of a second or
more per command (``benchmarks/bench_cli.py`` times the commands themselves).
"""

import json
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: Runs in a fresh interpreter; prints what the help and bad-parameter paths left loaded.
PROBE = r"""
import contextlib, io, json, sys
from abm.registry import model_names
from analysis.cli import main

codes = {}
for name in model_names():
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        try:
            main(["run", name, "--help"])
        except SystemExit as exc:
            codes[name + " --help"] = exc.code
        codes[name + " bad"] = main(["run", name, "--trace-interval", "-1"])

from numba.core.dispatcher import Dispatcher
from abm import portable

kernels = sorted(
    f"{module}.{attr}"
    for module, mod in list(sys.modules.items())
    if module.split(".")[0] in ("abm", "models", "analysis")
    for attr, value in list(vars(mod).items())
    if isinstance(value, Dispatcher) and value.signatures
)
print(json.dumps({
    "codes": codes,
    "modules": sorted(m for m in ("matplotlib", "analysis.run_folder", "abm.draw")
                      if m in sys.modules),
    "kernels": kernels,
    "ufuncs": [n for n in ("exp", "log10", "power", "arctan2", "sin", "cos", "tan")
               if n in vars(portable)],
}))
"""


def test_help_and_bad_parameter_load_nothing_a_run_needs():
    """Every model's ``--help`` exits 0 and its bad parameter exits 2 (one line), having
    imported no plotting or run-folder code and compiled or loaded no numba kernel.
    """
    out = subprocess.run(
        [sys.executable, "-c", PROBE], cwd=ROOT, capture_output=True, text=True, check=True
    ).stdout
    seen = json.loads(out.strip().splitlines()[-1])
    assert seen["codes"], "no model registered"
    for command, code in seen["codes"].items():
        assert code == (0 if command.endswith("--help") else 2), command
    assert seen["modules"] == []
    assert seen["kernels"] == []
    assert seen["ufuncs"] == []


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
