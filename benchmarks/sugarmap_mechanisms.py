"""What carries SugarMap's Figs. 8, 9 and 11 (Purohit et al. 2013, Sect. 4.3.3-4.3.5): each
candidate mechanism switched on alone, on paired fresh seeds, with the figure's effect measured.

Each figure has its levels (Fig. 9: particles per explorer; Fig. 11: the arena geometry; Fig. 8:
the split of 10 nodes between anchors and explorers) and a set of variants, each a reading the
model's README lists as a keyword (eq. 8's weight shape, resampling schedule and noise, anchor
placement, the dispersion cut-off, backtracking, the RToF noise). Every variant runs every level
on the same seeds (``--seed`` onward, 840000+ by default: no test, sweep or README number uses
them), so variants and levels are paired by seed. Printed per variant and level: mean true
coverage at the checkpoint, the brain's estimate, pose error, overlap, false-match rate, bumps
(wall collisions per explorer per second), the share of ticks with a revisit match and the
median true distance between a match's two positions ("gap", m); then
the figure's effect with a 95 % interval:

* Fig. 9 (C14): coverage with the most particles minus with 1 (the paper: positive);
* Fig. 11 (C17): serpentine minus circle (the paper: about 0);
* Fig. 8 (C12): the knee, (gain per anchor given up from 4 to 2 anchors) minus (from 8 to 4)
  (the paper: negative, the gain "diminishes when the number of anchors is reduced below 4").

Usage (a few minutes each on a shared 2-core machine):
    python benchmarks/sugarmap_mechanisms.py fig9 --runs 6
    python benchmarks/sugarmap_mechanisms.py fig11 --runs 4 --horizon 1000
    python benchmarks/sugarmap_mechanisms.py fig8 --runs 6 --horizon 1000
    python benchmarks/sugarmap_mechanisms.py fig9 --variants default gauss   # some variants
    python benchmarks/sugarmap_mechanisms.py fig9 --read out/mech/fig9   # a sweep's readings
"""

import argparse
import time
from contextlib import contextmanager

import numpy as np
import pandas as pd
from scipy import stats

from models.sugarmap import SugarMapModel
from models.sugarmap.agents import Explorer
from models.sugarmap.model import CHECKPOINTS

__all__ = ["CONTRASTS", "FIGURES", "READINGS", "effect", "effect_unpaired", "read_sweep", "run_one"]

#: figure -> the keywords of every run, those of each level, the default horizon (s, also the
#: checkpoint of the coverage compared: the last of the model's checkpoints within it) and the
#: variants (name -> keywords).
FIGURES = {
    "fig9": {
        "base": {"n_explorers": 2, "n_anchors": 6},
        "levels": {f"N={n}": {"n_particles": n} for n in (1, 10, 100)},
        "horizon": 400.0,
        "variants": {
            "default": {},
            "gauss": {"weights": "gauss"},
            "gauss, sigma_m 2 m": {"weights": "gauss", "sigma_m": 2.0},
            "resample every tick": {"resample": "every_tick"},
            "resample noise 0.25 m": {"resample_noise": 0.25},
            "gauss + resample noise 0.25 m": {"weights": "gauss", "resample_noise": 0.25},
            "cover_th 0.5": {"cover_th": 0.5},
            "own path covered": {"self_cover": "tree"},
            "gauss + own path covered": {"weights": "gauss", "self_cover": "tree"},
            "hard backtracking": {"backtrack": "hard"},
            "frontier backtracking": {"backtrack": "frontier"},
            "own path covered + frontier": {"self_cover": "tree", "backtrack": "frontier"},
            "anchors spread": {"anchor_placement": "spread"},
            "RToF noise 0.25 m": {"rtof_noise": 0.25},
            "gauss + RToF noise 0.25 m": {"weights": "gauss", "rtof_noise": 0.25},
            "gauss + own path covered + RToF noise 0.25 m": {
                "weights": "gauss",
                "self_cover": "tree",
                "rtof_noise": 0.25,
            },
            "gauss + SIG_TH 0.4": {"weights": "gauss", "sig_th": 0.4},
            "SIG_TH 0.4": {"sig_th": 0.4},
            "RToF noise 0.25 m, SIG_TH 0.5 (its calibration)": {"rtof_noise": 0.25, "sig_th": 0.5},
            "gauss + RToF noise 0.25 m, SIG_TH 0.5": {
                "weights": "gauss",
                "rtof_noise": 0.25,
                "sig_th": 0.5,
            },
            "min_match_age 30 s": {"min_match_age": 30.0},
            "gauss + min_match_age 30 s": {"weights": "gauss", "min_match_age": 30.0},
        },
    },
    "fig11": {
        "base": {"n_explorers": 4, "n_anchors": 6},
        "levels": {"circle": {"arena": "circle"}, "serpentine": {"arena": "serpentine"}},
        "horizon": 1000.0,
        "variants": {
            "default": {},
            "InitCutoff 3000 s": {"init_cutoff": 3000.0},
            "anchors spread": {"anchor_placement": "spread"},
            "hard backtracking": {"backtrack": "hard"},
            "anchors spread + hard backtracking": {
                "anchor_placement": "spread",
                "backtrack": "hard",
            },
            "own path covered": {"self_cover": "tree"},
            "anchors spread + own path covered": {
                "anchor_placement": "spread",
                "self_cover": "tree",
            },
            "gauss": {"weights": "gauss"},
            "RToF noise 0.25 m": {"rtof_noise": 0.25},
            "blocked_ttl 300 s": {"blocked_ttl": 300.0},
            "blocked_ttl 3000 s": {"blocked_ttl": 3000.0},
            "noise-free (actuation and RToF)": {"noise_scale": 0.0, "rtof_noise": 0.0},
            "noise-free + blocked_ttl 3000 s": {
                "noise_scale": 0.0,
                "rtof_noise": 0.0,
                "blocked_ttl": 3000.0,
            },
            "own path covered + blocked_ttl 3000 s": {
                "self_cover": "tree",
                "blocked_ttl": 3000.0,
            },
            "frontier backtracking": {"backtrack": "frontier"},
            "frontier + blocked_ttl 3000 s": {"backtrack": "frontier", "blocked_ttl": 3000.0},
            "noise-free + frontier": {
                "noise_scale": 0.0,
                "rtof_noise": 0.0,
                "backtrack": "frontier",
            },
            "noise-free + frontier + blocked_ttl 3000 s": {
                "noise_scale": 0.0,
                "rtof_noise": 0.0,
                "backtrack": "frontier",
                "blocked_ttl": 3000.0,
            },
        },
    },
    "fig8": {
        "base": {},
        "levels": {f"{a}a/{10 - a}e": {"n_anchors": a, "n_explorers": 10 - a} for a in (2, 4, 8)},
        "horizon": 1000.0,
        "variants": {
            "default": {},
            "gauss": {"weights": "gauss"},
            "RToF noise 2 m": {"rtof_noise": 2.0},
            "gauss + RToF noise 2 m": {"weights": "gauss", "rtof_noise": 2.0},
            "RToF bias 1 m": {"rtof_bias": 1.0},
            "anchors spread": {"anchor_placement": "spread"},
            "hard backtracking": {"backtrack": "hard"},
            "own path covered": {"self_cover": "tree"},
            "frontier backtracking": {"backtrack": "frontier"},
        },
    },
}


