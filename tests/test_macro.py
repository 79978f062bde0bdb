import numpy as np
import pandas as pd
import pytest

from abm.errors import ConfigError
from analysis.macro import (
    a0_from_lambdas,
    alpha6_from_lambdas,
    fit_lambdas,
    fit_recurrence,
    mean_counts,
    predict_from_lambdas,
    recurrence,
    refine_lambdas,
    rmsd,
)
from models.stigmergy.published import LAMBDAS, TABLE1, TABLE1_COLUMNS


def test_recurrence_conserves_robots():
    r = recurrence(0.1, 0.999, 0.01, steps=2000)
    assert r.loc[0, "wander"] == 0 and r.loc[0, "beacon"] == 1
    assert np.allclose(r["wander"] + r["beacon"], 1 + 0.01 * r["step"])
    assert r["time"].iloc[-1] == 1000.0


def test_paper_lambdas_reproduce_table1_map1_large_radii():
    # With l1, l2 < 0 (signs restored) the published lambdas give Table 1's predictions.
    for radius in (30, 40):
        row = dict(zip(TABLE1_COLUMNS, TABLE1[(1, radius)], strict=True))
        end = predict_from_lambdas(LAMBDAS, radius, 0.2405, 1e4, int(row["t"] / 0.5))
        assert end["wander"].iloc[-1] == pytest.approx(row["w_hat"], abs=0.5)
        assert end["beacon"].iloc[-1] == pytest.approx(row["b_hat"], abs=0.5)


def _synthetic(a0, alpha6, seeds=3, steps=3000, noise=0.3):
    rng = np.random.default_rng(0)
    base = recurrence(a0, alpha6, 0.01, steps)
    frames = []
    for s in range(seeds):
        frames.append(
            pd.DataFrame(
                {
                    "time": base["time"],
                    "wander": base["wander"] + rng.normal(0, noise, len(base)),
                    "beacon": base["beacon"] + rng.normal(0, noise, len(base)),
                    "seed": s,
                }
            )
        )
    return pd.concat(frames, ignore_index=True)


def test_fit_recovers_parameters():
    fit = fit_recurrence(_synthetic(0.05, 0.998), alpha5=0.01)
    assert fit.params["a0"] == pytest.approx(0.05, rel=0.1)
    assert fit.params["alpha6"] == pytest.approx(0.998, abs=2e-4)
    assert fit.stderr["a0"] > 0
    assert fit.rmsd_w < 0.3 and fit.rmsd_b < 0.3
    assert list(fit.predicted.columns) == ["time", "wander", "beacon"]


def test_fit_generic_columns_and_alpha5_estimate():
    counts = _synthetic(0.05, 0.998, noise=0.0).rename(
        columns={"wander": "explorer", "beacon": "beacon"}
    )
    fit = fit_recurrence(counts, wander="explorer", beacon="beacon")
    assert fit.params["alpha5"] == pytest.approx(0.01, rel=1e-6)


def test_mean_counts_steps_and_runs_ending():
    counts = pd.DataFrame(
        {
            "time": [0, 1.0, 3.0, 0, 2.0],
            "wander": [0, 1, 2, 0, 5],
            "beacon": [1, 1, 1, 1, 1],
            "seed": [1, 1, 1, 2, 2],
        }
    )
    m = mean_counts(counts, step=1.0, min_share=0.5)
    assert m["time"].tolist() == [0, 1, 2, 3]
    assert m["wander"].tolist() == [0, 0.5, 3.0, 2.0]
    assert m["runs"].tolist() == [2, 2, 2, 1]


