"""Polygonal obstacles in the plane: inside tests, segment blocking and pushing points out,
vectorised over many points or segments at once.

A polygon is an ``(m, 2)`` array of vertices (m) in either orientation; several polygons are
a list of them. These are the no-fly zones of a planner (:mod:`abm.visibility_graph`) or any model
whose obstacles are shapes rather than grid cells. "Inside" is the open interior: points on an
edge are outside, so a path may run along an edge.
"""

from collections.abc import Sequence

import numba
import numpy as np

from abm.errors import ConfigError

__all__ = [
    "as_polygon",
    "edge_distance2",
    "inside_any",
    "inside_padded",
    "padded",
    "inside_polygon",
    "offset_polygon",
    "push_outside",
    "segments_blocked",
]

_EPS = 1e-9


def as_polygon(vertices: object, name: str = "polygon") -> np.ndarray:
    """The vertices as a float ``(m, 2)`` array, counter-clockwise.

    Raises:
        ConfigError: fewer than 3 vertices, wrong shape, or zero area (naming ``name``).

    """
    poly = np.asarray(vertices, dtype=float)
    if poly.ndim != 2 or poly.shape[1] != 2 or len(poly) < 3:
        raise ConfigError(f"{name} must be 3 or more (x, y) vertices, got shape {poly.shape}")
    area = _signed_area(poly)
    if abs(area) < _EPS:
        raise ConfigError(f"{name} has zero area: {poly.tolist()}")
    return poly if area > 0 else poly[::-1].copy()


