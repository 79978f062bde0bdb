"""A sweep's folder is the sweep's alone: plain names, no writes outside, a lock, no foreign
runs counted or reported, and one line (never a traceback, never a lost run) for a bad file,
a full disk or a read-only folder.
"""

import errno
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from abm.errors import ConfigError
from abm.orphans import identity
from analysis.cli import main
from analysis.sweep import Sweep, load_results, load_sweep, plan, storage

ROOT = Path(__file__).resolve().parents[1]
ABM = "import sys; from analysis.cli import main; sys.exit(main())"
#: Two corridor runs cut at 30 s of simulated time (~0.1 s of wall time each).
SMALL = (
    'model = "beacon-explorer"\nseed = 13\nreplications = 2\n[grid]\nworld = ["corridor"]\n'
    'complexity = ["high"]\nlaunch_period = [24.0]\ntime_limit = [30.0]\n'
)


def _tree(root: Path) -> set[str]:
    return {p.relative_to(root).as_posix() for p in root.rglob("*")}


def _errors(err: str, verb: str = "sweep") -> list[str]:
    """The error lines of ``abm <verb>``'s stderr (tqdm's bar and the header aside)."""
    assert "Traceback" not in err, err
    return [ln for ln in err.splitlines() if ln.startswith(f"abm {verb}: error:")]


@pytest.mark.parametrize("name", ["{abs}", "../../../escaped", "", ".", "..", "a/b", ".hidden"])
def test_traversal_names_are_refused_and_nothing_is_written_outside(
    tmp_path, monkeypatch, capsys, name
):
    work = tmp_path / "work" / "a" / "b"
    work.mkdir(parents=True)
    monkeypatch.chdir(work)
    name = name.format(abs=tmp_path / "elsewhere" / "x")
    sweep_file = tmp_path / "s.toml"
    sweep_file.write_text(f"name = {json.dumps(name)}\n" + SMALL)
    before = _tree(tmp_path)
    assert main(["sweep", str(sweep_file), "--executor", "serial"]) == 2
    err = capsys.readouterr().err
    (line,) = _errors(err)
    assert "name must be 1 to 100 characters" in line and str(sweep_file) in line
    assert _tree(tmp_path) == before  # nothing written anywhere, not even out/sweeps


