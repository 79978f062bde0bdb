"""What the framework comparison publishes about the flocking model: how many times slower than
Agents.jl each framework ran it (median wall time of construction + 100 steps).

Source: JuliaDynamics/ABMFrameworksComparison, the results table of its README (Mesa 3.2),
as quoted in issue 14. These are timings, not model outputs, so they are not ``Published``
records of a sweep: ``benchmarks/bench_flocking.py`` prints ours beside them. The model's
report (``abm report``) draws the flock's order against the visual distance.
"""

from abm.published import ReportLayout

__all__ = ["PUBLISHED", "REPORT", "SLOWER_THAN_AGENTS_JL"]

#: framework -> (small, large): median run time / Agents.jl's median run time.
SLOWER_THAN_AGENTS_JL = {
    "Mesa 3.2": (159.3, 59.5),
    "MASON": (1.42, 0.61),
    "NetLogo": (15.4, 19.1),
}

#: The comparison publishes no model output to set ours beside.
PUBLISHED = ()

REPORT = ReportLayout(
    x="visual_distance",
    metrics=("polarisation", "mean_neighbours"),
    curves=("polarisation",),
    labels={
        "visual_distance": "Visual distance (m)",
        "polarisation": "Polarisation |mean unit velocity|",
        "mean_neighbours": "Neighbours per bird (last step)",
    },
)
