"""`abm run` and `abm render` around the run folder: one line for every bad input, checked
before the run; a new folder per run; nothing lost when saving fails; the progress line.

The runs are of the tests' tiny model (a second of simulated walking takes milliseconds).
"""

import errno
import io
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from abm.errors import ConfigError, OutputError
from analysis.cli import main
from analysis.run_folder import RUN_FILES, load_run, save_run

ROOT = Path(__file__).resolve().parents[1]
TINY = ["run", "tiny", "--time-limit", "20"]


@pytest.fixture
def here(tmp_path, monkeypatch, tiny_package):
    """Run the commands in an empty folder (``out/runs`` goes there) with the tiny model."""
    monkeypatch.chdir(tmp_path)
    return tmp_path


def _run(args: list[str], capsys) -> tuple[int, str, list[str]]:
    """Exit code, stdout and the lines of stderr of ``abm ARGS``."""
    rc = main(args)
    captured = capsys.readouterr()
    return rc, captured.out, captured.err.strip().splitlines()


def _one_line_error(rc: int, err: list[str], verb: str = "run") -> str:
    assert rc == 2
    assert len(err) == 1, err
    assert err[0].startswith(f"abm {verb}: error: ") or err[0].startswith("abm: error: ")
    return err[0]


def _next(out: str) -> Path:
    """The folder a run says to render (its ``next: abm render FOLDER`` line)."""
    line = next(line for line in out.splitlines() if line.startswith("next: abm render "))
    return Path(line.removeprefix("next: abm render "))


# ----------------------------------------------------------------- model targets
def test_a_module_class_target_is_checked_before_its_module_runs(tmp_path, monkeypatch, capsys):
    """``abm run module:Class`` reads the module's source first: a module that does not define
    the class is never imported (importing runs its code; ``this:X`` prints the Zen of Python).
    """
    marker = tmp_path / "imported"
    (tmp_path / "side_effect_module.py").write_text(
        f"from pathlib import Path\nPath({str(marker)!r}).write_text('ran')\n"
    )
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.chdir(tmp_path)
    rc, out, err = _run(["run", "side_effect_module:Model"], capsys)
    line = _one_line_error(rc, err)
    assert "has no class 'Model' at its top level, so it was not imported" in line
    assert not marker.exists() and out == ""


# ----------------------------------------------------------------- seeds
@pytest.mark.parametrize(
    "seed", ["-1", "9223372036854775808", "99999999999999999999999999999999999", "1.5", "x"]
)
def test_a_bad_seed_is_one_line_before_the_run(here, capsys, seed):
    rc, out, err = _run([*TINY, "--seed", seed], capsys)
    line = _one_line_error(rc, err)
    assert "seed must be an integer in [0, 2**63 - 1]" in line
    assert out == "" and not (here / "out").exists()  # nothing ran, nothing written


def test_a_model_refuses_a_bad_seed_before_any_work():
    from tiny_model import TinyModel

    for seed in (-1, 2**63, 1.5, "3", True):
        with pytest.raises(ConfigError, match=r"seed must be an integer in \[0, 2\*\*63 - 1\]"):
            TinyModel(seed=seed)
    model = TinyModel(seed=np.int64(2**63 - 1), time_limit=2.0)
    assert type(model.seed) is int  # stored in run.json as it is


def test_mesa_batch_run_meets_the_same_seed_rule(tiny_package):
    import mesa
    from tiny_model import TinyModel

    def batch(seed: int) -> list[dict]:
        return mesa.batch_run(
            TinyModel, {"time_limit": 2.0}, rng=[seed], max_steps=3, display_progress=False
        )

    with pytest.raises(ConfigError, match=r"seed must be an integer in \[0, 2\*\*63 - 1\]"):
        batch(-1)
    assert batch(2**63 - 1)[0]["seed"] == 2**63 - 1


def test_the_largest_seed_runs_and_is_saved(here, capsys):
    rc, out, _ = _run([*TINY, "--seed", str(2**63 - 1)], capsys)
    assert rc == 0
    assert load_run(_next(out)).meta["seed"] == 2**63 - 1


