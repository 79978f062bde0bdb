"""Record types for published numbers, claims and figure layout, read by ``abm report``.

A model's *source* is the publication it reproduces. Its ``published.py`` lists the numbers the
source reports as :class:`Published` records (what was measured, under every setting the source
fixed, the value and its spread, and its kind: a level, the direction of an effect or an ordering),
its checkable claims as :class:`Claim` records, the summary metrics a run's end can cut short as
:class:`Censored` records, and the layout of the source's figures as a :class:`ReportLayout`. The
model class exposes them (``PUBLISHED``, ``CLAIMS``, ``CENSORED``, ``REPORT``), so reports, tests
and benchmarks read the source's numbers from one place. The rule that judges each kind is in
:mod:`abm.verdicts`. Nothing here holds a source's number.
"""

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import pandas as pd

from abm.errors import ConfigError

__all__ = [
    "CHECKS",
    "KINDS",
    "MEASURES",
    "Censored",
    "Claim",
    "MacroSpec",
    "Published",
    "ReportLayout",
    "Verdict",
]

#: What kind of result a published number is, each judged by one rule
#: (:mod:`abm.verdicts`): a level with the published spread, the direction of an effect, or an
#: ordering of conditions.
KINDS = ("level", "direction", "ordering")

#: How our value is computed from the runs of the condition.
MEASURES = ("mean", "change", "pair", "ratio", "r", "convex")

#: The checks of each kind: what the source's number says.
CHECKS = {
    "level": ("band", "shown"),
    "direction": ("same sign", "decreases", "increases", "above 1", "below 1", "positive",
                  "negative"),
    "ordering": ("first", "rises", "falls", "minimum inside"),
}  # fmt: skip

#: The measures each kind may use.
_MEASURES = {
    "level": ("mean",),
    "direction": ("change", "pair", "ratio", "r"),
    "ordering": ("mean", "convex"),
}


@dataclass(frozen=True)
class Published:
    """One published number, the condition it was measured under, and its kind.

    Attributes:
        section: the source's experiment ("corridor", "open space", "map 1", ...).
        quantity: what is measured, with its unit.
        condition: every setting the source fixed for this number, parameter -> value (the
            world, robots, particles, iterations, arena, time limit, ...). Ours is computed
            only from runs that match every one (a setting a sweep does not vary takes the
            model's default); otherwise the report says which setting differs.
        value: the published value (a number, or a short text such as "0.32 -> 0.02").
        kind: "level" (the published level, with its spread), "direction" (the sign of an
            effect) or "ordering" (how conditions rank): see :data:`KINDS`.
        metric: the summary column.
        check: what the source's number says (see :data:`CHECKS`): a level is tested as a
            two-sided "band" (``value +- spread``; without a spread, the value itself) or only
            "shown" beside ours (``note`` says why); a direction "decreases", "increases",
            has the "same sign" as the published change, a ratio "above 1" / "below 1", a
            correlation "positive" / "negative"; an ordering "rises" or "falls" from the
            previous record of the same section and quantity (the "first" of them is the
            reference), or has its "minimum inside" the range of ``factor``.
        measure: how ours is computed: "mean" (of ``metric``), "change" (percent change of
            the mean from ``factor = a`` to ``factor = b``), "pair" (the two means), "ratio"
            (mean at ``b`` / mean at ``a``), "r" (Pearson r of the condition means of
            ``metric`` and ``other``, conditions = values of ``by``), "convex" (where the mean
            of ``metric`` over ``factor`` is lowest).
        spread: the half-width of a level's band, in the value's unit (the published spread, or
            where ``note`` says so a band the source's own text sets); None: none published.
        factor: the parameter ``a`` and ``b`` are values of.
        a: the reference value of ``factor``.
        b: the compared value of ``factor``.
        other: the second column of an "r" record.
        by: the parameters whose combinations are the conditions of an "r" record.
        source: where in the source (table, figure, section).
        note: why a "shown" level has no verdict, or where a spread comes from.
        by_construction: why ours agrees by the model's own definitions (e.g. an energy that
            is a power times the time it correlates with); the report then labels the row
            "by construction (not a test)", never counted as reproduced. "": a test.

    """

    section: str
    quantity: str
    condition: Mapping[str, object]
    value: float | str
    kind: str
    metric: str
    check: str
    measure: str = "mean"
    spread: float | None = None
    factor: str | None = None
    a: object = None
    b: object = None
    other: str | None = None
    by: tuple[str, ...] = ()
    source: str = ""
    note: str = ""
    by_construction: str = ""

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ConfigError(f"kind must be one of {KINDS}, got {self.kind!r}")
        if self.check not in CHECKS[self.kind]:
            raise ConfigError(
                f"check of a {self.kind!r} record must be one of {CHECKS[self.kind]}, "
                f"got {self.check!r}"
            )
        if self.measure not in _MEASURES[self.kind]:
            raise ConfigError(
                f"measure of a {self.kind!r} record must be one of {_MEASURES[self.kind]}, "
                f"got {self.measure!r}"
            )
        if (self.measure == "convex") != (self.check == "minimum inside"):
            raise ConfigError("'minimum inside' is the check of a 'convex' measure, and only")
        if self.measure in ("change", "pair", "ratio", "convex") and self.factor is None:
            raise ConfigError(f"a {self.measure!r} record needs the factor it varies")
        if self.measure == "r" and (self.other is None or not self.by):
            raise ConfigError("an 'r' record needs other (the second column) and by")
        if self.check == "band" and isinstance(self.value, str):
            raise ConfigError("a 'band' level needs a numeric value")
        if self.spread is not None and not self.spread > 0:
            raise ConfigError(f"spread must be > 0 (or None), got {self.spread!r}")
        if self.check == "shown" and not self.note:
            raise ConfigError("a 'shown' level must say in note why it has no verdict")


