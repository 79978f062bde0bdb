"""SwarmModel: the Mesa model whose clock is a SimPy environment, and the model contract's hooks.

The model owns everything a swarm needs: the SimPy environment (the only clock), a Mesa
continuous space, the arena, the comm network, the physics process, the energy ledger, the
recorder, the robots' lifecycle events (:mod:`abm.lifecycle`) and (when the model covers an
area) the coverage raster. Its robots are Mesa's ``model.agents``. ``step()`` runs the
environment for a fixed slice of simulated time so that ``mesa.batch_run`` and SolaraViz drive
it unchanged; ``run()`` runs to completion.

A model is a subclass that declares its ``Params`` dataclass, its ``STATES`` and the optional
hooks below; every tool of the project reads those and nothing else (see
``docs/adding-a-model.md``).
"""

import inspect
import math
from collections.abc import Callable, Mapping, Sequence
from operator import attrgetter
from typing import ClassVar

import mesa
import numpy as np
import pandas as pd
import simpy
from mesa.experimental.continuous_space import ContinuousSpace
from numba import njit

from abm.arena import Arena
from abm.checks import check_controller, check_metrics, check_reporters
from abm.clock import Clock, call_later
from abm.collector import StepCollector
from abm.comms import CommNetwork, Shadowing
from abm.coverage import CoverageRaster
from abm.energy import EnergyLedger, PowerModes
from abm.errors import ConfigError, check_seed
from abm.faults import FAILED, FaultInjector
from abm.lifecycle import Lifecycle
from abm.params import COLLISION_ROWS, SwarmParams, bind_params, make_params, param_fields
from abm.physics import Controller, FlightParams, Physics
from abm.published import Censored, Claim, MacroSpec, Published, ReportLayout
from abm.record import Recorder
from abm.robot import Robot
from abm.styles import Layer, StateStyle, resolve_styles
from abm.units import Quantity
from abm.units import declare as declare_units

#: The attributes a position sample reads of every robot.
_STATE_OF, _ID_OF = attrgetter("state"), attrgetter("unique_id")
#: How a failed robot is drawn unless the model says otherwise.
FAILED_STYLE = StateStyle("#000000", marker="X", size=45.0, layer=6.0)

__all__ = ["SwarmModel"]


