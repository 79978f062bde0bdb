"""The explorer controller of Stirling et al. (2010), Sect. 3.4.1 and Fig. 4, for all flyers.

Every control step each explorer measures N, the vector to the beacon it follows (its nearest,
kept until another is ``guide_hysteresis`` nearer; relative positioning, noisy), reads that
beacon's desired direction D (length I_r), forms L = N + D, adds
the collision-avoidance vector C (away from walls sensed by the four distance sensors, magnitude
growing as 1/distance) and flies along T = L + C. When |T| <= eps at a spot where a beacon is
required, it ascends and attaches. All of this is one compiled loop over the flyers
(:func:`_steer`), with the sensor models of :mod:`abm.sensors` and the model's random generator
supplying every noise draw.
"""

import math
from collections.abc import Callable

import numpy as np
from numba import njit

from abm.arena import CARDINALS, Arena
from abm.gridkernels import cardinal_distances, nearest_visible_on, segment_crosses
from abm.neighbours import cell_grid
from abm.physics import Physics
from abm.sensors import measured_relative, noisy_reading
from models.beacon_explorer.beacon import BeaconNetwork
from models.beacon_explorer.params import BeaconExplorerParams

__all__ = ["ExplorerController"]


#: The algorithm's constants the compiled controller reads (see BeaconExplorerParams), as the
#: fields of a one-record numpy array: numba takes such an array in under 1 us, where a
#: NamedTuple of these 19 fields costs about 5 us to type on every call (measured on the
#: controller's arguments), a few per cent of a small swarm's tick.
_CONSTANTS = np.dtype(
    [
        ("comm_range", np.float64),
        ("sensor_range", np.float64),
        ("sensor_noise", np.float64),
        ("avoid_gain", np.float64),
        ("slow_radius", np.float64),
        ("attach_eps", np.float64),
        ("attach_speed", np.float64),
        ("interspace", np.float64),
        ("gain", np.float64),  # of the low-pass filter on T, per tick
        ("max_speed", np.float64),
        ("guide_hysteresis", np.float64),
        ("guide_commit", np.bool_),
        ("taken_hold", np.float64),  # inf: hold off
        ("lost_return", np.bool_),
        ("slide_after", np.float64),  # inf: never slide
        ("dt", np.float64),
        ("range_noise", np.float64),
        ("bearing_noise", np.float64),
        ("reference_range", np.float64),
    ]
)