@dataclass(frozen=True)
class Censored:
    """A summary metric that the end of a run can cut short (right-censored).

    A time to reach a target (coverage time, time to 95 %, iterations to converge) is only
    known for runs that reached it; a run cut by the time limit reports the limit instead,
    and a run that ended without reaching the target may report nothing. Reports show such
    a metric as censored (the share of censored runs, the Kaplan-Meier median) and never
    judge a claim from censored values.

    Attributes:
        metric: the summary column.
        ends: prefixes of ``end_reason`` after which the metric is censored (the value the
            run reports is then only a lower bound).
        bound: for a metric that is missing (NaN) when the target was never reached: the
            summary column whose value is then the lower bound (e.g. the run's time); None:
            a missing value is not a censored one.
        since: a summary column subtracted from ``bound`` (the start of the metric's clock,
            e.g. the end of a deployment phase); None: 0.

    """

    metric: str
    ends: tuple[str, ...] = ("time limit",)
    bound: str | None = None
    since: str | None = None


@dataclass(frozen=True)
class ReportLayout:
    """The source's figure types for a model's sweeps (``abm report`` draws them).

    Attributes:
        x: the swept parameter on the x axis (e.g. the inter-launch period), or a numeric
            summary column derived from the swept parameters (e.g. the total robot count).
        hue: one line (or panel) per value of this parameter (or summary column).
        hue_order: the order of ``hue``'s values.
        metrics: summary columns drawn as mean +- standard error against ``x``.
        stacked: columns stacked into one bar per ``x`` value (e.g. energy per mode), with
            ``total`` their sum.
        total: the column that is the sum of ``stacked``.
        compare: a parameter whose values are compared in one bar chart of ``compare_metric``.
        compare_metric: the column of that chart.
        optimum: columns whose normalised sum is minimised over ``x`` (the optimal value).
        correlate: two columns whose condition means are correlated (Pearson r).
        curves: columns of the model's time series (``SwarmModel.samples``) drawn against
            ``curve_x``, mean and spread over the runs of each condition.
        curve_x: the time column of those curves.
        curve_spread: "sd" (standard deviation over runs, as the usual error bars) or "se".
        labels: column -> axis label with unit.
        notes: column -> how to read it (shown under the figure).
        alternatives: layouts for other kinds of sweep of the same model (e.g. against a fault
            rate); a sweep is drawn with the first of this layout and its alternatives whose
            ``x`` it varies.

    """

    x: str | None = None
    hue: str | None = None
    hue_order: tuple[str, ...] = ()
    metrics: tuple[str, ...] = ()
    stacked: tuple[str, ...] = ()
    total: str | None = None
    compare: str | None = None
    compare_metric: str | None = None
    optimum: tuple[str, ...] = ()
    correlate: tuple[str, str] | None = None
    curves: tuple[str, ...] = ()
    curve_x: str = "time"
    curve_spread: str = "sd"
    labels: Mapping[str, str] = field(default_factory=dict)
    notes: Mapping[str, str] = field(default_factory=dict)
    alternatives: tuple["ReportLayout", ...] = ()


