"""The mean-field model of a :class:`~analysis.macroscopic.rates.RateModel` and its
stochastic twin.

Mean field (:func:`expected_counts`): the expected count n_i of each state follows

    dn_i/dt = sum_j lambda_ji(t, n) n_j - sum_j lambda_ij(t, n) n_i  (+ launches),

integrated by a compiled fixed-step RK4 between launches (:mod:`.compiled`); a launch adds
(or moves) its mean number of robots at its time (the fitted runs' launch times, each weighted
by 1 / runs), or flows at the fitted constant rate.

Stochastic twin (:func:`simulate_counts`): the same hazards as a population Markov chain,
advanced by binomial tau-leaping: in a step dt each of the n_i robots in state i leaves it
with probability ``1 - exp(-Lambda_i dt)`` (Lambda_i: the sum of its hazards, frozen over the
step), to j with odds lambda_ij / Lambda_i. Counts never go negative; each step is short
enough (``STEP_FRACTION`` over the highest per-robot hazard at its start, across
replicates) that a robot rarely could have moved twice. Each replicate
takes the launch times of one fitted run drawn at random (or Poisson launches at the fitted
rate). The 5 % and 95 % quantiles across replicates give the 90 % band.
"""

from dataclasses import dataclass

import numpy as np
import pandas as pd

from analysis.macroscopic.compiled import integrate
from analysis.macroscopic.rates import RateModel

__all__ = ["MIN_STEP", "STEP_FRACTION", "Band", "expected_counts", "simulate_counts"]

#: Expected transitions per robot per tau-leaping step at the highest hazard (ours).
STEP_FRACTION = 0.05
#: Shortest step, as a share of the mean time between two output times (ours): bounds the work
#: of a hazard that grows without bound (a steep time trend) while its state holds robots.
MIN_STEP = 1e-4


def expected_counts(model: RateModel, times: np.ndarray) -> pd.DataFrame:
    """The mean-field expected counts at ``times`` (s, increasing from 0): ``time`` plus one
    column per state (compiled: :mod:`analysis.macroscopic.compiled`).
    """
    times = np.asarray(times, dtype=float)
    out = integrate(model.compiled, times, len(model.states))
    return pd.DataFrame(out, columns=list(model.states)).assign(time=times)[["time", *model.states]]


@dataclass(frozen=True)
class Band:
    """The stochastic model's counts: ``mean``, ``low`` (5 %) and ``high`` (95 %) per state
    and time (DataFrames with ``time`` plus one column per state), ``var`` (variance across
    replicates) and the ``replicates`` array (replicate, time, state).
    """

    mean: pd.DataFrame
    low: pd.DataFrame
    high: pd.DataFrame
    var: pd.DataFrame
    replicates: np.ndarray


def _replicate_jumps(
    model: RateModel, replicates: int, horizon: float, rng: np.random.Generator
) -> pd.DataFrame:
    """Each replicate's launches: ``replicate``, ``time``, ``source``, ``target``."""
    if model.launches == "observed":
        pick = rng.integers(len(model.schedules), size=replicates)
        return pd.concat(
            [model.schedules[k].assign(replicate=r) for r, k in enumerate(pick)],
            ignore_index=True,
        )
    frames = []
    for row in model.streams.itertuples():
        if not np.isfinite(row.rate):
            count = np.full(replicates, int(round(row.total)))
            times = [np.full(c, row.first) for c in count]
        else:
            count = rng.poisson(row.rate * (row.last - row.first), size=replicates)
            times = [np.sort(rng.uniform(row.first, row.last, c)) for c in count]
        for r, t in enumerate(times):
            frames.append(
                pd.DataFrame(
                    {"time": t, "source": row.source, "target": row.target, "replicate": r}
                )  # fmt: skip
            )
    return pd.concat(frames, ignore_index=True)[lambda f: f["time"] <= horizon]


