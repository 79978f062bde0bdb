"""Sweeps that survive kill -9 and damaged files: nothing lost, nothing duplicated, nothing
damaged read as a result."""

import os
import random
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pandas as pd
import pyarrow as pa
import pyarrow.parquet as pq
import pytest

from analysis.sweep import Sweep, SweepError, execute, load_results, plan

ROOT = Path(__file__).resolve().parents[1]
VOLATILE = ["wall_time", "worker"]
#: 2 x 2 grid points x 4 replications of corridor runs cut at 240 s (~0.1-0.2 s of wall time each).
RUNS = 16
GRID = {"world": ["corridor"], "complexity": ["low", "high"], "launch_period": [6.0, 24.0],
        "time_limit": [240.0]}  # fmt: skip
SWEEP_TOML = """model = "beacon-explorer"
seed = 13
replications = 4
time_series = true
[grid]
world = ["corridor"]
complexity = ["low", "high"]
launch_period = [6.0, 24.0]
time_limit = [240.0]
"""
ABM = "import sys; from analysis.cli import main; sys.exit(main())"


def _rows(df: pd.DataFrame) -> pd.DataFrame:
    return df.drop(columns=VOLATILE).sort_values("run_id").reset_index(drop=True)


@pytest.fixture(scope="module")
def reference(tmp_path_factory) -> pd.DataFrame:
    """The sweep run once, uninterrupted, in this process."""
    sweep = Sweep("beacon-explorer", GRID, replications=4, seed=13, time_series=True)
    out = tmp_path_factory.mktemp("reference")
    return _rows(execute(sweep, out, executor="serial", progress=False))


def _files(folder: Path) -> list[str]:
    return sorted(p.name for p in folder.glob("*.parquet")) if folder.is_dir() else []


