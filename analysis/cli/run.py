"""``abm run``: one run of a model; prints its summary, writes a PNG and what render needs."""

import argparse
from pathlib import Path

VERB = "run"
HELP = "run one simulation, print its summary, save a snapshot PNG and its event log"
EXAMPLE = "abm run beacon-explorer --world corridor --complexity high --launch-period 6 --seed 1"

MODELS = ("beacon-explorer",)


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Options of ``abm run``."""
    parser.add_argument("model", nargs="?", default="beacon-explorer", choices=MODELS)
    parser.add_argument("--world", default="corridor", help="corridor | open | mixed | a map file")
    parser.add_argument("--complexity", default="high", choices=("low", "medium", "high"))
    parser.add_argument("--launch-period", type=float, default=6.0, help="inter-launch period (s)")
    parser.add_argument("--n-robots", type=int, default=None, help="default: the paper's size")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--hover-beacons", action="store_true")
    parser.add_argument("--time-limit", type=float, default=3600.0, help="(s)")
    parser.add_argument(
        "--battery-capacity",
        type=float,
        default=None,
        help="charge of each explorer's battery (J); default: unlimited, as in the paper",
    )
    parser.add_argument("--out", type=Path, default=Path("out/run"), help="output folder")


def main(args: argparse.Namespace) -> int:
    """Run, print, save."""
    from abm.draw import save_swarm_png
    from models.beacon_explorer import BeaconExplorerModel

    model = BeaconExplorerModel(
        world=args.world,
        complexity=args.complexity,
        n_robots=args.n_robots,
        launch_period=args.launch_period,
        seed=args.seed,
        hover_beacons=args.hover_beacons,
        time_limit=args.time_limit,
        battery_capacity=args.battery_capacity,
    )
    model.run()
    summary = model.summary()
    print(format_summary(summary))
    args.out.mkdir(parents=True, exist_ok=True)
    png = save_swarm_png(model, args.out / "final.png", title=_title(summary))
    from analysis.runio import save_run

    print(f"\nwrote {png}")
    for path in save_run(model, args.out):
        print(f"wrote {path}")
    return 0


def _title(summary: dict) -> str:
    return (
        f"{summary['world']} ({summary['complexity']}), period {summary['launch_period']:g} s, "
        f"seed {summary['seed']}: t = {summary['coverage_time']:.0f} s, "
        f"coverage {summary['coverage_area']:.1f} %"
    )


def format_summary(summary: dict) -> str:
    """A two-column table of a run's summary, with units."""
    units = {
        "coverage_time": "s",
        "coverage_area": "%",
        "flight_time": "s",
        "energy_flight": "J",
        "energy_beacon": "J",
        "energy_ground": "J",
        "energy_total": "J",
        "launch_period": "s",
    }
    lines = []
    for key, value in summary.items():
        shown = f"{value:,.1f}" if isinstance(value, float) else str(value)
        unit = units.get(key, "")
        lines.append(f"  {key:<18} {shown:>14} {unit}")
    return "\n".join(lines)
