"""Which floor-plan rule moves the mixed-world energy effect (24 s vs 6 s launch period)?

Runs the mixed world (medium corridors, 20 robots) at 6 s and 24 s with all five floor-plan
rules on, each one off in turn, and all five off, on fresh seeds, and prints the percent change
of mean total energy from 6 s to 24 s per variant (paper, Sect. 4: -25.3 %). Resumable: each
variant is a sweep folder under OUT.

    python benchmarks/ablate_floorplan_rules.py [--runs 60] [--out out/ablate_floorplan_rules]
"""

import argparse

from analysis.sweep import run_sweep

SEED = 777001
RULES_OFF = {
    "guide_commit": False,
    "report_taken": False,
    "lost_return": False,
    "searched_follows_signal": False,
    "slide_after": None,
}
VARIANTS = {
    "all_on": {},
    **{f"off_{key}": {key: value} for key, value in RULES_OFF.items()},
    "all_off": RULES_OFF,
}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=60, help="runs per condition")
    parser.add_argument("--out", default="out/ablate_floorplan_rules")
    args = parser.parse_args()
    for name, off in VARIANTS.items():
        grid = {"world": ["mixed"], "complexity": ["medium"], "launch_period": [6.0, 24.0]}
        grid.update({key: [value] for key, value in off.items()})
        runs = run_sweep("beacon-explorer", grid, args.runs, SEED, f"{args.out}/{name}")
        ok = runs[runs.status == "ok"]
        energy = ok.groupby("launch_period")["energy_total"].mean()
        change = 100.0 * (energy.loc[24.0] / energy.loc[6.0] - 1.0)
        ends = ok.end_reason.str.split(":").str[0].value_counts().to_dict()
        print(
            f"{name:28s} energy 6 s {energy.loc[6.0]:9.0f} J, 24 s {energy.loc[24.0]:9.0f} J, "
            f"change {change:+6.1f} %, ended {ends}",
            flush=True,
        )
    print(f"wrote {args.out}/")


if __name__ == "__main__":
    main()
