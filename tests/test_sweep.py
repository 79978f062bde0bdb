"""Sweeps: planning, validation before any run, executors agree, failures and restarts."""

import json
import os
import re
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from abm.errors import ConfigError
from analysis.sweep import Sweep, SweepError, execute, load_results, load_sweep, plan, run_sweep
from models.beacon_explorer import BeaconExplorerModel

ROOT = Path(__file__).resolve().parents[1]
SMOKE = ROOT / "experiments" / "smoke.toml"
TINY = {"world": ["corridor"], "complexity": ["high"], "launch_period": [6.0, 24.0],
        "time_limit": [30.0]}  # fmt: skip
VOLATILE = ["wall_time", "worker"]


def _rows(df: pd.DataFrame) -> pd.DataFrame:
    return df.drop(columns=VOLATILE).sort_values("run_id").reset_index(drop=True)


def test_every_experiment_file_loads():
    sizes = {}
    for path in sorted((ROOT / "experiments").glob("*.toml")):
        sizes[path.stem] = load_sweep(path).n_runs
    assert sizes["corridor"] == 6 * 3 * 100
    assert sizes["open"] == 5 * 3 * 100
    assert sizes["mixed"] == 6 * 100
    assert sizes["hover"] == 2 * 100
    assert sizes["smoke"] == 8
    assert sizes["stigmergy_radius"] == 3 * 10


def test_plan_is_deterministic_and_stable_when_the_grid_grows():
    small = plan(Sweep("beacon-explorer", TINY, replications=3, seed=5))
    again = plan(Sweep("beacon-explorer", TINY, replications=3, seed=5))
    assert small == again
    assert len({s.seed for s in small}) == len({s.run_id for s in small}) == 6
    grown = plan(Sweep("beacon-explorer", {**TINY, "launch_period": [6.0, 12.0, 24.0]}, 4, 5))
    by_id = {s.run_id: s.seed for s in grown}
    assert all(by_id[s.run_id] == s.seed for s in small)
    other = plan(Sweep("beacon-explorer", TINY, replications=3, seed=6))
    assert {s.seed for s in other}.isdisjoint({s.seed for s in small})


@pytest.mark.parametrize(
    ("text", "match"),
    [
        ('model = "beacon-explorer"\n[grid]\nwings = [2]\n', "'wings'"),
        ('model = "beacon-explorer"\n[grid]\nlaunch_period = ["fast"]\n', "'launch_period'"),
        ('model = "beacon-explorer"\n[grid]\nhover_beacons = [1]\n', "'hover_beacons'"),
        ('model = "beacon-explorer"\n[grid]\n', "grid is empty"),
        ('model = "beacon-explorer"\n[grid]\ncomplexity = []\n', "'complexity'"),
        ('model = "beacon-explorer"\n[grid]\nseed = [1, 2]\n', "'seed'"),
        ('model = "beacon-explorer"\nreplication = 3\n[grid]\nworld = ["open"]\n', "'replication'"),
        ('model = "ants"\n[grid]\nworld = ["open"]\n', "'ants'"),
        ('model = "beacon-explorer"\nreplications = 0\n[grid]\nworld = ["open"]\n', "replications"),
        ('model = "flocking"\nseed = -1\n[grid]\nbirds = [10]\n', "seed must be an integer in"),
        (f'model = "flocking"\nseed = {2**63}\n[grid]\nbirds = [10]\n', r"\[0, 2\*\*63 - 1\]"),
    ],
)
def test_bad_sweep_files_name_the_offending_key(tmp_path, text, match):
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(ConfigError, match=match):
        load_sweep(path)


def test_bad_values_fail_before_any_run(tmp_path):
    sweep = Sweep("beacon-explorer", {"world": ["corridor", "mixed"], "complexity": ["high"]})
    with pytest.raises(ConfigError, match="world='mixed'"):
        execute(sweep, tmp_path / "out", executor="serial", progress=False)
    assert not (tmp_path / "out").exists()


