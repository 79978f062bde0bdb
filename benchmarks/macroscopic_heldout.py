"""Held-out checks of the rate-equation macroscopic model on the paper models (issue 29).

For each model with two or more states, runs it with its defaults on FIT fresh seeds, fits
the rate equations (``analysis.macroscopic.fit_rates``), runs HELD more seeds and prints, per
state, the RMSD of the mean count (share of the swarm) and the share of points inside the
90 % band, then the well-mixed verdict and the speed ratio (held-out agent runs' wall time
over the mean-field prediction's, and over the 200-replicate stochastic band's).

    python benchmarks/macroscopic_heldout.py [--fit 4] [--held 2] [MODEL ...]
"""

import argparse
import time

import numpy as np
import pandas as pd

from analysis.macroscopic import check_heldout, collect_runs, fit_rates, well_mixed

SEED = 810900
MODELS = ("beacon-explorer", "stigmergy", "sugarmap", "hierarchy", "tangible-pso")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("models", nargs="*", default=list(MODELS))
    parser.add_argument("--fit", type=int, default=4, help="runs fitted on")
    parser.add_argument("--held", type=int, default=2, help="held-out runs")
    args = parser.parse_args()
    pd.set_option("display.width", 160)
    for name in args.models:
        seeds = range(SEED, SEED + args.fit + args.held)
        start = time.perf_counter()
        logs = collect_runs(name, seeds)
        fitted, held = logs[: args.fit], logs[args.fit :]
        model = fit_rates(fitted)
        checks = check_heldout(model, held, np.random.default_rng(SEED))
        mixing = well_mixed(fitted)
        print(f"== {name}: seeds {seeds.start}-{seeds.stop - 1} (fit on {args.fit}, "
              f"held out {args.held}), N = {checks.swarm_size}")  # fmt: skip
        print(model.table()[["source", "target", "family", "coefficient", "estimate", "se"]]
              .to_string(index=False))  # fmt: skip
        print(checks.table.to_string(index=False, float_format=lambda v: f"{v:.3f}"))
        print(f"worst RMSD {checks.rmsd_max:.3f} of N; band coverage {checks.band_coverage:.3f}")
        if mixing.computable:
            flagged = mixing.table[mixing.table["flagged"]]
            pairs = ", ".join(f"{r.source}->{r.target} vs {r.k} (gap {r.gap:.2f})"
                              for r in flagged.itertuples()) or "none"  # fmt: skip
            print(f"well mixed: {'no' if mixing.flagged else 'yes'} (radius "
                  f"{mixing.radius:.2f} m; flagged: {pairs})")  # fmt: skip
        else:
            print(f"well mixed: cannot be computed ({mixing.reason})")
        total = time.perf_counter() - start
        print(f"speed ratio: {checks.speed_ratio:.0f} x (ODE {checks.ode_seconds:.3f} s), "
              f"{checks.band_speed_ratio:.1f} x (band {checks.band_seconds:.2f} s) vs "
              f"{checks.agent_seconds:.1f} s of agent runs; total {total:.0f} s")  # fmt: skip
        print(flush=True)


if __name__ == "__main__":
    main()
