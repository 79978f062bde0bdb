"""The PSO core (abm.pso) beside pyswarms' GlobalBestPSO, on textbook functions with the same
settings: dimensionless particles, no constraints, the same initial positions and velocity
distribution, 30 seeds each; the median best cost per iteration side by side, and a PNG.

Usage:
    pip install -e ".[pso-check]"         # pyswarms (not needed by anything else)
    python benchmarks/bench_pso_vs_pyswarms.py [--seeds 30] [--iterations 100]

Two settings: the paper's (c1 = 2.5, c2 = 2.0, w = 1, no velocity limit: a divergent PSO on a
free problem, kept in check only by the tangible particles' flights) and Clerc's constriction
(w = 0.7298, c1 = c2 = 1.49618), the usual stable choice. The random streams differ (pyswarms
uses numpy's global generator), so the comparison is of distributions, judged by a two-sided
Mann-Whitney test on the final best costs.
"""

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from scipy import stats  # noqa: E402

from abm.pso import minimise  # noqa: E402

FUNCTIONS = {
    "sphere": (lambda x: (x**2).sum(axis=1), 5.12),
    "rosenbrock": (
        lambda x: (100 * (x[:, 1:] - x[:, :-1] ** 2) ** 2 + (1 - x[:, :-1]) ** 2).sum(axis=1),
        2.048,
    ),
    "rastrigin": (
        lambda x: 10 * x.shape[1] + (x**2 - 10 * np.cos(2 * np.pi * x)).sum(axis=1),
        5.12,
    ),
}
SETTINGS = {
    "paper (c1 2.5, c2 2.0, w 1)": {"c1": 2.5, "c2": 2.0, "w": 1.0},
    "constriction (c 1.49618, w 0.7298)": {"c1": 1.49618, "c2": 1.49618, "w": 0.7298},
}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seeds", type=int, default=30)
    parser.add_argument("--iterations", type=int, default=100)
    parser.add_argument("--particles", type=int, default=40)
    parser.add_argument("--dimensions", type=int, default=10)
    parser.add_argument("--out", type=Path, default=Path("out/pso_vs_pyswarms.png"))
    args = parser.parse_args()
    try:
        import pyswarms
    except ImportError:
        print('pyswarms is not installed: pip install -e ".[pso-check]"')
        return
    print(f"pyswarms {pyswarms.__version__}; {args.particles} particles, {args.dimensions} "
          f"dimensions, {args.iterations} iterations, {args.seeds} seeds")  # fmt: skip
    fig, axes = plt.subplots(len(SETTINGS), len(FUNCTIONS), figsize=(13, 7), squeeze=False)
    for row, (setting, opts) in enumerate(SETTINGS.items()):
        print(f"\n{setting}: median best cost at iterations 10 / 50 / {args.iterations}")
        for col, (name, (f, bound)) in enumerate(FUNCTIONS.items()):
            ours, theirs = [], []
            for seed in range(args.seeds):
                rng = np.random.default_rng(seed)
                x0 = rng.uniform(-bound, bound, (args.particles, args.dimensions))
                v0 = rng.uniform(0, 1, x0.shape)  # pyswarms' default: U[0, 1) without a clamp
                res = minimise(f, x0, v0, args.iterations, rng, c1=opts["c1"], c2=opts["c2"],
                               w_start=opts["w"])  # fmt: skip
                ours.append(res.history[: args.iterations])
                np.random.seed(seed)
                opt = pyswarms.single.GlobalBestPSO(
                    args.particles, args.dimensions, options=dict(opts), init_pos=x0.copy()
                )
                opt.optimize(f, args.iterations, verbose=False)
                theirs.append(np.array(opt.cost_history))
            ours, theirs = np.array(ours), np.array(theirs)
            at = [9, 49, args.iterations - 1]
            p = stats.mannwhitneyu(ours[:, -1], theirs[:, -1]).pvalue
            print(
                f"  {name:10s} abm.pso "
                + " / ".join(f"{np.median(ours[:, i]):.3g}" for i in at)
                + "   pyswarms "
                + " / ".join(f"{np.median(theirs[:, i]):.3g}" for i in at)
                + f"   (Mann-Whitney p = {p:.2f})"
            )
            ax = axes[row, col]
            it = np.arange(1, args.iterations + 1)
            for label, data, colour in (
                ("abm.pso", ours, "#0072B2"),
                ("pyswarms", theirs, "#D55E00"),
            ):
                q1, med, q3 = np.percentile(data, [25, 50, 75], axis=0)
                ax.plot(it, med, color=colour, label=label)
                ax.fill_between(it, q1, q3, color=colour, alpha=0.2)
            ax.set(yscale="log", title=f"{name}: {setting}", xlabel="iteration")
            ax.title.set_fontsize(9)
            if col == 0:
                ax.set_ylabel("best cost (median, IQR)")
            ax.legend(fontsize=8)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    fig.tight_layout()
    fig.savefig(args.out, dpi=100)
    print(f"\nwrote {args.out}")


if __name__ == "__main__":
    main()
