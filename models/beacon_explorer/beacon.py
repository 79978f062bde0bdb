"""The beacon network of Stirling et al. (2010), Sect. 3.3: every beacon's sensing, its
hop-count gradients, and the signals explorers read.

Each beacon, whenever something it can sense changes (a neighbour attaches or detaches, a hop
count or a neighbour's desired direction changes), senses its surroundings and runs the
flowchart of Fig. 2 (:func:`models.beacon_explorer.flowchart.decide`). Evaluations are
messages: a beacon re-evaluates one control period after being woken, and only on hop counts
the newest flood has reached; one that finds them stale waits, and is woken when the wave has
reached it and its lattice neighbours.
"""

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cache

import networkx as nx
import numpy as np
import simpy
from numba import njit

from abm import portable
from abm.arena import CARDINALS, Arena
from abm.clock import scheduler
from abm.comms import CommNetwork, GradientFlood
from abm.sensors import distance_sensors, measured_relative, ray_sensors
from models.beacon_explorer.flowchart import (
    DIRECTIONS,
    NO_DIRECTION,
    Neighbour,
    Sensing,
    decide,
    opposite,
)
from models.beacon_explorer.params import BeaconExplorerParams

__all__ = ["Beacon", "BeaconNetwork"]


@cache
def quadrant_rays() -> np.ndarray:
    """Unit vectors of the rays probing the NE, SE, SW and NW quadrants, five per quadrant at
    compass bearings 15 to 75 degrees past its first cardinal (clockwise from North).

    Computed on first use, not at import: the portable sine and cosine are numba functions,
    and loading them took a fifth of a second that ``abm run beacon-explorer --help`` paid.
    """
    return np.array(
        [
            [portable.sin_scalar(a), portable.cos_scalar(a)]
            for a in np.radians([q * 90 + b for q in range(4) for b in (15, 30, 45, 60, 75)])
        ]
    )


@dataclass
class Beacon:
    """What one beacon knows: its sensing at attach time, its memory and its signal."""

    robot: int
    position: np.ndarray
    walls: tuple[bool, bool, bool, bool]
    corridor: bool
    is_base: bool = False
    #: directions remembered as searched: a neighbour there detached after its search (and,
    #: with ``searched_follows_signal`` off, one that ever signalled back)
    searched: set[int] = field(default_factory=set)
    reported_taken: set[int] = field(default_factory=set)
    neighbour_dirs: dict[int, int] = field(default_factory=dict)
    desired: int = NO_DIRECTION
    redeploying: bool = False
    frontier: bool = False
    may_detach: bool = False
    #: what its robot waits on to redeploy (:meth:`BeaconNetwork.free_to_detach`)
    detach_wanted: simpy.Event | None = None


