"""The flocking benchmark's own logic: ratios, the Mesa worker, the side venv's failure message.

Installing Mesa 3.2.0 is not tested here (it needs the network); its failure path is, with a
pip that fails as an offline one does.
"""

import io
import json
import subprocess
import sys

import mesa
import numpy as np
import pytest

from tests.scripts import load_benchmark

bench = load_benchmark("bench_flocking")
flocking_mesa = load_benchmark("flocking_mesa")
TINY = {"birds": 12, "extent": 20.0, "visual_distance": 5.0}


def test_ratios_are_each_mesa_over_each_of_our_modes_medians():
    rows = {
        "3.5.1": [
            (10.0, 8.0, 9.0, 7.0, 0.2),
            (30.0, 12.0, 27.0, 11.0, 0.4),
            (20.0, 10.0, 18.0, 9.0, 0.3),
        ],
        "3.2.0": [(40.0, 20.0, 36.0, 18.0, 0.5)],
        "DC off": [(0.1, 0.05, 0.08, 0.04, 0.1), (0.3, 0.02, 0.1, 0.01, 0.3)],
        "defaults": [(0.5, 0.25, 0.45, 0.2, 0.2)],
    }
    out = bench.summarise(rows, ["3.5.1", "3.2.0"])
    assert np.allclose(out["median"]["3.5.1"], [20.0, 10.0, 18.0, 9.0, 0.3])
    assert np.allclose(out["median"]["DC off"], [0.2, 0.035, 0.09, 0.025, 0.2])
    assert set(out["ratio"]) == {(m, o) for m in ("3.5.1", "3.2.0") for o in ("DC off", "defaults")}
    assert np.allclose(out["ratio"][("3.5.1", "DC off")], [100.0, 10.0 / 0.035, 200.0, 360.0])
    assert np.allclose(out["ratio"][("3.2.0", "defaults")], [80.0, 80.0, 80.0, 90.0])
    # quartiles of the CPU column (the second), linear between the sorted values
    assert np.allclose(out["cpu_quartiles"]["3.5.1"], [9.0, 11.0])
    assert np.allclose(out["cpu_quartiles"]["DC off"], [0.0275, 0.0425])
    assert np.allclose(out["cpu_quartiles"]["defaults"], [0.25, 0.25])


def test_the_mesa_worker_names_its_versions_and_times_a_run():
    requests = io.StringIO(json.dumps({"seed": 3, "steps": 4, **TINY}) + "\n\n")
    replies = []
    flocking_mesa.serve(requests, replies.append)
    assert json.loads(replies[0])["mesa"] == mesa.__version__
    run = json.loads(replies[1])
    assert len(replies) == 2 and set(run) == set(bench.FIELDS)
    assert run["wall"] >= run["wall_steps"] > 0 and run["cpu"] >= run["cpu_steps"] >= 0
    assert 0.0 <= run["polarisation"] <= 1.0


def test_a_worker_process_of_this_python_answers_as_the_function_does():
    worker = bench.MesaWorker(sys.executable)
    try:
        assert worker.versions["mesa"] == mesa.__version__
        row = worker.run(5, TINY, steps=3)
    finally:
        worker.close()
    direct = flocking_mesa.mesa_run(5, steps=3, **TINY)
    assert len(row) == len(bench.FIELDS) and row[-1] == direct["polarisation"]


def test_our_modes_are_timed_and_trace_only_with_the_defaults():
    off = bench.our_run(2, TINY, bench.MODES["DC off"], steps=3)
    defaults = bench.our_run(2, TINY, bench.MODES["defaults"], steps=3)
    assert off[-1] == defaults[-1]  # the same run, recorded differently
    assert bench.MODES["DC off"] == {"trace_interval": None} and bench.MODES["defaults"] == {}


def test_a_mesa_that_pip_cannot_install_is_named_with_pip_s_words(tmp_path):
    def offline_pip(command, **_kwargs):
        if "pip" in command:
            return subprocess.CompletedProcess(
                command, 1, "", "ERROR: Could not find a version that satisfies mesa==3.2.0"
            )
        (tmp_path / "mesa-3.2.0" / "bin").mkdir(parents=True, exist_ok=True)
        return subprocess.CompletedProcess(command, 0, "", "")

    with pytest.raises(bench.MesaUnavailableError) as caught:
        bench.mesa_python("3.2.0", tmp_path, run=offline_pip)
    said = str(caught.value)
    assert "Mesa 3.2.0 could not be installed" in said and "PyPI" in said
    assert "Could not find a version" in said and "goes on without Mesa 3.2.0" in said
    assert not (tmp_path / "mesa-3.2.0" / "installed.txt").exists()


def test_an_installed_side_mesa_is_reused_without_pip(tmp_path):
    home = tmp_path / "mesa-3.2.0"
    home.mkdir()
    (home / "installed.txt").write_text("mesa==3.2.0\n")

    def no_pip(command, **_kwargs):
        raise AssertionError(f"ran {command}")

    assert bench.mesa_python("3.2.0", tmp_path, run=no_pip).parent.parent == home
