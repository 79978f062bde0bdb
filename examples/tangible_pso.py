"""Tangible PSO (Saska et al. 2016): a 3-MAV swarm deployed past a no-fly zone to two areas of
interest, with and without motion planning inside the optimiser, then the paper's 6-MAV run
on an open plane.

Covers: one Table-1 run per variant (40 particles, 70 iterations, k = 1 localised neighbour):
the best cost of eq. 1, whether the feasibility check stopped MAVs at the zone (a "collision
run"), the deadlock readings and goal swapping; one Fig. 9 run (6 MAVs, k = 2, 40 x 20) with
the groups its best swarm formed; PNGs of the final scenes (AoI map, zone, every virtual MAV,
the best swarm with its localisation links and trajectories) and of the convergence. Prints
where every output went.
"""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from abm.draw import save_swarm_png  # noqa: E402
from models.tangible_pso import TangiblePSOModel  # noqa: E402

TABLE1 = {"scenario": "nofly", "n_mavs": 3, "neighbours": 1, "particles": 40, "iterations": 70}
FIG9 = {"scenario": "open", "n_mavs": 6, "neighbours": 2, "particles": 40, "iterations": 20}
SEED = 1
OUT = Path("out/tangible_pso")


def main() -> None:
    runs = {}
    for mp in (False, True):
        model = TangiblePSOModel(motion_planning=mp, seed=SEED, **TABLE1).run()
        s = model.summary()
        runs["with MP" if mp else "without MP"] = model
        print(f"Table 1 set-up, k = 1, {'with' if mp else 'without'} motion planning, seed {SEED}:")
        print(f"  best cost           {s['best_cost']:.2f} of {s['initial_cost']:.0f} "
              f"(found at iteration {s['best_iteration']})")  # fmt: skip
        print(f"  collision run       {s['collision']} ({s['zone_stops']} swarm moves stopped "
              f"at the zone; {s['proposals_in_zone']} proposals shifted out of it)")  # fmt: skip
        print(f"  deadlock run        {s['deadlock']} (share of particles at the zone, worst of "
              f"the last 10 iterations: {s['zone_pressed_min']:.2f})")  # fmt: skip
        if mp:
            print(f"  goal swapping       {s['swap_resolved']} of {s['swap_conflicts']} mutual "
                  f"path collisions resolved")  # fmt: skip
        print(f"  flight time         {s['time']:.0f} s simulated; best swarm feasible: "
              f"{s['best_feasible']}")  # fmt: skip
    fig9 = TangiblePSOModel(seed=SEED, **FIG9).run()
    s = fig9.summary()
    print(f"Fig. 9 set-up, 6 MAVs, k = 2, seed {SEED}:")
    print(f"  best cost           {s['best_cost']:.2f} of {s['initial_cost']:.0f} "
          f"(found at iteration {s['best_iteration']})")  # fmt: skip
    print(f"  groups              {s['groups']} (localisation-linked groups of the best swarm)")
    written = []
    for label, model in {**runs, "fig9": fig9}.items():
        name = label.replace(" ", "_").lower()
        written.append(save_swarm_png(model, OUT / f"{name}.png", f"tangible PSO: {label}"))
    fig, ax = plt.subplots(figsize=(6, 4))
    for label, model in {**runs, "Fig. 9": fig9}.items():
        curve = model.samples()
        ax.plot(curve["iteration"], curve["best_cost_ratio"], label=label)
    ax.set(xlabel="PSO iteration", ylabel="best cost / cost at the start", ylim=(0, 1.05))
    ax.legend()
    fig.tight_layout()
    fig.savefig(OUT / "convergence.png", dpi=110)
    plt.close(fig)
    written.append(OUT / "convergence.png")
    print()
    for path in written:
        print(f"wrote {path}")


if __name__ == "__main__":
    main()
