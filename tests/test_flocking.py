"""The flocking model: the declared rules step for step, sequential activation, invariants."""

import math
import os
import subprocess
import sys

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from mesa.experimental.continuous_space import ContinuousSpaceAgent

from abm.arena import Arena
from abm.errors import ConfigError
from abm.model import SwarmModel
from models.flocking import LARGE, Bird, FlockingModel, FlockingParams
from models.flocking.kernel import squared_limit

DECLARED = {"speed": 1.0, "separation": 1.0, "cohere": 0.03, "separate": 0.015, "match": 0.05}


def _reference(rng, birds, extent, visual, steps, sequential=True, move=DECLARED["speed"]):
    """The declaration in plain Python: yields (positions, velocities) at the start and after
    every step.

    Draws from ``rng`` in the model's order: positions, headings, then one activation order
    per step; a bird moves ``move`` (m) per step. ``sequential=False`` is the variant the
    declaration rules out: every bird reads the flock as it was at the start of the step.
    """
    pos = [list(p) for p in rng.random((birds, 2)) * extent]
    vel = [list(h / np.linalg.norm(h)) for h in rng.uniform(-1.0, 1.0, (birds, 2))]
    yield np.array(pos), np.array(vel)
    for _ in range(steps):
        order = rng.permutation(birds)
        seen_pos = pos if sequential else [list(p) for p in pos]
        seen_vel = vel if sequential else [list(v) for v in vel]
        for i in order:
            n, cohere, separate, match = 0, [0.0, 0.0], [0.0, 0.0], [0.0, 0.0]
            for j in range(birds):
                if j == i:
                    continue
                offset = [seen_pos[j][a] - seen_pos[i][a] for a in (0, 1)]
                offset = [d - extent * round(d / extent) for d in offset]  # nearest image
                distance = math.hypot(*offset)
                if distance <= visual:
                    n += 1
                    for a in (0, 1):
                        cohere[a] += offset[a]
                        match[a] += seen_vel[j][a]
                        if distance < DECLARED["separation"]:
                            separate[a] -= offset[a]
            n = max(n, 1)
            new = [
                (
                    seen_vel[i][a]
                    + cohere[a] / n * DECLARED["cohere"]
                    + separate[a] / n * DECLARED["separate"]
                    + match[a] / n * DECLARED["match"]
                )
                / 2
                for a in (0, 1)
            ]
            norm = math.hypot(*new)
            vel[i] = [v / norm for v in new]
            pos[i] = [(pos[i][a] + vel[i][a] * move) % extent for a in (0, 1)]
        yield np.array(pos), np.array(vel)


def _torus_gap(a, b, extent):
    d = np.abs(a - b)
    return np.minimum(d, extent - d).max()


def _follow(model, reference, extent, tolerance):
    """Step ``model`` beside the reference's states, checking positions and velocities."""
    for step, (pos, vel) in enumerate(reference):
        if step:
            model.step()
        assert model.time == step * model.params.dt and model.updates == step
        assert _torus_gap(model.space.agent_positions, pos, extent) < tolerance, step
        assert np.abs(model.velocity - vel).max() < tolerance, step


@pytest.mark.parametrize(
    ("birds", "extent", "visual"),
    [(40, 20.0, 5.0), (25, 9.0, 4.0)],  # a cell list of 4 x 4 cells; one cell holding all
)
def test_a_seeded_run_equals_the_declared_rules_step_for_step(birds, extent, visual):
    model = FlockingModel(
        seed=11, birds=birds, extent=extent, visual_distance=visual, trace_interval=None
    )
    _follow(model, _reference(np.random.default_rng(11), birds, extent, visual, 40), extent, 1e-9)
    assert model.summary()["mean_neighbours"] > 1  # the birds did see each other


