"""The mean-field ODE of a rate model, compiled: the hazards as arrays and a fixed-step RK4.

A :class:`~analysis.macroscopic.rates.RateModel` holds its hazards as objects whose
:meth:`~analysis.macroscopic.hazards.Hazard.rate` works on numpy arrays: right for fitting and
for the stochastic twin's replicates at once, but a few tens of microseconds per call, and the
ODE calls it thousands of times. Here the hazards become flat arrays (:func:`compile_rates`)
and the ODE runs in one compiled loop (:func:`integrate`), so the macroscopic prediction
costs well under a millisecond where the agent runs it replaces cost a second.

Integration: Lawson's integrating-factor fourth-order Runge-Kutta between *breaks* (launch
times, the pieces of a piecewise hazard, the steps of a covariate's path, the ends of
constant-rate launch streams), where the right-hand side may jump. Each state's departure
rate, frozen at a step's start, is integrated exactly (``exp(-Lambda h)``) and the rest by
RK4, so the method is fourth order where rates are moderate and stays stable where a fitted
hazard is far faster than any step (a time trend that empties a state at once). The step is
at most ``STEP`` over the highest departure rate of an occupied state at its start, but not
shorter than ``SHORTEST`` of the output spacing; output times are hit exactly. A launch adds
its robots at its break. ``tests/test_macroscopic_meanfield.py`` checks the result against
closed forms and against an adaptive solver (scipy's LSODA on the hazards' own ``rate``).
"""

from dataclasses import dataclass

import numpy as np
from numba import njit

from analysis.macroscopic.hazards import PIECES
from analysis.macroscopic.rates import RateModel

__all__ = ["OCCUPIED", "SHORTEST", "STEP", "CompiledRates", "compile_rates", "integrate"]

#: Expected departures per robot per step at the highest hazard of an occupied state (ours:
#: against scipy's LSODA on the paper models' fitted rates, 0.1 keeps the expected counts
#: within 3e-4 of the swarm size, 0.02 within 1e-4 at 2-5 times the work).
STEP = 0.1
#: Shortest step, as a share of the mean time between two output times (ours): bounds the
#: work where a hazard grows without bound; the frozen decay keeps such a step stable.
SHORTEST = 1e-3
#: Expected robots below which a state counts as empty for the step size (its decay is exact
#: anyway; a state emptied by a huge hazard must not hold every later step short).
OCCUPIED = 1e-6
#: Hazard families as codes.
_KINDS = {"constant": 0, "counts": 1, "time": 2, "covariate": 3, "piecewise": 4}


@dataclass(frozen=True)
class CompiledRates:
    """A rate model's hazards and sources as arrays (see :func:`compile_rates`)."""

    source: np.ndarray
    target: np.ndarray
    kind: np.ndarray
    variable: np.ndarray
    params: np.ndarray
    scale: np.ndarray
    cov_times: np.ndarray
    cov_values: np.ndarray
    stream_source: np.ndarray
    stream_target: np.ndarray
    stream_rate: np.ndarray
    stream_first: np.ndarray
    stream_last: np.ndarray
    jump_times: np.ndarray
    jumps: np.ndarray
    breaks: np.ndarray


