"""Published numbers and claims beside ours: each judged by one stated rule on the runs whose
condition matches the paper's.

Every :class:`abm.published.Published` record names every setting the paper fixed; ours is
computed only from runs that match all of them (a setting the sweep does not vary takes the
model's default), and otherwise the row says "not comparable" and which setting differs. A
metric the runs' ends can censor (the model's ``CENSORED``) is shown as censored (share of
censored runs, Kaplan-Meier median) and never judged. Each row states its rule
(:mod:`abm.verdicts`), our value with its 95 % interval and the number of runs; the same rows
are written as ``comparison.csv`` beside the report (:func:`comparison_csv`).
"""

import dataclasses
from collections.abc import Mapping, Sequence
from dataclasses import replace

import numpy as np
import pandas as pd

from abm import verdicts
from abm.published import Censored, Claim, Published, Verdict
from analysis import stats
from analysis.censoring import censoring_causes, ended_by, survival

__all__ = [
    "BY_CONSTRUCTION",
    "CSV_COLUMNS",
    "NOT_COMPARABLE",
    "NOT_IN_SWEEP",
    "VERDICTS",
    "compare_published",
    "comparison_csv",
    "fault_free",
    "judge_claims",
    "matching_runs",
    "parameter_defaults",
]

NOT_IN_SWEEP = "not in this sweep"
NOT_COMPARABLE = "not comparable"
CENSORED = "censored"
BY_CONSTRUCTION = "by construction (not a test)"
#: Verdict.holds -> the verdict shown.
VERDICTS = {True: "holds", False: "does not hold", None: "undecided"}

#: The columns of ``comparison.csv``, one row per published number and per claim.
CSV_COLUMNS = (
    "claim or metric",
    "condition",
    "paper value",
    "paper spread",
    "ours",
    "ours mean",
    "ours 95% low",
    "ours 95% high",
    "runs",
    "censored share",
    "rule",
    "verdict",
    "reason",
)

_CHECK_SIGN = {"decreases": -1, "increases": 1, "above 1": 1, "below 1": -1, "positive": 1,
               "negative": -1, "rises": 1, "falls": -1}  # fmt: skip

#: The keywords whose non-default values inject faults (the papers' numbers have none).
_FAULT_SWITCHES = ("fault_rate", "fault_times", "link_outage_rate", "loss_burst_rate",
                   "sensor_fault_rate")  # fmt: skip


def fault_free(runs: pd.DataFrame, keep: Sequence[str] = ()) -> pd.DataFrame:
    """The runs without injected faults (:mod:`abm.faults`), judged on every fault keyword
    except those in ``keep`` (e.g. a condition that names one itself).
    """
    for key in _FAULT_SWITCHES:
        if key in runs and key not in keep:
            runs = runs[~runs[key].map(_injects)]
    return runs


def _injects(value: object) -> bool:
    """True for a fault keyword's value that injects faults (a rate > 0, some times)."""
    if value is None or (isinstance(value, float) and np.isnan(value)):
        return False
    if isinstance(value, int | float | np.number):
        return value > 0
    return len(value) > 0


def _equal(column: pd.Series, value) -> pd.Series:
    if value is None:  # a setting left at None (e.g. "the default reading"): a missing value
        return column.isna()
    if isinstance(value, bool) or not isinstance(value, int | float):
        return column == value
    numbers = pd.to_numeric(column, errors="coerce").astype(float)
    return pd.Series(np.isclose(numbers, value), index=column.index)


def _shown(value: object) -> str:
    if value is None:
        return "unset (the model's default reading)"
    return f"{value:g}" if isinstance(value, float) else str(value)


def _name(key: str) -> str:
    return key.replace("_", " ")


def parameter_defaults(cls: type | None) -> dict[str, object]:
    """The model class's parameter defaults: the value of a setting a run does not record
    (the sweep did not vary it). Empty for None (a model not loadable here).
    """
    if cls is None:
        return {}
    return {f.name: f.default for f in dataclasses.fields(cls.Params)}


