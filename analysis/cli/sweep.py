"""``abm sweep``: run a sweep file (model x parameter grid x replications) to a Parquet dataset."""

import argparse
import sys
import time
from pathlib import Path

VERB = "sweep"
HELP = "run a parameter sweep (TOML file) on local cores or Dask; resumable, results to Parquet"
EXAMPLE = "abm sweep experiments/corridor.toml --executor processes"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Options of ``abm sweep``."""
    from analysis.cli.flags import seed_argument

    parser.add_argument("file", type=Path, help="sweep file, e.g. experiments/corridor.toml")
    add_execution_options(parser)
    parser.add_argument(
        "--replications", type=int, default=None, help="override the file's replications"
    )
    parser.add_argument(
        "--seed",
        type=seed_argument,
        default=None,
        help="override the file's sweep seed, an integer in [0, 2**63 - 1] (per-run seeds are "
        "spawned from it; a folder holding runs of another seed is refused)",
    )


def add_execution_options(parser: argparse.ArgumentParser) -> None:
    """Where a sweep's runs execute and are kept: the options ``abm sweep`` and ``abm
    explore`` share.
    """
    parser.add_argument(
        "--executor",
        default="processes",
        choices=("serial", "processes", "dask"),
        help="where runs execute (default: local processes on all cores)",
    )
    parser.add_argument(
        "--address", default=None, help="Dask scheduler address (default: a LocalCluster)"
    )
    parser.add_argument("--workers", type=int, default=None, help="local workers (default: cores)")
    parser.add_argument(
        "--out",
        type=Path,
        default=None,
        help="dataset folder: new, empty or this sweep's (default: out/sweeps/<name>)",
    )
    parser.add_argument(
        "--no-retry", action="store_true", help="do not re-run runs recorded as failed"
    )


def run_sweep(sweep: object, out: Path, args: argparse.Namespace) -> tuple[object, int]:
    """Run what is missing of ``sweep`` into ``out`` with the execution options, print the
    tally and the wall time; the runs' table and how many failed.
    """
    from analysis.sweep import execute

    start = time.perf_counter()
    df = execute(
        sweep,
        out,
        executor=args.executor,
        address=args.address,
        workers=args.workers,
        retry_failed=not args.no_retry,
    )
    wall = time.perf_counter() - start
    n_failed = int((df["status"] == "failed").sum()) if len(df) else 0
    print(f"{len(df) - n_failed} runs finished, {n_failed} failed, wall time {wall:.1f} s")
    return df, n_failed


def main(args: argparse.Namespace) -> int:
    """Load, validate (before any run), run what is missing, print where it wrote."""
    from analysis.sweep import load_sweep
    from analysis.sweep.execute import DRY_BUILD_POINTS

    sweep = load_sweep(args.file, replications=args.replications, seed=args.seed)
    out = args.out if args.out is not None else Path("out/sweeps") / sweep.name
    print(
        f"sweep {sweep.name!r}: {sweep.n_runs} runs "
        f"({sweep.n_points} grid points x {sweep.replications} replications), "
        f"seed {sweep.seed}, executor {args.executor}",
        file=sys.stderr,
    )
    if sweep.n_points > DRY_BUILD_POINTS:
        print(
            f"every value checked; {DRY_BUILD_POINTS} grid points built before the first run, "
            "the others as their runs start (a bad combination is a recorded failure)",
            file=sys.stderr,
        )
    df, n_failed = run_sweep(sweep, out, args)
    if n_failed:
        first = df.loc[df["status"] == "failed", "error"].iloc[0]
        print(f"first failure: {first} (details in {out / 'failed'})")
    print(f"wrote {out}")
    print(f"next: abm report {out}")
    return 1 if n_failed else 0
