"""Shortest paths around polygonal obstacles on a visibility graph, many queries at once.

The graph's nodes are the obstacles' vertices grown by a clearance (a robot's radius), its
edges the pairs of nodes that see each other (networkx); all shortest node-to-node routes are
computed once when the planner is built. A query then only needs which nodes its start and goal
see: the route is the best ``start -> a -> ... -> b -> goal`` over all visible pairs (a, b),
found for every query of a batch in one array operation. Any model whose robots fly around no-fly
zones can use it.
"""

from collections.abc import Sequence
from dataclasses import dataclass

import networkx as nx
import numpy as np

from abm.polygons import as_polygon, offset_polygon, segments_blocked

__all__ = ["Paths", "VisibilityPlanner"]

#: Nodes sit this much (m) outside the grown obstacles, so edges along them are not blocked.
NODE_GAP = 1e-6


@dataclass(frozen=True)
class Paths:
    """A batch of planar polylines, padded to one length.

    Attributes:
        points: ``(q, w, 2)`` waypoints (m); each path starts at its start and ends at its
            goal, then repeats the goal up to ``w``.
        count: ``(q,)`` waypoints in use per path (2 for a straight line).
        length: ``(q,)`` path lengths (m); ``inf`` when the goal cannot be reached (the path
            is then the start alone).
        direct: ``(q,)`` True where the straight line was free.

    """

    points: np.ndarray
    count: np.ndarray
    length: np.ndarray
    direct: np.ndarray


class VisibilityPlanner:
    """Plans shortest planar paths that keep ``clearance`` (m) from the obstacles.

    Args:
        obstacles: polygons (vertex arrays, m) a path must not enter.
        clearance: how far paths keep from the obstacles (m), e.g. a robot's radius; the
            obstacles are grown by it (mitred corners).

    """

    def __init__(self, obstacles: Sequence[np.ndarray], clearance: float = 0.0) -> None:
        polys = [as_polygon(p, f"obstacle {i}") for i, p in enumerate(obstacles)]
        #: The grown obstacles every path avoids.
        self.grown = [offset_polygon(p, clearance) for p in polys]
        self.clearance = float(clearance)
        nodes = [offset_polygon(p, clearance + NODE_GAP) for p in polys]
        self.nodes = np.concatenate(nodes) if nodes else np.zeros((0, 2))
        v = len(self.nodes)
        graph = nx.Graph()
        graph.add_nodes_from(range(v))
        if v:
            a, b = np.triu_indices(v, 1)
            free = ~segments_blocked(self.nodes[a], self.nodes[b], self.grown)
            for i, j in zip(a[free], b[free], strict=True):
                graph.add_edge(
                    int(i), int(j), weight=float(np.hypot(*(self.nodes[i] - self.nodes[j])))
                )
        #: The visibility graph among the nodes (weights = lengths, m).
        self.graph = graph
        self.distance = np.full((v, v), np.inf)
        routes = dict(nx.all_pairs_dijkstra_path(graph, weight="weight"))
        longest = max((len(r) for rs in routes.values() for r in rs.values()), default=0)
        self.route = np.zeros((v, v, max(longest, 1)), dtype=np.int64)
        self.route_len = np.zeros((v, v), dtype=np.int64)
        for i, rs in routes.items():
            for j, route in rs.items():
                self.route[i, j, : len(route)] = route
                self.route_len[i, j] = len(route)
                self.distance[i, j] = sum(
                    np.hypot(*(self.nodes[route[k + 1]] - self.nodes[route[k]]))
                    for k in range(len(route) - 1)
                )

    def blocked(self, starts: np.ndarray, goals: np.ndarray) -> np.ndarray:
        """Which straight segments enter a grown obstacle."""
        return segments_blocked(starts, goals, self.grown)

    def plan(self, starts: np.ndarray, goals: np.ndarray) -> Paths:
        """Shortest paths from every ``starts[i]`` to ``goals[i]`` (``(q, 2)`` arrays, m).

        Start and goal must lie outside the grown obstacles; a goal that cannot be reached
        gives a path of length ``inf`` that stays at the start.
        """
        s = np.asarray(starts, dtype=float).reshape(-1, 2)
        g = np.asarray(goals, dtype=float).reshape(-1, 2)
        q, v = len(s), len(self.nodes)
        direct = ~self.blocked(s, g)
        width = 2 + (self.route.shape[2] if v else 0)
        points = np.repeat(g[:, None, :], width, axis=1)
        points[:, 0] = s
        count = np.full(q, 2, dtype=np.int64)
        length = np.hypot(*(g - s).T)
        around = np.nonzero(~direct)[0]
        if len(around) and v:
            ss, gg = s[around], g[around]
            sees_s = ~segments_blocked(ss[:, None, :], self.nodes[None], self.grown)
            sees_g = ~segments_blocked(gg[:, None, :], self.nodes[None], self.grown)
            to_a = np.where(sees_s, np.linalg.norm(self.nodes[None] - ss[:, None], axis=-1), np.inf)
            from_b = np.where(
                sees_g, np.linalg.norm(self.nodes[None] - gg[:, None], axis=-1), np.inf
            )
            total = to_a[:, :, None] + self.distance[None] + from_b[:, None, :]
            best = total.reshape(len(around), -1).argmin(axis=1)
            a, b = np.divmod(best, v)
            length[around] = total.reshape(len(around), -1)[np.arange(len(around)), best]
            n_route = self.route_len[a, b]
            steps = np.arange(self.route.shape[2])
            inner = self.nodes[self.route[a, b]]  # (k, longest, 2)
            keep = steps[None, :] < n_route[:, None]
            inner = np.where(keep[..., None], inner, gg[:, None, :])
            points[around, 1:-1] = inner
            count[around] = n_route + 2
            lost = ~np.isfinite(length[around])
            points[around[lost]] = s[around[lost], None, :]
            count[around[lost]] = 1
        elif len(around):
            length[around] = np.inf
            points[around] = s[around, None, :]
            count[around] = 1
        return Paths(points, count, length, direct)
