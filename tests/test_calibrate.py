"""``abm calibrate``: a known (conjugate) posterior recovered, bad input refused before any run,
the folder resumed or refused.
"""

import json

import numpy as np
import pandas as pd
import pytest

from analysis.cli import main as abm

NORMAL = "normal_model:NormalModel"
#: One observation y0 of y ~ N(mu, sigma = 1): with a flat prior on mu, mu | y0 ~ N(y0, 1).
Y0, SIGMA = 3.0, 1.0


def _target(tmp_path, text: str = f"metric,value,sd\ny,{Y0},{SIGMA}\n"):
    path = tmp_path / "target.csv"
    path.write_text(text)
    return path


def _calibrate(tmp_path, *extra: str, target=None, out=None, free="mu=-20:20") -> int:
    target = target or _target(tmp_path)
    out = out or tmp_path / "out"
    fixed = ["--set", f"sigma={SIGMA}", "--out", str(out), "--workers", "1"]
    return abm(["calibrate", NORMAL, "--target", str(target), "--free", free, *fixed, *extra])


def _posterior_sd(out) -> float:
    import pyabc

    history = pyabc.History(f"sqlite:///{out / 'abc.db'}")
    frame, w = history.get_distribution()
    mean = np.sum(w * frame["mu"]) / np.sum(w)
    return float(np.sqrt(np.sum(w * (frame["mu"] - mean) ** 2) / np.sum(w)))


def test_conjugate_posterior_quick(tmp_path):
    """Small budget (~2 s, the library alone): 6 populations of 60 particles put the
    posterior of mu around y0 (mean within 0.6 sigma) with a spread near sigma (within 35 %):
    a calibration that ignored the data would keep the prior's sd, 40 / sqrt(12) = 11.5.
    """
    import pyabc

    from abm.registry import model_class
    from analysis.calibrate import Calibration, posterior_table, run_abc
    from analysis.calibration_inputs import parse_prior, read_target

    cls = model_class(NORMAL)
    fixed = {"sigma": SIGMA}
    prior = parse_prior(cls, "mu=-20:20", fixed)
    target = read_target(cls, _target(tmp_path), fixed, ["mu"])
    calib = Calibration(cls, target, (prior,), fixed, seed=1)
    history = run_abc(calib, tmp_path, populations=6, population_size=60, epsilon=0.1,
                      workers=1, address=None, resume=False)  # fmt: skip
    post = posterior_table(history, (prior,)).set_index("parameter").loc["mu"]
    assert abs(post["mean"] - Y0) < 0.6 * SIGMA
    assert isinstance(history, pyabc.History)
    assert abs(_posterior_sd(tmp_path) - SIGMA) < 0.35 * SIGMA


@pytest.mark.slow
def test_conjugate_posterior_through_the_cli(tmp_path, capsys):
    """The whole command (~6 s): mean +-0.4, sd within 35 %, y0 inside the 90 % interval,
    and every output written.
    """
    out = tmp_path / "out"
    code = _calibrate(tmp_path, "--population-size", "80", "--populations", "4",
                      "--epsilon", "0.1", "--check-runs", "4")  # fmt: skip
    printed = capsys.readouterr()
    assert code == 0, printed.err
    # the run says whether its last epsilon reached the target, not only what it was
    import pyabc

    pops = pyabc.History(f"sqlite:///{out / 'abc.db'}").get_all_populations()
    reached = pops.loc[pops["t"] >= 0, "epsilon"].iloc[-1] <= 0.1
    said = "the target 0.1 reached" if reached else "NOT the target 0.1"
    assert said in printed.out
    post = pd.read_csv(out / "posterior.csv").set_index("parameter").loc["mu"]
    assert abs(post["mean"] - Y0) < 0.4
    assert abs(_posterior_sd(out) - SIGMA) < 0.35 * SIGMA
    assert post["q05"] < Y0 < post["q95"]
    pred = pd.read_csv(out / "predictive.csv")
    assert list(pred["metric"]) == ["y"] and pred["runs"].iloc[0] == 4
    assert (out / "posterior.png").stat().st_size > 0
    assert (out / "heldout.csv").is_file()