def test_cli_reports_a_bad_file_in_one_line(tmp_path, capsys):
    from analysis.cli import main

    path = tmp_path / "bad.toml"
    path.write_text('model = "beacon-explorer"\n[grid]\nlaunch_periods = [6]\n')
    assert main(["sweep", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "'launch_periods'" in err


def test_dask_local_cluster_gives_the_serial_rows(tmp_path):
    serial = run_sweep(BeaconExplorerModel, TINY, 2, 11, tmp_path / "s", "serial", progress=False)
    dask = run_sweep(
        BeaconExplorerModel, TINY, 2, 11, tmp_path / "d", "dask", workers=1, progress=False
    )
    assert len(serial) == 4 and (serial["status"] == "ok").all()
    pd.testing.assert_frame_equal(_rows(serial), _rows(dask))
    columns = {"run_id", "seed", "rep", "world", "launch_period", "coverage_time", "energy_total"}
    assert columns <= set(serial.columns)


def test_processes_give_the_serial_rows(tmp_path):
    grid = {**TINY, "launch_period": [24.0]}
    serial = run_sweep("beacon-explorer", grid, 1, 3, tmp_path / "s", "serial", progress=False)
    procs = run_sweep(
        "beacon-explorer", grid, 1, 3, tmp_path / "p", "processes", workers=1, progress=False
    )
    pd.testing.assert_frame_equal(_rows(serial), _rows(procs))


class FlakyModel(BeaconExplorerModel):
    """Fails its run at the periods in ``FAIL``; counts the runs it started."""

    FAIL: set = set()
    STARTED: list = []

    def run(self, until=None):
        type(self).STARTED.append(self.launch_period)
        if self.launch_period in type(self).FAIL:
            raise RuntimeError(f"injected failure at {self.launch_period:g} s")
        return super().run(until)


def test_failed_run_is_recorded_and_restart_completes_without_redoing(tmp_path):
    out = tmp_path / "flaky"
    FlakyModel.FAIL, FlakyModel.STARTED = {24.0}, []
    first = run_sweep(FlakyModel, TINY, 2, 1, out, "serial", progress=False)
    assert sorted(first["status"]) == ["failed", "failed", "ok", "ok"]
    failed = first[first["status"] == "failed"]
    assert failed["error"].str.contains("injected failure at 24 s").all()
    assert failed["traceback"].str.contains("RuntimeError").all()
    done = {p.name: p.stat().st_mtime_ns for p in (out / "runs").glob("*.parquet")}
    assert len(done) == 2

    FlakyModel.FAIL, FlakyModel.STARTED = set(), []
    second = run_sweep(FlakyModel, TINY, 2, 1, out, "serial", progress=False)
    assert FlakyModel.STARTED == [24.0, 24.0]  # only the failed runs ran again
    assert (second["status"] == "ok").all() and second["run_id"].is_unique and len(second) == 4
    assert set(second["run_id"]) == set(first["run_id"])
    assert not list((out / "failed").glob("*.parquet"))
    assert {p.name: p.stat().st_mtime_ns for p in (out / "runs").glob("*.parquet")
            if p.name in done} == done  # fmt: skip


def test_a_sweep_of_another_seed_refuses_the_folder(tmp_path):
    run_sweep("beacon-explorer", {**TINY, "launch_period": [24.0]}, 1, 1, tmp_path, "serial",
              progress=False)  # fmt: skip
    with pytest.raises(SweepError, match="seed"):
        run_sweep("beacon-explorer", TINY, 1, 2, tmp_path, "serial", progress=False)


def _ctrl_c_as_in_a_terminal() -> None:
    """Give the child SIGINT's default disposition and an unblocked mask, as a shell does.

    Earlier tests in the same pytest process (worker pools, Dask) can leave SIGINT ignored or
    blocked, and a child inherits both, so it would never see the Ctrl-C this test sends.
    """
    signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})
    signal.signal(signal.SIGINT, signal.SIG_DFL)


@pytest.mark.slow
def test_ctrl_c_loses_nothing_and_restart_completes(tmp_path):
    out = tmp_path / "small"
    sweep_file = tmp_path / "small.toml"
    sweep_file.write_text(
        SMOKE.read_text().replace('["low", "high"]', '["high"]')
        .replace("replications = 2", "replications = 100")
    )  # fmt: skip
    abm = "import sys; from analysis.cli import main; sys.exit(main())"
    cmd = [sys.executable, "-c", abm, "sweep", str(sweep_file), "--executor", "serial",
           "--out", str(out)]  # fmt: skip
    proc = subprocess.Popen(cmd, cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            preexec_fn=_ctrl_c_as_in_a_terminal)  # fmt: skip
    deadline = time.monotonic() + 60
    while len(list((out / "runs").glob("*.parquet"))) < 2 and time.monotonic() < deadline:
        time.sleep(0.05)
    proc.send_signal(signal.SIGINT)
    _stdout, stderr = proc.communicate(timeout=60)
    assert proc.returncode == 130, stderr.decode()
    kept = {p.name: p.stat().st_mtime_ns for p in (out / "runs").glob("*.parquet")}
    assert 2 <= len(kept) < 200

    done = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert f"skipping {len(kept)} runs already in" in done.stderr
    df = load_results(out)
    assert len(df) == 200 and df["run_id"].is_unique and (df["status"] == "ok").all()
    assert {n: (out / "runs" / n).stat().st_mtime_ns for n in kept} == kept
    assert not [p for p in out.rglob("*.tmp")]


def test_leftover_temporary_files_are_ignored(tmp_path):
    grid = {**TINY, "launch_period": [24.0]}
    run_sweep("beacon-explorer", grid, 1, 4, tmp_path, "serial", progress=False)
    (tmp_path / "runs" / ".abc.parquet.1.tmp").write_bytes(b"half a file")
    df = run_sweep("beacon-explorer", grid, 1, 4, tmp_path, "serial", progress=False)
    assert len(df) == 1 and not list((tmp_path / "runs").glob("*.tmp"))


