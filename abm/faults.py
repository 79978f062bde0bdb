"""The fault injector: robots, links and sensors that fail, as seeded, recorded SimPy events.

Every model owns one :class:`FaultInjector` (``model.faults``), configured by the fault
keywords of the kinds the model declares (``SwarmModel.FAULTS``; the fields of
:data:`abm.params.FAULT_PARAMS` its params get). With the defaults it
injects nothing, draws no random number and schedules no event, so a run without faults is the
run it always was.

Robot faults. Each robot has a lifetime drawn from a Weibull law (shape k, scale 1/lambda;
exponential at k = 1), counted only while the robot is in one of ``fault_states``; at
``fault_times`` one robot drawn among the eligible ones fails too. Any failure -- these, a flat
battery, or a model's own call of :meth:`FaultInjector.fail` -- takes the same path:

1. the fault is written to the event log (``event == "fault"``, with its ``cause`` and the
   ``state`` the robot was in);
2. the failure is published on ``model.lifecycle`` (:mod:`abm.lifecycle`): the robot leaves
   the air (physics), the comm network (messages to or from it in flight are dropped, not
   delivered) and its energy ledger is closed (it draws nothing more); then its state becomes
   ``failed`` (counted like any state, so the counts stay conserved);
3. its SimPy process is interrupted (``Process.interrupt``): the events it waited on no longer
   resume it, and :class:`~abm.robot.Robot` refuses any later change of its state or mode;
4. the model's hook ``on_robot_failed(robot)`` runs, for the model's own structures and repair.

Link faults act on :class:`~abm.comms.CommNetwork`: an outage takes one link down for a while
(the pair cannot link again until it ends); a loss burst drops each transmission with some
probability while it lasts. Sensor faults make a robot's readings stuck or noisy where the
model reads its sensors through :meth:`FaultInjector.sensed`.

All fault randomness comes from one generator spawned from ``model.rng``
(``Generator.spawn``, which does not advance the model's own stream): until the first fault
changes what happens, a run with faults is the same run as without them.
"""

from collections import defaultdict
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from abm.clock import call_later
from abm.errors import ConfigError
from abm.params import FAULT_PARAMS
from abm.robot import Robot

if TYPE_CHECKING:
    from abm.model import SwarmModel

__all__ = ["FAILED", "FAULT_KINDS", "Failure", "FaultInjector"]

#: The state of a failed robot (added to a model's states when its robots can fail).
FAILED = "failed"

#: The kinds of fault a model can declare it handles (``SwarmModel.FAULTS``).
FAULT_KINDS = frozenset(FAULT_PARAMS)


@dataclass(frozen=True)
class Failure:
    """Why and when a robot failed.

    Attributes:
        time: simulated time of the failure (s).
        cause: "hazard", "scheduled", "battery" or the cause a model gave.
        state: the state the robot was in when it failed.

    """

    time: float
    cause: str
    state: str


