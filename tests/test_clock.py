"""call_later schedules like a SimPy timeout: same instants, same order among ties, also when
events schedule further events and the run stops and resumes at chosen times; a Clock runs
like SimPy's environment and knows the event it scheduled last.
"""

import pytest
import simpy
from hypothesis import given, settings
from hypothesis import strategies as st

from abm.clock import Clock, call_later

#: Few distinct delays, so many events share an instant and their order is the eid order.
DELAYS = st.sampled_from([0.0, 0.1, 0.2, 0.30000000000000004, 1.0])
#: An event: its delay, and the delays of the events it schedules when it runs.
PLAN = st.lists(st.tuples(DELAYS, st.lists(DELAYS, max_size=3)), min_size=1, max_size=25)


def fired(
    plan, use_call_later: list[bool], stops: list[float], env: simpy.Environment
) -> list[tuple[float, str]]:
    """Run the plan; the k-th scheduling uses call_later if ``use_call_later[k % len]``."""
    log: list[tuple[float, str]] = []
    count = iter(range(10**6))

    def schedule(delay: float, name: str, children: list[float]) -> None:
        def run(_event) -> None:
            log.append((env.now, name))
            for i, child in enumerate(children):
                schedule(child, f"{name}.{i}", [])

        if use_call_later[next(count) % len(use_call_later)]:
            event = call_later(env, delay, run)
        else:
            event = env.timeout(delay)
            event.callbacks.append(run)
        if isinstance(env, Clock):
            assert env.last_scheduled is event

    for i, (delay, children) in enumerate(plan):
        schedule(delay, str(i), children)
    for stop in stops:
        if stop > env.now:
            env.run(until=stop)
    env.run()
    return log


@settings(max_examples=100, deadline=None)
@given(
    PLAN,
    st.lists(st.booleans(), min_size=1, max_size=7),
    st.lists(st.sampled_from([0.1, 0.2, 0.5, 1.0]), max_size=3),
)
def test_call_later_fires_in_the_order_timeouts_would(plan, mix, stops):
    timeouts = fired(plan, [False], sorted(stops), simpy.Environment())
    assert fired(plan, mix, sorted(stops), simpy.Environment()) == timeouts
    assert fired(plan, mix, sorted(stops), Clock()) == timeouts


def test_the_event_carries_its_value_and_a_negative_delay_is_refused():
    env = simpy.Environment()
    got = []
    call_later(env, 0.5, lambda event: got.append((env.now, event.value)), value="v")
    env.run()
    assert got == [(0.5, "v")]
    with pytest.raises(ValueError, match="negative delay"):
        call_later(env, -0.1, print)
