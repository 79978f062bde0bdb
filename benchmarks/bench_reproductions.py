"""Each model's figure set, timed: the sweeps its README's reproduction commands run, then their
reports (and, for stigmergy, the fit of its Table 1, ``abm fit stigmergy --read``, as its README
does). Target (issue 32): at most 5 minutes per model on 2 cores.

Usage:
    python benchmarks/bench_reproductions.py                          # every model, 2 workers
    python benchmarks/bench_reproductions.py --models sugarmap hierarchy
    python benchmarks/bench_reproductions.py --replications 2         # a quick look

A model's sweeps share one process pool and are fed to it at once (no idle core while one
sweep waits for its last run); runs go through the common sweep runner with the files' own
seeds and replications, so the output is the figure set's data. The runner resumes, so the
folder must be fresh to time the whole set: an ``--out`` that already holds runs is refused.
Prints the machine, its load and its speed (:func:`machine.speed_probe`) before and after each
model, each sweep's runs and when it finished, the reports' time, and each model's total
against the 5-minute target.
"""

import argparse
import contextlib
import sys
import time
from concurrent.futures import ThreadPoolExecutor, as_completed
from pathlib import Path

from abm.pools import process_pool
from analysis.cli import main as abm
from analysis.report import write_report
from analysis.sweep.execute import execute
from analysis.sweep.spec import load_sweep

sys.path.insert(0, str(Path(__file__).resolve().parent))
from machine import load_average, machine, speed_probe  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
TARGET_SECONDS = 300.0

#: Per model, the reports of its README's reproduction commands, each the sweeps it reads
#: (``experiments/<name>.toml``). Beacon/explorer reports one sweep at a time, as its README
#: says (hover's reference condition differs from the others').
FIGURE_SETS: dict[str, list[list[str]]] = {
    "beacon-explorer": [["corridor"], ["open"], ["mixed"], ["hover"]],
    "stigmergy": [["stigmergy_table1"]],
    "sugarmap": [
        ["sugarmap_fig15", "sugarmap_fig5", "sugarmap_fig6", "sugarmap_fig7"],
        ["sugarmap_fig11"],
    ],
    "tangible-pso": [["tangible_pso_table1"], ["tangible_pso_fig9"], ["tangible_pso_fig10"]],
    "hierarchy": [
        ["hierarchy_scaling", "hierarchy_equal_scouts"],
        ["hierarchy_no_waves"],
    ],
}
#: Models whose figure set ends with the macroscopic fit of one of its sweeps.
FITS = {"stigmergy": "stigmergy_table1"}


def _timed_sweep(sweep, folder: Path, pool) -> tuple:
    """Run one sweep on the shared pool: its runs and the seconds until it finished."""
    t0 = time.perf_counter()
    runs = execute(sweep, folder, executor=pool, progress=False)
    return runs, time.perf_counter() - t0


def run_together(sweeps: list, folders: list[Path], workers: int) -> tuple[int, float]:
    """Run ``sweeps`` (into ``folders``) on one pool of ``workers`` processes, fed by all of
    them at once: no pool start-up per sweep and no idle core while one sweep waits for its
    last run. Prints each sweep's runs as it finishes; returns the runs and their run time (s).
    """
    total_runs, run_seconds = 0, 0.0
    with process_pool(workers) as pool, ThreadPoolExecutor(len(sweeps)) as feeders:
        jobs = {
            feeders.submit(_timed_sweep, sweep, folder, pool): sweep.name
            for sweep, folder in zip(sweeps, folders, strict=True)
        }
        for job in as_completed(jobs):
            runs, seconds = job.result()
            ok = int((runs["status"] == "ok").sum())
            total_runs += len(runs)
            run_seconds += float(runs["wall_time"].sum()) if "wall_time" in runs else 0.0
            print(f"  {jobs[job]:24s} {ok:5d}/{len(runs):<5d} runs ok, done after {seconds:6.1f} s")
    return total_runs, run_seconds


def figure_set(model: str, out: Path, workers: int, replications: int | None) -> float:
    """Run and report one model's figure set; print its timings; return its wall seconds."""
    names = [name for group in FIGURE_SETS[model] for name in group]
    sweeps = [load_sweep(ROOT / "experiments" / f"{name}.toml", replications) for name in names]
    folders = {sweep.name: out / model / sweep.name for sweep in sweeps}
    print(f"\n{model}: {load_average()}; {speed_probe()}", flush=True)
    start = time.perf_counter()
    _, run_seconds = run_together(sweeps, list(folders.values()), workers)
    sweeps_seconds = time.perf_counter() - start
    for group in FIGURE_SETS[model]:
        report = write_report([folders[name] for name in group])  # in its first folder
        print(f"  report {report}")
    if model in FITS:
        fitted = out / model / "fit"
        fitted.mkdir()
        with open(fitted / "fit.log", "w") as log, contextlib.redirect_stdout(log):
            abm(["fit", model, "--read", str(folders[FITS[model]]), "--out", str(fitted)])
        print(f"  fit {fitted / 'fit_report.html'}")
    total = time.perf_counter() - start
    verdict = "within" if total <= TARGET_SECONDS else "over"
    if replications is not None:
        verdict = f"--replications {replications}: not the figure set, not judged against"
    after = "reports and fit" if model in FITS else "reports"
    print(
        f"  {model}: sweeps {sweeps_seconds:.1f} s ({run_seconds:.0f} s of run time on "
        f"{workers} workers), {after} {total - sweeps_seconds:.1f} s, total {total:.1f} s "
        f"({total / 60:.1f} min): {verdict} the {TARGET_SECONDS / 60:.0f}-minute target; "
        f"{load_average()}; {speed_probe()}",
        flush=True,
    )
    return total


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--models", nargs="+", choices=sorted(FIGURE_SETS), default=None)
    parser.add_argument("--out", type=Path, default=Path("out/reproductions"))
    parser.add_argument("--workers", type=int, default=2, help="processes [2]")
    parser.add_argument("--replications", type=int, default=None, help="override the files'")
    args = parser.parse_args()
    if args.workers < 1:
        parser.error(f"--workers must be 1 or more processes, got {args.workers}")
    if args.replications is not None and args.replications < 1:
        parser.error(f"--replications must be 1 or more, got {args.replications}")
    models = args.models or list(FIGURE_SETS)
    held = [m for m in models if (args.out / m).exists() and any((args.out / m).iterdir())]
    if held:
        parser.error(
            f"{args.out} already holds runs of {', '.join(held)}: the runner would skip them; "
            "give a fresh --out to time the whole figure set"
        )
    print(f"{machine()}; {args.workers} workers")
    totals = {m: figure_set(m, args.out, args.workers, args.replications) for m in models}
    print("\nmodel             wall (min)  target 5 min")
    for model, seconds in totals.items():
        met = "met" if seconds <= TARGET_SECONDS else "not met"
        met = "not judged (--replications)" if args.replications is not None else met
        print(f"{model:17s} {seconds / 60:10.1f}  {met}")


if __name__ == "__main__":
    main()
