"""Kinematic moves per time step, for models whose robots move in whole commands (turn, then
fly forward for one step) rather than under the continuous flight dynamics of
:mod:`abm.physics`.

Headings follow the compass: degrees clockwise from north, so a move of length d at heading
phi is ``d * (sin phi, cos phi)`` in (x, y). A move whose end point is not free, or whose
straight path enters a wall cell, does not happen (the bump model): the robot stays where it
is and the move is reported as blocked. So no robot ever enters or crosses a wall.
"""

import numpy as np

from abm import gridkernels, portable
from abm.arena import Arena

__all__ = ["bump_moves", "heading_vectors", "wrap_degrees"]


def wrap_degrees(angle: np.ndarray) -> np.ndarray:
    """Angles (deg) wrapped to (-180, 180]: a turn of 270 is a turn of -90."""
    return 180.0 - np.mod(180.0 - np.asarray(angle, dtype=float), 360.0)


def heading_vectors(heading: np.ndarray) -> np.ndarray:
    """Unit vectors ``(n, 2)`` of compass headings (degrees clockwise from north)."""
    rad = np.radians(np.asarray(heading, dtype=float))
    return np.stack([portable.sin(rad), portable.cos(rad)], axis=-1)


def bump_moves(
    arena: Arena, positions: np.ndarray, heading: np.ndarray, distance: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Move every robot ``distance`` (m) along its ``heading`` (deg), all at once.

    Returns:
        ``(positions, blocked)``: the new positions ``(n, 2)`` (the old one where blocked) and
        a boolean ``(n,)`` that is True where the move would have entered a wall.

    """
    positions = np.ascontiguousarray(np.atleast_2d(np.asarray(positions, dtype=float)))
    n = len(positions)
    return gridkernels.bump_moves(
        arena.padded,
        arena.walls_sat,
        arena.resolution,
        positions,
        _per_row(heading, n),
        _per_row(distance, n),
    )


def _per_row(values: np.ndarray, n: int) -> np.ndarray:
    """``values`` (one per row, or one for all) as a contiguous float ``(n,)`` array."""
    values = np.asarray(values, dtype=float)
    if values.shape == (n,) and values.flags.c_contiguous:
        return values
    return np.ascontiguousarray(np.broadcast_to(values, (n,)))