@settings(max_examples=40, deadline=None)
@given(
    birds=st.integers(1, 40),
    extent=st.floats(5.0, 80.0),
    visual_share=st.floats(0.01, 0.5),
    move_share=st.floats(0.0, 0.6),
    seed=st.integers(0, 2**31),
)
def test_any_cell_list_gives_the_declared_rules(birds, extent, visual_share, move_share, seed):
    """Whatever the cell list (one cell or many, cells just wide enough or much wider, moves
    long or short against the visual distance, birds crossing cells within a step), every
    bird sees exactly the neighbours the declaration gives it: the run equals the plain-Python
    rules for a few steps."""
    visual, move = visual_share * extent, move_share * extent
    model = FlockingModel(
        seed=seed,
        birds=birds,
        extent=extent,
        visual_distance=visual,
        speed=move,
        steps=4,
        trace_interval=None,
    )
    reference = _reference(np.random.default_rng(seed), birds, extent, visual, 4, move=move)
    # a neighbour gained or lost would move a bird by far more than rounding does
    _follow(model, reference, extent, 1e-7)


def test_the_sums_are_the_same_bit_for_bit_on_a_plain_processor(tmp_path):
    """The kernel's sums are taken in the order the code writes them (no fast-math: the
    compiler may not reorder or fuse them for this processor's SIMD width or FMA units), so the
    large case compiled for a generic CPU (no AVX, no FMA; a fresh numba cache) ends where it
    ends here, bit for bit, positions and velocities, after 100 chaotic steps."""
    code = (
        "import sys; from models.flocking import LARGE, FlockingModel; "
        "m = FlockingModel(seed=3, trace_interval=None, **LARGE).run(); "
        "sys.stdout.write(m.space.agent_positions.tobytes().hex() + m.velocity.tobytes().hex())"
    )
    env = {**os.environ, "NUMBA_CPU_NAME": "generic", "NUMBA_CACHE_DIR": str(tmp_path)}
    plain = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True
    ).stdout
    here = FlockingModel(seed=3, trace_interval=None, **LARGE).run()
    assert plain == here.space.agent_positions.tobytes().hex() + here.velocity.tobytes().hex()


@settings(max_examples=200, deadline=None)
@given(limit=st.floats(0.0, 1e6), strict=st.booleans(), ulps=st.integers(-4, 4))
def test_the_squared_limit_decides_as_the_distance_does(limit, strict, ulps):
    """The kernel's neighbour test on squared distances is the declared test on distances,
    decision for decision, also for squared distances a few ulps either side of the limit."""
    bound = squared_limit(limit, strict)
    squared = limit * limit
    for _ in range(abs(ulps)):
        squared = math.nextafter(squared, math.copysign(math.inf, ulps))
    squared = max(squared, 0.0)
    inside = math.sqrt(squared) < limit if strict else math.sqrt(squared) <= limit
    assert inside == (squared <= bound)


def test_the_squared_limit_of_the_small_case_is_not_its_square():
    """sqrt(25 + 1 ulp) rounds to 5: such a bird is a neighbour at visual distance 5."""
    assert squared_limit(5.0) == math.nextafter(25.0, math.inf)
    assert math.sqrt(squared_limit(5.0)) <= 5.0 < math.sqrt(math.nextafter(squared_limit(5.0), 30))
    assert squared_limit(1.0, strict=True) < 1.0 and squared_limit(0.0, strict=True) == -1.0


def test_the_update_is_sequential_not_simultaneous():
    """A bird activated later sees the moves made before it: the simultaneous update is a
    different model, and the comparison above would catch it."""
    args = (40, 20.0, 5.0)
    sequential = list(_reference(np.random.default_rng(3), *args, steps=1))[-1]
    simultaneous = list(_reference(np.random.default_rng(3), *args, steps=1, sequential=False))[-1]
    model = FlockingModel(seed=3, birds=40, extent=20.0, visual_distance=5.0)
    model.step()
    assert np.abs(model.velocity - sequential[1]).max() < 1e-12
    assert np.abs(model.velocity - simultaneous[1]).max() > 1e-3


