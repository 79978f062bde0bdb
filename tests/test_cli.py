"""The `abm` command line: help, every verb once with tiny inputs, one-line errors, --debug."""

import socket
import subprocess
import sys
from pathlib import Path

import pytest

from analysis.cli import VERB_MODULES, _load_verbs, main
from analysis.run_folder import RUN_FILES, save_run

ROOT = Path(__file__).resolve().parents[1]


def _wrote(out: str) -> list[Path]:
    """The paths a command says it wrote (lines ``wrote PATH``)."""
    return [Path(line[6:].strip()) for line in out.splitlines() if line.startswith("wrote ")]


def test_help_lists_every_verb_with_an_example(capsys):
    with pytest.raises(SystemExit) as exit_:
        main(["--help"])
    assert exit_.value.code == 0
    out = capsys.readouterr().out
    verbs = _load_verbs()
    assert [v.VERB for v in verbs] == list(VERB_MODULES)
    for verb in verbs:
        assert verb.EXAMPLE.startswith(f"abm {verb.VERB}")
        assert verb.EXAMPLE in out
        with pytest.raises(SystemExit):
            main([verb.VERB, "--help"])
        assert verb.EXAMPLE in capsys.readouterr().out


def test_no_verb_prints_help(capsys):
    assert main([]) == 0
    assert "examples:" in capsys.readouterr().out


def test_run_saves_what_render_needs(tmp_path, capsys):
    out = tmp_path / "run"
    rc = main(
        ["run", "beacon-explorer", "--n-robots", "3", "--time-limit", "30", "--seed", "2",
         "--out", str(out)]
    )  # fmt: skip
    assert rc == 0
    written = _wrote(capsys.readouterr().out)
    assert written and all(path.exists() for path in written)
    missing = [name for name in RUN_FILES if not (out / name).is_file()]
    assert not missing, f"abm run must call analysis.run_folder.save_run; missing {missing}"


@pytest.fixture(scope="module")
def run_dir(tmp_path_factory):
    from models.beacon_explorer import BeaconExplorerModel

    folder = tmp_path_factory.mktemp("saved")
    save_run(BeaconExplorerModel(n_robots=3, time_limit=25.0, seed=5).run(), folder)
    return folder


def test_render_writes_snapshots_and_a_gif(run_dir, tmp_path, capsys):
    out = tmp_path / "render"
    rc = main(["render", str(run_dir), "--times", "0", "10", "--frames", "3", "--out", str(out)])
    assert rc == 0
    written = _wrote(capsys.readouterr().out)
    assert [p.name for p in written] == ["snapshot_00000s.png", "snapshot_00010s.png", "run.gif"]
    assert all(p.is_file() and p.stat().st_size > 1000 for p in written)


@pytest.mark.parametrize(("flag", "said"), [("--frames=0", "frames"), ("--fps=0", "fps")])
def test_a_bad_animation_option_is_refused_before_any_snapshot_is_drawn(
    run_dir, tmp_path, capsys, flag, said
):
    out = tmp_path / "render"
    assert main(["render", str(run_dir), flag, "--out", str(out)]) == 2
    assert f"{said} must be" in capsys.readouterr().err
    assert not out.exists()


def test_render_defaults_to_four_snapshots(run_dir, capsys):
    assert main(["render", str(run_dir), "--no-gif"]) == 0
    written = _wrote(capsys.readouterr().out)
    assert len(written) == 4
    assert all(p.parent == run_dir / "render" for p in written)


def test_errors_are_one_line_without_traceback(tmp_path, capsys):
    assert main(["render", str(tmp_path / "missing")]) == 2
    captured = capsys.readouterr()
    err = captured.err.strip().splitlines()
    assert len(err) == 1
    assert err[0].startswith("abm render: error: run folder")
    assert "Traceback" not in captured.err


@pytest.mark.parametrize(
    ("argv", "said"),
    [
        (["run", "flocking", "--birdz", "3"], "abm run: error: unrecognized arguments: --birdz 3; "
         "did you mean --birds for --birdz? (see abm run flocking --help)"),
        (["sweep", "--workrs=3", "x.toml"], "abm sweep: error: unrecognized arguments: "
         "--workrs=3; did you mean --workers for --workrs? (see abm sweep --help)"),
        (["--degub"], "abm: error: unrecognized arguments: --degub; did you mean --debug for "
         "--degub? (see abm --help)"),
        (["report", "--zzzz", "x"], "abm report: error: unrecognized arguments: --zzzz "
         "(see abm report --help)"),
        (["calibrate", "tangible-pso"], "abm calibrate: error: the following arguments are "
         "required: --target, --free, --out (see abm calibrate --help)"),
    ],
)  # fmt: skip
def test_a_bad_command_line_is_named_by_the_verb_that_refused_it_with_its_closest_option(
    argv, said, tmp_path, monkeypatch, capsys
):
    monkeypatch.chdir(tmp_path)
    assert main(argv) == 2
    assert capsys.readouterr().err.strip() == said
    assert list(tmp_path.iterdir()) == []  # refused before any work