class BeaconNetwork:
    """All beacons' controllers, their hop-count gradients and the signals explorers read.

    Args:
        env: the clock.
        arena: walls (for the beacons' distance sensors).
        comms: the comm network beacons are nodes of.
        rng: the model's generator (sensor noise).
        params: the algorithm's constants.
        control_period: delay between a wake-up and the controller's reaction (s).

    """

    def __init__(
        self,
        env,
        arena: Arena,
        comms: CommNetwork,
        rng: np.random.Generator,
        params: BeaconExplorerParams,
        control_period: float,
    ) -> None:
        self.env = env
        self._call_later = scheduler(env)
        self.arena = arena
        self.comms = comms
        self.rng = rng
        self.params = params
        self.control_period = control_period
        self.beacons: dict[int, Beacon] = {}
        self.base: int | None = None
        # The lattice, kept up to date incrementally (see _update_lattice): each beacon's pick
        # per direction, the mutual picks (lattice links), and each beacon's attach turn.
        self._picks: dict[int, dict[int, int]] = {}
        self._links: dict[int, set[int]] = {}
        self._turn: dict[int, int] = {}
        self._turns = 0
        self._xy = np.empty((64, 2))  # beacon positions by attach turn (the sensor's kernel)
        self._touched: set[int] = set()
        # lattice_neighbours, computed on first use and kept until the beacon's links change
        self._ordered = _Memo(self._lattice_order)
        # per beacon, until its links change: its comm neighbours, their rows of _xy, and
        # which of them are lattice neighbours (what the relative-positioning sensor sees)
        self._near: dict[int, tuple[list[int], np.ndarray, np.ndarray]] = {}
        self._members: _Members | None = None  # what signals() returns, kept up to date
        self.forwards = GradientFlood(
            comms, "forwards", params.forwards_start, +1, links=self._ordered.__getitem__
        )
        self.reverse = GradientFlood(
            comms, "reverse", params.reverse_start, -1, floor=0, links=self._ordered.__getitem__
        )
        self.forwards.on_change(self._hop_changed)
        self.reverse.on_change(self._hop_changed)
        # Beacons waiting for the newest waves: each one's nodes (itself and its lattice
        # neighbours), and per node the beacons waiting on it (dicts: insertion order).
        self._waiting: dict[int, tuple[int, ...]] = {}
        self._waiting_on: dict[int, dict[int, None]] = {}
        self.forwards.on_reach(self._wave_reached, only=self._waiting_on)
        self.reverse.on_reach(self._wave_reached, only=self._waiting_on)
        comms.on_link_change(self._link_changed)
        self._pending: set[int] = set()
        self._wakes_in_flight = 0
        self.version = 0  # bumped whenever a signal explorers read changes
        #: readings as a robot's possibly faulty sensors give them (``abm.faults``): the model
        #: sets ``model.faults.sensed``; by default the readings as measured
        self.sensed: Callable[[str, list[int], np.ndarray], np.ndarray] = _as_measured

    # ------------------------------------------------------------------ membership
    def attach(self, robot: int, position: np.ndarray, is_base: bool = False) -> Beacon:
        """A robot attached at ``position``: sense, join the network, start signalling."""
        position = np.asarray(position, dtype=float)
        walls, corridor = self._sense_walls(position, robot)
        beacon = Beacon(robot, position, walls, corridor, is_base=is_base)
        self.beacons[robot] = beacon
        if self._members is not None:
            self._members = self._members.joined(robot, position, corridor)
        self._turn[robot] = self._turns
        if self._turns == len(self._xy):
            self._xy = np.concatenate([self._xy, np.empty_like(self._xy)])
        self._xy[self._turns] = position
        self._turns += 1
        self._touched.add(robot)
        if is_base:
            self.base = robot
            self.forwards.set_sources([robot])
        self.comms.add(robot, position)
        self._topology_changed()
        self.wake(robot)
        self.version += 1
        return beacon

    def detach(self, robot: int, searched: bool = True) -> None:
        """A beacon let go of the ceiling: it leaves the network.

        A beacon detaches to redeploy only once the area beyond it is searched, so its
        neighbours remember its direction as searched; a beacon that failed (battery flat,
        ``searched=False``) says nothing about the area beyond it.
        """
        beacon = self.beacons.pop(robot)
        self._stop_waiting(robot)
        if self._members is not None:
            self._members = self._members.left(robot)
        for other in self.beacons.values() if searched else ():
            for d, n in other.neighbour_dirs.items():
                if n == robot:
                    other.searched.add(d)
        if beacon.frontier:
            self.reverse.set_sources(self.reverse.sources - {robot})
        if robot in self.comms.graph:  # a failed robot has left it already
            self.comms.remove(robot)
        self._touched.add(robot)
        self.forwards.forget(robot)
        self.reverse.forget(robot)
        self._topology_changed()
        self.version += 1

    def links_changed(self) -> None:
        """A link between beacons went down or came back (an outage): the lattice is drawn
        again and the hop counts re-flood over it.
        """
        self._topology_changed()
        self.version += 1

    def _topology_changed(self) -> None:
        self._update_lattice()
        self.forwards.restart()
        self.reverse.restart()

    def _update_lattice(self) -> None:
        """Lattice links: mutual nearest linked neighbours in opposite compass directions.

        Hop counts travel through the relative-positioning sensor to these <= 4 neighbours
        (Sect. 3.3, App. A), so neighbours differ by exactly one hop. A drifted lattice can
        bring a diagonal beacon within C_r; flooding over it would give equal hop counts to
        neighbours, which the controller's rules never expect.

        A beacon's picks depend only on its comm links and the (fixed) positions of the
        beacons, so only beacons that attached, detached or whose links changed since the last
        update (``_touched``) pick again, and only their links are re-checked: the cost of a
        change is that of its neighbourhood, not of the whole network.
        """
        touched, self._touched = self._touched, set()
        stale = set(touched)  # beacons whose lattice_neighbours may change: they and their links
        for robot in touched - self.beacons.keys():  # detached
            self._picks.pop(robot, None)
            self._turn.pop(robot, None)
            for other in self._links.pop(robot, ()):
                self._links[other].discard(robot)
                stale.add(other)
        present = [robot for robot in touched if robot in self.beacons]
        for robot in present:
            self._picks[robot] = self._pick(robot)
            self._links.setdefault(robot, set())
        for robot in present:
            stale.update(self._links[robot])
            for other in list(self._links[robot]):
                if not self._mutual(robot, other):
                    self._links[robot].discard(other)
                    self._links[other].discard(robot)
            for other in self._picks[robot].values():
                if self._mutual(robot, other):
                    self._links[robot].add(other)
                    self._links[other].add(robot)
                    stale.add(other)
        for robot in stale:
            self._ordered.pop(robot, None)
            self._near.pop(robot, None)

    def _pick(self, robot: int) -> dict[int, int]:
        """The nearest linked beacon in each direction (directions in order of first sight)."""
        beacon = self.beacons[robot]
        nearest: dict[int, tuple[float, int]] = {}
        for other in self.comms.neighbours(robot):
            rel = self.beacons[other].position - beacon.position
            d = int(np.argmax(CARDINALS @ rel))
            r = float(np.hypot(*rel))
            if d not in nearest or r < nearest[d][0]:
                nearest[d] = (r, other)
        return {d: other for d, (_r, other) in nearest.items()}

    def _mutual(self, robot: int, other: int) -> bool:
        """Both beacons pick each other, in opposite directions."""
        theirs = self._picks.get(other, {})
        return any(
            o == other and theirs.get(opposite(d)) == robot for d, o in self._picks[robot].items()
        )

    def lattice_neighbours(self, robot: int) -> list[int]:
        """The beacons a beacon exchanges hop counts with.

        In the order the whole lattice would list them if it were built afresh beacon by
        beacon in attach order (messages go out in this order, so it fixes the order of
        same-time events): first the neighbours that attached earlier, in attach order, then
        the later ones in the order of this beacon's picks.
        """
        return self._ordered[robot]

    def _lattice_order(self, robot: int) -> list[int]:
        """:meth:`lattice_neighbours` worked out from the links and attach turns."""
        links = self._links.get(robot)
        if not links:
            return []
        turn = self._turn
        mine = turn[robot]
        earlier = sorted((o for o in links if turn[o] < mine), key=turn.__getitem__)
        later = [o for o in self._picks[robot].values() if o in links and turn[o] > mine]
        return earlier + later

    @property
    def lattice(self) -> nx.Graph:
        """The lattice as a graph (for drawings and analysis; built on demand)."""
        graph = nx.Graph()
        graph.add_nodes_from(self.beacons)
        graph.add_edges_from(
            (robot, other) for robot in self.beacons for other in self.lattice_neighbours(robot)
        )
        return graph

    # ------------------------------------------------------------------ sensing
    def _sense_walls(
        self, position: np.ndarray, robot: int | None = None
    ) -> tuple[tuple[bool, ...], bool]:
        """Obstacle labels N/E/S/W and the corridor/open-space classification.

        Corridor beacon (paper): two opposing walls closer than 3 m. A corridor junction senses
        only one wall, so with four sensors alone it would pass for open space and lose the
        junction memory the depth-first search relies on; we call a beacon open-space only if
        some quadrant is open: two adjacent free cardinal directions and nothing sensed on five
        rays between them (space wider than a corridor). Two opposing walls within the obstacle
        threshold leave no two adjacent free directions, so the paper's test is implied by this
        one and needs no code of its own. See README.
        """
        p = self.params
        reading = distance_sensors(
            self.arena, position[None], self.rng, p.sensor_range, p.sensor_noise
        )
        if robot is not None:  # the readings of this robot's (possibly faulty) sensors
            reading = self.sensed("walls", [robot], reading)
        reading = reading[0]
        walls = tuple(bool(r < p.obstacle_threshold) for r in reading)
        # Five rays into each quadrant (NE, SE, SW, NW; 15 to 75 degrees from its first
        # cardinal): a single diagonal ray from a beacon that drifted towards a T-junction's
        # corner can run 3.5 m up the side branch and pass for open space.
        reach = ray_sensors(
            self.arena, position, quadrant_rays(), self.rng, p.sensor_range, p.sensor_noise
        )
        if robot is not None:
            reach = self.sensed("rays", [robot], reach[None])[0]
        quadrant_clear = (reach > p.open_diagonal).reshape(4, -1).all(axis=1)
        open_quadrant = any(
            not walls[d] and not walls[(d + 1) % 4] and quadrant_clear[d] for d in DIRECTIONS
        )
        return walls, not open_quadrant

    def _sense_beacons(self, robot: int) -> tuple[dict[int, int], set[int]]:
        """What the relative-positioning sensor tells a beacon about the beacons around it.

        Returns the lattice neighbour in each direction (direction -> nearest linked lattice
        neighbour there) and the directions labelled "beacon" although no lattice neighbour
        holds them (Fig. 3's labels come from this sensor, which sees every beacon in range):

        - a direction whose lattice spot (I_r away) lies inside another beacon's share of the
          plane: an explorer flying there finds that beacon nearest and follows its signal
          instead of attaching, so advertising the spot as empty keeps explorers shuttling
          between two targets for ever. In corridors, one beacon wide, any sensed beacon nearer
          the spot than I_r has it (at a T-junction a beacon that had drifted to the side
          branch's edge advertised the branch while a branch beacon 2.4 m from the spot, not
          its lattice neighbour, covered it: 2 of 1800 corridor runs ran to the time limit).
          In open space a diagonal neighbour that drifted in range would hide a free spot that
          way, so the spot must be within ``spot_taken`` (< I_r) of the other beacon (room
          corners of mixed worlds, where the lattice is irregular, stalled 6 of 600 runs).
        """
        me = self.beacons[robot]
        near = self._near.get(robot)
        if near is None:
            others = self.comms.neighbours(robot)
            linked = self.lattice_neighbours(robot)
            near = self._near[robot] = (
                others,
                np.array([self._turn[n] for n in others], dtype=np.int64),
                np.array([n in linked for n in others], dtype=np.bool_),
            )
        others, rows, linked = near
        if not others:
            return {}, set(me.reported_taken)
        p = self.params
        # The same draws relative_positions makes, measured and classified in one compiled call:
        # per direction in order of first sight the nearest lattice neighbour, then the spots
        # some neighbour fills (bits).
        picked = _sense_relatives(
            self._xy,
            rows,
            linked,
            self._turn[robot],
            self.rng.standard_normal((len(others), 2)),
            p.range_noise,
            p.bearing_noise,
            p.reference_range,
            p.interspace,
            p.interspace if me.corridor else p.spot_taken,
        ).tolist()
        neighbours = {}
        for k in range(0, 8, 2):
            if picked[k] < 0:
                break
            neighbours[picked[k]] = others[picked[k + 1]]
        taken = set(_DIRECTION_SETS[picked[8]])
        taken |= me.reported_taken
        taken -= neighbours.keys()
        return neighbours, taken

    def spot_reported_taken(self, robot: int | None, where: np.ndarray) -> None:
        """An explorer that flew to beacon ``robot``'s advertised spot found another beacon
        there: the beacon labels that direction "beacon" from now on (``report_taken``).

        Its own sensors can miss that beacon: a pillar between them blocks the line of sight
        while the distance sensor's ray passes beside the pillar (see the README).
        """
        beacon = self.beacons.get(robot)
        if beacon is None:
            return  # it detached meanwhile
        beacon.reported_taken.add(int(np.argmax(CARDINALS @ (where - beacon.position))))
        self.wake(robot)

    # ------------------------------------------------------------------ the flowchart
    def wake(self, robot: int) -> None:
        """Ask a beacon to run its controller at the next control step.

        A beacon waiting for the newest waves is not woken: it could decide nothing before
        they arrive (:meth:`_wave_reached` wakes it then), unless its links change
        (:meth:`_link_changed`), which changes what it senses.
        """
        if robot in self._pending or robot in self._waiting or robot not in self.beacons:
            return
        self._pending.add(robot)
        self._call_later(self.control_period, self._evaluate, robot)

    def _evaluate(self, robot: int) -> None:
        self._pending.discard(robot)
        self._stop_waiting(robot)
        beacon = self.beacons.get(robot)
        if beacon is None:
            return
        before = beacon.neighbour_dirs.keys()
        beacon.neighbour_dirs, taken = self._sense_beacons(robot)
        if beacon.neighbour_dirs.keys() != before:
            # Whether its desired spot is empty (what explorers read) may change with them.
            self._signal_changed(beacon)
            self.version += 1
        nb = beacon.neighbour_dirs
        # Act only on settled hop counts: a value the newest wave has not reached yet is stale.
        nodes = (robot, *nb.values())
        if not self._settled(nodes):
            self._wait_for_waves(robot, nodes)
            return
        fwd, rev = self.forwards.value, self.reverse.value
        decision = decide(
            Sensing(
                corridor=beacon.corridor,
                walls=beacon.walls,
                neighbours={
                    d: Neighbour(fwd(n), rev(n), self.beacons[n].desired) for d, n in nb.items()
                },
                taken=frozenset(taken),
                searched=frozenset(beacon.searched),
                forwards=fwd(robot),
                reverse=rev(robot),
                is_base=beacon.is_base,
            )
        )
        if not self.params.searched_follows_signal:
            beacon.searched = set(decision.searched)  # every signal remembered for good
        self._publish(
            beacon, decision.desired, decision.redeploying, decision.frontier, decision.may_detach
        )

    def _settled(self, nodes: tuple[int, ...]) -> bool:
        """The newest wave of both gradients has reached every one of ``nodes``."""
        return self.forwards.settled_all(nodes) and self.reverse.settled_all(nodes)

    def _wait_for_waves(self, robot: int, nodes: tuple[int, ...]) -> None:
        """A beacon found stale hop counts: it decides nothing until the newest waves have
        reached it and the lattice neighbours it sensed (:meth:`_wave_reached` wakes it).

        It does not look again meanwhile: sensing nothing new (beacons stand still) but noise,
        a look every message latency plus control period was most of a large swarm's work.
        """
        self._waiting[robot] = nodes
        for node in nodes:
            self._waiting_on.setdefault(node, {})[robot] = None

    def _stop_waiting(self, robot: int) -> None:
        nodes = self._waiting.pop(robot, ())
        for node in nodes:
            waiters = self._waiting_on[node]
            del waiters[robot]
            if not waiters:
                del self._waiting_on[node]

    def _wave_reached(self, node: int) -> None:
        """The newest wave of a gradient reached ``node``: wake the beacons that waited on it
        and now see settled hop counts everywhere they look.
        """
        waiters = self._waiting_on[node]
        for robot in [r for r in waiters if self._settled(self._waiting[r])]:
            self._stop_waiting(robot)
            self.wake(robot)

    def _publish(
        self, beacon: Beacon, desired: int, redeploying: bool, frontier: bool, may_detach: bool
    ) -> None:
        robot = beacon.robot
        changed = desired != beacon.desired
        beacon.desired = desired
        beacon.redeploying = redeploying
        if frontier != beacon.frontier:
            beacon.frontier = frontier
            sources = self.reverse.sources | {robot} if frontier else self.reverse.sources - {robot}
            self.reverse.set_sources(sources)
            self.version += 1
        if changed:
            self._signal_changed(beacon)
            self.version += 1
            for n in self.lattice_neighbours(robot):
                self.wake_later(n)
        wanted = beacon.detach_wanted
        if may_detach and not beacon.may_detach and wanted is not None and not wanted.triggered:
            wanted.succeed()
        beacon.may_detach = may_detach

    def free_to_detach(self, robot: int) -> simpy.Event:
        """An event that fires once beacon ``robot`` is free to detach (Fig. 2's last step:
        redeploying, every neighbour's forwards hop count lower or equal); at once if it is.
        """
        beacon = self.beacons[robot]
        beacon.detach_wanted = wanted = self.env.event()
        if beacon.may_detach:
            wanted.succeed()
        return wanted

    def wake_later(self, robot: int) -> None:
        """Wake a beacon once a message has reached it."""
        self._wakes_in_flight += 1
        self._call_later(self.comms.latency, self._woken_by_message, robot)

    def _woken_by_message(self, robot: int) -> None:
        self._wakes_in_flight -= 1
        self.wake(robot)

    @property
    def quiescent(self) -> bool:
        """True when both gradients have settled everywhere and no beacon has a pending decision.

        Only then do the beacons' phases and detach permissions reflect the current network; a
        robot that has just attached, for instance, has no hop count until the waves reach it.
        """
        return (
            self.forwards.settled_everywhere
            and self.reverse.settled_everywhere
            and not self._pending
            and not self._waiting
            and self._wakes_in_flight == 0
        )

    def _hop_changed(self, node: int, _old: int, _new: int) -> None:
        self.wake(node)
        for n in self.lattice_neighbours(node):
            self.wake(n)

    def _link_changed(self, _kind: str, a: int, b: int) -> None:
        self._touched.update((a, b))
        self._near.pop(a, None)
        self._near.pop(b, None)
        for robot in (a, b):
            self._stop_waiting(robot)
            self.wake(robot)

    # ------------------------------------------------------------------ what explorers read
    def signals(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Arrays for the explorers: robot ids, positions, desired vectors D, target-is-empty."""
        members = self._current_members()
        return members.ids, members.pos, members.vectors.copy(), members.to_empty.copy()

    def corridors(self) -> np.ndarray:
        """Whether each beacon is a corridor beacon, in the order of :meth:`signals`."""
        return self._current_members().corridor

    def rows_by_id(self) -> np.ndarray:
        """Each beacon's row in :meth:`signals` by robot id (-1: not a beacon), for O(1)
        look-ups (a new array whenever a beacon attaches or leaves).
        """
        return self._current_members().rows

    def _current_members(self) -> "_Members":
        """The beacons' arrays, built on first use, then kept up to date: a row added or
        removed as a beacon attaches or detaches (:meth:`_Members.joined`,
        :meth:`_Members.left`; positions are fixed), and :meth:`_signal_changed` keeping the
        signals current. Rebuilding them from every beacon after each attach cost
        O(beacons) Python work per attach: quadratic in a 10,000-robot run.
        """
        if self._members is None:
            beacons = self.beacons.values()
            n = len(self.beacons)
            ids = np.fromiter(self.beacons, dtype=np.int64, count=n)
            rows = np.full(int(ids.max(initial=-1)) + 1, -1, dtype=np.int64)
            rows[ids] = np.arange(n)
            self._members = _Members(
                ids=ids,
                pos=np.array([b.position for b in beacons]).reshape(-1, 2),
                corridor=np.fromiter((b.corridor for b in beacons), dtype=bool, count=n),
                rows=rows,
                vectors=np.array([self._vector(b.desired) for b in beacons]).reshape(-1, 2),
                to_empty=np.fromiter((_to_empty(b) for b in beacons), dtype=bool, count=n),
            )
        return self._members

    def _vector(self, desired: int) -> np.ndarray:
        """The desired vector D of a direction: I_r along it (zero for none)."""
        if desired < 0:
            return np.zeros(2)
        return CARDINALS[desired] * self.params.interspace

    def _signal_changed(self, beacon: Beacon) -> None:
        """A beacon's desired direction or its neighbours' directions changed."""
        if self._members is not None:
            row = self._members.rows[beacon.robot]
            self._members.vectors[row] = self._vector(beacon.desired)
            self._members.to_empty[row] = _to_empty(beacon)


@dataclass
class _Members:
    """The beacons as arrays, in the order of ``BeaconNetwork.beacons``.

    A change of members makes new arrays (what :meth:`BeaconNetwork.signals` handed out
    before stays as it was), in C loops: no Python work per beacon.
    """

    ids: np.ndarray
    pos: np.ndarray
    corridor: np.ndarray
    #: row of each beacon by robot id (-1: not a beacon)
    rows: np.ndarray
    vectors: np.ndarray
    to_empty: np.ndarray

    def joined(self, robot: int, position: np.ndarray, corridor: bool) -> "_Members":
        """The members with beacon ``robot`` (at ``position``, signalling nothing yet) last."""
        rows = self.rows
        if robot >= len(rows):
            rows = np.concatenate([rows, np.full(robot + 1 - len(rows), -1, dtype=np.int64)])
        else:
            rows = rows.copy()
        rows[robot] = len(self.ids)
        return _Members(
            ids=np.append(self.ids, robot),
            pos=np.concatenate([self.pos, np.asarray(position, dtype=float).reshape(1, 2)]),
            corridor=np.append(self.corridor, corridor),
            rows=rows,
            vectors=np.concatenate([self.vectors, np.zeros((1, 2))]),
            to_empty=np.append(self.to_empty, False),
        )

    def left(self, robot: int) -> "_Members":
        """The members without beacon ``robot`` (the later rows move up one)."""
        row = int(self.rows[robot])
        rows = self.rows.copy()
        rows[robot] = -1
        rows[self.ids[row + 1 :]] -= 1
        return _Members(
            ids=np.delete(self.ids, row),
            pos=np.delete(self.pos, row, axis=0),
            corridor=np.delete(self.corridor, row),
            rows=rows,
            vectors=np.delete(self.vectors, row, axis=0),
            to_empty=np.delete(self.to_empty, row),
        )


class _Memo(dict):
    """A cache that fills a missing key with ``compute(key)`` and keeps it until popped: one
    subscript, a C call, to read (the floods read each beacon's lattice links millions of
    times; a Python method per read was a tenth of a 3,000-robot run in cProfile).
    """

    def __init__(self, compute: Callable[[int], list[int]]) -> None:
        super().__init__()
        self._compute = compute

    def __missing__(self, key: int) -> list[int]:
        value = self[key] = self._compute(key)
        return value


def _to_empty(beacon: Beacon) -> bool:
    """The beacon signals a direction and no lattice neighbour holds it (its spot is free)."""
    return beacon.desired >= 0 and beacon.desired not in beacon.neighbour_dirs


def _as_measured(_channel: str, _robots: list[int], readings: np.ndarray) -> np.ndarray:
    return readings


#: The set of directions each 4-bit mask names (bit d: direction d).
_DIRECTION_SETS = tuple(frozenset(d for d in DIRECTIONS if mask >> d & 1) for mask in range(16))


@njit(cache=True)
def _sense_relatives(
    xy: np.ndarray,
    rows: np.ndarray,
    linked: np.ndarray,
    me: int,
    z: np.ndarray,
    range_noise: float,
    bearing_noise: float,
    reference_range: float,
    interspace: float,
    reach: float,
) -> np.ndarray:
    """The relative-positioning sensor of beacon row ``me`` measuring the beacons in ``rows``
    of ``xy`` (with the standard normal draws ``z``, as :func:`abm.sensors.relative_positions`
    makes them), then classified. Each neighbour lies in the compass direction it is most
    along (the first cardinal on ties); in each direction the nearest measured neighbour among
    the ``linked`` ones (the first of equals) is the lattice neighbour there.

    Returns 9 integers: (direction, neighbour index) for each direction holding a lattice
    neighbour, in the order the directions were first seen, padded with -1; then a bit mask
    of the directions whose lattice spot (I_r away) some neighbour is closer than ``reach`` to.
    """
    best = np.full(4, -1, dtype=np.int64)
    best_dist = np.zeros(4)
    first = np.full(4, -1, dtype=np.int64)
    seen = 0
    taken = 0
    for i in range(rows.shape[0]):
        x, y = measured_relative(
            xy[rows[i], 0] - xy[me, 0],
            xy[rows[i], 1] - xy[me, 1],
            z[i, 0],
            z[i, 1],
            range_noise,
            bearing_noise,
            reference_range,
        )
        d = 0
        along = x * CARDINALS[0, 0] + y * CARDINALS[0, 1]
        for c in range(1, 4):
            v = x * CARDINALS[c, 0] + y * CARDINALS[c, 1]
            if v > along:
                d, along = c, v
        r = math.hypot(x, y)
        if linked[i]:
            if best[d] < 0:
                first[seen] = d
                seen += 1
                best[d], best_dist[d] = i, r
            elif r < best_dist[d]:
                best[d], best_dist[d] = i, r
        for c in range(4):
            if (
                math.hypot(CARDINALS[c, 0] * interspace - x, CARDINALS[c, 1] * interspace - y)
                < reach
            ):
                taken |= 1 << c
    out = np.full(9, -1, dtype=np.int64)
    for k in range(seen):
        out[2 * k] = first[k]
        out[2 * k + 1] = best[first[k]]
    out[8] = taken
    return out