@pytest.mark.slow
def _quantile_error(out, q: float = 0.05) -> float:
    """Four standard errors of a sample q-quantile of the final population, from its
    effective size ``(sum w)^2 / sum w^2``: sqrt(q (1 - q) / ESS) / pdf(z_q), in sigma units.
    """
    import pyabc
    from scipy import stats as sps

    _, w = pyabc.History(f"sqlite:///{out / 'abc.db'}").get_distribution()
    ess = float(np.sum(w) ** 2 / np.sum(w**2))
    return 4 * SIGMA * np.sqrt(q * (1 - q) / ess) / sps.norm.pdf(sps.norm.ppf(q))


def test_conjugate_posterior_tight(tmp_path, capsys):
    """Larger budget: mean within 0.15 sigma of y0, sd within 15 % of sigma, and each end of
    the 90 % interval within four standard errors of the sample quantile of the conjugate one
    (y0 -+ 1.645 sigma; a fixed 0.3 was about three standard errors and failed once at 0.304).
    """
    out = tmp_path / "out"
    code = _calibrate(tmp_path, "--population-size", "500", "--populations", "8",
                      "--epsilon", "0.05", "--check-runs", "4")  # fmt: skip
    assert code == 0, capsys.readouterr().err
    post = pd.read_csv(out / "posterior.csv").set_index("parameter").loc["mu"]
    assert abs(post["mean"] - Y0) < 0.15 * SIGMA
    assert abs(_posterior_sd(out) - SIGMA) < 0.15 * SIGMA
    error = _quantile_error(out)
    assert abs(post["q05"] - (Y0 - 1.645 * SIGMA)) < error
    assert abs(post["q95"] - (Y0 + 1.645 * SIGMA)) < error


def test_resume_continues_the_same_calibration(tmp_path, capsys):
    out = tmp_path / "out"
    small = ("--population-size", "20", "--epsilon", "0", "--check-runs", "2")
    assert _calibrate(tmp_path, "--populations", "1", *small) == 0
    assert _calibrate(tmp_path, "--populations", "2", *small) == 0
    assert "resuming" in capsys.readouterr().err
    import pyabc

    assert pyabc.History(f"sqlite:///{out / 'abc.db'}").n_populations == 2


def _refused(capsys, code: int, *words: str) -> str:
    err = capsys.readouterr().err
    assert code == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("abm calibrate: error:"), err
    for word in words:
        assert word in lines[0], lines[0]
    return lines[0]


@pytest.mark.parametrize(
    ("text", "words"),
    [
        ("metric,value,sd\nspeed,3.0,1.0\n", ("'speed'", "accepted", "y")),
        ("metric,value\ny,3.0\n", ("'sd'", "metric, value, sd")),
        ("metric,value,sd\ny,3.0,0\n", ("row 2", "sd must be a spread > 0")),
        ("metric,value,sd\ny,3.0,\n", ("row 2", "sd must be a spread > 0", "nothing")),
        ("metric,value,sd,sigma\ny,3.0,1.0,-1\n", ("row 2", "'sigma'")),
    ],
    ids=["unknown metric", "no sd column", "zero sd", "missing sd", "bad condition"],
)
def test_bad_target_refused_before_any_run(tmp_path, capsys, text, words):
    out = tmp_path / "out"
    code = abm(["calibrate", NORMAL, "--target", str(_target(tmp_path, text)),
                "--free", "mu=-20:20", "--out", str(out)])  # fmt: skip
    _refused(capsys, code, *words)
    assert not out.exists()


@pytest.mark.parametrize(
    ("free", "words"),
    [
        ("mu=-200:20", ("mu", "-200")),  # Params accept -100 <= mu <= 100
        ("speed=0:1", ("'speed'", "not a parameter", "mu, sigma")),
        ("mu=log:-1:2", ("log-uniform", "LOW > 0")),
        ("mu=5:1", ("LOW < HIGH",)),
        ("mu=1", ("NAME=LOW:HIGH",)),
    ],
    ids=["outside Params", "unknown parameter", "log below 0", "reversed", "no range"],
)
def test_bad_prior_refused_before_any_run(tmp_path, capsys, free, words):
    out = tmp_path / "out"
    _refused(capsys, _calibrate(tmp_path, free=free, out=out), *words)
    assert not out.exists()