@dataclass(frozen=True)
class MacroSpec:
    """How ``abm fit`` fits the wander/beacon recurrence to a model's counts.

    The recurrence moves robots from a moving state w to a settled state
    b: ``w_t = w_{t-1} - a_t w_{t-1} + alpha5``, ``b_t = b_{t-1} + a_t w_{t-1}``,
    ``a_t = alpha6 a_{t-1}``; ``alpha5`` robots arrive per step.

    Attributes:
        moving: the state counted as w.
        settled: the state counted as b.
        step: the recurrence's step (s).
        arrival_period: the parameter holding the time between two arrivals (s), so that
            alpha5 = step / period; None: alpha5 is estimated from the growth of w + b.
        supply: how many robots there are in all (w + b never exceeds it: arrivals stop, our
            extension for swarms of fixed size); None: no limit, as in the source.
        regression: covariate -> where its value is, for the published lambda regressions
            (``alpha6 = l0 + l1 r + l2 r^2``, ``a0 = l3 - l4 entropy + l5 envsize``): keys
            "radius", "entropy", "envsize"; None: no regression.
        rates: the model's own names of the recurrence's rates, by symbol: "a0" (the share of
            the moving robots that settle in the first step), "alpha6" (the factor that share
            changes by at each step) and "alpha5" (robots arriving per step); a rate not named
            here is named after the states (see :meth:`names`).
        published: condition (the values of ``condition_keys``, in order) -> the published
            numbers for it (e.g. w, b, w_hat, b_hat, t, rmsd_w, rmsd_b).
        condition_keys: the parameters a published condition names.
        published_summary: the published overall figures, name -> (mean, std), e.g. mean RMSDs.
        published_label: where the per-condition numbers are published (e.g. "Table 1").
        summary_label: where the overall figures are published (e.g. "Table 2, 10 maps").
        lambdas: the published fitted l0..l5, if any.
        source: the source's citation.

    ``arrival_period``, ``supply`` and the values of ``regression`` each name a parameter of
    the model (a field or property of its ``Params``: ``abm fit`` reads each run's own value,
    the default where a sweep did not set it) or, for a figure only the run determines (a
    generated map's entropy), a key of its summary.

    """

    moving: str
    settled: str
    step: float = 1.0
    arrival_period: str | None = None
    supply: str | None = None
    regression: Mapping[str, str] | None = None
    published: Mapping[tuple, Mapping[str, float]] = field(default_factory=dict)
    condition_keys: tuple[str, ...] = ()
    published_summary: Mapping[str, tuple[float, float]] = field(default_factory=dict)
    published_label: str = ""
    summary_label: str = ""
    lambdas: Mapping[str, float] | None = None
    source: str = ""
    rates: Mapping[str, str] = field(default_factory=dict)

    @property
    def inputs(self) -> tuple[str, ...]:
        """The parameters and summary keys the spec reads (arrival period, supply, covariates)."""
        names = (self.arrival_period, self.supply, *(self.regression or {}).values())
        return tuple(dict.fromkeys(n for n in names if n is not None))

    def names(self) -> dict[str, str]:
        """What ``abm fit`` calls the recurrence's symbols in what it prints: w and b by the
        two counted states, a0, alpha6 and alpha5 by ``rates``, else after the states
        (``<settled>_share_0``, ``<settled>_share_decay``, ``arrivals``).
        """
        named = {
            "a0": f"{self.settled}_share_0",
            "alpha6": f"{self.settled}_share_decay",
            "alpha5": "arrivals",
            **self.rates,
        }
        return {"w": self.moving, "b": self.settled, **named}


@dataclass(frozen=True)
class Verdict:
    """What a sweep's runs say about one claim, and by which rule.

    Attributes:
        ours: our measured value(s), as text.
        holds: True / False; None when these runs cannot decide (``why`` says why).
        why: the reason (e.g. by how much a level differs).
        rule: the test applied, in words (e.g. "two-sided band 85 +- 10: our 95 % interval
            inside it"); empty for a claim whose test states its rule in ``why``.
        mean: our value the rule judged (a mean, a difference, a share, rho), if one number.
        low: the lower end of its 95 % interval.
        high: the upper end.
        runs: the runs the rule used.
        censored: the share of those runs a time limit censored (0-1), where the claim's
            metric can be censored.

    """

    ours: str
    holds: bool | None
    why: str = ""
    rule: str = ""
    mean: float | None = None
    low: float | None = None
    high: float | None = None
    runs: int | None = None
    censored: float | None = None


@dataclass(frozen=True)
class Claim:
    """A checkable claim of a source and the test a sweep's runs put it to.

    Attributes:
        id: the claim's label (e.g. "C01").
        source: where the source makes it (section, figure).
        statement: the claim, in the source's words or close to them.
        kind: "Q" (the source gives a number) or "QL" (a direction, ordering or shape).
        setup: the runs that test it, in words.
        test: ``f(runs, samples) -> Verdict | None`` on the tidy run rows (one per run) and
            the model's time series (``samples``, may be None); None when these runs lack the
            set-up. A claim no simulation can test has no test and says why in ``untestable``.
        untestable: why a claim without a test cannot be tested (or where else it is tested).
        condition: the settings the source fixed for every run of the claim, parameter ->
            value (a setting a sweep does not vary takes the model's default). The test sees
            only matching runs; when none match, the report says which setting differs.
        by_construction: why the claim holds by construction of the model or of its test
            (empty: it does not). Such a claim is labelled "by construction (not a test)"
            and never counted as reproduced.

    """

    id: str
    source: str
    statement: str
    kind: str
    setup: str
    test: Callable[[pd.DataFrame, pd.DataFrame | None], Verdict | None] | None = None
    untestable: str = ""
    condition: Mapping[str, object] = field(default_factory=dict)
    by_construction: str = ""

    def __post_init__(self) -> None:
        if self.kind not in ("Q", "QL"):
            raise ConfigError(f"kind must be 'Q' or 'QL', got {self.kind!r}")
        if self.test is None and not (self.untestable or self.by_construction):
            raise ConfigError(f"claim {self.id}: without a test, say why in untestable")