def test_fit_lambdas_recovers_known():
    lam = dict(l0=1.0, l1=-3e-5, l2=-2e-6, l3=0.09, l4=0.02, l5=5e-6)
    rows = []
    for ent, size in ((0.24, 1e4), (0.19, 2e4), (0.28, 1e4), (0.46, 1e4)):
        for r in (10, 20, 30, 40):
            rows.append(
                {
                    "radius": r,
                    "entropy": ent,
                    "envsize": size,
                    "alpha6": lam["l0"] + lam["l1"] * r + lam["l2"] * r * r,
                    "a0": lam["l3"] - lam["l4"] * ent + lam["l5"] * size,
                }
            )
    got, se = fit_lambdas(pd.DataFrame(rows))
    for k, v in lam.items():
        assert got[k] == pytest.approx(v, rel=1e-4, abs=1e-12)


def test_fit_lambdas_of_one_map_fixes_what_it_cannot_identify_and_gives_no_false_errors():
    # one map: entropy and size the same in every row, so l4 and l5 cannot be told from l3;
    # three radii: the quadratic in C_rb interpolates them, with no residual to give errors
    rows = [{"radius": r, "entropy": 0.2405, "envsize": 1e4, "a0": 0.016 + 0.001 * k,
             "alpha6": 1.0 - 1e-4 * r - 1e-6 * r * r}
            for k, r in enumerate((20.0, 30.0, 40.0))]  # fmt: skip
    got, se = fit_lambdas(pd.DataFrame(rows))
    assert got["l4"] == 0.0 and got["l5"] == 0.0 and np.isnan(se["l4"]) and np.isnan(se["l5"])
    assert got["l3"] == pytest.approx(0.017)  # the mean a0: all the map term can say
    assert all(np.isnan(se[k]) for k in ("l0", "l1", "l2"))
    assert se["l3"] > 0  # three a0 values, one term: a real standard error


def test_refine_lambdas_fits_the_curves_it_is_judged_on():
    true = dict(l0=1.0, l1=-3e-5, l2=-2e-6, l3=0.05, l4=0.02, l5=1e-6)
    curves = []
    for ent, size in ((0.24, 1e4), (0.19, 2e4), (0.46, 1e4)):
        for r in (20, 30, 40):
            obs = predict_from_lambdas(true, r, ent, size, 1500)
            curves.append((obs[["time", "wander", "beacon"]], r, ent, size))
    # a start a regression could give: alpha6 off by 1e-4, tiny in parameter space
    start = dict(true, l0=1.0001, l3=0.06)

    def mean_rmsd(lam):
        out = []
        for obs, r, ent, size in curves:
            pred = predict_from_lambdas(lam, r, ent, size, 1500)
            out.append(rmsd(pred["wander"], obs["wander"]) + rmsd(pred["beacon"], obs["beacon"]))
        return np.mean(out)

    got, se = refine_lambdas(start, curves)
    assert mean_rmsd(got) < 0.01 < mean_rmsd(start)
    assert got["l0"] == pytest.approx(1.0, abs=2e-6)
    assert set(se) == set(true)
    with pytest.raises(ConfigError, match="curves"):
        refine_lambdas(start, [])


def test_bad_input():
    with pytest.raises(ConfigError, match="'beacon'"):
        fit_recurrence(pd.DataFrame({"time": [0, 1], "wander": [0, 1]}))
    with pytest.raises(ConfigError, match="3 distinct radii"):
        fit_lambdas(
            pd.DataFrame(
                {
                    "radius": [10, 20],
                    "alpha6": [1, 1],
                    "a0": [0.1, 0.1],
                    "entropy": [0.2, 0.2],
                    "envsize": [1e4, 1e4],
                }
            )
        )
    assert rmsd([1, 2], [1, 4]) == pytest.approx(np.sqrt(2))