def test_plain_names_write_under_out_sweeps(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    sweep_file = tmp_path / "s.toml"
    sweep_file.write_text('name = "corridor-v2.1_a"\n' + SMALL)
    assert main(["sweep", str(sweep_file), "--executor", "serial"]) == 0
    assert len(list((tmp_path / "out/sweeps/corridor-v2.1_a/runs").glob("*.parquet"))) == 2


def test_a_file_name_that_is_not_a_plain_name_needs_a_name_key(tmp_path):
    path = tmp_path / "my sweep.toml"
    path.write_text(SMALL)
    with pytest.raises(ConfigError, match=r"my sweep.toml: name must be .*set name ="):
        load_sweep(path)


def test_a_users_folder_is_refused_and_left_untouched(tmp_path, capsys):
    users = tmp_path / "mine"
    (users / "runs").mkdir(parents=True)
    pd.DataFrame({"x": [1]}).to_parquet(users / "runs" / "precious.parquet")
    (users / "notes.txt").write_text("mine")
    before = {p: p.stat().st_mtime_ns for p in users.rglob("*")}
    sweep_file = tmp_path / "s.toml"
    sweep_file.write_text(SMALL)
    assert main(["sweep", str(sweep_file), "--executor", "serial", "--out", str(users)]) == 2
    (line,) = _errors(capsys.readouterr().err)
    assert f"{users} is not a sweep folder (no sweep.json) and holds notes.txt, runs" in line
    assert {p: p.stat().st_mtime_ns for p in users.rglob("*")} == before


def _sweep_cmd(sweep_file: Path, out: Path) -> list[str]:
    return [sys.executable, "-c", ABM, "sweep", str(sweep_file), "--executor", "serial",
            "--out", str(out)]  # fmt: skip


def test_a_second_sweep_on_a_locked_folder_stops_and_the_first_runs_each_run_once(tmp_path):
    sweep_file = tmp_path / "long.toml"
    sweep_file.write_text(SMALL.replace("replications = 2", "replications = 60")
                          .replace("time_limit = [30.0]", "time_limit = [240.0]"))  # fmt: skip
    out = tmp_path / "shared"
    first = subprocess.Popen(_sweep_cmd(sweep_file, out), cwd=ROOT, stdout=subprocess.PIPE,
                             stderr=subprocess.PIPE, text=True)  # fmt: skip
    deadline = time.monotonic() + 90
    while len(list((out / "runs").glob("*.parquet"))) < 2 and time.monotonic() < deadline:
        time.sleep(0.02)
    second = subprocess.run(_sweep_cmd(sweep_file, out), cwd=ROOT, capture_output=True,
                            text=True, timeout=120)  # fmt: skip
    assert first.poll() is None, "the first sweep ended before the second one started"
    _out, first_err = first.communicate(timeout=300)
    assert second.returncode == 2
    (line,) = _errors(second.stderr)
    assert f"{out} is in use by another sweep: pid {first.pid} on " in line
    assert first.returncode == 0, first_err
    df = load_results(out)
    assert len(df) == 60 and df["run_id"].is_unique and (df["status"] == "ok").all()
    assert set(df["worker"].str.rpartition(":")[2]) == {str(first.pid)}  # none ran twice
    assert not (out / "set_aside").exists() and not (out / ".lock").exists()


def test_a_lock_whose_holder_is_gone_is_broken_with_a_word(tmp_path, capsys):
    sweep_file = tmp_path / "s.toml"
    sweep_file.write_text(SMALL)
    out = tmp_path / "stale"
    out.mkdir()
    gone = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                          capture_output=True, text=True, check=True)  # fmt: skip
    holder = {"pid": int(gone.stdout), "host": os.uname().nodename, "start": None,
              "since": "2026-01-01T00:00:00"}  # fmt: skip
    (out / ".lock").write_text(json.dumps(holder))
    assert main(["sweep", str(sweep_file), "--executor", "serial", "--out", str(out)]) == 0
    err = capsys.readouterr().err
    assert f"broke the lock of a sweep that is gone (pid {holder['pid']} on " in err
    assert len(load_results(out)) == 2 and not (out / ".lock").exists()


def test_a_report_on_a_sweep_still_running_is_one_line_and_waits_for_no_lock(tmp_path, capsys):
    """A report of a sweep being written judged its runs so far as the whole sweep (68 of 70
    runs); while the lock's holder runs, the report stops in one line; a stale lock does not
    stop it.
    """
    sweep_file = tmp_path / "s.toml"
    sweep_file.write_text(SMALL)
    out = tmp_path / "busy"
    assert main(["sweep", str(sweep_file), "--executor", "serial", "--out", str(out)]) == 0
    capsys.readouterr()
    start = identity().partition(":")[2] or None
    running = {"pid": os.getpid(), "host": os.uname().nodename, "start": start,
               "since": "2026-01-01T00:00:00"}  # fmt: skip
    (out / ".lock").write_text(json.dumps(running))
    assert main(["report", str(out)]) == 2
    (line,) = _errors(capsys.readouterr().err, "report")
    assert f"{out} is being written by a running sweep (pid {os.getpid()} on " in line
    assert not (out / "report.html").exists()
    gone = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                          capture_output=True, text=True, check=True)  # fmt: skip
    (out / ".lock").write_text(json.dumps({**running, "pid": int(gone.stdout), "start": None}))
    assert main(["report", str(out)]) == 0
    assert (out / "report.html").exists()


