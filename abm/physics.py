"""The single motion process: every flying robot advanced per tick in one compiled loop.

One SimPy process owns all continuous motion. Each tick of ``dt`` seconds it asks the model's
controller for every flyer's desired velocity (and which flyers have finished their flight),
applies point-mass flight dynamics with drag (below) to all flyers at once, resolves
wall and robot-robot contacts, writes the positions into the Mesa space, and turns threshold
crossings (a flight finished) back into SimPy events. While nothing flies it sleeps, so
simulated time jumps straight to the next event.

Dynamics per flyer (point mass m): F = F_c + F_d, with the flight controller's force
F_c = m (v_desired - v) / tau (magnitude capped at ``max_force``) and quadratic drag
F_d = -1/2 rho |v|^2 A C_d v_hat; the body is jostled by Gaussian noise of std ``body_noise``
per tick and the speed is capped at ``max_speed``.

Walls: a robot's body is an axis-aligned square of half-width ``body_radius``; moves are applied
one axis at a time and each axis move is shorter than a grid pixel, so a body can never pass
through a wall: it is stopped flush against it. A new contact counts one wall collision.
Robots whose centres come closer than two body radii collide elastically; each new contact
counts two collisions (one for each robot). The per-flyer work is
compiled (:func:`abm.gridkernels.flight_rows`): with tens of flyers, numpy's per-call overhead,
not arithmetic, would set the speed. Up to :data:`DIRECT_PAIRS` flyers a whole tick (flight,
walls, contacts) is one compiled call that returns no array unless a contact changed.
"""

import math
import os
from collections.abc import Callable, Iterable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import TYPE_CHECKING, Protocol

import numpy as np
import simpy
from numba import njit

from abm import gridkernels
from abm.arena import Arena
from abm.checks import check_control, check_controller
from abm.errors import ConfigError, check_range
from abm.neighbours import new_pairs, pairs_within, same_keys

if TYPE_CHECKING:  # annotations only: the parts do not need Mesa to run
    from mesa.experimental.continuous_space import ContinuousSpaceAgent

__all__ = ["Physics", "Controller", "FlightParams"]

#: Mask of the low 32 bits (the higher robot id) of a contact key ``low_id << 32 | high_id``.
_LOW = (1 << 32) - 1
#: Flyers per thread of the flight step: a tick of fewer than twice this many runs in one call
#: (a thread hand-off costs about as much as stepping a few thousand flyers).
ROWS_PER_THREAD = 20_000
#: Contact candidates are the pairs within two body radii plus a skin this many ticks of the
#: largest move wide; they are searched again only once some flyer has moved half the skin.
CONTACT_SKIN_TICKS = 10
#: Up to this many flyers a tick is one compiled call (:func:`_tick_direct`) that measures every
#: pair directly (a few hundred distances at most) instead of keeping contact candidates: with
#: a handful of flyers the Python and numpy calls around the kernels, not the kernels, cost.
DIRECT_PAIRS = 32
_CPUS = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1
_pool: tuple[int, ThreadPoolExecutor] | None = None


