"""Calibrate the corridor branching constants against the paper's branch counts.

Run ``python -m models.environments.calibrate`` (a few minutes on two cores). For every
``min_gap`` it
finds by bisection the ``p_branch`` (to 0.01) whose mean branch count over 40-cell worlds is
nearest the paper's, then keeps the pair that best matches mean and standard deviation,
re-measured on more worlds. The result is copied by hand into
:data:`models.environments.corridor.BRANCHING`.
"""

import numpy as np

from abm.pools import process_pool
from models.environments.corridor import branch_count, grow_corridor

__all__ = ["PAPER_BRANCHES", "branch_stats", "calibrate", "main"]

#: ``complexity -> (mean, sd)`` branch counts of 40-cell corridors (Stirling 2010, Sect. 3.5).
PAPER_BRANCHES = {"low": (3.56, 1.23), "medium": (5.82, 1.07), "high": (9.5, 1.63)}

SEED = 20100101
N_SEARCH = 1500  # worlds per bisection step
N_CHECK = 8000  # worlds for the final comparison of candidates
MEAN_WEIGHT = 4.0  # weight of the squared relative mean error against the sd error
GAPS = range(1, 13)


def branch_stats(
    p_branch: float, min_gap: int, n_worlds: int, seed: int = SEED, n_cells: int = 40
) -> tuple[float, float]:
    """Mean and sd of the branch count of ``n_worlds`` corridors grown with these constants."""
    rng = np.random.default_rng(seed)
    branching = (p_branch, min_gap)
    counts = [
        branch_count(grow_corridor(n_cells, rng, branching=branching)) for _ in range(n_worlds)
    ]
    return float(np.mean(counts)), float(np.std(counts))


def _error(stats: tuple[float, float], target: tuple[float, float]) -> float:
    (mean, sd), (t_mean, t_sd) = stats, target
    return MEAN_WEIGHT * ((mean - t_mean) / t_mean) ** 2 + ((sd - t_sd) / t_sd) ** 2


def _best_p(min_gap: int, target_mean: float) -> float:
    """Smallest p_branch (to 0.01) whose mean branch count reaches ``target_mean``."""
    lo, hi = 0, 100  # in hundredths
    while hi - lo > 1:
        mid = (lo + hi) // 2
        mean, _ = branch_stats(mid / 100, min_gap, N_SEARCH)
        lo, hi = (lo, mid) if mean >= target_mean else (mid, hi)
    candidates = [(branch_stats(p / 100, min_gap, N_SEARCH), p / 100) for p in (lo, hi)]
    return min(candidates, key=lambda c: abs(c[0][0] - target_mean))[1]


def _search(level: str) -> tuple[str, float, int, float, float]:
    target = PAPER_BRANCHES[level]
    scored = []
    for gap in GAPS:
        p = _best_p(gap, target[0])
        scored.append((_error(branch_stats(p, gap, N_SEARCH), target), p, gap))
    scored.sort()
    finals = []
    for _, p, gap in scored[:3]:
        stats = branch_stats(p, gap, N_CHECK, seed=SEED + 1)
        finals.append((_error(stats, target), p, gap, *stats))
    _, p, gap, mean, sd = min(finals)
    return level, p, gap, mean, sd


def calibrate() -> dict[str, tuple[float, int, float, float]]:
    """Return ``complexity -> (p_branch, min_gap, measured mean, measured sd)``."""
    with process_pool() as pool:
        rows = list(pool.map(_search, PAPER_BRANCHES))
    return {level: (p, gap, mean, sd) for level, p, gap, mean, sd in rows}


def main() -> None:
    """Print the calibrated constants and their branch statistics."""
    for level, (p, gap, mean, sd) in calibrate().items():
        t_mean, t_sd = PAPER_BRANCHES[level]
        print(
            f"{level:>6}: p_branch={p:.2f} min_gap={gap:2d}  mean {mean:.2f} (paper {t_mean}) "
            f"sd {sd:.2f} (paper {t_sd})"
        )


if __name__ == "__main__":
    main()