class SwarmModel(mesa.Model):
    """Base class of every swarm model.

    Class attributes a model declares (the contract; checked by :func:`abm.contract.check_model`):

    - ``Params``: its frozen parameters dataclass (a :class:`~abm.params.SwarmParams`
      subclass). Every field is also a keyword of the constructor, which takes nothing else
      but ``seed``.
    - ``STATES``: the robot states, counted by the recorder in this order.
    - ``STATE_STYLES``: optional :class:`~abm.styles.StateStyle` per state.
    - ``MACRO``: optional :class:`~abm.published.MacroSpec`: the two counted states (moving,
      settled) the macroscopic recurrence describes, for ``abm fit``, and the published fits.
    - ``ARROWS_LABEL``: legend text of :meth:`arrows`; None when the model draws no arrows.
    - ``PUBLISHED`` / ``REPORT`` / ``CLAIMS``: the published numbers, figure layout and
      checkable claims for ``abm report`` (usually imported from the model's ``published.py``).
    - ``CENSORED``: the summary metrics a run's end can cut short (:class:`~abm.published.Censored`:
      a time to a target, or anything a run accumulates, that a time limit censors); reports
      show them as censored (share, Kaplan-Meier median), judge no published number from
      censored values and run no statistic on them.
    - ``CUT_ENDS``: prefixes of ``end_reason`` that end a run before the run its source
      describes is complete (a time limit before the last iteration); a published number or
      claim whose runs include such a run is not judged ("not comparable", saying how many).
      Empty for a model whose source's runs themselves end at a time limit.
    - ``CONTACTS``: False for a model whose robots cannot touch a wall or one another (no
      physics and no :meth:`collision` calls: flocking's birds pass through each other); its
      summary then has no collision counts, which would read 0 whatever happened, and
      ``collision_rows`` is refused.
    - ``APP``: module of the model's SolaraViz page (``page`` attribute); None = a default page
      with sliders for its numeric parameters.
    - ``QUICK``: keywords of a small set-up on which a run of a couple of simulated minutes
      already shows every part of the model (empty when the defaults do); the contract tests
      run every model with them.
    - ``SUMMARY_UNITS``: the unit and meaning of each key of the model's :meth:`metrics`
      (key or ``fnmatch`` pattern -> :class:`~abm.units.Quantity`); the common keys are
      documented once in :data:`abm.units.COMMON`.
    - ``FAULTS``: the kinds of fault the model handles ("robot", "link", "sensor"; see
      :mod:`abm.faults`): ``Params`` gets the fault keywords of these kinds, and only those,
      when the class is defined (:func:`abm.params.with_faults`); a keyword of another kind
      is refused naming the kinds the model handles. A model declares "robot" once its
      behaviour copes with :meth:`on_robot_failed`, "link" once its messages travel on
      ``self.comms``, "sensor" once it reads its sensors through ``self.faults.sensed``.

    What every model instance offers the tools: ``params``, ``coverage`` (a
    :class:`~abm.coverage.CoverageRaster` or None), :meth:`summary` (the common keys of
    :meth:`common_summary` plus the model's :meth:`metrics`), :meth:`state_counts`,
    :meth:`events`, :meth:`positions` and :meth:`arrows`.

    Args:
        params: the validated parameters (see :meth:`make_params`).
        arena: the world, or a function ``f(rng) -> Arena`` that builds it from the model's
            random generator (so a seed fixes the world too).
        seed: seed of the model's single random generator ``model.rng`` (None = fresh entropy).
        comm_range: range of the comm network (m).
        latency: delay of one message on the comm network (s); for a model that sends messages,
            a field of its params.
        message_loss: probability that one transmission attempt is lost; likewise.
        shadowing: the radio's log-normal shadowing (None: a disc with line of sight).
        powers: power (W) drawn in each mode; None when the model has no energy model.
        flight: flight dynamics of the flyers.
        physics: False for a model whose robots never fly under the continuous dynamics (they
            move by whole steps, :mod:`abm.kinematics`): ``self.physics`` is then None.
        controller: the vectorised flight controller (may be set later as
            ``physics.controller``, in the model's ``__init__``): an object with
            ``control(physics)`` (:class:`~abm.physics.Controller`). A model with ``physics``
            must have one before :meth:`run` or :meth:`step` starts (else HookError).
        torus: True for a periodic world: the Mesa space wraps at the arena's edges (for a
            wall-free arena and robots that move by whole steps, ``physics=False``).
        failures: the model's robots can fail although no fault keyword asks for it (e.g.
            batteries): the state ``failed`` is counted.

    """

    Params: ClassVar[type[SwarmParams]] = SwarmParams
    STATES: ClassVar[tuple[str, ...]] = ()
    STATE_STYLES: ClassVar[Mapping[str, StateStyle]] = {}
    MACRO: ClassVar[MacroSpec | None] = None
    ARROWS_LABEL: ClassVar[str | None] = None
    PUBLISHED: ClassVar[Sequence[Published]] = ()
    CLAIMS: ClassVar[Sequence[Claim]] = ()
    CENSORED: ClassVar[Sequence[Censored]] = ()
    CUT_ENDS: ClassVar[tuple[str, ...]] = ()
    CONTACTS: ClassVar[bool] = True
    REPORT: ClassVar[ReportLayout | None] = None
    APP: ClassVar[str | None] = None
    QUICK: ClassVar[Mapping[str, object]] = {}
    FAULTS: ClassVar[frozenset[str]] = frozenset()
    SUMMARY_UNITS: ClassVar[Mapping[str, Quantity]] = {}

    def __init_subclass__(cls, **kwargs) -> None:
        super().__init_subclass__(**kwargs)
        # the fault keywords of the kinds the model declares, and only those, join its params
        cls.Params = bind_params(cls.Params, cls.FAULTS, cls.__module__, cls.__qualname__)
        cls.__signature__ = _signature(cls.Params)
        if isinstance(cls.SUMMARY_UNITS, Mapping):  # else the contract refuses the class
            declare_units(cls.SUMMARY_UNITS)

    def __init__(
        self,
        params: SwarmParams,
        arena: Arena | Callable[[np.random.Generator], Arena],
        *,
        seed: int | None = None,
        comm_range: float = 1.0,
        latency: float = 0.1,
        message_loss: float = 0.0,
        shadowing: Shadowing | None = None,
        powers: Mapping[str, float] | None = None,
        flight: FlightParams | None = None,
        physics: bool = True,
        controller: Controller | None = None,
        torus: bool = False,
        failures: bool = False,
    ) -> None:
        seed = check_seed(seed)
        if not isinstance(params, self.Params):
            raise ConfigError(
                f"params must be a {self.Params.__name__}, got {type(params).__name__}"
            )
        if torus and physics:
            raise ConfigError(
                "torus=True needs physics=False: the flight physics bounces off the arena's "
                "edges instead of wrapping"
            )
        if not self.CONTACTS and params.collision_rows != COLLISION_ROWS:
            raise ConfigError(
                f"collision_rows: {type(self).__name__}'s robots never touch a wall or one "
                "another, so there are no collisions to log; leave it out"
            )
        super().__init__(rng=seed)
        _hand_time_to_simpy(self)
        self.params = params
        self.seed = seed
        self.env = Clock()
        if not isinstance(arena, Arena):
            arena = arena(self.rng)
        self.arena = arena
        self.step_duration = params.step_duration
        self.time_limit = params.time_limit
        self.space = ContinuousSpace(
            [[0.0, arena.width], [0.0, arena.height]], torus=torus, random=self.random
        )
        self._row_of = np.zeros(0, dtype=np.int64)  # robot id -> row of space.agent_positions
        # the ids and state codes of the space's rows, recorder.moves when they were read, and
        # an all-False comm mask of their length: position samples reuse them (the same arrays,
        # which the recorder then does not compare again) until an agent joins, leaves or
        # changes state
        self._space_rows: tuple[np.ndarray, np.ndarray, int, np.ndarray] | None = None
        # the physics' ids array at the last tick and their rows of the space (place_flyers)
        self._flyer_rows: tuple[np.ndarray, np.ndarray] | None = None
        self.comms = CommNetwork(
            self.env, arena, self.rng, comm_range, latency, message_loss, shadowing
        )
        self.ledger = EnergyLedger(self.env, PowerModes(powers))
        if (failures or params.fault_kinds & {"robot"}) and FAILED not in self.STATES:
            self.STATES = (*self.STATES, FAILED)
        self.recorder = Recorder(
            self.env, self.STATES, row_limits={"collision": params.collision_rows}
        )
        self.lifecycle = Lifecycle()
        self.faults = FaultInjector(self)
        self.coverage: CoverageRaster | None = None
        self.wall_collisions = 0
        self.robot_collisions = 0
        self.physics: Physics | None = None
        if physics:
            self.physics = Physics(
                self.env,
                arena,
                self.rng,
                controller=controller,
                positions_out=self.place_flyers,
                params=flight,
                dt=params.dt,
                on_collision=self.collision,
                owner=type(self).__qualname__,
            )
        for part in (self.physics, self.comms, self.ledger):
            if part is not None:  # each forgets a robot that fails or leaves
                self.lifecycle.subscribe("failed", part.robot_left)
                self.lifecycle.subscribe("removed", part.robot_left)
        self.done = self.env.event()
        self.end_reason: str | None = None
        call_later(self.env, self.time_limit, self.finish, "time limit")
        self._datacollector: mesa.DataCollector | None = None
        #: Simulated time of the last position sample (None: positions are not traced).
        self._traced_at: float | None = None
        if params.trace_interval is not None:
            self._traced_at = -math.inf
            self.env.process(self._trace(params.trace_interval))

    @classmethod
    def make_params(cls, **kwargs: object) -> SwarmParams:
        """Validated ``Params`` from constructor keywords: the one place keywords are mapped."""
        return make_params(cls.Params, kwargs)

    @classmethod
    def from_params(cls, params: SwarmParams, seed: int | None = None) -> "SwarmModel":
        """A model built from a ready params instance."""
        return cls(seed=seed, **params.as_dict())

    @property
    def datacollector(self) -> StepCollector:
        """Mesa's DataCollector of :meth:`reporters` and ``time`` (s), keyed by the step count
        (so ``mesa.batch_run``'s ``Step`` counts steps); made on first use, once the model is
        built.
        """
        if self._datacollector is None:
            reporters = check_reporters(self.reporters(), f"{type(self).__qualname__}.reporters()")
            self._datacollector = StepCollector(reporters)
        return self._datacollector

    @property
    def state_styles(self) -> dict[str, StateStyle]:
        """A style for every state of this run (declared or from the palette)."""
        return resolve_styles(self.STATES, {FAILED: FAILED_STYLE, **self.STATE_STYLES})

    # ------------------------------------------------------------------ time
    @property
    def time(self) -> float:
        """Simulated time (s): Mesa's ``model.time``, which a discrete-event simulator
        controls (here SimPy: it is always ``env.now``).

        Assigning a later time advances the simulation to it (or to its end), which is how
        Mesa's own ``run_for`` and ``run_until`` move time; an earlier one is refused.
        """
        env = self.__dict__.get("env")
        return env.now if env is not None else 0.0

    @time.setter
    def time(self, value: float) -> None:
        if "env" not in self.__dict__:
            return  # Mesa's constructor starts the clock at 0, before SimPy's exists
        if value < self.env.now:
            raise ValueError(
                f"model.time cannot go back: it is {self.env.now:g} s, asked for {value:g} s"
            )
        if value > self.env.now and self.running:
            self.check_ready()
            self._advance(self.env.any_of([self.done, self.env.timeout(value - self.env.now)]))

    def step(self) -> None:
        """Mesa's step: run the simulation for ``step_duration`` simulated seconds (or until
        it ends), count the step in ``steps`` and collect the data collector's row.
        """
        if not self.running:
            return
        self.check_ready()
        self.steps += 1
        self._advance(self.env.any_of([self.env.timeout(self.step_duration), self.done]))
        self.datacollector.collect(self)

    def _advance(self, stop: simpy.events.Event) -> None:
        """Run SimPy until ``stop``; the model stops running once the run is over."""
        self.env.run(until=stop)
        if self.done.triggered:
            if self.running and self._traced_at is not None and self._traced_at < self.env.now:
                self._sample_positions()  # the end itself, as the run's final picture shows it
            self.running = False

    def run(self, until: float | None = None) -> "SwarmModel":
        """Run to the end (or to simulated time ``until``, s); returns self."""
        if until is None:
            stop = self.done
        else:
            if isinstance(until, bool) or not isinstance(until, int | float):
                raise ConfigError(f"until must be a number of seconds, got {until!r}")
            if until < self.env.now:
                raise ConfigError(
                    f"until must be >= the current time {self.env.now:g}, got {until}"
                )
            stop = self.env.any_of([self.done, self.env.timeout(until - self.env.now)])
        if self.running:
            self.check_ready()
            self._advance(stop)
            self.datacollector.collect(self)
        return self

    def check_ready(self) -> None:
        """Raise HookError unless the built model can start: a model that flies robots has a
        flight controller (an AttributeError from inside SimPy at the first take-off
        otherwise). :meth:`run` and :meth:`step` call it before simulated time moves; a tool
        that builds models without running them (a sweep's dry build) calls it too.
        """
        if self.physics is not None:
            check_controller(self.physics.controller, type(self).__qualname__)

    def finish(self, reason: str) -> None:
        """Mark the run as over (the first reason wins)."""
        if not self.done.triggered:
            self.end_reason = reason
            self.recorder.log("end", reason=reason)
            self.done.succeed(reason)

    # ------------------------------------------------------------------ hooks
    def metrics(self) -> dict:
        """The model's own results, added to the common summary keys (override): a dict of
        str keys (not those of :meth:`common_summary`) to one number, true/false, text or None
        each (:meth:`summary` checks it).
        """
        return {}

    def on_robot_failed(self, robot: Robot) -> None:
        """A robot failed (override for the model's own structures and repair).

        When this runs the framework has already done its part: the fault is in the event
        log, the robot is out of the air and the comm network, its state is ``failed``, its
        energy ledger is closed, its process interrupted, and ``robot.failure`` says when, why
        and in what state. The model drops it from its own structures (a beacon network, a
        tree, particle arrays) and may start a repair.
        """

    def on_link_fault(self, a: object, b: object, up: bool) -> None:
        """A link outage took the link ``a``-``b`` down (``up`` False) or it came back up
        (override when the model keeps structures built on the comm graph's links).
        """

    def arrows(self) -> tuple[np.ndarray, np.ndarray] | None:
        """Arrows to draw: ``(points, vectors)``, both ``(k, 2)`` in m, or None (models with
        ``ARROWS_LABEL``; checked where drawn, :func:`abm.checks.arrows_of`).
        """
        return None

    def layers(self) -> list[Layer]:
        """Extra point clouds or rasters the live page and PNGs draw (e.g. particle clouds):
        a list of :class:`~abm.styles.Layer` (checked where drawn, :func:`abm.checks.layers_of`).
        """
        return []

    def reporters(self) -> dict:
        """Mesa DataCollector model reporters: robots per state, ``coverage`` (% of the free
        area, when the model covers) and ``energy`` (J, when it has an energy model).
        """
        out = {state: (lambda m, s=state: m.recorder.counts[s]) for state in self.STATES}
        if self.coverage is not None:
            out["coverage"] = lambda m: 100.0 * m.coverage.fraction
        if self.ledger.has_powers:
            out["energy"] = lambda m: m.ledger.energy()
        return out

    # ------------------------------------------------------------------ data
    @property
    def collisions(self) -> int:
        """Collisions so far: wall contacts plus two per robot-robot contact."""
        return self.wall_collisions + self.robot_collisions

    def common_summary(self) -> dict:
        """The keys every model's summary has.

        ``time`` (s) and ``end_reason`` always; ``collisions`` (wall contacts plus two per
        robot-robot contact), ``wall_collisions`` and ``robot_collisions`` unless the model's
        robots make no contacts (``CONTACTS`` False); ``coverage_area``
        (% of the free area) when the model covers; ``energy_total`` (J) when it has an energy
        model; ``failed`` (robots failed so far) when its robots can fail (:mod:`abm.faults`);
        ``faults_skipped`` (scheduled faults that found no robot in ``fault_states``) when the
        run has ``fault_times``.
        """
        out = {"time": float(self.env.now), "end_reason": self.end_reason or "running"}
        if self.CONTACTS:
            out["collisions"] = self.collisions
            out["wall_collisions"] = self.wall_collisions
            out["robot_collisions"] = self.robot_collisions
        if self.coverage is not None:
            out["coverage_area"] = 100.0 * self.coverage.fraction
        if self.ledger.has_powers:
            out["energy_total"] = self.ledger.energy()
        if FAILED in self.STATES:
            out["failed"] = len(self.faults.failures)
        if getattr(self.params, "fault_times", ()):  # a scheduled fault may find no robot
            out["faults_skipped"] = self.faults.skipped
        return out

    def summary(self) -> dict:
        """A flat dict of the run's results: :meth:`common_summary` then :meth:`metrics`
        (checked: str keys other than the common ones, one number, true/false, text or None
        each; else HookError).
        """
        common = self.common_summary()
        hook = f"{type(self).__qualname__}.metrics()"
        return {**common, **check_metrics(self.metrics(), hook, tuple(common))}

    def state_counts(self) -> pd.DataFrame:
        """Robots per state after every change: ``time`` plus one column per state."""
        return self.recorder.state_counts()

    def events(self) -> pd.DataFrame:
        """The run's event log."""
        return self.recorder.events()

    def samples(self) -> pd.DataFrame:
        """The model's own time series (``time`` plus its metrics), if it records one; sweeps
        keep it beside the state counts and reports draw its curves.
        """
        return self.recorder.samples()

    def place(self, ids: np.ndarray, positions: np.ndarray) -> None:
        """Put robots at ``positions`` (m) in the Mesa space (the physics does this for flyers;
        a model moving robots by whole steps calls it).
        """
        self.space.agent_positions[self.rows_of(ids)] = positions

    def place_flyers(self, ids: np.ndarray, positions: np.ndarray) -> None:
        """:meth:`place` for the physics after every tick, with the rows of ``ids`` looked up
        once per flyer set.

        The physics replaces its ids array when flyers join or leave and never changes it in
        place, so the same array object means the same flyers; the rows are looked up again
        for a new array, and after an agent left the space (the rows after it moved up; one
        that joins takes a new last row and moves none).
        """
        cached = self._flyer_rows
        if cached is None or cached[0] is not ids:
            cached = self._flyer_rows = (ids, self.rows_of(ids))
        _put_rows(self.space.agent_positions, cached[1], positions)

    def robots_of(self, role: type[Robot]) -> mesa.agent.AgentSet:
        """The robots of class ``role`` in creation order: Mesa's ``agents_by_type[role]``, or
        an empty AgentSet while the model has made none (a baseline without anchors, a swarm
        not deployed yet), where ``agents_by_type`` has no key.
        """
        found = self.agents_by_type.get(role)
        return found if found is not None else mesa.agent.AgentSet([], random=self.random)

    def robot(self, robot_id: int) -> Robot:
        """The robot with this id (for callbacks that name robots by id, such as a battery's
        or a controller's), found through its row of the space.

        Raises:
            KeyError: no robot in the model has this id (it was removed, or never made).

        """
        rows = self._row_of
        if not 0 <= robot_id < len(rows) or rows[robot_id] < 0:
            raise KeyError(f"no robot {robot_id} in the model")
        return self.space.active_agents[int(rows[robot_id])]

    def rows_of(self, ids: np.ndarray) -> np.ndarray:
        """The rows of ``space.agent_positions`` that hold the agents ``ids`` (for a model's
        vectorised work on its robots' positions; valid until an agent leaves the space).
        """
        return self._row_of[np.asarray(ids, dtype=np.int64)]

    def positions(self) -> pd.DataFrame:
        """Sampled robot positions (time, robot, x, y, state, comm), every ``trace_interval`` s.

        ``comm`` says whether the robot was a node of the comm network then.
        """
        return self.recorder.positions()

    # ------------------------------------------------------------------ robots in the space
    def joined_space(self, robot_id: int) -> None:
        """An agent joined the space as its last row: :class:`~abm.robot.Robot` calls this
        itself; an agent of another kind that takes a row of the space (a bird of a flock)
        calls it from its constructor, so the id -> row table stays complete.
        """
        row = len(self.space.active_agents) - 1
        self._space_rows = None
        if robot_id >= len(self._row_of):
            grown = np.full(max(2 * len(self._row_of), robot_id + 1), -1, dtype=np.int64)
            grown[: len(self._row_of)] = self._row_of
            self._row_of = grown
        self._row_of[robot_id] = row

    def left_space(self) -> None:
        """Rows shift when an agent leaves the space: rebuild the id -> row table (called by
        :meth:`Robot.remove <abm.robot.Robot.remove>` after the agent is gone).
        """
        self._space_rows = self._flyer_rows = None
        self._row_of[:] = -1
        for row, agent in enumerate(self.space.active_agents):
            self._row_of[agent.unique_id] = row

    # ------------------------------------------------------------------ plumbing
    def _trace(self, interval: float):
        """Sample every robot's position, state and comm membership every ``interval`` s (and
        once more at the end, :meth:`_advance`, when the run ends between two samples).
        """
        while True:
            self._sample_positions()
            yield self.env.timeout(interval)

    def _sample_positions(self) -> None:
        """One sample of every robot's position, state and comm membership, now.

        The per-robot attributes are read with ``map`` (C loops, no Python frame per robot):
        at 10,000 robots a sample took 16 ms as list comprehensions.
        """
        self._traced_at = self.env.now
        agents = self.space.active_agents
        if not agents:
            return
        rows = self._space_rows
        if rows is None or rows[2] != self.recorder.moves or len(rows[0]) != len(agents):
            rows = self._space_rows = (
                np.fromiter(map(_ID_OF, agents), dtype=np.int64, count=len(agents)),
                self.recorder.state_codes(map(_STATE_OF, agents)),
                self.recorder.moves,
                np.zeros(len(agents), dtype=bool),  # no robot a comm node
            )
        graph = self.comms.graph
        self.recorder.snapshot(
            rows[0],
            self.space.agent_positions,  # copied (the rows that changed) by the recorder
            rows[1],
            np.fromiter(map(graph._adj.__contains__, rows[0].tolist()), bool, len(agents))
            if graph
            else rows[3],
        )

    def collision(self, kind: str, a: int, b: int | None = None) -> None:
        """Count and log a new contact: ``kind`` "wall" (robot ``a`` bumped a wall) or "robot"
        (``a`` and ``b`` touched; counted twice, once for each robot).
        """
        if kind == "robot":
            self.robot_collisions += 2
        else:
            self.wall_collisions += 1
        self.recorder.log("collision", a, against=kind, other=b)