def test_a_lock_held_from_another_host_is_never_broken(tmp_path, capsys):
    sweep_file = tmp_path / "s.toml"
    sweep_file.write_text(SMALL)
    out = tmp_path / "remote"
    out.mkdir()
    holder = {"pid": 1, "host": "node-17.cluster", "start": None, "since": "2026-01-01T00:00"}
    (out / ".lock").write_text(json.dumps(holder))
    assert main(["sweep", str(sweep_file), "--executor", "serial", "--out", str(out)]) == 2
    (line,) = _errors(capsys.readouterr().err)
    assert "in use by another sweep: pid 1 on node-17.cluster" in line
    assert f"if it is gone, delete {out / '.lock'}" in line
    assert sorted(p.name for p in out.iterdir()) == [".lock"]


def _foreign_files(tmp_path: Path, out: Path) -> dict[str, str]:
    """Three run files that are not runs of ``out``'s sweep; returns file -> reason."""
    other = tmp_path / "other"
    reseeded = tmp_path / "reseeded.toml"
    reseeded.write_text(SMALL.replace("seed = 13", "seed = 14"))
    assert main(["sweep", str(reseeded), "--executor", "serial", "--out", str(other)]) == 0
    runs = sorted((out / "runs").glob("*.parquet"))
    # A run of a sweep with another seed, under the same run id (run ids do not hold the seed).
    (out / "runs" / runs[0].name).write_bytes((other / "runs" / runs[0].name).read_bytes())
    # A run whose parameters were changed.
    edited = pd.read_parquet(runs[1]).assign(launch_period=7.0)
    edited.to_parquet(runs[1], index=False)
    # A valid run file under a run id the plan does not have.
    stranger = pd.read_parquet(runs[1]).assign(launch_period=24.0, run_id="0123456789abcdef")
    stranger.to_parquet(out / "runs" / "0123456789abcdef.parquet", index=False)
    return {runs[0].name: "wrong-seed", runs[1].name: "wrong-params",
            "0123456789abcdef.parquet": "not-in-plan"}  # fmt: skip


def test_foreign_run_files_are_refused_by_report_and_set_aside_by_sweep(tmp_path, capsys):
    sweep_file = tmp_path / "s.toml"
    sweep_file.write_text(SMALL)
    out = tmp_path / "mine"
    args = ["sweep", str(sweep_file), "--executor", "serial", "--out", str(out)]
    assert main(args) == 0
    reference = load_results(out).drop(columns=["wall_time", "worker"])
    foreign = _foreign_files(tmp_path, out)
    capsys.readouterr()

    assert main(["report", str(out)]) == 2
    (line,) = _errors(capsys.readouterr().err, "report")
    assert f"{out} holds 3 run file(s) that are not runs of its sweep" in line
    for name, reason in foreign.items():
        assert f"runs/{name} ({reason}:" in line
    assert not (out / "report.html").exists()

    assert main(args) == 0
    err = capsys.readouterr().err
    for name, reason in foreign.items():
        assert f"{out / 'runs' / name} -> " in err and f"({reason}:" in err
    assert "3 damaged, half-written or foreign file(s) set aside" in err
    df = load_results(out).drop(columns=["wall_time", "worker"])
    pd.testing.assert_frame_equal(df, reference)  # the plan's runs, each once, as first run
    assert len(list((out / "set_aside" / "runs").glob("*.parquet"))) == 3


def test_a_sweep_over_other_keys_refuses_the_folder(tmp_path, capsys):
    sweep_file = tmp_path / "s.toml"
    sweep_file.write_text(SMALL)
    out = tmp_path / "keys"
    assert main(["sweep", str(sweep_file), "--executor", "serial", "--out", str(out)]) == 0
    sweep_file.write_text(SMALL + "n_robots = [5]\n")
    assert main(["sweep", str(sweep_file), "--executor", "serial", "--out", str(out)]) == 2
    (line,) = _errors(capsys.readouterr().err)
    assert "this one sets complexity, launch_period, n_robots, time_limit, world" in line


@pytest.mark.parametrize("encoding", ["utf-16", "latin-1"])
def test_a_sweep_file_not_in_utf8_is_one_line(tmp_path, capsys, encoding):
    path = tmp_path / "s.toml"
    path.write_bytes(('description = "Müller\'s corridor"\n' + SMALL).encode(encoding))
    assert main(["sweep", str(path), "--executor", "serial", "--out", str(tmp_path / "o")]) == 2
    (line,) = _errors(capsys.readouterr().err)
    assert f"{path}: not UTF-8 text" in line and "save the file as UTF-8" in line
    assert not (tmp_path / "o").exists()


