"""``abm render``: PNG snapshots and an animation of a saved run, without re-running it."""

import argparse
import shutil
from pathlib import Path

from abm.errors import ABMError, OutputError

VERB = "render"
HELP = "draw PNG snapshots and an animated GIF (or MP4) of a run saved by `abm run`"
EXAMPLE = "abm render out/runs/flocking-20260101-120000-1 --times 0 60 120 --gif"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Options of ``abm render``."""
    parser.add_argument(
        "run",
        nargs="?",
        type=Path,
        default=None,
        help="run folder written by `abm run` (default: the newest in out/runs)",
    )
    parser.add_argument(
        "--times",
        type=float,
        nargs="+",
        metavar="T",
        help="snapshot times (s); default: --snapshots evenly spaced times over the run",
    )
    parser.add_argument(
        "--snapshots", type=int, default=4, help="number of evenly spaced snapshots (default 4)"
    )
    parser.add_argument(
        "--gif",
        action=argparse.BooleanOptionalAction,
        default=True,
        help="write an animated GIF of the whole run (default: yes)",
    )
    parser.add_argument("--mp4", action="store_true", help="also write an MP4 (needs ffmpeg)")
    parser.add_argument(
        "--frames", type=int, default=60, help="animation frames over the run (default 60)"
    )
    parser.add_argument(
        "--fps", type=float, default=8.0, help="animation frames per second (default 8)"
    )
    parser.add_argument(
        "--out", type=Path, default=None, help="output folder (default: RUN/render)"
    )


def main(args: argparse.Namespace) -> int:
    """Load the run folder, draw, print every path written."""
    from analysis.render import (
        check_animation,
        render_animation,
        render_snapshots,
        snapshot_times,
    )
    from analysis.run_folder import load_run

    if args.mp4 and shutil.which("ffmpeg") is None:
        raise ABMError("--mp4 needs ffmpeg on PATH (apt-get install -y ffmpeg); use the GIF")
    if args.gif or args.mp4:  # before any snapshot is drawn
        check_animation(args.frames, args.fps)
    folder = args.run if args.run is not None else _newest_run()
    run = load_run(folder)
    out = args.out if args.out is not None else folder / "render"
    if out.exists() and not out.is_dir():
        raise OutputError(f"--out {str(out)!r} is a file; give a folder for the pictures")
    times = args.times if args.times else snapshot_times(run, args.snapshots)
    written = render_snapshots(run, times, out)
    for path in written:
        print(f"wrote {path}")
    kinds = ([".gif"] if args.gif else []) + ([".mp4"] if args.mp4 else [])
    for kind in kinds:
        path = render_animation(run, out / f"run{kind}", frames=args.frames, fps=args.fps)
        print(f"wrote {path}")
    if not kinds and not written:
        print("nothing to draw (no --times and --no-gif)")
    return 0


def _newest_run() -> Path:
    """The newest run folder in ``out/runs`` (where ``abm run`` saves runs by default)."""
    from analysis.cli.run import RUNS
    from analysis.run_folder import runs_in

    runs = runs_in(RUNS)
    if not runs:
        raise ABMError(f"no run folder in {RUNS}/ yet; make one with `abm run MODEL`, or name one")
    return runs[-1]