def run_one(seed: int, horizon: float, params: dict) -> dict:
    """One run's summary (true and estimated coverage, pose error, overlap, false matches) and
    the true distances (m) between the two positions of each of its revisit matches.
    """
    with _match_gaps() as gaps:
        summary = SugarMapModel(seed=seed, horizon=horizon, **params).run().summary()
    return {**summary, "gap": float(np.median(gaps)) if gaps else np.nan, "gaps": gaps}


@contextmanager
def _match_gaps():
    """Collect, while it is open, how far apart the true positions of every revisit match are
    (what :meth:`Explorer.record` scores as true or false) by wrapping that method.
    """
    gaps: list[float] = []
    record = Explorer.record

    def scored(explorer, match, here):
        if match.matched:
            gaps.append(float(np.hypot(*(here - explorer.truth[match.index]))))
        record(explorer, match, here)

    Explorer.record = scored
    try:
        yield gaps
    finally:
        Explorer.record = record


#: figure -> the effect as a contrast of its levels' coverage (level -> coefficient): Fig. 9
#: the most particles minus 1; Fig. 11 serpentine minus circle; Fig. 8 the knee, the gain per
#: anchor turned explorer from 4 to 2 anchors minus that from 8 to 4.
CONTRASTS = {
    "fig9": {"N=100": 1.0, "N=1": -1.0},
    "fig11": {"serpentine": 1.0, "circle": -1.0},
    "fig8": {"2a/8e": 0.5, "4a/6e": -0.75, "8a/2e": 0.25},
}

#: The keywords a sensitivity sweep of these readings may vary (``--read``: one reading per
#: combination of the ones a sweep has).
READINGS = (
    "weights", "sigma_m", "resample", "resample_noise", "self_cover", "backtrack",
    "blocked_ttl", "cover_th", "sig_th", "min_match_age", "anchor_placement", "init_cutoff",
    "noise_scale", "rtof_noise", "rtof_bias",
)  # fmt: skip


def effect(figure: str, table: pd.DataFrame, metric: str) -> tuple[float, float, float]:
    """The figure's effect (:data:`CONTRASTS`) and its 95 % t-interval over the seeds (paired:
    one value per seed).
    """
    wide = table.pivot(index="seed", columns="level", values=metric)
    per_seed = sum(c * wide[level] for level, c in CONTRASTS[figure].items())
    n = len(per_seed)
    mean = float(per_seed.mean())
    half = float(stats.t.ppf(0.975, n - 1) * per_seed.std(ddof=1) / np.sqrt(n)) if n > 1 else np.nan
    return mean, mean - half, mean + half


