"""The HST world and start layout (README "Choices": room, start layout): the 20 m x 20 m room,
optionally with random axis-aligned boxes, or any bitmap; workers in a row (or around the centre)
with their scouts on a small circle around each.
"""

import numpy as np

from abm import portable
from abm.arena import Arena
from abm.errors import ConfigError, MapError
from models.environments import load_map
from models.hierarchy.params import WORLDS, HierarchyParams

__all__ = ["MIN_START_GAP", "build_world", "start_layout"]

#: Smallest distance between two start positions (m): a padded robot cell (3 cells of 0.10 m)
#: must not make another robot's start cell undrivable (README "Choices": start layout).
MIN_START_GAP = 0.3
#: Clearance kept free of boxes around every start position (m; ours).
BOX_CLEARANCE = 1.0


def start_layout(p: HierarchyParams, width: float, height: float, rng: np.random.Generator):
    """Start positions ``(workers (W, 2), scouts (W, S, 2))`` in m, snapped to cell centres.

    "row": workers ``worker_spacing`` apart, 1 m from the south wall, centred along it;
    "centre": the same row through the map's centre. Each worker's S scouts sit evenly on a
    circle of radius ``scout_ring`` around it. Each group (a worker and its scouts) is shifted
    by up to ``start_jitter`` per axis (from the model's generator) before snapping.

    Raises:
        ConfigError: the row does not fit the world, or two robots start closer than 0.3 m.

    """
    w, s = p.workers, p.scouts_per_worker
    span = (w - 1) * p.worker_spacing + 2 * (p.scout_ring + 0.5)
    if span > width:
        raise ConfigError(
            f"workers={w} at worker_spacing={p.worker_spacing} m need a {span:.1f} m wide row, "
            f"the world {p.world!r} is {width:g} m wide"
        )
    xs = width / 2 + (np.arange(w) - (w - 1) / 2) * p.worker_spacing
    y = 1.0 + p.scout_ring if p.start_layout == "row" else height / 2
    workers = np.stack([xs, np.full(w, y)], axis=1)
    angle = 2 * np.pi * np.arange(s) / s + np.pi / 2
    ring = p.scout_ring * np.stack([portable.cos(angle), portable.sin(angle)], axis=1)
    scouts = workers[:, None, :] + ring[None, :, :]
    shift = rng.uniform(-p.start_jitter, p.start_jitter, size=(w, 2))  # one per group
    workers = workers + shift
    scouts = scouts + shift[:, None, :]
    h = p.cell_size
    snapped = (np.floor(np.concatenate([workers, scouts.reshape(-1, 2)]) / h) + 0.5) * h
    gaps = np.hypot(*(snapped[:, None, :] - snapped[None, :, :]).transpose(2, 0, 1))
    np.fill_diagonal(gaps, np.inf)
    if gaps.min() < MIN_START_GAP - 1e-9:
        raise ConfigError(
            f"scout_ring={p.scout_ring} m with scouts_per_worker={s} (and worker_spacing="
            f"{p.worker_spacing} m) puts two robots {gaps.min():.2f} m apart; they need "
            f">= {MIN_START_GAP} m"
        )
    return snapped[:w], snapped[w:].reshape(w, s, 2)


def build_world(p: HierarchyParams, starts: np.ndarray, rng: np.random.Generator) -> Arena:
    """The ground-truth arena: the room (with ``boxes`` random boxes kept ``BOX_CLEARANCE``
    from every start position ``(k, 2)``) or the bitmap named by ``world``.

    Raises:
        ConfigError: an unreadable or malformed bitmap (naming ``world``).

    """
    if p.world not in WORLDS:
        try:
            return load_map(p.world, resolution=p.world_pixel)
        except (MapError, OSError, ValueError) as err:
            raise ConfigError(f"world {p.world!r} is not a usable map: {err}") from err
    n = int(round(p.world_size / p.world_pixel))
    free = np.ones((n, n), dtype=bool)
    side = max(1, int(round(p.box_size / p.world_pixel)))
    placed = 0
    for _attempt in range(100 * max(p.boxes, 1)):
        if placed == p.boxes:
            break
        ix, iy = rng.integers(0, n - side + 1, size=2)
        lo = np.array([ix, iy]) * p.world_pixel - BOX_CLEARANCE
        hi = np.array([ix + side, iy + side]) * p.world_pixel + BOX_CLEARANCE
        if np.any(np.all((starts >= lo) & (starts <= hi), axis=1)):
            continue
        free[iy : iy + side, ix : ix + side] = False
        placed += 1
    if placed < p.boxes:
        raise ConfigError(
            f"boxes={p.boxes} of box_size={p.box_size} m do not fit the room beside the start "
            f"positions (placed {placed})"
        )
    return Arena(free, p.world_pixel, name="room" if p.boxes == 0 else f"room+{p.boxes} boxes")
