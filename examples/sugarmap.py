"""SugarMap (Purohit, Sun, Zhang 2013): location-less coverage of the paper's 5 m x 3 m testbed
by 5 anchors and 2 explorers, beside a random walk and OMSTC on the same arena.

Covers: the anchors' dispersion and landing, 180 s of coverage with RToF signatures and
particle filters, the true coverage beside the brain's estimate (and how wrong the estimate
is), the same run with both baselines, and a PNG of the final scene: the explorers, their
particle clouds, the anchors and the GlobalMap over the truly covered cells. Prints where every
output went.
"""

from pathlib import Path

from abm.draw import save_swarm_png
from models.sugarmap import SugarMapModel

SETUP = {"arena": "testbed", "n_explorers": 2, "horizon": 180.0}
ANCHORS = 5
SEED = 1
OUT = Path("out/sugarmap")


def main() -> None:
    model = SugarMapModel(algorithm="sugarmap", n_anchors=ANCHORS, seed=SEED, **SETUP).run()
    s = model.summary()
    print(f"SugarMap on the testbed, {ANCHORS} anchors, 2 explorers, seed {SEED}:")
    print(f"  anchors landed at     t = {s['t_deploy']:.0f} s (cut-off fired: {s['cutoff_fired']})")
    at90, at180 = s["coverage_90"], s["coverage_180"]
    print(f"  true coverage         {at90:.1f} % at 90 s, {at180:.1f} % at 180 s")
    print(f"  estimated coverage    {s['coverage_est']:.1f} % (GlobalMap >= COVER_TH)")
    print(f"  map error             {s['map_error']:.3f} (mean |GlobalMap - truth| per cell)")
    print(f"  pose error            {s['pose_error']:.2f} m (mean particle to true explorer)")
    print(f"  revisits matched      {s['matches']} ({100 * s['false_match_rate']:.0f} % false)")
    print(f"  overlap               {s['overlap']:.2f} cell entries per covered cell")
    print(f"  wall bumps            {s['wall_collisions']}")
    for algorithm in ("random_walk", "omstc"):
        other = SugarMapModel(algorithm=algorithm, seed=SEED, **SETUP).run().summary()
        print(f"  {algorithm:12s}          {other['coverage_180']:.1f} % at 180 s")
    png = save_swarm_png(model, OUT / "final_swarm.png")
    print(f"\nwrote {png}")


if __name__ == "__main__":
    main()
