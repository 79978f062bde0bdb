"""The wander/beacon macroscopic model of Arnaldo et al. (2018): simulate, fit, regress, RMSD.

The recurrence (one model step = ``step`` seconds, 0.5 s in the paper)::

    w_t = w_{t-1} - a_t w_{t-1} + alpha5        w_0 = 0
    b_t = a_t w_{t-1} + b_{t-1}                 b_0 = 1
    a_t = alpha6 a_{t-1}                        a_0 given

and the paper's regressions across maps and radii::

    alpha6 = l0 + l1 C_rb + l2 C_rb^2
    a0     = l3 + l4 sum_k P_k log2 P_k + l5 envsize      (sum_k P_k log2 P_k = -entropy)

Everything here reads tidy DataFrames only (state counts with a ``time`` column and an optional
``seed`` column), so it fits any model's counts, not just :class:`StigmergyModel`'s.
"""

import warnings
from dataclasses import dataclass, field

import lmfit
import numpy as np
import pandas as pd
from numba import njit

from abm.errors import ConfigError, check_range

__all__ = [
    "FitResult",
    "alpha6_from_lambdas",
    "a0_from_lambdas",
    "fit_lambdas",
    "final_counts",
    "fit_recurrence",
    "mean_counts",
    "predict_from_lambdas",
    "recurrence",
    "refine_lambdas",
    "rmsd",
]


def recurrence(
    a0: float,
    alpha6: float,
    alpha5: float = 0.01,
    steps: int = 30000,
    w0: float = 0.0,
    b0: float = 1.0,
    step: float = 0.5,
    supply: float = np.inf,
) -> pd.DataFrame:
    """Iterate the recurrence for ``steps`` model steps.

    ``supply`` (our extension, for swarms of a fixed size such as beacon/explorer): robots stop
    arriving once ``supply`` have arrived in all; the paper's recurrence has no limit (inf).

    Returns:
        DataFrame with ``step`` (0..steps), ``time`` (s), ``wander`` (w_t), ``beacon`` (b_t),
        ``a`` (a_t).

    """
    check_range("steps", steps, 0, integer=True)
    check_range("step", step, 0.0, low_open=True)
    a = a0 * np.power(alpha6, np.arange(steps + 1, dtype=float))
    w, b = _iterate(a, float(alpha5), float(w0), float(b0), float(supply))
    idx = np.arange(steps + 1)
    return pd.DataFrame({"step": idx, "time": idx * step, "wander": w, "beacon": b, "a": a})


def final_counts(
    a0: float, alpha6: float, alpha5: float, steps: int, w0: float = 0.0, b0: float = 1.0
) -> tuple[float, float]:
    """(w, b) after ``steps`` steps of the recurrence, without building its table (for
    fits that only compare end points, e.g. against a paper's final counts).
    """
    check_range("steps", steps, 0, integer=True)
    a = a0 * np.power(alpha6, np.arange(steps + 1, dtype=float))
    w, b = _iterate(a, float(alpha5), float(w0), float(b0))
    return float(w[-1]), float(b[-1])


@njit(cache=True)
def _iterate(
    a: np.ndarray, alpha5: float, w0: float, b0: float, supply: float = np.inf
) -> tuple[np.ndarray, np.ndarray]:
    """w_t, b_t of the recurrence for the given a_t (a compiled loop: fits call it often);
    arrivals stop once ``supply`` robots have arrived.
    """
    w = np.empty(a.shape[0])
    b = np.empty(a.shape[0])
    w[0], b[0] = w0, b0
    arrived = 0.0
    for t in range(1, a.shape[0]):
        moved = a[t] * w[t - 1]
        arriving = min(alpha5, max(0.0, supply - arrived))
        arrived += arriving
        w[t] = w[t - 1] - moved + arriving
        b[t] = b[t - 1] + moved
    return w, b


def rmsd(predicted: np.ndarray, observed: np.ndarray) -> float:
    """Root-mean-square deviation."""
    predicted, observed = np.asarray(predicted, float), np.asarray(observed, float)
    return float(np.sqrt(np.mean((predicted - observed) ** 2)))