def test_birds_are_mesa_agents_on_a_periodic_space_moved_by_the_update():
    model = FlockingModel(seed=5, birds=30, extent=30.0, trace_interval=None)
    assert model.space.torus
    assert len(model.agents) == 30
    birds = model.agents_by_type[Bird]
    assert len(birds) == 30 and all(isinstance(b, ContinuousSpaceAgent) for b in birds)
    before = np.array([bird.position for bird in birds])
    model.run()
    after = np.array([bird.position for bird in birds])
    assert np.array_equal(after, model.space.agent_positions)
    assert not np.array_equal(before, after)
    seventh = next(b for b in birds if b.row == 7)
    assert np.array_equal(seventh.velocity, model.velocity[7])
    assert model.time == 100.0 and model.updates == 100
    assert model.summary()["end_reason"] == "100 steps"


@settings(max_examples=25, deadline=None)
@given(
    birds=st.integers(1, 30),
    extent=st.floats(8.0, 60.0),
    visual_share=st.floats(0.02, 0.5),
    speed=st.floats(0.0, 1.5),
    dt=st.sampled_from([0.5, 1.0, 2.0]),
    seed=st.integers(0, 2**31),
)
def test_speed_is_constant_and_birds_stay_on_the_torus(
    birds, extent, visual_share, speed, dt, seed
):
    model = FlockingModel(
        seed=seed,
        birds=birds,
        extent=extent,
        visual_distance=visual_share * extent,
        speed=speed,
        dt=dt,
        steps=6,
        trace_interval=None,
    )
    for _ in range(6):
        before = model.space.agent_positions.copy()
        model.run(until=model.time + dt)
        after = model.space.agent_positions
        assert ((after >= 0) & (after < extent)).all()
        step = np.abs(after - before)
        step = np.minimum(step, extent - step)
        assert np.allclose(np.hypot(*step.T), speed * dt, atol=1e-9)
        assert np.allclose(np.linalg.norm(model.velocity, axis=1), 1.0)


def test_same_seed_same_history_and_another_seed_another():
    def run(seed):
        model = FlockingModel(seed=seed, birds=60, extent=40.0, trace_interval=5.0)
        model.run()
        return model

    a, b, c = run(4), run(4), run(5)
    assert np.array_equal(a.space.agent_positions, b.space.agent_positions)
    pd.testing.assert_frame_equal(a.positions(), b.positions())
    pd.testing.assert_frame_equal(a.samples(), b.samples())
    assert not np.array_equal(a.space.agent_positions, c.space.agent_positions)


def test_the_flock_gathers_and_aligns_on_fresh_seeds():
    """Flocking emerges (the comparison's purpose): after 100 steps of the large case birds
    have far more neighbours than scattered birds would and head the same way far more than
    random headings do."""
    p = FlockingParams(**LARGE)
    scattered = (p.birds - 1) * math.pi * p.visual_distance**2 / p.extent**2
    finals = [FlockingModel(seed=seed, trace_interval=None, **LARGE).run() for seed in (21, 22, 23)]
    neighbours = np.mean([m.summary()["mean_neighbours"] for m in finals])
    polarisation = np.mean([m.summary()["polarisation"] for m in finals])
    assert neighbours > 2 * scattered
    assert polarisation > 3 / math.sqrt(p.birds)  # random unit headings: about 1 / sqrt(N)
    curve = finals[0].samples()
    assert list(curve["time"]) == [float(t) for t in range(1, 101)]


@pytest.mark.parametrize(
    ("params", "match"),
    [
        ({"visual_distance": 60.0}, "visual_distance must be at most extent / 2 = 50"),
        ({"birds": 0}, "birds"),
        ({"speed": -1.0}, "speed"),
        ({"extent": 0.0}, "extent"),
        ({"steps": 2.5}, "steps"),
        ({"separation": -0.5}, "separation"),
    ],
)
def test_bad_input_is_named(params, match):
    with pytest.raises(ConfigError, match=match):
        FlockingModel(**params)


def test_a_periodic_space_is_refused_with_the_flight_physics():
    params = FlockingParams()
    arena = Arena(np.ones((4, 4), dtype=bool))
    with pytest.raises(ConfigError, match="torus=True needs physics=False"):
        SwarmModel(params, arena, torus=True)
