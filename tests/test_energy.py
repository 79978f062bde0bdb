from itertools import pairwise

import pytest
import simpy
from hypothesis import given, settings
from hypothesis import strategies as st

from abm.energy import Battery, EnergyLedger, PowerModes
from abm.errors import ConfigError

POWER = {"ground": 0.5, "flight": 120.0, "beacon": 5.0, "hover": 115.0, "off": 0.0}

MODES = ["ground", "flight", "beacon", "hover"]


@settings(max_examples=60, deadline=None)
@given(
    st.lists(
        st.tuples(st.integers(0, 3), st.sampled_from(MODES), st.floats(0.0, 50.0)), max_size=40
    )
)
def test_ledger_equals_integral_of_power_over_mode_timeline(changes):
    env = simpy.Environment()
    ledger = EnergyLedger(env, PowerModes(POWER))
    for robot in range(4):
        ledger.set_mode(robot, "ground")
    for robot, mode, wait in changes:
        if env.now + wait > env.now:
            env.run(until=env.now + wait)
        ledger.set_mode(robot, mode)
    env.run(until=env.now + 7.0)
    end = env.now
    # integrate each robot's piecewise-constant power from the recorded timeline
    for robot in range(4):
        segments = [(t, m) for t, r, m in ledger.timeline if r == robot] + [(end, None)]
        expected = sum(POWER[m] * (t1 - t0) for (t0, m), (t1, _) in pairwise(segments))
        assert ledger.energy(robot) == pytest.approx(expected, rel=1e-12, abs=1e-9)
    assert ledger.energy() == pytest.approx(sum(ledger.frame().energy))


def test_battery_runs_flat_exactly_when_its_charge_is_used():
    env = simpy.Environment()
    ledger = EnergyLedger(env, PowerModes(POWER))
    flat = []
    Battery(ledger, capacity=1200.0, on_empty=lambda r: flat.append((r, env.now)))
    ledger.set_mode(7, "ground")  # 0.5 W
    env.run(until=100.0)  # 50 J used
    ledger.set_mode(7, "flight")  # 120 W: 1150 J left -> flat after 9.5833 s
    env.run(until=200.0)
    assert flat == [(7, pytest.approx(100.0 + 1150.0 / 120.0))]
    assert ledger.energy(7) == pytest.approx(1200.0 + 120.0 * (200.0 - flat[0][1]))


def test_bad_power_and_unknown_mode_are_rejected():
    with pytest.raises(ConfigError, match="power"):
        PowerModes({"flight": -1.0})
    env = simpy.Environment()
    ledger = EnergyLedger(env, PowerModes(POWER))
    with pytest.raises(ConfigError, match="unknown power mode 'warp'"):
        ledger.set_mode(1, "warp")


def test_a_model_without_powers_keeps_durations_and_has_no_batteries():
    env = simpy.Environment()
    ledger = EnergyLedger(env, PowerModes(None))
    ledger.set_mode(1, "anything")
    env.run(until=4.0)
    assert not ledger.has_powers
    assert ledger.duration("anything") == 4.0 and ledger.energy() == 0.0
    with pytest.raises(ConfigError, match="batteries need an energy model"):
        Battery(ledger, capacity=10.0, on_empty=lambda r: None)


def test_a_retired_robot_draws_no_more_power():
    env = simpy.Environment()
    ledger = EnergyLedger(env, PowerModes(POWER))
    ledger.set_mode(3, "flight")
    env.run(until=2.0)
    ledger.retire(3)
    env.run(until=10.0)
    assert ledger.energy(3) == pytest.approx(240.0)


@settings(max_examples=40, deadline=None)
@given(
    st.lists(
        st.tuples(st.integers(0, 3), st.sampled_from(MODES), st.floats(0.0, 50.0)), max_size=30
    ),
    st.lists(st.floats(0.0, 400.0), min_size=4, max_size=4),
)
def test_a_failed_robots_energy_stops_exactly_when_it_fails(changes, fail_at):
    """The fault path closes a robot's ledger whichever comes first, a fault or a flat battery
    (abm.faults): its energy is the integral of its power up to that moment, never more than
    the battery's charge, and it fails once."""
    env = simpy.Environment()
    ledger = EnergyLedger(env, PowerModes(POWER))
    failed: dict[int, float] = {}

    def fail(robot: int) -> None:
        if robot not in failed:
            failed[robot] = env.now
            ledger.retire(robot)

    battery = Battery(ledger, capacity=5_000.0, on_empty=fail)
    for robot, when in enumerate(fail_at):
        ledger.set_mode(robot, "ground")
        env.timeout(when).callbacks.append(lambda _ev, robot=robot: fail(robot))
    for robot, mode, wait in changes:
        env.run(until=env.now + wait + 1e-9)
        if robot not in failed:
            ledger.set_mode(robot, mode)
    env.run(until=env.now + 500.0)
    assert sorted(failed) == [0, 1, 2, 3]
    for robot, when in failed.items():
        assert when <= fail_at[robot]
        segments = [(t, m) for t, r, m in ledger.timeline if r == robot] + [(when, None)]
        expected = sum(POWER[m] * (t1 - t0) for (t0, m), (t1, _) in pairwise(segments))
        assert ledger.energy(robot) == pytest.approx(expected, rel=1e-12, abs=1e-9)
        assert ledger.energy(robot) <= battery.capacity + 1e-6