def mean_counts(
    counts: pd.DataFrame,
    wander: str = "wander",
    beacon: str = "beacon",
    step: float = 0.5,
    min_share: float = 0.5,
) -> pd.DataFrame:
    """Mean and standard error over runs of the counts, on a grid of ``step`` seconds.

    Args:
        counts: state counts, ``time`` plus the two count columns, one row per change; an
            optional ``seed`` (or ``run``) column tells runs apart. The last row of a run marks
            its end: a run contributes from t = 0 to its last time.
        wander: the column read as w.
        beacon: the column read as b.
        step: grid spacing (s), the model step.
        min_share: keep only grid times at which at least this share of the runs is running.

    Returns:
        ``time``, ``wander``, ``beacon`` (means), ``wander_se``, ``beacon_se``, ``runs``.

    """
    for col in ("time", wander, beacon):
        if col not in counts.columns:
            raise ConfigError(f"counts must have a {col!r} column, has {list(counts.columns)}")
    key = next((c for c in ("seed", "run") if c in counts.columns), None)
    groups = [counts] if key is None else [g for _, g in counts.groupby(key, sort=True)]
    end = max(float(g["time"].max()) for g in groups)
    grid = np.arange(0.0, end + step / 2, step)
    w_runs = np.full((len(groups), len(grid)), np.nan)
    b_runs = np.full_like(w_runs, np.nan)
    for i, g in enumerate(groups):
        g = g.sort_values("time", kind="stable")
        t = g["time"].to_numpy(float)
        where = np.searchsorted(t, grid + 1e-9, side="right") - 1
        alive = (grid <= t[-1] + 1e-9) & (where >= 0)
        w_runs[i, alive] = g[wander].to_numpy(float)[where[alive]]
        b_runs[i, alive] = g[beacon].to_numpy(float)[where[alive]]
    n = np.sum(~np.isnan(w_runs), axis=0)
    keep = n >= max(1, int(np.ceil(min_share * len(groups))))
    with np.errstate(invalid="ignore", divide="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        out = pd.DataFrame(
            {
                "time": grid,
                "wander": np.nanmean(w_runs, axis=0),
                "beacon": np.nanmean(b_runs, axis=0),
                "wander_se": np.nanstd(w_runs, axis=0, ddof=1) / np.sqrt(n),
                "beacon_se": np.nanstd(b_runs, axis=0, ddof=1) / np.sqrt(n),
                "runs": n,
            }
        )
    return out[keep].reset_index(drop=True)


@dataclass
class FitResult:
    """A fitted recurrence.

    Attributes:
        params: best-fit values (a0, alpha6, alpha5, w0, b0).
        stderr: their standard errors (NaN when fixed or not estimable).
        predicted: the recurrence on the observation grid (``time``, ``wander``, ``beacon``).
        observed: the mean counts it was fitted to (see :func:`mean_counts`).
        rmsd_w: RMSD of predicted vs observed w.
        rmsd_b: RMSD of predicted vs observed b.
        lmfit: the underlying ``lmfit.MinimizerResult``.

    """

    params: dict
    stderr: dict
    predicted: pd.DataFrame
    observed: pd.DataFrame
    rmsd_w: float
    rmsd_b: float
    lmfit: object = field(repr=False, default=None)


def _predict(p: dict, steps: int, step: float, supply: float = np.inf) -> pd.DataFrame:
    return recurrence(p["a0"], p["alpha6"], p["alpha5"], steps, p["w0"], p["b0"], step, supply)


