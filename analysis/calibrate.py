"""Likelihood-free calibration of a model against measured numbers: ABC-SMC with pyABC.

Each particle (values of the free parameters, drawn from uniform or log-uniform priors) runs
the model ``replicates`` times per condition of the target; its summary statistics are the
target's metrics, row by row, each the mean over those runs. With one run per particle the
distance carries a single run's spread, so the posterior cannot be narrower than what one run
tells apart; a target measured as the mean of many runs is matched by particles that are means
of several (then give the target the spread of such a mean as ``sd``). The distance of a
particle is ``sqrt(mean_i ((x_i - value_i) / sd_i)^2)``: each metric counts in units of the
target's spread, so a count and a time weigh alike. ABC-SMC
(Toni et al. 2009; pyABC's ``ABCSMC``) lowers the acceptance threshold population by
population (the median of the previous distances) until ``epsilon`` or the population budget.

Seeds: every evaluation's seed is drawn from ``numpy.random.default_rng([seed, bits of the
particle])`` and stored with its summary statistics in pyABC's database (``_seed``), so any
particle's runs can be replayed. With one worker the sampler is seeded too and a calibration
repeats exactly; pyABC's parallel samplers accept particles in the order workers finish, so
with several workers the particles differ from one run to the next and only posterior
summaries reproduce (within their Monte Carlo error).
"""

import math
import struct
from collections.abc import Callable, Mapping, Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from analysis.calibration_inputs import Prior, Target

__all__ = [
    "DB",
    "Calibration",
    "distance",
    "posterior_figure",
    "evaluation_seed",
    "posterior_table",
    "predictive_table",
    "run_abc",
    "run_at",
]

#: pyABC's database inside the output folder.
DB = "abc.db"
#: Posterior quantiles reported (5 % and 95 %: the 90 % interval).
QUANTILES = (0.05, 0.95)


def evaluation_seed(seed: int, values: Sequence[float]) -> int:
    """The seed of the model runs of one particle: a draw of a Generator seeded by the
    calibration's seed and the particle's exact values (the same particle, the same runs).
    Below 2**53, so pyABC's database, which stores statistics as floats, keeps it exactly.
    """
    bits = [struct.unpack("<Q", struct.pack("<d", float(v)))[0] for v in values]
    return int(np.random.default_rng([seed, *bits]).integers(2**53))


def distance(sd: np.ndarray) -> Callable[[Mapping, Mapping], float]:
    """The distance between two sets of summary statistics (``r0``, ``r1``, ...), each row
    scaled by its target spread ``sd``.
    """

    def d(x: Mapping, x0: Mapping) -> float:
        diff = np.array([(x[f"r{i}"] - x0[f"r{i}"]) / s for i, s in enumerate(sd)])
        return float(np.sqrt(np.mean(diff**2))) if np.all(np.isfinite(diff)) else math.inf

    return d


@dataclass(frozen=True)
class Calibration:
    """Everything one model evaluation needs (picklable for worker processes).

    Attributes:
        model: the model class.
        target: the measured numbers.
        priors: the free parameters.
        fixed: the parameters set with ``--set``.
        seed: the calibration's seed.
        replicates: runs per condition and particle; each statistic is their mean.

    """

    model: type
    target: Target
    priors: tuple[Prior, ...]
    fixed: Mapping
    seed: int
    replicates: int = 1

    def evaluate(self, values: Mapping[str, float], seed: int) -> dict:
        """``replicates`` runs per condition of the target at ``values``: the target's
        metrics by row, each the mean of its runs (NaN when a run does not report it).
        """
        from analysis.runner import run_model

        summaries = []
        for k, cond in enumerate(self.target.condition_list()):
            params = {**self.fixed, **cond, **{p.name: float(values[p.name]) for p in self.priors}}
            runs = [
                run_model(self.model, params, _run_seed(seed, k, r)).summary
                for r in range(self.replicates)
            ]
            summaries.append((cond, runs))
        out = {}
        for i in range(len(self.target.rows)):
            cond = self.target.condition_of(i)
            runs = next(s for c, s in summaries if c == cond)
            metric = self.target.rows["metric"].iloc[i]
            got = [run.get(metric) for run in runs]
            out[f"r{i}"] = math.nan if None in got else float(np.mean(np.asarray(got, float)))
        return out

    def __call__(self, particle: Mapping) -> dict:
        """The model pyABC calls: one particle's summary statistics, with the seed it ran on."""
        values = [float(particle[p.name]) for p in self.priors]
        seed = evaluation_seed(self.seed, values)
        return {**self.evaluate(particle, seed), "_seed": seed}

    def observed(self) -> dict:
        """The target as summary statistics."""
        return {f"r{i}": float(v) for i, v in enumerate(self.target.rows["value"])}


def _run_seed(seed: int, condition: int, replicate: int) -> int:
    """The seed of one run of an evaluation (replicate 0 keeps the seed of a single run)."""
    key = [seed, condition] if replicate == 0 else [seed, condition, replicate]
    return int(np.random.SeedSequence(key).generate_state(1)[0])


def _prior(priors: Sequence[Prior]):
    import pyabc

    return pyabc.Distribution(
        **{
            p.name: pyabc.RV("loguniform", p.low, p.high)
            if p.log
            else pyabc.RV("uniform", p.low, p.high - p.low)
            for p in priors
        }
    )


