"""Is the swarm well mixed? A transition's rate against local density vs the global count.

A rate equation that makes the hazard of i -> j a function of the count n_k of state k
assumes every robot in i meets the whole population of k alike (well mixed). Where robots
are matters when a robot's own neighbourhood predicts its transition better than the global
count does. The diagnostic reads the sampled positions (``trace_interval``) and, for each
robot in state i at each sample time t_s, its exposure until the next sample (or until it
left i), whether it left to j in that window, the global count n_k(t_s) and the local count
m_k(t_s) of robots in k within ``radius`` of it (itself excluded). Three Poisson GLMs with
offset log(exposure) are fitted to these robot-windows:

- null: log lambda = b0;
- global: log lambda = b0 + b1 log(1 + n_k);
- local: log lambda = b0 + b1 log(1 + m_k).

The statistic is the gap in deviance explained, ``gap = R2_local - R2_global`` with
``R2_x = 1 - D_x / D_null`` (D: the model's deviance), and a likelihood-ratio p-value of
adding log(1 + m_k) to the global model. The pair (i -> j, k) is flagged not well mixed when
``gap >= GAP`` and ``p < ALPHA``: local density explains at least ``GAP`` more of the
deviance than the global count the rate equation uses, and not by chance.
"""

import math
import warnings
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd
import statsmodels.api as sm
from scipy.spatial import cKDTree
from scipy.stats import chi2

from analysis.macroscopic.logs import LAUNCH, RunLog, transitions

__all__ = ["ALPHA", "GAP", "Mixing", "default_radius", "well_mixed"]

#: Smallest gap in deviance explained that flags a transition (ours).
GAP = 0.05
#: Largest likelihood-ratio p-value that flags a transition (ours).
ALPHA = 0.01


@dataclass(frozen=True)
class Mixing:
    """The diagnostic's answer for the whole model.

    Attributes:
        computable: False when the runs kept no positions (then ``reason`` says why).
        reason: why it could not be computed, else "".
        radius: the neighbourhood radius used (m).
        table: one row per (source, target, k): ``windows``, ``events``, ``r2_global``,
            ``r2_local``, ``gap``, ``p_value``, ``flagged``.

    """

    computable: bool
    reason: str
    radius: float
    table: pd.DataFrame

    @property
    def flagged(self) -> bool:
        """True when any transition's rate follows local density rather than the count."""
        return bool(self.computable and self.table["flagged"].any())


def default_radius(logs: Sequence[RunLog]) -> float:
    """Twice the median nearest-neighbour distance of the sampled positions (m; ours)."""
    distances = []
    for log in logs:
        if log.positions is None:
            continue
        for _, sample in log.positions.groupby("time"):
            if len(sample) < 2:
                continue
            xy = sample[["x", "y"]].to_numpy(dtype=float)
            d, _ = cKDTree(xy).query(xy, k=2)
            distances.append(d[:, 1])
    return 2.0 * float(np.median(np.concatenate(distances))) if distances else math.nan


def _windows(log: RunLog, source: str, others: Sequence[str], radius: float) -> pd.DataFrame:
    """The robot-windows of one run for robots in ``source`` (see the module's docstring):
    ``time``, ``exposure``, ``target`` (the state it left to within the window, else NaN),
    and ``global:<k>``/``local:<k>`` for each k of ``others``.
    """
    leave = log.moves[log.moves["source"] == source][["robot", "time", "target"]]
    leave = leave.rename(columns={"time": "left"}).astype({"robot": np.int64})
    positions = log.positions.sort_values("time", kind="stable")
    times = positions["time"].to_numpy(dtype=float)
    states = positions["state"].to_numpy()
    robots = positions["robot"].to_numpy(dtype=np.int64)
    xy = positions[["x", "y"]].to_numpy(dtype=float)
    starts, first = np.unique(times, return_index=True)
    bounds = np.append(first, len(times))
    ends = np.append(starts[1:], log.end)
    columns: dict[str, list] = {"time": [], "end": [], "robot": []}
    for other in others:
        columns[f"global:{other}"] = []
        columns[f"local:{other}"] = []
    for k, (t, end) in enumerate(zip(starts, ends, strict=True)):
        rows = slice(bounds[k], bounds[k + 1])
        at, here = states[rows], xy[rows]
        mine = at == source
        if not mine.any() or end <= t:
            continue
        columns["time"].append(np.full(mine.sum(), t))
        columns["end"].append(np.full(mine.sum(), end))
        columns["robot"].append(robots[rows][mine])
        for other in others:
            partners = here[at == other]
            local = np.zeros(mine.sum(), dtype=int)
            if len(partners):
                hits = cKDTree(partners).query_ball_point(here[mine], radius, return_length=True)
                local = np.asarray(hits) - (other == source)
            columns[f"global:{other}"].append(
                np.full(mine.sum(), len(partners) - (other == source))
            )
            columns[f"local:{other}"].append(local)
    if not columns["time"]:
        return pd.DataFrame()
    windows = pd.DataFrame({name: np.concatenate(parts) for name, parts in columns.items()})
    windows = pd.merge_asof(
        windows, leave.sort_values("left", kind="stable"), left_on="time", right_on="left",
        by="robot", direction="forward", allow_exact_matches=False,
    )  # fmt: skip
    left = windows["left"].fillna(math.inf).to_numpy(dtype=float)
    end = windows["end"].to_numpy(dtype=float)
    windows["exposure"] = np.minimum(left, end) - windows["time"].to_numpy(dtype=float)
    windows["target"] = windows["target"].where(left <= end)
    return windows


