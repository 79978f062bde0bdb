"""SugarMapModel as a whole: the paper's invariants on whole runs, determinism, bad input, and
the two claims that are properties of the models rather than of the figures (C20, C25).

The modules have their own tests (test_sugarmap_{arenas,planner,baselines,particles}.py); the
published effects are claims checked on the figure sweeps (models/sugarmap/claims.py).
"""

import numpy as np
import pandas as pd
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from abm.errors import ConfigError
from abm.kinematics import bump_moves
from models.sugarmap import SugarMapModel
from models.sugarmap.arenas import load_arena
from models.sugarmap.rtof import RToF

#: The testbed set-up of Fig. 15: the smallest one with every part of the model.
TESTBED = {"arena": "testbed", "n_anchors": 5, "n_explorers": 2}


def _stepper(model: SugarMapModel):
    """Advance the model one simulated second at a time, yielding after each."""
    while model.running:
        model.step()
        yield model


def test_coverage_grows_and_the_summary_reports_it_at_the_checkpoints():
    model = SugarMapModel(seed=11, horizon=250, **TESTBED).run()
    s = model.summary()
    assert s["end_reason"] == "horizon" and s["t_deploy"] is not None
    tau = model.samples()["tau"]
    assert tau.iloc[0] == 0 and tau.iloc[-1] == pytest.approx(250)
    assert np.all(np.diff(model.samples()["coverage"]) >= 0)  # true coverage never falls
    assert 0 < s["coverage_90"] <= s["coverage_180"] <= s["coverage_250"] == s["coverage_area"]
    assert s["overlap"] >= 1


@given(seed=st.integers(0, 10_000), particles=st.integers(1, 12))
@settings(max_examples=8, deadline=None, suppress_health_check=[HealthCheck.too_slow])
def test_weights_normalised_and_maps_are_probabilities_every_tick(seed, particles):
    model = SugarMapModel(seed=seed, horizon=40, n_particles=particles, **TESTBED)
    for m in _stepper(model):
        if m.filter is None:
            continue
        np.testing.assert_allclose(m.filter.weights.sum(axis=1), 1.0, atol=1e-9)
        assert (m.filter.weights >= 0).all()
        for belief in (m.filter.node_maps(), m.global_map):
            assert np.isfinite(belief).all() and belief.min() >= 0 and belief.max() <= 1
        # eq. 10: the GlobalMap is at least every explorer's NodeMap
        assert (m.global_map >= m.filter.node_maps().max(axis=0) - 1e-12).all()


@pytest.mark.parametrize("arena", ["testbed", "ushape"])
def test_without_noise_the_particles_ride_on_the_true_pose_and_the_estimate_is_the_truth(arena):
    # a speed whose multiples never land on a cell edge (at 0.35 m/s, 15 ticks from a cell
    # centre end exactly on one, where rounding may put the particle and the truth apart)
    quiet = {"noise_scale": 0.0, "rtof_noise": 0.0, "init_cutoff": 60.0, "speed": 0.3512}
    setup = {**TESTBED, "arena": arena} if arena == "testbed" else {"arena": arena}
    model = SugarMapModel(seed=5, horizon=150, **setup, **quiet)
    for m in _stepper(model):
        if m.filter is None:
            continue
        offset = m.filter.pos - m.pos[:, None, :]
        assert np.abs(offset).max() < 1e-9
    samples = model.samples()
    assert samples["coverage"].iloc[-1] > 5  # the run did cover something
    np.testing.assert_allclose(samples["coverage_est"], samples["coverage"], atol=1e-9)
    assert (samples["map_error"] == 0).all()


@given(
    seed=st.integers(0, 10_000),
    arena=st.sampled_from(["ushape", "serpentine", "testbed"]),
    algorithm=st.sampled_from(["sugarmap", "random_walk", "omstc"]),
    noise=st.sampled_from([1.0, 3.0]),
)
@settings(max_examples=10, deadline=None, suppress_health_check=[HealthCheck.too_slow])
def test_explorers_never_enter_or_cross_a_wall(seed, arena, algorithm, noise):
    extra = {"n_anchors": 4, "init_cutoff": 60.0} if algorithm == "sugarmap" else {}
    model = SugarMapModel(
        seed=seed, arena=arena, algorithm=algorithm, noise_scale=noise, horizon=120, **extra
    )
    before = None
    for m in _stepper(model):
        if not hasattr(m, "pos"):
            continue
        assert m.arena.is_free(m.pos).all()
        if before is not None:
            assert not m.arena.segment_crosses_wall(before, m.pos).any()
        before = m.pos.copy()
    assert before is not None, "the coverage phase never started"


