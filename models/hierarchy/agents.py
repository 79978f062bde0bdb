"""The queen, the workers and the scouts (the report's "Queen / Worker" and "Scout").

A worker and a scout are :class:`abm.robot.Robot` s (:class:`Worker`, :class:`Scout`); the queen
is a laptop with no body (README "Choices": the queen), so :class:`Queen` is a member of the tree
but no robot. Each role's behaviour is its ``life()`` generator, started by the model.

Every member holds only its local address book (``links``: 0 = parent, 1..k = children,
"Communication") and an inbox; it sends through the model's comm network, whose tree policy
refuses anything but a parent/child link. Nothing a member keeps names the swarm's size or depth.

- A **scout** (leaf) answers REQUEST_INFO with its limits (the IR range), then runs its FIFO
  command loop: MOVE -> drive, ARRIVED; SCAN r -> sweep the sensors, one POINT per obstacle
  reading, SCAN_COMPLETE asking the parent to infer line-of-sight coverage.
- A **director** (the queen, or a worker) first learns its children's limits, then on every
  assignment runs the coverage loop over its ProbMap: place all children (synchronous rounds),
  move idle robots in the way, then the placed children wave by wave, send MAP_DOWN (to children
  with children) and SCAN, merge the reports as they arrive, and re-plan when every placed child
  has finished. A worker reports its bubble upward (MAP_REPORT + SCAN_COMPLETE); the queen's
  COMPLETE (or CANNOT_COMPLETE) ends the run.
- With ``subtree_transits="staggered"`` (ours) the queen sends her placed workers one subtree
  at a time (:meth:`Queen.stagger`): MOVE, SCAN, then she waits for the worker's SETTLED (its
  scouts have driven into the new bubble) before the next worker gets its order.

Failures (the report's "Node Failure Detection", Future Work): a member whose body failed does
nothing more. Its parent's and children's heartbeat watchdogs notice after
``heartbeat_timeout`` (a :class:`LinkLost` in their inbox, not a radio message: the report's
heartbeats are not counted, README "Choices": start-up heartbeat). The parent forgets the child (no
longer waited for, its bubble left unscanned for a later round); an orphaned scout finishes the
command it is running, re-attaches to the queen (the tree's only legal new parent that directs) and
sends her its INFO; she places it from her next round on like any child.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from abm.comms.inbox import Inbox
from abm.robot import Robot
from models.hierarchy.coverage import Child, Plan, Status, coverage
from models.hierarchy.planning import path_length, wave_order_violations
from models.hierarchy.probmap import Bubble, MapWindow, ProbMap, Rect
from models.hierarchy.protocol import (
    ArrivedMsg,
    AssignMsg,
    InfoMsg,
    LosHintMsg,
    MapDownMsg,
    MapReportMsg,
    Message,
    MoveMsg,
    PointMsg,
    RequestInfoMsg,
    ScanCompleteMsg,
    ScanMsg,
    SettledMsg,
    rle_bytes,
)

if TYPE_CHECKING:
    from models.hierarchy.model import HierarchyModel

__all__ = [
    "QUEEN",
    "Director",
    "LinkLost",
    "Member",
    "NoProgressError",
    "Queen",
    "Scout",
    "TreeRobot",
    "Worker",
]

#: The queen's name on the comm network.
QUEEN = "queen"


class NoProgressError(RuntimeError):
    """A director exceeded ``max_rounds`` coverage rounds (README "Choices": no-progress guard)."""


class LinkLost:
    """A member's heartbeat watchdog: the neighbour at this local address stopped answering
    (it failed). Put in the member's own inbox; not a radio message.
    """

    KIND = "LINK_LOST"


class Member:
    """What every member of the tree keeps ("Communication"): its local address book, an inbox,
    and the report's per-level measures (scan area, drive distance; "Data Collection").

    A mixin: :class:`Scout` and :class:`Worker` are robots with it, :class:`Queen` is not.

    Attributes:
        links: the address book, local number -> the neighbour's name on the comm network
            (0: the parent, 1..k: the children).
        inbox: the messages received, as ``(sender's local number, message)``.
        scan_area: sum of pi r^2 over every SCAN this member ran (m^2).
        drive_distance: length of every path it drove (m).

    """

    #: Its name on the comm network (the simulator's, never seen by other members).
    id: object
    #: "queen", "worker" or "scout".
    role: str
    model: HierarchyModel

    def __init__(self, *args: object, **kwargs: object) -> None:
        super().__init__(*args, **kwargs)  # a robot's body first (the queen: none)
        self.links: dict[int, object] = {}
        self._local_of: dict[object, int] = {}
        self.inbox = Inbox(self.model.env)
        self.scan_area = 0.0
        self.drive_distance = 0.0

    def link(self, local: int, node_id: object) -> None:
        """Learn a local address (0: the parent, 1..k: the children)."""
        self.links[local] = node_id
        self._local_of[node_id] = local

    def new_local(self) -> int:
        """A child number never used before (a lost child's number is not given again)."""
        return max(self._local_of.values(), default=0) + 1

    def local_of(self, node_id: object) -> int:
        """The local address under which this member knows ``node_id``."""
        return self._local_of[node_id]

    @property
    def parent(self) -> object:
        """The parent's name on the comm network (None for the root)."""
        return self.links.get(0)

    @property
    def children(self) -> list[int]:
        """Local numbers of the children, 1..k."""
        return sorted(k for k in self.links if k > 0)

    def send(self, local: int, msg: Message, origin: object = None, hop: int = 0) -> None:
        """Send ``msg`` to local address ``local`` over the comm network (logged there; no
        member waits on a delivery, so it is posted, not an event).
        """
        dst = self.links[local]
        self.model.comms.post(
            self.id,
            dst,
            msg,
            self.model.deliver,
            kind=msg.KIND,
            items=msg.items,
            nbytes=msg.nbytes,
            phase=msg.PHASE,
            origin=origin,
            hop=hop,
        )

    def receive(self, src: object, msg: object) -> None:
        """A message arrived from ``src``: file it under the sender's local number."""
        self.inbox.put((self._local_of[src], msg))


class TreeRobot(Member, Robot):
    """A member of the tree with a body: a worker or a scout. Its comm-network name is its
    robot id, and it drives its paths through the model's physics.
    """

    @property
    def id(self) -> int:
        """Its name on the comm network: its robot id."""
        return self.unique_id

    @property
    def row(self) -> int:
        """Its row in the model's arrays of all robots (``model.space.agent_positions``)."""
        return int(self.model.rows_of(np.asarray(self.unique_id)))

    def drive(self, waypoints: np.ndarray):
        """Drive the waypoints through the physics (a SimPy generator); the radio link moves
        with the body.
        """
        waypoints = np.asarray(waypoints, dtype=float)
        self.drive_distance += path_length(waypoints)
        if len(waypoints) < 2:
            return
        self.set_state(f"{self.role}_driving")
        yield self.model.follower.drive(self.unique_id, waypoints[0], waypoints[1:])
        self.model.comms.move(self.id, self.position.copy())

    def introduce(self, r_min: float, r_max: float) -> None:
        """INFO to the parent: where the robot is and its bubble limits (m)."""
        x, y = self.position
        self.send(0, InfoMsg(float(x), float(y), r_min, r_max))


class Scout(TreeRobot):
    """A level-2 robot ("Scout"): no map; it drives what it is told and reports what its IR
    sees.

    Args:
        model: the HST model.
        position: where it starts (m).

    """

    role = "scout"

    def __init__(self, model: HierarchyModel, position: np.ndarray) -> None:
        super().__init__(model, position, "scout_idle", "drive")

    def life(self):
        """Start-up (INFO on REQUEST_INFO), then the FIFO command loop ("Task organization"); an
        orphan re-attaches to the queen and introduces itself with an INFO.
        """
        p = self.model.params
        while True:
            _, cmd = yield self.inbox.get()
            if isinstance(cmd, LinkLost):
                self.model.reattach(self)
            if isinstance(cmd, LinkLost | RequestInfoMsg):
                self.introduce(p.scout_r_min, p.scout_r_max)
            if isinstance(cmd, MoveMsg | AssignMsg):
                yield from self.drive(cmd.waypoints)
                self.send(0, ArrivedMsg())
                self.set_state("scout_idle")
            if isinstance(cmd, ScanMsg | AssignMsg):
                yield from self.scan(cmd.r)

    def scan(self, r: float):
        """One stationary sweep of radius ``r``: a POINT per obstacle hit, then SCAN_COMPLETE."""
        p = self.model.params
        self.scan_area += math.pi * r * r
        self.set_state("scout_scanning")
        if p.scan_time > 0:
            yield self.env.timeout(p.scan_time)
        for x, y in self.model.sense(self.position, min(r, p.scout_r_max)).tolist():
            self.send(0, PointMsg(x, y, p.sigma_sensor))
        if p.los_hint_separate:
            self.send(0, LosHintMsg())
        self.send(0, ScanCompleteMsg(infer_los=not p.los_hint_separate))
        self.set_state("scout_idle")


class Director(Member):
    """A member that directs children: the queen or a worker ("Queen / Worker"). It runs the
    coverage loop (Fig. 24) for its children over its ProbMap.

    Attributes:
        info: each child's INFO (its place and bubble limits), by local number.
        where: where each child is, or is going (m), by local number.
        bubble: the last bubble given to each child, by local number.
        map: the ProbMap of its current (or last) assignment.
        directing: True while it runs an assignment (its bubbles are drawn).
        iterations: coverage rounds run so far.
        wave_order_violations: later waves whose paths cross an earlier wave's end cell, or the
            reverse with start cells, over all its rounds (README "Choices": wave-order and
            proximity diagnostics).

    """

    def __init__(self, *args: object, **kwargs: object) -> None:
        super().__init__(*args, **kwargs)
        self.info: dict[int, InfoMsg] = {}
        self.where: dict[int, np.ndarray] = {}
        self.iterations = 0
        self.wave_order_violations = 0
        self.bubble: dict[int, Bubble] = {}
        self.map: ProbMap | None = None
        self.directing = False
        #: Reports that arrived while a wave was still driving (with ASSIGN a child scans on
        #: arrival), merged by the next :meth:`collect`.
        self.early: list[tuple[int, Message]] = []

    def occupied(self) -> list[tuple[float, float]]:
        """The places its own body occupies (m): none for the queen."""
        return []

    def keep(self, m: ProbMap) -> None:
        """What it keeps of an assignment's map once done: nothing but ``map`` for the queen."""

    # ------------------------------------------------------------------ the coverage loop
    def discover(self):
        """REQUEST_INFO to every child and wait for all their INFOs (a child lost meanwhile
        is not waited for).
        """
        for k in self.children:
            self.send(k, RequestInfoMsg())
        while len(self.info) < len(self.children):
            k, msg = yield self.inbox.get()
            self._membership(k, msg)

    def _membership(self, k: int, msg: object) -> bool:
        """Handle a change of children: a lost child is forgotten, an INFO records a child's
        limits and place (at start-up, or an orphan adopted later). True if ``msg`` was one.
        """
        if isinstance(msg, LinkLost):
            for table in (self.links, self.info, self.where, self.bubble):
                table.pop(k, None)
            return True
        if isinstance(msg, InfoMsg):
            self.info[k] = msg
            self.where[k] = np.array([msg.x, msg.y])
            # the child knows its own cell is free (README "Choices": initial knowledge)
            if self.map is not None:
                self.map.mark_free([(msg.x, msg.y)])
            return True
        return False

    def _alive(self, keys) -> list[int]:
        """The children among ``keys`` not lost."""
        return [k for k in keys if k in self.links]

    def _children_box(self) -> Rect:
        """A box around its children's positions, so that its map can route them all."""
        xy = np.array(list(self.where.values()))
        pad = 2 * self.model.params.cell_size
        return Rect(*(xy.min(axis=0) - pad), *(xy.max(axis=0) + pad))

    def _children(self) -> list[Child]:
        return [
            Child(k, float(self.where[k][0]), float(self.where[k][1]), i.r_min, i.r_max)
            for k, i in sorted(self.info.items())
        ]

    def assignment(self, region: Rect | Bubble, cover, known: tuple[MapWindow | None, ...] = ()):
        """Cover ``region`` with the children (the coverage loop of Fig. 24), starting from the
        ``known`` maps; returns the last coverage status.
        """
        p = self.model.params
        m = ProbMap(region, self.model.world_rect, cell_size=p.cell_size,
                    tau=p.blocked_threshold, stamp=p.stamp, cover=cover)  # fmt: skip
        for window in known:
            if window is not None:
                m.merge(window)
        own = self.occupied()
        m.mark_free([tuple(w) for w in self.where.values()] + own)
        self.map = m
        self.directing = True
        self.set_state("worker_directing")
        rounds = 0
        while True:
            while not self.info:  # every child lost: wait for the orphans to re-attach
                k, msg = yield self.inbox.get()
                self._membership(k, msg)
            plan = coverage(m, self._children(), self.model.rng, alpha=p.alpha, beta=p.beta,
                            decay=p.radius_decay, occupied=own,
                            reset_radius_after_removal=p.reset_radius_after_removal,
                            drop_unreachable_first=p.drop_unreachable_first)  # fmt: skip
            if plan.status is not Status.IN_PROGRESS:
                break
            rounds += 1
            if rounds > p.max_rounds:
                raise NoProgressError(
                    f"{self.role} {self.id} needed more than max_rounds={p.max_rounds} rounds"
                )
            self.iterations += 1
            yield from self.round(m, plan, region)
        self.keep(m)
        self.directing = False
        return plan.status

    def round(self, m: ProbMap, plan: Plan, region):
        """Dispatch one plan and merge every placed child's report (README "Choices": rounds)."""
        p = self.model.params
        self.model.log_plan(self, m, plan)
        yield from self.dispatch(plan.idle_moves, plan.idle_waves, MoveMsg)
        placed = sorted(plan.centres)
        combine = p.combine_move_scan
        moves = {k: plan.paths[k] for k in placed if len(plan.paths[k]) > 1}
        for k in self._alive(placed):
            self._map_down(k, plan, m)
        if self.staggers():
            yield from self.stagger(moves, plan.waves, placed, plan.radius)
        elif combine:
            yield from self.dispatch(moves, plan.waves, AssignMsg, r=plan.radius)
            for k in self._alive(placed):
                if k not in moves:
                    self.send(k, ScanMsg(plan.radius))
        else:
            yield from self.dispatch(moves, plan.waves, MoveMsg)
            for k in self._alive(placed):
                self.send(k, ScanMsg(plan.radius))
        self.settled()
        placed = self._alive(placed)
        for k in placed:
            self.bubble[k] = Bubble(*plan.centres[k], plan.radius)
        yield from self.collect(m, plan, placed)

    def staggers(self) -> bool:
        """Whether it sends its placed children in one subtree at a time (only the queen, with
        ``subtree_transits="staggered"``).
        """
        return False

    def stagger(
        self, moves: dict[int, np.ndarray], planned: list[list[int]], placed: list[int], r: float
    ):
        """Send the placed children into their new bubbles one subtree at a time (ours, issue
        30): in wave order (``planned``: the plan's waves of ``moves``; the children that do not
        move last), each gets its MOVE, then its SCAN (or one ASSIGN), and the next is sent only
        when this one's subtree has settled: SETTLED from a child with children, ARRIVED from a
        child without.
        """
        p = self.model.params
        h = p.cell_size
        wave_list = planned if p.wave_generator else [sorted(moves)]
        order = [k for wave in wave_list for k in wave]
        self.wave_order_violations += wave_order_violations([[k] for k in order], moves, h)
        order += [k for k in placed if k not in moves]
        for k in order:
            if k not in self.links:
                continue
            if k in moves:
                self.where[k] = np.asarray(moves[k][-1], dtype=float)
            if k in moves and p.combine_move_scan:
                self.send(k, AssignMsg(moves[k], r))
            else:
                if k in moves:
                    self.send(k, MoveMsg(moves[k]))
                    yield from self._await(k, ArrivedMsg)
                if k in self.links:
                    self.send(k, ScanMsg(r))
            if k not in self.links:
                continue
            if self.model.has_children(self.links[k]):
                yield from self._await(k, SettledMsg)
            elif k in moves and p.combine_move_scan:
                yield from self._await(k, ArrivedMsg)

    def _await(self, k: int, kind: type):
        """Wait for a ``kind`` message from child ``k`` (or for ``k``'s loss); what else
        arrives meanwhile is kept for :meth:`collect`, except ``k``'s own ARRIVED.
        """
        while k in self.links:
            j, msg = yield self.inbox.get()
            if self._membership(j, msg):
                continue
            if j == k and isinstance(msg, kind):
                return
            if not (j == k and isinstance(msg, ArrivedMsg)):
                self.early.append((j, msg))

    def settled(self) -> None:
        """Its children's moves of this round are done (a worker tells a staggering queen)."""

    def _map_down(self, k: int, plan: Plan, m: ProbMap) -> None:
        """MAP_DOWN to a child with children: known cells over its previous and new bubble."""
        if self.model.has_children(self.links[k]):
            box = Bubble(*plan.centres[k], plan.radius).box()
            if k in self.bubble:
                box = box.union(self.bubble[k].box())
            self.send(k, MapDownMsg(m.window(box), m.tau))

    def dispatch(
        self, moves: dict[int, np.ndarray], planned: list[list[int]], kind, r: float | None = None
    ):
        """Send the moves wave by wave (``planned``: the plan's waves of ``moves``, used with
        the wave generator; without it one wave); the next wave leaves when the last has
        arrived.
        """
        if not moves:
            return
        h = self.model.params.cell_size
        wave_list = planned if self.model.params.wave_generator else [sorted(moves)]
        self.wave_order_violations += wave_order_violations(wave_list, moves, h)
        for wave in wave_list:
            wave = self._alive(wave)
            for k in wave:
                msg = MoveMsg(moves[k]) if kind is MoveMsg else AssignMsg(moves[k], r)
                self.send(k, msg)
                self.where[k] = np.asarray(moves[k][-1], dtype=float)
            waiting = set(wave)
            while waiting:
                k, msg = yield self.inbox.get()
                if self._membership(k, msg) or isinstance(msg, ArrivedMsg):
                    waiting.discard(k)
                else:
                    self.early.append((k, msg))

    def collect(self, m: ProbMap, plan: Plan, placed: list[int]):
        """Merge reports until every placed child sent SCAN_COMPLETE ("Interpreting Incoming
        Data").
        """
        p = self.model.params
        gained = dict.fromkeys(placed, 0)
        pending = set(placed)
        los: set[int] = set()
        unscanned: dict[int, np.ndarray] = {}
        queue, self.early = list(self.early), []
        while pending:
            if queue:
                k, msg = queue.pop(0)
            else:
                k, msg = yield self.inbox.get()
            if self._membership(k, msg):  # a lost child is no longer waited for
                pending.discard(k)
                continue
            if k not in gained:  # queued before its sender was lost: nothing waits for it
                continue
            before = m.n_scanned
            if isinstance(msg, PointMsg):
                accepted = m.stamp_point(msg.x, msg.y, msg.sigma)
                if accepted and self.role == "worker" and p.worker_report == "relay":
                    self.send(0, PointMsg(msg.x, msg.y, msg.sigma), origin=self.links[k], hop=1)
            elif isinstance(msg, LosHintMsg):
                los.add(k)
            elif isinstance(msg, MapReportMsg):
                for x, y, sigma in msg.points:
                    m.stamp_point(x, y, sigma)
                unscanned[k] = msg.unscanned
            elif isinstance(msg, ScanCompleteMsg):
                b = self.bubble[k]
                if msg.infer_los or k in los:
                    m.infer_scan(b.x, b.y, b.r)
                else:
                    m.mark_bubble(b.x, b.y, b.r, unscanned.pop(k, ()))
                pending.discard(k)
            gained[k] += m.n_scanned - before
            if k not in pending and gained[k] == 0:
                m.exhaust(*plan.centres[k])  # README "Choices": no-progress guard
                gained[k] = -1


class Queen(Director):
    """The root director, a laptop with no body (README "Choices": the queen): a member of the
    tree and of the comm network (off the arena), but no robot and no Mesa agent.

    Args:
        model: the HST model.

    """

    id = QUEEN
    role = "queen"
    #: The queen never fails (faults strike robots).
    failed = False

    def __init__(self, model: HierarchyModel) -> None:
        self.model = model  # no body to build first: the address book needs the clock
        super().__init__()

    def set_state(self, state: str) -> None:
        """The queen has no body: nothing to show."""

    def staggers(self) -> bool:
        """She sends her workers' subtrees one at a time with ``subtree_transits="staggered"``."""
        return self.model.params.subtree_transits == "staggered"

    def life(self):
        """The operator's START, start-up (bottom-up radius discovery), then one assignment:
        the whole world ("Queen / Worker"); its status ends the run.
        """
        _, start = yield self.inbox.get()
        yield from self.discover()
        world = Rect(start.x_min, start.y_min, start.x_max, start.y_max)
        status = yield from self.assignment(world, cover=())
        self.model.queen_done(status)


class Worker(Director, TreeRobot):
    """A level-1 robot ("Queen / Worker"): a scout to the queen, a director to its scouts.

    Args:
        model: the HST model.
        position: where it starts (m).
        r_min: its minimum bubble radius (m).
        r_max: its maximum bubble radius (m).

    Attributes:
        retained: the map of its last bubble (README "Choices": two regions).
        map_down: the known cells the queen last sent down (MAP_DOWN).

    """

    role = "worker"

    def __init__(
        self, model: HierarchyModel, position: np.ndarray, r_min: float, r_max: float
    ) -> None:
        super().__init__(model, position, "worker_idle", "drive")
        self.r_min, self.r_max = r_min, r_max
        self.retained: MapWindow | None = None
        self.map_down: MapWindow | None = None
        #: Whether the staggering queen still waits for this bubble's SETTLED.
        self.unsettled = False

    def occupied(self) -> list[tuple[float, float]]:
        """Its own place (m): its scouts must not be sent there."""
        return [tuple(self.position)]

    def keep(self, m: ProbMap) -> None:
        """Retain the bubble's map for the next bubbles (README "Choices": two regions)."""
        self.retained = m.window(m.bounds)

    def settled(self) -> None:
        """SETTLED to a staggering queen, once per bubble: its scouts' first moves are done."""
        if self.unsettled:
            self.unsettled = False
            self.send(0, SettledMsg())

    def life(self):
        """Start-up (REQUEST_INFO: learn the scouts' limits, then INFO upward), then the
        command loop ("Queen / Worker"): MOVE, SCAN (cover the bubble with its scouts and report
        it upward), MAP_DOWN.
        """
        yield self.inbox.get()  # REQUEST_INFO
        yield from self.discover()
        self.introduce(self.r_min, self.r_max)
        while True:
            _, cmd = yield self.inbox.get()
            if isinstance(cmd, MapDownMsg):
                self.map_down = cmd.window
            if isinstance(cmd, MoveMsg | AssignMsg):
                yield from self.drive(cmd.waypoints)
                self.send(0, ArrivedMsg())
                self.set_state("worker_idle")
            if isinstance(cmd, ScanMsg | AssignMsg):
                yield from self.cover_bubble(cmd.r)

    def cover_bubble(self, r: float):
        """Cover the bubble of radius ``r`` about itself with its scouts, then MAP_REPORT and
        SCAN_COMPLETE to the queen.
        """
        self.scan_area += math.pi * r * r
        x, y = self.position
        cover = [w.box for w in (self.map_down, self.retained) if w is not None]
        cover.append(self._children_box())
        known = (self.retained, self.map_down)
        self.unsettled = self.model.params.subtree_transits == "staggered"
        yield from self.assignment(Bubble(float(x), float(y), r), cover, known)
        self.settled()  # no round ran: nothing moved, the next subtree may go
        points = np.array(
            self.map.points if self.model.params.worker_report == "batch" else [],
            dtype=float,
        ).reshape(-1, 3)
        raster, _extent = self.map.raster()
        unscanned = self.map.unscanned_points()
        self.send(0, MapReportMsg(points, unscanned, rle_bytes(raster == -1)))
        self.send(0, ScanCompleteMsg(infer_los=False))
        self.set_state("worker_idle")