def matching_runs(
    df: pd.DataFrame,
    condition: Mapping[str, object],
    defaults: Mapping[str, object],
    varied: Sequence[str] = (),
    cut_ends: Sequence[str] = (),
) -> tuple[pd.DataFrame, str]:
    """The finished, fault-free runs of ``df`` that match every setting of ``condition``, and
    (when none does) why: "<setting> is X here, Y in the paper".

    When any of the matching runs ended in one of ``cut_ends`` (the model's ``CUT_ENDS``:
    ended before the run the paper describes was complete), none is returned, with how many
    were cut: dropping only those would keep the runs that happened to finish in time, a
    biased sample of the condition.

    A setting a run does not record (the sweep did not vary it) takes its value from
    ``defaults`` (the model's parameter defaults). A setting in ``varied`` (the parameters a
    sensitivity design varies) that the condition does not name must be at its default too:
    the paper's condition leaves it at the paper's value (or our reading), and a design's runs
    each move dozens of them, so pooling them would put numbers of other models beside the
    paper's.
    """
    runs = fault_free(stats.ok_runs(df), keep=list(condition))
    if runs.empty:
        return runs, "no finished run"
    for key in varied:
        if key in condition or key not in runs or key not in defaults:
            continue
        runs = runs[_equal(_recorded(runs, key, defaults), defaults[key])]
        if runs.empty:
            return runs, (
                f"{_name(key)} varies here (a sensitivity design), "
                f"{_shown(defaults[key])} at the paper's condition"
            )
    for key, want in condition.items():
        if key in runs:
            column = _recorded(runs, key, defaults)
        elif key in defaults:
            column = pd.Series([defaults[key]] * len(runs), index=runs.index, dtype=object)
        else:
            return runs.iloc[0:0], f"{_name(key)} is not recorded here, {_shown(want)} in the paper"
        match = _equal(column, want)
        if not match.any():
            here = ", ".join(sorted({_shown(v) for v in column}))
            return runs.iloc[0:0], f"{_name(key)} is {here} here, {_shown(want)} in the paper"
        runs = runs[match]
    return _uncut(runs, cut_ends)


def _uncut(runs: pd.DataFrame, cut_ends: Sequence[str]) -> tuple[pd.DataFrame, str]:
    """``runs`` and "" when none ended in ``cut_ends``; else no run, and how many were cut."""
    cut = ended_by(runs, cut_ends)
    if not cut.any():
        return runs, ""
    ends = " or ".join(sorted(set(runs.loc[cut, "end_reason"].astype(str))))
    return runs.iloc[0:0], (
        f"{int(cut.sum())} of {len(runs)} runs ended by {ends} before the run the paper "
        "describes was complete"
    )


def _recorded(runs: pd.DataFrame, key: str, defaults: Mapping[str, object]) -> pd.Series:
    """The runs' setting ``key``, the model's default where a run does not record it (a run
    of a sweep that did not vary it, pooled with one that did).
    """
    column = runs[key]
    if key in defaults:
        column = column.astype(object).where(column.notna(), defaults[key])
    return column


def _values(runs: pd.DataFrame, metric: str) -> tuple[np.ndarray, bool]:
    """The metric's values and whether they are a share (0/1, shown in %)."""
    column = runs[metric]
    known = column.dropna()
    # a column of flags (bool, or object when some rows lack it) is a share of runs
    share = column.dtype == bool or (
        len(known) > 0 and known.map(lambda v: isinstance(v, bool | np.bool_)).all()
    )
    return column.astype(float).to_numpy(), bool(share)


def _described(values: np.ndarray, share: bool) -> Verdict:
    """Our mean and its 95 % interval as a Verdict without a decision (a row that is shown,
    not judged), so that the CSV carries the numbers too.
    """
    scale = 100.0 if share else 1.0
    mean, low, high = (scale * v for v in verdicts.interval(values, share=share))
    n = int(np.sum(~np.isnan(values)))
    text = (
        f"{mean:.4g} (1 run)"
        if not np.isfinite(low)
        else (f"{mean:.4g} (95 % interval {low:.4g} to {high:.4g})")
    )
    return Verdict(text, None, mean=mean, low=low, high=high, runs=n)


def _published_text(item: Published) -> str:
    if isinstance(item.value, str):
        return item.value
    text = f"{item.value:+.1f}" if item.measure == "change" else f"{item.value:g}"
    return text + (f" +- {item.spread:g}" if item.spread is not None else "")


def _condition_text(item: Published) -> str:
    parts = [f"{_name(k)} {_shown(v)}" for k, v in item.condition.items()]
    if item.measure in ("change", "pair", "ratio"):
        parts.append(f"{_name(item.factor)} {_shown(item.a)} -> {_shown(item.b)}")
    return ", ".join(parts)


