"""The unit and meaning of each key of the tangible PSO swarm's summary (Saska et al. 2016);
the common keys are documented in :data:`abm.units.COMMON`.
"""

from abm.units import Quantity

__all__ = ["SUMMARY_UNITS"]

SUMMARY_UNITS = {
    "scenario": Quantity("text", "the area of interest's scenario"),
    "n_mavs": Quantity("count", "MAVs in a swarm distribution (a particle)"),
    "neighbours": Quantity("count", "neighbours each MAV must see to stay localised"),
    "motion_planning": Quantity("flag", "proposals are flown by the motion planner"),
    "initial_velocity": Quantity("text", "how the particles' velocities start"),
    "stop_rule": Quantity("text", "what stops a MAV at a no-fly zone"),
    "iterations_done": Quantity("count", "PSO iterations run"),
    "best_cost": Quantity("1", "cost CF of eq. 1 of the best distribution (sum over cells)"),
    "best_cost_ratio": Quantity("1", "best_cost over the cost of observing nothing"),
    "initial_cost": Quantity("1", "lowest cost CF of the first iteration's distributions"),
    "best_iteration": Quantity("count", "iteration that found the best distribution"),
    "collision": Quantity("flag", "a MAV was stopped by a no-fly zone"),
    "zone_stops": Quantity("count", "MAV stops at no-fly zones"),
    "collision_proposal": Quantity("flag", "a proposal lay in a no-fly zone"),
    "proposals_in_zone": Quantity("count", "proposals in a no-fly zone"),
    "deadlock": Quantity("flag", "the run ended in deadlock (deadlock_share pressed)"),
    "zone_pressed_min": Quantity("1", "least share of particles pressed in the last window"),
    "deadlock_frozen": Quantity("flag", "no particle moved more than frozen_move at the end"),
    "frozen_max_move": Quantity("m", "largest move of a MAV in the last window"),
    "deadlock_best": Quantity("flag", "the best particle was pressed in the whole last window"),
    "swap_conflicts": Quantity("count", "goal conflicts between MAVs"),
    "swap_resolved": Quantity("count", "goal conflicts resolved by swapping"),
    "swap_resolved_pct": Quantity("%", "share of the goal conflicts resolved"),
    "groups": Quantity("count", "connected groups of the best swarm's localisation graph"),
    "best_feasible": Quantity("flag", "the best distribution keeps every MAV localised"),
    "mavs_failed": Quantity("count", "MAVs failed during the deployment"),
    "failure_transition": Quantity("count", "transition at which the first MAV failed"),
    "transitions": Quantity("count", "transitions of the deployment"),
    "localised_at_failure": Quantity("flag", "the survivors were localised at the first failure"),
    "survivors_localised": Quantity("flag", "the survivors stayed localised after it"),
    "deployed_cost": Quantity("1", "cost CF of eq. 1 where the survivors ended"),
    "deployed_cost_ratio": Quantity("1", "deployed_cost over the cost of observing nothing"),
    "tracking_error_max": Quantity("m", "largest distance of a MAV from its reference path"),
    "method": Quantity("text", "how the particles move: tangible (flown) or state_space (jump)"),
    "deploy_time": Quantity("s", "duration of the deployment's flight, until the swarm stopped"),
    "deploy_deadlock": Quantity("flag", "the deployment stopped short of the planned b_g"),
    "reach_time": Quantity("s", "time to reach the planned b_g (NaN: never reached)"),
    "plan_unlocalised": Quantity("flag", "the plan flown unchecked loses a MAV's k neighbours"),
    "plan_unlocalised_time": Quantity("s", "flight time of the unchecked plan with a MAV lost"),
    "plan_collision": Quantity(
        "flag", "the plan flown unchecked brings MAVs within d_min or into a zone"
    ),
}
