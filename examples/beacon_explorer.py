"""Main demo: one beacon/explorer search (Stirling et al. 2010) on a generated high-complexity
corridor world.

Covers: building a model from plain keyword arguments, running it to the end of the search,
the summary table, a PNG of the final swarm (beacons with their desired directions, comm
links, covered area), and an animated GIF of the whole run rendered afterwards from the saved
run (no re-run). Prints where every output went.
"""

from pathlib import Path

from abm.draw import save_swarm_png
from analysis.cli.run import format_summary
from analysis.render import render_animation
from analysis.run_folder import load_run, save_run
from models.beacon_explorer import BeaconExplorerModel

WORLD = "corridor"  # corridor | open | mixed
COMPLEXITY = "high"  # branching level of the corridors
LAUNCH_PERIOD = 6.0  # s between two take-offs
SEED = 1
OUT = Path("out/demo")


def main() -> None:
    model = BeaconExplorerModel(
        world=WORLD, complexity=COMPLEXITY, launch_period=LAUNCH_PERIOD, seed=SEED
    )
    model.run()
    summary = model.summary()
    print(f"Beacon/explorer search, {WORLD} world ({COMPLEXITY}), period {LAUNCH_PERIOD:g} s:")
    print(format_summary(summary))
    png = save_swarm_png(
        model,
        OUT / "final_swarm.png",
        title=(
            f"{WORLD} ({COMPLEXITY}), t = {summary['time']:.0f} s, "
            f"coverage {summary['coverage_area']:.1f} %"
        ),
    )
    print(f"\nwrote {png}")
    for path in save_run(model, OUT / "run"):
        print(f"wrote {path}")
    gif = render_animation(load_run(OUT / "run"), OUT / "run.gif", frames=40, progress=False)
    print(f"wrote {gif}  (re-render any run folder with: abm render {OUT / 'run'})")


if __name__ == "__main__":
    main()