def fit_recurrence(
    counts: pd.DataFrame,
    wander: str = "wander",
    beacon: str = "beacon",
    step: float = 0.5,
    alpha5: float | None = None,
    a0: float = 0.05,
    alpha6: float = 0.999,
    min_share: float = 0.5,
    supply: float | None = None,
) -> FitResult:
    """Fit a0 and alpha6 of the recurrence to the mean counts of one or more runs (lmfit).

    Args:
        counts: state counts of one model (``time``, the two count columns, optional ``seed``).
        wander: column of w (e.g. ``"explorer"`` for BeaconExplorerModel counts).
        beacon: column of b.
        step: model step (s); the recurrence advances one step per ``step`` seconds.
        alpha5: robots added per step; None = estimated from the growth of w + b (fixed in
            the fit either way).
        a0: starting value, bounded to [0, 1].
        alpha6: starting value, bounded to [0.9, 1].
        min_share: see :func:`mean_counts`.
        supply: robots that can arrive in all, counting those at t = 0 (a swarm of fixed
            size); None: no limit (the paper's recurrence).

    Returns:
        A :class:`FitResult`; w0 and b0 are the mean observed counts at t = 0, rounded.

    """
    check_range("step", step, 0.0, low_open=True)
    observed = mean_counts(counts, wander, beacon, step, min_share)
    if len(observed) < 3:
        raise ConfigError(f"counts must span at least 3 steps of {step} s, got {len(observed)}")
    t = observed["time"].to_numpy()
    w_obs = observed["wander"].to_numpy()
    b_obs = observed["beacon"].to_numpy()
    if alpha5 is None:
        total = w_obs + b_obs
        alpha5 = float(np.polyfit(t, total, 1)[0] * step)
    limit = np.inf if supply is None else float(supply) - np.round(w_obs[0] + b_obs[0])
    steps = int(round(t[-1] / step))
    idx = np.round(t / step).astype(int)
    params = lmfit.Parameters()
    params.add("a0", value=a0, min=0.0, max=1.0)
    params.add("alpha6", value=alpha6, min=0.9, max=1.0)
    params.add("alpha5", value=alpha5, vary=False)
    params.add("w0", value=float(np.round(w_obs[0])), vary=False)
    params.add("b0", value=float(np.round(b_obs[0])), vary=False)

    def residual(p: lmfit.Parameters) -> np.ndarray:
        pred = _predict(p.valuesdict(), steps, step, limit)
        return np.concatenate(
            [pred["wander"].to_numpy()[idx] - w_obs, pred["beacon"].to_numpy()[idx] - b_obs]
        )

    # A coarse grid start avoids lmfit stalling in the flat region a0 ~ 0.
    best = None
    for a_try in (0.005, 0.02, 0.1, 0.4):
        for g_try in (0.99, 0.999, 0.9999):
            params["a0"].value, params["alpha6"].value = a_try, g_try
            cost = float(np.sum(residual(params) ** 2))
            if best is None or cost < best[0]:
                best = (cost, a_try, g_try)
    params["a0"].value, params["alpha6"].value = best[1], best[2]
    result = lmfit.minimize(residual, params, method="leastsq")
    values = result.params.valuesdict()
    stderr = {
        k: (float(v.stderr) if v.stderr is not None else float("nan"))
        for k, v in result.params.items()
    }
    pred = _predict(values, steps, step, limit).iloc[idx].reset_index(drop=True)
    predicted = pd.DataFrame(
        {"time": t, "wander": pred["wander"].to_numpy(), "beacon": pred["beacon"].to_numpy()}
    )
    return FitResult(
        params={k: float(v) for k, v in values.items()},
        stderr=stderr,
        predicted=predicted,
        observed=observed,
        rmsd_w=rmsd(predicted["wander"], w_obs),
        rmsd_b=rmsd(predicted["beacon"], b_obs),
        lmfit=result,
    )


# ---------------------------------------------------------------------- lambda regressions
def alpha6_from_lambdas(lambdas: dict, radius: float) -> float:
    """alpha6 = l0 + l1 C_rb + l2 C_rb^2."""
    return lambdas["l0"] + lambdas["l1"] * radius + lambdas["l2"] * radius**2


def a0_from_lambdas(lambdas: dict, entropy: float, envsize: float) -> float:
    """a0 = l3 + l4 sum_k P_k log2 P_k + l5 envsize (the sum is minus the entropy)."""
    return lambdas["l3"] - lambdas["l4"] * entropy + lambdas["l5"] * envsize


def predict_from_lambdas(
    lambdas: dict,
    radius: float,
    entropy: float,
    envsize: float,
    steps: int,
    alpha5: float = 0.01,
    step: float = 0.5,
) -> pd.DataFrame:
    """The recurrence with alpha6 and a0 taken from the lambda regressions."""
    a0 = min(1.0, max(0.0, a0_from_lambdas(lambdas, entropy, envsize)))
    alpha6 = min(1.0, max(0.0, alpha6_from_lambdas(lambdas, radius)))
    return recurrence(a0, alpha6, alpha5, steps, 0.0, 1.0, step)


def _linear_fit(y: np.ndarray, columns: dict[str, np.ndarray], names: list[str]) -> tuple:
    params = lmfit.Parameters()
    for name in names:
        params.add(name, value=0.0)
    x = np.column_stack(list(columns.values()))

    def residual(p):
        coef = np.array([p[n].value for n in names])
        return x @ coef - y

    start, *_ = np.linalg.lstsq(x, y, rcond=None)
    for name, v in zip(names, start, strict=True):
        params[name].value = float(v) if v != 0 else 1e-9
    res = lmfit.minimize(residual, params, method="leastsq")
    values = {n: float(res.params[n].value) for n in names}
    if len(y) <= len(names):  # an exact fit (no residual): no standard error to speak of
        return values, dict.fromkeys(names, float("nan"))
    errors = {
        n: float(res.params[n].stderr) if res.params[n].stderr is not None else float("nan")
        for n in names
    }
    return values, errors


