"""``abm calibrate MODEL``: the values of free parameters that make a model match measurements.

Every input is checked before any run (priors against the model's ``Params``, the target's
columns, spreads and metrics against one dry build's summary, the output folder); then ABC-SMC
(:mod:`analysis.calibrate`) runs, resumably, and the posterior, its predictive check against
the target and a held-out check are written beside pyABC's database.
"""

import argparse
import importlib.util
import json
import os
import sys
import time
from pathlib import Path

VERB = "calibrate"
HELP = "calibrate free parameters against measured numbers (ABC-SMC, pyABC)"
EXAMPLE = (
    "abm calibrate stigmergy --target measured.csv --free pheromone_radius=10:40 --out out/cal"
)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Options of ``abm calibrate``."""
    from abm.registry import model_names
    from analysis.cli.flags import seed_argument

    parser.add_argument("model", help=f"the model: {', '.join(model_names())} (or module:Class)")
    parser.add_argument(
        "--target",
        required=True,
        help="CSV with columns metric, value, sd (and parameter columns fixing each row's "
        "condition), or 'published' for the model's published levels with a spread",
    )
    parser.add_argument(
        "--free",
        action="append",
        default=[],
        required=True,
        metavar="NAME=LOW:HIGH",
        help="a calibrated parameter and its uniform prior (NAME=log:LOW:HIGH: log-uniform)",
    )
    parser.add_argument(
        "--set", action="append", default=[], metavar="NAME=VALUE", help="a fixed parameter"
    )
    parser.add_argument("--out", type=Path, required=True, help="output folder (resumable)")
    parser.add_argument("--populations", type=int, default=8, help="population budget [8]")
    parser.add_argument("--population-size", type=int, default=100, help="particles [100]")
    parser.add_argument(
        "--epsilon", type=float, default=0.5, help="stop at this distance (in target sds) [0.5]"
    )
    parser.add_argument("--seed", type=seed_argument, default=0, help="the calibration's seed [0]")
    parser.add_argument(
        "--workers", type=int, default=min(2, os.cpu_count() or 1), help="local processes"
    )
    parser.add_argument("--address", default=None, help="a Dask scheduler's address")
    parser.add_argument(
        "--check-runs", type=int, default=20, help="runs of each predictive/held-out check [20]"
    )
    parser.add_argument(
        "--replicates",
        type=int,
        default=1,
        help="runs per condition and particle, averaged (give the target the spread of such "
        "a mean as its sd) [1]",
    )
    parser.add_argument(
        "--holdout",
        type=Path,
        default=None,
        help="CSV like --target, not fitted: the held-out check compares the posterior "
        "median's runs with it (a condition not in the target)",
    )


def main(args: argparse.Namespace) -> int:
    """Check everything, run ABC-SMC, write the posterior and the checks."""
    from abm.errors import ConfigError
    from abm.registry import model_class, name_of
    from analysis.calibrate import Calibration
    from analysis.calibration_inputs import (
        MANIFEST,
        check_folder,
        check_metrics,
        parse_prior,
        published_target,
        read_target,
    )
    from analysis.cli.flags import parse_assignment
    from analysis.sweep.folder import SweepLock

    cls = model_class(args.model)
    name = name_of(cls) or args.model
    for opt, value, low in (
        ("--populations", args.populations, 1),
        ("--population-size", args.population_size, 2),
        ("--workers", args.workers, 1),
        ("--check-runs", args.check_runs, 2),
        ("--replicates", args.replicates, 1),
    ):
        if value < low:
            raise ConfigError(f"{opt} must be at least {low}, got {value}")  # fmt: skip
    if not args.epsilon >= 0:
        raise ConfigError(f"--epsilon must be >= 0, got {args.epsilon}")
    fixed = {k: v[0] for k, v in (parse_assignment(cls.Params, t) for t in args.set)}
    priors = [parse_prior(cls, text, fixed) for text in args.free]
    names = [p.name for p in priors]
    if len(set(names)) != len(names):
        raise ConfigError(f"--free names a parameter twice: {', '.join(names)}")
    if args.target == "published":
        target = published_target(cls, names)
    else:
        target = read_target(cls, Path(args.target), fixed, names)
    holdout = None if args.holdout is None else read_target(cls, args.holdout, fixed, names)
    check_metrics(cls, target, fixed)
    if holdout is not None:
        check_metrics(cls, holdout, fixed)
    manifest = {
        "model": name,
        "target": target.manifest(),
        "priors": [p.manifest() for p in priors],
        "set": {k: v for k, v in fixed.items()},
        "seed": args.seed,
        "population_size": args.population_size,
        **({"replicates": args.replicates} if args.replicates > 1 else {}),
    }
    if importlib.util.find_spec("pyabc") is None:
        raise ConfigError(
            "pyABC is not installed: run `.venv/bin/pip install -e '.[calibrate]'` (or make venv)"
        )
    resume = check_folder(args.out, manifest)
    print(
        f"calibrate {name}: {len(priors)} free ({', '.join(names)}), target {target.source} "
        f"({len(target.rows)} numbers, {len(target.condition_list())} conditions), "
        f"{'resuming' if resume else 'new'} in {args.out}",
        file=sys.stderr,
    )
    for line in target.skipped:
        print(f"  skipped {line}", file=sys.stderr)
    calib = Calibration(cls, target, tuple(priors), fixed, args.seed, args.replicates)
    with SweepLock(args.out):
        (args.out / MANIFEST).write_text(json.dumps(manifest, indent=2, default=str))
        return _calibrate(args, calib, holdout, resume)


def _calibrate(args: argparse.Namespace, calib, holdout, resume: bool) -> int:
    """ABC-SMC, then the posterior, the predictive check and the held-out check."""
    import numpy as np

    from analysis.calibrate import (
        posterior_figure,
        posterior_table,
        predictive_table,
        run_abc,
        run_at,
    )

    out = args.out
    start = time.perf_counter()
    history = run_abc(
        calib, out, populations=args.populations, population_size=args.population_size,
        epsilon=args.epsilon, workers=args.workers, address=args.address, resume=resume,
    )  # fmt: skip
    pops = history.get_all_populations()
    pops = pops[pops["t"] >= 0]
    last = float(pops["epsilon"].iloc[-1])
    reached = (
        f"the target {args.epsilon:g} reached"
        if last <= args.epsilon
        else f"NOT the target {args.epsilon:g}: the posterior is wider than asked for"
    )
    print(
        f"{history.n_populations} populations, {int(pops['samples'].sum())} model evaluations, "
        f"last epsilon {last:.3g} (target sds; {reached}), "
        f"{time.perf_counter() - start:.0f} s with {args.workers} worker(s)"
    )
    table = posterior_table(history, calib.priors)
    table.to_csv(out / "posterior.csv", index=False)
    figure = posterior_figure(history, calib.priors, table, out / "posterior.png")
    print(table.to_string(index=False, float_format=lambda v: f"{v:.4g}"))

    rng = np.random.default_rng([calib.seed, 1])  # fresh seeds, none used by the ABC runs
    frame, w = history.get_distribution()
    picks = rng.choice(len(frame), size=args.check_runs, p=w / w.sum())
    points = [frame.iloc[i].to_dict() for i in picks]
    seeds = [int(s) for s in rng.integers(2**63, size=args.check_runs)]
    predictive = predictive_table(calib.target, run_at(calib, points, seeds, args.workers))
    predictive.to_csv(out / "predictive.csv", index=False)

    median = dict(zip(table["parameter"], table["median"], strict=True))
    seeds = [int(s) for s in rng.integers(2**63, size=args.check_runs)]
    checked = calib if holdout is None else _with_target(calib, holdout)
    held = predictive_table(
        checked.target, run_at(checked, [median] * args.check_runs, seeds, args.workers)
    )
    held.insert(0, "check", "held-out condition" if holdout is not None else "fresh seeds")
    held.to_csv(out / "heldout.csv", index=False)
    shown = lambda f: f.to_string(index=False, float_format=lambda v: f"{v:.4g}")  # noqa: E731
    print(f"\nposterior predictive ({args.check_runs} posterior draws, fresh seeds):")
    print(shown(predictive))
    print(f"\nheld-out check at the posterior median ({args.check_runs} fresh seeds):")
    print(shown(held))
    if holdout is None:
        print("no condition outside the target was checked (give one with --holdout FILE)")
    for name in ("posterior.csv", figure.name, "predictive.csv", "heldout.csv", "abc.db"):
        print(f"wrote {out / name}")
    return 0


def _with_target(calib, target):
    """The same calibration evaluated on another target's rows."""
    import dataclasses

    return dataclasses.replace(calib, target=target)