def run_abc(
    calib: Calibration,
    out: Path,
    *,
    populations: int,
    population_size: int,
    epsilon: float,
    workers: int,
    address: str | None,
    resume: bool,
):
    """Run (or continue) ABC-SMC until ``epsilon`` or ``populations`` populations in all.

    Returns:
        pyABC's History of the run.

    """
    import pyabc
    from pyabc.sampler import MulticoreEvalParallelSampler, SingleCoreSampler

    client = None
    if address is not None:
        from dask.distributed import Client
        from pyabc.sampler import DaskDistributedSampler

        client = Client(address)
        sampler = DaskDistributedSampler(client)
    elif workers > 1:
        sampler = MulticoreEvalParallelSampler(n_procs=workers)
    else:
        sampler = SingleCoreSampler()
    np.random.seed(calib.seed % 2**32)  # pyABC draws particles from numpy's global state
    sd = calib.target.rows["sd"].to_numpy(float)
    abc = pyabc.ABCSMC(
        calib, _prior(calib.priors), distance(sd), population_size=population_size,
        sampler=sampler,
    )  # fmt: skip
    db = f"sqlite:///{(out / DB).resolve()}"
    if resume:
        abc.load(db, 1)
        done = abc.history.n_populations
    else:
        abc.new(db, calib.observed())
        done = 0
    try:
        if populations > done:
            abc.run(minimum_epsilon=epsilon, max_nr_populations=populations - done)
    finally:
        if client is not None:
            client.close()  # else it keeps reconnecting to a scheduler that went away
    return abc.history


def _weighted_quantile(x: np.ndarray, w: np.ndarray, q: float) -> float:
    order = np.argsort(x)
    cw = np.cumsum(w[order])
    return float(np.interp(q * cw[-1], cw, x[order]))


def posterior_table(history, priors: Sequence[Prior]) -> pd.DataFrame:
    """Per parameter: weighted mean, median, 5 % and 95 % quantiles of the last population."""
    frame, w = history.get_distribution()
    rows = []
    for p in priors:
        x = frame[p.name].to_numpy(float)
        rows.append({
            "parameter": p.name,
            "mean": float(np.sum(w * x) / np.sum(w)),
            "median": _weighted_quantile(x, w, 0.5),
            "q05": _weighted_quantile(x, w, QUANTILES[0]),
            "q95": _weighted_quantile(x, w, QUANTILES[1]),
            "prior_low": p.low,
            "prior_high": p.high,
        })  # fmt: skip
    return pd.DataFrame(rows)


def run_at(calib: Calibration, points: Sequence[Mapping], seeds: Sequence[int], workers: int):
    """The target's statistics at each parameter point (one evaluation each, its own seed)."""
    if workers > 1 and len(points) > 1:
        with ProcessPoolExecutor(workers) as pool:
            results = list(pool.map(calib.evaluate, points, seeds))
    else:
        results = [calib.evaluate(p, s) for p, s in zip(points, seeds, strict=True)]
    return pd.DataFrame(results)


def predictive_table(target: Target, runs: pd.DataFrame) -> pd.DataFrame:
    """Target value and sd beside the runs' mean and 5/95 % quantiles, per target row."""
    rows = []
    for i, row in target.rows.iterrows():
        x = runs[f"r{i}"].to_numpy(float)
        x = x[np.isfinite(x)]
        rows.append({
            "metric": row["metric"],
            **target.condition_of(i),
            "target": float(row["value"]),
            "sd": float(row["sd"]),
            "runs": len(x),
            "predicted_mean": float(np.mean(x)) if len(x) else math.nan,
            "q05": float(np.quantile(x, QUANTILES[0])) if len(x) else math.nan,
            "q95": float(np.quantile(x, QUANTILES[1])) if len(x) else math.nan,
            "z": (float(np.mean(x)) - float(row["value"])) / float(row["sd"])
            if len(x) else math.nan,
        })  # fmt: skip
    return pd.DataFrame(rows)


def posterior_figure(history, priors: Sequence[Prior], table: pd.DataFrame, path: Path) -> Path:
    """One panel per parameter: the last population's weighted histogram (30 bins over the
    particles' span), its median and 90 % interval marked; the prior's range is in the label
    (drawn at full width a narrow posterior would be one bar).
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    frame, w = history.get_distribution()
    fig, axes = plt.subplots(1, len(priors), figsize=(4 * len(priors), 3.4), squeeze=False)
    for ax, p, (_, row) in zip(axes[0], priors, table.iterrows(), strict=True):
        x = frame[p.name].to_numpy(float)
        lo, hi = (x.min(), x.max()) if x.max() > x.min() else (p.low, p.high)
        edges = (np.geomspace if p.log else np.linspace)(lo, hi, 31)
        ax.hist(x, bins=edges, weights=w, density=True, color="#4c72b0", alpha=0.8)
        ax.axvline(row["median"], color="k", label=f"median {row['median']:.4g}")
        for q in ("q05", "q95"):
            ax.axvline(row[q], color="k", linestyle="--")
        if p.log:
            ax.set_xscale("log")
        kind = "log-uniform" if p.log else "uniform"
        ax.set_title(p.name)
        ax.set_xlabel(f"prior {kind} {p.low:g}..{p.high:g}\ndashed: 5 % and 95 % quantiles")
        ax.set_ylabel("posterior density")
        ax.legend(fontsize="small")
    fig.suptitle(f"posterior after {history.n_populations} populations")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path
