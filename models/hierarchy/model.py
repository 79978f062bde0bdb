"""HierarchyModel: a hierarchical swarm (queen, workers, scouts) mapping a room by bubble
coverage (Alunni et al. 2011).

The story of a run: the operator sends START to the queen; every director learns its children's
bubble limits bottom-up (REQUEST_INFO / INFO); the queen then covers the whole world with its
workers' bubbles, each worker covers its bubble with its scouts' bubbles, and the scouts scan
with their IR sensors. Every message travels over the framework's comm network, whose tree
policy refuses any link but parent/child, and is logged (kind, sender, receiver, items, bytes).
Robots drive their smoothed paths at 0.3048 m/s through the framework's physics (one vectorised
path-following controller for every body). The run ends when the queen's coverage call returns
COMPLETE (or CANNOT_COMPLETE).

The queen has no body ("a laptop", no position in the arena; README "Choices": the queen): she is a
comm node off the arena (a node without a position, whose radio reaches everyone, limited by the
tree policy to her workers) and not a Mesa agent, so she is never drawn, never occupies a cell and
never collides; she still counts in N = 1 + W + W S. Workers and scouts are robots
(:class:`~models.hierarchy.agents.Worker`, :class:`~models.hierarchy.agents.Scout`), and the
model's ``agents`` is the one index of them (``agents_by_type[Worker]``, in creation order).
"""

import math

import numpy as np
from mesa.agent import AgentSet
from numba import njit

from abm import portable
from abm.clock import call_later
from abm.comms import MessageLog, RingLinks, Shadowing, TreeLinks
from abm.model import SwarmModel
from abm.neighbours import new_pairs, same_keys
from abm.pathfollow import PathFollower, ground_robot
from abm.robot import Robot
from abm.styles import Layer, StateStyle
from models.hierarchy import published
from models.hierarchy.agents import QUEEN, Director, LinkLost, Member, Queen, Scout, Worker
from models.hierarchy.coverage import Plan, Status
from models.hierarchy.flat import FlatHolder, FlatScout, ring_order
from models.hierarchy.params import HierarchyParams
from models.hierarchy.probmap import ProbMap, Rect
from models.hierarchy.protocol import KINDS, SettledMsg, StartMsg
from models.hierarchy.units import SUMMARY_UNITS
from models.hierarchy.world import build_world, start_layout

__all__ = ["BODY_SIDE", "QUEEN", "HierarchyModel"]

#: Side of a scout's body (m): the 6-inch cube of the report ("Scout").
BODY_SIDE = 0.1524
#: Nudge (m) that puts a ray's hit point inside the obstacle it hit, not on its surface.
HIT_NUDGE = 1e-6


