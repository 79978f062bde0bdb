"""The flocking model of the ABMFrameworksComparison suite (boids on a periodic square), in
its small and large cases.

Covers: a seeded run of each case (construction and exactly 100 update steps, every bird
updated in turn in a new random order), how ordered the flock became (polarisation
|mean unit velocity| and neighbours per bird, at the start and after 100 steps), and a PNG of
each final flock with every bird's heading. The timing against Mesa is
``benchmarks/bench_flocking.py``. Prints where every output went.
"""

from pathlib import Path

from abm.draw import save_swarm_png
from models.flocking import LARGE, SMALL, FlockingModel

CASES = {"small": SMALL, "large": LARGE}  # birds, side of the square (m), visual distance (m)
SEED = 1
OUT = Path("out/flocking")


def main() -> None:
    pngs = []
    for name, case in CASES.items():
        model = FlockingModel(seed=SEED, **case)
        start = model.summary()["polarisation"]
        model.run()
        s = model.summary()
        print(
            f"Flocking, {name} case: {case['birds']} birds, {case['extent']:g} m x "
            f"{case['extent']:g} m, visual distance {case['visual_distance']:g} m, seed {SEED}:"
        )
        print(f"  ended by       {s['end_reason']} at t = {s['time']:.0f} s")
        print(f"  polarisation   {start:.3f} at the start, {s['polarisation']:.3f} after")
        print(f"  neighbours     {s['mean_neighbours']:.2f} per bird at the last step")
        title = f"{name} case after {s['updates']} steps"
        pngs.append(save_swarm_png(model, OUT / f"{name}_flock.png", title=title))
    print()
    for png in pngs:
        print(f"wrote {png}")


if __name__ == "__main__":
    main()