def test_a_damaged_or_non_utf8_sweep_json_is_one_line_in_report(tmp_path, capsys):
    sweep_file = tmp_path / "s.toml"
    sweep_file.write_text(SMALL)
    out = tmp_path / "o"
    assert main(["sweep", str(sweep_file), "--executor", "serial", "--out", str(out)]) == 0
    capsys.readouterr()
    for damaged in (b'{"grid": ', '{"name": "Müller"}'.encode("latin-1")):
        (out / "sweep.json").write_bytes(damaged)
        assert main(["report", str(out)]) == 2
        (line,) = _errors(capsys.readouterr().err, "report")
        assert f"{out / 'sweep.json'} is damaged" in line


def _failing_writes(monkeypatch, after: int, code: int, text: str) -> None:
    """Result files (the storage's one Parquet writer) are written ``after`` times, then the
    write fails with ``code`` as pyarrow reports it (the errno only in the message)."""
    real = storage._write_parquet
    calls = []

    def write(data, path):
        calls.append(path)
        if len(calls) > after:
            Path(path).write_bytes(b"PAR1 cut")  # what a full disk leaves: a part of a file
            raise OSError(
                f"[Errno {code}] Error writing bytes to file. Detail: [errno {code}] {text}"
            )
        return real(data, path)

    monkeypatch.setattr(storage, "_write_parquet", write)


@pytest.mark.parametrize(
    ("code", "text", "advice"),
    [(errno.ENOSPC, "No space left on device", "free some space and run the same command again"),
     (errno.EROFS, "Read-only file system", "the folder is read-only")],
)  # fmt: skip
def test_a_full_disk_or_read_only_folder_during_a_sweep_keeps_finished_runs(
    tmp_path, monkeypatch, capsys, code, text, advice
):
    sweep_file = tmp_path / "s.toml"
    sweep_file.write_text(SMALL.replace("replications = 2", "replications = 5"))
    out = tmp_path / "o"
    args = ["sweep", str(sweep_file), "--executor", "serial", "--out", str(out)]
    _failing_writes(monkeypatch, 2, code, text)
    assert main(args) == 2
    (line,) = _errors(capsys.readouterr().err)
    assert f"{text}: {out / 'runs'}" in line and advice in line
    kept = {p.name: p.stat().st_mtime_ns for p in (out / "runs").glob("*.parquet")}
    assert len(kept) == 2 and not list(out.rglob("*.tmp")) and not (out / ".lock").exists()
    assert len(load_results(out)) == 2  # whole and verified

    monkeypatch.undo()
    assert main(args) == 0
    assert "skipping 2 runs already in" in capsys.readouterr().err
    df = load_results(out)
    assert len(df) == 5 and df["run_id"].is_unique and not (out / "set_aside").exists()
    assert {n: (out / "runs" / n).stat().st_mtime_ns for n in kept} == kept


def test_a_read_only_place_at_start_is_one_line(tmp_path, monkeypatch, capsys):
    sweep_file = tmp_path / "s.toml"
    sweep_file.write_text(SMALL)
    out = tmp_path / "ro" / "o"

    def read_only(self, *args, **kwargs):
        raise OSError(errno.EROFS, "Read-only file system", str(self))

    monkeypatch.setattr(Path, "mkdir", read_only)
    assert main(["sweep", str(sweep_file), "--executor", "serial", "--out", str(out)]) == 2
    (line,) = _errors(capsys.readouterr().err)
    assert f"Read-only file system: {out}" in line and "the folder is read-only" in line