def test_debug_shows_the_traceback(tmp_path):
    command = [
        sys.executable, "-c", "import sys; from analysis.cli import main; sys.exit(main())",
        "--debug", "render", str(tmp_path / "missing"),
    ]  # fmt: skip
    result = subprocess.run(command, cwd=ROOT, capture_output=True, text=True, timeout=60)
    assert result.returncode != 0
    assert "Traceback (most recent call last)" in result.stderr
    assert "RunFolderError" in result.stderr


def test_viz_refuses_a_busy_port_in_one_line(capsys):
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        sock.listen(1)
        port = sock.getsockname()[1]
        rc = main(["viz", "beacon-explorer", "--host", "127.0.0.1", "--port", str(port)])
    assert rc == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("abm viz: error:")


def test_an_unknown_model_is_one_line_naming_the_known_ones(capsys):
    for verb in ("run", "viz", "fit"):
        assert main([verb, "no-such-model"]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and "unknown model 'no-such-model'" in err[0]
        assert "beacon-explorer" in err[0] and "stigmergy" in err[0]
    assert main(["run"]) == 2
    err = capsys.readouterr().err
    assert "name a model: beacon-explorer, " in err and ", stigmergy" in err  # sorted names


def test_run_flags_come_from_the_params_with_their_help(capsys):
    with pytest.raises(SystemExit):
        main(["run", "beacon-explorer", "--help"])
    out = capsys.readouterr().out
    for flag in ("--attach-eps", "--guide-hysteresis", "--message-loss", "--latency"):
        assert flag in out
    assert "the paper gives no value" in out  # attach_eps's docstring text
    assert main(["run", "beacon-explorer", "--attach-eps", "-1"]) == 2
    assert "attach_eps must be in (0" in capsys.readouterr().err


def test_run_of_a_mixed_world_needs_no_complexity(tmp_path, capsys):
    out = tmp_path / "mixed"
    args = ["run", "beacon-explorer", "--world", "mixed", "--time-limit", "20", "--out", str(out)]
    assert main(args) == 0
    assert "medium" in capsys.readouterr().out


def test_sweep_then_report(tmp_path, capsys):
    out = tmp_path / "sweep"
    smoke = ROOT / "experiments" / "smoke.toml"
    args = ["sweep", str(smoke), "--executor", "serial", "--replications", "1", "--out", str(out)]
    assert main(args) == 0
    assert all(p.exists() for p in _wrote(capsys.readouterr().out))
    assert main(["report", str(out)]) == 0
    written = _wrote(capsys.readouterr().out)
    assert written and all(p.exists() for p in written)


@pytest.mark.slow
def test_fit_regresses_the_lambdas_and_holds_maps_out(tmp_path, capsys):
    """Two maps x three radii: the lambda regression (it needs 3 radii) and the held-out check
    (it needs 2 maps) both run and reach the report."""
    out = tmp_path / "fit"
    args = ["fit", "stigmergy", "--grid", "map=hall100,divided",
            "--grid", "pheromone_radius=20,30,40", "--set", "time_limit=400", "--runs", "2",
            "--workers", "1", "--out", str(out)]  # fmt: skip
    assert main(args) == 0
    printed = capsys.readouterr().out
    written = _wrote(printed)
    assert written and all(p.exists() for p in written)
    assert "wander_hat" in printed and "rmsd_wander" in printed
    # both fitting methods side by side, with the paper's figures
    assert "[6 conditions, the paper's method" in printed
    assert "[6 conditions, joint refinement" in printed and "[paper (Table 2" in printed
    html = (out / "fit_report.html").read_text()
    assert "Fitted lambdas" in html and "Held-out conditions" in html
    assert "Fitting methods side by side" in html
    assert main(["fit", "stigmergy", "--read", str(out), "--out", str(tmp_path / "again")]) == 0
    assert capsys.readouterr().out.splitlines()[:8] == printed.splitlines()[:8]
    # the sweep report of the same runs shows the fitting methods side by side too
    assert main(["report", str(out), "--out", str(tmp_path / "report.html")]) == 0
    page = (tmp_path / "report.html").read_text()
    assert "fitting methods side by side" in page and "joint refinement: the six" in page


def test_fit_assignments_read_each_parameter_type():
    from abm.errors import ConfigError
    from analysis.cli.flags import parse_assignment
    from models.beacon_explorer.params import BeaconExplorerParams as P

    assert parse_assignment(P, "launch_period=6,12", many=True) == ("launch_period", [6.0, 12.0])
    assert parse_assignment(P, "n-robots=5") == ("n_robots", [5])
    assert parse_assignment(P, "n_robots=none") == ("n_robots", [None])
    assert parse_assignment(P, "hover_beacons=true,no", many=True) == (
        "hover_beacons", [True, False],
    )  # fmt: skip
    assert parse_assignment(P, "complexity=low,high", many=True) == ("complexity", ["low", "high"])
    assert parse_assignment(P, "start=2.5,5.5") == ("start", [(2.5, 5.5)])
    assert parse_assignment(P, "start=1,2;3,4", many=True) == ("start", [(1.0, 2.0), (3.0, 4.0)])
    for text, match in [
        ("launch_period", "expected NAME=VALUE"),
        ("wings=2", "unknown parameter 'wings'"),
        ("launch_period=fast", "launch_period: cannot read 'fast'"),
        ("launch_period=-1", r"launch_period must be in \(0"),
        ("hover_beacons=maybe", "hover_beacons takes true or false"),
        ("complexity=extreme", "complexity must be one of"),
    ]:
        with pytest.raises(ConfigError, match=match):
            parse_assignment(P, text)


@pytest.mark.parametrize(
    ("extra", "said"),
    [(["--grid", "n_anchors=4,6"], "the grid has 0 interior point(s)"),
     (["--grid", "n_anchors=4,6,8", "--set", "n_anchors=5"], "both swept (--grid) and fixed"),
     (["--read", "somewhere"], "no sweep folder 'somewhere'"),
     (["--runs", "1"], "--runs must be at least 2 to fit rates"),
     (["--held", "0"], "--held must be at least 1"),
     (["--set", "n_anchors=-3"], "n_anchors")],
)  # fmt: skip
def test_rate_equations_refuse_what_they_cannot_do_before_any_run(extra, said, tmp_path, capsys):
    out = tmp_path / "fit"
    assert main(["fit", "sugarmap", *extra, "--out", str(out)]) != 0
    err = capsys.readouterr().err
    assert said in err and len(err.strip().splitlines()) == 1 and not out.exists()


@pytest.mark.parametrize("verb", ["calibrate", "fit"])
def test_a_bad_seed_is_one_line_before_any_folder(verb, tmp_path, capsys):
    # calibrate once started pyABC with a negative seed and died deep inside its workers
    target = tmp_path / "t.csv"
    target.write_text("metric,value,sd\ncoverage_time,300,50\n")
    extra = ["--target", str(target), "--free", "launch_period=2:20"] if verb == "calibrate" else []
    out = tmp_path / "out"
    assert main([verb, "beacon-explorer", *extra, "--seed", "-3", "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "seed must be an integer in [0, 2**63 - 1], got -3" in err[0]
    assert not out.exists()


def test_fit_leaves_states_no_run_occupies_unchecked_and_says_slower_not_0x_faster(
    tmp_path, capsys
):
    # tangible PSO without a deployment never enters blocked/deploying/deployed: an RMSD of 0
    # there would be a statistic of zeros, printed as a perfect fit
    quick = ["--set", "particles=10", "--set", "iterations=6"]
    rc = main(["fit", "tangible-pso", "--runs", "2", "--held", "1", *quick,
               "--out", str(tmp_path / "fit")])  # fmt: skip
    out = capsys.readouterr().out
    assert rc == 0
    assert (
        "never occupied, held out or predicted (not checked): blocked, deploying, deployed" in out
    )
    speed = next(line for line in out.splitlines() if line.startswith("speed:"))
    assert " 0." not in speed and ("faster" in speed or "slower" in speed)


@pytest.mark.parametrize(
    ("argv", "hint"),
    [
        (["run", "hierarchy", "--scouts", "3"], "--scouts-per-worker for --scouts"),
        (["run", "sugarmap", "--n-anchor", "3"], "--n-anchors for --n-anchor"),
        (["sweep", "experiments/smoke.toml", "--rep", "2"], "--replications for --rep"),
    ],
)
def test_an_abbreviated_option_is_refused_naming_the_option_it_begins(argv, hint, capsys):
    # argparse would take "--scouts 3" for "--scouts-per-worker 3" without a word
    assert main(argv) == 2
    assert hint in capsys.readouterr().err