class HierarchyModel(SwarmModel):
    """A queen, ``workers`` workers and ``scouts_per_worker`` scouts each map the world.

    Every field of :class:`HierarchyParams` is a keyword of the constructor, e.g.
    ``HierarchyModel(workers=3, scouts_per_worker=4, seed=1)``.

    Args:
        seed: seed of the model's random generator (start jitter, boxes, value ties).
        **params: fields of :class:`HierarchyParams`.

    """

    Params = HierarchyParams
    STATES = (
        "scout_idle",
        "scout_driving",
        "scout_scanning",
        "worker_idle",
        "worker_driving",
        "worker_directing",
    )
    FAULTS = frozenset({"robot"})
    STATE_STYLES = {
        "scout_idle": StateStyle("#0072B2", marker="o", size=30.0, label="scout (idle)"),
        "scout_driving": StateStyle("#56B4E9", marker="o", size=30.0, label="scout (driving)"),
        "scout_scanning": StateStyle("#009E73", marker="o", size=40.0, label="scout (scanning)"),
        "worker_idle": StateStyle("#E69F00", marker="s", size=60.0, layer=7.0,
                                  label="worker (idle)"),
        "worker_driving": StateStyle("#D55E00", marker="s", size=60.0, layer=7.0,
                                     label="worker (driving)"),
        "worker_directing": StateStyle("#CC79A7", marker="s", size=60.0, layer=7.0,
                                       label="worker (directing its scouts)"),
    }  # fmt: skip
    PUBLISHED = published.PUBLISHED
    CENSORED = published.CENSORED
    # the report's runs end by the queen's coverage call (complete, or it gives up); a run our
    # time limit stops first is cut short: its claims are not judged on it
    CUT_ENDS = ("time limit",)
    CLAIMS = published.CLAIMS
    REPORT = published.REPORT
    APP = "models.hierarchy.app"
    QUICK = {"workers": 2, "scouts_per_worker": 2, "world_size": 4.0, "worker_spacing": 1.6}

    SUMMARY_UNITS = SUMMARY_UNITS

    def __init__(self, *, seed: int | None = None, **params: object) -> None:
        p = self.make_params(**params)
        super().__init__(
            p,
            lambda rng: self._world(p, rng),
            seed=seed,
            comm_range=p.comm_range,
            latency=p.latency,
            message_loss=p.message_loss,
            shadowing=Shadowing(sd=0.0, through_walls=True),
            flight=ground_robot(p.speed, BODY_SIDE / 2, p.dt),
        )
        self.world_rect = Rect(0.0, 0.0, self.arena.width, self.arena.height)
        angles = np.deg2rad(np.arange(0.0, 360.0, p.scan_step))
        #: Unit directions of an IR sweep's rays, one every ``scan_step`` degrees (the same
        #: for every sweep of the run).
        self.ray_directions = np.stack([portable.cos(angles), portable.sin(angles)], axis=1)
        self.follower = PathFollower(self.physics, p.speed)
        self.physics.controller = self
        self.tree = TreeLinks()
        self.comms.policy = self.tree
        self.comms.log = MessageLog()
        self.robot_proximity_events = 0
        self.sibling_proximity_events = 0
        self.plans: list[dict] = []
        self.path_cells_blocked = 0
        self.completion_status: str | None = None
        self.reattached = 0
        self.completion_time: float | None = None
        self._truth: np.ndarray | None = None  # free cells of the queen's grid (true world)
        self._build_tree()
        #: Scout pairs (``min * scouts + max``, by scout index) closer than a body at the
        #: last tick, sorted.
        self._near = np.zeros(0, dtype=np.int64)
        self.env.process(self._operator())

    # ------------------------------------------------------------------ set-up
    def _world(self, p: HierarchyParams, rng: np.random.Generator):
        size = p.world_size
        workers, scouts = start_layout(p, size, size, rng)
        self._starts = (workers, scouts)
        arena = build_world(p, np.concatenate([workers, scouts.reshape(-1, 2)]), rng)
        if arena.width != size or arena.height != size:
            workers, scouts = start_layout(p, arena.width, arena.height, rng)
            self._starts = (workers, scouts)
        self._check_starts(arena, np.concatenate([workers, scouts.reshape(-1, 2)]))
        return arena

    @staticmethod
    def _check_starts(arena, starts: np.ndarray) -> None:
        """Every body must start on free ground with its whole footprint free."""
        from abm.errors import ConfigError

        half = BODY_SIDE / 2
        corners = np.concatenate(
            [starts + np.array([dx, dy]) for dx in (-half, half) for dy in (-half, half)]
        )
        if not (arena.is_free(starts).all() and arena.is_free(corners).all()):
            raise ConfigError(
                f"start_layout={arena.name!r}: a robot would start inside an obstacle or "
                "outside the world (unreachable start); choose another start_layout or world"
            )

    def _build_tree(self) -> None:
        """The queen (or the flat arms' map holder), the workers and the scouts, linked as the
        topology says; then every member's life starts (the queen's first, then the robots' in
        creation order).
        """
        p = self.params
        workers, scouts = self._starts
        if p.topology in ("fc", "ring"):
            self._build_flat(scouts.reshape(-1, 2))
        else:
            self.queen = Queen(self)
            self.tree.attach(QUEEN, None)
            self.comms.add(QUEEN, None)
        if p.topology == "star":
            for s, spos in enumerate(scouts.reshape(-1, 2)):
                self._join(self._scout(spos), self.queen, s + 1)
        if p.topology == "hst":
            for w, wpos in enumerate(workers):
                worker = Worker(self, wpos, p.worker_r_min_value, p.worker_r_max)
                self._join(worker, self.queen, w + 1)
                for s, spos in enumerate(scouts[w]):
                    self._join(self._scout(spos), worker, s + 1)
        scouts = self.scouts()
        ids = np.array(scouts.get("unique_id"), dtype=np.int64)
        self._scout_of = np.full(max(self.agents.get("unique_id")) + 1, -1, dtype=np.int64)
        self._scout_of[ids] = np.arange(len(ids))
        self._scout_rows = self.rows_of(ids)
        # first parents (README "Choices": wave-order and proximity diagnostics), as codes
        # equal where the parents are
        codes: dict[object, int] = {}
        self._parent_code = np.array(
            [codes.setdefault(parent, len(codes)) for parent in scouts.get("parent")],
            dtype=np.int64,
        )
        self.env.process(self.queen.life())
        # a robot's life runs as its process: a failure of the body interrupts it
        self.agents.do(lambda robot: robot.start(robot.life()))

    def _scout(self, position: np.ndarray) -> Scout:
        scout = (FlatScout if self.params.topology in ("fc", "ring") else Scout)(self, position)
        self.faults.exempt(scout)  # only workers fail in this model
        return scout

    def _build_flat(self, scouts: np.ndarray) -> None:
        """The map holder and the scouts on a complete graph (FC) or a ring (README, "The message
        comparison").
        """
        self.queen = holder = FlatHolder(self)
        for spos in scouts:
            self._scout(spos)
        ids = self.scouts().get("id")
        if self.params.topology == "ring":
            self.comms.policy = RingLinks(ring_order(holder.id, ids, scouts))
        else:
            self.comms.policy = None
        self.tree.attach(holder.id, None)
        self.comms.add(holder.id, None)
        for s, scout in enumerate(self.scouts()):
            self._join(scout, holder, s + 1)

    def _join(self, child: Member, parent: Member, local: int) -> None:
        self.tree.attach(child.id, parent.id)  # the simulator's record of who is whose child
        self.comms.add(child.id, child.position.copy())
        child.link(0, parent.id)
        parent.link(local, child.id)

    def _operator(self):
        """M10: the operator starts the queen with the bounds of the area to map."""
        yield self.env.timeout(0)
        w = self.world_rect
        start = StartMsg(w.x_min, w.y_min, w.x_max, w.y_max)
        root = self.queen.id
        self.comms.log.record(self.env.now, "operator", root, start.KIND, 0, start.nbytes)
        self.queen.inbox.put((None, start))

    # ------------------------------------------------------------------ the members
    def scouts(self) -> AgentSet:
        """The scouts (the flat arms' too), in creation order."""
        return self.agents.select(agent_type=Scout)

    def workers(self) -> AgentSet:
        """The workers, in creation order (none in the star and flat arms)."""
        return self.agents.select(agent_type=Worker)

    def directors(self) -> list[Director]:
        """The queen (or the map holder), then the workers."""
        return [self.queen, *self.workers()]

    def member_ids(self) -> list[object]:
        """Every member's name on the comm network: the queen's, then the robots' ids."""
        return [self.queen.id, *self.agents.get("id")]

    def member(self, node_id: object) -> Member:
        """The member with this name on the comm network: the queen, or the robot of that id."""
        if node_id == self.queen.id:
            return self.queen
        return self.robot(int(node_id))

    def deliver(self, src: object, dst: object, msg) -> None:
        """The comm network delivered ``msg``: into the receiver's inbox."""
        self.member(dst).receive(src, msg)

    # ------------------------------------------------------------------ failures
    def on_robot_failed(self, robot: Robot) -> None:
        """A worker failed (the injector took it off the radio network, stopped it and ended
        its process): its parent and children notice when their heartbeat watchdogs time out.
        Scouts are exempt from failures: an orphan must be able to re-attach.
        """
        call_later(self.env, self.params.heartbeat_timeout, self._heartbeat_lost, robot)

    def _heartbeat_lost(self, failed: Worker) -> None:
        """Every live neighbour of the ``failed`` worker finds a LinkLost in its inbox."""
        for other in failed.links.values():
            peer = self.member(other)
            if not peer.failed:
                peer.inbox.put((peer.local_of(failed.id), LinkLost()))

    def reattach(self, orphan: Scout) -> None:
        """An orphan joins the queen's children: the tree's record, both address books and
        its radio links change; logged as a ``reattach`` event.
        """
        queen, old = self.queen, orphan.parent
        self.tree.reattach(orphan.id, queen.id)
        orphan.link(0, queen.id)
        queen.link(queen.new_local(), orphan.id)
        self.comms.move(orphan.id, orphan.position.copy())
        self.reattached += 1
        self.recorder.log("reattach", orphan.unique_id, old_parent=old, parent=str(queen.id))

    def has_children(self, node_id: object) -> bool:
        """Whether a node directs others (the simulator's view; a parent learns it from the
        INFO radii it gets, never the count).
        """
        return bool(self.tree.children(node_id))

    def sense(self, position: np.ndarray, r: float) -> np.ndarray:
        """One IR sweep from ``position`` up to ``r``: hit points ``(k, 2)`` (m), one per ray
        that meets an obstacle within ``r`` (one per hit cell with ``dedupe_points_per_cell``).
        """
        p = self.params
        dirs = self.ray_directions
        dist = self.arena.raycast(position, dirs, r)
        hit = dist < r - 1e-9
        if not hit.any():
            return np.empty((0, 2))
        points = position + dirs[hit] * (dist[hit] + HIT_NUDGE)[:, None]
        if p.dedupe_points_per_cell:
            cells = np.floor(points / p.cell_size).astype(np.int64)
            _, first = np.unique(cells, axis=0, return_index=True)
            points = points[np.sort(first)]
        return points

    def control(self, physics) -> tuple[np.ndarray, np.ndarray]:
        """The physics' controller: the path follower, plus the proximity diagnostic."""
        desired, done = self.follower.control(physics)
        self._proximity(physics)
        return desired, done

    def _proximity(self, physics) -> None:
        """Count scout pairs whose centres come closer than one body width while one moves
        (``robot_proximity_events``, README "Choices": wave-order and proximity diagnostics; a pair
        counts once per approach).
        """
        near, new, siblings = _approaches(
            self.space.agent_positions, self._scout_rows, self._scout_of, physics.ids,
            BODY_SIDE, self._near, self._parent_code,
        )  # fmt: skip
        if near is not None:
            self._near = near
            self.robot_proximity_events += new
            self.sibling_proximity_events += siblings

    def log_plan(self, director: Director, m: ProbMap, plan: Plan) -> None:
        """Record a round's bubbles and paths (the invariant tests read them)."""
        for k, (x, y) in plan.centres.items():
            self.recorder.log(
                "bubble", director.unique_id if isinstance(director, Robot) else None,
                director=str(director.id), child=str(director.links[k]), x=x, y=y,
                r=plan.radius, round=director.iterations, known_free=m.known_free(x, y),
                in_bounds=m.in_bounds(x, y),
            )  # fmt: skip
        for k, path in {**plan.idle_moves, **plan.paths}.items():
            self.path_cells_blocked += m.known_blocked_on(path)  # the path's own cells
            self.plans.append(
                {"director": director.id, "child": director.links[k], "path": path,
                 "round": director.iterations, "r": plan.radius}
            )  # fmt: skip

    def queen_done(self, status: Status) -> None:
        """The queen's coverage call returned COMPLETE or CANNOT_COMPLETE: the run is over."""
        self.completion_status = status.value
        self.completion_time = float(self.env.now)
        self.finish(status.value)

    # ------------------------------------------------------------------ results
    def metrics(self) -> dict:
        """Per-level scan area and drive distance, iterations, completion time, message counts
        and diagnostics.

        Scan areas are in m^2 and drive distances in m, like every length the model keeps (the
        world, the bubbles' radii r and the paths are built in metres). The report gives them
        in cm^2 and cm ("Data Collection", Figs. 36-38): 1 m^2 = 10^4 cm^2, 1 m = 100 cm.
        """
        p = self.params
        scouts, workers = self.scouts(), self.workers()
        log = self.comms.log.frame()
        task = log[log["phase"] == "task"]
        load = self.comms.log.load(log)
        out = {
            "topology": p.topology,
            "N": 1 + len(self.agents),
            "links": self.comms.graph.number_of_edges(),
            "W": p.workers,
            "S": p.scouts_per_worker,
            "scouts": len(scouts),
            "complete": float(self.completion_status == Status.COMPLETE.value),
            "completion_time": self.completion_time if self.completion_time else math.nan,
            "scout_scan_area": float(np.mean(scouts.get("scan_area"))),
            "worker_scan_area": _mean(workers.get("scan_area")),
            "queen_scan_area": self.arena.width * self.arena.height,
            "scout_drive": float(np.mean(scouts.get("drive_distance"))),
            "worker_drive": _mean(workers.get("drive_distance")),
            "queen_iterations": self.queen.iterations,
            "worker_iterations": _mean(workers.get("iterations")),
            "known_free_fraction": self.known_free_fraction(),
            "wave_order_violations": sum(d.wave_order_violations for d in self.directors()),
            "robot_proximity_events": self.robot_proximity_events,
            "sibling_proximity_events": self.sibling_proximity_events,
            "path_cells_blocked": self.path_cells_blocked,
            "stalled_moves": self.follower.stalled,
            "workers_failed": sum(workers.get("failed")),
            "reattached": self.reattached,
            "messages": len(log),
            "messages_task": len(task),
            "transmissions_task": self.comms.log.transmissions("task"),
            "messages_startup": int((log["phase"] == "startup").sum()),
            "bytes": int(log["bytes"].sum()),
            "max_node_load": int(load.max()) if len(load) else 0,
            "queen_load": int(load.get(self.queen.id, 0)),
            "worker_load_max": int(max((load.get(w.id, 0) for w in workers), default=0)),
            "scout_load_max": int(max((load.get(s.id, 0) for s in scouts), default=0)),
        }
        counts = log["kind"].value_counts()
        for kind in KINDS:
            out[f"msg_{kind}"] = int(counts.get(kind, 0))
        if p.subtree_transits == "staggered":  # a column of the staggered arm only
            out[f"msg_{SettledMsg.KIND}"] = int(counts.get(SettledMsg.KIND, 0))
        return out

    def known_free_fraction(self) -> float:
        """Share of the world's free cells that the queen's map knows to be free."""
        m = self.queen.map
        if m is None:
            return 0.0
        raster, box = m.raster()
        if self._truth is None:
            h = self.params.cell_size
            ny, nx = raster.shape
            gx, gy = np.meshgrid(box.x_min + (np.arange(nx) + 0.5) * h,
                                 box.y_min + (np.arange(ny) + 0.5) * h)  # fmt: skip
            free = self.arena.is_free(np.stack([gx.ravel(), gy.ravel()], 1)).reshape(ny, nx)
            self._truth = free & ~np.isnan(raster)
        return float((self._truth & (raster == 0)).sum() / max(self._truth.sum(), 1))

    def reporters(self) -> dict:
        """Robots per state and ``known``: % of the free cells the queen's map knows."""
        return {**super().reporters(), "known": lambda m: 100.0 * m.known_free_fraction()}

    def layers(self) -> list[Layer]:
        """The queen's known map (free, obstacles) and every director's current bubbles."""
        out: list[Layer] = []
        m = self.queen.map
        if m is not None:
            raster, box = m.raster()
            extent = (box.x_min, box.x_max, box.y_min, box.y_max)
            out.append(Layer("known free (queen's map)", raster=(raster == 0).astype(float) * 0.5,
                             extent=extent, colour="#009E73"))  # fmt: skip
            out.append(Layer("known obstacle", raster=(raster == 1).astype(float),
                             extent=extent, colour="#000000"))  # fmt: skip
        rings = []
        angle = np.linspace(0.0, 2 * np.pi, 48, endpoint=False)
        for director in self.directors():
            if director.map is None or not director.directing or director.failed:
                continue
            for b in director.bubble.values():
                if b.r < 50:
                    rings.append(
                        np.stack(
                            [b.x + b.r * portable.cos(angle), b.y + b.r * portable.sin(angle)], 1
                        )
                    )
        if rings:
            out.append(Layer("bubbles", points=np.concatenate(rings), colour="#CC79A7", size=2.0))
        return out


