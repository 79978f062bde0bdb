"""What Saska et al. (2016) publish about tangible PSO: Table 1 (collisions, deadlocks and
average final cost with and without motion planning at k = 0, 1, 2 required neighbours), the
goal-swapping statistic, Fig. 9's run, and the checkable claims (C1-C6, below) with their tests.

The paper's costs are in its own (unstated) map units; ours are in 1 m cells with A_max = 1,
so the cost levels are shown beside each other and the ratios between rows are what compare.
"""

from functools import partial

from abm.published import Claim, Published, ReportLayout
from models.tangible_pso.claims import BY_PLANNING, TESTS, c4

__all__ = [
    "BASELINE_REPORT",
    "CLAIMS",
    "FAULT_REPORT",
    "FIG9_BEST_ITERATION",
    "FIG10_SETTINGS",
    "FOLLOWER",
    "FIG9_SETTINGS",
    "PUBLISHED",
    "REPORT",
    "SECONDS_PER_RUN",
    "SWAP_RESOLVED_PCT",
    "TABLE1",
    "TABLE1_SETTINGS",
]

#: Table 1 (Sect. 7.1): (k, motion planning) -> (collision runs, deadlock runs, average cost).
TABLE1 = {
    (0, False): (0.98, 0.31, 2.3e5),
    (0, True): (0.013, 0.0, 1.0e5),
    (1, False): (1.00, 0.73, 9.2e5),
    (1, True): (0.045, 0.0, 2.4e5),
    (2, False): (1.00, 0.81, 6.7e7),
    (2, True): (0.098, 0.0, 3.8e6),
}
#: Share of mutual path collisions goal swapping resolved (%, Sect. 5).
SWAP_RESOLVED_PCT = 96.8
#: MATLAB seconds per run: Table 1 (3 MAVs, 40 x 70) and Fig. 9 (6 MAVs, 40 x 20), Sect. 7.1.
SECONDS_PER_RUN = {"table1": 28.0, "fig9": 32.0}
#: Fig. 9: the best swarm distribution was found in the 17th of 20 populations.
FIG9_BEST_ITERATION = 17

#: The settings Table 1 fixes beside k and motion planning (Sect. 7.1: "200 runs of the PSO
#: algorithm with 40 particles and 70 iterations", 3 MAVs in the no-fly-zone scenario).
TABLE1_SETTINGS = {"scenario": "nofly", "n_mavs": 3, "particles": 40, "iterations": 70,
                   "method": "tangible", "controller": "exact"}  # fmt: skip
#: Our second-order follower at its default gains (the paper publishes neither its controller's
#: gains nor its noise): Table 1 with motion planning under it is judged apart.
FOLLOWER = {"controller": "second_order", "ctrl_omega": 2.0, "ctrl_zeta": 0.5, "ctrl_noise": 0.0}
#: Fig. 9's settings (Sect. 7.1: 6 MAVs, k = 2, "20 iterations and 40 PSO particles").
FIG9_SETTINGS = {"scenario": "open", "n_mavs": 6, "neighbours": 2, "particles": 40,
                 "iterations": 20, "method": "tangible"}  # fmt: skip
#: Figs. 10-11's settings (Sect. 7.1: 3 MAVs, "at least one neighbor", a no-fly zone too wide
#: for two MAVs on its opposite sides to see each other; our Table 1 map is one: its zone is
#: 10 m x 14 m against a 5 m localisation range). Population sizes are not given for them.
FIG10_SETTINGS = {"scenario": "nofly", "n_mavs": 3, "neighbours": 1, "motion_planning": True}

_COST_UNITS = "the paper's cost units are not stated (ours: 1 m cells, A_max = 1): levels differ"