@pytest.mark.parametrize("code", [errno.ENOSPC, errno.EROFS])
def test_a_full_disk_or_read_only_folder_in_report_is_one_line(tmp_path, monkeypatch, capsys, code):
    import analysis.report

    sweep_file = tmp_path / "s.toml"
    sweep_file.write_text(SMALL)
    out = tmp_path / "o"
    assert main(["sweep", str(sweep_file), "--executor", "serial", "--out", str(out)]) == 0
    capsys.readouterr()

    def cannot_write(template, path, **context):
        raise OSError(code, os.strerror(code), str(path))

    monkeypatch.setattr(analysis.report, "render_page", cannot_write)
    assert main(["report", str(out)]) == 2
    (line,) = _errors(capsys.readouterr().err, "report")
    assert f"{os.strerror(code)}: {out / 'report.html'}" in line
    assert len(load_results(out)) == 2  # the runs stay


def test_module_class_targets_are_checked_before_import(tmp_path):
    path = tmp_path / "zen.toml"
    path.write_text('model = "this:X"\n[grid]\nworld = ["open"]\n')
    done = subprocess.run([sys.executable, "-c", ABM, "sweep", str(path)], cwd=tmp_path,
                          capture_output=True, text=True, timeout=120)  # fmt: skip
    assert done.returncode == 2 and "Beautiful is better" not in done.stdout + done.stderr
    (line,) = _errors(done.stderr)
    assert "model 'this:X'" in line and "has no class 'X' at its top level, so it was not " \
        "imported" in line  # fmt: skip
    assert not (tmp_path / "out").exists()


def test_a_sweep_json_naming_another_module_is_refused_by_report_before_import(tmp_path):
    sweep_file = tmp_path / "s.toml"
    sweep_file.write_text(SMALL)
    out = tmp_path / "o"
    assert main(["sweep", str(sweep_file), "--executor", "serial", "--out", str(out)]) == 0
    manifest = json.loads((out / "sweep.json").read_text())
    (out / "sweep.json").write_text(json.dumps({**manifest, "target": "this:X"}))
    done = subprocess.run([sys.executable, "-c", ABM, "report", str(out)], cwd=tmp_path,
                          capture_output=True, text=True, timeout=300)  # fmt: skip
    assert done.returncode == 2 and "Beautiful is better" not in done.stdout + done.stderr
    (line,) = _errors(done.stderr, "report")
    assert f"{out / 'sweep.json'}: model 'this:X'" in line


def test_a_registered_models_target_still_loads():
    sweep = Sweep("models.beacon_explorer:BeaconExplorerModel", {"world": ["open"]})
    assert sweep.model_cls.__name__ == "BeaconExplorerModel"


BIG = {"launch_period": [1.0 + k / 1000 for k in range(1000)],
       "time_limit": [1.0 + k for k in range(1000)]}  # fmt: skip


def test_a_million_run_plan_gives_its_first_run_at_once():
    from analysis.sweep.seeding import iter_plan

    sweep = Sweep("beacon-explorer", BIG, replications=1, seed=3)
    assert sweep.n_runs == 1_000_000
    start = time.perf_counter()
    first = [spec for spec, _ in zip(iter_plan(sweep), range(3), strict=False)]
    assert time.perf_counter() - start < 1.0
    small = Sweep("beacon-explorer", {k: v[:1] for k, v in BIG.items()}, 1, 3)
    assert first[0] == plan(small)[0]  # the same run, whichever way it was planned


@pytest.mark.slow
def test_a_million_run_sweep_starts_its_first_run_within_10_s(tmp_path):
    path = tmp_path / "big.toml"
    path.write_text('model = "beacon-explorer"\nseed = 3\n[grid]\n' + "".join(
        f"{k} = {v}\n" for k, v in BIG.items()))  # fmt: skip
    out = tmp_path / "big"
    start = time.monotonic()
    proc = subprocess.Popen(_sweep_cmd(path, out), cwd=ROOT, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)  # fmt: skip
    try:
        while not list((out / "runs").glob("*.parquet")) and time.monotonic() - start < 60:
            time.sleep(0.05)
        first = time.monotonic() - start
    finally:
        proc.send_signal(signal.SIGKILL)
        _stdout, err = proc.communicate(timeout=120)
    assert first < 10.0, f"first run on disk after {first:.1f} s"
    assert "1000000 runs (1000000 grid points x 1 replications)" in err
    assert "/1000000 [" in err  # the progress line, with the total


