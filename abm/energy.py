"""Power modes, an exact energy ledger and batteries whose depletion is a SimPy event.

Power is piecewise constant: a robot draws the power of its current mode until the mode
changes. The ledger therefore integrates exactly: energy = sum over mode segments of
P(mode) * duration. The power of each mode is the model's (its params); a model without an
energy model still names modes, and the ledger then keeps only their durations.
"""

from collections import defaultdict
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING

import pandas as pd
import simpy

from abm.clock import call_later
from abm.errors import ConfigError, check_range

if TYPE_CHECKING:  # annotations only: the parts do not need Mesa to run
    from mesa import Agent

__all__ = ["PowerModes", "EnergyLedger", "Battery"]


@dataclass(frozen=True)
class PowerModes:
    """Power (W) drawn in each named mode; ``watts=None``: no energy model (every mode 0 W).

    Attributes:
        watts: mode name -> power (W), or None.

    """

    watts: Mapping[str, float] | None = None

    def __post_init__(self) -> None:
        for mode, power in (self.watts or {}).items():
            check_range(f"power[{mode!r}]", power, 0.0)

    @property
    def declared(self) -> bool:
        """True when the model gave powers (it has an energy model)."""
        return self.watts is not None

    def __getitem__(self, mode: str) -> float:
        if self.watts is None:
            return 0.0
        try:
            return self.watts[mode]
        except KeyError:
            known = ", ".join(sorted(self.watts))
            raise ConfigError(f"unknown power mode {mode!r}; known modes: {known}") from None


class EnergyLedger:
    """Integrates each robot's power over its mode timeline, exactly.

    Args:
        env: the SimPy environment (the clock).
        powers: the power of each mode.

    """

    def __init__(self, env: simpy.Environment, powers: PowerModes) -> None:
        self.env = env
        self.powers = powers
        self._mode: dict[int, str] = {}
        self._since: dict[int, float] = {}
        self._energy: dict[tuple[int, str], float] = defaultdict(float)
        self._duration: dict[tuple[int, str], float] = defaultdict(float)
        self.timeline: list[tuple[float, int, str]] = []
        self._listeners: list[Callable[[int, str], None]] = []

    @property
    def has_powers(self) -> bool:
        """True when energies mean something (the model declared its powers)."""
        return self.powers.declared

    def on_mode_change(self, listener: Callable[[int, str], None]) -> None:
        """Call ``listener(robot_id, new_mode)`` after every mode change (batteries use it)."""
        self._listeners.append(listener)

    def set_mode(self, robot_id: int, mode: str) -> None:
        """Close the robot's current mode segment at ``env.now`` and open a new one."""
        self.powers[mode]  # validates the name
        now = self.env.now
        if robot_id in self._mode:
            self._close(robot_id, now)
        self._mode[robot_id] = mode
        self._since[robot_id] = now
        self.timeline.append((now, robot_id, mode))
        for listener in self._listeners:
            listener(robot_id, mode)

    def _close(self, robot_id: int, now: float) -> None:
        mode = self._mode[robot_id]
        dt = now - self._since[robot_id]
        self._energy[robot_id, mode] += self.powers[mode] * dt
        self._duration[robot_id, mode] += dt
        self._since[robot_id] = now

    def retire(self, robot_id: int) -> None:
        """Close a robot's last segment: it left the model and draws nothing more."""
        if robot_id in self._mode:
            self._close(robot_id, self.env.now)
            del self._mode[robot_id]
            del self._since[robot_id]

    def robot_left(self, robot: "Agent") -> None:
        """A robot failed or was removed (a lifecycle event): it draws nothing more."""
        self.retire(robot.unique_id)

    def mode(self, robot_id: int) -> str | None:
        """The robot's current mode (None for a robot that never had one, or retired)."""
        return self._mode.get(robot_id)

    def power(self, robot_id: int) -> float:
        """The robot's current power draw (W)."""
        return self.powers[self._mode[robot_id]]

    def _settled(self) -> tuple[dict, dict]:
        """Energy and durations including the open segments up to ``env.now``."""
        energy = defaultdict(float, self._energy)
        duration = defaultdict(float, self._duration)
        now = self.env.now
        for rid, mode in self._mode.items():
            dt = now - self._since[rid]
            energy[rid, mode] += self.powers[mode] * dt
            duration[rid, mode] += dt
        return energy, duration

    def energy(self, robot_id: int | None = None, mode: str | None = None) -> float:
        """Energy (J) used so far, optionally by one robot and/or in one mode."""
        energy, _ = self._settled()
        return sum(
            e
            for (rid, m), e in energy.items()
            if (robot_id is None or rid == robot_id) and (mode is None or m == mode)
        )

    def duration(self, mode: str, robot_id: int | None = None) -> float:
        """Time (s) spent in ``mode`` so far, by one robot or summed over the swarm."""
        _, duration = self._settled()
        return sum(
            d
            for (rid, m), d in duration.items()
            if m == mode and (robot_id is None or rid == robot_id)
        )

    def frame(self) -> pd.DataFrame:
        """Tidy table: one row per robot and mode with ``time`` (s) and ``energy`` (J)."""
        energy, duration = self._settled()
        rows = [
            {"robot": rid, "mode": m, "time": duration[rid, m], "energy": e}
            for (rid, m), e in sorted(energy.items())
        ]
        return pd.DataFrame(rows, columns=["robot", "mode", "time", "energy"])


class Battery:
    """A battery per robot whose running flat is a scheduled SimPy event.

    Every mode change reschedules the depletion time ``now + charge / power``; stale
    schedules are recognised by a generation counter (SimPy timeouts cannot be cancelled).

    Args:
        ledger: the ledger whose mode changes drive the batteries.
        capacity: charge of a full battery (J).
        on_empty: called as ``on_empty(robot_id)`` when a battery runs flat.

    """

    def __init__(
        self, ledger: EnergyLedger, capacity: float, on_empty: Callable[[int], None]
    ) -> None:
        check_range("battery_capacity", capacity, 0.0, low_open=True)
        if not ledger.has_powers:
            raise ConfigError("batteries need an energy model: the model declares no powers")
        self.ledger = ledger
        self.capacity = float(capacity)
        self.on_empty = on_empty
        self._generation: dict[int, int] = defaultdict(int)
        self.depleted: set[int] = set()
        self._exempt: set[int] = set()
        ledger.on_mode_change(self._reschedule)

    def exempt(self, robot_id: int) -> None:
        """Give one robot no battery limit (e.g. a powered base station)."""
        self._exempt.add(robot_id)
        self._generation[robot_id] += 1  # any depletion already scheduled is void

    def charge(self, robot_id: int) -> float:
        """Charge left (J)."""
        return max(0.0, self.capacity - self.ledger.energy(robot_id))

    def _reschedule(self, robot_id: int, mode: str) -> None:
        self._generation[robot_id] += 1
        power = self.ledger.powers[mode]
        if power <= 0 or robot_id in self.depleted or robot_id in self._exempt:
            return
        delay = self.charge(robot_id) / power
        generation = self._generation[robot_id]
        call_later(self.ledger.env, delay, lambda _value: self._expire(robot_id, generation))

    def _expire(self, robot_id: int, generation: int) -> None:
        if self._generation[robot_id] != generation or robot_id in self.depleted:
            return
        self.depleted.add(robot_id)
        self.on_empty(robot_id)
