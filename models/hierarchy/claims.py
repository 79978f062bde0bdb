"""The tests of the report's checkable claims (the model README's "The claims"), on a sweep's
tidy run rows.

Each function takes the runs (one row per run: parameters and summary) and the model's time
series (unused) and returns a :class:`abm.published.Verdict`, or None when the runs lack the
claim's set-up. The report publishes no numbers, so only shapes and trends are judged, each by
one rule of :mod:`abm.verdicts` stated in its verdict (an ordering over N by Spearman's rho over
the runs with its p, a comparison of arms by a Welch interval, a coefficient the report says is
0 by the interval of its OLS estimate). C1 keeps a band of our own, named below. Every
threshold is free of units; the
verdicts quote scan areas in m² and drive distances in m, the
summary's units (the report's Figs. 36-38 are in cm² and cm: 1 m² = 10⁴ cm², 1 m = 100 cm).
"""

from dataclasses import replace

import numpy as np
import pandas as pd
from scipy import stats as sps

from abm.published import Verdict
from abm.verdicts import (
    ALPHA,
    band,
    censored,
    coefficient,
    combine,
    difference,
    interval,
    level,
    rank_order,
    spread,
)

__all__ = ["ACCOUNTINGS", "TESTS"]

#: C1: share of the free cells that must be known at the end (ours; cells in world corners and
#: wall pockets next to a parked worker cannot be reached under the padding rules).
KNOWN_MIN = 0.999


def _staggered(runs: pd.DataFrame) -> pd.Series:
    """Which runs staggered the subtrees' transits (ours, ``subtree_transits``); a sweep
    without the parameter ran the report's (together).
    """
    if "subtree_transits" not in runs:
        return pd.Series(False, index=runs.index)
    return runs["subtree_transits"].fillna("together") == "staggered"


def _ok(runs: pd.DataFrame) -> pd.DataFrame:
    """The finished runs of the standard set-up (the hierarchy, wave generator on, subtrees
    moving together).
    """
    if "scout_scan_area" not in runs:
        return runs.iloc[0:0]
    out = runs[runs["scout_scan_area"].notna()]
    out = out[~_staggered(out)]
    if "wave_generator" in out:
        out = out[out["wave_generator"].astype(bool)]
    if "topology" in out:
        out = out[out["topology"] == "hst"]
    return out


def _configs(runs: pd.DataFrame, metric: str) -> pd.DataFrame:
    """Mean of ``metric`` per (W, S), with N (empty when no run has the metric)."""
    if metric not in runs:
        return pd.DataFrame(columns=["W", "S", "N", "y"])
    runs = runs.dropna(subset=[metric])
    return runs.groupby(["W", "S"], as_index=False).agg(N=("N", "first"), y=(metric, "mean"))


def _falls(runs: pd.DataFrame, metric: str, unit: str) -> Verdict | None:
    """C2/C6: the metric falls with N, by Spearman's rho over the runs with two-sided p < 0.05
    (the report gives no strength, so none is required); the W-series that rise somewhere in
    S are listed, not judged.
    """
    runs = _ok(runs)
    cfg = _configs(runs, metric) if len(runs) else runs
    if len(cfg) < 4 or cfg["N"].nunique() < 4:
        return None
    falls = rank_order(runs["N"], runs[metric], -1)
    rises = []
    for w, g in cfg.groupby("W"):
        y = g.sort_values("S")["y"].to_numpy()
        rises += [f"W={w}" for a, b in zip(y[:-1], y[1:], strict=True) if b > a * 1.0001][:1]
    first, last = cfg.loc[cfg["N"].idxmin()], cfg.loc[cfg["N"].idxmax()]
    ours = (
        f"Spearman {falls.ours} over {len(cfg)} configurations; "
        f"{first.y:,.1f} {unit} at N={first.N:.0f} -> {last.y:,.1f} {unit} at N={last.N:.0f}; "
        f"series of means not monotone: {', '.join(rises) or 'none'}"
    )
    return replace(falls, ours=ours)


def c1(runs, samples) -> Verdict | None:
    runs = _ok(runs)
    if runs.empty:
        return None
    done = runs["complete"].astype(float)
    known = runs["known_free_fraction"].astype(float)
    ended = runs["end_reason"].isin(["complete", "cannot_complete"])
    level = band(known, 100.0, 100.0 * (1 - KNOWN_MIN), scale=100.0)
    configs = len(runs.groupby(["W", "S"])) if {"W", "S"} <= set(runs) else 1
    ours = (
        f"free cells known: {level.ours.replace(' (', ' % (', 1)}, min {100 * known.min():.2f} %"
        f" over {configs} configuration{'s' if configs != 1 else ''} (W, S) of the report's 42;"
        f" {ended.mean():.0%} of {len(runs)} runs end by the queen's coverage call "
        f"({done.mean():.0%} COMPLETE, the rest CANNOT_COMPLETE once the no-progress guard "
        f"has exhausted wall-ring pockets)"
    )
    return replace(
        level,
        ours=ours,
        rule=level.rule.replace("level:", "level of the share of free cells known, in %:")
        + f" (the band is ours: cells next to a parked worker cannot be reached, {KNOWN_MIN:.1%})",
    )