def row_chunks(n: int) -> list[tuple[int, int]]:
    """Row ranges ``[first, last)`` that split ``n`` flyers over the threads worth using."""
    parts = max(1, min(_CPUS, n // ROWS_PER_THREAD))
    bounds = [n * k // parts for k in range(parts + 1)]
    return list(zip(bounds[:-1], bounds[1:], strict=True))


def _thread_pool() -> ThreadPoolExecutor:
    """The process's worker threads for the flight step (new ones in a forked child)."""
    global _pool
    if _pool is None or _pool[0] != os.getpid():
        _pool = (os.getpid(), ThreadPoolExecutor(_CPUS, thread_name_prefix="abm-physics"))
    return _pool[1]


class Controller(Protocol):
    """What the physics asks of a model every tick."""

    def control(self, physics: "Physics") -> tuple[np.ndarray, np.ndarray]:
        """Return a tuple of the desired velocities, a float array ``(n, 2)`` of finite
        values (m/s), and a bool array ``(n,)`` of the flyers whose flight ends now, both in
        the rows of ``physics.ids``; checked every tick (:func:`abm.checks.check_control`).
        """
        ...


@dataclass(frozen=True)
class FlightParams:
    """Flight-dynamics constants (SI units); the defaults are a generic small multirotor, not
    any particular robot (models pass their own).

    Attributes:
        mass: m (kg).
        max_speed: speed cap (m/s).
        max_force: cap on the control force (N).
        tau: flight-controller time constant (s).
        rho: air density (kg/m^3).
        area: frontal reference area A (m^2).
        drag_coefficient: C_d.
        body_noise: std of the Gaussian body displacement per tick (m).
        body_radius: half-width of the body for contacts (m).

    """

    mass: float = 0.5
    max_speed: float = 1.0
    max_force: float = 2.0
    tau: float = 0.5
    rho: float = 1.2
    area: float = 0.03
    drag_coefficient: float = 1.0
    body_noise: float = 0.0
    body_radius: float = 0.2

    def __post_init__(self) -> None:
        for name in ("mass", "max_speed", "max_force", "tau", "body_radius"):
            check_range(name, getattr(self, name), 0.0, low_open=True)
        for name in ("rho", "area", "drag_coefficient", "body_noise"):
            check_range(name, getattr(self, name), 0.0)


class Physics:
    """Advances all flying robots together.

    Args:
        env: the clock.
        arena: walls.
        rng: the model's generator (body noise).
        controller: the model's vectorised flight controller.
        positions_out: called with (robot ids, positions) after each tick so the Mesa space
            mirrors the flyers.
        params: flight dynamics.
        dt: tick length (s).
        on_collision: called as ``on_collision(kind, robot_a, robot_b)`` for each new contact.
        owner: the model's class name, which errors about its controller name.

    Raises:
        HookError: (from :meth:`fly_many` and :meth:`tick`) no controller when a robot takes
            off, or a controller output that is not of the documented shape, dtype and range.

    """

    def __init__(
        self,
        env: simpy.Environment,
        arena: Arena,
        rng: np.random.Generator,
        controller: Controller | None = None,
        positions_out: Callable[[np.ndarray, np.ndarray], None] | None = None,
        params: FlightParams | None = None,
        dt: float = 0.1,
        on_collision: Callable[[str, int, int | None], None] | None = None,
        owner: str = "",
    ) -> None:
        check_range("dt", dt, 0.0, low_open=True)
        self.params = params or FlightParams()
        step = self.params.max_speed * dt + 4 * self.params.body_noise
        room = arena.resolution - 2 * self.params.body_radius
        if step >= room:
            raise ConfigError(
                f"dt={dt} s is too long for max_speed={self.params.max_speed} m/s with "
                f"body_noise={self.params.body_noise} m and body_radius="
                f"{self.params.body_radius} m on a {arena.resolution} m grid: a tick may move "
                f"max_speed * dt + 4 body_noise = {step:.3f} m, must stay below "
                f"resolution - 2 body_radius = {room:.3f} m"
            )
        if 2 * self.params.body_radius >= arena.resolution:
            raise ConfigError(
                f"body_radius={self.params.body_radius} m does not fit a {arena.resolution} m grid"
            )
        self.env = env
        self.arena = arena
        self.rng = rng
        self.controller = controller
        self.positions_out = positions_out
        self.dt = float(dt)
        p = self.params
        #: The arguments of :func:`gridkernels.flight_rows` that stay fixed (the parameters are
        #: frozen), from the body noise scale to the body radius.
        self._flight_constants = (
            p.body_noise,
            arena.padded,
            arena.resolution,
            p.mass,
            p.tau,
            p.max_force,
            0.5 * p.rho * p.area * p.drag_coefficient,
            p.max_speed,
            self.dt,
            p.body_radius,
        )
        self.on_collision = on_collision
        self.owner = owner
        #: The flyers' robot ids, one row each; a new array whenever flyers join or leave,
        #: never changed in place (a listener may key what it caches on the array).
        self.ids = np.empty(0, dtype=np.int64)
        self.pos = np.empty((0, 2))
        self.vel = np.empty((0, 2))
        self._arrivals: list[simpy.Event] = []
        self._wall_contact = np.empty(0, dtype=bool)
        #: Robot pairs touching after the last tick, as sorted keys ``low_id << 32 | high_id``.
        self._pairs_in_contact = np.empty(0, dtype=np.int64)
        #: Reused buffer of the body-noise draws (rows >= the flyers).
        self._noise = np.zeros((0, 2))
        #: Contact candidates (pairs within two radii plus the skin) and where the flyers were
        #: when they were searched; None after flyers joined or left (rows changed).
        self._candidates: tuple[np.ndarray, np.ndarray] | None = None
        self._searched_at = np.empty((0, 2))
        self._skin = CONTACT_SKIN_TICKS * step
        self.wall_collisions = 0
        self.robot_collisions = 0
        #: Path length flown by all flyers so far (m), walls' stops included, noise included.
        self.distance = 0.0
        self.ticks = 0
        self.flyer_steps = 0
        self.trace: list[tuple[float, np.ndarray, np.ndarray]] | None = None
        #: Per-flyer arrays a controller keeps between ticks (filters, memories); rows follow
        #: the flyers as they join and leave. Register with :meth:`add_flyer_state`.
        self.flyer_state: dict[str, np.ndarray] = {}
        self._wake: simpy.Event = env.event()
        self.process = env.process(self._run())

    # ------------------------------------------------------------------ flyers
    def add_flyer_state(self, name: str, width: int) -> np.ndarray:
        """Register a per-flyer float array of ``width`` columns (zeros for a new flyer)."""
        self.flyer_state[name] = np.zeros((self.n_flying, width))
        return self.flyer_state[name]

    @property
    def n_flying(self) -> int:
        """Number of robots currently flying."""
        return len(self.ids)

    def fly(self, robot_id: int, position: np.ndarray) -> simpy.Event:
        """Start moving a robot; the returned event fires when its flight is done (the
        controller's done mask, or :meth:`finish`).
        """
        return self.fly_many([robot_id], np.asarray(position, dtype=float)[None, :])[0]

    def fly_many(self, robot_ids: Iterable[int], positions: np.ndarray) -> list[simpy.Event]:
        """Start moving several robots at once (a swarm launched together): one event each,
        as :meth:`fly` gives, in the order given.
        """
        check_controller(self.controller, self.owner)
        ids = np.asarray(list(robot_ids), dtype=np.int64)
        positions = np.asarray(positions, dtype=float).reshape(-1, 2)
        if len(ids) != len(positions):
            raise ValueError(f"{len(ids)} robot ids but {len(positions)} positions")
        flying = ids[_member_of(ids, self.ids)]
        if len(flying):
            raise ValueError(f"robot {int(flying[0])} is already flying")
        if _distinct(ids) != len(ids):
            raise ValueError(f"robot ids {ids.tolist()} repeat")
        arrived = [self.env.event() for _ in range(len(ids))]
        k = len(ids)
        self.ids = np.concatenate([self.ids, ids])
        self.pos = np.concatenate([self.pos, positions])
        self.vel = np.concatenate([self.vel, np.zeros((k, 2))])
        self._wall_contact = np.concatenate([self._wall_contact, np.zeros(k, dtype=bool)])
        for name, array in self.flyer_state.items():
            self.flyer_state[name] = np.concatenate([array, np.zeros((k, array.shape[1]))])
        self._arrivals.extend(arrived)
        self._candidates = None
        if k and not self._wake.triggered:
            self._wake.succeed()
        return arrived

    def stop(self, robot_id: int) -> np.ndarray:
        """Take a robot out of the air without ending its flight event (a robot that failed);
        returns its last position.
        """
        return self._remove(self._rows([robot_id]))[0]

    def robot_left(self, robot: "ContinuousSpaceAgent") -> None:
        """A robot failed or was removed (a lifecycle event): out of the air, where it was."""
        if robot.unique_id in self.ids:
            robot.position = self.stop(robot.unique_id)

    def finish(self, robot_ids: Iterable[int]) -> np.ndarray:
        """End these robots' flights now (they landed, attached, ...): each one's event from
        :meth:`fly` fires. Returns their last positions ``(k, 2)``.
        """
        return self._land(self._rows(robot_ids))

    def _land(self, gone: np.ndarray) -> np.ndarray:
        """:meth:`finish` for the flyers of the bool row mask ``gone`` (a tick's done mask is
        one already: no ids to look up).
        """
        finished = [a for a, g in zip(self._arrivals, gone.tolist(), strict=True) if g]
        last = self._remove(gone)
        for event in finished:
            event.succeed()
        return last

    def _rows(self, robot_ids: Iterable[int]) -> np.ndarray:
        """The bool row mask of the flyers ``robot_ids``; ValueError if one is not flying."""
        wanted = np.asarray(list(robot_ids), dtype=np.int64)
        rows = _member_of(self.ids, wanted)
        if np.count_nonzero(rows) != _distinct(wanted):
            missing = sorted(set(wanted.tolist()) - set(self.ids.tolist()))
            raise ValueError(f"robots {missing} are not flying")
        return rows

    def _remove(self, gone: np.ndarray) -> np.ndarray:
        """Take the flyers of the bool row mask ``gone`` out of the air; their last positions."""
        keep = ~gone
        last = self.pos[gone]
        pairs = self._pairs_in_contact
        if len(pairs):
            ids = self.ids[gone]
            self._pairs_in_contact = pairs[
                ~(_member_of(pairs >> 32, ids) | _member_of(pairs & _LOW, ids))
            ]
        self.ids = self.ids[keep]
        self.pos = self.pos[keep]
        self.vel = self.vel[keep]
        self._wall_contact = self._wall_contact[keep]
        for name, array in self.flyer_state.items():
            self.flyer_state[name] = array[keep]
        self._arrivals = [a for a, k in zip(self._arrivals, keep.tolist(), strict=True) if k]
        self._candidates = None
        return last

    # ------------------------------------------------------------------ the process
    def _run(self):
        while True:
            if self.n_flying == 0:
                self._wake = self.env.event()
                yield self._wake
            self.tick()
            yield self.env.timeout(self.dt)

    def tick(self) -> None:
        """Advance every flyer by one ``dt``, as the controller's checked output asks."""
        self.ticks += 1
        n = len(self.ids)
        self.flyer_steps += n
        controller = self.controller
        if controller is None:
            check_controller(controller, self.owner)
        desired, done = check_control(controller.control(self), self.ids, self.owner, controller)
        desired = np.ascontiguousarray(desired, dtype=float)
        noise = self._body_noise(n)
        if n <= DIRECT_PAIRS:
            distance, finished, contacts = _tick_direct(
                self.pos, self.vel, desired, noise, *self._flight_constants,
                self._wall_contact, self.ids, self._pairs_in_contact, done,
            )  # fmt: skip
            self.distance += distance
        else:
            contact = np.empty(n, dtype=bool)
            self._fly_one_tick(desired, noise, contact)
            contacts = _after_flight(
                self.pos, self.vel, contact, self._wall_contact, *self._contact_candidates(),
                2 * self.params.body_radius, self.ids, self._pairs_in_contact,
            )  # fmt: skip
            finished = done.any()
        if contacts is not None:
            self._contacts_changed(*contacts)
        if self.trace is not None:
            self.trace.append((self.env.now, self.ids.copy(), self.pos.copy()))
        if self.positions_out is not None:
            self.positions_out(self.ids, self.pos)
        if finished:
            self._land(done)

    def _body_noise(self, n: int) -> np.ndarray:
        """A reused buffer of at least ``n`` rows whose first ``n`` hold the tick's standard
        normal body-noise draws (the flight kernel reads only those).

        Drawn as ``rng.standard_normal`` and scaled in the flight kernel: the same numbers as
        ``rng.normal(0, body_noise)``, without a new array per tick (zeros, and no draw and no
        slice, for a body without noise).
        """
        if len(self._noise) < n:
            self._noise = np.zeros((max(n, 2 * len(self._noise)), 2))
        if self.params.body_noise > 0:
            self.rng.standard_normal(out=self._noise[:n])
        return self._noise

    def _fly_one_tick(self, desired: np.ndarray, noise: np.ndarray, contact: np.ndarray) -> None:
        """Flight dynamics and wall contacts for every flyer (:func:`gridkernels.flight_rows`),
        with ``contact`` set to which bodies touch a wall and the path length flown added to
        :attr:`distance`.

        From twice :data:`ROWS_PER_THREAD` flyers the rows are split over threads (rows are
        independent, so the result is the same as one pass).
        """
        n = self.n_flying
        args = (self.pos, self.vel, desired, noise, *self._flight_constants, contact)
        if n < 2 * ROWS_PER_THREAD:  # one range (row_chunks), without its cost per tick
            self.distance += gridkernels.flight_rows(*args, 0, n)
            return
        (first, last), *others = row_chunks(n)
        pool = _thread_pool() if others else None
        elsewhere = [pool.submit(gridkernels.flight_rows, *args, *rows) for rows in others]
        self.distance += gridkernels.flight_rows(*args, first, last)
        for job in elsewhere:
            self.distance += job.result()

    def _contacts_changed(
        self, new_walls: np.ndarray, now: np.ndarray, new_pairs: np.ndarray
    ) -> None:
        """Keep the robot contacts ``now`` and count and report this tick's new contacts:
        walls (rows of the bodies that touch one now and did not last tick), then robot pairs
        (sorted id keys ``low_id << 32 | high_id``, two collisions each).
        """
        self._pairs_in_contact = now
        self.wall_collisions += len(new_walls)
        self.robot_collisions += 2 * len(new_pairs)
        if self.on_collision is not None:
            for rid in self.ids[new_walls].tolist():
                self.on_collision("wall", rid, None)
            for key in new_pairs.tolist():
                self.on_collision("robot", key >> 32, key & _LOW)

    def _contact_candidates(self) -> tuple[np.ndarray, np.ndarray]:
        """Row pairs ``i < j`` that may touch, in lexicographic order: a Verlet list that holds
        every pair :func:`abm.neighbours.pairs_within` ``(pos, 2 r)`` finds.

        The cell-list search runs with a skin (``CONTACT_SKIN_TICKS`` ticks of the largest
        move) and is reused while no flyer has moved more than half the skin since: two bodies
        touching now were then within two radii plus the skin. Each tick only measures the
        candidates, so the search (the costly part at 100,000 flyers) runs every few ticks.
        """
        if self._candidates is None or _moved_beyond(
            self.pos, self._searched_at, 0.5 * self._skin * (1.0 - 1e-9)
        ):
            self._candidates = pairs_within(self.pos, 2 * self.params.body_radius + self._skin)
            self._searched_at = self.pos.copy()
        return self._candidates


@njit(cache=True)
def _tick_direct(
    pos, vel, desired, noise, noise_scale, padded, res, mass, tau, max_force, drag, max_speed,
    dt, radius, wall_contact, ids, before, done,
):  # fmt: skip
    """A whole tick of a few flyers in one call: the flight step (:func:`gridkernels.flight_rows`)
    then :func:`_after_flight` on every row pair ``i < j``, in lexicographic order (the
    candidates :func:`abm.neighbours.pairs_within` would give, and more).

    Returns the path length flown, whether ``done`` marks any flyer (a flight ends this tick)
    and what :func:`_after_flight` returns.
    """
    n = pos.shape[0]
    contact = np.empty(n, dtype=np.bool_)
    distance = gridkernels.flight_rows(
        pos, vel, desired, noise, noise_scale, padded, res, mass, tau, max_force, drag,
        max_speed, dt, radius, contact, 0, n,
    )  # fmt: skip
    m = n * (n - 1) // 2
    first = np.empty(m, dtype=np.int64)
    second = np.empty(m, dtype=np.int64)
    k = 0
    for i in range(n):
        for j in range(i + 1, n):
            first[k] = i
            second[k] = j
            k += 1
    contacts = _after_flight(
        pos, vel, contact, wall_contact, first, second, 2.0 * radius, ids, before
    )
    finished = False
    for k in range(n):
        if done[k]:
            finished = True
            break
    return distance, finished, contacts


@njit(cache=True)
def _after_flight(
    pos: np.ndarray,
    vel: np.ndarray,
    contact: np.ndarray,
    wall_contact: np.ndarray,
    first: np.ndarray,
    second: np.ndarray,
    reach: float,
    ids: np.ndarray,
    before: np.ndarray,
) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """The contacts after a flight step: walls, then robots among the candidate row pairs.

    A body that touches a wall now (``contact``) and did not last tick (``wall_contact``,
    updated in place) is a new wall collision. The candidate pairs closer than ``reach`` touch
    and are bounced (:func:`_bounce`, in place). Returns None when nothing changed (no new
    wall contact, the robot contacts are ``before``, last tick's): the usual tick, whose
    return then costs no arrays. Else the rows of the new wall contacts, the robot contacts as
    sorted keys ``low_id << 32 | high_id``, and the keys not in ``before`` (sorted): the new
    contacts, found by a binary search each.
    """
    new_walls = _new_contacts(contact, wall_contact)
    first, second = _closer_than(pos, first, second, reach)
    _bounce(pos, vel, first, second)
    now = np.empty(first.shape[0], dtype=np.int64)
    for k in range(first.shape[0]):
        a, b = ids[first[k]], ids[second[k]]
        now[k] = (min(a, b) << 32) | max(a, b)
    now.sort()  # the pairs are unique, so are the keys
    if new_walls.size == 0 and same_keys(now, before):
        return None
    return new_walls, now, new_pairs(now, before)


@njit(cache=True)
def _new_contacts(contact: np.ndarray, wall_contact: np.ndarray) -> np.ndarray:
    """The rows where ``contact`` is set and ``wall_contact`` (last tick's) is not, and
    ``wall_contact`` set to ``contact``: ``np.flatnonzero(contact & ~wall_contact)`` without
    the temporary arrays.
    """
    found = 0
    for k in range(contact.shape[0]):
        found += contact[k] and not wall_contact[k]
    rows = np.empty(found, dtype=np.int64)
    found = 0
    for k in range(contact.shape[0]):
        if contact[k] and not wall_contact[k]:
            rows[found] = k
            found += 1
        wall_contact[k] = contact[k]
    return rows


@njit(cache=True)
def _moved_beyond(pos: np.ndarray, before: np.ndarray, limit: float) -> bool:
    """Tell whether some row of ``pos`` lies more than ``limit`` from its row in ``before``."""
    limit2 = limit * limit
    for k in range(pos.shape[0]):
        dx = pos[k, 0] - before[k, 0]
        dy = pos[k, 1] - before[k, 1]
        if dx * dx + dy * dy > limit2:
            return True
    return False


@njit(cache=True)
def _closer_than(
    pos: np.ndarray, first: np.ndarray, second: np.ndarray, reach: float
) -> tuple[np.ndarray, np.ndarray]:
    """The candidate pairs whose rows are closer than ``reach`` now (order kept), measured as
    :func:`abm.neighbours.pairs_within` measures them.
    """
    r2 = reach * reach
    keep = np.zeros(first.shape[0], dtype=np.bool_)
    for k in range(first.shape[0]):
        dx = pos[second[k], 0] - pos[first[k], 0]
        dy = pos[second[k], 1] - pos[first[k], 1]
        keep[k] = dx * dx + dy * dy < r2
    return first[keep], second[keep]


@njit(cache=True)
def _bounce(pos: np.ndarray, vel: np.ndarray, first: np.ndarray, second: np.ndarray) -> None:
    """Elastic impulses (equal masses) for touching pairs that approach, applied in place.

    All impulses come from the velocities before this tick's contacts, as one simultaneous
    exchange; a robot touching two others gets both.
    """
    m = first.shape[0]
    impulse = np.zeros((m, 2))
    for k in range(m):
        i, j = first[k], second[k]
        nx = pos[i, 0] - pos[j, 0]
        ny = pos[i, 1] - pos[j, 1]
        dist = max(math.hypot(nx, ny), 1e-9)
        nx /= dist
        ny /= dist
        closing = (vel[i, 0] - vel[j, 0]) * nx + (vel[i, 1] - vel[j, 1]) * ny
        if closing < 0:
            impulse[k, 0] = closing * nx
            impulse[k, 1] = closing * ny
    for k in range(m):
        vel[first[k], 0] -= impulse[k, 0]
        vel[first[k], 1] -= impulse[k, 1]
    for k in range(m):
        vel[second[k], 0] += impulse[k, 0]
        vel[second[k], 1] += impulse[k, 1]


def _distinct(ids: np.ndarray) -> int:
    """How many distinct values ``ids`` holds (without ``np.unique``'s sort for one id)."""
    return len(ids) if len(ids) < 2 else len(np.unique(ids))


@njit(cache=True)
def _member_of(values: np.ndarray, pool: np.ndarray) -> np.ndarray:
    """``np.isin(values, pool)`` for integer arrays, compiled.

    A flight's start and end ask it four times, mostly of one id against the flyers, where
    ``np.isin`` costs about 17 us a call whatever the size. When either side is short the
    values are compared directly (O(values x pool)); two long ones go through a sorted copy
    of ``pool``.
    """
    out = np.zeros(values.shape[0], dtype=np.bool_)
    if min(values.shape[0], pool.shape[0]) <= 16 or values.shape[0] * pool.shape[0] <= 4096:
        for i in range(values.shape[0]):
            for j in range(pool.shape[0]):
                if values[i] == pool[j]:
                    out[i] = True
                    break
        return out
    ordered = np.sort(pool)
    for i in range(values.shape[0]):
        k = np.searchsorted(ordered, values[i])
        out[i] = k < ordered.shape[0] and ordered[k] == values[i]
    return out
