"""SwarmModel: the Mesa model whose clock is a SimPy environment.

The model owns everything a swarm needs: the SimPy environment (the only clock), a Mesa
continuous space, the arena, the comm network, the physics process, the energy ledger and the
recorder. ``step()`` runs the environment for a fixed slice of simulated time so that
``mesa.batch_run`` and SolaraViz drive it unchanged; ``run()`` runs to completion.
"""

from collections.abc import Callable, Mapping

import mesa
import numpy as np
import pandas as pd
import simpy
from mesa.experimental.continuous_space import ContinuousSpace

from abm.arena import Arena
from abm.comms import CommNetwork
from abm.energy import STIRLING_POWER, EnergyLedger, PowerModes
from abm.errors import ConfigError, check_range
from abm.physics import Controller, FlightParams, Physics
from abm.record import Recorder

__all__ = ["SwarmModel"]


class SwarmModel(mesa.Model):
    """Base class of every swarm model.

    Subclasses set ``STATES``, build robots and their behaviours, call :meth:`finish` when the
    run is over and implement :meth:`summary`.

    Args:
        arena: the world, or a function ``f(rng) -> Arena`` that builds it from the model's
            random generator (so a seed fixes the world too).
        seed: seed of the model's single random generator ``model.rng`` (None = fresh entropy).
        step_duration: simulated seconds per ``step()`` (s).
        time_limit: the run ends at this simulated time at the latest (s).
        comm_range: C_r (m).
        latency: message latency (s).
        message_loss: probability a transmission attempt is lost.
        powers: power (W) per mode.
        flight: flight dynamics.
        dt: physics tick (s).
        controller: the vectorised flight controller (may be set later as ``physics.controller``).

    """

    STATES: tuple[str, ...] = ()

    def __init__(
        self,
        arena: Arena | Callable[[np.random.Generator], Arena],
        *,
        seed: int | None = None,
        step_duration: float = 1.0,
        time_limit: float = 3600.0,
        comm_range: float = 4.0,
        latency: float = 0.1,
        message_loss: float = 0.0,
        powers: Mapping[str, float] | None = None,
        flight: FlightParams | None = None,
        dt: float = 0.1,
        controller: Controller | None = None,
        trace_interval: float | None = 1.0,
    ) -> None:
        if seed is not None and (isinstance(seed, bool) or not isinstance(seed, int | np.integer)):
            raise ConfigError(f"seed must be an integer or None, got {seed!r}")
        check_range("step_duration", step_duration, 0.0, low_open=True)
        check_range("time_limit", time_limit, 0.0, low_open=True)
        super().__init__(rng=seed)
        # Mesa replaces ``self.step`` by its own scheduler wrapper; our clock is SimPy, so the
        # class's step() (which runs SimPy for one slice) must be what batch_run and SolaraViz call.
        del self.step
        self.seed = seed
        self.env = simpy.Environment()
        if not isinstance(arena, Arena):
            arena = arena(self.rng)
        self.arena = arena
        self.step_duration = float(step_duration)
        self.time_limit = float(time_limit)
        self.space = ContinuousSpace(
            [[0.0, arena.width], [0.0, arena.height]], torus=False, random=self.random
        )
        self.comms = CommNetwork(self.env, arena, self.rng, comm_range, latency, message_loss)
        self.ledger = EnergyLedger(self.env, PowerModes({**STIRLING_POWER, **(powers or {})}))
        self.recorder = Recorder(self.env, self.STATES)
        self.physics = Physics(
            self.env,
            arena,
            self.rng,
            controller=controller,
            positions_out=self._write_positions,
            params=flight,
            dt=dt,
            on_collision=self._log_collision,
        )
        self.done = self.env.event()
        self.end_reason: str | None = None
        limit = self.env.timeout(self.time_limit)
        limit.callbacks.append(lambda _ev: self.finish("time limit"))
        self.datacollector = mesa.DataCollector(model_reporters=self.reporters())
        if trace_interval is not None:
            check_range("trace_interval", trace_interval, 0.0, low_open=True)
            self.env.process(self._trace(trace_interval))

    # ------------------------------------------------------------------ time
    @property
    def time(self) -> float:
        """Simulated time (s): always the SimPy clock's ``env.now``."""
        env = self.__dict__.get("env")
        return env.now if env is not None else 0.0

    @time.setter
    def time(self, value: float) -> None:
        # Mesa's constructor sets time = 0.0; the clock is SimPy's, so nothing else may set it.
        if value != self.time:
            raise AttributeError("model.time follows env.now; advance it with step() or run()")

    def step(self) -> None:
        """Run the simulation for ``step_duration`` simulated seconds (or until it ends)."""
        if not self.running:
            return
        self.steps += 1
        horizon = self.env.timeout(self.step_duration)
        self.env.run(until=self.env.any_of([horizon, self.done]))
        self.datacollector.collect(self)
        if self.done.triggered:
            self.running = False

    def run(self, until: float | None = None) -> "SwarmModel":
        """Run to the end of the search (or to simulated time ``until``); returns self."""
        if until is None:
            stop = self.done
        else:
            check_range("until", until, self.env.now)
            stop = self.env.any_of([self.done, self.env.timeout(until - self.env.now)])
        if self.running:
            self.env.run(until=stop)
            self.datacollector.collect(self)
        if self.done.triggered:
            self.running = False
        return self

    def finish(self, reason: str) -> None:
        """Mark the run as over (the first reason wins)."""
        if not self.done.triggered:
            self.end_reason = reason
            self.recorder.log("end", reason=reason)
            self.done.succeed(reason)

    # ------------------------------------------------------------------ data
    def reporters(self) -> dict:
        """Mesa DataCollector model reporters: robots per state (override to add more)."""
        return {state: (lambda m, s=state: m.recorder.counts[s]) for state in self.STATES}

    def state_counts(self) -> pd.DataFrame:
        """Robots per state after every change: ``time`` plus one column per state."""
        return self.recorder.state_counts()

    def events(self) -> pd.DataFrame:
        """The run's event log."""
        return self.recorder.events()

    def summary(self) -> dict:
        """A flat dict of the run's metrics (subclasses define it)."""
        raise NotImplementedError

    def positions(self) -> pd.DataFrame:
        """Sampled robot positions (time, robot, x, y, state), every ``trace_interval`` s."""
        return self.recorder.positions()

    # ------------------------------------------------------------------ plumbing
    def _trace(self, interval: float):
        while True:
            agents = self.space.active_agents
            if agents:
                self.recorder.snapshot(
                    np.array([a.unique_id for a in agents]),
                    self.space.agent_positions.copy(),
                    [a.state for a in agents],
                )
            yield self.env.timeout(interval)

    def _write_positions(self, rows: np.ndarray, positions: np.ndarray) -> None:
        self.space.agent_positions[rows] = positions

    def _log_collision(self, kind: str, a: int, b: int | None) -> None:
        self.recorder.log("collision", a, against=kind, other=b)
