"""The rules a reproduction report judges a published number or claim by, one per kind.

Each rule returns a :class:`abm.published.Verdict` that states the rule, the number of runs,
our value and its 95 % interval, so the report shows how every verdict was reached:

- a **level** (:func:`band`, :func:`level`): the published level with its spread is a two-sided
  band ``value +- spread``. It holds when our 95 % interval of the mean lies inside the band,
  fails when the interval lies outside it, and is undecided when the interval crosses an
  edge. Without a published spread, it holds when our interval contains the published value,
  and otherwise says by how much ours differs.
- a **direction** or an **ordering of two conditions** (:func:`difference`): the Welch 95 %
  interval of the difference of the means excludes zero on the published side (holds), on the
  other side (fails), or includes zero (undecided), with the two-sided Welch p.
- a **difference of differences** (:func:`contrast`, e.g. "the gain from 2 to 4 is larger
  than from 8 to 10"): the Welch 95 % interval of a linear combination of group means,
  judged like a direction.
- a **larger spread** (:func:`spread`): the Brown-Forsythe test (Levene's about the
  medians) with its p, judged like an ordering.
- an **ordering over several values** (:func:`rank_order`): Spearman's rho over the runs with
  its two-sided permutation p (:func:`spearman`); it holds when rho has the published sign and
  p < 0.05, fails when rho has the other sign and p < 0.05, and is undecided otherwise.
- a **correlation of condition means** (:func:`correlation`): Pearson's r with its Fisher-z
  95 % interval, judged like a direction.
- an **agreement** of conditions the source says give the same value (:func:`agreement`, e.g.
  "the curves follow each other closely"): the published difference is 0, with no margin,
  so the rule is the level rule without a spread: the Kruskal-Wallis test over the conditions
  (Holm-adjusted over checkpoints) finds no difference (holds) or finds one (fails, saying by
  how much the extreme means differ). The largest gap is shown with its Welch interval, so the
  reader sees how large a difference these runs could miss.
- a **coefficient** the source gives a value for (:func:`coefficient`, e.g. a speed-up
  "almost linear" in n: the slope of log T on log n is -1; "no effect of W": 0): the level
  rule on the OLS coefficient's 95 % t-interval.

A claim is never decided from fewer than two runs per group: the verdict is then undecided.
A rule that holds because it found no difference (a level without a spread, an agreement)
needs at least :data:`MIN_AGREE` runs per group: fewer give intervals so wide that nothing
could be told apart, and the verdict is undecided.

Nor is a statistic computed from runs without spread. A t-interval of identical values has no
width, so a level without a published spread is undecided there (a band is still judged:
every run lies inside it or outside it); a difference of groups that are each constant is
the fixed difference, with no interval or p-value; a spread, an ordering or a correlation
over values that do not vary is undecided, saying so; a pooled share the same in every run
takes Wilson's interval over its events; a coefficient of an exact fit (no residual) is
undecided.
"""

import itertools
from collections.abc import Callable, Mapping, Sequence
from dataclasses import replace

import numpy as np
import pandas as pd
from scipy import stats as sps

from abm.errors import ConfigError
from abm.published import Published, Verdict

__all__ = [
    "ALPHA",
    "EXACT_UP_TO",
    "MIN_AGREE",
    "SHUFFLES",
    "agreement",
    "band",
    "censored",
    "coefficient",
    "combine",
    "contrast",
    "correlation",
    "difference",
    "interval",
    "level",
    "level_test",
    "pooled_share",
    "rank_order",
    "spearman",
    "spread",
]

#: One minus the confidence of every interval, and the level of every test.
ALPHA = 0.05
#: The fewest runs per group from which "no difference found" may count as holding.
MIN_AGREE = 5