# ----------------------------------------------------------------- the run folder
def test_every_run_gets_a_new_folder_and_says_where(here, capsys):
    folders = []
    for seed in ("1", "2", "2"):
        rc, out, _ = _run([*TINY, "--seed", seed], capsys)
        assert rc == 0
        folder = _next(out)
        assert f"wrote {folder / 'run.json'}" in out
        folders.append(folder)
    assert len(set(folders)) == 3
    assert all(f.parent == Path("out/runs") and f.name.startswith("tiny-") for f in folders)
    assert folders[0].name.endswith("-1") and "-2" in folders[2].name
    assert [load_run(f).meta["seed"] for f in folders] == [1, 2, 2]
    # `abm render` with no folder draws the newest run
    rc, out, _ = _run(["render", "--no-gif", "--snapshots", "1"], capsys)
    assert rc == 0 and Path(out.split()[1]).parent == folders[2] / "render"


def test_out_refuses_a_folder_holding_another_run(here, capsys):
    assert main([*TINY, "--seed", "1", "--out", "mine"]) == 0
    before = {p.name: p.stat().st_mtime_ns for p in Path("mine").iterdir()}
    capsys.readouterr()
    rc, out, err = _run([*TINY, "--seed", "2", "--out", "mine"], capsys)
    line = _one_line_error(rc, err)
    assert "holds another run (tiny, seed 1)" in line and "--out" in line
    assert out == ""  # refused before the run
    assert {p.name: p.stat().st_mtime_ns for p in Path("mine").iterdir()} == before
    rc, out, err = _run([*TINY, "--seed", "1", "--walkers", "3", "--out", "mine"], capsys)
    assert "holds another run" in _one_line_error(rc, err)
    # the same run again (same model, seed and parameters) replaces itself
    assert main([*TINY, "--seed", "1", "--out", "mine"]) == 0


def test_out_refuses_a_folder_of_other_files_a_file_and_a_path_through_a_file(here, capsys):
    Path("notes").mkdir()
    Path("notes/paper.txt").write_text("mine")
    Path("afile").write_text("x")
    for out, expected in [
        ("notes", "holds other files and is not a run folder"),
        ("afile", "'afile' is a file, not a folder"),
        ("afile/run", "'afile' is a file"),
    ]:
        rc, printed, err = _run([*TINY, "--out", out], capsys)
        assert expected in _one_line_error(rc, err)
        assert printed == ""
    assert Path("notes/paper.txt").read_text() == "mine" and Path("afile").read_text() == "x"


def test_out_in_a_place_that_cannot_be_written_is_one_line_before_the_run(here, capsys):
    real_mkdtemp = tempfile.mkdtemp

    def read_only(*args, dir=None, **kwargs):  # noqa: A002 - tempfile's own keyword
        if dir is not None and "ro" in Path(dir).parts:
            raise OSError(errno.EROFS, os.strerror(errno.EROFS), str(dir))
        return real_mkdtemp(*args, dir=dir, **kwargs)

    # root may write anywhere, so a read-only file system is simulated where the check writes
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(tempfile, "mkdtemp", read_only)
        rc, out, err = _run([*TINY, "--out", "ro"], capsys)
    line = _one_line_error(rc, err)
    assert "Read-only file system: ro; the folder is read-only: choose a writable place" in line
    assert out == "" and not Path("ro").exists()  # nothing ran; the folder made is gone
    rc, out, err = _run([*TINY, "--out", "x" * 300], capsys)
    assert "File name too long: " + "x" * 300 in _one_line_error(rc, err)
    assert out == ""


# ----------------------------------------------------------------- a failure while saving
def _disk_full_under(folder: Path, monkeypatch, after: int = 1) -> None:
    """The Parquet writer fails with ENOSPC for files under ``folder`` once ``after`` files
    were written there.
    """
    real = pd.DataFrame.to_parquet
    written = []

    def to_parquet(self, path, *args, **kwargs):
        name = Path(getattr(path, "name", path)).resolve()
        if folder.resolve() in name.parents:
            if len(written) >= after:
                raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
            written.append(name)
        return real(self, path, *args, **kwargs)

    monkeypatch.setattr(pd.DataFrame, "to_parquet", to_parquet)