def test_folder_of_another_calibration_refused(tmp_path, capsys):
    out = tmp_path / "out"
    small = ("--population-size", "10", "--populations", "1", "--check-runs", "2")
    assert _calibrate(tmp_path, *small) == 0
    capsys.readouterr()
    before = (out / "abc.db").stat().st_mtime_ns
    _refused(capsys, _calibrate(tmp_path, *small, free="mu=-10:10"), "another calibration",
             "priors")  # fmt: skip
    assert (out / "abc.db").stat().st_mtime_ns == before
    assert json.loads((out / "calibration.json").read_text())["priors"][0]["low"] == -20


def test_folder_with_other_files_refused(tmp_path, capsys):
    out = tmp_path / "out"
    out.mkdir()
    (out / "notes.txt").write_text("mine")
    _refused(capsys, _calibrate(tmp_path), "not a calibration folder", "notes.txt")
    assert sorted(p.name for p in out.iterdir()) == ["notes.txt"]


def test_published_target_uses_levels_with_a_spread_and_says_what_it_skips(tmp_path, capsys):
    out = tmp_path / "out"
    code = abm(["calibrate", NORMAL, "--target", "published", "--free", "mu=-20:20",
                "--out", str(out), "--workers", "1", "--population-size", "10",
                "--populations", "1", "--check-runs", "2"])  # fmt: skip
    err = capsys.readouterr().err
    assert code == 0, err
    assert "1 numbers" in err
    assert "skipped toy: y (T2): no published spread" in err
    assert "skipped toy: y (T3): its condition fixes a free parameter" in err
    rows = json.loads((out / "calibration.json").read_text())["target"]
    assert rows == [{"metric": "y", "value": 3.0, "sd": 1.0, "sigma": 1.0}]


def test_published_target_without_usable_records_refused(tmp_path, capsys):
    code = abm(["calibrate", "beacon-explorer", "--target", "published",
                "--free", "launch_period=2:20", "--out", str(tmp_path / "out")])  # fmt: skip
    _refused(capsys, code, "no published level with a spread", "not a level")
    assert not (tmp_path / "out").exists()


def test_each_evaluation_seed_is_stored_and_replays_its_statistics(tmp_path, capsys):
    """The seed stored with a particle is the one drawn for its values, and running the model
    on it again gives the stored statistic; with one worker a calibration repeats exactly.
    """
    import pyabc

    from abm.registry import model_class
    from analysis.calibrate import Calibration, evaluation_seed
    from analysis.calibration_inputs import parse_prior, read_target

    small = ("--population-size", "10", "--populations", "2", "--check-runs", "2")
    for name in ("a", "b"):
        assert _calibrate(tmp_path, *small, out=tmp_path / name) == 0
    a, b = (pd.read_csv(tmp_path / n / "posterior.csv") for n in ("a", "b"))
    pd.testing.assert_frame_equal(a, b)

    history = pyabc.History(f"sqlite:///{tmp_path / 'a' / 'abc.db'}")
    particles = history.get_population_extended(t=history.max_t)
    cls = model_class(NORMAL)
    fixed = {"sigma": SIGMA}
    calib = Calibration(cls, read_target(cls, _target(tmp_path), fixed, ["mu"]),
                        (parse_prior(cls, "mu=-20:20", fixed),), fixed, seed=0)  # fmt: skip
    assert len(particles) == 10
    for _, row in particles.iterrows():
        assert int(row["sumstat__seed"]) == evaluation_seed(0, [row["par_mu"]])
        assert (
            calib.evaluate({"mu": row["par_mu"]}, int(row["sumstat__seed"]))["r0"]
            == (row["sumstat_r0"])
        )