def _row(item: Published, verdict: str, reason: str, ours: str = "", runs: int = 0,
         judged: Verdict | None = None, censored: float | None = None) -> dict:  # fmt: skip
    """One row of the comparison (the HTML's columns plus the CSV's numbers)."""
    return {
        "section": item.section,
        "quantity": item.quantity,
        "condition": _condition_text(item),
        "published": _published_text(item),
        "ours": ours,
        "runs": runs,
        "rule": judged.rule if judged is not None else "",
        "verdict": verdict,
        "reason": reason,
        "source": item.source,
        "_mean": None if judged is None else judged.mean,
        "_low": None if judged is None else judged.low,
        "_high": None if judged is None else judged.high,
        "_censored": censored,
        "_value": item.value,
        "_spread": item.spread,
    }


def compare_published(
    df: pd.DataFrame,
    records: Sequence[Published],
    defaults: Mapping[str, object] | None = None,
    censored: Sequence[Censored] = (),
    varied: Sequence[str] = (),
    cut_ends: Sequence[str] = (),
) -> pd.DataFrame:
    """Every published record beside ours for the same condition, with its verdict.

    Args:
        df: the sweeps' run rows (parameters and summary, one row per run).
        records: the model's published numbers.
        defaults: the model's parameter defaults (the value of a setting a run does not
            record).
        censored: the summary metrics the runs' ends can censor (the model's ``CENSORED``).
        varied: parameters a sensitivity design varies; a run counts for a record only at
            their defaults (unless the record's condition or factor names them), see
            :func:`matching_runs`.
        cut_ends: ends of a run cut short (the model's ``CUT_ENDS``): a record whose runs
            include one is "not comparable" (:func:`matching_runs`).

    Returns:
        Columns section, quantity, condition, published, ours, runs, rule, verdict ("holds",
        "does not hold", "undecided", "censored", "not comparable", "not in this sweep",
        "(reference)" or "shown only"), reason, source; and the CSV's numbers in columns whose
        names start with "_".

    """
    defaults = defaults or {}
    specs = {c.metric: c for c in censored}
    previous: dict = {}
    rows = []
    for item in records:
        free = [k for k in varied if k != item.factor]  # a change's factor is compared
        runs, why = matching_runs(df, item.condition, defaults, free, cut_ends)
        key, before = (item.section, item.quantity), None
        if item.kind == "ordering" and item.measure == "mean":
            before = previous.get(key)
            previous[key] = runs if not runs.empty and item.metric in runs else None
        if runs.empty:
            verdict = NOT_COMPARABLE if why != "no finished run" else NOT_IN_SWEEP
            rows.append(_row(item, verdict, why))
            continue
        if item.metric not in runs or (item.other is not None and item.other not in runs):
            rows.append(_row(item, NOT_IN_SWEEP, f"these runs do not record {item.metric}"))
            continue
        row = _judge(item, runs, before, specs)
        if item.by_construction and row["verdict"] in VERDICTS.values():
            row.update({"verdict": BY_CONSTRUCTION, "reason": item.by_construction})
        rows.append(row)
    return pd.DataFrame(rows)


def _groups(item: Published, runs: pd.DataFrame, before: pd.DataFrame | None) -> list:
    """The runs each side of the record's comparison uses."""
    if item.measure in ("change", "pair", "ratio"):
        return [runs[_equal(runs[item.factor], item.a)], runs[_equal(runs[item.factor], item.b)]]
    if item.measure == "mean" and item.kind == "ordering" and before is not None:
        return [before, runs]
    return [runs]


