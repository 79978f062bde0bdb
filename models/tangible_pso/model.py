"""TangiblePSOModel: swarm distribution for surveillance by PSO whose particles must fly
(Saska et al. 2016).

Every PSO particle is a virtual swarm of n_r MAVs (:class:`~models.tangible_pso.agents.VirtualMAV`
agents in the framework's space; the altitude is their third coordinate, kept beside the space's
x, y in the model's arrays, one row per virtual MAV). The story of a run, one SimPy
process on the simulated clock (Sect. 5, Fig. 6):

1. The population starts at the depot (Sect. 4) or, each particle, at random in a circle of
   diameter equal to the localisation distance (Fig. 9); the velocities are random.
2. Each iteration: the PSO rules (eqs. 2-5) propose p_j(t); proposals outside the area, in a
   no-fly zone or too close to another MAV are shifted (Fig. 5a); each MAV gets a path (a
   visibility-graph path with goal swapping, or a straight line without motion planning); the
   swarms follow their paths while the clock runs for the transition's flight time and stop
   where a constraint would break (the feasibility check); the realised positions p''_j(t) set
   the velocities (eq. 6) and are evaluated by the cost of eq. 1.
3. After t_max iterations the solution is the history of the best particle.
4. With ``deploy``: the real swarm (n_r :class:`~models.tangible_pso.agents.MAV` agents) flies
   that history, transition by transition; an MAV may fail on the way (the fault injector,
   state "deploying"), and the survivors fly on to their own planned places under the same
   feasibility check (:mod:`models.tangible_pso.deployment`).

``method="state_space"`` is the baseline of Figs. 10-11: in step 2 the particles jump to their
shifted proposals (nothing flies, no time passes) and a distribution that breaks the
constraints costs infinity; the solution is then b_g alone, which step 4 flies from the best
particle's start in one leg, planned and checked as tangible PSO's deployment is.
"""

import networkx as nx
import numpy as np
import simpy

from abm import portable
from abm.errors import ConfigError
from abm.model import SwarmModel
from abm.polygons import inside_any, offset_polygon, padded
from abm.pso import inertia_weight, update_bests, velocity_update
from abm.robot import Robot
from abm.styles import Layer, StateStyle
from abm.visibility_graph import VisibilityPlanner
from models.tangible_pso import published
from models.tangible_pso.agents import MAV, VirtualMAV
from models.tangible_pso.controller import follow_tracked, settle_ticks
from models.tangible_pso.cost import CoverageCost
from models.tangible_pso.deployment import Leg, checked_leg, replanned_leg
from models.tangible_pso.feasibility import OUTCOMES, follow, localised
from models.tangible_pso.flight import fly_open_loop
from models.tangible_pso.params import DEPOT_RADIUS, TangiblePSOParams
from models.tangible_pso.scenario import load_scenario
from models.tangible_pso.transition import plan_paths, shift_proposals
from models.tangible_pso.units import SUMMARY_UNITS

__all__ = ["TangiblePSOModel"]

#: Draws of the random initial circle before giving up (each draws every particle at once).
INIT_TRIES = 2000
#: An MAV of the real swarm reached its planned place when it ended this close to it (m).
REACHED = 0.01
#: The summary's readings of the virtual swarms' flights (Table 1's collision and deadlock,
#: goal swapping), left out with ``method="state_space"``, whose particles do not fly.
FLIGHT_READINGS = ("collision", "zone_stops", "deadlock", "zone_pressed_min", "deadlock_frozen",
                   "frozen_max_move", "deadlock_best", "swap_conflicts", "swap_resolved",
                   "swap_resolved_pct")  # fmt: skip


