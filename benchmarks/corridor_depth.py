"""How deep our corridor worlds are, and what the paper's complete-coverage rates need.

For generated 40-cell corridor worlds (``models.environments.make_world``) this prints, per
complexity:
branch count, the longest path from the base (cells), the depths of the dead ends, and the
share of worlds within the two bounds of ``models.beacon_explorer.diagnose`` for 20 explorers
(the path bound: deepest cell <= 20; the perfect depth-first search under the paper's rules).
A search cannot complete more often than its bound allows, so the paper's complete-coverage
rates (38.5 / 64.2 / 74.3 %) are lower limits on the share of the paper's worlds within it.
The same trees with the base at their centre (the cell nearest every dead end) show how much
the start cell decides.

Usage: python benchmarks/corridor_depth.py [--worlds 2000] [--seed 700000]
"""

import argparse

import networkx as nx
import numpy as np

from models.beacon_explorer.diagnose import cell_depths, paper_dfs_completes
from models.beacon_explorer.published import COMPLETE
from models.environments import World, make_world
from models.environments.world import world_from_cells

N_ROBOTS = 20


def at_centre(world: World) -> World:
    """The same corridor with the base at its centre (least eccentricity; ties: lowest cell)."""
    cells = [tuple(int(v) for v in c) for c in world.cells]
    graph = nx.Graph()
    graph.add_nodes_from(cells)
    graph.add_edges_from(
        (c, (c[0] + dx, c[1] + dy))
        for c in cells
        for dx, dy in ((1, 0), (0, 1))
        if (c[0] + dx, c[1] + dy) in graph
    )
    centre = min(nx.center(graph))
    return world_from_cells(cells, centre, "corridor", world.complexity, world.branches, 3.0)


def stats(worlds: list[World]) -> dict[str, float]:
    deepest, ends, path, dfs = [], [], 0, 0
    for world in worlds:
        depth = cell_depths(world)
        cells = set(depth)
        deepest.append(max(depth.values()))
        for (x, y), d in depth.items():
            degree = sum((x + dx, y + dy) in cells for dx, dy in ((0, 1), (1, 0), (0, -1), (-1, 0)))
            if degree == 1 and d > 0:
                ends.append(d)
        path += deepest[-1] <= N_ROBOTS
        dfs += paper_dfs_completes(world, N_ROBOTS)
    n = len(worlds)
    return {
        "branches": float(np.mean([w.branches for w in worlds])),
        "deepest": float(np.mean(deepest)),
        "deepest_p10": float(np.percentile(deepest, 10)),
        "deepest_p90": float(np.percentile(deepest, 90)),
        "dead_end": float(np.mean(ends)),
        "path": 100 * path / n,
        "dfs": 100 * dfs / n,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--worlds", type=int, default=2000)
    parser.add_argument("--seed", type=int, default=700_000)
    args = parser.parse_args()
    print(
        f"{'level':>6} {'base':>7} {'branches':>8} {'deepest (p10-p90)':>18} {'dead end':>8} "
        f"{'path bound':>10} {'DFS bound':>9} {'paper complete':>14}"
    )
    for level in ("low", "medium", "high"):
        rng = np.random.default_rng(args.seed)
        worlds = [make_world("corridor", level, rng) for _ in range(args.worlds)]
        for base, ws in (("random", worlds), ("centre", [at_centre(w) for w in worlds])):
            s = stats(ws)
            print(
                f"{level:>6} {base:>7} {s['branches']:8.2f} {s['deepest']:7.1f} "
                f"({s['deepest_p10']:.0f}-{s['deepest_p90']:.0f}){'':>4} {s['dead_end']:8.1f} "
                f"{s['path']:9.1f}% {s['dfs']:8.1f}% {COMPLETE[level]:13.1f}%"
            )


if __name__ == "__main__":
    main()
