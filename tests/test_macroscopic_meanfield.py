"""The mean-field ODE and its stochastic twin (analysis.macroscopic.meanfield)."""

import dataclasses

import numpy as np
import pandas as pd
import pytest
from rates_model import RatesModel

from analysis.macroscopic import (
    LAUNCH,
    Hazard,
    RateModel,
    check_heldout,
    collect_runs,
    expected_counts,
    fit_rates,
    observed_counts,
    simulate_counts,
)


def _chain(rates: dict, robots: int, launches: str = "observed", at: float = 0.0) -> RateModel:
    """A rate model of constant hazards, all robots appearing in A at time ``at``."""
    hazards = tuple(
        Hazard(i, j, "constant", np.array([np.log(r)]), np.array([0.0]))
        for (i, j), r in rates.items()
    )
    schedule = pd.DataFrame({"time": at, "source": LAUNCH, "target": ["A"] * robots})
    streams = pd.DataFrame(
        [(LAUNCH, "A", np.inf, at, at, float(robots))],
        columns=["source", "target", "rate", "first", "last", "total"],
    )
    return RateModel(
        states=("A", "B", "C"),
        hazards=hazards,
        schedules=(schedule,),
        launches=launches,
        streams=streams,
        horizon=100.0,
        swarm_size=robots,
        covariate_times=np.zeros(1),
        covariate_paths={},
        bin_width=1.0,
    )


@pytest.mark.parametrize("launches", ["observed", "rate"])
def test_ode_of_a_chain_of_constant_rates_matches_its_closed_form(launches):
    """A -> B -> C at constant rates a, b from N robots in A: n_A = N e^{-at},
    n_B = N a / (b - a) (e^{-at} - e^{-bt}), n_C the rest."""
    a, b, n = 0.07, 0.02, 40
    times = np.linspace(0.0, 100.0, 51)
    got = expected_counts(_chain({("A", "B"): a, ("B", "C"): b}, n, launches), times)
    n_a = n * np.exp(-a * times)
    n_b = n * a / (b - a) * (np.exp(-a * times) - np.exp(-b * times))
    np.testing.assert_allclose(got["A"], n_a, atol=1e-4 * n)
    np.testing.assert_allclose(got["B"], n_b, atol=1e-4 * n)
    np.testing.assert_allclose(got["C"], n - n_a - n_b, atol=1e-4 * n)


def test_ode_waits_for_a_late_launch():
    """Robots appearing at t = 30 s decay from then on, not from 0."""
    times = np.linspace(0.0, 100.0, 101)
    got = expected_counts(_chain({("A", "B"): 0.05}, 10, at=30.0), times)
    want = np.where(times < 30.0, 0.0, 10 * np.exp(-0.05 * (times - 30.0)))
    np.testing.assert_allclose(got["A"], want, atol=1e-3)


def test_stochastic_twin_is_repeatable_and_matches_the_exponential_decay():
    """Same seed, same band; the mean of 400 replicates of A -> B follows N e^{-at} and
    its variance the binomial N p (1 - p)."""
    model = _chain({("A", "B"): 0.05}, 30)
    times = np.array([0.0, 10.0, 20.0, 40.0])
    one = simulate_counts(model, times, 400, np.random.default_rng(5))
    two = simulate_counts(model, times, 400, np.random.default_rng(5))
    np.testing.assert_array_equal(one.replicates, two.replicates)
    p = np.exp(-0.05 * times)
    np.testing.assert_allclose(one.mean["A"], 30 * p, atol=4 * np.sqrt(30 * 0.25 / 400))
    var = one.var["A"].to_numpy()[1:]
    want = (30 * p * (1 - p))[1:]
    assert np.all((var > 0.7 * want) & (var < 1.4 * want)), (var, want)


def test_stochastic_macro_and_agent_runs_agree_in_mean_and_variance():
    """Fitted on 16 runs of the test model, the stochastic twin's mean and variance of each
    state's count at several times agree with 40 fresh agent runs'."""
    model = fit_rates(collect_runs(RatesModel, range(200, 216)))
    fresh = collect_runs(RatesModel, range(300, 340))
    times = np.array([0.0, 10.0, 20.0, 35.0, 60.0])
    agents = observed_counts(fresh, times)
    band = simulate_counts(model, times, 400, np.random.default_rng(810900))
    for k, state in enumerate(model.states):
        mean_a, var_a = agents[:, :, k].mean(axis=0), agents[:, :, k].var(axis=0, ddof=1)
        mean_m, var_m = band.mean[state].to_numpy(), band.var[state].to_numpy()
        se = np.sqrt(var_a / len(fresh) + var_m / 400)
        moving = var_a > 0
        assert np.all(np.abs(mean_a - mean_m)[moving] <= 4 * se[moving] + 0.5), state
        ratio = var_m[moving] / var_a[moving]
        assert np.all((ratio > 0.4) & (ratio < 2.5)), (state, ratio)