def _deviance(y: np.ndarray, x: np.ndarray, offset: np.ndarray) -> float:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return float(sm.GLM(y, x, family=sm.families.Poisson(), offset=offset).fit().deviance)


def _compare(frame: pd.DataFrame, target: str, other: str) -> tuple[float, float, float, float]:
    frame = frame[frame["exposure"] > 0]
    y = (frame["target"] == target).to_numpy(dtype=float)
    offset = np.log(frame["exposure"].to_numpy())
    ones = np.ones(len(y))
    g = np.log1p(frame[f"global:{other}"].to_numpy(dtype=float))
    m = np.log1p(frame[f"local:{other}"].to_numpy(dtype=float))
    d_null = _deviance(y, ones[:, None], offset)
    d_global = _deviance(y, np.column_stack([ones, g]), offset) if np.ptp(g) > 0 else d_null
    d_local = _deviance(y, np.column_stack([ones, m]), offset) if np.ptp(m) > 0 else d_null
    both = [ones, *([g] if np.ptp(g) > 0 else []), m]
    d_both = _deviance(y, np.column_stack(both), offset) if np.ptp(m) > 0 else d_global
    r2_global = 1 - d_global / d_null if d_null > 0 else 0.0
    r2_local = 1 - d_local / d_null if d_null > 0 else 0.0
    p_value = float(chi2.sf(max(d_global - d_both, 0.0), 1)) if np.ptp(m) > 0 else 1.0
    return r2_global, r2_local, r2_local - r2_global, p_value


def well_mixed(
    logs: Sequence[RunLog],
    pairs: Sequence[tuple[str, str, str]] | None = None,
    radius: float | None = None,
) -> Mixing:
    """The well-mixed diagnostic (see the module's docstring) over ``logs``.

    Args:
        logs: runs of one model and condition.
        pairs: (source, target, k) to examine; default every hazard transition i -> j seen
            against every state k other than i.
        radius: neighbourhood radius (m); default :func:`default_radius`.

    """
    if any(log.positions is None for log in logs):
        return Mixing(
            False,
            "the runs kept no robot positions (the model ran with trace_interval=None), so "
            "local density cannot be computed",
            math.nan,
            pd.DataFrame(),
        )
    radius = default_radius(logs) if radius is None else float(radius)
    if pairs is None:
        moves = pd.concat([transitions(log) for log in logs])
        moves = moves[(moves["source"] != LAUNCH) & ~moves["launch"].astype(bool)]
        seen = moves[["source", "target"]].drop_duplicates().itertuples(index=False)
        states = logs[0].states
        pairs = [(i, j, k) for i, j in seen if j in states for k in states if k != i]
    rows = []
    for source in sorted({i for i, _, _ in pairs}):
        others = sorted({k for i, _, k in pairs if i == source})
        frame = pd.concat([_windows(log, source, others, radius) for log in logs])
        for _, target, other in [p for p in pairs if p[0] == source]:
            events = int((frame.get("target") == target).sum()) if len(frame) else 0
            if events == 0:
                continue
            r2_global, r2_local, gap, p_value = _compare(frame, target, other)
            rows.append(
                (
                    source,
                    target,
                    other,
                    len(frame),
                    events,
                    r2_global,
                    r2_local,
                    gap,
                    p_value,
                    gap >= GAP and p_value < ALPHA,
                )  # fmt: skip
            )
    columns = ["source", "target", "k", "windows", "events", "r2_global", "r2_local", "gap",
               "p_value", "flagged"]  # fmt: skip
    return Mixing(True, "", radius, pd.DataFrame(rows, columns=columns))