def fit_lambdas(fits: pd.DataFrame) -> tuple[dict, dict]:
    """Regress alpha6 on C_rb (quadratic: l0, l1, l2) and a0 on entropy and size (l3, l4, l5).

    Args:
        fits: one row per (map, radius) with columns ``radius``, ``alpha6``, ``a0``,
            ``entropy`` and ``envsize`` (m^2).

    Returns:
        ``(lambdas, stderr)`` dicts keyed l0..l5. With a single map size the size term is not
        identifiable: l5 is then fixed at 0 (stderr NaN); likewise l4 with a single entropy.
        A regression with no more rows than terms (the quadratic on 3 radii) interpolates:
        its standard errors are NaN.

    """
    for col in ("radius", "alpha6", "a0", "entropy", "envsize"):
        if col not in fits.columns:
            raise ConfigError(f"fits must have a {col!r} column, has {list(fits.columns)}")
    r = fits["radius"].to_numpy(float)
    if len(np.unique(r)) < 3:
        raise ConfigError("fit_lambdas needs at least 3 distinct radii for the quadratic")
    one = np.ones(len(fits))
    lam, err = _linear_fit(
        fits["alpha6"].to_numpy(float), {"1": one, "r": r, "r2": r**2}, ["l0", "l1", "l2"]
    )
    cols, names = {"1": one}, ["l3"]
    if fits["entropy"].nunique() > 1:
        cols["plogp"] = -fits["entropy"].to_numpy(float)
        names.append("l4")
    if fits["envsize"].nunique() > 1:
        cols["size"] = fits["envsize"].to_numpy(float)
        names.append("l5")
    lam2, err2 = _linear_fit(fits["a0"].to_numpy(float), cols, names)
    lam.update(lam2)
    err.update(err2)
    for fixed in ("l4", "l5"):
        lam.setdefault(fixed, 0.0)
        err.setdefault(fixed, float("nan"))
    return lam, err