#: Run inside a private mount namespace (``unshare -m``): a tiny tmpfs fills up mid-sweep, is
#: grown and the sweep resumed, then is made read-only for another sweep and a report.
_REAL_DEVICE = r"""
import json, subprocess, sys
from pathlib import Path
disk, toml, big = Path(sys.argv[1]), sys.argv[2], sys.argv[3]
abm = [sys.executable, "-c", "import sys; from analysis.cli import main; sys.exit(main())"]
def sh(*args): subprocess.run(args, check=True)
def run(*args):
    done = subprocess.run([*abm, *args], capture_output=True, text=True)
    return {"rc": done.returncode, "err": done.stderr,
            "runs": sorted(p.name for p in (disk / "o" / "runs").glob("*.parquet")),
            "tmp": sorted(str(p) for p in disk.rglob("*.tmp"))}
sh("mount", "-t", "tmpfs", "-o", "size=96k", "tmpfs", str(disk))
steps = {"full": run("sweep", toml, "--executor", "serial", "--out", str(disk / "o"))}
sh("mount", "-o", "remount,size=64m", str(disk))
steps["resumed"] = run("sweep", toml, "--executor", "serial", "--out", str(disk / "o"))
sh("mount", "-o", "remount,ro", str(disk))
steps["ro_sweep"] = run("sweep", big, "--executor", "serial", "--out", str(disk / "o"))
steps["ro_report"] = run("report", str(disk / "o"))
print(json.dumps(steps))
"""


@pytest.mark.slow
def test_a_real_full_disk_and_read_only_folder_keep_finished_runs(tmp_path):
    probe = subprocess.run(["unshare", "-m", "mount", "-t", "tmpfs", "tmpfs", str(tmp_path)],
                           capture_output=True)  # fmt: skip
    if probe.returncode != 0:
        pytest.skip("mounting a tmpfs needs root (unshare -m)")
    disk = tmp_path / "disk"
    disk.mkdir()
    toml = tmp_path / "s.toml"
    toml.write_text(SMALL.replace("replications = 2", "replications = 12"))
    big = tmp_path / "big.toml"
    big.write_text(SMALL.replace("replications = 2", "replications = 14"))
    done = subprocess.run(["unshare", "-m", sys.executable, "-c", _REAL_DEVICE, str(disk),
                           str(toml), str(big)], cwd=ROOT, capture_output=True, text=True,
                          timeout=600)  # fmt: skip
    assert done.returncode == 0, done.stderr
    steps = json.loads(done.stdout)
    full, resumed = steps["full"], steps["resumed"]
    (line,) = _errors(full["err"])
    assert f"No space left on device: {disk / 'o' / 'runs'}" in line and "free some space" in line
    assert 0 < len(full["runs"]) < 12 and not full["tmp"]
    assert resumed["rc"] == 0 and f"skipping {len(full['runs'])} runs already in" in resumed["err"]
    assert len(resumed["runs"]) == 12 and set(full["runs"]) <= set(resumed["runs"])
    for step, verb in (("ro_sweep", "sweep"), ("ro_report", "report")):
        assert steps[step]["rc"] == 2 and steps[step]["runs"] == resumed["runs"]
        (line,) = _errors(steps[step]["err"], verb)
        assert f"Read-only file system: {disk / 'o'}" in line and "read-only" in line


@settings(max_examples=60, deadline=None, derandomize=True, database=None)
@given(periods=st.lists(st.sampled_from([6.0, 12.0, 24.0, 48.0]), min_size=1, max_size=3,
                        unique=True),
       reps=st.integers(1, 3), seed=st.integers(0, 2**40), pick=st.integers(0, 99),
       change=st.sampled_from(["seed", "param", "run_id", "rep"]))  # fmt: skip
