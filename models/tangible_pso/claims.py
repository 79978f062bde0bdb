"""The tests of the tangible-PSO claims (``published.CLAIMS``) on a sweep's tidy run rows.

Each function takes the runs (one row per run: parameters and summary) and the time series
(unused) and returns a :class:`abm.published.Verdict`, or None when the runs lack the set-up.
Each applies one rule of :mod:`abm.verdicts`: a direction by the Welch 95 % interval of the
difference, an ordering over k by Spearman's rho with its p, a level by the paper's own
number, a share by its Wilson interval. Collisions and deadlocks with motion planning are 0
by construction and judge nothing.
"""

from collections.abc import Callable
from dataclasses import replace

import numpy as np
import pandas as pd

from abm.published import Verdict
from abm.verdicts import band, difference, interval, pooled_share, rank_order

__all__ = ["BASELINE", "BY_CHECK", "BY_PLANNING", "TABLE1", "TESTS", "c4"]

#: Table 1's set-up: the no-fly-zone scenario, 3 MAVs.
TABLE1 = {"scenario": "nofly", "n_mavs": 3}
#: Table 1's columns: summary column -> label.
COLUMNS = {"collision": "collisions", "deadlock": "deadlocks", "best_cost": "cost"}


def _table(runs: pd.DataFrame) -> pd.DataFrame | None:
    """Means of Table 1's columns per (neighbours, motion_planning), or None without both
    variants at two or more k.
    """
    need = {"scenario", "n_mavs", "neighbours", "motion_planning", *COLUMNS}
    if not need <= set(runs):
        return None
    rows = runs[(runs["scenario"] == "nofly") & (runs["n_mavs"] == 3)]
    if rows.empty:
        return None
    table = rows.groupby(["neighbours", "motion_planning"])[list(COLUMNS)].mean()
    ks = sorted({k for k, _ in table.index})
    if len(ks) < 2 or any((k, mp) not in table.index for k in ks for mp in (False, True)):
        return None
    return table


def _verdict(parts: dict[str, Verdict], rule: str, note: str, runs: int) -> Verdict:
    """One verdict from several checks of the same rule on ``runs`` runs: holds when every
    one holds, fails when any fails, undecided otherwise.
    """
    holds = [v.holds for v in parts.values()]
    result = False if False in holds else (True if all(holds) else None)
    ours = "; ".join(f"{label}: {v.ours}" for label, v in parts.items())
    against = [label for label, v in parts.items() if v.holds is False]
    unclear = [label for label, v in parts.items() if v.holds is None]
    why = "; ".join(
        f"{words} {', '.join(labels)}"
        for words, labels in (("the other way for", against), ("undecided for", unclear))
        if labels
    )
    return Verdict(ours, result, "; ".join(w for w in (why, note) if w), rule, runs=runs)


#: Why collisions and deadlocks with motion planning are not evidence: the planner routes
#: every MAV around the no-fly zones, so none is stopped at one, which is what both count.
BY_PLANNING = (
    "collisions and deadlocks with motion planning are 0 by construction with the exact "
    "follower (controller 'exact', the default: both count an MAV stopped at a no-fly zone, "
    "which the planner routes around): not judged"
)


def _rows(runs: pd.DataFrame) -> pd.DataFrame:
    return runs[(runs["scenario"] == "nofly") & (runs["n_mavs"] == 3)]


def c1(runs, samples) -> Verdict | None:
    """Motion planning lowers the cost at every k (Welch 95 % interval of the difference)."""
    table = _table(runs)
    if table is None:
        return None
    rows = _rows(runs)
    parts = {}
    for k in sorted({k for k, _ in table.index}):
        at = rows[rows["neighbours"] == k]
        without = at[at["motion_planning"] == False]["best_cost"]  # noqa: E712 (bools)
        with_mp = at[at["motion_planning"] == True]["best_cost"]  # noqa: E712
        parts[f"cost at k={k}, without -> with"] = difference(without, with_mp, -1)
    rule = next(iter(parts.values())).rule
    return _verdict(parts, rule, BY_PLANNING, len(rows))


def c1b(runs, samples) -> Verdict | None:
    """Each column rises with k: Spearman rho of the runs' values on k, p < 0.05; the
    columns that are 0 by construction (collisions, deadlocks with motion planning) are left
    out.
    """
    table = _table(runs)
    if table is None:
        return None
    rows = _rows(runs)
    parts = {}
    for mp in (False, True):
        variant = rows[rows["motion_planning"] == mp]
        for col, label in COLUMNS.items():
            if mp and col != "best_cost":
                continue
            name = f"{label} {'with' if mp else 'without'} MP"
            parts[name] = rank_order(variant["neighbours"], variant[col].astype(float), +1)
    return _verdict(parts, next(iter(parts.values())).rule, BY_PLANNING, len(rows))


