"""A vectorised controller that drives ground robots along polylines through the physics.

Each flying robot follows its own list of waypoints at a constant speed: every tick all flyers'
desired velocities point at their current waypoint (one numpy step), a flyer within one tick's
travel of an intermediate waypoint moves on to the next, and a flyer at its last waypoint lands
(its flight event fires). A flyer that makes no progress for ``stall_ticks`` ticks (a body
pressed against a wall it was not told about) lands where it is, and is counted as stalled.
With the physics' time constant equal to its tick, the robot moves at exactly the commanded
velocity, so a path of length L takes L / speed seconds (to within one tick).
"""

import math

import numpy as np
import simpy
from numba import njit

from abm.errors import ConfigError, check_range
from abm.physics import FlightParams, Physics

__all__ = ["PathFollower", "ground_robot"]


def ground_robot(speed: float, body_radius: float, dt: float) -> FlightParams:
    """Flight parameters of a wheeled robot that moves at exactly its commanded velocity."""
    return FlightParams(
        mass=1.0,
        max_speed=speed,
        max_force=1e6,
        tau=dt,
        rho=0.0,
        area=0.0,
        drag_coefficient=0.0,
        body_noise=0.0,
        body_radius=body_radius,
    )


class PathFollower:
    """The physics controller of robots that drive polylines.

    Args:
        physics: the model's physics (this object becomes its controller).
        speed: driving speed (m/s).
        stall_ticks: ticks without progress after which a flyer lands where it is.

    """

    def __init__(self, physics: Physics, speed: float, stall_ticks: int = 20) -> None:
        check_range("speed", speed, 0.0, low_open=True)
        self.physics = physics
        self.speed = float(speed)
        self.stall_ticks = int(stall_ticks)
        self.stalled = 0
        self._paths: dict[int, np.ndarray] = {}
        self._next: dict[int, int] = {}
        # per flyer: its waypoint (x, y), 1.0 if that is the last one, ticks without progress
        physics.add_flyer_state("path", 4)
        physics.controller = self

    def drive(self, robot_id: int, start: np.ndarray, waypoints: np.ndarray) -> simpy.Event:
        """Start driving ``robot_id`` from ``start`` through ``waypoints`` ``(k, 2)`` (m); the
        event fires on arrival at the last one.
        """
        waypoints = np.asarray(waypoints, dtype=float).reshape(-1, 2)
        if len(waypoints) == 0:
            raise ConfigError("waypoints must hold at least one point")
        self._paths[robot_id] = waypoints
        self._next[robot_id] = 0
        event = self.physics.fly(robot_id, start)
        row = len(self.physics.ids) - 1
        state = self.physics.flyer_state["path"]
        state[row, :2] = waypoints[0]
        state[row, 2] = float(len(waypoints) == 1)
        event.callbacks.append(lambda _ev: self._forget(robot_id))
        return event

    def _forget(self, robot_id: int) -> None:
        self._paths.pop(robot_id, None)
        self._next.pop(robot_id, None)

    def control(self, physics: Physics) -> tuple[np.ndarray, np.ndarray]:
        """Desired velocities toward each flyer's waypoint, and which flyers arrived.

        One compiled call (:func:`_follow`) in the usual tick; a flyer at a corner is moved on
        to its next waypoint here, between calls that look for the next one in later rows.
        """
        state = physics.flyer_state["path"]
        args = (physics.pos, physics.vel, state, self.speed, physics.dt, self.stall_ticks)
        step = self.speed * physics.dt
        desired, done, stalled, row = _follow(*args, step, 0)
        while row >= 0:  # only the flyers at a corner this tick, each once, in row order
            rid = int(physics.ids[row])
            k = self._next[rid] + 1
            self._next[rid] = k
            path = self._paths[rid]
            state[row, :2] = path[k]
            state[row, 2] = float(k == len(path) - 1)
            desired, done, stalled, row = _follow(*args, step, row + 1)
        self.stalled += stalled
        return desired, done


@njit(cache=True)
def _follow(pos, vel, state, speed, dt, stall_ticks, step, start):
    """One tick of the follower from row ``start`` on: the first row from there whose flyer is
    within ``step`` (one tick's travel) of an intermediate waypoint, with no velocities (None,
    None, 0); else -1 with :func:`_steer`'s desired velocities, done mask and stall count.
    ``state`` holds each flyer's waypoint (x, y), 1.0 if that is its last one, and its ticks
    without progress.

    The caller moves a row at a corner on and asks again from the next row, so each flyer
    moves on at most once per tick, and the steering sees every flyer's new waypoint.
    """
    for k in range(start, pos.shape[0]):
        if state[k, 2] == 0.0:
            if math.hypot(state[k, 0] - pos[k, 0], state[k, 1] - pos[k, 1]) <= step:
                return None, None, 0, k
    desired, done, stalled = _steer(pos, vel, state, speed, dt, stall_ticks)
    return desired, done, stalled, -1


@njit(cache=True)
def _steer(pos, vel, state, speed, dt, stall_ticks):
    """Desired velocity of every flyer (at most ``speed``, landing exactly on the last
    waypoint), and which flyers are done (arrived, or stalled ``stall_ticks`` ticks); the
    ticks without progress (``state[:, 3]``) counted in place.
    """
    n = pos.shape[0]
    desired = np.zeros((n, 2))
    done = np.zeros(n, dtype=np.bool_)
    stalled = 0
    for k in range(n):
        gx = state[k, 0] - pos[k, 0]
        gy = state[k, 1] - pos[k, 1]
        dist = math.hypot(gx, gy)
        arrived = state[k, 2] == 1.0 and dist < 1e-6
        v = min(speed, dist / dt)
        if dist > 1e-12:
            desired[k, 0] = gx * v / dist
            desired[k, 1] = gy * v / dist
        moving = math.hypot(vel[k, 0], vel[k, 1]) * dt > 1e-4
        state[k, 3] = 0.0 if (moving or arrived) else state[k, 3] + 1.0
        if state[k, 3] >= stall_ticks:
            stalled += 1
            done[k] = True
        if arrived:
            done[k] = True
    return desired, done, stalled
