"""Noisy sensor models, vectorised over robots; every constant comes from the caller (a
model's params), so the same models serve any robot.

- distance sensors: the distance to the first wall along a ray, with Gaussian noise, clipped
  to the sensor's range (a sensor that sees nothing reads its range);
- relative positioning: the vector to another robot measured with a range error whose std
  grows linearly with range (``range_noise`` at ``reference_range``) and a constant bearing
  error.

The per-reading models are compiled scalar functions (:func:`noisy_reading`,
:func:`measured_relative`) so that compiled controllers apply exactly the same models as the
numpy-facing functions here; the random numbers always come from the model's generator.
"""

import math

import numpy as np
from numba import njit

from abm.arena import Arena
from abm.portable import atan2_scalar, cos_scalar, sin_scalar

__all__ = [
    "distance_sensors",
    "measured_relative",
    "noisy_reading",
    "ray_sensors",
    "relative_positions",
]


@njit(cache=True, inline="always")
def noisy_reading(true: float, z: float, noise: float, max_range: float) -> float:
    """A distance sensor's reading of a wall at ``true`` m, given a standard normal draw ``z``.

    A sensor that sees nothing within range reads ``max_range`` (no noise is added then).
    """
    value = true + z * noise if true < max_range else true
    return min(max(value, 0.0), max_range)


@njit(cache=True, inline="always")
def measured_relative(
    dx: float,
    dy: float,
    z_range: float,
    z_bearing: float,
    range_noise: float,
    bearing_noise: float,
    reference_range: float,
) -> tuple[float, float]:
    """Measured relative position of a robot at ``(dx, dy)``, given two standard normal draws.

    Range noise std ``range_noise * r / reference_range``; bearing noise std ``bearing_noise``
    (radians).
    """
    r = math.hypot(dx, dy)
    theta = atan2_scalar(dy, dx) + z_bearing * bearing_noise
    r = max(r + z_range * range_noise * r / reference_range, 0.0)
    return r * cos_scalar(theta), r * sin_scalar(theta)


@njit(cache=True)
def _noisy_readings(true, z, noise, max_range):
    out = np.empty_like(true)
    for i in range(true.shape[0]):
        for d in range(true.shape[1]):
            out[i, d] = noisy_reading(true[i, d], z[i, d], noise, max_range)
    return out


@njit(cache=True)
def _measured_relatives(vectors, z, range_noise, bearing_noise, reference_range):
    out = np.empty_like(vectors)
    for i in range(vectors.shape[0]):
        out[i, 0], out[i, 1] = measured_relative(
            vectors[i, 0],
            vectors[i, 1],
            z[i, 0],
            z[i, 1],
            range_noise,
            bearing_noise,
            reference_range,
        )
    return out


def distance_sensors(
    arena: Arena,
    points: np.ndarray,
    rng: np.random.Generator,
    max_range: float,
    noise: float,
) -> np.ndarray:
    """Noisy N/E/S/W wall distances ``(n, 4)`` (m), clipped to ``[0, max_range]``.

    A sensor that sees nothing within range reads ``max_range``.
    """
    return _with_noise(arena.cardinal_distances(points, max_range), rng, max_range, noise)


def ray_sensors(
    arena: Arena,
    origins: np.ndarray,
    directions: np.ndarray,
    rng: np.random.Generator,
    max_range: float,
    noise: float,
) -> np.ndarray:
    """Noisy wall distances ``(n,)`` along arbitrary rays: the distance sensors' model."""
    true = arena.raycast(origins, directions, max_range)
    return _with_noise(true[:, None], rng, max_range, noise)[:, 0]


def _with_noise(
    true: np.ndarray, rng: np.random.Generator, max_range: float, noise: float
) -> np.ndarray:
    if noise <= 0:
        return true
    return _noisy_readings(true, rng.standard_normal(true.shape), float(noise), float(max_range))


def relative_positions(
    vectors: np.ndarray,
    rng: np.random.Generator,
    range_noise: float,
    bearing_noise: float,
    reference_range: float,
) -> np.ndarray:
    """Noisy measurement of relative position vectors ``(n, 2)``.

    Range noise has std ``range_noise * r / reference_range``; bearing noise has a constant std
    of ``bearing_noise`` radians.
    """
    vectors = np.ascontiguousarray(np.atleast_2d(np.asarray(vectors, dtype=float)))
    return _measured_relatives(
        vectors,
        rng.standard_normal(vectors.shape),
        float(range_noise),
        float(bearing_noise),
        float(reference_range),
    )