def compile_rates(model: RateModel) -> CompiledRates:
    """The hazards, covariate paths, launch streams and launch jumps of ``model`` as arrays."""
    index = {s: k for k, s in enumerate(model.states)}
    covariates = list(model.covariate_paths)
    h = len(model.hazards)
    source = np.array([index[z.source] for z in model.hazards], dtype=np.int64)
    target = np.array([index.get(z.target, -1) for z in model.hazards], dtype=np.int64)
    kind = np.array([_KINDS[z.family.split(":")[0]] for z in model.hazards], dtype=np.int64)
    variable = np.full(h, -1, dtype=np.int64)
    params = np.zeros((h, max(PIECES, 2)))
    scale = np.ones((h, 2))
    for k, z in enumerate(model.hazards):
        if z.variable is not None:
            variable[k] = index[z.variable] if kind[k] == 1 else covariates.index(z.variable)
        params[k, : len(z.params)] = z.params
        scale[k, : len(z.scale)] = z.scale
    cov_times = np.asarray(model.covariate_times, dtype=float)
    cov_values = (
        np.array([model.covariate_paths[c] for c in covariates], dtype=float)
        if covariates
        else np.zeros((0, len(cov_times)))
    )
    streams = model.streams
    jump_times, jumps = _jumps(model, index)
    breaks = [jump_times]
    for k in np.flatnonzero(kind == 4):
        breaks.append(scale[k, 0] * np.arange(1, PIECES) / PIECES)
    if covariates and np.any(kind == 3):
        breaks.append(cov_times[1:])
    rate_mode = model.launches == "rate"
    if rate_mode and len(streams):
        edges = streams[["first", "last"]].to_numpy(dtype=float).ravel()
        breaks.append(edges[np.isfinite(edges)])
    live = streams[np.isfinite(streams["rate"])] if rate_mode else streams.iloc[:0]
    return CompiledRates(
        source=source,
        target=target,
        kind=kind,
        variable=variable,
        params=params,
        scale=scale,
        cov_times=cov_times,
        cov_values=cov_values,
        stream_source=live["source"].map(index).fillna(-1).to_numpy(dtype=np.int64),
        stream_target=live["target"].map(index).to_numpy(dtype=np.int64),
        stream_rate=live["rate"].to_numpy(dtype=float),
        stream_first=live["first"].to_numpy(dtype=float),
        stream_last=live["last"].to_numpy(dtype=float),
        jump_times=jump_times,
        jumps=jumps,
        breaks=np.unique(np.concatenate(breaks)) if breaks else np.zeros(0),
    )


def _jumps(model: RateModel, index: dict) -> tuple[np.ndarray, np.ndarray]:
    """(times, per time the change of every state's expected count): the launches of every
    fitted run each worth 1 / runs robots ("observed"), or the streams without spread in time
    ("rate": all their robots at their one time).
    """
    import pandas as pd

    if model.launches == "observed":
        table = pd.concat(model.schedules, ignore_index=True)
        table = table.assign(amount=1.0 / len(model.schedules))
    else:
        single = model.streams[~np.isfinite(model.streams["rate"])]
        table = pd.DataFrame(
            {"time": single["first"], "source": single["source"], "target": single["target"],
             "amount": single["total"]}
        )  # fmt: skip
    times = np.unique(table["time"].to_numpy(dtype=float))
    jumps = np.zeros((len(times), len(model.states)))
    row = np.searchsorted(times, table["time"].to_numpy(dtype=float))
    amount = table["amount"].to_numpy(dtype=float)
    np.add.at(jumps, (row, table["target"].map(index).to_numpy(dtype=int)), amount)
    source = table["source"].map(index)
    known = source.notna().to_numpy()
    np.add.at(jumps, (row[known], source[known].to_numpy(dtype=int)), -amount[known])
    return times, jumps


@njit(cache=True)
def _hazards(kind, variable, params, scale, cov_times, cov_values, t, n, out):
    """Each hazard's per-robot rate (1/s) at time t and counts n, into ``out``: the same
    formulas as :meth:`~analysis.macroscopic.hazards.Hazard.rate`.
    """
    for h in range(len(kind)):
        k = kind[h]
        b0 = params[h, 0]
        if k == 0:
            out[h] = np.exp(b0)
        elif k == 1:
            m = max(n[variable[h]], 0.0)
            b1 = params[h, 1]
            if m >= 1.0:
                out[h] = np.exp(b0 + b1 * np.log(m))
            else:
                empty = 0.0 if b1 > 0 else np.exp(b0)
                out[h] = empty + (np.exp(b0) - empty) * m
        elif k == 2:
            out[h] = np.exp(b0 + params[h, 1] * t / scale[h, 0])
        elif k == 3:
            where = np.searchsorted(cov_times, t, side="right") - 1
            where = min(max(where, 0), len(cov_times) - 1)
            z = (cov_values[variable[h], where] - scale[h, 0]) / scale[h, 1]
            out[h] = np.exp(b0 + params[h, 1] * z)
        else:
            piece = min(max(int(t / scale[h, 0] * PIECES), 0), PIECES - 1)
            out[h] = np.exp(params[h, piece])