class ExplorerController:
    """Vectorised explorer behaviour; the physics calls :meth:`control` every tick.

    Args:
        arena: walls.
        beacons: the beacon network whose signals explorers follow.
        rng: the model's generator (sensor noise).
        params: the algorithm's constants.
        physics: the physics process whose flyers this controls.
        stopped_to_attach: called as ``stopped_to_attach(robot_id, guide_id)`` for each flyer
            the controller stops to attach, with the beacon whose spot it reached.

    """

    def __init__(
        self,
        arena: Arena,
        beacons: BeaconNetwork,
        rng: np.random.Generator,
        params: BeaconExplorerParams,
        physics: Physics,
        stopped_to_attach: Callable[[int, int], None],
    ) -> None:
        self.arena = arena
        self.beacons = beacons
        self.rng = rng
        self.stopped_to_attach = stopped_to_attach
        self._version = -1
        self._signals = None
        self._corridor = np.zeros(0, dtype=bool)  # corridor beacon or not, in signals() order
        self._row_of = np.zeros(0, dtype=np.int64)  # each beacon's row by robot id
        self._placed: tuple | None = None  # the beacons' places and their cell grid
        # reused per-tick arrays (rows >= the flyers): the draws, the desired velocities and
        # the attach mask; a compiled call's new arrays cost more to hand back than to fill
        self._draws = np.zeros((0, 6))
        self._desired = np.zeros((0, 2))
        self._attach = np.zeros(0, dtype=bool)
        self._views = (self._draws, self._desired, self._attach)
        self._beacon_args: tuple | None = None
        physics.add_flyer_state("T", 2)
        physics.add_flyer_state("guide", 1)  # robot id of the beacon followed (0: none yet)
        # where the flyer last was in touch with a beacon (x, y) and whether it ever was (1/0)
        physics.add_flyer_state("contact", 3)
        # where it was pressed (x, y), for how long, slide time left, side (+1 left, -1 right)
        physics.add_flyer_state("slide", 5)
        # committed to its guide's empty spot last tick (1/0); holding a guide whose spot was
        # taken (1/0); the D it was committed to (x, y); time held with that D (s); see
        # ``taken_hold``
        physics.add_flyer_state("loyal", 5)
        constants = (
            params.comm_range,
            params.sensor_range,
            params.sensor_noise,
            params.avoid_gain,
            params.slow_radius,
            params.attach_eps,
            params.attach_speed,
            params.interspace,
            min(1.0, physics.dt / params.filter_time),
            params.max_speed,
            params.guide_hysteresis,
            params.guide_commit,
            math.inf if params.taken_hold is None else params.taken_hold,
            params.lost_return,
            math.inf if params.slide_after is None else params.slide_after,
            physics.dt,
            params.range_noise,
            params.bearing_noise,
            params.reference_range,
        )
        self._constants = np.array([constants], dtype=_CONSTANTS)

    def _current_signals(self):
        """The beacons' signals (ids, positions, D, to-empty) as the explorers read them."""
        self._beacon_arguments()
        return self._signals

    def _beacon_arguments(self) -> tuple | None:
        """What :func:`_steer` reads of the beacons, ``ids`` to ``corridor`` in its order (None
        while there is none), renewed whenever a signal explorers read changes (the network's
        version) and otherwise reused as one tuple: assembling it every tick cost a few us.
        """
        if self._version != self.beacons.version:
            self._signals = ids, beacon_pos, desired_vec, to_empty = self.beacons.signals()
            self._corridor = self.beacons.corridors()
            self._row_of = self.beacons.rows_by_id()
            self._version = self.beacons.version
            self._beacon_args = None
            if len(beacon_pos):
                placed, grid = self._beacons_placed(beacon_pos)
                vectors = np.ascontiguousarray(desired_vec)
                self._beacon_args = (ids, self._row_of, placed, *grid, vectors, to_empty,
                                     self._corridor)  # fmt: skip
        return self._beacon_args

    def _beacons_placed(self, beacon_pos: np.ndarray) -> tuple:
        """The beacons' positions (contiguous) and the cell grid :func:`nearest_visible_on`
        searches them with: rebuilt only when a beacon attaches or leaves (the network then
        hands out a new position array; the signals change far more often). Building the grid
        each tick cost more than the search itself with a few flyers.
        """
        if self._placed is None or self._placed[0] is not beacon_pos:
            pos = np.ascontiguousarray(beacon_pos)
            lo, width, dims, _which, start, order = cell_grid(pos, self._constants[0]["comm_range"])
            self._placed = (beacon_pos, pos, (lo, width, dims, start, order))
        return self._placed[1:]

    def _buffers(self, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The first ``n`` rows of the reused draw, desired-velocity and attach arrays
        (grown to twice the size when too short; the views kept while ``n`` stays). The
        physics reads the last two only within the tick they are returned for.
        """
        if len(self._views[0]) != n:
            if len(self._draws) < n:
                rows = max(n, 2 * len(self._draws))
                self._draws = np.zeros((rows, 6))
                self._desired = np.zeros((rows, 2))
                self._attach = np.zeros(rows, dtype=bool)
            self._views = (self._draws[:n], self._desired[:n], self._attach[:n])
        return self._views

    def control(self, physics: Physics) -> tuple[np.ndarray, np.ndarray]:
        """Desired velocities of all flyers and which of them attach now."""
        n = physics.n_flying
        beacons = self._beacon_arguments()
        if beacons is None:
            return np.zeros((n, 2)), np.zeros(n, dtype=bool)
        arena = self.arena
        draws, desired, attach = self._buffers(n)
        self.rng.standard_normal(out=draws)  # the same numbers as standard_normal((n, 6))
        attaching = _steer(
            arena.padded,
            arena.runs,
            arena.walls_sat,
            arena.resolution,
            physics.pos,
            physics.vel,
            physics.flyer_state["T"],
            physics.flyer_state["guide"],
            physics.flyer_state["contact"],
            physics.flyer_state["slide"],
            physics.flyer_state["loyal"],
            *beacons,
            draws,
            self._constants,
            desired,
            attach,
        )
        if attaching:
            for row in np.flatnonzero(attach):
                guide = int(physics.flyer_state["guide"][row, 0])
                self.stopped_to_attach(int(physics.ids[row]), guide)
        return desired, attach


@njit(cache=True)
def _steer(
    padded,
    runs,
    sat,
    res,
    pos,
    vel,
    T,  # noqa: N803 (the paper's symbol)
    guide,
    contact,
    slide,
    loyal,
    ids,
    row_of,
    beacon_pos,
    grid_lo,
    grid_width,
    grid_dims,
    grid_start,
    grid_order,
    desired_vec,
    to_empty,
    corridor,
    z,
    constants,
    desired,
    attach,
):
    """Fig. 4 for every flyer: T = L + C with L = N + D; attach when |T| <= eps.

    ``z`` holds six standard normal draws per flyer: two for the relative-positioning sensor,
    four for the distance sensors; ``constants`` is the one record of :data:`_CONSTANTS`.
    ``row_of`` gives each beacon's row by robot id (-1: not a beacon; ``BeaconNetwork.rows_by_id``)
    and ``grid_*`` is the beacons' cell grid (:meth:`ExplorerController._beacons_placed`).
    ``T`` (the low-pass filtered translation vector) and ``guide`` (the beacon each flyer
    follows) and ``contact`` (where it was last in touch) are updated in place. A flyer out of
    touch with every beacon flies back to that point (``lost_return``; else it hovers).
    Writes the desired velocities into ``desired`` ``(n, 2)`` and the attach mask into
    ``attach`` ``(n,)`` (every row: zero velocity and no attach where a flyer hovers) and
    returns how many flyers attach: handing back two new arrays cost more than the loop
    for a few flyers.
    """
    p = constants[0]
    n = pos.shape[0]
    attaching = 0
    nearest = nearest_visible_on(
        padded, sat, res, pos, beacon_pos, p.comm_range,
        grid_lo, grid_width, grid_dims, grid_start, grid_order,
    )  # fmt: skip
    walls = cardinal_distances(padded, runs, res, pos, p.sensor_range)
    for i in range(n):
        desired[i, 0] = 0.0
        desired[i, 1] = 0.0
        attach[i] = False
        lost = nearest[i] < 0  # out of touch with every beacon
        k = max(nearest[i], 0)
        if not lost:
            nearest_k = k
            k = _keep_guide(
                padded, sat, res, pos[i], guide[i, 0], row_of, beacon_pos, to_empty, k, p
            )
            if p.taken_hold < math.inf:
                k = _hold_guide(
                    padded,
                    sat,
                    res,
                    pos[i],
                    guide[i, 0],
                    loyal[i],
                    row_of,
                    beacon_pos,
                    desired_vec,
                    to_empty,
                    corridor,
                    k,
                    nearest_k,
                    p,
                )
            guide[i, 0] = ids[k]
            contact[i, 0] = pos[i, 0]
            contact[i, 1] = pos[i, 1]
            contact[i, 2] = 1.0
        # N: measured vector to the nearest beacon; D: its desired direction (length I_r).
        # Its bearing goes through abm.portable's atan2/cos/sin: the same bits on every CPU.
        nx, ny = measured_relative(
            beacon_pos[k, 0] - pos[i, 0],
            beacon_pos[k, 1] - pos[i, 1],
            z[i, 0],
            z[i, 1],
            p.range_noise,
            p.bearing_noise,
            p.reference_range,
        )
        lx = nx + desired_vec[k, 0]
        ly = ny + desired_vec[k, 1]
        returning = lost and p.lost_return and contact[i, 2] > 0.0
        if returning:  # back to where it last was in touch (its own odometry)
            lx = contact[i, 0] - pos[i, 0]
            ly = contact[i, 1] - pos[i, 1]
        # C: away from the walls the four distance sensors see, growing as 1 / distance.
        cx = 0.0
        cy = 0.0
        for d in range(4):
            reading = noisy_reading(walls[i, d], z[i, 2 + d], p.sensor_noise, p.sensor_range)
            push = p.avoid_gain * max(0.0, 1.0 / max(reading, 0.05) - 1.0 / p.sensor_range)
            cx -= push * CARDINALS[d, 0]
            cy -= push * CARDINALS[d, 1]
        # Each explorer low-pass filters its noisy T (a real sensor stack smooths at 10 Hz).
        T[i, 0] += p.gain * (lx + cx - T[i, 0])
        T[i, 1] += p.gain * (ly + cy - T[i, 1])
        size = math.hypot(T[i, 0], T[i, 1])
        if lost and not returning:
            continue  # hover and wait
        scale = p.max_speed / max(size, p.slow_radius)
        desired[i, 0] = T[i, 0] * scale
        desired[i, 1] = T[i, 1] * scale
        side = _slide_side(slide[i], pos[i], lx, ly, walls[i], p)
        if side != 0.0:  # pressed against an obstacle: slide along it, across L
            desired[i, 0] -= side * ly * scale
            desired[i, 1] += side * lx * scale
        if lost:
            continue
        attach[i] = (
            size <= p.attach_eps
            and math.hypot(vel[i, 0], vel[i, 1]) <= p.attach_speed
            and to_empty[k]
            and math.hypot(nx, ny) > p.interspace / 2
        )
        attaching += attach[i]
    return attaching


@njit(cache=True)
def _slide_side(slide, point, lx, ly, walls, p):
    """Whether a flyer slides along an obstacle now: 0, or the side (+1 left of L, -1 right).

    A flyer whose goal (L, before collision avoidance) lies more than half the slow-down radius
    away but that has stayed within half the slow-down radius of one point for ``slide_after``
    seconds is pressed against an obstacle (a pillar or a wall on the straight line to its
    goal: the four cardinal sensors' C pushes straight back, never sideways, and T = L + C
    balances short of the goal). It then slides across L for ``slide_after`` seconds towards
    the side whose cardinal sensor reads farther, or, when both read alike, the other side
    than its last slide (a door's edge: the first way may lead back). ``slide`` holds (x, y of
    the point, time there, slide time left, side).
    """
    if slide[3] > 0.0:
        slide[3] -= p.dt
        return slide[4]
    moved = math.hypot(point[0] - slide[0], point[1] - slide[1]) > 0.5 * p.slow_radius
    if math.hypot(lx, ly) <= 0.5 * p.slow_radius or moved:
        slide[0] = point[0]
        slide[1] = point[1]
        slide[2] = 0.0
        return 0.0
    slide[2] += p.dt
    if slide[2] < p.slide_after:
        return 0.0
    left = 0
    for d in range(4):  # the cardinal nearest the left perpendicular (-l_y, l_x)
        if -ly * CARDINALS[d, 0] + lx * CARDINALS[d, 1] > (
            -ly * CARDINALS[left, 0] + lx * CARDINALS[left, 1]
        ):
            left = d
    slide[2] = 0.0
    slide[3] = p.slide_after
    right = (left + 2) % 4
    if abs(walls[left] - walls[right]) > 2.0 * p.sensor_noise:
        slide[4] = 1.0 if walls[left] > walls[right] else -1.0
    else:  # both sides alike: the other side than last time (the first slide goes left)
        slide[4] = -1.0 if slide[4] > 0.0 else 1.0
    return slide[4]


@njit(cache=True)
def _hold_guide(
    padded,
    sat,
    res,
    point,
    guide_id,
    loyal,
    row_of,
    beacon_pos,
    desired_vec,
    to_empty,
    corridor,
    k,
    nearest,
    p,
):
    """The beacon a flyer follows under ``taken_hold``, given ``k`` from :func:`_keep_guide`.

    A flyer committed to its corridor guide's empty spot last tick whose spot is gone (another
    explorer attached there) keeps that guide while it stays in touch, until the guide is its
    nearest beacon again or the flyer is within I_r / 2 of the spot the guide turned to: at a
    junction the guide turns to its next neighbour and the flyer follows it there instead of
    following the newcomer into a side branch. If the guide still signals the taken spot's
    direction after ``taken_hold`` seconds (it has decided, and the newcomer carries the search
    on, as along a chain), the flyer follows the newcomer as before. ``loyal`` holds
    (committed last tick, holding, committed D x and y, time held with that D) and is updated
    in place. Open-space guides are not held: there the paper sends explorers to the nearest
    empty space, which the newcomer's signal is.
    """
    gid = int(guide_id)
    g = row_of[gid] if 0 <= gid < row_of.shape[0] and gid == guide_id else -1
    if g >= 0 and loyal[0] > 0.0 and not to_empty[g] and corridor[g]:
        loyal[1] = 1.0  # the spot it was committed to is gone
        loyal[4] = 0.0
    if g < 0 or g == nearest:
        loyal[1] = 0.0
    elif loyal[1] > 0.0:
        same = abs(desired_vec[g, 0] - loyal[2]) + abs(desired_vec[g, 1] - loyal[3]) < 1e-9
        if same:
            loyal[4] += p.dt
        to_guide = math.hypot(beacon_pos[g, 0] - point[0], beacon_pos[g, 1] - point[1])
        crosses = segment_crosses(
            padded, sat, res, point[0], point[1], beacon_pos[g, 0], beacon_pos[g, 1]
        )
        goal = math.hypot(
            beacon_pos[g, 0] + desired_vec[g, 0] - point[0],
            beacon_pos[g, 1] + desired_vec[g, 1] - point[1],
        )
        decided = same and loyal[4] > p.taken_hold  # still the taken spot's way: follow on
        arrived = not same and goal <= p.interspace / 2  # at the spot the guide turned to
        if to_guide <= p.comm_range and not crosses and not decided and not arrived:
            k = g
        else:
            loyal[1] = 0.0
    loyal[0] = 1.0 if to_empty[k] else 0.0
    if to_empty[k]:
        loyal[2] = desired_vec[k, 0]
        loyal[3] = desired_vec[k, 1]
    return k


@njit(cache=True)
def _keep_guide(padded, sat, res, point, guide_id, row_of, beacon_pos, to_empty, nearest, p):
    """The beacon a flyer follows: the nearest one, unless the one it followed is still in
    touch (within C_r, line of sight) and either signals an empty spot (``guide_commit``: the
    flyer is on its way to attach there) or is less than ``guide_hysteresis`` farther away.

    The paper's explorer follows its nearest beacon. Where an advertised spot lies nearly as
    close to another beacon, the nearest one flips on the way there, the two beacons' signals
    point to different spots, and the explorer shuttles between them for ever (the stalled runs).
    Hysteresis alone leaves a band of spots (those 2.2 to 2.5 m from another beacon with the
    defaults) that a beacon advertises but an explorer arriving there leaves for the other
    beacon: on floor plans whose walls stop the lattice short, whole swarms circled such a spot.
    """
    gid = int(guide_id)
    g = row_of[gid] if 0 <= gid < row_of.shape[0] and gid == guide_id else -1
    if g < 0 or g == nearest:
        return nearest
    to_guide = math.hypot(beacon_pos[g, 0] - point[0], beacon_pos[g, 1] - point[1])
    to_nearest = math.hypot(beacon_pos[nearest, 0] - point[0], beacon_pos[nearest, 1] - point[1])
    if to_guide > p.comm_range:
        return nearest
    if to_guide >= to_nearest + p.guide_hysteresis and not (p.guide_commit and to_empty[g]):
        return nearest
    if segment_crosses(padded, sat, res, point[0], point[1], beacon_pos[g, 0], beacon_pos[g, 1]):
        return nearest
    return g
