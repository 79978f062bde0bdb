"""The unit and meaning of each key of the SugarMap swarm's summary (Purohit et al. 2013);
the common keys are documented in :data:`abm.units.COMMON`. Times after deployment are on
the coverage clock tau.
"""

from abm.units import Quantity

__all__ = ["SUMMARY_UNITS"]

SUMMARY_UNITS = {
    "algorithm": Quantity("text", "coverage algorithm (sugarmap, random_walk, omstc)"),
    "arena": Quantity("text", "the arena's name"),
    "random_walk": Quantity("text", "the random walk's kind (random_walk only)"),
    "noise_scale": Quantity("1", "scale of the RToF noise (1: the reference set-up)"),
    "heading_model": Quantity("text", "how an explorer's heading drifts"),
    "n_anchors": Quantity("count", "anchors dispersed before coverage"),
    "n_explorers": Quantity("count", "explorers covering"),
    "n_particles": Quantity("count", "particles per explorer's filter (0 without filter)"),
    "t_deploy": Quantity("s", "simulated time when the anchors' deployment ended"),
    "cutoff_fired": Quantity("flag", "InitCutoff landed anchors still flying"),
    "coverage_*": Quantity("%", "true coverage at tau = * s, share of the navigable cells"),
    "overlap_*": Quantity("1", "cell entries per distinct covered cell at tau = * s"),
    "map_error_*": Quantity("1", "mean |P - truth| of the global map at tau = * s"),
    "t50": Quantity("s", "tau when the true coverage reached 50 %"),
    "t80": Quantity("s", "tau when the true coverage reached 80 %"),
    "t90": Quantity("s", "tau when the true coverage reached 90 % (NaN: it never did)"),
    "overlap": Quantity("1", "cell entries per distinct covered cell at the end"),
    "idle": Quantity("count", "explorers idle (no planner target) at the end"),
    "coverage_est": Quantity("%", "estimated coverage: share of cells with P >= COVER_TH"),
    "map_error": Quantity("1", "mean |P - truth| of the global map at the end"),
    "pose_error": Quantity("m", "mean distance of the mean particle from the true position"),
    "signatures": Quantity("count", "RToF signatures stored"),
    "matches": Quantity("count", "signature matches (revisits recognised)"),
    "false_match_rate": Quantity("1", "share of the matches whose two positions differ"),
    "stopped": Quantity("count", "explorers stopped at the end"),
    "failed_anchors": Quantity("count", "anchors failed"),
    "failed_explorers": Quantity("count", "explorers failed"),
}
