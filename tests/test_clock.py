"""call_later (and the scheduler bound to an environment) runs a call where a SimPy timeout
would: same instants, same order among ties, also when calls schedule further calls and
timeouts, start processes (urgent events) and the run stops and resumes at chosen times; on a
Clock, which gathers calls due together into one event, the run is the same event for event.
"""

import pytest
import simpy
from hypothesis import given, settings
from hypothesis import strategies as st

from abm.clock import Clock, call_later, scheduler

#: Few distinct delays, so many events share an instant and their order is the eid order.
DELAYS = st.sampled_from([0.0, 0.1, 0.2, 0.30000000000000004, 1.0])
#: An event: its delay, whether it starts a process when it runs, and the delays of the events
#: it schedules then.
PLAN = st.lists(
    st.tuples(DELAYS, st.booleans(), st.lists(DELAYS, max_size=3)), min_size=1, max_size=25
)


def fired(
    plan, ways: list[int], stops: list[float], env: simpy.Environment
) -> list[tuple[float, str]]:
    """Run the plan; the k-th scheduling uses a timeout, call_later or the bound scheduler
    (``ways[k % len]`` 0, 1 or 2).
    """
    log: list[tuple[float, str]] = []
    count = iter(range(10**6))

    def process(name: str):
        log.append((env.now, f"{name} starts"))
        yield env.timeout(0.1)
        log.append((env.now, f"{name} ends"))

    def schedule(delay: float, name: str, starts: bool, children: list[float]) -> None:
        def run(_value) -> None:
            log.append((env.now, name))
            if starts:
                env.process(process(name))
            for i, child in enumerate(children):
                schedule(child, f"{name}.{i}", False, [])

        way = ways[next(count) % len(ways)]
        if way == 1:
            call_later(env, delay, run)
        elif way == 2:
            scheduler(env)(delay, run, None)
        else:
            env.timeout(delay).callbacks.append(run)

    for i, (delay, starts, children) in enumerate(plan):
        schedule(delay, str(i), starts, children)
    for stop in stops:
        if stop > env.now:
            env.run(until=stop)
    env.run()
    return log


@settings(max_examples=150, deadline=None)
@given(
    PLAN,
    st.lists(st.integers(0, 2), min_size=1, max_size=7),
    st.lists(st.sampled_from([0.1, 0.2, 0.5, 1.0]), max_size=3),
)
def test_call_later_runs_where_a_timeout_would(plan, mix, stops):
    timeouts = fired(plan, [0], sorted(stops), simpy.Environment())
    assert fired(plan, mix, sorted(stops), simpy.Environment()) == timeouts
    assert fired(plan, mix, sorted(stops), Clock()) == timeouts


def test_a_clock_gathers_calls_due_together_into_one_event():
    env = Clock()
    got = []
    for k in range(5):
        call_later(env, 0.5, got.append, k)
    env.timeout(0.5).callbacks.append(lambda _event: got.append("timeout"))
    call_later(env, 0.5, got.append, 5)  # after the timeout: an event of its own
    assert len(env._queue) == 3
    env.run()
    assert got == [0, 1, 2, 3, 4, "timeout", 5] and env.now == 0.5


@pytest.mark.parametrize("env_class", [simpy.Environment, Clock])
def test_a_negative_delay_is_refused(env_class):
    with pytest.raises(ValueError, match="negative delay"):
        call_later(env_class(), -0.1, print)


@pytest.mark.parametrize("env_class", [simpy.Environment, Clock])
def test_a_call_scheduled_for_now_runs_after_a_process_started_by_a_later_call(env_class):
    env = env_class()
    got = []

    def process():
        got.append("process starts")
        yield env.timeout(0)

    call_later(env, 1.0, lambda _v: call_later(env, 0.0, got.append, "scheduled for now"))
    call_later(env, 1.0, lambda _v: env.process(process()))
    env.run()
    assert got == ["process starts", "scheduled for now"]


def test_a_clock_keeps_simpys_event_classes_bound_as_a_plain_environment_does():
    """SimPy binds ``timeout``, ``event``, ``process``, ... to an environment once; a
    subclass must too, or every ``env.timeout`` makes a new bound method."""
    plain, clock = simpy.Environment(), Clock()
    bound = {name for name, value in vars(plain).items() if callable(value)}
    assert {"timeout", "event", "process"} <= bound
    for name in bound:
        assert name in vars(clock), name
        assert getattr(clock, name).__self__ is clock
    event = clock.timeout(2.0, value="v")
    clock.run()
    assert clock.now == 2.0 and event.value == "v"