def c3(runs, samples) -> Verdict | None:
    """The deadlock share with motion planning per k (shown; the claim holds by
    construction).
    """
    table = _table(runs)
    if table is None:
        return None
    values = {k: table.loc[(k, True)]["deadlock"] for k, mp in table.index if mp}
    return Verdict(
        ", ".join(f"k={k}: {100 * v:.1f} %" for k, v in values.items()),
        bool(all(v == 0 for v in values.values())),
        "deadlock runs with motion planning",
    )


def c3b(runs, samples) -> Verdict | None:
    """Deadlocks with motion planning under the second-order follower, where they can happen:
    at every k the paper's 0 % must lie in our Wilson 95 % interval of the share of deadlock
    runs (the level rule without a published spread).
    """
    if not {"motion_planning", "neighbours", "deadlock"} <= set(runs):
        return None
    rows = runs[(runs["motion_planning"] == True) & runs["deadlock"].notna()]  # noqa: E712
    if rows.empty:
        return None
    parts = {
        f"deadlocks at k={k}": band(at["deadlock"].astype(float), 0.0, share=True, scale=100.0)
        for k, at in rows.groupby("neighbours")
    }
    return _verdict(parts, next(iter(parts.values())).rule, "", len(rows))


def c4(runs, samples, paper: float) -> Verdict | None:
    """The share of mutual path collisions goal swapping resolved, pooled over the
    motion-planning runs, against the paper's share ``paper`` (%): "most" means what the
    paper reports, so it holds when ``paper`` lies in our 95 % interval, and otherwise says
    by how much ours differs.
    """
    if not {"swap_conflicts", "swap_resolved", "motion_planning"} <= set(runs):
        return None
    mp = runs[runs["motion_planning"] == True]  # noqa: E712 (a column of bools)
    if mp.empty or mp["swap_conflicts"].sum() == 0:
        return None
    verdict = pooled_share(mp["swap_resolved"], mp["swap_conflicts"], paper)
    by_k = ""
    if "neighbours" in mp:
        g = mp.groupby("neighbours")[["swap_resolved", "swap_conflicts"]].sum()
        by_k = "; " + ", ".join(
            f"k={k}: {100 * r.swap_resolved / max(r.swap_conflicts, 1):.1f} %"
            for k, r in g.iterrows()
        )
    return replace(verdict, ours=f"resolved by swapping: {verdict.ours}{by_k}")


#: C5: "often" read as at least this share of the runs (ours: the paper gives no number).
HALF = 0.5


def c5(runs, samples) -> Verdict | None:
    """Fig. 9's best swarm splits into two groups by itself: the Wilson 95 % interval of the
    share of runs whose best swarm is in 2+ groups lies above one half (holds), below it
    (fails), or across it (undecided).
    """
    if not {"scenario", "groups"} <= set(runs):
        return None
    rows = runs[(runs["scenario"] == "open") & (runs.get("n_mavs", 6) == 6)]
    if "neighbours" in rows:
        rows = rows[rows["neighbours"] == 2]
    if len(rows) < 10:
        return None
    split, low, high = interval((rows["groups"] >= 2).astype(float), share=True)
    when = rows["best_iteration"].to_numpy(dtype=float) if "best_iteration" in rows else np.zeros(0)
    holds = True if low > HALF else False if high < HALF else None
    return Verdict(
        f"best swarm in 2+ groups in {100 * split:.0f} % of {len(rows)} runs (95 % interval "
        f"{100 * low:.0f} to {100 * high:.0f} %); best found at iteration "
        f"{np.median(when):.0f} (median) of 20",
        holds,
        "" if holds is not None else f"the interval includes {100 * HALF:.0f} %",
        f"share: Wilson 95 % interval of the share of runs split into 2+ groups above "
        f"{100 * HALF:.0f} % ('often' read as at least half the runs)",
        mean=100 * split,
        low=100 * low,
        high=100 * high,
        runs=len(rows),
    )


#: What the flight of each method's solution is judged on (Figs. 10-11), and what is shown.
BASELINE = ("plan_unlocalised", "deploy_deadlock", "best_cost", "deployed_cost_ratio",
            "reach_time", "plan_collision")  # fmt: skip

