"""``abm report``: a self-contained HTML reproduction report of a sweep folder."""

import argparse
from pathlib import Path

VERB = "report"
HELP = "write an HTML reproduction report (figures, ANOVA, published vs ours) of a sweep"
EXAMPLE = "abm report out/sweeps/corridor"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Options of ``abm report``."""
    parser.add_argument("sweep", type=Path, help="a sweep folder written by `abm sweep`")
    parser.add_argument(
        "--out", type=Path, default=None, help="HTML file (default: <sweep>/report.html)"
    )


def main(args: argparse.Namespace) -> int:
    """Write the report and print its path."""
    from abm.errors import ConfigError
    from analysis.report import write_report

    if not (args.sweep / "sweep.json").is_file():
        raise ConfigError(
            f"{args.sweep} is not a sweep folder (no sweep.json); run `abm sweep FILE` first"
        )
    path = write_report(args.sweep, args.out)
    print(f"wrote {path}")
    print(f"wrote {path.parent / 'figures'}")
    return 0