def test_a_full_disk_while_saving_loses_no_finished_run(here, capsys, monkeypatch):
    spare = here / "elsewhere"
    spare.mkdir()
    monkeypatch.setattr(tempfile, "tempdir", str(spare))
    _disk_full_under(here / "out", monkeypatch)
    rc, out, err = _run([*TINY, "--seed", "4"], capsys)
    line = _one_line_error(rc, err)
    assert "No space left on device: out/runs/tiny-" in line and "positions.parquet" in line
    assert "`mv " in line and "Traceback" not in "\n".join(err)
    # no half-written run folder, no temporary files left where the disk is full
    assert list((here / "out" / "runs").iterdir()) == []
    # the finished run is whole in the folder the message names
    rescued = Path(line.split("was saved to ")[1].split(" instead")[0])
    assert rescued.is_relative_to(spare)
    run = load_run(rescued)
    assert "tiny, seed 4:" in out and run.meta["seed"] == 4
    monkeypatch.undo()
    from tiny_model import TinyModel

    again = TinyModel(seed=4, time_limit=20.0, trace_interval=1.0).run()
    pd.testing.assert_frame_equal(run.events, again.events())


def test_when_no_place_can_be_written_the_message_says_how_to_repeat_the_run(
    here, capsys, monkeypatch
):
    spare = here / "full-too"
    spare.mkdir()
    monkeypatch.setattr(tempfile, "tempdir", str(spare))
    _disk_full_under(here, monkeypatch, after=0)
    rc, out, err = _run([*TINY, "--seed", "4", "--out", "kept"], capsys)
    line = _one_line_error(rc, err)
    assert "the run is not saved" in line
    assert "`abm run tiny --time-limit 20 --seed 4 --out kept` repeats it event for event" in line
    assert "tiny, seed 4:" in out  # its summary was printed before saving
    assert not Path("kept").exists()
    assert [p for p in spare.rglob("*") if p.is_file()] == []


def test_a_failure_while_replacing_a_run_keeps_the_run_that_was_there(tmp_path, monkeypatch):
    from tiny_model import TinyModel

    folder = tmp_path / "run"
    save_run(TinyModel(seed=1, time_limit=5.0).run(), folder)
    before = {name: (folder / name).read_bytes() for name in RUN_FILES}
    _disk_full_under(tmp_path, monkeypatch, after=2)
    with pytest.raises(OutputError) as caught:
        save_run(TinyModel(seed=1, time_limit=8.0).run(), folder)
    assert caught.value.errno == errno.ENOSPC
    assert caught.value.filename == str(folder / "state_counts.parquet")
    assert {name: (folder / name).read_bytes() for name in RUN_FILES} == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run"]  # no partial folder left


# ----------------------------------------------------------------- encodings
def test_a_folder_name_in_no_encoding_is_saved_and_rendered(here, capsys):
    name = os.fsdecode(b"run-\xff")  # not UTF-8: the file system takes it, pyarrow would not
    rc, out, _ = _run([*TINY, "--out", name], capsys)
    assert rc == 0 and load_run(Path(name)).meta["seed"] == 1
    assert main(["render", name, "--no-gif", "--snapshots", "1"]) == 0


@pytest.mark.slow
def test_a_non_utf8_folder_name_and_an_ascii_terminal(tmp_path, tiny_package):
    name = os.fsdecode(b"run-\xff-\xc3\xa9")  # an undecodable byte, then an e-acute
    command = [sys.executable, "-c", "import sys; from analysis.cli import main; sys.exit(main())"]
    command += [*TINY, "--out", name]
    env = {**os.environ, "PYTHONIOENCODING": "ascii", "PYTHONPATH": os.environ["PYTHONPATH"]}
    env["PYTHONPATH"] += os.pathsep + str(ROOT)
    result = subprocess.run(command, cwd=tmp_path, capture_output=True, env=env, timeout=120)
    assert result.returncode == 0, result.stderr.decode(errors="replace")
    assert b"Traceback" not in result.stderr
    assert b"next: abm render run-\\udcff-\\xe9" in result.stdout
    assert load_run(tmp_path / name).meta["seed"] == 1


def test_render_of_a_run_json_in_another_encoding_is_one_line(here, capsys):
    assert main([*TINY, "--out", "r"]) == 0
    Path("r/run.json").write_bytes(b'{"model": "\xff"}')
    capsys.readouterr()
    rc, _, err = _run(["render", "r"], capsys)
    line = _one_line_error(rc, err, "render")
    assert "run folder 'r' is damaged (UnicodeDecodeError" in line