def effect_unpaired(figure: str, table: pd.DataFrame, metric: str) -> tuple[float, float, float]:
    """The figure's effect from runs that are not paired by seed (a sweep's), with a 95 %
    normal-approximation interval: sum c_l mean_l, variance sum c_l^2 s_l^2 / n_l.
    """
    mean, var = 0.0, 0.0
    for level, c in CONTRASTS[figure].items():
        values = table.loc[table["level"] == level, metric]
        mean += c * float(values.mean())
        var += c**2 * float(values.var(ddof=1)) / len(values)
    half = 1.96 * float(np.sqrt(var))
    return mean, mean - half, mean + half


def read_sweep(figure: str, folder: str) -> None:
    """Print each reading's table and effect from a finished sensitivity sweep's runs."""
    from analysis.sweep.storage import load_results  # benchmarks may use the analysis layer

    spec = FIGURES[figure]
    runs = load_results(folder, failed=False)
    metric = f"coverage_{max(c for c in CHECKPOINTS if c <= runs['horizon'].min())}"
    runs["level"] = None
    for level, keywords in spec["levels"].items():
        match = np.logical_and.reduce([runs[k] == v for k, v in keywords.items()])
        runs.loc[match, "level"] = level
    keys = [k for k in READINGS if k in runs and runs[k].nunique(dropna=False) > 1]
    names = runs[keys].apply(
        lambda r: ", ".join(f"{k}={r[k]}" for k in keys if pd.notna(r[k])) or "paper's", axis=1
    )
    columns = [metric, "coverage_est", "pose_error", "overlap", "false_match_rate"]
    print(f"{figure}: {len(runs)} runs from {folder}, {metric}")
    for name, table in runs.groupby(names, sort=False):
        table = table[table["level"].notna()]
        mean, low, high = effect_unpaired(figure, table, metric)
        print(f"\n== {name} ({len(table)} runs)")
        print(table.groupby("level", sort=False)[columns].mean().round(2).to_string())
        print(f"effect: {mean:+.1f} points, 95 % interval {low:+.1f} to {high:+.1f} (unpaired)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("figure", choices=sorted(FIGURES))
    parser.add_argument("--runs", type=int, default=6, help="seeds per variant and level")
    parser.add_argument("--seed", type=int, default=840000, help="first seed")
    parser.add_argument(
        "--horizon", type=float, default=None, help="coverage phase (s), the checkpoint if one"
    )
    parser.add_argument("--variants", nargs="*", default=None, help="variant names to run")
    parser.add_argument(
        "--read", default=None, help="print a finished sensitivity sweep's readings instead"
    )
    args = parser.parse_args()
    if args.read is not None:
        read_sweep(args.figure, args.read)
        return
    spec = FIGURES[args.figure]
    horizon = spec["horizon"] if args.horizon is None else args.horizon
    if horizon < CHECKPOINTS[0]:
        parser.error(f"--horizon must be at least {CHECKPOINTS[0]} s (the first checkpoint)")
    checkpoint = max(c for c in CHECKPOINTS if c <= horizon)  # the last within the horizon
    metric = f"coverage_{checkpoint}"
    variants = spec["variants"]
    chosen = list(variants) if args.variants is None else args.variants
    unknown = set(chosen) - set(variants)
    if unknown:
        parser.error(f"unknown variants {sorted(unknown)}; known: {list(variants)}")
    seeds = range(args.seed, args.seed + args.runs)
    print(f"{args.figure}: {args.runs} seeds from {args.seed}, horizon {horizon:g} s, {metric}")
    for name in chosen:
        start = time.perf_counter()
        rows = []
        for level, keywords in spec["levels"].items():
            for seed in seeds:
                params = {**spec["base"], **keywords, **variants[name]}
                rows.append({"level": level, "seed": seed, **run_one(seed, horizon, params)})
        table = pd.DataFrame(rows)
        table["bumps"] = table["wall_collisions"] / (table["n_explorers"] * horizon)
        table["match_share"] = table["matches"] / (table["n_explorers"] * horizon)
        columns = [metric, "coverage_est", "pose_error", "overlap", "false_match_rate", "bumps"]
        columns += ["match_share", "gap"]
        means = table.groupby("level", sort=False)[[*columns, "t_deploy"]].mean()
        mean, low, high = effect(args.figure, table, metric)
        print(f"\n== {name} ({time.perf_counter() - start:.0f} s)")
        print(means.round(2).to_string())
        print(f"effect: {mean:+.1f} points, 95 % interval {low:+.1f} to {high:+.1f}")
        gaps = np.concatenate([np.asarray(g, dtype=float) for g in table["gaps"]])
        if len(gaps):
            print(
                f"revisit matches: {len(gaps)}, true gap median {np.median(gaps):.2f} m, within "
                f"one cell (0.5 m) {np.mean(gaps < 0.5):.2f}, beyond 2 m {np.mean(gaps > 2):.2f}"
            )


if __name__ == "__main__":
    main()
