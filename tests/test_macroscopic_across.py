"""Rate equations across parameters: the hazards' parameter effects are recovered on a model
whose rates are known, a held-out grid point is predicted, and bad grids are refused before
any run."""

import itertools

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from rates_model import RatesModel

from abm.errors import ConfigError
from analysis.cli import main
from analysis.macroscopic import check_heldout, collect_runs
from analysis.macroscopic.across import fit_across
from analysis.rate_across import held_out_points

MODEL = RatesModel
#: Two-sided z of a 99.9 % interval: a true value outside it is a failure, not bad luck.
Z = 3.29


def _runs(rate_ab: float, first_seed: int, n: int, **params) -> list:
    return collect_runs(
        MODEL, list(range(first_seed, first_seed + n)), {"rate_ab": rate_ab, **params}
    )


def _coefficient(model, source: str, target: str, name: str) -> tuple[float, float]:
    table = model.table()
    row = table[(table.source == source) & (table.target == target) & (table.coefficient == name)]
    return float(row.estimate.iloc[0]), float(row.se.iloc[0])


@settings(max_examples=3, deadline=None, derandomize=True)
@given(st.integers(0, 10_000), st.floats(0.03, 0.06))
def test_a_rate_proportional_to_a_parameter_is_a_power_law_of_exponent_one(first, held_rate):
    """lambda_AB = rate_ab exactly, so log lambda_AB = 1 * log(rate_ab): the fitted exponent's
    interval holds 1; lambda_BC does not depend on rate_ab: its effect's interval holds 0; and
    the held-out point's A -> B rate comes out near the truth."""
    fitted = [(r, _runs(r, first + 100 * k, 6)) for k, r in enumerate((0.02, 0.035, 0.09))]
    model = fit_across([({"rate_ab": r}, logs) for r, logs in fitted], ["rate_ab"])
    log, _mean, sd = model.numeric["rate_ab"]
    assert log  # all positive: the rate is fitted as a power law of rate_ab
    effect, se = _coefficient(model, "A", "B", "effect_of_rate_ab")
    assert abs(effect / sd - 1.0) <= Z * se / sd
    effect, se = _coefficient(model, "B", "C", "effect_of_rate_ab")
    assert abs(effect) <= Z * se
    held = _runs(held_rate, first + 900, 4)
    predicted = model.at({"rate_ab": held_rate}, held)
    ab = next(h for h in predicted.hazards if (h.source, h.target) == ("A", "B"))
    if ab.family == "constant":
        assert np.exp(ab.params[0]) == pytest.approx(held_rate, rel=0.2)
    checks = check_heldout(predicted, held, np.random.default_rng(first))
    assert checks.rmsd_max < 0.1  # the rates of a condition never fitted, predicted


def test_a_parameter_that_does_not_vary_or_a_single_condition_is_refused():
    logs = _runs(0.05, 1, 2)
    with pytest.raises(ConfigError, match="at least 2 fitted conditions"):
        fit_across([({"rate_ab": 0.05}, logs)], ["rate_ab"])
    with pytest.raises(ConfigError, match="none of the swept parameters \\(contact\\) varies"):
        fit_across([({"contact": 0.002}, logs[:1]), ({"contact": 0.002}, logs[1:])], ["contact"])


def test_an_unseen_level_or_a_value_outside_the_logs_domain_cannot_be_predicted():
    runs = [
        ({"rate_ab": r, "mixing": m}, _runs(r, 10 + 10 * k, 3, mixing=m))
        for k, (r, m) in enumerate([(0.02, "global"), (0.05, "local"), (0.08, "global")])
    ]
    model = fit_across([(dict(c), logs) for c, logs in runs], ["rate_ab", "mixing"])
    assert model.levels == {"mixing": ("global", "local")}
    with pytest.raises(ConfigError, match="cannot predict at a value <= 0"):
        model.effect_values({"rate_ab": 0.0, "mixing": "global"})
    model = fit_across([(dict(c), logs) for c, logs in runs[::2]], ["rate_ab", "mixing"])
    assert "mixing" not in model.levels  # one level only among the fitted: no effect
    runs[1][0]["mixing"] = "elsewhere"
    model = fit_across([(dict(c), logs) for c, logs in runs], ["rate_ab", "mixing"])
    with pytest.raises(ConfigError, match="'nowhere' was not among the fitted conditions"):
        model.effect_values({"rate_ab": 0.05, "mixing": "nowhere"})


@settings(max_examples=40, deadline=None)
@given(
    st.lists(st.integers(3, 6), min_size=1, max_size=3),
    st.integers(1, 4),
)
def test_held_out_points_are_distinct_interior_points(sizes, count):
    grid = {f"p{i}": [float(v) for v in range(n)] for i, n in enumerate(sizes)}
    points = [dict(zip(grid, p, strict=True)) for p in itertools.product(*grid.values())]
    interior = int(np.prod([n - 2 for n in sizes]))
    if count > interior:
        with pytest.raises(ConfigError, match="interior point"):
            held_out_points(points, count)
        return
    chosen = held_out_points(points, count)
    assert len(set(chosen)) == count
    for k in chosen:
        assert all(0 < points[k][f"p{i}"] < n - 1 for i, n in enumerate(sizes))


def test_grids_that_cannot_hold_a_point_out_are_refused():
    grid = {"radius": [20.0, 40.0], "map": ["a", "b", "c"]}
    points = [dict(zip(grid, p, strict=True)) for p in itertools.product(*grid.values())]
    with pytest.raises(ConfigError, match="0 interior point"):
        held_out_points(points, 1)
    with pytest.raises(ConfigError, match="at least 1"):
        held_out_points([{"radius": r} for r in (20.0, 30.0, 40.0)], 0)


