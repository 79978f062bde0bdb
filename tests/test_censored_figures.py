"""A metric the end of some runs censors is not drawn as a mean of lower bounds: the report's
metric panel shows its Kaplan-Meier median per condition, with an open triangle at the bound
where fewer than half the runs reached the target; the stacked bars say how many runs the
time limit cut."""

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from abm.published import Censored, ReportLayout  # noqa: E402
from analysis.figures import metric_panels, stacked_bars  # noqa: E402

LAYOUT = ReportLayout(x="period", metrics=("coverage_time", "energy"), stacked=("a", "b"))
CUT = (Censored("coverage_time"),)


def _runs() -> pd.DataFrame:
    rows = []
    for period, times in ((6, [100, 110, 120, 130]), (24, [90, 120, 120, 120])):
        for t in times:
            cut = t == 120 and period == 24
            rows.append({"period": period, "coverage_time": t, "energy": t * 2.0, "a": 1.0,
                         "b": 2.0, "status": "ok",
                         "end_reason": "time limit" if cut else "complete"})  # fmt: skip
    return pd.DataFrame(rows)


def test_a_censored_metric_is_drawn_as_kaplan_meier_medians_not_means():
    fig = metric_panels(_runs(), LAYOUT, CUT)
    censored, plain = fig.axes
    assert "Kaplan-Meier" in censored.get_title() and "Kaplan-Meier" in fig._suptitle.get_text()
    (line,) = censored.get_lines()  # one line of medians, no error bars
    assert list(line.get_xdata()) == [6]  # period 24: 3 of 4 runs cut, median not reached
    assert line.get_ydata()[0] == 110  # the Kaplan-Meier median of 100, 110, 120, 130
    (bound,) = censored.collections  # the open triangle at the bound
    assert np.allclose(bound.get_offsets(), [[24, 120]])
    assert plain.get_title() == "" and len(plain.get_lines()) > 1  # mean with its error bars


def test_without_censored_runs_every_metric_is_a_mean_with_its_standard_error():
    runs = _runs().assign(end_reason="complete")
    fig = metric_panels(runs, LAYOUT, CUT)
    assert all("Kaplan-Meier" not in ax.get_title() for ax in fig.axes)
    assert "Kaplan-Meier" not in fig._suptitle.get_text()


def test_stacked_bars_count_the_runs_the_time_limit_cut():
    fig = stacked_bars(_runs(), LAYOUT)
    notes = [t.get_text() for t in fig.axes[0].texts]
    assert notes == ["3/4 cut"]