def test_the_robots_are_conserved_and_counted_in_one_state_each():
    model = SugarMapModel(seed=2, horizon=100, **TESTBED).run()
    counts = model.state_counts()
    total = counts[list(SugarMapModel.STATES)].sum(axis=1)
    assert (total == TESTBED["n_anchors"] + TESTBED["n_explorers"]).all()


@pytest.mark.parametrize("algorithm", ["sugarmap", "random_walk", "omstc"])
def test_same_seed_same_event_log_and_samples_and_another_seed_differs(algorithm):
    extra = {"n_anchors": 5} if algorithm == "sugarmap" else {}
    setup = {"arena": "testbed", "n_explorers": 2, "algorithm": algorithm, **extra}
    a = SugarMapModel(seed=21, horizon=120, trace_interval=1.0, **setup).run()
    b = SugarMapModel(seed=21, horizon=120, trace_interval=1.0, **setup).run()
    c = SugarMapModel(seed=22, horizon=120, trace_interval=1.0, **setup).run()
    pd.testing.assert_frame_equal(a.events(), b.events())
    pd.testing.assert_frame_equal(a.samples(), b.samples())
    pd.testing.assert_frame_equal(a.positions(), b.positions())
    assert not a.positions().equals(c.positions())


def test_an_explorer_that_hears_no_anchor_stops():
    # a radio range shorter than any anchor's distance: the explorers stop at once (README
    # "Choices": stop rule)
    model = SugarMapModel(seed=4, horizon=30, radio_range=0.05, **TESTBED).run()
    assert model.summary()["stopped"] == TESTBED["n_explorers"]
    assert (model.events()["event"] == "stopped").sum() == TESTBED["n_explorers"]


def test_a_run_cut_short_by_time_limit_reports_no_coverage_for_later_checkpoints():
    model = SugarMapModel(seed=3, time_limit=100, horizon=500, init_cutoff=30, **TESTBED).run()
    s = model.summary()
    assert s["end_reason"] == "time limit" and s["time"] == 100
    reached = 100 - s["t_deploy"]  # tau at the end
    for checkpoint in (90, 180, 250, 400, 500):
        assert np.isnan(s[f"coverage_{checkpoint}"]) == (checkpoint > reached)


def test_the_nodes_enter_at_the_given_entrance():
    model = SugarMapModel(seed=1, arena="ushape", entrance=(10.2, 10.3), horizon=5)
    cells = np.floor(model.starts / model.cell).astype(int)
    assert tuple(cells[0]) == (20, 20)
    assert (np.abs(cells - cells[0]).sum(axis=1) <= 2).all()  # its nearest free cells
    assert model.arena.is_free(model.starts).all()


def test_a_users_bitmap_is_an_arena(tmp_path):
    from PIL import Image

    image = np.full((12, 16), 255, dtype=np.uint8)  # top row north; dark = wall
    image[0, :] = image[-1, :] = image[:, 0] = image[:, -1] = 0
    image[3:9, 7] = 0  # a wall in the middle
    path = tmp_path / "room.png"
    Image.fromarray(image).save(path)
    model = SugarMapModel(seed=1, arena=str(path), n_anchors=3, n_explorers=2, horizon=60)
    model.run()
    assert model.arena.free.sum() == (10 * 14 - 6)
    assert model.summary()["coverage_area"] > 0


