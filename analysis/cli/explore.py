"""``abm explore``: run a sweep file with a ``[design]`` and report its sensitivity indices.

A design lives in a sweep file (beside ``model``, ``seed`` and the fixed settings in
``[grid]``), so this verb takes that file, as ``abm sweep`` does, rather than a model name and
a second file that could name another model: it runs the design's sample as a sweep (same
executors, progress bar, output-folder rules, resume) and then writes the report, whose
sensitivity part ranks the parameters. ``abm sweep`` runs the same file without the report.
"""

import argparse
import sys
from pathlib import Path

VERB = "explore"
HELP = "run a sweep file's [design] (Sobol', Morris, LHS) and report the sensitivity indices"
EXAMPLE = "abm explore experiments/morris_beacon_explorer.toml"

#: Parameters named in the ranking printed at the end.
SHOWN = 10


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Options of ``abm explore``: a sweep file with a design, and where its runs execute."""
    from analysis.cli.sweep import add_execution_options

    parser.add_argument("file", type=Path, help="sweep file with a [design] table")
    add_execution_options(parser)


def main(args: argparse.Namespace) -> int:
    """Load and check the file (before any run), run what is missing, report, print the ranking."""
    from abm.errors import ConfigError
    from analysis.cli.sweep import run_sweep
    from analysis.report import write_report
    from analysis.sweep import load_sweep

    sweep = load_sweep(args.file)
    if sweep.design is None:
        raise ConfigError(
            f"{args.file} has no [design] table (kind, n, parameters); `abm sweep` runs grids"
        )
    out = args.out if args.out is not None else Path("out/sweeps") / sweep.name
    design = sweep.design
    print(
        f"explore {sweep.name!r}: {design.kind} design over {len(design.parameters)} "
        f"parameters, n = {design.n}: {design.n_rows} sample rows, {sweep.n_points} distinct "
        f"points x {sweep.replications} replications = {sweep.n_runs} runs, design seed "
        f"{design.seed}, sweep seed {sweep.seed}, executor {args.executor}",
        file=sys.stderr,
    )
    _, n_failed = run_sweep(sweep, out, args)
    path = write_report(out)
    _print_ranking(path.with_name("sensitivity.csv"), design.kind)
    print(f"wrote {out}")
    print(f"wrote {path}")
    return 1 if n_failed else 0


def _print_ranking(csv: Path, kind: str) -> None:
    """The ranking the report draws, as text (or why there is none)."""
    import pandas as pd

    from analysis.sensitivity import HEADLINE, ranking, unranked

    if not csv.exists():
        print("no sensitivity indices (see the report's notes)")
        return
    frame = pd.read_csv(csv)
    table = ranking(frame, kind)
    means = table.mean(axis=1)
    echoes = unranked(frame)
    left_out = f"; not ranked, set by one parameter alone: {', '.join(echoes)}" if echoes else ""
    print(
        f"ranking by {HEADLINE[kind]} (mean over {table.shape[1]} metrics, 1 = largest{left_out}):"
    )
    for rank, (name, value) in enumerate(means.head(SHOWN).items(), start=1):
        print(f"  {rank:2d}. {name} {value:.3f}")
    if len(means) > SHOWN:
        print(f"  ... {len(means) - SHOWN} more in {csv}")
    print(f"wrote {csv}")
