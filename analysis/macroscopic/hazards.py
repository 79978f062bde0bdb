"""Per-robot hazards of one transition i -> j, fitted as Poisson regressions (statsmodels GLM).

Each family is a log-linear model of the hazard lambda_ij (1/s) of one robot in state i,
fitted to an exposure table (:mod:`analysis.macroscopic.design`): the transitions counted in
each bin are Poisson with mean ``exposure * lambda_ij``, i.e. a Poisson GLM with log link and
offset ``log(exposure)``. The families:

- ``constant``: ``log lambda = b0``.
- ``counts:<k>`` (mass action / encounters): ``lambda = exp(b0) * n_k ** b1`` while state k
  holds robots (``b1 = 1`` is mass action). With no robot in k the rate is 0 for a positive
  exponent (no partner, no encounter) and its one-robot value ``exp(b0)`` for a non-positive
  one (inhibition: fewest partners, highest rate); the fit first uses the bins where k holds
  robots and, when the exponent comes out non-positive, refits with the empty bins as n = 1.
  The mean-field ODE also meets counts between 0 and 1: the rate is interpolated linearly
  between its values at 0 and 1 robot, so it never blows up as an expected count empties.
- ``time``: ``log lambda = b0 + b1 * t / T`` (T: the longest run).
- ``covariate:<c>``: ``log lambda = b0 + b1 * z`` with z the standardised value of a sample
  column the model records (coverage, pheromone level, ...).
- ``piecewise``: ``log lambda = b_p`` on each of ``PIECES`` equal pieces of [0, T]; a piece
  without any transition has rate 0 (its MLE) and is left out of the regression.

Fitted across conditions (:mod:`analysis.macroscopic.across`), the constant, counts and time
families take further log-linear terms, the *effects* of the swept parameters: ``log lambda =
(family's terms) + sum_p g_p x_p`` with ``x_p`` a standardised parameter value (or a 0/1 level
of a categorical one). :meth:`Hazard.at` folds them into the intercept for one condition.
"""

import dataclasses
import math
import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
import pandas as pd
import statsmodels.api as sm
from scipy.special import gammaln

__all__ = ["PIECES", "Hazard", "candidate_families", "fit_hazard", "heldout_loglik"]

#: Pieces of the piecewise-constant family (ours: few enough to fit from a handful of runs).
PIECES = 4


@dataclass(frozen=True)
class Hazard:
    """A fitted per-robot hazard lambda_ij (1/s) of the transition ``source -> target``.

    Attributes:
        source: state i.
        target: state j (or :data:`~analysis.macroscopic.logs.REMOVED`).
        family: the family's name (see the module's docstring).
        params: the coefficients (b0, b1, ... or b_p per piece; -inf for a piece with rate 0).
        bse: their standard errors (NaN where not estimated).
        scale: T (s) of the ``time``/``piecewise`` families; (mean, sd) of a covariate.
        events: transitions the fit saw.
        exposure: robot-seconds in ``source`` the fit saw.
        score: held-out log-likelihood per held-out run that chose the family (NaN if unscored).
        names: the coefficients' names.
        effects: the exposure columns of the parameter effects whose coefficients follow the
            family's (empty for a fit of one condition); a column ``x:<name>`` gives the
            coefficient ``effect_of_<name>``.

    """

    source: str
    target: str
    family: str
    params: np.ndarray
    bse: np.ndarray
    scale: tuple[float, ...] = ()
    events: int = 0
    exposure: float = 0.0
    score: float = float("nan")
    names: tuple[str, ...] = field(default=())
    effects: tuple[str, ...] = ()

    @property
    def variable(self) -> str | None:
        """The state (``counts:``) or covariate (``covariate:``) the rate depends on."""
        return self.family.split(":", 1)[1] if ":" in self.family else None

    def rate(
        self, t: np.ndarray | float, counts: Mapping[str, np.ndarray], covariates: Mapping
    ) -> np.ndarray:
        """lambda_ij (1/s) at time(s) ``t`` with state counts and covariate values given by
        name (arrays broadcast together).
        """
        if self.effects:
            raise ValueError("a hazard fitted across conditions gives rates at a condition: at()")
        b = self.params
        kind = self.family.split(":", 1)[0]
        t = np.asarray(t, dtype=float)
        if kind == "constant":
            return np.exp(b[0]) + 0.0 * t
        if kind == "counts":
            n = np.asarray(counts[self.variable], dtype=float)
            whole = np.exp(b[0] + b[1] * np.log(np.maximum(n, 1.0)))
            empty = 0.0 if b[1] > 0 else np.exp(b[0])
            share = np.clip(n, 0.0, 1.0)
            return np.where(n >= 1, whole, empty + (np.exp(b[0]) - empty) * share)
        if kind == "time":
            return np.exp(b[0] + b[1] * t / self.scale[0])
        if kind == "covariate":
            z = (np.asarray(covariates[self.variable], dtype=float) - self.scale[0]) / self.scale[1]
            return np.exp(b[0] + b[1] * z)
        piece = np.clip((t / self.scale[0] * PIECES).astype(int), 0, PIECES - 1)
        return np.exp(b[piece])

    def at(self, values: Mapping[str, float]) -> "Hazard":
        """The hazard at one condition: the effects times ``values`` (by effect column) added
        to the intercept.
        """
        own = len(self.params) - len(self.effects)
        shift = sum(g * values[e] for g, e in zip(self.params[own:], self.effects, strict=True))
        params = self.params[:own].copy()
        params[0] += shift
        return dataclasses.replace(
            self, params=params, bse=self.bse[:own], names=self.names[:own], effects=()
        )

    def table(self) -> pd.DataFrame:
        """One row per coefficient: name, estimate, standard error and 95 % interval."""
        return pd.DataFrame(
            {
                "source": self.source,
                "target": self.target,
                "family": self.family,
                "coefficient": list(self.names),
                "estimate": self.params,
                "se": self.bse,
                "low": self.params - 1.959964 * self.bse,
                "high": self.params + 1.959964 * self.bse,
            }
        )