def test_refine_lambdas_minimises_the_mean_rmsd():
    """The fit is judged on the mean RMSD of w and b over curves (the paper's Table 2); a
    sum of squared errors lets the long curves decide it and leaves that mean higher."""
    rng = np.random.default_rng(3)
    true = dict(l0=1.0, l1=-3e-5, l2=-2e-6, l3=0.05, l4=0.02, l5=1e-6)
    curves = []
    for ent, size in ((0.24, 1e4), (0.19, 2e4), (0.46, 1e4)):
        for r, steps in ((10, 3000), (30, 1000)):
            # curves the lambda model cannot fit exactly: a0, alpha6 off by up to 2x
            a0 = a0_from_lambdas(true, ent, size) * rng.uniform(0.5, 2.0)
            alpha6 = 1 - (1 - alpha6_from_lambdas(true, r)) * rng.uniform(0.7, 1.4)
            obs = recurrence(a0, alpha6, 0.01, steps).iloc[::20]
            curves.append((obs[["time", "wander", "beacon"]], r, ent, size))

    def mean_rmsd(lam):
        out = []
        for obs, r, ent, size in curves:
            pred = predict_from_lambdas(lam, r, ent, size, int(obs["step"].iloc[-1]))
            idx = obs["step"].to_numpy()
            out.append(rmsd(pred["wander"].to_numpy()[idx], obs["wander"]))
            out.append(rmsd(pred["beacon"].to_numpy()[idx], obs["beacon"]))
        return np.mean(out)

    curves = [(c.assign(step=np.round(c["time"] / 0.5).astype(int)), *rest) for c, *rest in curves]
    by_rmsd, _ = refine_lambdas(true, curves)
    by_mse, _ = refine_lambdas(true, curves, objective="mse")
    assert mean_rmsd(by_rmsd) < 0.97 * mean_rmsd(by_mse)
    with pytest.raises(ConfigError, match="objective"):
        refine_lambdas(true, curves, objective="mae")


def test_papers_method_recovers_known_a0_alpha6_from_noisy_curves():
    """The paper's method end to end (analysis.fit.analyse): curves of the recurrence with
    known lambdas plus noise, 3 runs per condition over 3 maps x 3 radii; the per-curve fits
    recover each condition's a0 and alpha6, the regressions recover the lambdas' a0 and alpha6,
    and both methods stand side by side with the paper's figures."""
    from abm.published import MacroSpec
    from analysis.fit import analyse, methods

    true = dict(l0=1.0, l1=-4e-5, l2=-1.5e-6, l3=0.06, l4=0.05, l5=2e-6)
    maps = {"a": (0.24, 1e4), "b": (0.05, 2e4), "c": (0.45, 1e4)}
    rng = np.random.default_rng(15)
    summaries, counts = [], []
    for name, (entropy, size) in maps.items():
        for radius in (10.0, 25.0, 40.0):
            a0 = a0_from_lambdas(true, entropy, size)
            alpha6 = alpha6_from_lambdas(true, radius)
            base = recurrence(a0, alpha6, 0.01, 2400).iloc[::4]
            for rep in range(3):
                run_id = f"{name}-{radius:g}-{rep}"
                summaries.append({"run_id": run_id, "map": name, "pheromone_radius": radius,
                                  "entropy": entropy, "envsize": size, "launch_period": 50.0,
                                  "time": 1200.0})  # fmt: skip
                counts.append(
                    pd.DataFrame(
                        {
                            "run_id": run_id,
                            "time": base["time"].to_numpy(),
                            "wander": base["wander"].to_numpy() + rng.normal(0, 0.3, len(base)),
                            "beacon": base["beacon"].to_numpy() + rng.normal(0, 0.3, len(base)),
                            "map": name,
                            "pheromone_radius": radius,
                        }
                    )
                )
    spec = MacroSpec(
        "wander", "beacon", step=0.5, arrival_period="launch_period",
        regression={"radius": "pheromone_radius", "entropy": "entropy", "envsize": "envsize"},
        published={("a", 10.0): {"rmsd_w": 2.0, "rmsd_b": 1.0}},
        condition_keys=("map", "pheromone_radius"),
        published_summary={"rmsd_w": (1.5, 0.5), "rmsd_b": (1.4, 0.4)},
        published_label="Table 1", summary_label="Table 2",
    )  # fmt: skip
    result = analyse(
        pd.DataFrame(summaries), pd.concat(counts), spec, ["map", "pheromone_radius"],
        heldout=False,
    )  # fmt: skip
    table = result["table"]
    for row in table.to_dict("records"):
        entropy, size = maps[row["map"]]
        a0 = a0_from_lambdas(true, entropy, size)
        alpha6 = alpha6_from_lambdas(true, row["pheromone_radius"])
        assert row["a0"] == pytest.approx(a0, rel=0.15), row  # per curve
        assert row["alpha6"] == pytest.approx(alpha6, abs=3e-4), row
        assert row["a0_reg"] == pytest.approx(a0, rel=0.15), row  # the paper's regressions
        assert row["alpha6_reg"] == pytest.approx(alpha6, abs=3e-4), row
        assert row["rmsd_w_reg"] < 0.6 and row["rmsd_b_reg"] < 0.6
    side = methods(table, spec).set_index("method")
    assert side.index[0].startswith("the paper's method")
    assert side.index[1].startswith("joint refinement")
    assert side.loc["paper (Table 1), the same conditions", "rmsd_w"] == 2.0
    assert side.loc["paper (Table 1), the same conditions", "conditions"] == 1
    assert side.loc["paper (Table 2)", "rmsd_b"] == 1.4
    # the joint refinement starts at the regressions and minimises what they are judged on
    assert side["rmsd_w"].iloc[1] + side["rmsd_b"].iloc[1] <= (
        side["rmsd_w"].iloc[0] + side["rmsd_b"].iloc[0] + 1e-6
    )