def _table1(k: int, mp: bool, col: int, quantity: str, metric: str) -> Published:
    """One Table 1 cell as a level record: shares of runs against our 95 % interval; the
    cost and, with motion planning, the shares that are 0 by construction are only shown.
    """
    value = TABLE1[k, mp][col]
    note = _COST_UNITS if col == 2 else (BY_PLANNING if mp else "")
    return Published(
        f"Table 1, k = {k}, {'with' if mp else 'without'} motion planning",
        quantity,
        {**TABLE1_SETTINGS, "neighbours": k, "motion_planning": mp},
        100.0 * value if col < 2 else value,  # the report shows runs' shares in %
        "level",
        metric,
        "shown" if note else "band",
        source="Table 1 (200 runs, no spread published)",
        note=note,
    )


_QUANTITIES = (
    ("collision runs (%)", "collision"),
    ("deadlock runs (%)", "deadlock"),
    ("average cost after 70 iterations", "best_cost"),
)


def _table1_follower(k: int, col: int, quantity: str, metric: str) -> Published:
    """A Table 1 share with motion planning, judged on runs with our follower, where the
    tracking error lets MAVs hit the zone (the paper's 1.3-9.8 %, Sect. 5).
    """
    return Published(
        f"Table 1, k = {k}, with motion planning, our second-order follower",
        quantity,
        {**TABLE1_SETTINGS, **FOLLOWER, "neighbours": k, "motion_planning": True},
        100.0 * TABLE1[k, True][col],
        "level",
        metric,
        "band",
        source="Table 1 (200 runs, no spread published)",
        note="our follower's gains (omega 2 rad/s, zeta 0.5, no noise): the paper's are not "
        "published",
    )


PUBLISHED = [
    _table1(k, mp, col, quantity, metric)
    for k, mp in TABLE1
    for col, (quantity, metric) in enumerate(_QUANTITIES)
] + [
    _table1_follower(k, col, quantity, metric)
    for k in (0, 1, 2)
    for col, (quantity, metric) in enumerate(_QUANTITIES[:2])
]

#: (id, source, statement, kind, set-up); the test is TESTS[id] where one exists.
_CLAIMS = [
    ("C1", "Table 1", "with motion planning, collisions, deadlocks and cost are lower at every k",
     "QL", "table1: nofly, 3 MAVs, 40 particles, 70 iterations, k = 0/1/2, with and without MP"),
    ("C1b", "Table 1", "more required neighbours give more collisions, deadlocks and cost in "
     "both variants", "QL", "table1"),
    ("C3", "Table 1", "deadlocks are 0 % with motion planning at every k", "Q", "table1"),
    ("C3b", "Table 1", "deadlocks are 0 % with motion planning at every k (with our follower, "
     "where a deadlock can happen)", "Q", "table1 with motion planning, controller "
     "second_order at our gains"),
    ("C4", "Sect. 5", "goal swapping resolves most mutual path collisions (96.8 %)", "Q",
     "table1, motion-planning runs; holds when 96.8 % lies in our 95 % interval"),
    ("C5", "Sect. 7.1, Fig. 9", "with k = 2 and four AoIs in two pairs, the best swarm splits "
     "into two groups by itself", "QL", "fig9: open, 6 MAVs, k = 2, 40 particles, 20 iterations"),
    ("C6", "Sect. 7.1, Figs. 10-11", "an optimiser of CF alone finds a distribution that cannot "
     "be reached with k = 1 past a wide zone; tangible PSO's deployment never breaks it", "QL",
     "fig10: method tangible and state_space, each solution flown by the same planner "
     "(deploy); unchecked it loses localisation, checked it deadlocks"),
    ("C6b", "Sect. 7.1, Figs. 10-11", "the state-space search's solution covers the areas of "
     "interest better than tangible PSO's, which \"does not cover the areas of interest "
     "completely\"", "QL", "fig10: the best costs of both methods"),
]  # fmt: skip

#: The settings each claim's runs must have (the paper's; other runs are set aside).
_CONDITIONS = {"C1": TABLE1_SETTINGS, "C1b": TABLE1_SETTINGS, "C3": TABLE1_SETTINGS,
               "C3b": {**TABLE1_SETTINGS, **FOLLOWER},
               "C4": TABLE1_SETTINGS, "C5": FIG9_SETTINGS, "C6": FIG10_SETTINGS,
               "C6b": FIG10_SETTINGS}  # fmt: skip