def _judge(item: Published, runs: pd.DataFrame, before: pd.DataFrame | None, specs: dict) -> dict:
    """The row of one record whose condition these runs match."""
    if item.measure in ("change", "pair", "ratio", "convex") and item.factor not in runs:
        return _row(item, NOT_IN_SWEEP, f"these runs do not vary {_name(item.factor)}")
    groups = _groups(item, runs, before)
    n = sum(len(g) for g in groups)
    if any(g.empty for g in groups):
        missing = item.b if len(groups) == 2 and groups[1].empty else item.a
        return _row(item, NOT_IN_SWEEP, f"no run at {_name(item.factor)} {_shown(missing)}")
    spec = specs.get(item.metric)
    if spec is not None:
        parts = [survival(g, spec) for g in groups]
        hit = sum(p.censored for p in parts)
        if hit:
            share = hit / max(1, sum(p.runs for p in parts))
            ours = " -> ".join(p.text() for p in parts)
            causes = censoring_causes(pd.concat(groups), spec)
            reason = f"{hit} of {n} runs censored ({causes}): not judged from censored values"
            return _row(item, CENSORED, reason, ours, n, censored=share)
    share_of_censored = 0.0 if spec is not None else None
    if item.measure == "mean" and item.kind == "level":
        values, share = _values(runs, item.metric)
        if item.check == "shown":
            described = _described(values, share)
            return _row(item, "shown only", item.note, described.ours, n, described,
                        share_of_censored)  # fmt: skip
        judged = verdicts.band(values, item.value, item.spread, share, 100.0 if share else 1.0)
        return _verdict_row(item, judged, judged.ours, n, share_of_censored)
    if item.measure == "mean":  # an ordering against the previous condition
        values, share = _values(runs, item.metric)
        described = _described(values, share)
        if before is None or item.check == "first":
            why = (
                item.note or "the first of this ordering"
                if item.check == "first"
                else "the previous condition of this ordering is not in these runs"
            )
            return _row(item, "(reference)", why, described.ours, n, described, share_of_censored)
        first, _ = _values(before, item.metric)
        judged = verdicts.difference(first, values, _CHECK_SIGN[item.check],
                                     100.0 if share else 1.0)  # fmt: skip
        ours = f"{described.ours}; vs the previous: {judged.ours}"
        return _verdict_row(item, judged, ours, n, share_of_censored)
    if item.measure in ("change", "pair", "ratio"):
        (a, share), (b, _) = _values(groups[0], item.metric), _values(groups[1], item.metric)
        sign = int(np.sign(item.value)) if item.check == "same sign" else _CHECK_SIGN[item.check]
        scale = 100.0 if share else 1.0
        judged = verdicts.difference(a, b, sign, scale)
        m0, m1 = scale * np.nanmean(a), scale * np.nanmean(b)
        if item.measure == "pair":
            shown = f"{m0:.3g} -> {m1:.3g}"
        elif m0 == 0:
            shown = "undefined (0 at baseline)"
        elif item.measure == "ratio":
            shown = f"{m1 / m0:.2f}"
        else:
            shown = f"{100.0 * (m1 - m0) / m0:+.1f}"
        if item.measure == "change" and m0 > 0:  # the interval in % of the baseline mean
            judged = replace(
                judged,
                rule=judged.rule + "; shown in % of the baseline mean",
                mean=100.0 * judged.mean / m0 if judged.mean is not None else None,
                low=100.0 * judged.low / m0 if judged.low is not None else None,
                high=100.0 * judged.high / m0 if judged.high is not None else None,
            )
        return _verdict_row(item, judged, f"{shown}; difference {judged.ours}", n,
                            share_of_censored)  # fmt: skip
    if item.measure == "convex":
        return _convex(item, runs, share_of_censored)
    # "r": Pearson r of condition means
    by = [b for b in item.by if b in runs]
    if not by:
        return _row(item, NOT_IN_SWEEP, f"these runs do not vary {', '.join(item.by)}")
    means = runs.groupby(by)[[item.metric, item.other]].mean().dropna()
    judged = verdicts.correlation(means[item.metric], means[item.other],
                                  _CHECK_SIGN[item.check], n)  # fmt: skip
    return _verdict_row(item, judged, judged.ours, n, share_of_censored)


def _verdict_row(
    item: Published, judged: Verdict, ours: str, n: int, censored: float | None
) -> dict:
    return _row(item, VERDICTS[judged.holds], judged.why, ours, n, judged, censored)


def _convex(item: Published, runs: pd.DataFrame, censored: float | None) -> dict:
    """The lowest mean of the metric over the factor's values lies inside their range: both
    end values' means are higher, each by the direction rule.
    """
    levels = sorted(runs[item.factor].dropna().unique())
    if len(levels) < 3:
        return _row(item, NOT_IN_SWEEP, f"fewer than three values of {_name(item.factor)}")
    means = runs.groupby(item.factor)[item.metric].mean()
    best = means.idxmin()
    low = runs[_equal(runs[item.factor], best)][item.metric].to_numpy(float)
    ours = f"minimum at {_shown(best)}"
    rule = ("ordering: the lowest mean inside the range, each end's mean higher by a Welch 95 % "
            "interval that excludes 0")  # fmt: skip
    if best in (levels[0], levels[-1]):
        judged = Verdict(ours, False, "the lowest mean is at an end of the range", rule)
        return _row(item, VERDICTS[False], judged.why, ours, len(runs), judged, censored)
    ends = [
        verdicts.difference(low, runs[_equal(runs[item.factor], end)][item.metric], 1)
        for end in (levels[0], levels[-1])
    ]
    holds = True if all(e.holds for e in ends) else None
    shown = f"{ours}; ends higher by {ends[0].ours} and {ends[1].ours}"
    why = "" if holds else "an end's interval includes 0"
    judged = Verdict(shown, holds, why, rule)
    return _row(item, VERDICTS[holds], why, shown, len(runs), judged, censored)