@njit(cache=True)
def _put_rows(target: np.ndarray, rows: np.ndarray, values: np.ndarray) -> None:
    """``target[rows] = values`` for ``(n, 2)`` values, compiled (a quarter of numpy's fancy
    assignment's cost for a few rows).
    """
    for k in range(rows.shape[0]):
        target[rows[k], 0] = values[k, 0]
        target[rows[k], 1] = values[k, 1]


def _signature(params_cls: type[SwarmParams]) -> inspect.Signature:
    """``(*, seed=None, <every field of params_cls>=default)``: what Mesa, help() and tools see."""
    kw = inspect.Parameter.KEYWORD_ONLY
    parameters = [inspect.Parameter("seed", kw, default=None, annotation=int | None)]
    for f in param_fields(params_cls):
        parameters.append(inspect.Parameter(f.name, kw, default=f.default, annotation=f.type))
    return inspect.Signature(parameters)


def _hand_time_to_simpy(model: mesa.Model) -> None:
    """Make SimPy the model's clock the way Mesa's own discrete-event simulator does
    (``mesa.experimental.devs.DEVSimulator.setup`` stops the default schedule).

    Mesa 3.x binds ``model.step`` per instance to a wrapper that advances its clock by one
    time unit and calls the class's ``step()`` from a recurring event. Here a step is
    ``step_duration`` s of SimPy's clock, so ``model.step()`` is the class's own
    :meth:`SwarmModel.step` and Mesa's recurring step event is stopped: ``run_for`` and
    ``run_until`` then advance SimPy through ``model.time`` without running steps of their
    own. A Mesa that binds neither leaves nothing to undo, and one without Mesa 3's
    ``steps`` counter (Mesa 4) gets it here, since ``mesa.batch_run`` and the data collector
    count steps with it.
    """
    model.__dict__.pop("step", None)
    model.__dict__.setdefault("steps", 0)
    schedule = model.__dict__.get("_default_schedule")
    if schedule is not None:
        schedule.stop()
