"""Global-best particle swarm optimisation: the update rules, and a plain optimiser over them.

The standard rules with a linearly falling inertia weight, for
``P`` particles at once (arrays ``(P, D)``):

- velocity: ``u_j(t) = w(t) u_j(t-1) + Phi1 (b_j - p_j(t-1)) + Phi2 (b_g - p_j(t-1))``,
  ``Phi_k = c_k diag(rand_k)``, ``rand ~ U[0, 1]`` per component;
- inertia: ``w(t) = w_start + t (w_end - w_start) / t_max`` (``w = 1``: none);
- velocity limit: components beyond ``+-u_max`` are clipped;
- position: ``p_j(t) = p_j(t-1) + u_j(t)``.

A model that moves its particles itself (e.g. "tangible" particles that must fly there) calls
:func:`velocity_update` and :func:`update_bests` and owns the rest; :func:`minimise` is the
dimensionless optimiser, the textbook check against other implementations.
"""

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from abm.errors import ConfigError

__all__ = ["PSOResult", "inertia_weight", "minimise", "update_bests", "velocity_update"]


def inertia_weight(t: int, t_max: int, w_start: float, w_end: float) -> float:
    """The inertia at iteration ``t`` of ``t_max``, linear from ``w_start`` to ``w_end``."""
    return w_start + t * (w_end - w_start) / t_max


def velocity_update(
    u: np.ndarray,
    p: np.ndarray,
    own_best: np.ndarray,
    global_best: np.ndarray,
    rng: np.random.Generator,
    *,
    c1: float,
    c2: float,
    w: float = 1.0,
    u_max: float = np.inf,
) -> np.ndarray:
    """The velocity rule (with the inertia ``w`` and the limit ``u_max``): the new velocities.

    Args:
        u: ``(P, D)`` velocities u_j(t-1).
        p: ``(P, D)`` positions p_j(t-1).
        own_best: ``(P, D)`` each particle's best position b_j.
        global_best: ``(D,)`` the population's best b_g.
        rng: the random generator (two ``(P, D)`` uniform draws, Phi1's then Phi2's).
        c1: weight of the particle's own experience.
        c2: weight of the social knowledge.
        w: inertia applied to u_j(t-1).
        u_max: per-component velocity limit (``inf``: none).

    """
    r1 = rng.random(p.shape)
    r2 = rng.random(p.shape)
    new = w * u + c1 * r1 * (own_best - p) + c2 * r2 * (global_best - p)
    if np.isfinite(u_max):
        new = np.clip(new, -u_max, u_max)
    return new


def update_bests(cost: np.ndarray, p: np.ndarray, best_cost: np.ndarray, best_p: np.ndarray) -> int:
    """Update each particle's best (in place) where ``cost`` improved it; the index of the
    population's best particle (the first of equals).
    """
    better = cost < best_cost
    best_cost[better] = cost[better]
    best_p[better] = p[better]
    return int(np.argmin(best_cost))


@dataclass(frozen=True)
class PSOResult:
    """What :func:`minimise` found.

    Attributes:
        position: the best position b_g.
        cost: its cost.
        history: the best cost after the initial evaluation and after every iteration.

    """

    position: np.ndarray
    cost: float
    history: np.ndarray


def minimise(
    cost: Callable[[np.ndarray], np.ndarray],
    x0: np.ndarray,
    v0: np.ndarray,
    iterations: int,
    rng: np.random.Generator,
    *,
    c1: float = 2.5,
    c2: float = 2.0,
    w_start: float = 1.0,
    w_end: float | None = None,
    u_max: float = np.inf,
) -> PSOResult:
    """Plain global-best PSO of dimensionless particles (no constraints).

    Args:
        cost: vectorised cost, ``(P, D) -> (P,)``.
        x0: ``(P, D)`` initial positions.
        v0: ``(P, D)`` initial velocities.
        iterations: t_max.
        rng: the random generator.
        c1: own-experience weight.
        c2: social weight.
        w_start: inertia at t = 0.
        w_end: inertia at t_max (None: constant ``w_start``).
        u_max: per-component velocity limit.

    """
    x = np.array(x0, dtype=float)
    u = np.array(v0, dtype=float)
    if x.ndim != 2 or u.shape != x.shape:
        raise ConfigError(f"x0 and v0 must be (P, D) arrays of one shape, got {x.shape}, {u.shape}")
    if iterations < 1:
        raise ConfigError(f"iterations must be >= 1, got {iterations}")
    best_cost = np.asarray(cost(x), dtype=float).copy()
    best_x = x.copy()
    g = int(np.argmin(best_cost))
    history = [best_cost[g]]
    w_end = w_start if w_end is None else w_end
    for t in range(1, iterations + 1):
        w = inertia_weight(t, iterations, w_start, w_end)
        u = velocity_update(u, x, best_x, best_x[g], rng, c1=c1, c2=c2, w=w, u_max=u_max)
        x = x + u
        g = update_bests(np.asarray(cost(x), dtype=float), x, best_cost, best_x)
        history.append(best_cost[g])
    return PSOResult(best_x[g].copy(), float(best_cost[g]), np.array(history))