#: Claims that hold by construction: labelled so in the report, never counted as reproduced.
_BY_CONSTRUCTION = {"C3": BY_PLANNING}

#: C4 judged against the paper's own share.
_TESTS = {**TESTS, "C4": partial(c4, paper=SWAP_RESOLVED_PCT)}

#: Every checkable claim of the paper with its test (or why it has none).
CLAIMS = [
    Claim(
        i,
        source,
        statement,
        kind,
        setup,
        _TESTS.get(i),
        "",
        condition=_CONDITIONS.get(i, {}),
        by_construction=_BY_CONSTRUCTION.get(i, ""),
    )
    for i, source, statement, kind, setup in _CLAIMS
]

#: MAV failure during the deployment (issue 13, not the paper's): the deployed cost and the
#: survivors' localisation against each MAV's failure hazard.
FAULT_REPORT = ReportLayout(
    x="fault_rate",
    metrics=("deployed_cost_ratio", "localised_at_failure", "survivors_localised", "mavs_failed"),
    labels={
        "fault_rate": "Failure hazard of a deploying MAV (1/s)",
        "deployed_cost_ratio": "Deployed cost (share of CF with nothing seen)",
        "localised_at_failure": "Survivors localised at the failure (share)",
        "survivors_localised": "... and at every state after it (share)",
        "mavs_failed": "MAVs failed per run",
    },
    notes={
        "deployed_cost_ratio": "eq. 1 over the MAVs alive where they ended, divided by the cost "
        "with nothing observed",
        "survivors_localised": "runs with a failure only: after the first failure every survivor "
        "kept k neighbours at every realised state",
    },
)

#: Figs. 10-11 (claims C6, C6b): each method's solution flown by the same planner, the two
#: methods side by side.
BASELINE_REPORT = ReportLayout(
    x="method",
    metrics=(
        "plan_unlocalised",
        "deploy_deadlock",
        "best_cost_ratio",
        "deployed_cost_ratio",
        "reach_time",
        "plan_unlocalised_time",
        "plan_collision",
    ),
    labels={
        "method": "Method (tangible PSO or the state-space search)",
        "plan_unlocalised": "Plans that lose an MAV's k neighbours on the way (share)",
        "deploy_deadlock": "Deployments stopped short of the formation (share)",
        "best_cost_ratio": "Planned cost (share of CF with nothing seen)",
        "deployed_cost_ratio": "Deployed cost (share of CF with nothing seen)",
        "reach_time": "Time to reach the formation (s)",
        "plan_unlocalised_time": "Flight time of the unchecked plan with an MAV lost (s)",
        "plan_collision": "Unchecked plans with MAVs within d_min or in a zone (share)",
    },
    notes={
        "plan_unlocalised": "the plan flown to its end with nothing to stop it (Fig. 10)",
        "deploy_deadlock": "the plan flown under the feasibility check, which stops an MAV "
        "where a constraint would break",
        "reach_time": "runs that reached the formation only",
    },
)

#: Table 1's columns against the required neighbours, one line per variant; the best cost
#: against the iteration.
REPORT = ReportLayout(
    x="neighbours",
    hue="motion_planning",
    metrics=("collision", "deadlock", "best_cost", "collision_proposal", "deadlock_frozen"),
    alternatives=(FAULT_REPORT, BASELINE_REPORT),
    curves=("best_cost",),
    curve_x="iteration",
    curve_spread="sd",
    labels={
        "neighbours": "Required neighbours k",
        "motion_planning": "Motion planning",
        "collision": "Collision runs (share)",
        "deadlock": "Deadlock runs (share)",
        "best_cost": "Best cost CF (1 m cells, A_max = 1)",
        "collision_proposal": "Runs with a proposal in a zone (share)",
        "deadlock_frozen": "Runs with every particle frozen (share)",
        "iteration": "PSO iteration",
    },
    notes={
        "collision": "a run counts when the feasibility check stopped an MAV at a no-fly zone",
        "deadlock": "a run counts when, in each of its last 10 iterations, at least half the "
        "particles had an MAV stopped at a no-fly zone",
    },
)
