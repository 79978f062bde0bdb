"""Where the open-room energy goes: flight, beacon and ground energy against the launch period.

The paper (Stirling et al. 2010, Sect. 4, Fig. 9) finds medium-density energy convex in the
inter-launch period (an optimum inside 3-12 s) and a 29.9 % flight saving from 3 s to 12 s at
high density. This prints, per density and period, the means of flight time, collisions,
coverage time, the energy components, the flight time per attach (how long an explorer flies
for each beacon placed: queues at the frontier show here) and the share of runs that complete,
so the shape of each curve can be traced to its parts.

Seeds start at 600000 by default, away from every seed the tests use.

Usage: python benchmarks/open_room_energy.py [--seeds 20] [--densities medium high]
       [--periods 3 4 5 6 12] [--set key=value ...]
"""

import argparse
import time

import pandas as pd
from tqdm import tqdm

from abm.pools import process_pool
from models.beacon_explorer.model import BeaconExplorerModel


def one_run(job: tuple[str, float, int, dict]) -> dict:
    density, period, seed, extra = job
    model = BeaconExplorerModel(
        world="open",
        complexity=density,
        launch_period=period,
        seed=seed,
        trace_interval=None,
        **extra,
    )
    model.run()
    s = model.summary()
    events = model.recorder.events()
    attaches = int((events.event == "attach").sum()) - 1  # not the base
    return {
        "density": density,
        "period": period,
        "seed": seed,
        "flight_time": s["flight_time"],
        "collisions": s["collisions"],
        "coverage_time": s["coverage_time"],
        "energy_flight": s["energy_flight"] / 1e3,
        "energy_beacon": s["energy_beacon"] / 1e3,
        "energy_ground": s["energy_ground"] / 1e3,
        "energy_total": s["energy_total"] / 1e3,
        "flight_per_attach": s["flight_time"] / max(attaches, 1),
        "complete": bool(s["complete"]),
    }


def _value(text: str) -> object:
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return {"true": True, "false": False, "none": None}.get(text.lower(), text)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, default=20)
    parser.add_argument("--densities", nargs="+", default=["medium", "high"])
    parser.add_argument("--periods", type=float, nargs="+", default=[3.0, 4.0, 5.0, 6.0, 12.0])
    parser.add_argument("--first-seed", type=int, default=600_000)
    parser.add_argument("--set", nargs="*", default=[], help="model keywords, key=value")
    args = parser.parse_args()
    extra = {k: _value(v) for k, v in (s.split("=", 1) for s in args.set)}
    jobs = [
        (d, p, args.first_seed + i, extra)
        for d in args.densities
        for p in args.periods
        for i in range(args.seeds)
    ]
    start = time.perf_counter()
    with process_pool() as pool:
        rows = list(tqdm(pool.map(one_run, jobs), total=len(jobs), desc="open-room runs"))
    print(f"{len(rows)} runs, {time.perf_counter() - start:.0f} s wall, model keywords {extra}")
    table = pd.DataFrame(rows).groupby(["density", "period"]).mean(numeric_only=True)
    table = table.drop(columns="seed")
    with pd.option_context(
        "display.width", 250, "display.max_columns", None, "display.precision", 2
    ):
        print(table)
    for density in args.densities:
        t = table.loc[density]
        lo, hi = t.index.min(), t.index.max()

        def change(column: str) -> float:
            return 100 * (t[column][hi] / t[column][lo] - 1)  # noqa: B023 (used at once)

        print(
            f"{density}: {hi:g} s vs {lo:g} s flight {change('flight_time'):+.1f} %, energy "
            f"{change('energy_total'):+.1f} %, coverage time {change('coverage_time'):+.1f} %; "
            f"lowest energy at {t.energy_total.idxmin():g} s"
        )


if __name__ == "__main__":
    main()
