"""Parameters of the tangible-PSO model, with the paper's values and our readings.

Source: Saska, Vonasek, Chudoba, Thomas, Loianno, Kumar (2016), "Swarm distribution and
deployment for cooperative surveillance by micro-aerial vehicles", J. Intell. Robot. Syst.
The paper publishes the PSO settings (c1 = 2.5, c2 = 2.0, u_max = inf, w = 1, Sect. 7), the
population sizes of its experiments, the 1.2 m minimum distance (Sect. 7.2) and the cost of
eq. 1; every geometric value and every reading of a step it describes in words is ours
(the model's README, "What we had to choose") and marked so.
"""

import math
from dataclasses import dataclass

from abm.errors import ConfigError
from abm.params import SwarmParams, param

__all__ = ["DEPOT_RADIUS", "TangiblePSOParams"]

#: The depot ring's radius when ``depot_radius`` is None (m; ours).
DEPOT_RADIUS = 1.5


@dataclass(frozen=True)
class TangiblePSOParams(SwarmParams):
    """Everything a tangible-PSO run can vary (SI units; angles in degrees).

    Attributes:
        scenario: the surveillance task: "nofly" (Table 1: 30 m x 30 m, one no-fly zone between
            the depot and two AoIs), "open" (Fig. 9: 40 m x 40 m, four AoIs in two pairs) or
            a scenario TOML file (ours: the paper gives no geometry).
        depot: where the swarm starts (x, y, m); None: the scenario's depot.
        n_mavs: n_r, MAVs of the swarm (3 in Table 1, 6 in Fig. 9).
        neighbours: k, the localised neighbours every MAV must keep during the whole deployment
            and at the end (0, 1, 2 in Table 1), Sects. 3, 7.1.
        motion_planning: True: visibility-graph paths around the no-fly zones with goal
            swapping (tangible PSO); False: straight moves stopped at a zone's border (Table
            1's baseline), Sect. 7.1. With ``method="state_space"`` it only decides how the
            solution is flown (``deploy``).
        method: "tangible": every particle is a virtual swarm that flies each transition
            (Sect. 5, the paper's method); "state_space": the "standard state-space search"
            of Figs. 10-11 (Sect. 7.1), the same PSO whose particles jump to their (shifted)
            proposals without flying, so it "optimizes only the cost function (1)" and "the
            existence of feasible trajectories to reach this position is not checked"; the
            final distribution must still keep the constraints (a proposal that breaks them
            costs infinity: ours, the paper's Fig. 10 breaks them only on the way). With
            ``deploy`` its best distribution is flown from the best particle's start in one
            leg by the same planner and feasibility check as tangible PSO's deployment.
        particles: PSO particles, each a virtual swarm (40 in Table 1 and Fig. 9).
        iterations: t_max, PSO iterations (70 in Table 1, 20 in Fig. 9).
        c1: weight of a particle's own best, eq. 3 (2.5, Sect. 7).
        c2: weight of the population's best, eq. 3 (2.0, Sect. 7).
        w_start: inertia at the first iteration, eq. 5 (1: no decrease, Sect. 7).
        w_end: inertia at the last iteration, eq. 5 (1, Sect. 7); below w_start: linear
            decrease.
        u_max: per-component velocity limit (m; inf, Sect. 7).
        initial_speed: initial velocities are U[-initial_speed, initial_speed] per component
            (m; ours: 15, half the side of Table 1's area. The paper does not say; our first
            reading of 1 m leaves the whole population oscillating around the depot, where
            the cost of eq. 1 is flat, so no run improves on its start: see the README).
        initial_velocity: "component": every coordinate of every MAV draws its own initial
            velocity (standard PSO); "swarm": each virtual swarm draws one velocity its MAVs
            share, so it first flies as a formation (ours: the paper does not say).
        init: "depot": every particle starts from one depot configuration (Sect. 4), the MAVs
            evenly on a ring of radius depot_radius; "circle": each particle's MAVs at random
            in a circle of diameter loc_range around the depot (Fig. 9, Sect. 7.1), drawn
            until they keep the constraints.
        depot_radius: radius of the depot ring (m; ours); None: 1.5 m. Only with
            init="depot" (refused with "circle", where it would not act).
        loc_range: maximal localisation distance of the omnidirectional relative-localisation
            sensor (m; ours: 5, Sect. 7.1 gives none).
        d_min: minimum distance between MAVs (m; 1.2, Sect. 7.2).
        mav_radius: collision radius of an MAV around which paths keep clear of the no-fly
            zones (m; ours: half d_min, a cylinder instead of the two cones of Fig. 2b).
        camera_angle: theta, the surveillance camera's viewing angle (deg; ours).
        z_opt: the "optimal" altitude of eq. 1, which is also the lowest allowed (m; ours).
        z_max: the highest allowed altitude (m; ours).
        speed: flight speed along the paths; a transition lasts its longest path / speed
            on the simulated clock (m/s; ours: a point mass at 2 m/s; at least 1 cm/s, as the
            feasibility check walks each path in ticks of speed * dt and a slower flight
            overflowed its tick count).
        dt: tick of the feasibility check: the MAVs follow their paths in ticks of dt, the
            constraints checked after each, so the longest path moves speed * dt per tick
            (s; ours: 0.05 s, 10 cm at 2 m/s).
        stop_rule: "mav": only the MAVs that would break a constraint stop and the rest go on
            (the whole swarm stops when that is not enough); "swarm": the whole swarm stops at
            the first broken constraint (ours, the reading of Sect. 5's "the paths are
            shortened to such a position where all constraints are still satisfied").
        deadlock_window: last iterations over which a deadlock is judged (all of them in a
            shorter run; ours: 10).
        deadlock_share: a run ends in deadlock when, in each of the last deadlock_window
            iterations, at least this share of the particles had an MAV stopped by a no-fly
            zone (ours: the reading of "the movement of PSO particles was stopped due to the
            non-fly zone", Sect. 7.1).
        frozen_move: a particle "moved" in an iteration when one of its MAVs moved more than this
            (m; ours: 1 cm), for the alternative deadlock reading ``frozen`` (README "What we had to
            choose": deadlock run).
        controller: "exact": the MAVs track their paths exactly (point masses, ours);
            "second_order": each MAV follows its path with a second-order controller with
            tracking error (Sect. 6, Fig. 12's overshoot; ours, the paper's controller and
            gains are not published), in the feasibility check of the optimisation, so an MAV that
            overshoots a corner into a no-fly zone is a collision with motion planning too
            (:mod:`models.tangible_pso.controller`). Not with ``deploy`` or
            ``method="state_space"`` (not built there).
        ctrl_omega: omega, the follower's natural frequency (rad/s; ours). Only with
            controller="second_order"; omega * dt at most 0.5 (the integration's stability).
        ctrl_zeta: zeta, the follower's damping ratio (ours: 0.5, an overshoot as in Fig. 12).
            Only with controller="second_order".
        ctrl_noise: sigma, the intensity of the white acceleration noise on the follower
            (m s^-1.5; ours: 0). Only with controller="second_order".
        deploy: after the optimisation the real swarm (n_r more robots) flies the best
            particle's realised transitions to b_g (Sects. 5-6; ours: the paper plans the
            deployment but does not fly it in simulation). Needed for MAV failures
            (``fault_rate`` / ``fault_times``: only the real MAVs fail, while they deploy).

    """

    scenario: str = param("nofly")
    depot: tuple[float, float] | None = param(None)
    n_mavs: int = param(3, low=1, high=50, integer=True, shown=(1, 8))
    neighbours: int = param(1, low=0, integer=True, shown=(0, 5))
    motion_planning: bool = param(True)
    method: str = param("tangible", choices=("tangible", "state_space"))
    particles: int = param(40, low=1, high=2000, integer=True, shown=(2, 80))
    iterations: int = param(70, low=1, high=10000, integer=True, shown=(10, 150))
    c1: float = param(2.5, low=0.0)
    c2: float = param(2.0, low=0.0)
    w_start: float = param(1.0, low=0.0)
    w_end: float = param(1.0, low=0.0)
    u_max: float = param(math.inf, low=0.0, high=math.inf, low_open=True)
    initial_speed: float = param(15.0, low=0.0)
    initial_velocity: str = param("swarm", choices=("component", "swarm"))
    init: str = param("circle", choices=("circle", "depot"))
    depot_radius: float | None = param(None, low=0.0, low_open=True)
    loc_range: float = param(5.0, low=0.0, low_open=True)
    d_min: float = param(1.2, low=0.0, low_open=True)
    mav_radius: float = param(0.6, low=0.0)
    camera_angle: float = param(90.0, low=0.0, high=180.0, low_open=True)
    z_opt: float = param(5.0, low=0.0, low_open=True)
    z_max: float = param(15.0, low=0.0, low_open=True)
    speed: float = param(2.0, low=0.01)
    dt: float = param(0.05, low=0.0, low_open=True)
    stop_rule: str = param("mav", choices=("mav", "swarm"))
    deadlock_window: int = param(10, low=1, integer=True)
    deadlock_share: float = param(0.5, low=0.0, high=1.0, low_open=True)
    frozen_move: float = param(0.01, low=0.0)
    controller: str = param("exact", choices=("exact", "second_order"))
    ctrl_omega: float = param(2.0, low=0.0, low_open=True)
    ctrl_zeta: float = param(0.5, low=0.0, low_open=True)
    ctrl_noise: float = param(0.0, low=0.0)
    deploy: bool = param(False)
    time_limit: float = param(1.0e6, low=0.0, low_open=True)
    step_duration: float = param(10.0, low=0.0, low_open=True)
    trace_interval: float | None = param(None, low=0.0, low_open=True)

    def __post_init__(self) -> None:
        super().__post_init__()
        if self.neighbours >= self.n_mavs:
            raise ConfigError(
                f"neighbours (k) must be less than n_mavs = {self.n_mavs}, got {self.neighbours}"
            )
        if self.z_max < self.z_opt:
            raise ConfigError(f"z_max must be >= z_opt = {self.z_opt:g} m, got {self.z_max:g}")
        if self.loc_range < self.d_min:
            raise ConfigError(
                f"loc_range must be >= d_min = {self.d_min:g} m, got {self.loc_range:g}"
            )
        if self.depot_radius is not None and self.init != "depot":
            raise ConfigError(
                f"depot_radius {self.depot_radius:g} m only acts with init='depot', "
                f"got init={self.init!r}"
            )
        if "robot" in self.fault_kinds and (
            not self.deploy or not set(self.fault_states) <= {"deploying"}
        ):
            given = ", ".join(
                f"{k}={getattr(self, k)!r}"
                for k in ("fault_rate", "fault_times")
                if getattr(self, k)
            )
            raise ConfigError(
                f"{given}: MAV failures are modelled while the real swarm deploys: set "
                "deploy=True (and leave fault_states empty or ('deploying',)), got "
                f"deploy={self.deploy}, fault_states={self.fault_states!r}"
            )
        self._check_controller()
        if self.w_end > self.w_start:
            raise ConfigError(
                f"w_end must be <= w_start = {self.w_start:g} (eq. 5 decreases), got {self.w_end:g}"
            )

    def _check_controller(self) -> None:
        """The follower's settings act only with it, and it only where it is built."""
        defaults = {"ctrl_omega": 2.0, "ctrl_zeta": 0.5, "ctrl_noise": 0.0}
        if self.controller == "exact":
            changed = [
                f"{k}={getattr(self, k):g}" for k, v in defaults.items() if getattr(self, k) != v
            ]
            if changed:
                raise ConfigError(
                    f"{', '.join(changed)} {'acts' if len(changed) == 1 else 'act'} only with "
                    "controller='second_order', got controller='exact'"
                )
            return
        if self.deploy or self.method != "tangible":
            raise ConfigError(
                "controller='second_order' acts in tangible PSO's feasibility check only: set "
                f"method='tangible' and deploy=False, got method={self.method!r}, "
                f"deploy={self.deploy}"
            )
        if self.ctrl_omega * self.dt > 0.5:
            raise ConfigError(
                f"ctrl_omega * dt must be <= 0.5 for a stable integration, got "
                f"{self.ctrl_omega:g} rad/s * {self.dt:g} s = {self.ctrl_omega * self.dt:g}"
            )
