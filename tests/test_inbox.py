"""The inbox keeps simpy.Store's order of events exactly (seeded hierarchy runs rely on it)."""

import itertools

import pytest
import simpy
from hypothesis import given, settings
from hypothesis import strategies as st

from abm.comms.inbox import Inbox

#: A scenario: puts as (time, sender) and, per consumer, the pauses after each item it takes.
puts = st.lists(st.tuples(st.integers(0, 6), st.integers(0, 2)), max_size=25)
pause_lists = st.lists(st.sampled_from([0, 0, 1, 2]), min_size=30, max_size=30)
pauses = st.lists(pause_lists, min_size=1, max_size=3)


def trace(make_box, put_times, consumer_pauses, interrupt_at: int | None) -> list[tuple]:
    """Run one scenario on the box ``make_box(env)``; every step of every process, in order,
    and the number of events scheduled.
    """
    env = simpy.Environment()
    box = make_box(env)
    steps: list[tuple] = []
    ticket = itertools.count()

    def sender(name: int, times: list[int]):
        for t in times:
            yield env.timeout(t - env.now)
            item = next(ticket)
            box.put(item)
            steps.append((env.now, "put", name, item))

    def consumer(name: int, waits: list[int]):
        try:
            for wait in waits:
                item = yield box.get()
                steps.append((env.now, "got", name, item))
                if wait:
                    yield env.timeout(wait)
        except simpy.Interrupt:
            steps.append((env.now, "interrupted", name))

    def interrupter(victim):
        yield env.timeout(interrupt_at)
        if victim.is_alive:
            victim.interrupt()

    consumers = [env.process(consumer(k, w)) for k, w in enumerate(consumer_pauses)]
    for name in range(3):
        env.process(sender(name, sorted(t for t, s in put_times if s == name)))
    if interrupt_at is not None:
        env.process(interrupter(consumers[0]))
    env.run()
    steps.append(("events", next(env._eid), "left", list(box.items)))
    return steps


@settings(max_examples=200, deadline=None)
@given(puts, pauses, st.none() | st.integers(0, 6))
def test_inbox_schedules_what_a_store_schedules(put_times, consumer_pauses, interrupt_at):
    """Puts at shared instants, one to three consumers pausing between items, a consumer
    interrupted while it waits: the same steps, in the same order, and the same number of
    events as with simpy.Store.
    """
    expected = trace(simpy.Store, put_times, consumer_pauses, interrupt_at)
    assert trace(Inbox, put_times, consumer_pauses, interrupt_at) == expected


@pytest.mark.parametrize("make_box", [simpy.Store, Inbox])
def test_an_item_put_while_a_get_waits_is_taken_when_the_put_event_is_processed(make_box):
    """A waiting get is served by the put's event, not inside ``put``: a process started at
    the same instant in between runs first, as with a Store.
    """
    env = simpy.Environment()
    box, order = make_box(env), []

    def reader():
        order.append(("got", (yield box.get())))

    def writer():
        yield env.timeout(1)
        box.put("a")
        env.process(other())

    def other():
        order.append(("other", env.now))
        yield env.timeout(0)

    env.process(reader())
    env.process(writer())
    env.run()
    assert order == [("other", 1), ("got", "a")]