def interval(values: Sequence[float], share: bool = False) -> tuple[float, float, float]:
    """The mean of ``values`` and its 95 % interval (Student t; Wilson for a share of 0/1
    values, ``share=True``). The interval is (nan, nan) for fewer than two values.
    """
    x = np.asarray(values, dtype=float)
    x = x[~np.isnan(x)]
    n = len(x)
    if n == 0:
        return float("nan"), float("nan"), float("nan")
    mean = float(x.mean())
    if n < 2:
        return mean, float("nan"), float("nan")
    if share:
        return (mean, *_wilson(mean, n))
    half = float(sps.t.ppf(1 - ALPHA / 2, n - 1) * x.std(ddof=1) / np.sqrt(n))
    return mean, mean - half, mean + half


def _wilson(share: float, n: float) -> tuple[float, float]:
    """Wilson's 95 % interval of a share observed over ``n`` trials."""
    z = sps.norm.ppf(1 - ALPHA / 2)
    centre = (share + z * z / (2 * n)) / (1 + z * z / n)
    half = z * np.sqrt(share * (1 - share) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    # at a share of 0 (or 1) Wilson's bound is exactly 0 (or 1); rounding left 1.7e-16
    low = 0.0 if share == 0.0 else float(max(0.0, centre - half))
    high = 1.0 if share == 1.0 else float(min(1.0, centre + half))
    return low, high


def level(
    mean: float,
    low: float,
    high: float,
    runs: int,
    value: float,
    spread: float | None = None,
    ours: str = "",
) -> Verdict:
    """The level rule on our mean and its 95 % interval ``[low, high]`` (see the module)."""
    shown = ours or f"{mean:.4g} (95 % interval {low:.4g} to {high:.4g}, {runs} runs)"
    if spread is None:
        rule = f"level: the published {value:g} inside our 95 % interval of the mean"
    else:
        rule = (
            f"level: two-sided band {value:g} +- {spread:g}; our 95 % interval of the mean "
            "inside it holds, outside it fails, across an edge undecided"
        )
    common = {"rule": rule, "mean": mean, "low": low, "high": high, "runs": runs}
    if not np.isfinite(low) or not np.isfinite(high):
        return Verdict(shown, None, "fewer than two runs: no interval", **common)
    off = f"ours differs from the published {value:g} by {mean - value:+.3g}"
    if spread is None and low == high:
        why = "our interval has no width (no spread in the runs): not judged; " + off
        return Verdict(shown, None, why, **common)
    if spread is None:
        inside = bool(low <= value <= high)
        if inside and runs < MIN_AGREE:
            return Verdict(shown, None, f"fewer than {MIN_AGREE} runs: too few to tell", **common)
        return Verdict(shown, inside, "" if inside else off, **common)
    bottom, top = value - spread, value + spread
    if bottom <= low and high <= top:
        return Verdict(shown, True, off, **common)
    if high < bottom or low > top:
        return Verdict(shown, False, off, **common)
    return Verdict(shown, None, f"our interval crosses the band's edge; {off}", **common)


def band(
    values: Sequence[float],
    value: float,
    spread: float | None = None,
    share: bool = False,
    scale: float = 1.0,
) -> Verdict:
    """The level rule on per-run ``values`` (``scale`` converts them to the published unit,
    e.g. 100 for a share in %).
    """
    x = np.asarray(values, dtype=float)
    mean, low, high = (scale * v for v in interval(x, share=share))
    return level(mean, low, high, int(np.sum(~np.isnan(x))), value, spread)


def pooled_share(
    hits: Sequence[float], totals: Sequence[float], value: float, spread: float | None = None
) -> Verdict:
    """The level rule on a share pooled over runs, in % (e.g. conflicts resolved of all
    conflicts): sum(hits) / sum(totals), with a 95 % interval that treats each run as a
    cluster (the ratio estimator's delta-method variance), since events of one run are not
    independent of each other.
    """
    h, t = np.asarray(hits, dtype=float), np.asarray(totals, dtype=float)
    n, total = len(h), float(t.sum())
    if total == 0:
        return Verdict("no events", None, "nothing to share out", runs=n)
    share = float(h.sum() / total)
    if n < 2:
        return level(100 * share, np.nan, np.nan, n, value, spread)
    residual = h - share * t
    se = float(np.sqrt(n / (n - 1) * np.sum(residual**2)) / total)
    z = sps.norm.ppf(1 - ALPHA / 2)
    low, high = max(0.0, share - z * se), min(1.0, share + z * se)
    how = f"{n} runs"
    if se == 0:  # every run the same share (e.g. none): no spread between runs to cluster on
        low, high = _wilson(share, total)
        how = f"{n} runs, each the same share: Wilson over the {int(total)} events"
    ours = (
        f"{100 * share:.1f} % of {int(total)} (95 % interval {100 * low:.1f} to "
        f"{100 * high:.1f} %, {how})"
    )
    return level(100 * share, 100 * low, 100 * high, n, value, spread, ours=ours)


#: The reason of a direction's verdict.
_WHY = {
    True: "",
    False: "the interval excludes 0 on the other side",
    None: "the interval includes 0",
}


def _sided(low: float, high: float, sign: int) -> bool | None:
    """True when [low, high] excludes 0 on ``sign``'s side, False on the other, else None."""
    if sign * low > 0 and sign * high > 0:  # Python bools: a verdict is True, False or None
        return True
    if sign * low < 0 and sign * high < 0:
        return False
    return None


def _fixed(value: float, sign: int, rule: str, runs: int) -> Verdict:
    """The direction rule when every group's runs all gave one value: no spread, so no
    interval or p-value; the fixed difference ``value`` has ``sign``'s sign (holds), the other
    (fails), or is 0 (undecided).
    """
    ours = f"{value:+.4g} (no spread: every run of each group gave one value)"
    holds = None if value == 0 else bool(sign * value > 0)
    why = {True: "", False: "the fixed difference has the other sign", None: "no difference"}
    return Verdict(ours, holds, why[holds], rule, mean=value, low=value, high=value, runs=runs)


def difference(
    before: Sequence[float], after: Sequence[float], sign: int, scale: float = 1.0
) -> Verdict:
    """The direction rule: is mean(after) - mean(before) of sign ``sign`` (+1 or -1)? Welch's
    95 % interval of the difference and the two-sided Welch p (``scale`` as in :func:`band`).
    """
    a = np.asarray(before, dtype=float)
    b = np.asarray(after, dtype=float)
    a, b = scale * a[~np.isnan(a)], scale * b[~np.isnan(b)]
    word = "increase" if sign > 0 else "decrease"
    rule = f"direction: Welch 95 % interval of the difference of the means excludes 0 ({word})"
    runs = len(a) + len(b)
    if len(a) < 2 or len(b) < 2:
        return Verdict("", None, "fewer than two runs on a side: no interval", rule, runs=runs)
    diff = float(b.mean() - a.mean())
    va, vb = a.var(ddof=1) / len(a), b.var(ddof=1) / len(b)
    se = float(np.sqrt(va + vb))
    if se == 0:
        return _fixed(diff, sign, rule, runs)
    df = (va + vb) ** 2 / (va**2 / (len(a) - 1) + vb**2 / (len(b) - 1))
    half = float(sps.t.ppf(1 - ALPHA / 2, df) * se)
    low, high = diff - half, diff + half
    p = float(2 * sps.t.sf(abs(diff) / se, df))
    holds = _sided(low, high, sign)
    ours = f"{diff:+.4g} (95 % interval {low:+.4g} to {high:+.4g}, p = {p:.2g})"
    why = _WHY[holds]
    return Verdict(ours, holds, why, rule, mean=diff, low=low, high=high, runs=runs)


def contrast(
    groups: Sequence[Sequence[float]], weights: Sequence[float], sign: int, what: str
) -> Verdict:
    """The direction rule on a linear contrast ``sum(w_i mean_i)`` of group means (e.g.
    (m4 - m2) - (m10 - m8) with weights -1, 1, 1, -1): its Welch-Satterthwaite 95 % interval
    excludes 0 on ``sign``'s side (holds), on the other (fails), or includes 0 (undecided).
    ``what`` names the contrast in the rule.
    """
    xs = [np.asarray(g, dtype=float) for g in groups]
    xs = [x[~np.isnan(x)] for x in xs]
    word = "positive" if sign > 0 else "negative"
    rule = f"direction: Welch 95 % interval of {what} excludes 0 ({word})"
    runs = sum(len(x) for x in xs)
    if any(len(x) < 2 for x in xs):
        return Verdict("", None, "fewer than two runs in a group: no interval", rule, runs=runs)
    value = float(sum(w * x.mean() for w, x in zip(weights, xs, strict=True)))
    parts = [w * w * x.var(ddof=1) / len(x) for w, x in zip(weights, xs, strict=True)]
    se = float(np.sqrt(sum(parts)))
    if se == 0:
        return _fixed(value, sign, rule, runs)
    df = sum(parts) ** 2 / sum(v * v / (len(x) - 1) for v, x in zip(parts, xs, strict=True))
    half = float(sps.t.ppf(1 - ALPHA / 2, df) * se)
    low, high = value - half, value + half
    p = float(2 * sps.t.sf(abs(value) / se, df))
    holds = _sided(low, high, sign)
    ours = f"{value:+.4g} (95 % interval {low:+.4g} to {high:+.4g}, p = {p:.2g})"
    return Verdict(ours, holds, _WHY[holds], rule, mean=value, low=low, high=high, runs=runs)


def censored(ours: str, missing: int, runs: int, what: str) -> Verdict:
    """The undecided verdict of a claim whose metric ``missing`` of ``runs`` runs never reached
    (right-censored: only a lower bound is known), so it is not judged.
    """
    return Verdict(
        ours,
        None,
        f"{what} is censored: not judged from censored values",
        runs=runs,
        censored=missing / runs,
    )


def combine(parts: Sequence[Verdict], ours: str, runs: int, why: str = "") -> Verdict:
    """One verdict for a claim that needs every part to hold: it holds when all parts hold,
    fails when any part fails, and is undecided otherwise; the rule lists the parts' rules
    (``runs``: the runs the parts used together).
    """
    if any(v.holds is False for v in parts):
        holds: bool | None = False
    elif all(v.holds is True for v in parts) and parts:
        holds = True
    else:
        holds = None
    rules = list(dict.fromkeys(v.rule for v in parts if v.rule))
    return Verdict(ours, holds, why, "all of: " + "; ".join(rules), runs=runs)


def spread(before: Sequence[float], after: Sequence[float], what: str = "") -> Verdict:
    """Is the spread of ``after`` larger than that of ``before``? The Brown-Forsythe test
    (Levene's test about the medians): holds when the SD is larger and p < 0.05, fails when
    it is smaller and p < 0.05, and is undecided otherwise (``what`` names the values).
    """
    a = np.asarray(before, dtype=float)
    b = np.asarray(after, dtype=float)
    a, b = a[~np.isnan(a)], b[~np.isnan(b)]
    rule = f"spread: Brown-Forsythe test (Levene about the medians), p < {ALPHA:g}, larger SD"
    rule += f" of {what}" if what else ""
    runs = len(a) + len(b)
    if len(a) < 2 or len(b) < 2:
        return Verdict("", None, "fewer than two values on a side", rule, runs=runs)
    if all(np.ptp(np.abs(x - np.median(x))) == 0 for x in (a, b)):
        # Levene's statistic divides by the spread of these deviations: 0 for constant values
        # and for any two values a side
        why = "each side's deviations from its median are all equal: no test of spread"
        return Verdict(f"SD {b.std(ddof=1):.3g} vs {a.std(ddof=1):.3g}", None, why, rule, runs=runs)
    p = float(sps.levene(a, b, center="median").pvalue)
    holds = None if not p < ALPHA else bool(b.std(ddof=1) > a.std(ddof=1))
    why = "" if holds is not None else f"p = {p:.2g} >= {ALPHA:g}"
    ours = f"SD {b.std(ddof=1):.3g} vs {a.std(ddof=1):.3g} (Brown-Forsythe p = {p:.2g})"
    return Verdict(ours, holds, why, rule, runs=runs)


#: Runs up to which :func:`spearman` enumerates every permutation (8! = 40,320).
EXACT_UP_TO = 8
#: Seeded shuffles :func:`spearman` draws beyond :data:`EXACT_UP_TO` runs.
SHUFFLES = 9_999
#: Shuffles per batch (bounds the memory of a large sample: batch x runs floats).
_BATCH = 1_000


def spearman(x: Sequence[float], y: Sequence[float]) -> tuple[float, float, bool]:
    """Spearman's rho of ``y`` on ``x`` (average ranks for ties), its two-sided permutation p,
    and whether that p is exact.

    The p is the share of pairings of the values at least as far from no correlation as the
    observed one: over all n! of them up to :data:`EXACT_UP_TO` runs, else over
    :data:`SHUFFLES` seeded shuffles, ``(b + 1) / (SHUFFLES + 1)`` (b: shuffles as extreme),
    so never below 1e-4. The t approximation scipy's ``spearmanr`` reports is not used: on
    the few, heavily tied values of a sweep (a 0/1 outcome at three levels of a factor) it is
    far too small (6 runs: 0.047 where the exact p is 0.2; 30 runs, 1, 2 and 5 of 10 at three
    levels: 0.045 where it is 0.079). Both need two values or more (ConfigError otherwise).
    """
    rx = sps.rankdata(np.asarray(x, dtype=float))
    ry = sps.rankdata(np.asarray(y, dtype=float))
    rx, ry = rx - rx.mean(), ry - ry.mean()
    scale = float(np.sqrt((rx @ rx) * (ry @ ry)))
    if scale == 0:
        raise ConfigError("Spearman's rho needs two values or more of each variable")
    rho = float(rx @ ry) / scale
    tolerance = 1e-12 * max(1.0, abs(rho))
    n = len(rx)
    if n <= EXACT_UP_TO:
        pairings = ry[np.array(list(itertools.permutations(range(n))))]
        extreme = np.abs(pairings @ rx / scale) >= abs(rho) - tolerance
        return rho, float(extreme.mean()), True
    rng = np.random.default_rng(n)  # fixed: the same runs give the same p
    hits = 0
    for start in range(0, SHUFFLES, _BATCH):
        shuffled = rng.permuted(np.tile(ry, (min(_BATCH, SHUFFLES - start), 1)), axis=1)
        hits += int(np.sum(np.abs(shuffled @ rx / scale) >= abs(rho) - tolerance))
    return rho, (hits + 1) / (SHUFFLES + 1), False


def rank_order(factor: Sequence[float], values: Sequence[float], sign: int) -> Verdict:
    """The ordering rule over several values of a factor: Spearman's rho of ``values`` on
    ``factor`` over the runs, two-sided permutation p (:func:`spearman`) < 0.05 with the sign
    ``sign``.
    """
    x, y = np.asarray(factor, dtype=float), np.asarray(values, dtype=float)
    keep = ~(np.isnan(x) | np.isnan(y))
    x, y = x[keep], y[keep]
    word = "rises" if sign > 0 else "falls"
    rule = (
        f"ordering: Spearman rho over the runs, two-sided permutation p < {ALPHA:g} (exact up "
        f"to {EXACT_UP_TO} runs, else {SHUFFLES:,} seeded shuffles), the value {word}"
    )
    if len(x) < 3 or len(set(x)) < 2:
        return Verdict("", None, "fewer than three runs or one value", rule, runs=len(x))
    if np.ptp(y) == 0:
        why = f"the value is {y[0]:.4g} in every run: nothing to order"
        return Verdict("", None, why, rule, runs=len(x))
    rho, p, exact = spearman(x, y)
    holds = None if not p < ALPHA else bool(sign * rho > 0)
    why = "" if holds is not None else f"p = {p:.2g} >= {ALPHA:g}"
    shown = f"p = {p:.2g}" if exact or p > 1 / (SHUFFLES + 1) else f"p <= {p:.1g}"
    return Verdict(f"rho {rho:+.2f} ({shown}, {len(x)} runs)", holds, why, rule,
                   mean=rho, runs=len(x))  # fmt: skip


def correlation(x: Sequence[float], y: Sequence[float], sign: int, runs: int) -> Verdict:
    """The direction rule for a correlation of condition means (``x``, ``y``, one pair per
    condition): Pearson's r with its Fisher-z 95 % interval (needs four conditions).
    """
    a, b = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    n = len(a)
    rule = "direction: Fisher-z 95 % interval of Pearson r over the condition means excludes 0"
    if n < 4:
        return Verdict("", None, f"{n} conditions: at least 4 needed", rule, runs=runs)
    if np.ptp(a) == 0 or np.ptp(b) == 0:
        why = "one of the two is the same in every condition: no correlation to estimate"
        return Verdict("", None, why, rule, runs=runs)
    result = sps.pearsonr(a, b)
    r, p = float(result.statistic), float(result.pvalue)
    z, half = np.arctanh(np.clip(r, -0.999999, 0.999999)), sps.norm.ppf(1 - ALPHA / 2)
    low, high = float(np.tanh(z - half / np.sqrt(n - 3))), float(np.tanh(z + half / np.sqrt(n - 3)))
    holds = _sided(low, high, sign)
    ours = f"{r:.3f} (95 % interval {low:.3f} to {high:.3f}, {n} conditions, p = {p:.2g})"
    why = _WHY[holds]
    return Verdict(ours, holds, why, rule, mean=r, low=low, high=high, runs=runs)


def agreement(checkpoints: Mapping[str, Sequence[Sequence[float]]], what: str) -> Verdict:
    """The agreement rule (see the module) over ``checkpoints``: label -> the groups' values
    there (e.g. "1000 s" -> coverage of each geometry's runs); ``what`` names the groups.
    """
    rule = (
        f"agreement: Kruskal-Wallis over {what}, Holm-adjusted over the checkpoints; no "
        f"adjusted p < {ALPHA:g} holds (no difference found; no published margin), any "
        "fails"
    )
    tests = {}
    for label, groups in checkpoints.items():
        xs = [np.asarray(g, dtype=float) for g in groups]
        xs = [x[~np.isnan(x)] for x in xs]
        if len(xs) < 2 or any(len(x) < 2 for x in xs):
            runs = sum(len(x) for x in xs)
            return Verdict("", None, f"{label}: fewer than two runs in a group", rule, runs=runs)
        pooled = np.concatenate(xs)
        p = 1.0 if np.all(pooled == pooled[0]) else float(sps.kruskal(*xs).pvalue)
        tests[label] = (p, xs)
    if not tests:
        return Verdict("", None, "no checkpoint", rule, runs=0)
    order = sorted(tests, key=lambda k: tests[k][0])
    adjusted, running = {}, 0.0
    for rank, label in enumerate(order):  # Holm's step-down, kept monotone
        running = max(running, min(1.0, (len(order) - rank) * tests[label][0]))
        adjusted[label] = running
    worst = order[0]
    xs = tests[worst][1]
    means = [x.mean() for x in xs]
    low, high = xs[int(np.argmin(means))], xs[int(np.argmax(means))]
    gap = difference(low, high, +1)
    holds: bool | None = bool(adjusted[worst] >= ALPHA)
    runs = sum(len(x) for x in xs)
    few = min(len(x) for _, group in tests.values() for x in group) < MIN_AGREE
    ours = (
        f"smallest Holm-adjusted p = {adjusted[worst]:.2g} at {worst} ({len(tests)} "
        f"checkpoints); there the largest gap of the means {gap.ours}"
    )
    if holds and few:
        holds, why = None, f"no difference found, but fewer than {MIN_AGREE} runs in a group"
    elif holds:
        why = "no difference found; a gap within the interval above could go unseen"
    else:
        why = f"the {what} differ at {worst} by {gap.mean:+.3g}"
    return Verdict(ours, holds, why, rule, mean=gap.mean, low=gap.low, high=gap.high, runs=runs)


def coefficient(
    y: Sequence[float], regressors: Mapping[str, Sequence[float]], name: str, value: float
) -> Verdict:
    """The level rule on the coefficient ``name`` of the OLS fit ``y = a + sum_k b_k x_k`` over
    the runs (``regressors``: name -> values): the published ``value`` inside our 95 %
    t-interval of the coefficient holds; outside it fails, saying by how much ours differs. A
    design without full rank (collinear regressors) is not judged.
    """
    target = np.asarray(y, dtype=float)
    columns = [np.asarray(v, dtype=float) for v in regressors.values()]
    design = np.column_stack([np.ones_like(target), *columns])
    keep = ~np.isnan(design).any(axis=1) & ~np.isnan(target)
    design, target = design[keep], target[keep]
    n, k = design.shape
    terms = " + ".join(f"b_{key} {key}" for key in regressors)
    rule = f"level: the published {value:g} inside our 95 % interval of b_{name} in y = a + {terms}"
    if n <= k:
        return Verdict("", None, f"{n} runs for {k} coefficients", rule, runs=n)
    if np.linalg.matrix_rank(design) < k:
        return Verdict("", None, "the regressors are collinear: not computed", rule, runs=n)
    beta, *_ = np.linalg.lstsq(design, target, rcond=None)
    residual = target - design @ beta
    index = 1 + list(regressors).index(name)
    if np.all(np.abs(residual) <= 1e-12 * max(1.0, float(np.abs(target).max()))):
        why = "the fit leaves no residual (y is exact in the regressors): no interval"
        return Verdict(f"b_{name} {float(beta[index]):.4g}", None, why, rule, runs=n)
    sigma2 = float(residual @ residual) / (n - k)
    se = float(np.sqrt(sigma2 * np.linalg.inv(design.T @ design)[index, index]))
    half = float(sps.t.ppf(1 - ALPHA / 2, n - k) * se)
    b = float(beta[index])
    judged = level(b, b - half, b + half, n, value)
    return replace(judged, rule=rule, ours=f"b_{name} {judged.ours}")


def level_test(record: Published) -> Callable[[pd.DataFrame, pd.DataFrame | None], Verdict | None]:
    """A claim test that judges a "level" record by its own rule (:func:`band`) on the runs
    whose columns match its condition, so that a claim and the published number it restates
    are judged by one rule in one place. The test gives None when no run matches.
    """
    if record.kind != "level" or record.check != "band":
        raise ConfigError(f"level_test needs a 'band' level record, got {record.kind!r}")

    def test(runs: pd.DataFrame, samples: pd.DataFrame | None) -> Verdict | None:
        for key, value in record.condition.items():
            if key not in runs:
                return None
            if isinstance(value, int | float) and not isinstance(value, bool):
                numbers = pd.to_numeric(runs[key], errors="coerce").astype(float)
                runs = runs[np.isclose(numbers, value)]
            else:
                runs = runs[runs[key] == value]
        if runs.empty or record.metric not in runs:
            return None
        column = runs[record.metric]
        share = column.dtype == bool
        return band(column.astype(float), record.value, record.spread, share,
                    100.0 if share else 1.0)  # fmt: skip

    return test
