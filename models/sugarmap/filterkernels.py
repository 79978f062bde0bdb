"""Compiled (numba) kernels of the particle filters' per-tick work (eqs. 3-11).

A tick of the filters was a few dozen numpy calls per explorer on arrays of ten particles or a
handful of anchors, where numpy's per-call overhead, not the arithmetic, took most of a run.
Each kernel here is one loop doing the same arithmetic in the same order as those calls, so
every result is bit for bit what numpy gave and no decision of a run changes:

- a sum over a contiguous row is numpy's pairwise summation (:func:`pairwise_sum`), which
  ``ndarray.sum`` and ``mean`` use on such rows;
- degrees become radians as ``x * (pi / 180)``, numpy's ``radians``; sin and cos are
  :mod:`abm.portable`'s (the ufuncs the numpy code called are built from the same kernels);
- a product over explorers multiplies in explorer order, as numpy's reduction over the first
  axis does.

Symbols as :mod:`models.sugarmap.particles`: N particles, e explorer, i particle, j stored
signature.
"""

import math

import numpy as np
from numba import njit

from abm.portable import cos_scalar, sin_scalar

__all__ = [
    "eq7_distances",
    "eq8_weights",
    "global_map",
    "map_scores",
    "mark",
    "nearest_signature",
    "pairwise_sum",
    "predict",
    "resample",
]

#: numpy's block below which a pairwise sum is a plain loop (``PW_BLOCKSIZE``).
_BLOCK = 128
#: radians per degree, as numpy's ``radians`` multiplies by it.
_RAD = math.pi / 180.0


@njit(cache=True)
def _block_sum(a, start, n):
    """The pairwise sum of ``a[start : start + n]`` as numpy does it for n <= 128: below 8
    values one by one, else in eight running sums combined as a tree, then the rest.
    """
    if n < 8:
        total = 0.0
        for k in range(start, start + n):
            total += a[k]
        return total
    r0, r1, r2, r3 = a[start], a[start + 1], a[start + 2], a[start + 3]
    r4, r5, r6, r7 = a[start + 4], a[start + 5], a[start + 6], a[start + 7]
    k = start + 8
    end = start + n - n % 8
    while k < end:
        r0 += a[k]
        r1 += a[k + 1]
        r2 += a[k + 2]
        r3 += a[k + 3]
        r4 += a[k + 4]
        r5 += a[k + 5]
        r6 += a[k + 6]
        r7 += a[k + 7]
        k += 8
    total = ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))
    for k in range(end, start + n):
        total += a[k]
    return total


@njit(cache=True)
def _half(n):
    """Where numpy splits a pairwise sum of n > 128 values: half, down to a multiple of 8."""
    h = n // 2
    return h - h % 8


@njit(cache=True)
def pairwise_sum(a: np.ndarray, start: int, n: int) -> float:
    """The sum of ``a[start : start + n]`` (1-D) in numpy's pairwise order: blocks of up to
    128 values (:func:`_block_sum`); a longer range is split in two (:func:`_half`), each
    half summed so and the two added. The split is walked with an explicit stack (numba
    cannot cache a recursive kernel).
    """
    if n <= _BLOCK:
        return _block_sum(a, start, n)
    depth = 64  # a split at least halves the range: 2**64 values
    starts = np.empty(depth, dtype=np.int64)
    sizes = np.empty(depth, dtype=np.int64)
    left = np.empty(depth)
    on_right = np.zeros(depth, dtype=np.bool_)
    starts[0], sizes[0], top = start, n, 1
    value, returning = 0.0, False
    while True:
        i = top - 1
        if not returning:  # descend into the range on top of the stack
            if sizes[i] <= _BLOCK:
                value, returning = _block_sum(a, starts[i], sizes[i]), True
                top -= 1
            else:
                starts[top], sizes[top], on_right[top] = starts[i], _half(sizes[i]), False
                top += 1
        elif top == 0:
            return value
        elif not on_right[i]:  # the left half is done: keep it, descend into the right
            left[i], on_right[i] = value, True
            h = _half(sizes[i])
            starts[top], sizes[top], on_right[top] = starts[i] + h, sizes[i] - h, False
            top += 1
            returning = False
        else:  # both halves done
            value = left[i] + value
            top -= 1


@njit(cache=True)
def predict(
    z_phi, z_v, heading, turn, speed, moved, dt, turn_noise, speed_noise, accumulate, phi, pos
):
    """F1's motion (eqs. 3, 5, 6) of every particle, in place on ``phi`` and ``pos``.

    ``z_phi``, ``z_v`` ``(n_e, N)`` are the standard-normal draws of the turn and speed noise;
    the noise is ``z_phi * (turn_noise |Delta_k|)`` and ``z_v * (speed_noise v_k)``. The
    heading is ``phi_k + n_phi`` (H-lit) or ``phi + Delta_k + n_phi`` (H-acc); a particle of an
    explorer that moved flies ``max(v_k + n_v, 0) dt`` along ``(sin phi, cos phi)``.
    """
    for e in range(phi.shape[0]):
        sd_phi = turn_noise * abs(turn[e])
        sd_v = speed_noise * speed[e]
        duration = dt * (1.0 if moved[e] else 0.0)
        for i in range(phi.shape[1]):
            n_phi = z_phi[e, i] * sd_phi
            n_v = z_v[e, i] * sd_v
            if accumulate:
                phi[e, i] = phi[e, i] + turn[e] + n_phi
            else:
                phi[e, i] = heading[e] + n_phi
            step = max(speed[e] + n_v, 0.0) * duration
            rad = phi[e, i] * _RAD
            pos[e, i, 0] += step * sin_scalar(rad)
            pos[e, i, 1] += step * cos_scalar(rad)


