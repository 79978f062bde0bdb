"""What Alunni et al. (2011) publish about the hierarchical swarm: no number (the result figures
are images whose values did not survive), every checkable claim C1-C14 (README, "The claims";
C14 twice: counted per destination, and as C14b one transmission per broadcast) with its test,
and the paper-style figure layout (Figs. 36-38: mean scan area and drive distance per scout and
per worker against the total number of robots N, one line per W).

Units: the summary, and so the report's axes, are in SI (m^2, m). The report measures scan area
in cm^2 and drive distance in cm ("Data Collection"); its only legible scale, Fig. 37's y axis
"Scan Area (cm2)" running to 3,000,000 cm^2, is 300 m^2 (1 m^2 = 10^4 cm^2).
"""

from abm.published import Censored, Claim, ReportLayout
from models.hierarchy.claims import TESTS

__all__ = ["CENSORED", "CLAIMS", "FAULT_REPORT", "PUBLISHED", "REPORT", "ROOM"]

#: The report publishes no numeric result value (Figs. 36-38 carry none), so there is nothing to
#: list here.
PUBLISHED: list = []

#: The report's room and swarm: the empty 20 m x 20 m map and the queen-worker-scout tree
#: every claim about the scaling was made on (a topology sweep's star, FC and ring runs are not
#: pooled in).
ROOM = {"world_size": 20.0, "boxes": 0, "topology": "hst"}

_TOPOLOGY = (
    "topology = hst, star, fc, ring at 4-32 scouts (hierarchy_topology; paired seeds: "
    "benchmarks/bench_hierarchy_topology.py)"
)
_GRID = "the 42 configurations W = 2-7 x S = 2-8 on the empty 20 m room (hierarchy_scaling)"

#: (id, source, statement, kind, set-up); the test is TESTS[id] where one exists.
_CLAIMS = [
    (
        "C1",
        "Data Collection; Conclusion",
        "for every configuration the swarm maps the 20 m x 20 m area to completion",
        "QL",
        _GRID,
    ),
    (
        "C2",
        "Figs. 36-37",
        "the mean level-2 (scout) scan area decreases smoothly as the total "
        "number of robots N grows",
        "QL",
        _GRID,
    ),
    (
        "C3",
        "Fig. 37",
        "the scout scan area depends on the total N, not on the number of "
        "mediating workers W (the six W-series fall on one curve)",
        "QL",
        _GRID + ", plus the equal-scout control (hierarchy_equal_scouts)",
    ),
    (
        "C4",
        "Fig. 36",
        "the mean level-1 (worker) scan area also decreases with N, but is "
        "'slightly more sporadic' than level 2",
        "QL",
        _GRID,
    ),
    (
        "C6",
        "Figs. 37-38",
        "the mean level-2 drive distance decreases rapidly with N, mirroring the scan area",
        "QL",
        _GRID,
    ),
    (
        "C7",
        "Fig. 38",
        "the mean level-1 drive distance goes down only slightly with N",
        "QL",
        _GRID,
    ),
    (
        "C8",
        "Software Results",
        "almost no increase in the queen's coverage iterations for two "
        "workers instead of seven on a 20 m x 20 m map",
        "QL",
        _GRID,
    ),
    (
        "C9",
        "Abstract",
        "adding robots reduces the overall runtime",
        "QL",
        _GRID + " (our timed model: completion time)",
    ),
    (
        "C12",
        "Software Results",
        "with the wave generator and idle moves the robots move without colliding",
        "QL",
        _GRID + "; the counterfactual wave_generator=false (hierarchy_no_waves)",
    ),
    (
        "C14",
        "Introduction; Structure",
        "an HST needs significantly fewer communications than fully connected or ring "
        "topologies (argued, never measured in the report); counted per destination",
        "QL",
        _TOPOLOGY + "; every copy of a message to each destination counts (messages_task)",
    ),
    (
        "C14b",
        "Introduction; Structure",
        "the same claim, counted as radio transmissions on a shared channel",
        "QL",
        _TOPOLOGY + "; a message sent to several destinations at once counts once "
        "(transmissions_task: FC's copies, a ring origin's first hop both ways)",
    ),
]