def c2(runs, samples) -> Verdict | None:
    return _falls(runs, "scout_scan_area", "m²")


def c6(runs, samples) -> Verdict | None:
    return _falls(runs, "scout_drive", "m")


def _w_share(runs: pd.DataFrame, metric: str, size: str) -> tuple[float, float]:
    """(c, share): the W coefficient of log y = a + b log size + c W and the share of the
    variance left after log size that W explains (partial R^2).
    """
    y = np.log(runs[metric].astype(float).to_numpy())
    s = np.log(runs[size].astype(float).to_numpy())
    w = runs["W"].astype(float).to_numpy()
    base = np.column_stack([np.ones_like(s), s])
    full = np.column_stack([base, w])
    rss0 = float(np.sum((y - base @ np.linalg.lstsq(base, y, rcond=None)[0]) ** 2))
    coef = np.linalg.lstsq(full, y, rcond=None)[0]
    rss1 = float(np.sum((y - full @ coef) ** 2))
    return float(coef[2]), (rss0 - rss1) / rss0 if rss0 > 0 else 0.0


def c3(runs, samples) -> Verdict | None:
    """C3, the scout scan area is "entirely dependent on the total number of robots", and the
    number of workers W "does not actually increase or decrease" it (Fig. 37): in
    log A = a + b log N + c W over the runs, the report's c is 0, judged by the level rule on
    c's 95 % interval (the report gives no margin). The share of the variance left after
    log N that W explains, the same fit with log(W S) for log N, and the equal-scout groups are
    shown, not judged.
    """
    runs = _ok(runs)
    if len(runs) < 10 or runs["W"].nunique() < 3:
        return None
    runs = runs.assign(scouts_total=runs["W"] * runs["S"])
    area = np.log(runs["scout_scan_area"].astype(float))
    judged = coefficient(
        area, {"log N": np.log(runs["N"].astype(float)), "W": runs["W"].astype(float)}, "W", 0.0
    )
    _, share_n = _w_share(runs, "scout_scan_area", "N")
    c_s, share_s = _w_share(runs, "scout_scan_area", "scouts_total")
    spreads = []
    for total, sel in runs.groupby("scouts_total"):
        means = sel.groupby("W")["scout_scan_area"].mean()
        if len(means) >= 2:
            spreads.append(f"{total} scouts: W={list(means.index)} spread "
                           f"{(means.max() - means.min()) / means.mean():.1%}")  # fmt: skip
    ours = (
        f"log A = a + b log N + c W: {judged.ours.replace('b_W', 'c =')}; W explains "
        f"{share_n:.1%} of the variance left after log N; with log(W S) instead: "
        f"c = {c_s:+.3f}, {share_s:.1%}. Equal-scout groups: "
        f"{'; '.join(spreads) or 'none in these runs'}"
    )
    return replace(judged, ours=ours)


def _residuals(runs: pd.DataFrame, metric: str) -> np.ndarray:
    """The log configuration means' residuals about a quadratic in log N (C4's "sporadic")."""
    cfg = _configs(runs, metric)
    x, y = np.log(cfg["N"].to_numpy(float)), np.log(cfg["y"].to_numpy(float))
    return y - np.polyval(np.polyfit(x, y, 2), x)


def c4(runs, samples) -> Verdict | None:
    runs = _ok(runs)
    if runs.empty or runs["N"].nunique() < 6:
        return None
    workers, scouts = _residuals(runs, "worker_scan_area"), _residuals(runs, "scout_scan_area")
    falls = rank_order(runs["N"], runs["worker_scan_area"], -1)
    sporadic = spread(scouts, workers, "the configuration means' log residuals about a "
                      "quadratic in log N, level 1 vs level 2")  # fmt: skip
    ours = (
        f"worker area: Spearman {falls.ours}; residual scatter of the configuration means "
        f"(log units): {sporadic.ours}, workers vs scouts"
    )
    return combine([falls, sporadic], ours, len(runs),
                   "falls with N and scatters more than level 2")  # fmt: skip


def _slope(runs: pd.DataFrame, metric: str) -> tuple[float, float]:
    """The OLS slope of log ``metric`` on log N over the runs, and its standard error."""
    fit = sps.linregress(np.log(runs["N"].to_numpy(float)), np.log(runs[metric].to_numpy(float)))
    return float(fit.slope), float(fit.stderr)


