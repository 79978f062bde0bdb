"""A SwarmModel keeps Mesa's step/time contract with SimPy as its clock: ``model.step()``
advances one step and counts it in ``steps``; ``model.time`` is the simulated time a
discrete-event simulator controls (``env.now``), which Mesa's own ``run_for`` and
``run_until`` move forward and nothing moves back.
"""

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from abm import registry

LIMIT = 40.0


def _model():
    cls = registry.model_class("stigmergy")  # its Mesa step is 0.5 s, not Mesa's 1
    return cls(seed=1, time_limit=LIMIT)


def test_mesas_run_for_and_run_until_advance_the_simulation():
    model = _model()
    model.step()
    model.step()
    assert (model.steps, model.time) == (2, 2 * model.step_duration)
    model.run_for(3.0)
    assert model.time == model.env.now == pytest.approx(1.0 + 3.0)
    assert model.steps == 2  # run_for advances time, it runs no steps
    model.run_until(10.0)
    assert model.time == model.env.now == 10.0
    model.run_until(LIMIT + 100.0)  # past the end: the run stops at its end
    assert model.time == LIMIT and not model.running
    assert model.end_reason == "time limit"


def test_time_never_goes_back():
    model = _model()
    model.run_for(5.0)
    model.time = 5.0  # Mesa may set the time it already has
    with pytest.raises(ValueError, match="cannot go back: it is 5 s, asked for 1 s"):
        model.time = 1.0
    assert model.time == 5.0


@settings(max_examples=15, deadline=None)
@given(st.lists(st.one_of(st.none(), st.floats(0.1, 6.0)), min_size=1, max_size=12))
def test_steps_and_time_as_mesa_documents(calls):
    """Whatever mix of step() (None) and run_for(d) drives it, model.time is env.now, never
    decreases, ends at the time limit at the latest, and steps counts the step() calls that
    found the model running.
    """
    model = _model()
    steps = 0
    last = model.time
    for call in calls:
        if call is None:
            steps += model.running
            model.step()
        elif model.running:
            model.run_for(call)
        assert model.time == model.env.now >= last
        assert model.time <= LIMIT and model.steps == steps
        last = model.time