@pytest.mark.parametrize(
    ("name", "damage"),
    [("arena.npz", b"PK\x03\x04cut"), ("events.parquet", b"PAR1cut"), ("run.json", b"[]")],
)
def test_render_of_a_damaged_run_folder_is_one_line(here, capsys, name, damage):
    assert main([*TINY, "--out", "r"]) == 0
    Path("r", name).write_bytes(damage)
    capsys.readouterr()
    rc, _, err = _run(["render", "r"], capsys)
    line = _one_line_error(rc, err, "render")
    assert line.startswith("abm render: error: run folder 'r' is damaged (")
    assert "re-run it with `abm run MODEL --out r`" in line


def test_saved_files_get_the_usual_permissions(tmp_path, tiny_package):
    from tiny_model import TinyModel

    plain = tmp_path / "plain"
    plain.mkdir()
    save_run(TinyModel(seed=1, time_limit=2.0).run(), tmp_path / "run")
    assert (tmp_path / "run").stat().st_mode == plain.stat().st_mode


# ----------------------------------------------------------------- render's one-liners
def test_render_says_what_it_got_and_what_it_takes(here, capsys):
    Path("afile").write_text("x")
    Path("empty").mkdir()
    for target, expected in [
        ("afile", "'afile' is a file, not a run folder; give a run folder written by `abm run`"),
        ("empty", "'empty' is not a run folder (no run.json); give a run folder written by"),
        ("missing", "run folder 'missing' does not exist"),
    ]:
        rc, _, err = _run(["render", target], capsys)
        assert expected in _one_line_error(rc, err, "render")
    rc, _, err = _run(["render"], capsys)
    assert "no run folder in out/runs/ yet" in _one_line_error(rc, err, "render")
    assert main([*TINY, "--seed", "3"]) == 0
    capsys.readouterr()
    rc, _, err = _run(["render", "out/runs"], capsys)
    line = _one_line_error(rc, err, "render")
    assert "'out/runs' holds 1 run folder(s), not one run; name one" in line
    rc, _, err = _run(["render", "--out", "afile"], capsys)
    assert "--out 'afile' is a file; give a folder" in _one_line_error(rc, err, "render")
    rc, _, err = _run(["render", "--frames", "many"], capsys)
    assert "argument --frames: invalid int value: 'many'" in _one_line_error(rc, err, "render")


# ----------------------------------------------------------------- progress
def test_progress_leaves_the_run_unchanged_and_shows_time_robots_and_events(tiny_package):
    from tiny_model import TinyModel

    from analysis.cli.progress import RunProgress

    plain = TinyModel(seed=7, time_limit=60.0).run()
    watched = TinyModel(seed=7, time_limit=60.0)
    stream = io.StringIO()
    with RunProgress(watched, delay=0.0, file=stream):
        watched.run()
    pd.testing.assert_frame_equal(watched.events(), plain.events())
    pd.testing.assert_frame_equal(watched.state_counts(), plain.state_counts())
    last = stream.getvalue().split("\r")[-1]
    assert f"| t {plain.time:.0f}/60 s, 6 robots (resting 6), " in last  # all rested: the end
    assert f"{len(plain.events()):,} events" in last and "x real time" in last


def test_a_short_run_prints_no_progress_and_stdout_keeps_only_results(here, capsys):
    rc, out, err = _run([*TINY, "--seed", "2"], capsys)
    assert rc == 0 and err == []
    assert "robots" not in out and "%|" not in out


def test_seed_text_and_none():
    from abm.errors import check_seed, parse_seed

    assert parse_seed(" 42 ") == 42
    assert check_seed(None) is None
    with pytest.raises(ConfigError, match="seed must be an integer in"):
        check_seed(None, allow_none=False)
    with pytest.raises(ConfigError, match=r"\(4502 characters\)$"):
        parse_seed("1" * 4500)  # past Python's digit limit: still one short line


def test_run_json_is_json_with_the_seed_as_given(here, capsys):
    assert main([*TINY, "--seed", "12", "--out", "r"]) == 0
    assert json.loads(Path("r/run.json").read_text())["seed"] == 12


def test_run_help_gives_the_trace_interval_the_run_uses_not_the_models_none(capsys):
    # sugarmap samples no positions by default (sweeps); abm run samples every 1 s anyway
    from analysis.cli import main

    with pytest.raises(SystemExit):
        main(["run", "sugarmap", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "[1 here; none in sweeps and from Python]" in text