def candidate_families(states: Sequence[str], source: str, covariates: Sequence[str]) -> list[str]:
    """The families tried for a transition out of ``source``."""
    return [
        "constant",
        *(f"counts:{k}" for k in states if k != source),
        "time",
        *(f"covariate:{c}" for c in covariates),
        "piecewise",
    ]


def _design(
    rows: pd.DataFrame, family: str, scale: tuple[float, ...], effects: Sequence[str] = ()
) -> tuple[np.ndarray, np.ndarray]:
    """(design matrix, rows whose rate the family does not force to 0)."""
    x, live = _family_design(rows, family, scale)
    if effects:
        x = np.column_stack([x, rows[list(effects)].to_numpy(dtype=float)])
    return x, live


def _family_design(
    rows: pd.DataFrame, family: str, scale: tuple[float, ...]
) -> tuple[np.ndarray, np.ndarray]:
    kind, _, variable = family.partition(":")
    ones = np.ones(len(rows))
    if kind == "constant":
        return ones[:, None], ones > 0
    if kind == "counts":
        n = rows[f"n:{variable}"].to_numpy(dtype=float)
        return np.column_stack([ones, np.log(np.maximum(n, 1.0))]), n > 0
    if kind == "time":
        return np.column_stack([ones, rows["time"].to_numpy() / scale[0]]), ones > 0
    if kind == "covariate":
        z = (rows[variable].to_numpy(dtype=float) - scale[0]) / scale[1]
        return np.column_stack([ones, z]), ones > 0
    piece = np.clip((rows["time"].to_numpy() / scale[0] * PIECES).astype(int), 0, PIECES - 1)
    return np.eye(PIECES)[piece], ones > 0


def _names(family: str) -> tuple[str, ...]:
    kind, _, variable = family.partition(":")
    if kind == "constant":
        return ("log_rate",)
    if kind == "counts":
        return ("log_rate_at_1", f"exponent_of_n_{variable}")
    if kind == "time":
        return ("log_rate_at_0", "slope_per_T")
    if kind == "covariate":
        return ("log_rate_at_mean", f"slope_per_sd_of_{variable}")
    return tuple(f"log_rate_piece_{p + 1}" for p in range(PIECES))