@pytest.mark.slow
def test_sweep_killed_at_seeded_random_moments_completes_each_run_once(tmp_path, reference):
    sweep_file = tmp_path / "killed.toml"
    sweep_file.write_text(SWEEP_TOML)
    out = tmp_path / "killed"
    cmd = [sys.executable, "-c", ABM, "sweep", str(sweep_file), "--executor", "serial",
           "--out", str(out)]  # fmt: skip
    draw = random.Random(20261123)
    # Kill when this many runs are on disk (then within 30 ms, inside the next run or its
    # write); the first kill lands during start-up (imports, the scan of the folder).
    targets = sorted(draw.sample(range(1, RUNS - 1), 3))
    kills = []
    for target in [0, *targets]:
        proc = subprocess.Popen(cmd, cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        if target == 0:
            time.sleep(draw.uniform(0.0, 1.0))
        else:
            deadline = time.monotonic() + 60
            while len(_files(out / "runs")) < target and time.monotonic() < deadline:
                time.sleep(0.002)
            time.sleep(draw.uniform(0.0, 0.03))
        assert proc.poll() is None, "the sweep ended before it could be killed"
        proc.send_signal(signal.SIGKILL)
        proc.communicate(timeout=30)
        assert proc.returncode == -signal.SIGKILL
        kills.append(len(_files(out / "runs")))
    assert kills == sorted(kills) and kills[-1] < RUNS, kills  # cut short each time, never undone

    done = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    resumed = _rows(load_results(out))
    assert len(resumed) == RUNS and resumed["run_id"].is_unique
    pd.testing.assert_frame_equal(resumed, reference)
    series = load_results(out, series=True)
    assert set(series["run_id"]) == set(reference["run_id"])
    assert not list(out.glob("*/*.tmp"))


def _damage(out: Path, ids: list[str]) -> dict[str, str]:
    """Damage result files in seven ways and the manifest; returns file -> the reason it must be
    set aside."""
    runs = out / "runs"
    truncated = runs / f"{ids[0]}.parquet"
    truncated.write_bytes(truncated.read_bytes()[: truncated.stat().st_size // 2])
    (runs / f"{ids[1]}.parquet").write_bytes(b"PAR1 this is not a parquet file PAR1")
    (runs / f"{ids[2]}.parquet").write_bytes((runs / f"{ids[3]}.parquet").read_bytes())
    twice = pq.read_table(runs / f"{ids[3]}.parquet")
    pq.write_table(pa.concat_tables([twice, twice]), runs / f"{ids[3]}.parquet")
    reseeded = pd.read_parquet(runs / f"{ids[4]}.parquet").assign(seed=12345)
    reseeded.to_parquet(runs / f"{ids[4]}.parquet", index=False)
    flipped = out / "series" / f"{ids[5]}.parquet"
    data = bytearray(flipped.read_bytes())
    data[len(data) // 3] ^= 0xFF  # one flipped byte inside a data page: its CRC fails
    flipped.write_bytes(bytes(data))
    (runs / f".{ids[6]}.parquet.999.tmp").write_bytes(b"half a file")
    (out / "sweep.json").write_text('{"grid": ')
    return {
        "sweep.json": "unreadable",
        f"runs/{ids[0]}.parquet": "unreadable",
        f"runs/{ids[1]}.parquet": "unreadable",
        f"runs/{ids[2]}.parquet": "wrong-run-id",
        f"runs/{ids[3]}.parquet": "not-one-row",
        f"runs/{ids[4]}.parquet": "wrong-seed",
        f"series/{ids[5]}.parquet": "unreadable",
        f"runs/.{ids[6]}.parquet.999.tmp": "half-written",
    }


def test_damaged_files_are_set_aside_named_and_run_again(tmp_path, reference, capsys):
    from analysis.cli import main

    sweep_file = tmp_path / "damaged.toml"
    sweep_file.write_text(SWEEP_TOML)
    out = tmp_path / "damaged"
    args = ["sweep", str(sweep_file), "--executor", "serial", "--out", str(out)]
    assert main(args) == 0
    capsys.readouterr()
    ids = sorted(reference["run_id"])
    damaged_at = time.time_ns()
    expected = _damage(out, ids)

    with pytest.raises(SweepError, match=f"{ids[0]}.parquet is damaged"):
        load_results(out)  # never read silently

    assert main(args) == 0
    err = capsys.readouterr().err
    for name, reason in expected.items():
        line = next((ln for ln in err.splitlines() if f"{out / name} ->" in ln), "")
        assert f"({reason}:" in line, (name, err)
    summary = (
        f"{len(expected)} damaged, half-written or foreign file(s) set aside in {out / 'set_aside'}"
    )
    assert summary in err
    aside = sorted(p.relative_to(out / "set_aside").as_posix() for p in
                   (out / "set_aside").rglob("*") if p.is_file())  # fmt: skip
    assert len(aside) == len(expected)
    for name, reason in expected.items():
        folder, file = name.rpartition("/")[::2]
        prefix = f"{folder}/" if folder else ""
        stem = file.lstrip(".").split(".")[0]
        assert any(a.startswith(f"{prefix}{stem}.{reason}.") for a in aside), (name, aside)
    untouched = [p for p in (out / "runs").glob("*.parquet") if p.stem in ids[7:]]
    assert all(p.stat().st_mtime_ns < damaged_at for p in untouched)  # not run again
    pd.testing.assert_frame_equal(_rows(load_results(out)), reference)
    assert set(load_results(out, series=True)["run_id"]) == set(ids)


def test_a_run_file_of_two_rows_is_never_read_as_two_runs(tmp_path):
    sweep = Sweep("beacon-explorer", GRID, replications=1, seed=13)
    execute(sweep, tmp_path, executor="serial", progress=False)
    path = sorted((tmp_path / "runs").glob("*.parquet"))[1]
    row = pq.read_table(path)
    pq.write_table(pa.concat_tables([row, row]), path)
    with pytest.raises(SweepError, match=f"{path.name} holds 2 rows, a run has one; run the"):
        load_results(tmp_path)


@pytest.mark.slow
def test_a_dask_worker_killed_mid_run_does_not_lose_the_sweep(tmp_path, reference):
    from dask.distributed import Client, LocalCluster

    sweep = Sweep("beacon-explorer", GRID, replications=4, seed=13, time_series=True)
    cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                           dashboard_address=None)  # fmt: skip
    client = Client(cluster)
    killed: list[tuple[int, bool, int]] = []

    def kill_a_worker_once_runs_land() -> None:
        deadline = time.monotonic() + 60
        while len(_files(tmp_path / "runs")) < 3 and time.monotonic() < deadline:
            time.sleep(0.01)
        pids = client.run(os.getpid)  # worker address -> pid
        busy = [a for a, tasks in client.processing().items() if tasks]
        victim = pids[busy[0] if busy else next(iter(pids))]
        os.kill(victim, signal.SIGKILL)
        killed.append((victim, bool(busy), len(_files(tmp_path / "runs"))))

    killer = threading.Thread(target=kill_a_worker_once_runs_land)
    killer.start()
    try:
        df = execute(sweep, tmp_path, executor=client, progress=False)
    finally:
        killer.join()
        client.close()
        cluster.close()
    assert killed, "no worker was killed"
    _pid, was_busy, written = killed[0]
    assert was_busy and written < RUNS  # killed while running a run, with runs still to come
    assert len(df) == RUNS and df["run_id"].is_unique and (df["status"] == "ok").all()
    assert len(_files(tmp_path / "runs")) == RUNS == len({s.run_id for s in plan(sweep)})
    pd.testing.assert_frame_equal(_rows(df), reference)
