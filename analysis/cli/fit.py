"""``abm fit MODEL``: agent runs -> a macroscopic model -> its report.

A model that declares ``MACRO`` gets the wander/beacon recurrence fitted to its two counted
states (one HTML report); any other model with two or more states, or any model with
``--rates``, gets rate equations derived from its own event log, fitted on some seeds and
checked on others (:mod:`analysis.rate_fit`).
"""

import argparse
import json
import os
import time
from pathlib import Path

VERB = "fit"
HELP = "fit a macroscopic model: the recurrence a model declares, or rate equations from its log"
EXAMPLE = "abm fit stigmergy --grid map=hall100,divided --grid pheromone_radius=20,30,40 --runs 4"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Options of ``abm fit``."""
    from abm.registry import model_names
    from analysis.cli.flags import seed_argument

    parser.add_argument("model", help=f"the model: {', '.join(model_names())} (or module:Class)")
    parser.add_argument(
        "--grid",
        action="append",
        default=[],
        metavar="NAME=V1,V2",
        help="a parameter and its values (repeatable); one fitted curve per grid point",
    )
    parser.add_argument(
        "--set",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="a parameter held at one value in every run (repeatable)",
    )
    parser.add_argument("--runs", type=int, default=5, help="runs per grid point (fitted) [5]")
    parser.add_argument(
        "--rates",
        action="store_true",
        help="fit rate equations from the event log even where the model declares MACRO",
    )
    parser.add_argument(
        "--held", type=int, default=3, help="rate equations: held-out runs that check them [3]"
    )
    parser.add_argument(
        "--held-points",
        type=int,
        default=1,
        help="rate equations with --grid: interior grid points held out of the fit and "
        "predicted [1]",
    )
    parser.add_argument("--seed", type=seed_argument, default=0, help="the sweep seed [0]")
    parser.add_argument(
        "--workers", type=int, default=min(2, os.cpu_count() or 1), help="local processes"
    )
    parser.add_argument(
        "--read",
        type=Path,
        default=None,
        help="fit the runs of this sweep folder (kept with time series) instead of running; "
        "with rate equations, its first --runs runs per condition fit and the rest check",
    )
    parser.add_argument("--out", type=Path, default=None, help="output folder [out/fit/MODEL]")


def main(args: argparse.Namespace) -> int:
    """Run (or read), fit, write the report."""
    import pandas as pd

    from abm.errors import ConfigError
    from abm.registry import model_class, name_of
    from analysis.cli.flags import parse_assignment
    from analysis.fit import (
        analyse,
        fit_runs,
        macro_spec,
        methods,
        rate_legend,
        read_runs,
        speak,
        write_fit_report,
    )

    cls = model_class(args.model)
    name = name_of(cls) or args.model
    if args.rates or cls.MACRO is None:
        return _rates(args, cls, name)
    spec = macro_spec(cls)
    if args.runs < 1:
        raise ConfigError(f"--runs must be at least 1, got {args.runs}")
    out = args.out or Path("out/fit") / name
    start = time.perf_counter()
    if args.read is not None:
        if args.grid or args.set:
            raise ConfigError("--read fits the runs already in a folder: drop --grid and --set")
        summaries, counts, conditions = read_runs(args.read)
        source = f"runs read from {args.read}"
    else:
        grid = dict(parse_assignment(cls.Params, text, many=True) for text in args.grid)
        grid.update(parse_assignment(cls.Params, text) for text in args.set)
        if not grid:
            grid = {"time_limit": [cls.Params().time_limit]}
        summaries, counts, conditions = fit_runs(
            cls, grid, args.runs, out, seed=args.seed, workers=args.workers
        )
        source = f"runs in {out} (resumable: run again to add or finish runs)"
    logs = _logs_by_condition(args.read or out, summaries, conditions)
    elapsed = time.perf_counter() - start
    result = analyse(summaries, counts, spec, conditions, logs=logs)
    meta = [
        ("model", name),
        ("counted states", f"{spec.moving} and {spec.settled}, step {spec.step:g} s"),
        ("conditions", ", ".join(conditions) or "one"),
        ("runs", f"{len(summaries)}; {source}"),
        ("wall time", _wall_time(elapsed, None if args.read else args.workers)),
    ]
    report = write_fit_report(result, summaries, spec, out, meta, conditions)
    table = result["table"]
    shown = [c for c in ("condition", "runs", "w", "b", "w_hat", "b_hat", "t", "a0", "alpha6",
                         "rmsd_w", "rmsd_b", "rmsd_w_reg", "rmsd_b_reg", "rmsd_w_fit",
                         "rmsd_b_fit", "rmsd_w_rates", "rmsd_b_rates") if c in table]  # fmt: skip
    print(speak(table[shown], spec).to_string(index=False, float_format=lambda v: f"{v:.3g}"))
    print("", *rate_legend(spec), sep="\n  ")
    names = spec.names()
    print("\nmean RMSD over conditions, by fitting method (std in brackets):")
    for row in methods(table, spec).to_dict("records"):
        n = "" if pd.isna(row["conditions"]) else f"{row['conditions']:.0f} conditions, "
        print(
            f"  {names['w']} {row['rmsd_w']:.3g} ({row['rmsd_w_std']:.3g})  {names['b']} "
            f"{row['rmsd_b']:.3g} ({row['rmsd_b_std']:.3g})  [{n}{row['method']}]"
        )
    (out / "fit.json").write_text(
        json.dumps({"model": name, "conditions": conditions, "runs": len(summaries)}, indent=2)
    )
    print(f"\nwrote {report}\nwrote {out / 'runs.csv'}\nwrote {out / 'fit.json'}")
    return 0


def _logs_by_condition(folder: Path, summaries, conditions: list[str]) -> dict | None:
    """The run logs of the runs in ``summaries``, keyed by their condition's values (for the
    rate equations beside the recurrence), or None for a sweep that kept no state changes.
    """
    from abm.errors import ConfigError
    from analysis.macroscopic.sweep_logs import sweep_logs

    try:
        found = sweep_logs(folder)
    except ConfigError as exc:
        print(f"rate equations left out: {exc}")
        return None
    wanted = set(summaries["run_id"])
    out = {}
    for point, logs, ids in zip(found.points, found.logs, found.run_ids, strict=True):
        kept = [log for log, rid in zip(logs, ids, strict=True) if rid in wanted]
        if kept:
            out[tuple(point.get(k) for k in conditions)] = kept
    return out


def _rates(args: argparse.Namespace, cls: type, name: str) -> int:
    """The rate equations of one condition (``--set``), fitted and checked on held-out seeds."""
    from abm.errors import ConfigError
    from analysis.cli.flags import parse_assignment
    from analysis.rate_fit import fit_rate_equations, summary_lines, write_rate_fit

    out = args.out or Path("out/fit") / name
    if args.read is not None:
        if args.grid or args.set:
            raise ConfigError("--read fits the runs already in a folder: drop --grid and --set")
        return _rates_read(args, cls, name, out)
    params = {k: v[0] for k, v in (parse_assignment(cls.Params, text) for text in args.set)}
    if args.grid:
        return _rates_across(args, cls, name, params, out)
    start = time.perf_counter()
    result = fit_rate_equations(cls, params, args.seed, args.runs, args.held, args.workers)
    title = f"{name}: {args.runs} runs fitted, {args.held} held out (seeds from {args.seed})"
    paths = write_rate_fit(result, out, title)
    _print_fit(summary_lines(result), time.perf_counter() - start, args.workers, paths)
    return 0


def _rates_across(args: argparse.Namespace, cls: type, name: str, fixed: dict, out: Path) -> int:
    """Rate equations across the grid: fitted on most points, predicting the held-out ones."""
    from abm.errors import ConfigError
    from analysis.cli.flags import parse_assignment
    from analysis.rate_across import fit_rates_across, summary_lines, write_across

    grid = dict(parse_assignment(cls.Params, text, many=True) for text in args.grid)
    both = sorted(set(grid) & set(fixed))
    if both:
        raise ConfigError(f"{', '.join(both)}: both swept (--grid) and fixed (--set); pick one")
    start = time.perf_counter()
    result = fit_rates_across(
        cls, grid, fixed, args.seed, args.runs, args.held, args.held_points, args.workers
    )
    title = (
        f"{name}: rates across {', '.join(grid)}; {args.runs} runs fitted and {args.held} held "
        f"out per fitted point (seeds from {args.seed})"
    )
    paths = write_across(result, out, title)
    _print_fit(summary_lines(result), time.perf_counter() - start, args.workers, paths)
    return 0


def _rates_read(args: argparse.Namespace, cls: type, name: str, out: Path) -> int:
    """Rate equations fitted to a sweep's runs: one condition fitted on its first ``--runs``
    runs and checked on the rest; several fitted across, interior points held out.
    """
    from abm.errors import ConfigError
    from analysis.macroscopic import check_states
    from analysis.macroscopic.sweep_logs import sweep_logs
    from analysis.rate_across import fit_grid, held_out_points, write_across
    from analysis.rate_across import summary_lines as across_lines
    from analysis.rate_fit import fit_logs, summary_lines, write_rate_fit

    check_states(cls.STATES, cls.__name__)
    if args.runs < 2:
        raise ConfigError(f"--runs must be at least 2 to fit rates, got {args.runs}")
    start = time.perf_counter()
    found = sweep_logs(args.read)
    if found.target != f"{cls.__module__}:{cls.__qualname__}":
        raise ConfigError(f"{args.read} holds runs of {found.target}, not of {name}")
    if not found.grid:
        logs, seeds = found.logs[0], found.seeds[0]
        if len(logs) <= args.runs:
            raise ConfigError(
                f"{args.read} has {len(logs)} runs: --runs {args.runs} leaves none to check on"
            )
        result = fit_logs(logs[: args.runs], logs[args.runs :], seeds[: args.runs],
                          seeds[args.runs :], args.seed)  # fmt: skip
        title = f"{name}: runs of {args.read}, {args.runs} fitted, {len(logs) - args.runs} held out"
        paths = write_rate_fit(result, out, title)
        lines = summary_lines(result)
    else:
        held = held_out_points(found.points, args.held_points)
        result = fit_grid(found.points, found.logs, found.seeds, list(found.grid), held,
                          args.runs, args.seed)  # fmt: skip
        title = f"{name}: runs of {args.read}, rates across {', '.join(found.grid)}"
        paths = write_across(result, out, title)
        lines = across_lines(result)
    _print_fit(lines, time.perf_counter() - start, None, paths)
    return 0


def _print_fit(lines: list[str], seconds: float, workers: int | None, paths: list[Path]) -> None:
    """What a rate-equation fit prints: its summary, its wall time, the files it wrote."""
    print(*lines, sep="\n")
    print(f"wall time {_wall_time(seconds, workers)}")
    print("", *(f"wrote {p}" for p in paths), sep="\n")


def _wall_time(seconds: float, workers: int | None) -> str:
    """The wall time, with the local processes that ran the runs (None: runs were read)."""
    if workers is None:
        return f"{seconds:.0f} s (runs read, not run)"
    return f"{seconds:.0f} s with {workers} worker{'' if workers == 1 else 's'}"
