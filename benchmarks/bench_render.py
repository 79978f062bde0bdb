"""``abm render`` before and after, side by side: frames per second of the default pictures.

Renders one saved run the way ``abm render RUN`` does by default (4 snapshots, a 60-frame
GIF) twice in one process, alternating: with the ``analysis/render.py`` of a baseline commit
(default: the commit before the fast renderer), loaded from ``git show`` into a temporary
module, and with today's. Prints each one's time and frames per second (snapshots and GIF
frames together, and the GIF's alone), the ratio, the machine and the load average. On a
loaded machine the ratio is the number to read; absolute figures go with the machine named.
It also says whether both wrote the same pictures: the GIF byte for byte, and per snapshot the
pixels that differ (the baseline laid each snapshot out again on the figure of the previous
one, so after the first its panels could drift by a fraction of a pixel; now each is laid out
as a new figure is, as the first one always was).

Both draw from the same run folder and share everything but ``analysis/render.py`` (the
scene view, the run folder reader); a module the baseline imports under a name since changed
(:data:`RENAMED`) is given to it under its old name.

Usage: python benchmarks/bench_render.py [--run RUN_FOLDER] [--model beacon-explorer]
    [--seed 7] [--frames 60] [--snapshots 4] [--repeats 1] [--baseline COMMIT]
"""

import argparse
import importlib.util
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import imageio.v3 as iio
from machine import machine  # benchmarks/machine.py, beside this script

from abm.registry import model_class
from analysis import render as new_render
from analysis.run_folder import load_run, save_run

ROOT = Path(__file__).resolve().parent.parent
#: The last commit of main before the fast renderer.
BASELINE = "13de4e898798f1145c159edec80fccf942aee4a2"
#: Modules renamed since the baseline: old name -> today's (4babe9e: runio -> run_folder).
RENAMED = {"analysis.runio": "analysis.run_folder"}


def old_render(commit: str):
    """``analysis/render.py`` as it was at ``commit``, imported from a temporary copy."""
    source = subprocess.run(
        ["git", "-C", str(ROOT), "show", f"{commit}:analysis/render.py"],
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    folder = Path(tempfile.mkdtemp(prefix="bench-render-"))
    path = folder / "render_baseline.py"
    path.write_text(source)
    for was, now in RENAMED.items():
        if importlib.util.find_spec(was) is None:
            sys.modules[was] = importlib.import_module(now)
    spec = importlib.util.spec_from_file_location("render_baseline", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def time_render(module, run, frames: int, snapshots: int, out: Path) -> tuple[float, float]:
    """Seconds for the snapshots and for the GIF, as ``abm render`` draws them."""
    start = time.perf_counter()
    module.render_snapshots(run, module.snapshot_times(run, snapshots), out)
    middle = time.perf_counter()
    module.render_animation(run, out / "run.gif", frames=frames, progress=False)
    return middle - start, time.perf_counter() - middle


def same_pictures(old: Path, new: Path) -> str:
    """Whether both wrote the same GIF (bytes) and snapshots (pixels differing, per PNG)."""
    gif = (old / "run.gif").read_bytes() == (new / "run.gif").read_bytes()
    differing = [
        int((iio.imread(a) != iio.imread(new / a.name)).any(axis=-1).sum())
        for a in sorted(old.glob("snapshot_*.png"))
    ]
    return f"same GIF bytes: {gif}; snapshot pixels differing: {differing}"


def make_run(model: str, seed: int, folder: Path) -> Path:
    """A run of ``model`` with its default parameters, saved as ``abm run`` saves it."""
    save_run(model_class(model)(seed=seed).run(), folder)
    return folder


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--run", type=Path, help="a run folder (default: make one)")
    parser.add_argument("--model", default="beacon-explorer")
    parser.add_argument("--seed", type=int, default=7)
    parser.add_argument("--frames", type=int, default=60)
    parser.add_argument("--snapshots", type=int, default=4)
    parser.add_argument("--repeats", type=int, default=1)
    parser.add_argument("--baseline", default=BASELINE, help="commit of the old render.py")
    args = parser.parse_args()
    scratch = Path(tempfile.mkdtemp(prefix="bench-render-out-"))
    folder = args.run or make_run(args.model, args.seed, scratch / "run")
    run = load_run(folder)
    old = old_render(args.baseline)
    print(f"machine: {machine()}")
    print(f"run: {folder} ({run.meta['model']}, {len(run.positions)} position rows)")
    print(f"baseline: analysis/render.py at {args.baseline[:12]}; new: {new_render.__file__}")
    pictures = args.frames + args.snapshots
    results = {"old": [], "new": []}
    for repeat in range(args.repeats):
        for name, module in (("old", old), ("new", new_render)):
            out = scratch / f"{name}-{repeat}"
            snaps, gif = time_render(module, run, args.frames, args.snapshots, out)
            results[name].append((snaps, gif))
            load = os.getloadavg()[0]
            print(
                f"{name}: {args.snapshots} snapshots {snaps:.2f} s, {args.frames}-frame GIF "
                f"{gif:.2f} s -> {pictures / (snaps + gif):.2f} pictures/s, GIF "
                f"{args.frames / gif:.2f} frames/s (load average {load:.2f})"
            )
    print(same_pictures(scratch / "old-0", scratch / "new-0"))
    best = {name: min(r, key=sum) for name, r in results.items()}
    total = {name: sum(r) for name, r in best.items()}
    print(
        f"ratio new/old (best of {args.repeats}): pictures/s x{total['old'] / total['new']:.2f}, "
        f"GIF frames/s x{best['old'][1] / best['new'][1]:.2f}, "
        f"snapshots x{best['old'][0] / best['new'][0]:.2f}"
    )


if __name__ == "__main__":
    sys.exit(main())