#: Why tangible PSO's side of C6 is 0: its plan is the best particle's realised, checked
#: transitions.
BY_CHECK = (
    "tangible PSO's plan is its best particle's realised transitions, every state checked, so "
    "its side is 0 by construction: the state-space side is what is measured"
)


def _methods(runs: pd.DataFrame) -> tuple[pd.DataFrame, pd.DataFrame] | None:
    """The runs of each method that flew their solution, or None without both."""
    if not {"method", *BASELINE} <= set(runs):
        return None
    flown = runs[runs["plan_unlocalised"].notna()]
    tangible = flown[flown["method"] == "tangible"]
    state = flown[flown["method"] == "state_space"]
    if tangible.empty or state.empty:
        return None
    return tangible, state


def _share(rows: pd.DataFrame, column: str) -> str:
    """The share of runs with a flag, with its Wilson 95 % interval."""
    mean, low, high = interval(rows[column].astype(float), share=True)
    return f"{100 * mean:.0f} % ({100 * low:.0f}-{100 * high:.0f} %)"


def _shown(tangible: pd.DataFrame, state: pd.DataFrame) -> str:
    """The figures' other measures, side by side (tangible / state space), not judged."""
    reached = state["reach_time"].dropna(), tangible["reach_time"].dropna()
    time = ", ".join(
        f"{name} {np.median(r):.0f} s (median of {len(r)} that reached)" if len(r) else
        f"{name} never reached"
        for name, r in (("tangible", reached[1]), ("state space", reached[0]))
    )  # fmt: skip
    return (
        f"deployed cost (share of nothing seen) {tangible['deployed_cost_ratio'].mean():.2f} / "
        f"{state['deployed_cost_ratio'].mean():.2f}; planned cost "
        f"{tangible['best_cost'].mean():.3g} / {state['best_cost'].mean():.3g}; collisions on "
        f"the unchecked plan {_share(tangible, 'plan_collision')} / "
        f"{_share(state, 'plan_collision')}; time to reach the formation: {time}"
    )


def c6(runs, samples) -> Verdict | None:
    """Figs. 10-11: the state-space search's solution cannot be reached with the constraint,
    tangible PSO's can. Two directions, each by the Welch 95 % interval of the difference of
    the shares of runs (state space minus tangible): its plan, flown to the end, loses a
    MAV's k localised neighbours (Fig. 10 b-d), and flown under the feasibility check it
    stops short of its formation (a deadlock). The costs and times are shown, not judged.
    """
    both = _methods(runs)
    if both is None:
        return None
    tangible, state = both
    parts = {
        "plan loses localisation, tangible -> state space": difference(
            tangible["plan_unlocalised"].astype(float), state["plan_unlocalised"].astype(float),
            +1, 100.0,
        ),
        "deployment deadlocks, tangible -> state space": difference(
            tangible["deploy_deadlock"].astype(float), state["deploy_deadlock"].astype(float),
            +1, 100.0,
        ),
    }  # fmt: skip
    verdict = _verdict(parts, next(iter(parts.values())).rule, BY_CHECK, len(tangible) + len(state))
    shares = (
        f"unlocalised plans {_share(tangible, 'plan_unlocalised')} / "
        f"{_share(state, 'plan_unlocalised')}, deadlocks {_share(tangible, 'deploy_deadlock')} / "
        f"{_share(state, 'deploy_deadlock')} (tangible / state space, points)"
    )
    return replace(verdict, ours=f"{shares}; {verdict.ours}; {_shown(tangible, state)}")


def c6b(runs, samples) -> Verdict | None:
    """Figs. 10-11: the state-space search, free of the flight, plans a lower cost than
    tangible PSO ("does not cover the areas of interest completely"): the Welch 95 % interval
    of the difference of the best costs (state space minus tangible) lies below 0.
    """
    both = _methods(runs)
    if both is None:
        return None
    tangible, state = both
    verdict = difference(tangible["best_cost"], state["best_cost"], -1)
    return replace(verdict, ours=f"planned cost, tangible -> state space: {verdict.ours}")


#: Claim id -> its test (C4's needs the paper's share: published.py binds it).
TESTS: dict[str, Callable] = {
    "C1": c1, "C1b": c1b, "C3": c3, "C3b": c3b, "C5": c5, "C6": c6, "C6b": c6b,
}  # fmt: skip