def _signed_area(poly: np.ndarray) -> float:
    x, y = poly[:, 0], poly[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def offset_polygon(poly: np.ndarray, distance: float) -> np.ndarray:
    """The polygon grown by ``distance`` (m): every edge moved outward, mitred corners.

    For a convex polygon the result contains every point within ``distance`` of it (the
    mitred corners add a little more); it is how a planner keeps a robot's radius clear.
    """
    poly = as_polygon(poly)
    if distance == 0:
        return poly
    nxt = np.roll(poly, -1, axis=0)
    edge = nxt - poly
    normal = np.stack([edge[:, 1], -edge[:, 0]], axis=1)  # outward for counter-clockwise
    normal /= np.linalg.norm(normal, axis=1, keepdims=True)
    prev_normal = np.roll(normal, 1, axis=0)
    bisector = normal + prev_normal
    cos_half = np.einsum("ij,ij->i", bisector / np.linalg.norm(bisector, axis=1)[:, None], normal)
    mitre = bisector / np.linalg.norm(bisector, axis=1)[:, None] * (distance / cos_half)[:, None]
    return poly + mitre


def inside_polygon(points: np.ndarray, poly: np.ndarray) -> np.ndarray:
    """Which ``(..., 2)`` points lie in the open interior of ``poly`` (even-odd rule)."""
    p = np.asarray(points, dtype=float)
    x, y = p[..., 0, None], p[..., 1, None]
    a, b = poly, np.roll(poly, -1, axis=0)
    crosses = (a[:, 1] > y) != (b[:, 1] > y)
    with np.errstate(divide="ignore", invalid="ignore"):
        x_at = a[:, 0] + (y - a[:, 1]) * (b[:, 0] - a[:, 0]) / (b[:, 1] - a[:, 1])
    inside = (np.count_nonzero(crosses & (x < x_at), axis=-1) % 2).astype(bool)
    if inside.any():  # the rule may count a point on an edge as inside: it is not
        inside[inside] = ~_on_boundary(p[inside], poly)
    return inside


def _on_boundary(p: np.ndarray, poly: np.ndarray, tol: float = 1e-9) -> np.ndarray:
    a, b = poly, np.roll(poly, -1, axis=0)
    ab = b - a
    ap = p[:, None, :] - a
    t = np.clip(np.einsum("kij,ij->ki", ap, ab) / np.einsum("ij,ij->i", ab, ab), 0.0, 1.0)
    gap = ap - t[..., None] * ab
    return (np.einsum("kij,kij->ki", gap, gap) <= tol * tol).any(axis=-1)


def inside_any(points: np.ndarray, polygons: Sequence[np.ndarray]) -> np.ndarray:
    """Which points lie inside at least one of the polygons."""
    p = np.asarray(points, dtype=float)
    out = np.zeros(p.shape[:-1], dtype=bool)
    for poly in polygons:
        out |= inside_polygon(p, poly)
    return out


def padded(polygons: Sequence[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """The polygons as one ``(k, v, 2)`` array (padded with zeros) and their vertex counts,
    the form the compiled tests take.
    """
    width = max((len(p) for p in polygons), default=3)
    out = np.zeros((len(polygons), width, 2))
    for i, poly in enumerate(polygons):
        out[i, : len(poly)] = poly
    return out, np.array([len(p) for p in polygons], dtype=np.int64)


@numba.njit(cache=True)
def inside_padded(x: float, y: float, polys: np.ndarray, counts: np.ndarray) -> bool:
    """Whether (x, y) lies in the open interior of one of the padded polygons (compiled)."""
    for z in range(polys.shape[0]):
        m = counts[z]
        inside = False
        for a in range(m):
            b = (a + 1) % m
            ya, yb = polys[z, a, 1], polys[z, b, 1]
            if (ya > y) != (yb > y):
                xa, xb = polys[z, a, 0], polys[z, b, 0]
                if x < xa + (y - ya) * (xb - xa) / (yb - ya):
                    inside = not inside
        if not inside:
            continue
        # the even-odd rule may count a point on an edge: it is outside
        if edge_distance2(x, y, polys[z], m) > 1e-18:
            return True
    return False


@numba.njit(cache=True)
def edge_distance2(x: float, y: float, poly: np.ndarray, m: int) -> float:
    """Squared distance (m^2) from (x, y) to the nearest edge of ``poly``'s first ``m``
    vertices (a closed ring).
    """
    best = np.inf
    for a in range(m):
        b = (a + 1) % m
        ax, ay = poly[a, 0], poly[a, 1]
        ex, ey = poly[b, 0] - ax, poly[b, 1] - ay
        t = min(1.0, max(0.0, ((x - ax) * ex + (y - ay) * ey) / (ex * ex + ey * ey)))
        gx, gy = x - ax - t * ex, y - ay - t * ey
        best = min(best, gx * gx + gy * gy)
    return best


@numba.njit(cache=True)
def _blocked(s, e, polys, counts, out):
    for q in range(s.shape[0]):
        sx, sy, ex_, ey_ = s[q, 0], s[q, 1], e[q, 0], e[q, 1]
        hit = False
        for z in range(polys.shape[0]):
            m = counts[z]
            for a in range(m):
                b = (a + 1) % m
                ax, ay, bx, by = polys[z, a, 0], polys[z, a, 1], polys[z, b, 0], polys[z, b, 1]
                d1 = (bx - ax) * (sy - ay) - (by - ay) * (sx - ax)
                d2 = (bx - ax) * (ey_ - ay) - (by - ay) * (ex_ - ax)
                d3 = (ex_ - sx) * (ay - sy) - (ey_ - sy) * (ax - sx)
                d4 = (ex_ - sx) * (by - sy) - (ey_ - sy) * (bx - sx)
                if d1 * d2 < -_EPS and d3 * d4 < -_EPS:
                    hit = True
                    break
            if hit:
                break
        if not hit:
            hit = (
                inside_padded(0.5 * (sx + ex_), 0.5 * (sy + ey_), polys, counts)
                or inside_padded(sx, sy, polys, counts)
                or inside_padded(ex_, ey_, polys, counts)
            )
        out[q] = hit


def segments_blocked(
    starts: np.ndarray, ends: np.ndarray, polygons: Sequence[np.ndarray]
) -> np.ndarray:
    """Which segments ``starts[i] -> ends[i]`` pass through the interior of a polygon.

    A segment is blocked when it properly crosses an edge, or when a point of it (its end
    points or midpoint) lies inside: touching a vertex or running along an edge is allowed.
    """
    s, e = np.broadcast_arrays(np.asarray(starts, dtype=float), np.asarray(ends, dtype=float))
    out = np.zeros(s.shape[:-1], dtype=bool)
    if not len(polygons) or not out.size:
        return out
    polys, counts = padded(polygons)
    flat = np.empty(out.size, dtype=bool)
    _blocked(np.array(s.reshape(-1, 2)), np.array(e.reshape(-1, 2)), polys, counts, flat)
    return flat.reshape(out.shape)


def push_outside(
    points: np.ndarray, polygons: Sequence[np.ndarray], margin: float = 1e-6
) -> tuple[np.ndarray, np.ndarray]:
    """Move every point inside a polygon to the nearest point of its boundary plus ``margin``
    outward (m); points outside stay.

    Returns:
        The moved points and a mask of the points that were inside.

    """
    p = np.array(points, dtype=float, copy=True)
    moved = np.zeros(p.shape[:-1], dtype=bool)
    for poly in polygons:
        inside = inside_polygon(p, poly)
        if not inside.any():
            continue
        q = p[inside]
        a, b = poly, np.roll(poly, -1, axis=0)
        ab = b - a
        aq = q[:, None, :] - a
        t = np.clip(np.einsum("kij,ij->ki", aq, ab) / np.einsum("ij,ij->i", ab, ab), 0.0, 1.0)
        nearest = a + t[..., None] * ab
        gap = np.linalg.norm(nearest - q[:, None, :], axis=-1)
        k = np.argmin(gap, axis=1)
        rows = np.arange(len(q))
        target = nearest[rows, k]
        edge = ab[k]
        outward = np.stack([edge[:, 1], -edge[:, 0]], axis=1)
        outward /= np.linalg.norm(outward, axis=1, keepdims=True)
        p[inside] = target + margin * outward
        moved |= inside
    return p, moved
