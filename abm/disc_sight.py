"""Which cells of a disc a sensor at each grid cell can see, precomputed as a bit table.

A sensor at cell ``p`` sees the cell ``p + o`` (``o`` an offset of the disc) when the cell is
free and every cell on the digital line from ``p`` to it is free. The lines form a tree: the
line to ``o`` is the line to its parent ``round((L - 1) / L * o)`` (``L`` the Chebyshev length
of ``o``) plus ``o`` itself, so the whole table is one grid-wide AND per offset. A line moves at
most one cell per axis per step, so it cannot step over an axis-aligned wall one cell thick.

The table holds one row of ``ceil(k / 8)`` bytes per cell (``k`` offsets): a 40 m disc
(5,000 offsets) on a 100 x 100 m map at 1 m per cell takes about 6 MB.
"""

from functools import lru_cache

import numpy as np

from abm.errors import ConfigError

__all__ = ["cached_disc_visibility", "disc_parents", "disc_visibility", "visible_rows"]


def disc_parents(dy: np.ndarray, dx: np.ndarray) -> np.ndarray:
    """Index of each offset's parent on the digital line from (0, 0); -1 for (0, 0) itself.

    Raises:
        ConfigError: when the offsets lack (0, 0) or a parent (not a disc around the origin).

    """
    dy = np.asarray(dy, dtype=np.int64)
    dx = np.asarray(dx, dtype=np.int64)
    index = {(int(y), int(x)): i for i, (y, x) in enumerate(zip(dy, dx, strict=True))}
    if (0, 0) not in index:
        raise ConfigError("offsets must include (0, 0)")
    length = np.maximum(np.abs(dy), np.abs(dx))
    scale = np.where(length > 0, (length - 1) / np.maximum(length, 1), 0.0)
    py = np.floor(dy * scale + 0.5).astype(np.int64)
    px = np.floor(dx * scale + 0.5).astype(np.int64)
    parents = np.full(len(dy), -1, dtype=np.int64)
    for i in np.nonzero(length > 0)[0]:
        key = (int(py[i]), int(px[i]))
        if key not in index:
            raise ConfigError(f"offset {(int(dy[i]), int(dx[i]))} has no parent {key} in the set")
        parents[i] = index[key]
    return parents


def disc_visibility(
    free: np.ndarray, dy: np.ndarray, dx: np.ndarray, chunk_rows: int = 16
) -> np.ndarray:
    """Visibility bits ``(rows * cols, ceil(k / 8))`` (``np.packbits`` rows, row-major cells).

    Bit ``j`` of cell ``c``'s row says whether a sensor at ``c`` sees offset ``j``
    (``dy[j], dx[j]``). A cell outside the grid counts as a wall; a wall cell sees nothing.

    Args:
        free: boolean ``(rows, cols)`` grid, True = free.
        dy: the disc's integer row offsets (they must include (0, 0)).
        dx: the disc's integer column offsets, paired with ``dy``.
        chunk_rows: grid rows per pass (bounds the working memory to
            ``k * chunk_rows * cols`` bytes).

    """
    free = np.asarray(free, dtype=bool)
    rows, cols = free.shape
    dy = np.asarray(dy, dtype=np.int64)
    dx = np.asarray(dx, dtype=np.int64)
    parents = disc_parents(dy, dx)
    order = np.argsort(np.maximum(np.abs(dy), np.abs(dx)), kind="stable")
    r = int(max(np.abs(dy).max(), np.abs(dx).max()))
    padded = np.pad(free, r)
    k = len(dy)
    out = np.empty((rows * cols, (k + 7) // 8), dtype=np.uint8)
    for top in range(0, rows, chunk_rows):
        h = min(chunk_rows, rows - top)
        vis = np.empty((k, h, cols), dtype=bool)
        for j in order:
            y0 = r + top + dy[j]
            x0 = r + dx[j]
            cells = padded[y0 : y0 + h, x0 : x0 + cols]
            vis[j] = cells if parents[j] < 0 else vis[parents[j]] & cells
        out[top * cols : (top + h) * cols] = np.packbits(vis.reshape(k, -1), axis=0).T
    return out


def cached_disc_visibility(free: np.ndarray, dy: np.ndarray, dx: np.ndarray) -> np.ndarray:
    """:func:`disc_visibility`, remembered for the last few (grid, disc) pairs of the process
    (the runs of a sweep on one map share one table). Do not write to the result.
    """
    free = np.ascontiguousarray(free, dtype=bool)
    dy = np.ascontiguousarray(dy, dtype=np.int64)
    dx = np.ascontiguousarray(dx, dtype=np.int64)
    return _cached(free.shape, free.tobytes(), dy.tobytes(), dx.tobytes())


@lru_cache(maxsize=4)
def _cached(shape: tuple[int, int], free: bytes, dy: bytes, dx: bytes) -> np.ndarray:
    table = disc_visibility(
        np.frombuffer(free, dtype=bool).reshape(shape),
        np.frombuffer(dy, dtype=np.int64),
        np.frombuffer(dx, dtype=np.int64),
    )
    table.flags.writeable = False
    return table


def visible_rows(table: np.ndarray, cells: np.ndarray, k: int) -> np.ndarray:
    """Unpacked visibility ``(n, k)`` of the flat cell indices ``cells`` from a table."""
    return np.unpackbits(table[cells], axis=1, count=k).view(bool)