def judge_claims(
    runs: pd.DataFrame,
    samples: pd.DataFrame | None,
    claims: Sequence[Claim],
    defaults: Mapping[str, object] | None = None,
    varied: Sequence[str] = (),
    cut_ends: Sequence[str] = (),
) -> list[dict]:
    """Every claim with ours and its verdict on the finished, fault-free runs.

    A claim whose ``condition`` no run matches is "not comparable" (which setting differs;
    ``varied``: parameters a sensitivity design varies, which must be at their defaults, see
    :func:`matching_runs`), as is one whose runs include a run cut short (``cut_ends``, the
    model's ``CUT_ENDS``);
    a claim whose test finds no set-up in the runs is "not in this sweep"; a claim that holds
    by construction is labelled so whatever its test says, and is never counted as reproduced.

    Returns:
        One dict per claim: id, source, claim, type, set-up, ours, rule, runs, verdict, why;
        and the CSV's numbers in keys that start with "_".

    """
    defaults = defaults or {}
    rows = []
    for claim in claims:
        selected, differs = matching_runs(runs, claim.condition, defaults, varied, cut_ends)
        verdict: Verdict | None = None
        if claim.test is not None and not selected.empty:
            kept = samples
            if samples is not None and "run_id" in selected:
                kept = samples[samples["run_id"].isin(selected["run_id"])]
            verdict = claim.test(selected, kept)
        if claim.by_construction:
            shown, why = BY_CONSTRUCTION, claim.by_construction
        elif claim.test is None:
            shown, why = "not testable", claim.untestable
        elif selected.empty:
            shown = NOT_COMPARABLE if differs != "no finished run" else NOT_IN_SWEEP
            why = differs
        elif verdict is None:
            shown, why = NOT_IN_SWEEP, claim.setup
        elif verdict.censored and verdict.holds is None:  # decided parts keep their verdict
            shown, why = CENSORED, verdict.why
        else:
            shown, why = VERDICTS[verdict.holds], verdict.why
        rule = ""
        if verdict is not None and not claim.by_construction:
            rule = verdict.rule
            if not rule and not verdict.censored:  # a test that states its rule in ``why``
                rule, why = verdict.why, ""
        setup = claim.setup
        if claim.condition:
            fixed = ", ".join(f"{_name(k)} {_shown(v)}" for k, v in claim.condition.items())
            setup += f" (the paper's settings: {fixed})"
        rows.append(
            {
                "id": claim.id,
                "source": claim.source,
                "claim": claim.statement,
                "type": claim.kind,
                "set-up": setup,
                "ours": verdict.ours if verdict is not None else "",
                "rule": rule,
                "runs": "" if verdict is None or verdict.runs is None else verdict.runs,
                "verdict": shown,
                "why": why,
                "_mean": None if verdict is None else verdict.mean,
                "_low": None if verdict is None else verdict.low,
                "_high": None if verdict is None else verdict.high,
                "_censored": None if verdict is None else verdict.censored,
            }
        )
    return rows


def comparison_csv(published: pd.DataFrame | None, claims: list[dict] | None) -> pd.DataFrame:
    """The rows of ``comparison.csv``: every published number and every claim with its
    condition, the paper's value and spread, our mean and 95 % interval, runs, the censored
    share, the verdict and the reason (columns :data:`CSV_COLUMNS`).
    """
    rows = [
        _csv_row(
            row,
            f"{row['section']}: {row['quantity']}",
            row["condition"],
            row["reason"],
            paper=(row["_value"], row["_spread"]),
        )  # fmt: skip
        for row in ([] if published is None else published.to_dict("records"))
    ]
    rows += [
        _csv_row(row, f"{row['id']}: {row['claim']}", row["set-up"], row["why"])
        for row in claims or []
    ]
    return pd.DataFrame(rows, columns=list(CSV_COLUMNS))


def _csv_row(
    row: Mapping, name: str, condition: object, reason: object, paper: tuple = (None, None)
) -> dict:
    """One row of ``comparison.csv`` from a page row (a published number's or a claim's)."""
    return {
        "claim or metric": name,
        "condition": condition,
        "paper value": paper[0],
        "paper spread": paper[1],
        "ours": row["ours"],
        "ours mean": row["_mean"],
        "ours 95% low": row["_low"],
        "ours 95% high": row["_high"],
        "runs": row["runs"],
        "censored share": row["_censored"],
        "rule": row["rule"],
        "verdict": row["verdict"],
        "reason": reason,
    }