def test_held_out_checks_of_the_test_model():
    """On runs it has not seen the test model's macro model is within 5 % of the swarm per
    state, its band covers most points, and it is faster than the agent runs."""
    model = fit_rates(collect_runs(RatesModel, range(400, 412)))
    checks = check_heldout(model, collect_runs(RatesModel, range(500, 512)),
                           np.random.default_rng(1), replicates=200)  # fmt: skip
    assert checks.rmsd_max <= 0.05, checks.table
    assert 0.75 <= checks.band_coverage <= 1.0, checks.table
    assert set(checks.table["state"]) == {"A", "B", "C"}
    assert checks.speed_ratio > 0


def test_a_steep_hazard_of_an_empty_state_costs_the_stochastic_twin_no_steps(monkeypatch):
    """C -> A grows as exp(60 t / T) but C never holds a robot: the tau-leaping steps follow
    the hazards of robots present (A -> B), so the band takes a few hundred steps, not an
    endless number."""
    from analysis.macroscopic import meanfield

    model = _chain({("A", "B"): 0.1}, 30)
    steep = Hazard("C", "A", "time", np.array([0.0, 60.0]), np.zeros(2), scale=(100.0,))
    model = dataclasses.replace(model, hazards=(*model.hazards, steep))
    leaps = []
    leap = meanfield._leap

    def counted(*args):
        leaps.append(1)
        if len(leaps) > 10_000:
            raise RuntimeError("the stochastic twin took more than 10,000 steps")
        return leap(*args)

    monkeypatch.setattr(meanfield, "_leap", counted)
    band = simulate_counts(model, np.linspace(0.0, 100.0, 11), 50, np.random.default_rng(2))
    assert len(leaps) < 1_000
    assert band.mean["C"].max() == 0
    np.testing.assert_allclose(band.mean["A"].iloc[-1], 30 * np.exp(-10.0), atol=0.2)


def _lsoda(model: RateModel, times: np.ndarray) -> np.ndarray:
    """The ODE's definition solved by an adaptive solver on the hazards' own ``rate``:
    dn_i/dt = sum_j lambda_ji n_j - sum_j lambda_ij n_i, the launches added at their times.
    """
    from scipy.integrate import solve_ivp

    from analysis.macroscopic.compiled import compile_rates

    index = {s: k for k, s in enumerate(model.states)}
    jumps = compile_rates(model)
    breaks = np.unique(np.concatenate([jumps.breaks, [times[-1]]]))
    breaks = breaks[(breaks > 0) & (breaks <= times[-1])]

    def rhs(t, n):
        counts = dict(zip(model.states, np.maximum(n, 0.0), strict=True))
        out = np.zeros_like(n)
        for h in model.hazards:
            flow = float(h.rate(t, counts, model.covariates_at(t))) * max(n[index[h.source]], 0)
            out[index[h.source]] -= flow
            if h.target in index:
                out[index[h.target]] += flow
        return out

    def launch(at):
        for t, jump in zip(jumps.jump_times, jumps.jumps, strict=True):
            if t == at:
                n[:] += jump

    n = np.zeros(len(model.states))
    out = np.zeros((len(times), len(model.states)))
    launch(0.0)
    t0 = 0.0
    for t1 in breaks:
        inside = (times >= t0) & (times < t1)
        sol = solve_ivp(rhs, (t0, t1), n, method="LSODA", t_eval=np.append(times[inside], t1),
                        rtol=1e-8, atol=1e-10)  # fmt: skip
        out[inside] = sol.y[:, :-1].T
        n[:] = sol.y[:, -1]
        launch(t1)
        t0 = t1
    out[times >= t0] = n
    return out


@pytest.mark.parametrize("model", ["stigmergy", "sugarmap", "tangible-pso", "hierarchy"])
def test_the_compiled_ode_agrees_with_an_adaptive_solver_on_fitted_models(model):
    """Fitted rate models of the paper models (constant, count-dependent, time, covariate and
    piecewise hazards, many launches): the compiled integrator and LSODA agree within 5e-4 of
    the swarm size (far below any held-out RMSD)."""
    logs = collect_runs(model, range(812000, 812003), {"time_limit": 300.0})
    fitted = fit_rates(logs)
    times = np.linspace(0.0, max(log.end for log in logs), 201)
    got = expected_counts(fitted, times)[list(fitted.states)].to_numpy()
    np.testing.assert_allclose(got, _lsoda(fitted, times), atol=5e-4 * fitted.swarm_size)