def c7(runs, samples) -> Verdict | None:
    """The level-1 drive falls only slightly with N: |level-2 slope| - |level-1 slope| of log
    drive on log N over the runs, with a normal 95 % interval from the two slopes' standard
    errors (taken as independent), must exclude 0 on the positive side.
    """
    runs = _ok(runs).dropna(subset=["worker_drive", "scout_drive"])
    if runs.empty or runs["N"].nunique() < 4:
        return None
    (workers, se_w), (scouts, se_s) = _slope(runs, "worker_drive"), _slope(runs, "scout_drive")
    gap = abs(scouts) - abs(workers)
    half = float(sps.norm.ppf(1 - ALPHA / 2) * np.hypot(se_w, se_s))
    low, high = gap - half, gap + half
    holds = True if low > 0 else False if high < 0 else None
    ours = (
        f"log-log slope in N over {len(runs)} runs: worker drive {workers:+.2f} +- {se_w:.2f}, "
        f"scout drive {scouts:+.2f} +- {se_s:.2f}; |scout| - |worker| {gap:+.3f} "
        f"(95 % interval {low:+.3f} to {high:+.3f})"
    )
    why = {True: "", False: "the interval excludes 0 on the other side",
           None: "the interval includes 0"}[holds]  # fmt: skip
    rule = ("direction: normal 95 % interval of |level-2 slope| - |level-1 slope| (OLS of log "
            "drive on log N over the runs) excludes 0 (level 1 falls less)")  # fmt: skip
    return Verdict(ours, holds, why, rule, mean=gap, low=low, high=high, runs=len(runs))


def c8(runs, samples) -> Verdict | None:
    """C8, "there is almost no increase in the number of iterations" of the queen's coverage
    algorithm for two workers instead of seven: the report's increase is 0, judged by the
    level rule on the Welch 95 % interval of the difference (W = 7 minus W = 2, at the S values
    both have). The report gives no margin for "almost", so a measured increase fails, and the
    verdict says by how much.
    """
    runs = _ok(runs)
    two, seven = runs[runs["W"] == 2], runs[runs["W"] == 7]
    both = sorted(set(two["S"]) & set(seven["S"]))
    if not both:
        return None
    a = two[two["S"].isin(both)]["queen_iterations"].astype(float)
    b = seven[seven["S"].isin(both)]["queen_iterations"].astype(float)
    gap = difference(a, b, +1)
    if gap.low is None:
        return replace(gap, ours=f"queen iterations at S = {both}: too few runs")
    # the level rule counts runs per group: the smaller arm decides whether there are enough
    judged = level(gap.mean, gap.low, gap.high, min(len(a), len(b)), 0.0)
    judged = replace(judged, runs=gap.runs)
    ours = (
        f"queen iterations: {a.mean():.1f} with 2 workers, {b.mean():.1f} with 7 (same S = "
        f"{both}; ratio {b.mean() / a.mean():.2f}); W=7 - W=2 {gap.ours}"
    )
    rule = judged.rule.replace("interval of the mean", "Welch interval of W=7 - W=2")
    return replace(judged, ours=ours, rule=rule)


def c9(runs, samples) -> Verdict | None:
    runs = _ok(runs)
    cfg = _configs(runs, "completion_time") if len(runs) else runs
    if len(cfg) < 4:
        return None
    missing = int(runs["completion_time"].isna().sum())
    if missing:  # a run that did not complete has no completion time, only a lower bound
        ours = f"{missing} of {len(runs)} runs did not complete"
        return censored(ours, missing, len(runs), "completion time")
    falls = rank_order(runs["N"], runs["completion_time"], -1)
    first, last = cfg.loc[cfg["N"].idxmin()], cfg.loc[cfg["N"].idxmax()]
    ours = (f"completion time: Spearman {falls.ours}; {first.y:,.0f} s at N={first.N:.0f}"
            f" -> {last.y:,.0f} s at N={last.N:.0f}")  # fmt: skip
    return replace(falls, ours=ours)