class TangiblePSOModel(SwarmModel):
    """Tangible PSO: every particle a virtual MAV swarm that must fly to its new position.

    Every field of :class:`TangiblePSOParams` is a keyword of the constructor, e.g.
    ``TangiblePSOModel(neighbours=2, motion_planning=False, seed=1)``.

    Args:
        seed: seed of the model's random generator.
        **params: fields of :class:`TangiblePSOParams`.

    """

    Params = TangiblePSOParams
    STATES = (*OUTCOMES, "deploying", "deployed")
    FAULTS = frozenset({"robot"})
    STATE_STYLES = {
        "free": StateStyle("#56B4E9", marker="o", size=14.0, layer=4.0, label="virtual MAV: free"),
        "stopped": StateStyle("#E69F00", marker="s", size=16.0, layer=5.0,
                              label="virtual MAV: stopped by a swarm constraint"),
        "blocked": StateStyle("#D55E00", marker="X", size=22.0, layer=6.0,
                              label="virtual MAV: stopped at a no-fly zone"),
        "deploying": StateStyle("#009E73", marker="^", size=40.0, layer=8.0,
                                label="MAV flying the deployment"),
        "deployed": StateStyle("#000000", marker="^", size=40.0, layer=8.0,
                               label="MAV done deploying"),
    }  # fmt: skip
    ARROWS_LABEL = "localisation links of the best swarm"
    PUBLISHED = published.PUBLISHED
    CLAIMS = published.CLAIMS
    # the paper's runs end after their iterations (Table 1: 70) or their deployment; a run
    # our time limit stops earlier is a shorter optimisation, not a run of its condition
    CUT_ENDS = ("time limit",)
    # the MAVs are points that fly exactly (a run's "collision" is a stop at a no-fly zone,
    # counted by the model itself): no physical contact to count
    CONTACTS = False
    REPORT = published.REPORT
    APP = "models.tangible_pso.app"
    QUICK = {"particles": 10, "iterations": 12}

    SUMMARY_UNITS = SUMMARY_UNITS

    def __init__(self, *, seed: int | None = None, **params: object) -> None:
        p = self.make_params(**params)
        scenario = load_scenario(p.scenario)
        depot = scenario.depot if p.depot is None else np.asarray(p.depot, dtype=float)
        scenario.check_depot(depot, "depot")
        super().__init__(p, scenario.arena(), seed=seed, comm_range=p.loc_range, physics=False)
        self.task = scenario
        self.depot = depot
        self.cost = CoverageCost(scenario.aoi, scenario.a_max, p.camera_angle, p.z_opt)
        # with motion planning every path comes from the planner (straight where nothing is in
        # the way) and mutual path collisions are swapped away, zones or not
        self.planner = (
            VisibilityPlanner(scenario.zones, p.mav_radius) if p.motion_planning else None
        )
        #: The no-fly zones grown by the MAV radius: what no MAV centre may enter.
        self.zones = [offset_polygon(z, p.mav_radius) for z in scenario.zones]
        self._zone_arr, self._zone_len = padded(self.zones)
        w, h = scenario.size
        r = p.mav_radius
        self.low = np.array([r, r, p.z_opt])
        self.high = np.array([w - r, h - r, p.z_max])
        self.x = self._initial_positions()
        n_p, n = p.particles, p.n_mavs
        for j in range(n_p):  # in row order: VirtualMAV.row = j * n + i
            for i in range(n):
                VirtualMAV(self, j, i, self.x[j, i, :2])
        #: The virtual MAVs' ids in row order, for moving them all at once in the space.
        self._virtual_ids = np.array([r.unique_id for r in self.agents_by_type[VirtualMAV]])
        self._state_idx = np.zeros(n_p * n, dtype=np.int8)  # each row's outcome, as OUTCOMES
        self.iteration = 0
        self.best_cost = np.full(n_p, np.inf)
        self.best_x = self.x.copy()
        self.g = update_bests(self.cost(self.x), self.x, self.best_cost, self.best_x)
        self.best_found = np.zeros(n_p, dtype=np.int64)  # iteration of each personal best
        self.history = [self.x.copy()]  # realised positions after every iteration
        self.plans: list[tuple[np.ndarray, np.ndarray, np.ndarray]] = []
        self._zone_blocked: list[np.ndarray] = []  # (P,) per iteration: an MAV met a zone
        self._moved: list[np.ndarray] = []  # (P,) per iteration: the longest MAV move (m)
        self.proposals_in_zone = 0
        self.conflicts = self.resolved = 0
        #: The largest distance of an MAV from its reference path (m; the follower's).
        self.tracking_error = 0.0
        self._sample()
        self.deployment: dict = {}
        #: The real swarm's flight of the plan (a SimPy process), once it deploys.
        self.flight: simpy.Process | None = None
        self.env.process(self._run())

    # ------------------------------------------------------------------ start
    def _initial_positions(self) -> np.ndarray:
        """Every particle's first swarm ``(P, n, 3)``, feasible (Sect. 4 / Fig. 9)."""
        p = self.params
        n_p, n = p.particles, p.n_mavs
        if p.init == "depot":
            angle = 2 * np.pi * np.arange(n) / n
            radius = DEPOT_RADIUS if p.depot_radius is None else p.depot_radius
            ring = np.stack([portable.cos(angle), portable.sin(angle)], axis=1) * (
                radius if n > 1 else 0
            )
            swarm = np.column_stack([self.depot + ring, np.full(n, p.z_opt)])
            if not self._start_ok(swarm[None])[0]:
                raise ConfigError(
                    f"depot_radius {radius:g} m puts the {n} MAVs' ring outside the area, "
                    f"in a zone, closer than d_min or without {p.neighbours} localised neighbours"
                )
            return np.repeat(swarm[None], n_p, axis=0)
        out = np.empty((n_p, n, 3))
        todo = np.arange(n_p)
        for _ in range(INIT_TRIES):
            radius = 0.5 * p.loc_range * np.sqrt(self.rng.random((len(todo), n)))
            angle = self.rng.uniform(0, 2 * np.pi, (len(todo), n))
            xy = (
                self.depot
                + np.stack([portable.cos(angle), portable.sin(angle)], -1) * radius[..., None]
            )
            swarm = np.concatenate([xy, np.full((len(todo), n, 1), p.z_opt)], axis=-1)
            ok = self._start_ok(swarm)
            out[todo[ok]] = swarm[ok]
            todo = todo[~ok]
            if not len(todo):
                return out
        depot = ", ".join(f"{v:g}" for v in self.depot)
        raise ConfigError(
            f"init 'circle': no feasible start for n_mavs={n} MAVs in a circle of diameter "
            f"loc_range {p.loc_range:g} m around the depot ({depot}) (d_min {p.d_min:g} m, "
            f"outside the no-fly zones grown by mav_radius {p.mav_radius:g} m)"
        )

    def _start_ok(self, swarms: np.ndarray) -> np.ndarray:
        """Which swarms lie in the area, outside the zones, and keep the constraints."""
        p = self.params
        in_area = ((swarms >= self.low - 1e-9) & (swarms <= self.high + 1e-9)).all(axis=(-1, -2))
        clear = ~inside_any(swarms[..., :2], self.zones).any(axis=-1)
        return in_area & clear & localised(swarms, p.neighbours, p.d_min, p.loc_range)

    # ------------------------------------------------------------------ the story
    def _run(self):
        yield from self._optimise()
        if self.params.deploy:
            self.flight = self.env.process(self._fly_plan())
            yield self.flight
            # every MAV ends its own behaviour: "deployed", or earlier where it failed
            yield self.env.all_of([mav.process for mav in self.agents_by_type[MAV]])
            self.finish("deployed")
        else:
            self.finish("iterations")

    def _optimise(self):
        p = self.params
        n_p, n = p.particles, p.n_mavs
        shape = (n_p, n, 3) if p.initial_velocity == "component" else (n_p, 1, 3)
        u = self.rng.uniform(-p.initial_speed, p.initial_speed, shape)
        u = np.broadcast_to(u, (n_p, n, 3)).reshape(n_p, n * 3)
        for t in range(1, p.iterations + 1):
            w = inertia_weight(t, p.iterations, p.w_start, p.w_end)
            x = self.x.reshape(n_p, -1)
            u = velocity_update(
                u, x, self.best_x.reshape(n_p, -1), self.best_x[self.g].reshape(-1), self.rng,
                c1=p.c1, c2=p.c2, w=w, u_max=p.u_max,
            )  # fmt: skip
            proposal = (x + u).reshape(n_p, n, 3)
            goal, in_zone = shift_proposals(proposal, self.zones, self.low, self.high, p.d_min)
            self.proposals_in_zone += int(in_zone.sum())
            if p.method == "state_space":  # Figs. 10-11: a jump, nothing flies
                realised, outcome = goal, np.zeros((n_p, n), dtype=np.int8)
                self._zone_blocked.append(np.zeros(n_p, dtype=bool))
            else:
                plans = plan_paths(self.planner, self.x, goal, p.d_min)
                self.conflicts += plans.conflicts
                self.resolved += plans.resolved
                if p.controller == "second_order":
                    realised, outcome, travelled, flown = self._follow_tracked(plans)
                    yield self.env.timeout(flown)
                else:
                    realised, outcome, travelled = follow(
                        self.x, plans.points, plans.count, self._zone_arr, self._zone_len,
                        p.neighbours, p.d_min, p.loc_range, p.speed * p.dt,
                        p.stop_rule == "swarm",
                    )  # fmt: skip
                    yield self.env.timeout(float(travelled.max(initial=0.0)) / p.speed)
                self._zone_blocked.append((outcome == 2).any(axis=-1))
                self.plans.append((plans.points, plans.count, travelled))
            u = (realised - self.x).reshape(n_p, -1)  # eq. 6
            self._moved.append(np.linalg.norm(realised - self.x, axis=-1).max(axis=-1))
            self.x = realised
            self.iteration = t
            cost = self.cost(realised)
            improved = cost < self.best_cost
            self.best_found[improved] = t
            self.g = update_bests(cost, realised, self.best_cost, self.best_x)
            self.history.append(realised.copy())
            self._show(outcome)
            self._sample()

    def _follow_tracked(self, plans):
        """Step 4 with the second-order follower (:mod:`models.tangible_pso.controller`): the
        realised positions, outcomes and reference lengths followed, and the transition's
        flight time (s); the largest tracking error is kept for the summary.
        """
        p = self.params
        lengths = np.linalg.norm(np.diff(plans.points, axis=2), axis=-1).sum(axis=-1)
        step = p.speed * p.dt
        settle = settle_ticks(p.ctrl_omega, p.ctrl_zeta, p.dt)
        ticks = int(np.ceil(lengths.max(initial=0.0) / step)) + settle
        shape = (*lengths.shape, max(ticks, 1), 3)
        kicks = (
            self.rng.normal(0.0, p.ctrl_noise * np.sqrt(p.dt), shape)
            if p.ctrl_noise > 0
            else np.zeros(shape)
        )
        realised, outcome, travelled, flown, worst = follow_tracked(
            self.x, plans.points, plans.count, self._zone_arr, self._zone_len, p.neighbours,
            p.d_min, p.loc_range, step, p.stop_rule == "swarm", p.ctrl_omega**2,
            2 * p.ctrl_zeta * p.ctrl_omega, p.dt, settle, kicks,
        )  # fmt: skip
        self.tracking_error = max(self.tracking_error, float(worst.max(initial=0.0)))
        return realised, outcome, travelled, float(flown.max(initial=0)) * p.dt

    # ------------------------------------------------------------------ the deployment
    def plan(self) -> list[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray | None]]:
        """The deployment plan, per transition: the swarm's planned end ``(n, 3)``, each MAV's
        path waypoints ``(n, w, 3)`` (m), the waypoints in use ``(n,)`` and how far each MAV
        flies along its path ``(n,)`` (m; None: to its end).

        Tangible PSO's plan is the best particle's realised transitions up to b_g (Sect. 5);
        the state-space search's is one leg from the best particle's start to b_g, planned
        as every transition is (visibility graph with goal swapping, or straight lines) and
        flown to its end (Fig. 10).
        """
        p, g = self.params, self.g
        if p.method == "state_space":
            plans = plan_paths(self.planner, self.history[0][g][None], self.best[None], p.d_min)
            points, count = plans.points[0], plans.count[0]
            ends = points[np.arange(len(points)), np.maximum(count, 1) - 1]  # goals swapped
            return [(ends, points, count, None)]
        return [
            (self.history[t][g], *(a[g] for a in self.plans[t - 1]))
            for t in range(1, int(self.best_found[g]) + 1)
        ]

    def _fly_plan(self):
        """The real swarm flies the plan (:meth:`plan`) together (each
        :meth:`MAV.deploy <models.tangible_pso.agents.MAV.deploy>` waits for this), every leg
        under the feasibility check; after a failure the survivors stop, then fly on to their
        planned places of every later transition.
        """
        p, g = self.params, self.g
        pos = self.history[0][g].copy()
        self._launch_swarm(pos)
        alive = np.ones(p.n_mavs, dtype=bool)
        d = self.deployment = {"failed_at": [], "localised_at_failure": [], "trace": []}
        d["began"] = self.env.now
        d["trace"].append((self.env.now, pos.copy(), alive.copy()))
        for t, (goal, points, count, travelled) in enumerate(self.plan(), start=1):
            if alive.all() and travelled is not None:  # a realised transition: flown as it was
                leg = Leg(pos, points, count, travelled, goal, p.speed)
            elif alive.all():  # a plan never checked: the check stops where it must
                leg = checked_leg(
                    pos, points, count, (self._zone_arr, self._zone_len), p.neighbours, p.d_min,
                    p.loc_range, p.speed, p.dt, p.stop_rule == "swarm",
                )  # fmt: skip
            else:
                leg = self._survivors_leg(pos[alive], goal[alive])
            while True:
                began = self.env.now
                try:
                    yield self.env.timeout(leg.duration)
                except simpy.Interrupt:  # an MAV failed: everyone stops where it is
                    here = leg.positions(self.env.now - began)
                    pos[alive] = here
                    now_alive = np.zeros_like(alive)
                    for mav in self.agents_by_type[MAV]:
                        now_alive[mav.row] = not mav.failed
                    survivors = pos[now_alive]
                    d["failed_at"].append(t)
                    d["localised_at_failure"].append(self._localised(survivors))
                    alive = now_alive
                    self._place_mavs(pos)
                    d["trace"].append((self.env.now, pos.copy(), alive.copy()))
                    leg = self._survivors_leg(pos[alive], goal[alive])
                    continue
                pos[alive] = leg.end
                break
            self._place_mavs(pos)
            d["trace"].append((self.env.now, pos.copy(), alive.copy()))
        d["ended"] = self.env.now
        self.deployed = pos
        self.deployed_alive = alive

    def _launch_swarm(self, pos: np.ndarray) -> None:
        """The real swarm at the plan's first positions ``pos`` ``(n_r, 3)``, MAV i in row i,
        each starting its behaviour (:meth:`MAV.deploy <models.tangible_pso.agents.MAV.deploy>`).
        """
        for i in range(self.params.n_mavs):
            mav = MAV(self, i, pos[i, :2])
            mav.start(mav.deploy(self.flight))

    def _survivors_leg(self, start: np.ndarray, goal: np.ndarray) -> Leg:
        p = self.params
        return replanned_leg(
            start, goal, self.planner, (self._zone_arr, self._zone_len), p.neighbours, p.d_min,
            p.loc_range, p.speed, p.dt, p.stop_rule == "swarm",
        )  # fmt: skip

    def _localised(self, swarm: np.ndarray) -> bool:
        """Whether a swarm keeps the constraints (k neighbours each, d_min apart)."""
        p = self.params
        return bool(len(swarm) == 0 or localised(swarm, p.neighbours, p.d_min, p.loc_range))

    def _place_mavs(self, pos: np.ndarray) -> None:
        """The real MAVs' places in the space, each its row of ``pos`` (a failed one stays
        where it failed).
        """
        for mav in self.agents_by_type[MAV]:
            mav.position = pos[mav.row, :2].copy()

    def on_robot_failed(self, robot: Robot) -> None:
        """A real MAV failed while it deployed: the swarm's flight stops the others."""
        if self.flight is not None and self.flight.is_alive:
            self.flight.interrupt("mav failed")

    def _show(self, outcome: np.ndarray) -> None:
        """The virtual MAVs' new places in the space, and their states where they changed."""
        self.place(self._virtual_ids, self.x[..., :2].reshape(-1, 2))
        flat = outcome.reshape(-1)
        changed = np.nonzero(flat != self._state_idx)[0]
        if len(changed):
            virtual = self.agents_by_type[VirtualMAV].to_list()  # row order
            for k in changed:
                virtual[k].set_state(OUTCOMES[flat[k]])
        self._state_idx = flat.copy()

    def _sample(self) -> None:
        self.recorder.sample(
            iteration=self.iteration,
            best_cost=float(self.best_cost[self.g]),
            best_cost_ratio=float(self.best_cost[self.g]) / max(self.cost.total, 1e-12),
        )

    # ------------------------------------------------------------------ the solution
    @property
    def best(self) -> np.ndarray:
        """b_g, the best swarm distribution found ``(n, 3)`` (m)."""
        return self.best_x[self.g]

    def trajectory(self, samples: int = 12) -> np.ndarray:
        """The deployment plan's paths (:meth:`plan`) from the best particle's start to b_g,
        ``(n, m, 3)`` points (m), each transition sampled at ``samples`` points.
        """
        parts = [self.history[0][self.g][:, None, :]]
        for _goal, points, count, travelled in self.plan():
            reach = np.full(len(points), np.inf) if travelled is None else travelled
            parts.append(_prefix_points(points, count, reach, samples))
        return np.concatenate(parts, axis=1)

    def links(self, swarm: np.ndarray | None = None) -> list[tuple[int, int]]:
        """Pairs of MAVs of a swarm (default b_g) that can localise each other."""
        s = self.best if swarm is None else swarm
        p = self.params
        d = np.linalg.norm(s[:, None] - s[None], axis=-1)
        a, b = np.nonzero(np.triu((d >= p.d_min) & (d <= p.loc_range), 1))
        return list(zip(a.tolist(), b.tolist(), strict=True))

    def arrows(self) -> tuple[np.ndarray, np.ndarray]:
        """The best swarm's localisation links, as arrows from one MAV to the other."""
        s = self.best
        pairs = self.links()
        if not pairs:
            return np.zeros((0, 2)), np.zeros((0, 2))
        a, b = (np.array(v) for v in zip(*pairs, strict=True))
        return s[a, :2], s[b, :2] - s[a, :2]

    def layers(self) -> list[Layer]:
        """The AoI map, the best particle's trajectories and its swarm b_g."""
        w, h = self.task.size
        rows, cols = self.task.aoi.shape
        out = [
            Layer("AoI map (A / A_max)", raster=self.task.aoi / self.task.a_max,
                  extent=(0.0, float(cols), 0.0, float(rows)), colour="#009E73"),
            Layer("best particle's trajectories", points=self.trajectory()[..., :2].reshape(-1, 2),
                  colour="#CC79A7", size=3.0),
            Layer("best swarm b_g", points=self.best[:, :2], colour="#000000", size=70.0),
        ]  # fmt: skip
        return out

    # ------------------------------------------------------------------ measurements
    def reporters(self) -> dict:
        """The state counts, and the best cost CF(b_g) for the live page."""
        return {**super().reporters(), "best_cost": lambda m: float(m.best_cost[m.g])}

    def metrics(self) -> dict:
        """The run's results: the best cost, the collision and deadlock readings, the goal
        swapping statistics and the shape of the best swarm (with ``method="state_space"``:
        the method, and no readings of virtual flights, :data:`FLIGHT_READINGS`).
        """
        p = self.params
        blocked = np.array(self._zone_blocked).reshape(-1, p.particles)
        moved = np.array(self._moved).reshape(-1, p.particles)
        window = min(p.deadlock_window, len(blocked))
        last_blocked = blocked[len(blocked) - window :]
        pressed = last_blocked.mean(axis=1) if window else np.zeros(1)
        last_moved = moved[len(moved) - window :]
        graph = nx.Graph()
        graph.add_nodes_from(range(p.n_mavs))
        graph.add_edges_from(self.links())
        g = self.g
        done = len(blocked) == p.iterations
        out = {
            "scenario": self.task.name,
            "n_mavs": p.n_mavs,
            "neighbours": p.neighbours,
            "motion_planning": p.motion_planning,
            "initial_velocity": p.initial_velocity,
            "stop_rule": p.stop_rule,
            "iterations_done": len(blocked),
            "best_cost": float(self.best_cost[g]),
            "best_cost_ratio": float(self.best_cost[g]) / max(self.cost.total, 1e-12),
            "initial_cost": float(self.cost(self.history[0]).min()),
            "best_iteration": int(self.best_found[g]),
            "collision": bool(blocked.any()),
            "zone_stops": int(blocked.sum()),
            "collision_proposal": self.proposals_in_zone > 0,
            "proposals_in_zone": self.proposals_in_zone,
            "deadlock": bool(done and window and (pressed >= p.deadlock_share).all()),
            "zone_pressed_min": float(pressed.min()) if window else 0.0,
            "deadlock_frozen": bool(done and window and last_moved.max() <= p.frozen_move),
            "frozen_max_move": float(last_moved.max()) if window else 0.0,
            "deadlock_best": bool(done and window and last_blocked[:, g].all()),
            "swap_conflicts": self.conflicts,
            "swap_resolved": self.resolved,
            "swap_resolved_pct": (
                100.0 * self.resolved / self.conflicts if self.conflicts else np.nan
            ),
            "groups": nx.number_connected_components(graph),
            "best_feasible": bool(localised(self.best, p.neighbours, p.d_min, p.loc_range)),
            **self._deployment_metrics(),
        }  # fmt: skip
        if p.controller == "second_order":
            out["tracking_error_max"] = self.tracking_error
        if p.method == "state_space":
            out = {"method": p.method, **out}
            for key in FLIGHT_READINGS:
                del out[key]
        return out

    def _deployment_metrics(self) -> dict:
        """With ``deploy``: MAVs failed, the first failure's transition, whether the
        survivors kept their localisation at the first failure and at every realised state
        after it (the ends of the legs; a later failure may break it), and the cost of eq. 1
        where the survivors ended (a failed MAV observes nothing) with its share of the cost
        of observing nothing; how long the flight took, whether it stopped short of b_g (a
        deadlock: the check would not let the swarm on) and, when it did not, the time it took
        to reach b_g; and what the plan breaks when flown to its end with nothing to stop it
        (:func:`~models.tangible_pso.flight.fly_open_loop`, Fig. 10).
        """
        if not self.params.deploy or not hasattr(self, "deployed"):
            return {}
        p, d, alive = self.params, self.deployment, self.deployed_alive
        cost = float(self.cost(self.deployed[alive]))
        after = [self._localised(x[a]) for _t, x, a in d["trace"] if not a.all()]
        plan = self.plan()
        planned_end = plan[-1][0] if plan else self.history[0][self.g]
        off = np.linalg.norm(self.deployed[alive] - planned_end[alive], axis=-1)
        reached = bool((off <= REACHED).all())
        duration = d["ended"] - d["began"]
        starts = [self.history[0][self.g], *(leg[0] for leg in plan)][: len(plan)]
        loop = fly_open_loop(
            [(start, *leg[1:]) for start, leg in zip(starts, plan, strict=True)],
            self.zones, p.neighbours, p.d_min, p.loc_range, p.speed, p.dt,
        )  # fmt: skip
        return {
            "mavs_failed": int((~alive).sum()),
            "failure_transition": d["failed_at"][0] if d["failed_at"] else np.nan,
            "transitions": len(plan),
            "localised_at_failure": float(d["localised_at_failure"][0])
            if d["failed_at"]
            else np.nan,
            "survivors_localised": float(all(after)) if after else np.nan,
            "deployed_cost": cost,
            "deployed_cost_ratio": cost / max(self.cost.total, 1e-12),
            "deploy_time": duration,
            "deploy_deadlock": not reached,
            "reach_time": duration if reached else np.nan,
            "plan_unlocalised": loop.unlocalised > 0,
            "plan_unlocalised_time": loop.unlocalised_time,
            "plan_collision": loop.collided > 0,
        }


def _prefix_points(points: np.ndarray, count: np.ndarray, travelled: np.ndarray, samples: int):
    """Points along each MAV's path up to the length it flew, ``(n, samples, 3)``."""
    n = len(points)
    out = np.empty((n, samples, 3))
    for i in range(n):  # n MAVs of one particle, drawing only
        pts = points[i, : max(int(count[i]), 1)]
        seg = np.linalg.norm(np.diff(pts, axis=0), axis=-1)
        cum = np.concatenate([[0.0], np.cumsum(seg)])
        at = np.linspace(0.0, min(float(travelled[i]), cum[-1]), samples)
        for d in range(3):
            out[i, :, d] = np.interp(at, cum, pts[:, d]) if len(pts) > 1 else pts[0, d]
    return out
