"""A sweep killed with SIGKILL leaves no process behind, on local processes and on Dask's
LocalCluster, and its restart gives the rows of an uninterrupted sweep.

Each sweep starts in its own session (``start_new_session=True``, so the session id is the
sweep's pid); after ``kill -9`` of the sweep mid-run, every process of that session (pool
workers, forkserver, resource tracker, Dask nannies and workers) must be gone within seconds.
Linux only (the session of a process is read from ``/proc``).
"""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pandas as pd
import pytest

from abm import orphans
from analysis.sweep.storage import load_results

ROOT = Path(__file__).resolve().parents[1]
ABM = "import sys; from analysis.cli import main; sys.exit(main())"
#: 12 corridor runs of about a second each: long enough to kill a sweep in the middle.
SWEEP = """model = "beacon-explorer"
seed = 5
replications = 6
[grid]
world = ["corridor"]
complexity = ["high"]
launch_period = [6.0, 24.0]
time_limit = [400.0]
"""

pytestmark = pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="needs /proc")


def _session(sid: int) -> list[int]:
    """The pids of the live (non-zombie) processes whose session id is ``sid``."""
    pids = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            text = stat.read_text()
        except OSError:
            continue
        fields = text[text.rindex(")") + 2 :].split()
        if int(fields[3]) == sid and fields[0] not in ("Z", "X"):
            pids.append(int(stat.parent.name))
    return pids


def _rows(out: Path) -> pd.DataFrame:
    df = load_results(out).sort_values("run_id").reset_index(drop=True)
    where = ("worker", "error", "traceback")  # which process ran it, not what it gave
    return df.drop(columns=[c for c in df if "wall" in c or c in where])


@pytest.mark.slow
@pytest.mark.parametrize("executor", ["processes", "dask"])
def test_a_sweep_killed_with_sigkill_leaves_no_process_and_resumes_exactly(executor, tmp_path):
    if executor == "dask":
        pytest.importorskip("dask.distributed")
    sweep = tmp_path / "kill.toml"
    sweep.write_text(SWEEP)
    out = tmp_path / "killed"
    cmd = [sys.executable, "-c", ABM, "sweep", str(sweep), "--executor", executor,
           "--workers", "2", "--out", str(out)]  # fmt: skip
    proc = subprocess.Popen(cmd, cwd=ROOT, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL, start_new_session=True)  # fmt: skip
    deadline = time.monotonic() + 120
    while not list((out / "runs").glob("*.parquet")) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert len(_session(proc.pid)) > 2, "the pool never started"
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()
    written = len(list((out / "runs").glob("*.parquet")))
    assert 1 <= written < 12, "the sweep was not killed mid-run"
    deadline = time.monotonic() + 10
    while _session(proc.pid) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert not _session(proc.pid), f"left behind: {_session(proc.pid)}"

    done = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    whole = tmp_path / "whole"
    serial = [*cmd[:5], "--executor", "serial", "--out", str(whole)]
    assert subprocess.run(serial, cwd=ROOT, capture_output=True, timeout=300).returncode == 0
    pd.testing.assert_frame_equal(_rows(out), _rows(whole))


def test_the_watchdog_ends_a_process_whose_parent_died(tmp_path):
    # a parent that starts a child and dies at once; the child watches it and must exit
    flag = tmp_path / "child.pid"
    child = (
        "import sys, time; from abm.orphans import watch; "
        f"watch(sys.argv[1], period=0.05); open({str(flag)!r}, 'w').write('up'); time.sleep(60)"
    )
    parent = (
        "import subprocess, sys; from abm.orphans import identity; "
        f"p = subprocess.Popen([sys.executable, '-c', {child!r}, identity()]); "
        "print(p.pid, flush=True); import time; time.sleep(60)"
    )
    proc = subprocess.Popen([sys.executable, "-c", parent], cwd=ROOT, stdout=subprocess.PIPE,
                            text=True, start_new_session=True)  # fmt: skip
    child_pid = int(proc.stdout.readline())
    deadline = time.monotonic() + 30
    while not flag.exists() and time.monotonic() < deadline:
        time.sleep(0.05)
    assert orphans.alive(orphans.identity(child_pid))
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait()
    deadline = time.monotonic() + 5
    while orphans.alive(orphans.identity(child_pid)) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert not orphans.alive(orphans.identity(child_pid))


def test_alive_knows_this_process_and_not_a_reused_or_finished_pid():
    me = orphans.identity()
    assert orphans.alive(me)
    pid = me.split(":")[0]
    assert not orphans.alive(f"{pid}:1")  # same pid, another start time: a reused pid
    done = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                          capture_output=True, text=True)  # fmt: skip
    assert not orphans.alive(f"{int(done.stdout)}:")