class FaultInjector:
    """Injects the faults a model's params ask for, and fails robots on anyone's request.

    Args:
        model: the model; its params carry the fault keywords, ``model.FAULTS`` the kinds of
            fault it handles.

    Raises:
        ConfigError: ``fault_states`` naming a state the model does not have.

    """

    def __init__(self, model: "SwarmModel") -> None:
        self.model = model
        self.env = model.env
        self.kinds = model.params.fault_kinds
        robot, link, sensor = (_keywords(model.params, kind) for kind in FAULT_PARAMS)
        _check_states(model, robot)
        self.failures: dict[int, Failure] = {}
        #: Scheduled faults (``fault_times``) that found no robot to fail.
        self.skipped = 0
        self.rng: np.random.Generator | None = model.rng.spawn(1)[0] if self.kinds else None
        self.rate = robot.fault_rate
        self.shape = robot.fault_shape
        self.states = frozenset(robot.fault_states)
        self._sensor = sensor
        self._exempt: set[int] = set()
        self._life: dict[int, float] = {}  # drawn lifetime (s of exposure)
        self._exposure: dict[int, float] = defaultdict(float)  # time spent in fault_states
        self._since: dict[int, float] = {}  # when the current exposure began
        self._generation: dict[int, int] = defaultdict(int)  # voids stale failure events
        self._sensor_broken: dict[int, float] = {}  # robot -> time its sensors broke
        self._stuck: dict[tuple[int, str], np.ndarray] = {}
        if self.kinds & {"robot", "sensor"}:
            # only a model whose robots can fail or lose their sensors needs to follow them
            model.lifecycle.subscribe("state", self.state_changed)
            model.lifecycle.subscribe("removed", self.robot_removed)
        for t in robot.fault_times:
            call_later(self.env, t, lambda _value: self._scheduled_failure())
        if link.link_outage_rate > 0:
            self.env.process(self._link_outages(link.link_outage_rate, link.link_outage_duration))
        if link.loss_burst_rate > 0:
            self.env.process(
                self._loss_bursts(
                    link.loss_burst_rate, link.loss_burst_duration, link.loss_burst_loss
                )
            )

    # ------------------------------------------------------------------ robots
    @property
    def failed(self) -> list[int]:
        """Ids of the robots that failed, in the order they failed."""
        return list(self.failures)

    def exempt(self, robot: Robot) -> None:
        """Never fail this robot at random or by schedule (e.g. a powered base station); the
        model may still fail it with :meth:`fail`.
        """
        rid = robot.unique_id
        self._exempt.add(rid)
        self._generation[rid] += 1  # a failure already scheduled is void

    def state_changed(self, robot: Robot, old: str | None, new: str) -> None:
        """A robot entered state ``new`` (a lifecycle ``"state"`` event): its exposure to the
        hazard starts or stops with the states it may fail in.
        """
        rid = robot.unique_id
        if rid in self._exempt or rid in self.failures:
            return
        if old is None:
            if "sensor" in self.kinds:
                self._schedule_sensor_fault(robot)
        if self.rate <= 0:
            return
        if rid not in self._life:
            self._life[rid] = float(self.rng.weibull(self.shape)) / self.rate
        elif not self.states:
            return  # exposed in every state: the failure scheduled at birth stands
        if old is not None and rid in self._since:
            self._exposure[rid] += self.env.now - self._since.pop(rid)
        self._generation[rid] += 1
        if not self.states or new in self.states:
            self._since[rid] = self.env.now
            generation = self._generation[rid]
            left = max(0.0, self._life[rid] - self._exposure[rid])
            call_later(self.env, left, lambda _value: self._hazard_failure(robot, generation))

    def robot_removed(self, robot: Robot) -> None:
        """A robot left the model (a lifecycle ``"removed"`` event): nothing more is injected
        into it.
        """
        rid = robot.unique_id
        self._generation[rid] += 1
        self._sensor_broken.pop(rid, None)

    def _may_fail(self, robot: Robot) -> bool:
        """The robot is still in the model, has not failed and is not exempt."""
        return (
            robot.failure is None
            and robot.unique_id not in self._exempt
            and robot in self.model.agents
        )

    def _hazard_failure(self, robot: Robot, generation: int) -> None:
        if self._generation[robot.unique_id] == generation and self._may_fail(robot):
            self.fail(robot, "hazard")

    def _scheduled_failure(self) -> None:
        eligible = [
            r
            for r in self.model.agents
            if isinstance(r, Robot)
            and self._may_fail(r)
            and (not self.states or r.state in self.states)
        ]
        if not eligible:
            self.skipped += 1
            self.model.recorder.log("fault_skipped", cause="scheduled")
            return
        self.fail(eligible[int(self.rng.integers(len(eligible)))], "scheduled")

    def fail(self, robot: Robot, cause: str) -> bool:
        """Fail ``robot`` now (see the module's docstring for what that does).

        Args:
            robot: the robot.
            cause: why, for the event log ("hazard", "scheduled", "battery", ...).

        Returns:
            False when the robot had already failed (nothing is done twice), else True.

        """
        model = self.model
        rid = robot.unique_id
        if robot.failure is not None:
            return False
        if FAILED not in model.STATES:
            raise ConfigError(
                f"{type(model).__name__} cannot fail robot {rid}: its states {model.STATES} "
                f"lack {FAILED!r} (declare FAULTS, or pass failures=True to SwarmModel)"
            )
        failure = Failure(float(self.env.now), cause, robot.state)
        self.failures[rid] = failure
        self._generation[rid] += 1
        self._sensor_broken.pop(rid, None)
        model.recorder.log("fault", rid, cause=cause, state=robot.state)
        model.lifecycle.publish("failed", robot)
        robot.set_state(FAILED)
        robot.failure = failure  # from here on the robot refuses state and mode changes
        process = robot.process
        if process is not None and process.is_alive:
            if process is self.env.active_process:
                # A process cannot interrupt itself: stop it as soon as it yields.
                call_later(self.env, 0, lambda _value: _interrupt(process, cause))
            else:
                process.interrupt(cause)
        model.on_robot_failed(robot)
        return True

    # ------------------------------------------------------------------ links
    def _link_outages(self, rate: float, duration: float):
        """Outages arrive as a Poisson process over the whole network, one link each."""
        comms = self.model.comms
        while True:
            yield self.env.timeout(float(self.rng.exponential(1.0 / rate)))
            edges = list(comms.graph.edges)
            if not edges:
                continue
            a, b = edges[int(self.rng.integers(len(edges)))]
            self.model.recorder.log("link_down", a, other=b, duration=duration)
            comms.block(a, b)
            self.model.on_link_fault(a, b, up=False)
            call_later(self.env, duration, lambda _value, a=a, b=b: self._restore(a, b))

    def _restore(self, a, b) -> None:
        comms = self.model.comms
        if comms.unblock(a, b):
            self.model.recorder.log("link_up", a, other=b)
            self.model.on_link_fault(a, b, up=True)

    def _loss_bursts(self, rate: float, duration: float, loss: float):
        """Bursts arrive as a Poisson process; one lasts ``duration`` and drops messages."""
        comms = self.model.comms
        while True:
            yield self.env.timeout(float(self.rng.exponential(1.0 / rate)))
            self.model.recorder.log("loss_burst", loss=loss, duration=duration)
            comms.start_burst(loss, self.rng)
            yield self.env.timeout(duration)
            comms.end_burst()
            self.model.recorder.log("loss_burst_end")

    # ------------------------------------------------------------------ sensors
    def _schedule_sensor_fault(self, robot: Robot) -> None:
        """Draw when this robot's sensors break (exponential, rate ``sensor_fault_rate``)."""
        life = float(self.rng.exponential(1.0 / self._sensor.sensor_fault_rate))
        call_later(self.env, life, self._break_sensor, robot)

    def _break_sensor(self, robot: Robot) -> None:
        if not self._may_fail(robot):
            return  # it failed, left the model or was exempted meanwhile
        rid = robot.unique_id
        self._sensor_broken[rid] = self.env.now
        self.model.recorder.log("sensor_fault", rid, sensor=self._sensor.sensor_fault_kind)

    def sensor_broken(self, robot_id: int) -> bool:
        """True once this robot's sensors are faulty."""
        return robot_id in self._sensor_broken

    def sensed(self, channel: str, robot_ids: Sequence[int], readings: np.ndarray) -> np.ndarray:
        """Readings as the robots' possibly faulty sensors report them.

        A model that declares "sensor" faults passes every reading through here. A robot
        whose sensors broke reports, on each ``channel`` (a name for one sensor: "walls",
        "rays", ...), the first reading it took after the fault for ever ("stuck"), or the
        reading plus Gaussian noise of sd ``sensor_fault_noise`` ("noisy").

        Args:
            channel: which sensor.
            robot_ids: the robot of each row of ``readings``.
            readings: one row per robot (any trailing shape).

        """
        if not self._sensor_broken:
            return readings
        out = np.array(readings, dtype=float, copy=True)
        p = self._sensor
        for row, rid in enumerate(np.asarray(robot_ids).tolist()):
            if rid not in self._sensor_broken:
                continue
            if p.sensor_fault_kind == "stuck":
                stuck = self._stuck.setdefault((rid, channel), out[row].copy())
                if stuck.shape == out[row].shape:
                    out[row] = stuck
            else:
                out[row] = out[row] + self.rng.normal(0.0, p.sensor_fault_noise, out[row].shape)
        return out


def _interrupt(process, cause: str) -> None:
    if process.is_alive:
        process.interrupt(cause)


def _keywords(params, kind: str):
    """The params as keywords of ``kind``; the defaults (no fault) for a kind the model does
    not declare, whose keywords it does not have.
    """
    mixin = FAULT_PARAMS[kind]
    return params if isinstance(params, mixin) else mixin()


def _check_states(model: "SwarmModel", robot) -> None:
    """Raise ConfigError for ``fault_states`` naming a state the model does not have."""
    unknown = sorted(set(robot.fault_states) - set(model.STATES))
    if unknown:
        raise ConfigError(
            f"fault_states names {', '.join(map(repr, unknown))}, not states of "
            f"{type(model).__name__}; its states are {', '.join(map(repr, model.STATES))}"
        )