@njit(cache=True)
def _derivative(c, t, n, rates, dn, leave):
    """dn/dt at (t, n) into ``dn`` and each state's total per-robot hazard out of it into
    ``leave``; returns the highest of those over states that hold robots (``OCCUPIED``).
    """
    (source, target, kind, variable, params, scale, cov_times, cov_values,
     s_source, s_target, s_rate, s_first, s_last) = c  # fmt: skip
    _hazards(kind, variable, params, scale, cov_times, cov_values, t, n, rates)
    dn[:] = 0.0
    leave[:] = 0.0
    for h in range(len(kind)):
        i = source[h]
        flow = rates[h] * max(n[i], 0.0)
        dn[i] -= flow
        leave[i] += rates[h]
        if target[h] >= 0:
            dn[target[h]] += flow
    for s in range(len(s_rate)):
        if s_first[s] <= t < s_last[s]:
            dn[s_target[s]] += s_rate[s]
            if s_source[s] >= 0:
                dn[s_source[s]] -= s_rate[s]
    highest = 0.0
    for i in range(len(n)):
        if n[i] > OCCUPIED and leave[i] > highest:
            highest = leave[i]
    return highest


@njit(cache=True)
def _rest(c, t, y, decay, rates, out, leave):
    """The part of dn/dt beside the frozen decay: f(t, y) + decay * y."""
    _derivative(c, t, y, rates, out, leave)
    for i in range(len(y)):
        out[i] += decay[i] * max(y[i], 0.0)


@njit(cache=True)
def _lawson_rk4(c, t0, t1, n, rates, step_fraction, shortest):
    """Advance n in place from t0 to t1: Lawson's integrating-factor RK4 with each state's
    departure rate frozen at the step's start as the exact decay, so a hazard far faster
    than the step (a state emptied at once) stays stable; steps of at most ``step_fraction``
    over the highest departure rate of an occupied state, but not shorter than ``shortest``.
    """
    d = len(n)
    k1, k2, k3, k4 = np.empty(d), np.empty(d), np.empty(d), np.empty(d)
    y, decay, leave = np.empty(d), np.empty(d), np.empty(d)
    half, whole = np.empty(d), np.empty(d)
    t = t0
    while t < t1:
        highest = _derivative(c, t, n, rates, k1, decay)
        h = t1 - t
        if highest > 0 and step_fraction / highest < h:
            h = max(step_fraction / highest, min(shortest, h))
        for i in range(d):
            k1[i] += decay[i] * max(n[i], 0.0)
            half[i] = np.exp(-decay[i] * 0.5 * h)
            whole[i] = half[i] * half[i]
            y[i] = half[i] * (n[i] + 0.5 * h * k1[i])
        _rest(c, t + 0.5 * h, y, decay, rates, k2, leave)
        for i in range(d):
            y[i] = half[i] * n[i] + 0.5 * h * k2[i]
        _rest(c, t + 0.5 * h, y, decay, rates, k3, leave)
        for i in range(d):
            y[i] = whole[i] * n[i] + h * half[i] * k3[i]
        _rest(c, t + h, y, decay, rates, k4, leave)
        for i in range(d):
            n[i] = whole[i] * n[i] + h / 6.0 * (
                whole[i] * k1[i] + 2.0 * half[i] * (k2[i] + k3[i]) + k4[i]
            )
        t = t1 if h == t1 - t else t + h


@njit(cache=True)
def _integrate(c, jump_times, jumps, breaks, times, states, step_fraction):
    shortest = SHORTEST * times[-1] / max(len(times) - 1, 1)
    n = np.zeros(states)
    out = np.zeros((len(times), states))
    rates = np.zeros(len(c[2]))
    j = 0
    while j < len(jump_times) and jump_times[j] <= 0.0:
        n += jumps[j]
        j += 1
    b = 0
    t = 0.0
    for k in range(len(times)):
        while True:
            while b < len(breaks) and breaks[b] <= t:
                b += 1
            stop = times[k]
            if b < len(breaks) and breaks[b] < stop:
                stop = breaks[b]
            if stop > t:
                _lawson_rk4(c, t, stop, n, rates, step_fraction, shortest)
                t = stop
            while j < len(jump_times) and jump_times[j] <= t:
                n += jumps[j]
                j += 1
            if t >= times[k]:
                break
        out[k] = n
    return out


def integrate(rates: CompiledRates, times: np.ndarray, states: int) -> np.ndarray:
    """The expected counts (time, state) at ``times`` (s, increasing from 0)."""
    c = (rates.source, rates.target, rates.kind, rates.variable, rates.params, rates.scale,
         rates.cov_times, rates.cov_values, rates.stream_source, rates.stream_target,
         rates.stream_rate, rates.stream_first, rates.stream_last)  # fmt: skip
    return _integrate(c, rates.jump_times, rates.jumps, rates.breaks,
                      np.asarray(times, dtype=float), states, STEP)  # fmt: skip