def refine_lambdas(
    lambdas: dict,
    curves: list[tuple[pd.DataFrame, float, float, float]],
    alpha5: float = 0.01,
    step: float = 0.5,
    objective: str = "rmsd",
) -> tuple[dict, dict]:
    """Fit l0..l5 jointly to the observed count curves, starting from ``lambdas``.

    :func:`fit_lambdas` regresses alpha6 and a0 in parameter space, where an error of 1e-4 in
    alpha6 looks negligible but changes a_t = a0 alpha6^t by a factor exp(-1) after 10,000
    steps. Here the same six lambdas are fitted to what they are judged on: the predicted
    w and b of every (map, radius) against the observed means.

    ``objective="rmsd"`` (default) minimises ``sum over curves of (RMSD_w + RMSD_b)``: the
    paper's Table 2 figure, the mean RMSD of w and of b over maps and radii, times the number
    of curves (least squares on the residuals ``sqrt(RMSD)``, one per curve and state, after
    a start on the ``"mse"`` objective). ``objective="mse"`` minimises ``sum over curves of
    (MSE_w + MSE_b) / 2``, which lets the curves with the largest errors (long runs, many
    robots) decide the fit at the expense of the mean RMSD.

    a0 and alpha6 are fractions: a squared penalty keeps every curve's a0 and alpha6 in
    [0, 1] (clipping alone would leave the lambdas behind a clipped value free to drift).
    l4 (l5) stays fixed at its start value when every curve has the same entropy (size).

    Args:
        lambdas: start values l0..l5 (e.g. from :func:`fit_lambdas`).
        curves: ``(observed, radius, entropy, envsize)`` per (map, radius); ``observed`` has
            ``time``, ``wander``, ``beacon`` (e.g. :attr:`FitResult.observed`).
        alpha5: robots added per step.
        step: model step (s).
        objective: ``"rmsd"`` or ``"mse"``.

    Returns:
        ``(lambdas, stderr)`` dicts keyed l0..l5.

    """
    if not curves:
        raise ConfigError("curves must hold at least one (observed, radius, entropy, envsize)")
    if objective not in ("rmsd", "mse"):
        raise ConfigError(f"objective must be 'rmsd' or 'mse', got {objective!r}")
    prepared = []
    for observed, radius, entropy, envsize in curves:
        t = observed["time"].to_numpy(float)
        idx = np.round(t / step).astype(np.int64)
        w_obs = observed["wander"].to_numpy(float)
        b_obs = observed["beacon"].to_numpy(float)
        prepared.append((idx, w_obs, b_obs, float(radius), float(entropy), float(envsize)))
    free = {
        "l4": len({p[4] for p in prepared}) > 1,  # one entropy: l3 alone sets a0
        "l5": len({p[5] for p in prepared}) > 1,
    }
    params = lmfit.Parameters()
    for name in ("l0", "l1", "l2", "l3", "l4", "l5"):
        params.add(name, value=float(lambdas[name]), vary=free.get(name, True))

    def residual(p: lmfit.Parameters, kind: str) -> np.ndarray:
        lam = p.valuesdict()
        out = []
        for idx, w_obs, b_obs, radius, entropy, envsize in prepared:
            raw_a0 = a0_from_lambdas(lam, entropy, envsize)
            raw_alpha6 = alpha6_from_lambdas(lam, radius)
            a0 = min(1.0, max(0.0, raw_a0))
            alpha6 = min(1.0, max(0.0, raw_alpha6))
            a = a0 * np.power(alpha6, np.arange(idx[-1] + 1, dtype=float))
            w, b = _iterate(a, alpha5, 0.0, 1.0)
            dw, db = w[idx] - w_obs, b[idx] - b_obs
            if kind == "mse":
                weight = 1.0 / np.sqrt(2 * len(idx))
                out += [weight * dw, weight * db]
            else:
                out.append(np.sqrt([np.sqrt(np.mean(dw**2)), np.sqrt(np.mean(db**2))]))
            out.append(np.array([100.0 * (raw_a0 - a0), 1e4 * (raw_alpha6 - alpha6)]))
        return np.concatenate(out)

    result = lmfit.minimize(residual, params, method="leastsq", args=("mse",))
    if objective == "rmsd":
        result = _polish(residual, lmfit.minimize(residual, result.params, args=("rmsd",)))
    values = {k: float(v) for k, v in result.params.valuesdict().items()}
    errors = {
        k: float(v.stderr) if v.stderr is not None else float("nan")
        for k, v in result.params.items()
    }
    return values, errors


def _polish(residual, result):
    """Nelder-Mead on the sum of squared ``residual(p, "rmsd")`` from an lmfit result (the
    sum of RMSDs has several valleys, Levenberg-Marquardt stops in the first); then
    Levenberg-Marquardt again from the better point, for the standard errors. Returns the
    lmfit result with the lowest objective.
    """
    from scipy.optimize import minimize

    names = [n for n, v in result.params.items() if v.vary]
    start = np.array([result.params[n].value for n in names])
    # steps of the simplex: a relative 1 % for l3..l5, and for l0..l2 what moves alpha6 by
    # about 1e-5 at C_rb = 40 m (alpha6 differences of that size matter over 10^4 steps)
    scale = {"l0": 1e-5, "l1": 2.5e-7, "l2": 6e-9}
    steps = np.array([scale.get(n, 0.01 * max(abs(result.params[n].value), 1e-6)) for n in names])
    trial = result.params.copy()

    def cost(z: np.ndarray) -> float:
        for name, value in zip(names, start + z * steps, strict=True):
            trial[name].value = float(value)
        return float(np.sum(residual(trial, "rmsd") ** 2))

    best = result
    best_cost = float(np.sum(result.residual**2))
    z = np.zeros(len(names))
    for _ in range(2):  # restarts: a fresh simplex around the last point
        nm = minimize(cost, z, method="Nelder-Mead", options={"maxiter": 2000, "fatol": 1e-7})
        if nm.fun >= best_cost - 1e-9:
            break
        z = nm.x
        params = result.params.copy()
        for name, value in zip(names, start + z * steps, strict=True):
            params[name].value = float(value)
        again = lmfit.minimize(residual, params, method="leastsq", args=("rmsd",))
        again_cost = float(np.sum(again.residual**2))
        if again_cost <= nm.fun:
            best, best_cost = again, again_cost
            z = (np.array([again.params[n].value for n in names]) - start) / steps
        else:
            # keep the Nelder-Mead point; the Levenberg-Marquardt run still gives errors there
            for name, value in zip(names, start + z * steps, strict=True):
                again.params[name].value = float(value)
            best, best_cost = again, float(nm.fun)
    return best