def c12(runs, samples) -> Verdict | None:
    """C12, with the wave generator robots "could move around safely and without worry of
    colliding" (Software Results): no wave-order violation and no scout proximity event in any
    run with waves. Any event fails it. Runs without the wave generator are the control for
    a run of no events: when they show none either (or are missing), the diagnostics may be
    blind, and the claim is not judged. Runs with staggered subtree transits (ours) are shown
    beside the report's set-up, not judged.
    """
    if "wave_order_violations" not in runs:
        return None
    finished = runs[runs["scout_scan_area"].notna()]
    apart = finished[_staggered(finished)]
    finished = finished[~_staggered(finished)]
    waves = finished["wave_generator"].astype(bool) if "wave_generator" in finished else None
    on = finished[waves] if waves is not None else finished
    off = finished[~waves] if waves is not None else finished.iloc[0:0]
    if on.empty:
        return None

    def per_run(runs: pd.DataFrame) -> str:
        return (f"{runs['wave_order_violations'].mean():.1f} wave-order violations, "
                f"{runs['robot_proximity_events'].mean():.1f} scout proximity events "
                f"({runs['sibling_proximity_events'].mean():.1f} between siblings), "
                f"{runs['robot_collisions'].mean():.1f} robot_collisions per run (two per "
                f"body contact)")  # fmt: skip

    def events(runs: pd.DataFrame) -> pd.Series:
        return runs["wave_order_violations"] + runs["robot_proximity_events"]

    touched = (events(on) > 0).astype(float)
    share, low, high = interval(touched.to_numpy(), share=True)
    text = (f"with waves ({len(on)} runs): {per_run(on)}; runs with an event "
            f"{share:.0%} (95 % interval {low:.0%} to {high:.0%})")  # fmt: skip
    if not off.empty:
        text += f"; without waves ({len(off)} runs): {per_run(off)}"
    if "wave_generator" in apart:
        apart = apart[apart["wave_generator"].astype(bool)]
    if not apart.empty:
        slow = apart["completion_time"].mean(), on["completion_time"].mean()
        text += (f"; with waves and subtree transits staggered by the queen (ours, not judged; "
                 f"{len(apart)} runs): {per_run(apart)}; completion {slow[0]:,.0f} s against "
                 f"{slow[1]:,.0f} s")  # fmt: skip
    rule = ("no wave-order violation and no proximity event in any run with waves, against "
            "the no-wave control")  # fmt: skip
    common = {"rule": rule, "runs": len(on), "mean": share, "low": low, "high": high}
    if share > 0:
        return Verdict(text, False, "events with the wave generator", **common)
    if off.empty:  # no event, but would the diagnostics have seen one?
        return Verdict(text, None, "no run without waves: no control", **common)
    if not (events(off) > 0).any():
        return Verdict(text, None, "no event without waves either: the runs cannot tell",
                       **common)  # fmt: skip
    return Verdict(text, True, "", **common)


#: The two accountings of the message comparison (README, "The message comparison"): the
#: summary column each counts in, and its name in the verdicts.
ACCOUNTINGS = {
    "per_destination": ("messages_task", "task messages, one per destination"),
    "broadcast": ("transmissions_task", "task transmissions, one per broadcast"),
}


def _fewer(runs: pd.DataFrame, accounting: str) -> Verdict | None:
    """C14 under one accounting: HST sends fewer than FC and than RING at every size n_s = W S,
    each by the Welch 95 % interval of FC - HST (RING - HST) excluding 0 on the positive side.
    The star's ratio and star - HST (same rule) are shown, not judged: the report's claim
    names only the flat topologies.
    """
    metric, what = ACCOUNTINGS[accounting]
    if "topology" not in runs or metric not in runs or runs["topology"].nunique() < 2:
        return None
    ok = runs[runs["scout_scan_area"].notna()].assign(n_s=runs["W"] * runs["S"])
    ok = ok.dropna(subset=[metric])
    mean = ok.groupby(["n_s", "topology"])[metric].mean().unstack()
    flat = [t for t in ("fc", "ring") if t in mean]
    if "hst" not in mean or not flat:
        return None
    ratio = mean[flat].min(axis=1) / mean["hst"]
    ours = f"{accounting} accounting ({what}); flat / HST: " + ", ".join(
        f"{r:.2f} at {n} scouts" for n, r in ratio.items()
    )
    parts = []
    for n, group in ok.groupby("n_s"):
        hst = group.loc[group["topology"] == "hst", metric]
        for arm in flat:
            parts.append(difference(hst, group.loc[group["topology"] == arm, metric], +1))
            ours += f"; {arm} - HST at {n} scouts {parts[-1].ours or parts[-1].why}"
        if "star" in mean:
            star = difference(hst, group.loc[group["topology"] == "star", metric], +1)
            ours += f"; star - HST at {n} scouts (not judged) {star.ours or star.why}"
    return combine(parts, ours, len(ok), "HST sends fewer than FC and RING at every size")


def c14(runs, samples) -> Verdict | None:
    """C14 counting every copy of a message to each destination (one row per link and hop)."""
    return _fewer(runs, "per_destination")


def c14b(runs, samples) -> Verdict | None:
    """C14 counting a message sent to several destinations at once on a shared channel (FC's
    copies, a ring origin's first hop both ways) as one transmission.
    """
    return _fewer(runs, "broadcast")


TESTS = {"C1": c1, "C2": c2, "C3": c3, "C4": c4, "C6": c6, "C7": c7, "C8": c8,
         "C9": c9, "C12": c12, "C14": c14, "C14b": c14b}  # fmt: skip