def test_holdout_condition_is_checked_at_the_posterior_median(tmp_path, capsys):
    """Target rows at sigma = 1 (a condition column), held-out rows at sigma = 3: the
    held-out check runs the posterior median there, on fresh seeds.
    """
    target = _target(tmp_path, f"metric,value,sd,sigma\ny,{Y0},1.0,1.0\n")
    holdout = tmp_path / "holdout.csv"
    holdout.write_text(f"metric,value,sd,sigma\ny,{Y0},3.0,3.0\n")
    out = tmp_path / "out"
    code = abm(["calibrate", NORMAL, "--target", str(target), "--free", "mu=-20:20",
                "--holdout", str(holdout), "--out", str(out), "--workers", "1",
                "--population-size", "20", "--populations", "2", "--check-runs", "6"])  # fmt: skip
    assert code == 0, capsys.readouterr().err
    held = pd.read_csv(out / "heldout.csv")
    assert list(held["check"]) == ["held-out condition"]
    assert list(held["sigma"]) == [3.0] and held["runs"].iloc[0] == 6
    median = pd.read_csv(out / "posterior.csv")["median"].iloc[0]
    # six draws of N(median, 3): their mean within 4 standard errors of the median
    assert abs(held["predicted_mean"].iloc[0] - median) < 4 * 3.0 / np.sqrt(6)
    assert held["q95"].iloc[0] - held["q05"].iloc[0] > 2.0  # the sigma = 3 spread, not 1


@pytest.mark.slow
def test_conjugate_posterior_on_a_dask_cluster(tmp_path, tiny_package):
    """``--address``: the same ABC-SMC on a Dask cluster's workers (a LocalCluster of worker
    processes here; the tests' folder reaches them through PYTHONPATH, as a cluster's workers
    need the model's package installed) recovers the known posterior as the local run does.
    """
    from dask.distributed import LocalCluster

    from abm.registry import model_class
    from analysis.calibrate import Calibration, posterior_table, run_abc
    from analysis.calibration_inputs import parse_prior, read_target

    cls = model_class(NORMAL)
    fixed = {"sigma": SIGMA}
    prior = parse_prior(cls, "mu=-20:20", fixed)
    target = read_target(cls, _target(tmp_path), fixed, ["mu"])
    calib = Calibration(cls, target, (prior,), fixed, seed=2)
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster:  # fmt: skip
        history = run_abc(calib, tmp_path, populations=5, population_size=60, epsilon=0.1,
                          workers=1, address=cluster.scheduler_address, resume=False)  # fmt: skip
    post = posterior_table(history, (prior,)).set_index("parameter").loc["mu"]
    assert abs(post["mean"] - Y0) < 0.6 * SIGMA
    assert abs(_posterior_sd(tmp_path) - SIGMA) < 0.5 * SIGMA
    assert history.n_populations == 5


def test_replicates_average_runs_on_their_own_seeds(tmp_path):
    """A particle's statistic is the mean of ``replicates`` runs; replicate 0 runs on the seed a
    single run had, so calibrations without replicates repeat as before."""
    from abm.registry import model_class
    from analysis.calibrate import Calibration, _run_seed
    from analysis.calibration_inputs import parse_prior, read_target
    from analysis.runner import run_model

    cls = model_class(NORMAL)
    fixed = {"sigma": SIGMA}
    prior = parse_prior(cls, "mu=-20:20", fixed)
    target = read_target(cls, _target(tmp_path), fixed, ["mu"])
    single = Calibration(cls, target, (prior,), fixed, seed=4)
    triple = Calibration(cls, target, (prior,), fixed, seed=4, replicates=3)
    runs = [run_model(cls, {"sigma": SIGMA, "mu": 2.0}, _run_seed(77, 0, r)).summary["y"]
            for r in range(3)]  # fmt: skip
    assert single.evaluate({"mu": 2.0}, 77)["r0"] == runs[0]
    assert np.isclose(triple.evaluate({"mu": 2.0}, 77)["r0"], np.mean(runs))
    assert len(set(runs)) == 3  # three runs, three seeds
    # a mean of 16 runs is four times less spread than one run
    many = Calibration(cls, target, (prior,), fixed, seed=4, replicates=16)
    means = [many.evaluate({"mu": 0.0}, s)["r0"] for s in range(60)]
    assert 0.15 < np.std(means) < 0.4


def test_replicates_below_one_refused_before_any_run(tmp_path, capsys):
    out = tmp_path / "out"
    assert _calibrate(tmp_path, "--replicates", "0", out=out) == 2
    err = capsys.readouterr().err.strip()
    assert err.endswith("--replicates must be at least 1, got 0") and len(err.splitlines()) == 1
    assert not out.exists()
