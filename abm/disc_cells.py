"""Discs on a grid: the integer cell offsets a disc-shaped sensor or deposit covers."""

import numpy as np

from abm.errors import check_range

__all__ = ["disc_offsets"]


def disc_offsets(
    radius: float, resolution: float = 1.0, stride: int = 1, max_offset: int | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Integer cell offsets ``(dy, dx)`` of the cells whose centres lie within ``radius`` (m),
    on a lattice of every ``stride``-th cell (a coarser sensor).

    Args:
        radius: the disc's radius (m).
        resolution: cell side (m).
        stride: keep every ``stride``-th cell.
        max_offset: the largest ``|dx|``, ``|dy|`` to return; give the grid's larger side, as
            an offset beyond it lands on no cell of the grid from any cell (a disc larger than
            the world is the world, not an array too big for memory). None: no cap.

    """
    check_range("radius", radius, 0.0)
    check_range("stride", stride, 1, integer=True)
    r = int(np.floor(min(radius / resolution, np.iinfo(np.int32).max)))
    if max_offset is not None:
        r = min(r, int(max_offset))
    r -= r % stride
    dy, dx = np.mgrid[-r : r + 1 : stride, -r : r + 1 : stride]
    inside = np.hypot(dx, dy) * resolution <= radius + 1e-9
    return dy[inside].ravel(), dx[inside].ravel()
