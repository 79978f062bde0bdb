"""``abm report``: a self-contained HTML reproduction report of a sweep folder."""

import argparse
from pathlib import Path

VERB = "report"
HELP = "write an HTML reproduction report (published vs ours, claims, figures, ANOVA) of sweeps"
EXAMPLE = "abm report out/sweeps/corridor"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Options of ``abm report``."""
    parser.add_argument(
        "sweep", type=Path, nargs="+", help="sweep folders written by `abm sweep` (one model)"
    )
    parser.add_argument(
        "--out", type=Path, default=None, help="HTML file (default: <first sweep>/report.html)"
    )


def main(args: argparse.Namespace) -> int:
    """Write the report and print its path."""
    from abm.errors import ConfigError
    from analysis.report import write_report

    for folder in args.sweep:
        if not (folder / "sweep.json").is_file():
            raise ConfigError(
                f"{folder} is not a sweep folder (no sweep.json); run `abm sweep FILE` first"
            )
    if args.out is not None:  # checked before the work: a folder, or a place not writable
        if args.out.is_dir():
            raise ConfigError(f"--out {args.out} is a folder; give the HTML file's path")
        args.out.parent.mkdir(parents=True, exist_ok=True)
    path = write_report(args.sweep, args.out)
    print(f"wrote {path}")
    for table in ("comparison.csv", "statistics.csv"):
        if (path.parent / table).exists():
            print(f"wrote {path.parent / table}")
    for folder in args.sweep:
        print(f"wrote {folder / 'figures'}")
    return 0