# ---------------------------------------------------------------------- the fit report
def _fit_runs_of_three_radii():
    """Runs of three radii (6, 12, 24: their text sorts 12, 24, 6) with 60 summary columns."""
    from abm.published import MacroSpec
    from analysis.fit import analyse

    spec = MacroSpec(moving="wander", settled="beacon", step=1.0, source="synthetic")
    counts, rows = [], []
    for radius, a0 in ((6, 0.05), (12, 0.04), (24, 0.03)):
        part = _synthetic(a0, 0.998, seeds=2, steps=300)
        for seed, run in part.groupby("seed"):
            run_id = f"r{radius}-{seed}"
            counts.append(run.drop(columns="seed").assign(run_id=run_id, radius=radius))
            rows.append({"run_id": run_id, "rep": seed, "radius": radius, "time": 300.0,
                         "end_reason": "time limit", "status": "ok",
                         **{f"metric_{k}": float(k) for k in range(60)}})  # fmt: skip
    summaries, counts = pd.DataFrame(rows), pd.concat(counts, ignore_index=True)
    return analyse(summaries, counts, spec, ["radius"]), summaries, spec


def test_fit_report_says_what_it_shows(tmp_path):
    from analysis.fit import write_fit_report

    result, summaries, spec = _fit_runs_of_three_radii()
    meta = [("wall time", "1 s with 1 worker")]
    page = write_fit_report(result, summaries, spec, tmp_path, meta, ["radius"]).read_text()
    # the panels in the radii's order, not their text's
    titles = [t.split(" (")[0] for t in page.split('alt="')[1:]]
    assert [t for t in titles if t.startswith("radius=")] == ["radius=6", "radius=12", "radius=24"]
    # no regression here (the spec names none): one way of fitting, and the page says one
    methods = page.split("Fitting methods side by side")[1].split("<h2>")[0]
    assert methods.count("<tr>") == 2  # the heading and one method
    assert "got one way (one row each)" in methods and "five ways" not in page
    # the runs table fits the page: the run, its condition, its end; the rest in runs.csv
    runs = page.split("<h2>Runs</h2>")[1]
    heads = runs.split("</thead>")[0].count("<th class")
    assert heads == 6
    assert len(pd.read_csv(tmp_path / "runs.csv").columns) == len(summaries.columns)


def test_fit_wall_time_counts_its_workers():
    from analysis.cli.fit import _wall_time

    assert _wall_time(11.2, 1) == "11 s with 1 worker"
    assert _wall_time(11.2, 2) == "11 s with 2 workers"
    assert _wall_time(3.0, None) == "3 s (runs read, not run)"