# ---------------------------------------------------------------- bad input
@pytest.mark.parametrize(
    ("kwargs", "named"),
    [
        ({"n_anchors": 0}, "n_anchors"),
        ({"n_particles": 0}, "n_particles"),
        ({"sig_th": -0.5}, "sig_th"),
        ({"sig_th": 0.0}, "sig_th"),
        ({"cover_th": 1.5}, "cover_th"),
        ({"cover_th": 0.0}, "cover_th"),
        ({"n_explorers": 0}, "n_explorers"),
        ({"speed": 0.9}, "speed"),
        ({"arena": "atlantis"}, "arena"),
        ({"arena": "nowhere.png"}, "nowhere.png"),
        ({"entrance": (0.1, 0.1)}, "entrance"),
        ({"entrance": (99.0, 5.0)}, "entrance"),
        ({"algorithm": "random_walk", "n_anchors": 6}, "n_anchors"),
        ({"algorithm": "omstc", "random_walk": "bounce"}, "random_walk"),
        ({"algorithm": "teleport"}, "algorithm"),
        ({"arena": "testbed", "n_explorers": 61}, "n must be at most"),
    ],
)
def test_bad_input_raises_a_config_error_naming_the_parameter(kwargs, named):
    with pytest.raises(ConfigError, match=named):
        SugarMapModel(seed=1, **kwargs)


# ---------------------------------------------------------------- model claims C20, C25
def test_single_rtof_varies_more_than_the_signature():
    """C20: at a fixed point, each single anchor's RToF has a larger normalised
    variance (var / mean^2) than the signature's norm |s| / N_a, 10 anchors as Fig. 14."""
    rng = np.random.default_rng(14)
    anchors = rng.uniform(0.5, 19.5, (10, 2))
    rtof = RToF(anchors, noise=1.0, bias=0.5, extent=(20.0, 20.0), rng=rng)
    point = np.array([[7.3, 11.9]])
    draws = np.vstack([rtof.measure(point, np.ones((1, 10), bool), rng) for _ in range(2000)])
    single = draws.var(axis=0) / draws.mean(axis=0) ** 2
    norm = np.linalg.norm(draws, axis=1) / 10
    combined = norm.var() / norm.mean() ** 2
    assert (single > combined).all()
    assert np.median(single) > 3 * combined


@given(speed=st.floats(0.25, 0.45), ticks=st.integers(1, 30), heading=st.sampled_from([0, 90]))
def test_a_node_enters_the_next_cell_in_one_tick(speed, ticks, heading):
    """C25: noise off, from a cell centre a node enters the adjacent cell in exactly
    one tick at every speed in [0.25, 0.45] m/s, and k straight ticks enter
    floor((0.25 + k v) / 0.5) new cells."""
    edges = (0.25 + ticks * speed) / 0.5
    assume(abs(edges - round(edges)) > 1e-6)  # ending on a cell edge is a rounding question
    arena = load_arena("open")
    start = np.array([[2.25, 2.25]])  # the centre of cell (4, 4); open floor ahead
    cells, pos = [], start
    for _ in range(ticks):
        pos, blocked = bump_moves(arena, pos, np.array([heading]), np.array([speed]))
        assert not blocked.any()
        cells.append(tuple(np.floor(pos[0] / 0.5).astype(int)))
    assert cells[0] != (4, 4)
    assert len(set(cells) - {(4, 4)}) == int((0.25 + ticks * speed) // 0.5)


def test_the_calibrated_threshold_grows_with_the_rtof_noise():
    """C26's procedure on real deployments: SIG_TH rises with sigma_eps, and the reference
    set-up gives about the value the params use."""
    from models.sugarmap.calibrate import calibrate
    from models.sugarmap.params import CALIBRATED_SIG_TH

    at = {noise: calibrate(3, first_seed=900, rtof_noise=noise).mean() for noise in (0, 1, 2)}
    assert at[0] < at[1] < at[2]
    assert at[1] == pytest.approx(CALIBRATED_SIG_TH, abs=0.06)


def test_the_calibration_refuses_no_deployments_and_gives_no_sd_for_one(capsys):
    from models.sugarmap.calibrate import main

    with pytest.raises(SystemExit) as stop:
        main(["--replications", "0"])
    assert stop.value.code == 2
    assert "--replications must be 1 or more deployments, got 0" in capsys.readouterr().err
    assert main(["--replications", "1", "--first-seed", "900"]) == 0
    out = capsys.readouterr().out
    assert "no SD over 1 deployment;" in out and "nan" not in out
