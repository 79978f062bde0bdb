"""``abm run MODEL``: one run of any registered model; prints its summary, writes a PNG of the
final state and the run folder ``abm render`` draws from.

Every field of the model's params is a flag (``abm run MODEL --help`` lists them).
"""

import argparse
from pathlib import Path

VERB = "run"
HELP = "run one simulation of a model, print its summary, save a PNG and the run folder"
EXAMPLE = "abm run beacon-explorer --world corridor --complexity high --launch-period 6 --seed 1"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Options of ``abm run``: the model, then its own flags (parsed once the model is known)."""
    from abm.registry import model_names

    parser.add_argument(
        "model", nargs="?", help=f"the model: {', '.join(model_names())} (or module:Class)"
    )
    parser.add_argument(
        "options",
        nargs=argparse.REMAINDER,
        help="--seed N, --out DIR and the model's parameters (see: abm run MODEL --help)",
    )


def model_parser(name: str, model_cls: type) -> argparse.ArgumentParser:
    """The parser of ``abm run NAME ...``: seed, output folder, one flag per parameter."""
    from analysis.cli.flags import add_param_flags

    parser = argparse.ArgumentParser(
        prog=f"abm run {name}",
        description=(model_cls.__doc__ or "").strip().splitlines()[0],
    )
    parser.add_argument("--seed", type=int, default=1, help="the model's seed [1]")
    parser.add_argument("--out", type=Path, default=Path("out/run"), help="output folder [out/run]")
    add_param_flags(parser, model_cls.Params)
    return parser


def main(args: argparse.Namespace) -> int:
    """Build, run, print, save."""
    from abm.draw import save_swarm_png
    from abm.errors import ConfigError
    from abm.registry import model_class, model_names, name_of
    from analysis.cli.flags import given_params
    from analysis.runio import save_run

    if args.model is None:
        raise ConfigError(
            f"name a model: {', '.join(model_names())} (abm run MODEL --help lists its flags)"
        )
    cls = model_class(args.model)
    name = name_of(cls) or args.model
    options = model_parser(name, cls).parse_args(args.options)
    params = given_params(options)
    # `abm render` draws from the sampled positions: sample them even where the model's
    # default (fast sweeps) is not to.
    params.setdefault("trace_interval", cls.Params().trace_interval or 1.0)
    model = cls(seed=options.seed, **params)
    model.run()
    summary = model.summary()
    print(f"{name}, seed {options.seed}:")
    print(format_summary(summary))
    options.out.mkdir(parents=True, exist_ok=True)
    png = save_swarm_png(model, options.out / "final.png", title=_title(name, summary))
    print(f"\nwrote {png}")
    for path in save_run(model, options.out):
        print(f"wrote {path}")
    print(f"next: abm render {options.out}")
    return 0


def _title(name: str, summary: dict) -> str:
    parts = [name, f"t = {summary['time']:.0f} s ({summary['end_reason'].split(':')[0]})"]
    if "coverage_area" in summary:
        parts.append(f"coverage {summary['coverage_area']:.1f} %")
    return ", ".join(parts)


def unit_of(key: str) -> str:
    """The unit of a summary key as the framework (``abm.units.COMMON``) or the model
    (``SUMMARY_UNITS``) declares it; nothing for names, identifiers, true/false keys, counts
    and plain numbers.
    """
    from abm.units import unit_of as declared

    unit = declared(key)
    return "" if unit in ("text", "id", "flag", "count", "1") else unit


def format_summary(summary: dict) -> str:
    """A two-column table of a run's summary, with units."""
    lines = []
    for key, value in summary.items():
        shown = f"{value:,.1f}" if isinstance(value, float) else str(value)
        lines.append(f"  {key:<18} {shown:>14} {unit_of(key)}".rstrip())
    return "\n".join(lines)