def fit_hazard(
    rows: pd.DataFrame,
    source: str,
    target: str,
    family: str,
    horizon: float,
    effects: Sequence[str] = (),
) -> Hazard | None:
    """Fit ``family`` to the exposure rows of ``source`` (transitions to ``target``), with the
    parameter effects of the columns ``effects`` (constant, counts and time families only).

    Returns None when the family cannot be fitted to these rows (a covariate without
    spread, a count never above 0 while a transition happened, no convergence).
    """
    y_all = rows[f"to:{target}"].to_numpy(dtype=float)
    scale: tuple[float, ...] = (horizon,)
    kind, _, variable = family.partition(":")
    if effects and kind not in ("constant", "counts", "time"):
        raise ValueError(f"parameter effects need a constant, counts or time family: {family}")
    if kind == "covariate":
        values = rows[variable].to_numpy(dtype=float)
        weights = rows["exposure"].to_numpy()
        mean = float(np.average(values, weights=weights))
        sd = float(np.sqrt(np.average((values - mean) ** 2, weights=weights)))
        if not np.isfinite(sd) or sd == 0:
            return None
        scale = (mean, sd)
    x, live = _design(rows, family, scale, effects)
    x, y = x[live], y_all[live]
    offset = np.log(rows["exposure"].to_numpy()[live])
    params = np.full(x.shape[1], -np.inf)
    bse = np.full(x.shape[1], np.nan)
    used = np.ones(x.shape[1], dtype=bool)
    if kind == "piecewise":
        used = (x * y[:, None]).sum(axis=0) > 0  # a piece with no event: rate 0 (its MLE)
        keep = (x[:, ~used].sum(axis=1) == 0) if (~used).any() else np.ones(len(y), bool)
        x, y, offset = x[keep][:, used], y[keep], offset[keep]
    fitted = _glm(x, y, offset)
    if fitted is not None and y_all[~live].sum() > 0 and fitted[0][1] > 0:
        return None  # a rate 0 with no robot in k, yet a transition happened then
    if fitted is not None and kind == "counts" and fitted[0][1] <= 0 and (~live).any():
        x_all, _ = _design(rows, family, scale, effects)  # inhibition: empty bins as n = 1
        offset_all = np.log(rows["exposure"].to_numpy())
        fitted = _glm(x_all, y_all, offset_all)
        if fitted is not None and fitted[0][1] > 0:
            return None  # the two readings of an empty k disagree: no consistent fit
    if fitted is None:
        return None
    params[used], bse[used] = fitted
    return Hazard(
        source,
        target,
        family,
        params,
        bse,
        scale,
        events=int(y_all.sum()),
        exposure=float(rows["exposure"].sum()),
        names=_names(family) + tuple(f"effect_of_{e.split(':', 1)[-1]}" for e in effects),
        effects=tuple(effects),
    )


def _glm(x: np.ndarray, y: np.ndarray, offset: np.ndarray) -> tuple | None:
    """(params, bse) of the Poisson GLM, or None (nothing to fit, a covariate that does not
    vary where it counts, no convergence).
    """
    if y.sum() == 0 or np.linalg.matrix_rank(x) < x.shape[1]:
        return None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            result = sm.GLM(y, x, family=sm.families.Poisson(), offset=offset).fit()
        except (ValueError, np.linalg.LinAlgError):
            return None
    if not (np.all(np.isfinite(result.params)) and result.converged):
        return None
    return np.asarray(result.params), np.asarray(result.bse)


def heldout_loglik(hazard: Hazard, rows: pd.DataFrame) -> float:
    """Poisson log-likelihood of held-out exposure rows under ``hazard`` (-inf when it gives
    rate 0 where a transition happened).
    """
    y = rows[f"to:{hazard.target}"].to_numpy(dtype=float)
    x, live = _design(rows, hazard.family, hazard.scale, hazard.effects)
    if hazard.family.startswith("counts:") and hazard.params[1] <= 0:
        live = np.ones(len(rows), dtype=bool)  # inhibition: an empty k reads as n = 1
    if hazard.family == "piecewise":
        linear = hazard.params[x.argmax(axis=1)]  # a piece with rate 0 has b_p = -inf
    else:
        with np.errstate(invalid="ignore"):
            linear = x @ hazard.params
    with np.errstate(over="ignore"):
        mu = np.where(live, rows["exposure"].to_numpy() * np.exp(linear), 0.0)
    if np.any((mu == 0) & (y > 0)):
        return -math.inf
    with np.errstate(divide="ignore", invalid="ignore"):
        terms = np.where(y > 0, y * np.log(mu), 0.0) - mu - gammaln(y + 1)
    return float(terms.sum())