#: Claims that hold by construction: labelled so in the report, never counted as reproduced.
_BY_CONSTRUCTION = [
    (
        "C5",
        "Fig. 36",
        "the level-0 (queen) scan area equals the map area",
        "Q",
        _GRID,
        "the model sets the queen's scan area to the world's width x height",
    ),
]

_UNTESTABLE = [
    (
        "C10",
        "Executive Summary",
        "the work of any member is directly related to the total number of robots",
        "QL",
        "-",
        "the same statement as C2, C3 and C6 made in general; judged there",
    ),
    (
        "C11",
        "Software Results",
        "a mediator can be added at any level without increasing the swarm's overall workload",
        "QL",
        "-",
        "a corollary of C3; judged there",
    ),
    (
        "C13",
        "Exponential Decay; Fail-fast; Greedy",
        "radius decay, fail-fast and greedy placement cut the coverage algorithm's run time",
        "QL",
        "-",
        "claims about the algorithm's CPU time, not the swarm; the coverage call's time is "
        "measured by benchmarks/bench_hierarchy_coverage.py, the alternatives are not "
        "implemented",
    ),
]

CLAIMS = sorted([
    *(Claim(i, src, text, kind, setup, test=TESTS[i], condition={} if i.startswith("C14") else ROOM)
      for i, src, text, kind, setup in _CLAIMS),
    *(Claim(i, src, text, kind, setup, untestable=why)
      for i, src, text, kind, setup, why in _UNTESTABLE),
    *(Claim(i, src, text, kind, setup, condition=ROOM, by_construction=why)
      for i, src, text, kind, setup, why in _BY_CONSTRUCTION),
], key=lambda claim: (int(claim.id[1:].rstrip("b")), claim.id))  # fmt: skip

#: The queen's coverage call ends a run of the report, COMPLETE or CANNOT_COMPLETE (it gives
#: up), and its time is the run's completion time either way (the runtime C9 is about); a run
#: the time limit stops before the call returns has none: only a lower bound, its end.
CENSORED = (Censored("completion_time", bound="time"),)

#: Worker failure (issue 13, not the report's): completion, rounds and messages against each
#: worker's failure hazard.
FAULT_REPORT = ReportLayout(
    x="fault_rate",
    metrics=(
        "completion_time",
        "queen_iterations",
        "messages",
        "workers_failed",
        "known_free_fraction",
    ),  # fmt: skip
    labels={
        "fault_rate": "Failure hazard of a worker (1/s)",
        "completion_time": "Completion time (s)",
        "queen_iterations": "Queen's coverage rounds",
        "messages": "Messages (transmissions)",
        "workers_failed": "Workers failed per run",
        "known_free_fraction": "Free cells the queen knows (share)",
    },
)

REPORT = ReportLayout(
    x="N",
    hue="W",
    metrics=("scout_scan_area", "worker_scan_area", "scout_drive", "worker_drive"),
    alternatives=(FAULT_REPORT,),
    labels={
        "N": "Robots N, queen included (1 + W + W S in the hierarchy)",
        "W": "Workers W",
        "scout_scan_area": "Scout scan area (m²)",
        "worker_scan_area": "Worker scan area (m²)",
        "scout_drive": "Scout drive distance (m)",
        "worker_drive": "Worker drive distance (m)",
    },
    notes={
        "scout_scan_area": "Σ π r² over every SCAN a scout received (README, Choices: scan area), "
        "mean per scout; "
        "the report's Figs. 36-37 plot cm² (1 m² = 10⁴ cm²)",
        "worker_scan_area": "Σ π r² of the bubbles the queen gave a worker, mean per worker; "
        "the report's Fig. 36 plots cm² (1 m² = 10⁴ cm²)",
        "scout_drive": "Σ smoothed path lengths (README, Choices: drive distance), "
        "mean per scout; "
        "the report's Fig. 38 plots cm (1 m = 100 cm)",
        "worker_drive": "Σ smoothed path lengths, mean per worker; "
        "the report's Fig. 38 plots cm (1 m = 100 cm)",
    },
)
