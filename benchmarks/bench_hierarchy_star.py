"""Star against the hierarchy (HST), task messages per n_s = W S scouts, with 95 % intervals
(models/hierarchy/README.md, "The message comparison"; issue 30): pools the runs of one or
more sweeps of the two arms and, per n_s, gives star - HST with its Welch interval (the rule
of :func:`abm.verdicts.difference`: "star lower" when the interval lies below 0) and the
ratio star / HST with the Welch interval of the difference of log counts, exponentiated.

    python benchmarks/bench_hierarchy_star.py    # runs both sweeps first if missing
    python benchmarks/bench_hierarchy_star.py SWEEP [SWEEP ...]   # the runs of these folders

The two sweeps: ``experiments/hierarchy_star.toml`` (n_s = 4-32) and
``experiments/hierarchy_star_small.toml`` (n_s = 4 alone, 40 runs per arm: the size where
fewer runs could not tell). Prints a table and writes it as CSV beside the first sweep.
"""

import argparse
import sys
from pathlib import Path

import numpy as np
import pandas as pd

from abm.verdicts import difference

EXPERIMENTS = Path(__file__).resolve().parent.parent / "experiments"
#: Each default sweep folder and the file that makes it.
SWEEPS = {
    Path("out/sweeps/hierarchy_star"): EXPERIMENTS / "hierarchy_star.toml",
    Path("out/sweeps/hierarchy_star_small"): EXPERIMENTS / "hierarchy_star_small.toml",
}
#: The summary columns of the two accountings (they agree for star and HST: no broadcasts).
METRICS = ("messages_task", "transmissions_task")


def compare(runs: pd.DataFrame, metric: str) -> pd.DataFrame:
    """One row per n_s: runs per arm, the means, star - HST and star / HST with intervals."""
    runs = runs[runs["scout_scan_area"].notna()].assign(n_s=runs["W"] * runs["S"])
    rows = []
    for n_s, group in runs.groupby("n_s"):
        hst = group.loc[group["topology"] == "hst", metric].astype(float)
        star = group.loc[group["topology"] == "star", metric].astype(float)
        gap = difference(hst, star, -1)
        log = difference(np.log(hst), np.log(star), -1)
        lower = {True: "star", False: "HST", None: "cannot tell"}[gap.holds]
        rows.append({
            "n_s": n_s, "runs_hst": len(hst), "runs_star": len(star),
            "hst": hst.mean(), "star": star.mean(), "star_minus_hst": gap.mean,
            "low": gap.low, "high": gap.high, "ratio": np.exp(log.mean),
            "ratio_low": np.exp(log.low), "ratio_high": np.exp(log.high), "lower": lower,
        })  # fmt: skip
    return pd.DataFrame(rows)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("sweeps", nargs="*", type=Path, default=list(SWEEPS))
    ap.add_argument("--metric", choices=METRICS, default="messages_task")
    args = ap.parse_args(argv)
    for folder in args.sweeps:
        if not (folder / "runs").is_dir() and folder in SWEEPS:
            from analysis.cli import main as abm

            if code := abm(["sweep", str(SWEEPS[folder]), "--out", str(folder), "--workers", "1"]):
                return code
    files = [f for folder in args.sweeps for f in sorted((folder / "runs").glob("*.parquet"))]
    if not files:
        print(f"no runs in {', '.join(map(str, args.sweeps))}", file=sys.stderr)
        return 2
    runs = pd.concat([pd.read_parquet(f) for f in files], ignore_index=True)
    table = compare(runs[runs["topology"].isin(["hst", "star"])], args.metric)
    digits = {"hst": 0, "star": 0, "star_minus_hst": 0, "low": 0, "high": 0, "ratio": 3,
              "ratio_low": 3, "ratio_high": 3}  # fmt: skip
    with pd.option_context("display.width", 200):
        print(table.round(digits).to_string(index=False))
    out = args.sweeps[0] / f"star_vs_hst_{args.metric}.csv"
    table.to_csv(out, index=False)
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
