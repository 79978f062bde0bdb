"""A macroscopic model for any model, derived from its own event log.

The robots' state changes (``Robot.set_state`` logs each one) give a state machine
(:mod:`.graph`); binned robot-time per state and transition counts (:mod:`.design`) give
per-robot hazards fitted as Poisson regressions and chosen among a few families by held-out
likelihood (:mod:`.hazards`, :mod:`.rates`); the hazards give the mean-field ODE and its
stochastic twin (:mod:`.meanfield`), which are checked on runs they have not seen
(:mod:`.checks`), with a diagnostic of the well-mixed assumption (:mod:`.mixing`).
"""

from analysis.macroscopic.checks import GRID_POINTS, Checks, check_heldout, observed_counts
from analysis.macroscopic.design import counts_at, covariate_names, exposure_table
from analysis.macroscopic.graph import sinks, sources, state_graph
from analysis.macroscopic.hazards import (
    PIECES,
    Hazard,
    candidate_families,
    fit_hazard,
    heldout_loglik,
)
from analysis.macroscopic.logs import (
    LAUNCH,
    REMOVED,
    RunLog,
    check_states,
    collect_runs,
    run_log,
    stays,
    transitions,
)
from analysis.macroscopic.meanfield import (
    STEP_FRACTION,
    Band,
    expected_counts,
    simulate_counts,
)
from analysis.macroscopic.mixing import ALPHA, GAP, Mixing, default_radius, well_mixed
from analysis.macroscopic.rates import LAUNCH_MODES, RateModel, fit_rates

__all__ = [
    "ALPHA",
    "Band",
    "Checks",
    "GAP",
    "GRID_POINTS",
    "Hazard",
    "LAUNCH",
    "LAUNCH_MODES",
    "Mixing",
    "PIECES",
    "REMOVED",
    "RateModel",
    "RunLog",
    "STEP_FRACTION",
    "candidate_families",
    "check_heldout",
    "check_states",
    "collect_runs",
    "counts_at",
    "covariate_names",
    "default_radius",
    "expected_counts",
    "exposure_table",
    "fit_hazard",
    "fit_rates",
    "heldout_loglik",
    "observed_counts",
    "run_log",
    "simulate_counts",
    "sinks",
    "sources",
    "state_graph",
    "stays",
    "transitions",
    "well_mixed",
]