@njit(cache=True)
def mark(pos, localmap, counts, origin_x, origin_y, cell):
    """Eq. 4: every particle marks the cell it is in, ``floor((p - origin) / D)`` clipped into
    the grid, in its LocalMap; ``counts[e, iy, ix]`` (N x NodeMap) counts each first mark.
    """
    rows, cols = localmap.shape[2], localmap.shape[3]
    for e in range(pos.shape[0]):
        for i in range(pos.shape[1]):
            ix = min(max(int(math.floor((pos[e, i, 0] - origin_x) / cell)), 0), cols - 1)
            iy = min(max(int(math.floor((pos[e, i, 1] - origin_y) / cell)), 0), rows - 1)
            if not localmap[e, i, iy, ix]:
                localmap[e, i, iy, ix] = True
                counts[e, iy, ix] += 1


@njit(cache=True)
def nearest_signature(signature, stored, stored_at, now, min_age, rms):
    """Eq. 11 to each of the ``stored`` signatures ``(S, N_a)``: the first nearest one at
    least ``min_age`` old and its distance, ``(j, f)``; ``(0, inf)`` when none has an anchor
    in common or is old enough (as ``argmin`` of all-infinite distances).

    ``f = sqrt(sum of squared differences over the anchors both saw) / max(scale, 1)`` with
    scale their number ``n`` (``rms`` False, the paper's count) or ``sqrt(n)``; inf for n = 0.
    """
    n_a = signature.shape[0]
    squares = np.empty(n_a)
    best, best_j = math.inf, 0
    for j in range(stored.shape[0]):
        common = 0
        for a in range(n_a):
            if math.isnan(signature[a]) or math.isnan(stored[j, a]):
                squares[a] = 0.0
            else:
                d = signature[a] - stored[j, a]
                squares[a] = d * d
                common += 1
        if common == 0 or now - stored_at[j] < min_age:
            continue
        scale = math.sqrt(common) if rms else float(common)
        f = math.sqrt(pairwise_sum(squares, 0, n_a)) / max(scale, 1.0)
        if f < best:
            best, best_j = f, j
    return best_j, best


@njit(cache=True)
def eq7_distances(pos, store, j):
    """Eq. 7: each particle's distance ``||pos_i - Store_i[j]||`` (m), ``(N,)``."""
    delta = np.empty(pos.shape[0])
    for i in range(pos.shape[0]):
        delta[i] = math.hypot(pos[i, 0] - store[i, j, 0], pos[i, 1] - store[i, j, 1])
    return delta


@njit(cache=True)
def eq8_weights(delta):
    """Eq. 8 normalised, ``(sum delta - delta_i) / (sum delta (N - 1))``; uniform when N = 1
    or every delta is 0 (README "Choices": eq. 8's weights).
    """
    n = delta.shape[0]
    total = pairwise_sum(delta, 0, n)
    if n == 1 or total == 0:
        return np.full(n, 1.0 / n)
    return (total - delta) / (total * (n - 1))


@njit(cache=True)
def resample(weights, u, pos, phi, localmap, store, n_stored, counts):
    """Multinomial resampling of one explorer's particles in place: particle i becomes the
    particle whose cumulative normalised weight first exceeds ``u[i]`` (inverse CDF), with its
    position, heading, LocalMap and first ``n_stored`` Store entries; ``counts`` (N x NodeMap)
    is counted again from the new LocalMaps.
    """
    n = weights.shape[0]
    cdf = np.cumsum(weights)
    cdf = cdf / cdf[n - 1]
    pick = np.searchsorted(cdf, u, side="right")
    pos[:] = pos[pick]
    phi[:] = phi[pick]
    store[:, :n_stored] = store[pick, :n_stored]
    before = localmap.reshape(n, -1).copy()
    after = localmap.reshape(n, -1)
    total = counts.reshape(-1)
    total[:] = 0
    for i in range(n):
        source = before[pick[i]]
        for c in range(total.shape[0]):
            after[i, c] = source[c]
            total[c] += source[c]


@njit(cache=True)
def global_map(counts, n):
    """Eq. 10 from eq. 9's counts: ``G = 1 - prod_e (1 - counts_e / N)``, ``(H, W)``."""
    out = np.empty(counts.shape[1:])
    for iy in range(counts.shape[1]):
        for ix in range(counts.shape[2]):
            p = 1.0
            for e in range(counts.shape[0]):
                p *= 1.0 - counts[e, iy, ix] / n
            out[iy, ix] = 1.0 - p
    return out


@njit(cache=True)
def map_scores(estimate, free, covered, cover_th):
    """The brain's map against the truth over the navigable cells (``free``, row-major, as
    ``estimate[free]`` orders them): the share with ``G >= cover_th`` and the mean of
    ``|G - truth|`` (``covered`` the true coverage raster), as numpy's ``mean`` gives them.
    """
    error = np.empty(free.size)
    n, count = 0, 0
    for iy in range(free.shape[0]):
        for ix in range(free.shape[1]):
            if free[iy, ix]:
                g = estimate[iy, ix]
                count += g >= cover_th
                error[n] = abs(g - (1.0 if covered[iy, ix] else 0.0))
                n += 1
    return count / n, pairwise_sum(error, 0, n) / n