def test_time_series_are_kept_when_asked(tmp_path):
    grid = {**TINY, "launch_period": [24.0]}
    run_sweep("beacon-explorer", grid, 1, 4, tmp_path, "serial", time_series=True, progress=False)
    series = load_results(tmp_path, series=True)
    assert {"time", "ground", "explorer", "beacon", "run_id"} <= set(series.columns)
    assert os.path.isfile(tmp_path / "sweep.json")


def test_points_are_taken_together_and_combined_with_the_grid(tmp_path):
    path = tmp_path / "split.toml"
    path.write_text(
        'model = "beacon-explorer"\nreplications = 2\n[grid]\nworld = ["corridor"]\n'
        "[[points]]\nn_robots = 3\nlaunch_period = 6.0\n"
        "[[points]]\nn_robots = 5\nlaunch_period = 12.0\n"
    )
    sweep = load_sweep(path)
    assert sweep.n_runs == 4
    assert sweep.conditions() == [
        {"world": "corridor", "n_robots": 3, "launch_period": 6.0},
        {"world": "corridor", "n_robots": 5, "launch_period": 12.0},
    ]
    for text, match in [
        ('model = "beacon-explorer"\n[[points]]\nwings = 2\n', "'wings'"),
        ('model = "beacon-explorer"\n[grid]\nn_robots = [3]\n[[points]]\nn_robots = 4\n',
         "varies already"),
        ('model = "beacon-explorer"\npoints = [1]\n', r"points\[0\] must be a non-empty table"),
        ('model = "beacon-explorer"\n', "missing key 'grid'"),
    ]:  # fmt: skip
        path.write_text(text)
        with pytest.raises(ConfigError, match=match):
            load_sweep(path)


ONE_RUN = (
    'model = "beacon-explorer"\nseed = 7\nreplications = 1\n[grid]\nworld = ["corridor"]\n'
    'complexity = ["high"]\nlaunch_period = [24.0]\ntime_limit = [30.0]\n'
)


@given(seed=st.integers(0, 2**63 - 1), replications=st.one_of(st.none(), st.integers(1, 3)))
@settings(max_examples=25, deadline=None)
def test_a_seed_given_to_load_sweep_is_the_files_seed_changed(seed, replications):
    """``--seed N`` (``load_sweep(seed=N)``) must plan exactly what the file with ``seed = N``
    plans, and write the same ``sweep.json``: a re-measure on a fresh seed is then the
    repository's file plus one option, not an edited copy.
    """
    overridden = load_sweep(SMOKE, replications=replications, seed=seed)
    with tempfile.TemporaryDirectory() as folder:
        copy = Path(folder) / "smoke.toml"
        copy.write_text(re.sub(r"(?m)^seed = \d+$", f"seed = {seed}", SMOKE.read_text()))
        edited = load_sweep(copy, replications=replications)
    assert overridden.seed == seed
    assert overridden.manifest() == edited.manifest()
    assert plan(overridden) == plan(edited)


def test_cli_seed_runs_that_seed_and_a_resume_with_another_is_refused_in_one_line(tmp_path, capsys):
    from analysis.cli import main

    path = tmp_path / "one.toml"
    path.write_text(ONE_RUN)
    out = tmp_path / "out"
    common = ["sweep", str(path), "--executor", "serial", "--out", str(out)]
    assert main([*common, "--seed", "810600"]) == 0
    capsys.readouterr()
    assert json.loads((out / "sweep.json").read_text())["seed"] == 810600
    df = load_results(out)
    wanted = plan(load_sweep(path, seed=810600))
    assert list(df["seed"]) == [run.seed for run in wanted]
    assert [run.seed for run in wanted] != [run.seed for run in plan(load_sweep(path))]
    kept = {p.name: p.stat().st_mtime_ns for p in (out / "runs").glob("*.parquet")}

    for other in (["--seed", "810601"], []):  # another --seed, and the file's own seed 7
        assert main([*common, *other]) == 2
        err = capsys.readouterr().err
        refusal = [line for line in err.splitlines() if line.startswith("abm sweep: error:")]
        assert len(refusal) == 1 and "Traceback" not in err, err
        assert "seed 810600" in refusal[0] and ("810601" if other else "has 7") in refusal[0]
    assert {p.name: p.stat().st_mtime_ns for p in (out / "runs").glob("*.parquet")} == kept
    assert main([*common, "--seed", "810600"]) == 0  # the same seed resumes (nothing to run)
    assert len(load_results(out)) == 1


@pytest.mark.parametrize("text", ["-1", "abc", str(2**63), "1.5"])
def test_a_bad_seed_option_is_one_line_before_any_folder(tmp_path, capsys, text):
    from analysis.cli import main

    out = tmp_path / "out"
    assert main(["sweep", str(SMOKE), "--seed", text, "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--seed" in err[0] and "[0, 2**63 - 1]" in err[0], err
    assert not out.exists()
