"""Noisy sensor models of the papers, vectorised over robots.

Stirling et al. (2010) Sect. 3.1 and App. B: four cardinal infrared distance sensors with range
S_r = 3.5 m and Gaussian noise of 5 cm; a relative-positioning sensor with range std 17 cm and
bearing std 6.1 deg at 3 m (Pugh et al. 2009). We scale the range noise linearly with range.
"""

import numpy as np

from abm.arena import Arena

__all__ = ["distance_sensors", "relative_positions"]


def distance_sensors(
    arena: Arena,
    points: np.ndarray,
    rng: np.random.Generator,
    max_range: float = 3.5,
    noise: float = 0.05,
) -> np.ndarray:
    """Noisy N/E/S/W wall distances ``(n, 4)`` (m), clipped to ``[0, max_range]``.

    A sensor that sees nothing within range reads ``max_range``.
    """
    true = arena.cardinal_distances(points, max_range)
    if noise > 0:
        true = true + rng.normal(0.0, noise, size=true.shape) * (true < max_range)
    return np.clip(true, 0.0, max_range)


def relative_positions(
    vectors: np.ndarray,
    rng: np.random.Generator,
    range_noise: float = 0.17,
    bearing_noise_deg: float = 6.1,
    reference_range: float = 3.0,
) -> np.ndarray:
    """Noisy measurement of relative position vectors ``(n, 2)``.

    Range noise has std ``range_noise * r / reference_range``; bearing noise has a constant std.
    """
    vectors = np.atleast_2d(np.asarray(vectors, dtype=float))
    r = np.hypot(vectors[:, 0], vectors[:, 1])
    theta = np.arctan2(vectors[:, 1], vectors[:, 0])
    r_noisy = r + rng.normal(0.0, 1.0, size=r.shape) * range_noise * r / reference_range
    theta_noisy = theta + rng.normal(0.0, np.deg2rad(bearing_noise_deg), size=theta.shape)
    r_noisy = np.maximum(r_noisy, 0.0)
    return np.stack([r_noisy * np.cos(theta_noisy), r_noisy * np.sin(theta_noisy)], axis=1)
