"""Record types for a paper's published numbers and figure layout, read by ``abm report``.

A model's ``published.py`` lists the numbers its paper reports as :class:`Published` records
(what was measured, under which condition, the value, and the rule that says whether our
result "agrees in direction"), and the layout of the paper's figures as a
:class:`ReportLayout`. The model class exposes both (``PUBLISHED``, ``REPORT``), so reports,
tests and benchmarks read the paper's numbers from one place. Nothing here holds a paper's
number.
"""

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import pandas as pd

from abm.errors import ConfigError

__all__ = ["CHECKS", "KINDS", "Claim", "MacroSpec", "Published", "ReportLayout", "Verdict"]

#: How our value is computed from the runs of the condition.
KINDS = ("level", "change", "pair", "ratio", "r", "convex")

#: The rules deciding "direction agrees", per kind.
CHECKS = {
    "level": ("reference", "rises", "falls", "at least"),
    "change": ("same sign",),
    "pair": ("decreases", "increases"),
    "ratio": ("above 1", "below 1"),
    "r": ("positive", "negative"),
    "convex": ("minimum inside",),
}


@dataclass(frozen=True)
class Published:
    """One published number and how to compute ours from a sweep's runs.

    Attributes:
        section: the paper's experiment ("corridor", "open space", "map 1", ...).
        quantity: what is measured, with its unit.
        condition: parameter -> value selecting the runs (e.g. ``{"world": "corridor"}``).
        value: the published value (a number, or a short text such as "0.32 -> 0.02").
        kind: how ours is computed: "level" (mean of ``metric``), "change" (percent change of
            the mean from ``factor = a`` to ``factor = b``), "pair" (the two means), "ratio"
            (mean at ``b`` / mean at ``a``), "r" (Pearson r of the condition means of
            ``metric`` and ``other``, conditions = values of ``by``), "convex" (where the mean
            of ``metric`` over ``factor`` is lowest).
        metric: the summary column.
        check: the rule for "direction agrees" (see :data:`CHECKS`): for "level", "rises" and
            "falls" compare with the previous record of the same section and quantity.
        factor: the parameter ``a`` and ``b`` are values of.
        a: the reference value of ``factor``.
        b: the compared value of ``factor``.
        other: the second column of an "r" record.
        by: the parameters whose combinations are the conditions of an "r" record.
        threshold: the bound of an "at least" check.
        source: where in the paper (table, figure, section).

    """

    section: str
    quantity: str
    condition: Mapping[str, object]
    value: float | str
    kind: str
    metric: str
    check: str
    factor: str | None = None
    a: object = None
    b: object = None
    other: str | None = None
    by: tuple[str, ...] = ()
    threshold: float | None = None
    source: str = ""

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ConfigError(f"kind must be one of {KINDS}, got {self.kind!r}")
        if self.check not in CHECKS[self.kind]:
            raise ConfigError(
                f"check of a {self.kind!r} record must be one of {CHECKS[self.kind]}, "
                f"got {self.check!r}"
            )
        if self.kind in ("change", "pair", "ratio", "convex") and self.factor is None:
            raise ConfigError(f"a {self.kind!r} record needs the factor it varies")
        if self.kind == "r" and (self.other is None or not self.by):
            raise ConfigError("an 'r' record needs other (the second column) and by")
        if self.check == "at least" and self.threshold is None:
            raise ConfigError("an 'at least' check needs a threshold")


@dataclass(frozen=True)
class ReportLayout:
    """The paper's figure types for a model's sweeps (``abm report`` draws them).

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
        curve_spread: "sd" (standard deviation over runs, as the papers' error bars) or "se".
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

    The recurrence (Arnaldo et al. 2018) moves robots from a moving state w to a settled state
    b: ``w_t = w_{t-1} - a_t w_{t-1} + alpha5``, ``b_t = b_{t-1} + a_t w_{t-1}``,
    ``a_t = alpha6 a_{t-1}``; ``alpha5`` robots arrive per step.

    Attributes:
        moving: the state counted as w.
        settled: the state counted as b.
        step: the recurrence's step (s).
        arrival_period: summary column holding the time between two arrivals (s), so that
            alpha5 = step / period; None: alpha5 is estimated from the growth of w + b.
        supply: summary column holding how many robots there are in all (w + b never exceeds
            it: arrivals stop, our extension for swarms of fixed size); None: no limit, as in
            the paper.
        regression: covariate -> summary column for the paper's lambda regressions
            (``alpha6 = l0 + l1 r + l2 r^2``, ``a0 = l3 - l4 entropy + l5 envsize``): keys
            "radius", "entropy", "envsize"; None: no regression.
        published: condition (the values of ``condition_keys``, in order) -> the paper's
            numbers for it (e.g. w, b, w_hat, b_hat, t, rmsd_w, rmsd_b).
        condition_keys: the parameters a published condition names.
        published_summary: the paper's overall figures, name -> (mean, std), e.g. mean RMSDs.
        lambdas: the paper's fitted l0..l5, if any.
        source: the paper.

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
    lambdas: Mapping[str, float] | None = None
    source: str = ""


@dataclass(frozen=True)
class Verdict:
    """What a sweep's runs say about one claim.

    Attributes:
        ours: our measured value(s), as text.
        holds: True / False; None when these runs cannot decide (``why`` says why).
        why: the reason, or the rule applied.

    """

    ours: str
    holds: bool | None
    why: str = ""


@dataclass(frozen=True)
class Claim:
    """A checkable claim of a paper and the test a sweep's runs put it to.

    Attributes:
        id: the claim's label (e.g. "C01").
        source: where the paper makes it (section, figure).
        statement: the claim, in the paper's words or close to them.
        kind: "Q" (the paper gives a number) or "QL" (a direction, ordering or shape).
        setup: the runs that test it, in words.
        test: ``f(runs, samples) -> Verdict | None`` on the tidy run rows (one per run) and
            the model's time series (``samples``, may be None); None when these runs lack the
            set-up. A claim no simulation can test has no test and says why in ``untestable``.
        untestable: why a claim without a test cannot be tested (or where else it is tested).

    """

    id: str
    source: str
    statement: str
    kind: str
    setup: str
    test: Callable[[pd.DataFrame, pd.DataFrame | None], Verdict | None] | None = None
    untestable: str = ""

    def __post_init__(self) -> None:
        if self.kind not in ("Q", "QL"):
            raise ConfigError(f"kind must be 'Q' or 'QL', got {self.kind!r}")
        if self.test is None and not self.untestable:
            raise ConfigError(f"claim {self.id}: without a test, say why in untestable")
