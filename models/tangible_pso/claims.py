"""The tests of the tangible-PSO claims (spec §5) on a sweep's tidy run rows.

Each function takes the runs (one row per run: parameters and summary) and the time series
(unused) and returns a :class:`abm.published.Verdict`, or None when the runs lack the set-up.
Rates are shares of runs; "lower" and "higher" are judged on the means, and where both means
are 0 the claim is not contradicted (say so in the verdict).
"""

from collections.abc import Callable

import numpy as np
import pandas as pd

from abm.published import Verdict

__all__ = ["TABLE1", "TESTS"]

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


def _lower(a: float, b: float) -> bool:
    return a < b or (a == 0 and b == 0)


def c1(runs, samples) -> Verdict | None:
    table = _table(runs)
    if table is None:
        return None
    parts, ok = [], True
    for k in sorted({k for k, _ in table.index}):
        with_mp, without = table.loc[(k, True)], table.loc[(k, False)]
        for col in COLUMNS:
            ok &= _lower(with_mp[col], without[col])
        parts.append(
            f"k={k}: "
            + ", ".join(f"{lab} {without[c]:.3g} -> {with_mp[c]:.3g}" for c, lab in COLUMNS.items())
        )
    return Verdict("; ".join(parts), bool(ok), "without -> with motion planning, every k")


def c1b(runs, samples) -> Verdict | None:
    table = _table(runs)
    if table is None:
        return None
    ks = sorted({k for k, _ in table.index})
    parts, ok, ties = [], True, []
    for mp in (False, True):
        for col, label in COLUMNS.items():
            values = [table.loc[(k, mp)][col] for k in ks]
            rising = all(b > a or (a == b == 0) for a, b in zip(values, values[1:], strict=False))
            ok &= rising
            if any(a == b == 0 for a, b in zip(values, values[1:], strict=False)):
                ties.append(f"{label} {'with' if mp else 'without'} MP stays 0")
            parts.append(
                f"{label} {'with' if mp else 'without'} MP: "
                + " < ".join(f"{v:.3g}" for v in values)
            )
    why = "each rises with k" + (f" ({'; '.join(ties)}: not contradicted)" if ties else "")
    return Verdict("; ".join(parts), bool(ok), why)


def c3(runs, samples) -> Verdict | None:
    table = _table(runs)
    if table is None:
        return None
    values = {k: table.loc[(k, True)]["deadlock"] for k, mp in table.index if mp}
    return Verdict(
        ", ".join(f"k={k}: {100 * v:.1f} %" for k, v in values.items()),
        bool(all(v == 0 for v in values.values())),
        "deadlock runs with motion planning",
    )


def c4(runs, samples) -> Verdict | None:
    if not {"swap_conflicts", "swap_resolved", "motion_planning"} <= set(runs):
        return None
    mp = runs[runs["motion_planning"] == True]  # noqa: E712 (a column of bools)
    conflicts = mp["swap_conflicts"].sum()
    if mp.empty or conflicts == 0:
        return None
    share = 100.0 * mp["swap_resolved"].sum() / conflicts
    by_k = ""
    if "neighbours" in mp:
        g = mp.groupby("neighbours")[["swap_resolved", "swap_conflicts"]].sum()
        by_k = "; " + ", ".join(
            f"k={k}: {100 * r.swap_resolved / max(r.swap_conflicts, 1):.1f} %"
            for k, r in g.iterrows()
        )
    return Verdict(
        f"{share:.1f} % of {int(conflicts)} mutual path collisions resolved by swapping{by_k}",
        bool(share > 50.0),
        "most (> 50 %) resolved; the paper: 96.8 %",
    )


def c5(runs, samples) -> Verdict | None:
    if not {"scenario", "groups"} <= set(runs):
        return None
    rows = runs[(runs["scenario"] == "open") & (runs.get("n_mavs", 6) == 6)]
    if "neighbours" in rows:
        rows = rows[rows["neighbours"] == 2]
    if len(rows) < 10:
        return None
    split = float((rows["groups"] >= 2).mean())
    when = rows["best_iteration"].to_numpy(dtype=float) if "best_iteration" in rows else np.zeros(0)
    return Verdict(
        f"best swarm in 2+ groups in {100 * split:.0f} % of {len(rows)} runs; best found at "
        f"iteration {np.median(when):.0f} (median) of 20",
        bool(split >= 0.5),
        "'often' read as at least half the runs",
    )


#: Claim id -> its test.
TESTS: dict[str, Callable] = {"C1": c1, "C1b": c1b, "C3": c3, "C4": c4, "C5": c5}