@njit(cache=True)
def _approaches(positions, scout_rows, scout_of, flying, reach, near, parent):
    """One tick of the proximity diagnostic, compiled: the scout pairs closer than ``reach``
    with at least one of them flying, as sorted keys ``min * scouts + max`` of their scout
    indices; how many of them were not in ``near`` (the last tick's keys), and how many of
    those are siblings (the same ``parent`` code). The keys are None when they are ``near``
    (the usual tick: no array to return).
    """
    n = scout_rows.size
    keys = np.empty(flying.size * n, dtype=np.int64)
    found = 0
    for robot in flying:
        a = scout_of[robot] if robot < scout_of.size else -1
        if a < 0:
            continue  # not a scout
        ax, ay = positions[scout_rows[a], 0], positions[scout_rows[a], 1]
        for b in range(n):
            if b != a:
                dx = ax - positions[scout_rows[b], 0]
                dy = ay - positions[scout_rows[b], 1]
                if dx * dx + dy * dy < reach * reach:
                    keys[found] = min(a, b) * n + max(a, b)
                    found += 1
    now = np.unique(keys[:found])
    if same_keys(now, near):
        return None, 0, 0
    new = new_pairs(now, near)
    siblings = 0
    for key in new:
        siblings += parent[key // n] == parent[key % n]
    return now, new.size, siblings


def _mean(values: list[float]) -> float:
    """The mean, NaN for no values (an arm without workers)."""
    return float(np.mean(values)) if values else math.nan