def simulate_counts(
    model: RateModel, times: np.ndarray, replicates: int, rng: np.random.Generator
) -> Band:
    """Run the stochastic twin ``replicates`` times and report counts at ``times`` (s).

    Args:
        model: the fitted rate model.
        times: increasing output times from 0 (s).
        replicates: independent replicates (>= 2).
        rng: the one random generator (seed it for a repeatable band).

    """
    times = np.asarray(times, dtype=float)
    index = {s: k for k, s in enumerate(model.states)}
    step = times[-1] - times[0] or 1.0
    shortest = MIN_STEP * step / max(len(times) - 1, 1)
    jumps = _replicate_jumps(model, replicates, times[-1], rng).sort_values("time")
    jump_t = jumps["time"].to_numpy(dtype=float)
    jump_r = jumps["replicate"].to_numpy(dtype=int)
    jump_to = jumps["target"].map(index).to_numpy(dtype=int)
    jump_from = jumps["source"].map(index).fillna(-1).to_numpy(dtype=int)
    n = np.zeros((replicates, len(model.states)), dtype=np.int64)
    out = np.zeros((replicates, len(times), len(model.states)))
    by_source: dict[int, list] = {}
    for hazard in model.hazards:
        by_source.setdefault(index[hazard.source], []).append(hazard)
    t, done = 0.0, 0
    for k, t_out in enumerate(times):
        while True:
            upto = np.searchsorted(jump_t, t, side="right")
            for e in range(done, upto):  # launches due by t, before the next leap
                if jump_from[e] >= 0:
                    if n[jump_r[e], jump_from[e]] == 0:
                        continue
                    n[jump_r[e], jump_from[e]] -= 1
                n[jump_r[e], jump_to[e]] += 1
            done = upto
            if t >= t_out:
                break
            dt = _leap(model, by_source, index, n, t, min(step, t_out - t), shortest, rng)
            t = t_out if dt == t_out - t else t + dt
        out[:, k] = n
    return _band(model, times, out)


def _leap(model, by_source, index, n, t, longest, shortest, rng) -> float:
    """One binomial tau-leap of every replicate, in place on ``n`` (replicate, state); the
    step is ``longest`` or shorter, so that the highest per-robot hazard now gives at most
    ``STEP_FRACTION`` expected transitions, but not below ``shortest`` (s). Returns the step
    taken (s).
    """
    counts = {s: n[:, k].astype(float) for s, k in index.items()}
    covariates = model.covariates_at(t)
    rates = {
        i: np.stack([np.broadcast_to(h.rate(t, counts, covariates), n.shape[:1]) for h in hs])
        for i, hs in by_source.items()
    }
    highest = max(
        (float(r.sum(axis=0)[n[:, i] > 0].max(initial=0.0)) for i, r in rates.items()),
        default=0.0,
    )  # only hazards of robots present matter: a huge rate of an empty state costs no step
    dt = min(longest, max(STEP_FRACTION / highest, shortest)) if highest > 0 else longest
    change = np.zeros_like(n)
    for i, hazards in by_source.items():
        total = rates[i].sum(axis=0)
        left = rng.binomial(n[:, i], -np.expm1(-total * dt))
        share = total.copy()
        for h, rate in zip(hazards, rates[i], strict=True):
            with np.errstate(invalid="ignore", divide="ignore"):
                p = np.where(share > 0, np.clip(rate / share, 0.0, 1.0), 0.0)
            moved = rng.binomial(left, p)
            left -= moved
            share = share - rate
            change[:, i] -= moved
            if h.target in index:
                change[:, index[h.target]] += moved
    n += change
    return dt


def _band(model: RateModel, times: np.ndarray, out: np.ndarray) -> Band:
    def frame(values: np.ndarray) -> pd.DataFrame:
        table = pd.DataFrame(values, columns=list(model.states))
        table.insert(0, "time", times)
        return table

    return Band(
        mean=frame(out.mean(axis=0)),
        low=frame(np.quantile(out, 0.05, axis=0)),
        high=frame(np.quantile(out, 0.95, axis=0)),
        var=frame(out.var(axis=0, ddof=1)),
        replicates=out,
    )