def test_abm_fit_rates_across_a_grid_writes_its_report(tiny_package, tmp_path, capsys):
    out = tmp_path / "across"
    code = main(
        ["fit", "tiny", "--rates", "--grid", "rest_rate=0.03,0.05,0.08", "--runs", "3",
         "--held", "2", "--workers", "1", "--set", "walkers=8", "--set", "time_limit=120",
         "--out", str(out)]
    )  # fmt: skip
    assert code == 0
    printed = capsys.readouterr().out
    assert "HELD OUT rest_rate=0.05" in printed and "effect_of_rest_rate" in printed
    for name in ("rates_across.csv", "conditions.csv", "curves.png", "rates_across.html"):
        assert (out / name).stat().st_size > 0
    html = (out / "rates_across.html").read_text()
    assert "Held-out grid points" in html and "walking" in html


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--grid", "rest_rate=0.03,0.05", "--held-points", "1"], "0 interior point"),
        (["--grid", "rest_rate=0.03,0.05,0.08", "--held-points", "2"], "1 interior point"),
        (["--grid", "rest_rate=0.03,0.05,0.08", "--set", "rest_rate=0.1"], "both swept"),
        (["--grid", "rest_rate=0.03,-1,0.08"], "rest_rate"),
    ],
)
def test_abm_fit_across_refuses_a_bad_grid_in_one_line(
    tiny_package, tmp_path, capsys, args, message
):
    out = tmp_path / "nothing"
    fit = ["fit", "tiny", "--rates", "--runs", "2", "--workers", "1", "--out", str(out)]
    code = main([*fit, *args])
    err = capsys.readouterr().err.strip()
    assert code != 0 and message in err and len(err.splitlines()) == 1
    assert not out.exists()


def _sweep(tmp_path, capsys, grid: str, time_series: bool = True):
    """A sweep of the tiny model made with ``abm sweep``: its folder."""
    tmp_path.mkdir(exist_ok=True)
    spec = tmp_path / "tiny.toml"
    spec.write_text(
        f'model = "tiny"\nseed = 5\nreplications = 5\ntime_series = {str(time_series).lower()}\n'
        f"[grid]\nwalkers = [8]\ntime_limit = [120.0]\n{grid}\n"
    )
    out = tmp_path / "sweep"
    assert main(["sweep", str(spec), "--executor", "serial", "--out", str(out)]) == 0
    capsys.readouterr()
    return out


def test_abm_fit_rates_reads_a_sweeps_runs_across_its_grid(tiny_package, tmp_path, capsys):
    folder = _sweep(tmp_path, capsys, "rest_rate = [0.03, 0.05, 0.08]")
    out = tmp_path / "fit"
    code = main(["fit", "tiny", "--rates", "--read", str(folder), "--runs", "3", "--out", str(out)])
    assert code == 0
    printed = capsys.readouterr().out
    assert "HELD OUT rest_rate=0.05" in printed and "(runs read, not run)" in printed
    conditions = pd.read_csv(out / "conditions.csv")
    fitted = conditions[conditions.role.str.startswith("fitted")]
    assert set(fitted.rest_rate) == {0.03, 0.08} and len(set(conditions.checked_seeds)) == 3


def test_abm_fit_rates_reads_one_condition_and_refuses_what_it_cannot_fit(
    tiny_package, tmp_path, capsys
):
    folder = _sweep(tmp_path, capsys, "rest_rate = [0.05]")
    out = tmp_path / "fit"
    assert main(["fit", "tiny", "--rates", "--read", str(folder), "--runs", "3",
                 "--out", str(out)]) == 0  # fmt: skip
    assert "held-out seeds" in capsys.readouterr().out and (out / "rates.csv").exists()
    code = main(["fit", "tiny", "--rates", "--read", str(folder), "--runs", "5"])
    assert code != 0 and "5 runs: --runs 5 leaves none" in capsys.readouterr().err
    plain = _sweep(tmp_path / "plain", capsys, "rest_rate = [0.05]", time_series=False)
    code = main(["fit", "tiny", "--rates", "--read", str(plain), "--runs", "3"])
    assert code != 0 and "kept no state changes" in capsys.readouterr().err


def test_the_recurrence_fit_of_a_sweep_without_state_changes_says_rates_are_left_out(
    tiny_package, tmp_path, capsys
):
    folder = _sweep(tmp_path, capsys, "rest_rate = [0.05]")
    for path in (folder / "changes").iterdir():  # as a sweep made before they were kept
        path.unlink()
    (folder / "changes").rmdir()
    assert main(["fit", "tiny", "--read", str(folder), "--out", str(tmp_path / "fit")]) == 0
    printed = capsys.readouterr().out
    assert "rate equations left out" in printed and "kept no state changes" in printed
    assert "rmsd_walking_rates" not in printed and (tmp_path / "fit" / "fit_report.html").exists()


def test_conditions_run_on_the_same_seeds_are_fitted_as_separate_runs():
    """Sweeps with common random numbers give every condition the same seeds (the runs' labels):
    each run is still its own table in the held-out choice of families, so the scores do not
    depend on the labels (they used to triple, one table per seed holding every condition)."""
    import dataclasses

    runs = [({"rate_ab": r}, _runs(r, 1, 4)) for r in (0.02, 0.04, 0.08)]
    relabelled = [
        (c, [dataclasses.replace(log, run=f"{k}-{log.run}") for log in logs])
        for k, (c, logs) in enumerate(runs)
    ]
    shared = fit_across(runs, ["rate_ab"]).table()
    apart = fit_across(relabelled, ["rate_ab"]).table()
    pd.testing.assert_frame_equal(shared, apart)
