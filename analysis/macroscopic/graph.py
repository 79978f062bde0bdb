"""The state machine of a model as the runs saw it: a networkx DiGraph of states and transitions.

Nodes are the model's states plus :data:`~analysis.macroscopic.logs.LAUNCH` (robots appear
from it) and :data:`~analysis.macroscopic.logs.REMOVED` (robots leave to it) when the runs had
any. Each node carries the robot-time spent in it; each edge the number of transitions seen,
how many of them were scheduled launches, the robot-time spent in its source state and the
crude rate (transitions per robot-second in the source, the constant-hazard MLE).
"""

from collections.abc import Sequence

import networkx as nx
import numpy as np
import pandas as pd

from analysis.macroscopic.logs import LAUNCH, REMOVED, RunLog, stays, transitions

__all__ = ["sinks", "sources", "state_graph"]


def state_graph(logs: Sequence[RunLog]) -> nx.DiGraph:
    """The states and transitions of ``logs`` (many runs of one model) as a DiGraph.

    Node attributes: ``robot_time`` (robot-seconds spent in the state over all runs),
    ``entries`` (stays begun), ``dwell_mean`` (mean length of a finished stay, s; NaN when no
    stay ended), ``kind`` ("state", "source" or "sink").
    Edge attributes: ``count`` (transitions over all runs), ``launches`` (those the model
    logged as launches: a known schedule, not a hazard), ``exposure`` (robot-seconds in the
    source state), ``rate`` (``(count - launches) / exposure``, 1/s; NaN for edges from
    :data:`LAUNCH`, whose robots were nowhere before), ``dwell_mean`` (mean time in the
    source before this transition, s), ``runs`` (runs in which it happened).
    """
    graph = nx.DiGraph()
    states = logs[0].states if logs else ()
    for state in states:
        graph.add_node(state, kind="state", robot_time=0.0, entries=0, dwell_mean=np.nan)
    moves = pd.concat([transitions(log).assign(run=i) for i, log in enumerate(logs)])
    held = pd.concat([stays(log) for log in logs])
    held["length"] = held["stop"] - held["start"]
    for state, group in held.groupby("state"):
        graph.add_node(state, kind="state")
        graph.nodes[state]["robot_time"] = float(group["length"].sum())
        graph.nodes[state]["entries"] = len(group)
    for state, group in moves[moves["source"] != LAUNCH].groupby("source"):
        graph.nodes[state]["dwell_mean"] = float(group["dwell"].mean())
    for (source, target), group in moves.groupby(["source", "target"], sort=True):
        for node, kind in ((source, "source"), (target, "sink")):
            if node in (LAUNCH, REMOVED):
                graph.add_node(node, kind=kind)
        exposure = graph.nodes[source].get("robot_time", np.nan) if source != LAUNCH else np.nan
        hazard = len(group) - int(group["launch"].sum())
        graph.add_edge(
            source,
            target,
            count=len(group),
            launches=int(group["launch"].sum()),
            exposure=exposure,
            rate=hazard / exposure if exposure and np.isfinite(exposure) else np.nan,
            dwell_mean=float(group["dwell"].mean()) if source != LAUNCH else np.nan,
            runs=int(group["run"].nunique()),
        )
    return graph


def sources(graph: nx.DiGraph) -> list[str]:
    """States robots enter the model through (successors of :data:`LAUNCH`)."""
    return sorted(graph.successors(LAUNCH)) if LAUNCH in graph else []


def sinks(graph: nx.DiGraph) -> list[str]:
    """States no robot ever left (absorbing: failed, stopped, ...) and :data:`REMOVED`."""
    return sorted(n for n in graph if graph.out_degree(n) == 0 and n != LAUNCH)