def test_a_plan_accepts_exactly_its_own_rows(tmp_path_factory, periods, reps, seed, pick, change):
    from analysis.sweep.integrity import CorruptResultError
    from analysis.sweep.membership import PlanIndex

    sweep = Sweep("beacon-explorer", {"launch_period": periods, "world": ["corridor", "open"]},
                  reps, seed)  # fmt: skip
    specs = plan(sweep)
    index = PlanIndex(sweep.manifest())
    spec = specs[pick % len(specs)]
    row = {"run_id": spec.run_id, "rep": spec.rep, "seed": spec.seed, **spec.params}
    path = tmp_path_factory.mktemp("row") / "row.parquet"
    pd.DataFrame([row]).to_parquet(path, index=False)
    read = pd.read_parquet(path).iloc[0].to_dict()  # numpy scalars, as a scan reads them
    assert index.match(read, spec.run_id) == (spec.params, spec.rep)
    rid = spec.run_id
    if change == "seed":
        read["seed"] += 1
    elif change == "param":
        read["launch_period"] = 96.0
    elif change == "rep":
        read["rep"] = reps
    else:
        rid = next((s.run_id for s in specs if s.run_id != rid), "0123456789abcdef")
    with pytest.raises(CorruptResultError):
        index.match(read, rid)


_VALUES = st.one_of(
    st.integers(-3, 3),
    st.sampled_from([0.0, 1.0, -2.0, 0.5, float("nan"), True, False, None, "a", "1"]),
    st.lists(st.sampled_from([0, 1, 1.0, True, None, "a"]), max_size=2),
)


@settings(max_examples=300, deadline=None)
@given(
    points=st.lists(st.dictionaries(st.sampled_from(["x", "y", "z"]), _VALUES, min_size=1),
                    min_size=1, max_size=12),
    row=st.dictionaries(st.sampled_from(["x", "y", "z", "w"]), _VALUES),
    pick=st.integers(0, 11),
)  # fmt: skip
def test_points_are_found_by_key_exactly_as_compared_one_by_one(points, row, pick):
    """The plan's points a row holds, looked up by key, are those a comparison of every point
    by value finds (1 and 1.0 alike, True not 1, None and NaN alike), in plan order."""
    from analysis.sweep.integrity import CorruptResultError
    from analysis.sweep.membership import PlanIndex, _holds

    index = PlanIndex({"points": points})
    gridded = PlanIndex({"points": points, "grid": {"w": [0, "a"]}})
    assert index._index is not None
    for candidate in (row, {**row, **points[pick % len(points)]}):
        expected = [p for p in index.points if _holds(candidate, p)]  # NaN != NaN: by identity
        if expected:
            assert list(map(id, index._points(candidate))) == list(map(id, expected))
        else:
            with pytest.raises(CorruptResultError):
                index._points(candidate)
        for plan_index in (index, gridded):
            assert plan_index.holds(candidate, 0) == _holds_by_scan(plan_index, candidate)


def _holds_by_scan(index, params: dict) -> bool:
    """Whether the plan has the run ``params`` (exactly these keys), every point compared."""
    from analysis.sweep.membership import _same

    for point in index.points:
        if set(params) == set(index.grid) | set(point) and all(
            any(_same(params[k], v) for v in vs) for k, vs in index.grid.items()
        ):
            if all(_same(params[k], v) for k, v in point.items()):
                return True
    return False


def test_a_design_of_24000_points_matches_a_row_without_reading_them_all():
    """A restart checks every run file against the plan: a 4,096-base-point Sobol' design has
    24,576 points, and comparing each file with each point took minutes per thousand files."""
    from analysis.sweep.membership import PlanIndex

    points = [{"a": k * 0.25, "b": k % 7, "c": "corridor"} for k in range(24_000)]
    index = PlanIndex({"points": points, "design": {"kind": "sobol"}})
    started = time.perf_counter()
    for k in range(0, 24_000, 12):
        assert index._points({"a": k * 0.25, "b": k % 7, "c": "corridor", "x": 1}) == [points[k]]
        assert index.holds(points[k], 0)
    assert time.perf_counter() - started < 2.0  # a scan point by point: about a minute
