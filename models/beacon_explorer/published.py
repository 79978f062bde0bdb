"""Every number Stirling et al. (2010) publish for the beacon/explorer search, and the layout of
their figures: the one home that reports, tests and benchmarks read them from.

Sections follow the paper's Sect. 4 experiments: branching corridors (Fig. 6, 7), open rooms
(Fig. 8, 9), mixed worlds (Fig. 10) and hovering vs attached beacons (end of Sect. 4).
"""

from abm.published import Censored, MacroSpec, Published, ReportLayout

__all__ = [
    "BRANCHES",
    "CENSORED",
    "BRANCHES_SD",
    "COMPLETE",
    "FAULT_REPORT",
    "CORRIDOR_24_VS_6",
    "COVERAGE",
    "HOVER_RATIO",
    "MACRO",
    "PUBLISHED",
    "REPORT",
]

#: Corridor worlds, mean coverage area (% of free area) per complexity (Sect. 4.1).
COVERAGE = {"low": 79.4, "medium": 90.1, "high": 94.0}
#: Corridor worlds, runs that covered everything (% of trials) per complexity (Sect. 4.1).
COMPLETE = {"low": 38.5, "medium": 64.2, "high": 74.3}
#: Corridor worlds, mean branches per generated world (Sect. 3.5).
BRANCHES = {"low": 3.56, "medium": 5.82, "high": 9.5}
#: Corridor worlds, standard deviation of the branches per world (Sect. 3.5).
BRANCHES_SD = {"low": 1.23, "medium": 1.07, "high": 1.63}
#: Open rooms: obstacle cells in the 5 x 5 room per density (Sect. 3.5).
OBSTACLES = {"low": 5, "medium": 7, "high": 10}
#: High-complexity corridors, percent change of the mean from 6 s to 24 s (Sect. 4.1).
CORRIDOR_24_VS_6 = {
    "flight_time": -41.5,
    "collisions": -93.9,
    "coverage_time": 90.5,
    "energy_total": -30.8,
}
#: Open rooms, high density, percent change from 3 s to 12 s (Sect. 4.2).
OPEN_12_VS_3 = {"flight_time": -29.9, "energy_total": -16.4, "coverage_time": 149.7}
#: Open rooms, high density, percent change from 3 s to 6 s (Sect. 4.2).
OPEN_6_VS_3 = {"flight_time": -15.0, "coverage_time": 44.9}
#: Mixed worlds, percent change from 6 s to 24 s (Sect. 4.3).
MIXED_24_VS_6 = {
    "flight_time": -34.0,
    "collisions": -86.4,
    "coverage_time": 70.5,
    "energy_total": -25.3,
}
#: Hovering / attached beacons, total energy, mixed worlds at 6 s (end of Sect. 4).
HOVER_RATIO = 3.6

_QUANTITY = {
    "flight_time": "flight time",
    "collisions": "collisions",
    "coverage_time": "coverage time",
    "energy_total": "total energy",
}


#: Beacons attach (land) in every experiment of Sect. 4 but the hover comparison: a record
#: names it, so runs with hovering beacons are never pooled into the paper's conditions.
ATTACHED = {"hover_beacons": False}


def _levels(quantity: str, metric: str, values: dict) -> list[Published]:
    """Levels per complexity, published without a spread: what they support is their
    ordering (each rises from the previous complexity).
    """
    return [
        Published(
            "corridor",
            quantity,
            {"world": "corridor", "complexity": level, **ATTACHED},
            value,
            "ordering",
            metric,
            "first" if i == 0 else "rises",
            source="Sect. 4.1" if metric != "branches" else "Sect. 3.5",
        )
        for i, (level, value) in enumerate(values.items())
    ]


def _changes(section, world, complexity, a, b, values, source) -> list[Published]:
    return [
        Published(
            section,
            f"{_QUANTITY[metric]}: change {b:g} s vs {a:g} s (%)",
            {"world": world, "complexity": complexity, **ATTACHED},
            value,
            "direction",
            metric,
            "same sign",
            measure="change",
            factor="launch_period",
            a=a,
            b=b,
            source=source,
        )
        for metric, value in values.items()
    ]


#: Every published number, in the paper's order.
PUBLISHED: list[Published] = [
    *_levels("coverage area (%), mean over periods", "coverage_area", COVERAGE),
    *_levels("complete coverage (% of trials)", "complete", COMPLETE),
    *_levels("corridor branches per world (mean)", "branches", BRANCHES),
    *_changes("corridor", "corridor", "high", 6.0, 24.0, CORRIDOR_24_VS_6, "Sect. 4.1, Fig. 6"),
    Published(
        "corridor",
        "Pearson r, mean flight time vs mean energy across conditions",
        {"world": "corridor", **ATTACHED},
        0.974,
        "direction",
        "flight_time",
        "positive",
        measure="r",
        other="energy_total",
        by=("complexity", "launch_period"),
        source="Sect. 4.1",
        by_construction=(
            "a flying robot draws a constant power (power_flight, 120 W), so most of the energy"
            " is that power times the flight time: the two rise together whatever the swarm does"
        ),
    ),
    Published(
        "open space",
        "coverage area (%), mean over all conditions",
        {"world": "open", **ATTACHED},
        99.7,
        "level",
        "coverage_area",
        "band",
        source='Sect. 4.2 ("no significant variance"; no spread published)',
    ),
    *_changes("open space", "open", "high", 3.0, 12.0, OPEN_12_VS_3, "Sect. 4.2, Fig. 8"),
    Published(
        "open space",
        "collisions per run, 3 s -> 12 s",
        {"world": "open", "complexity": "high", **ATTACHED},
        "0.32 -> 0.02",
        "direction",
        "collisions",
        "decreases",
        measure="pair",
        factor="launch_period",
        a=3.0,
        b=12.0,
        source="Sect. 4.2",
    ),
    *_changes("open space", "open", "high", 3.0, 6.0, OPEN_6_VS_3, "Sect. 4.2"),
    Published(
        "open space",
        "total energy vs period (medium density)",
        {"world": "open", "complexity": "medium", **ATTACHED},
        "convex (optimum inside)",
        "ordering",
        "energy_total",
        "minimum inside",
        measure="convex",
        factor="launch_period",
        source="Sect. 4.2, Fig. 9",
    ),
    *_changes("mixed", "mixed", "medium", 6.0, 24.0, MIXED_24_VS_6, "Sect. 4.3, Fig. 10"),
    Published(
        "hover vs attach",
        "total energy, hovering / attached beacons (x)",
        {"world": "mixed", "complexity": "medium", "launch_period": 6.0},
        HOVER_RATIO,
        "direction",
        "energy_total",
        "above 1",
        measure="ratio",
        factor="hover_beacons",
        a=False,
        b=True,
        source="end of Sect. 4",
    ),
]

#: A search cut by the time limit or ended stalled reports its end, not its coverage time.
#: Metrics a run's end cuts short. Coverage time is only known for runs that covered the
#: world. The paper's runs end when the swarm is stuck or the search complete (Sect. 4), never
#: at a time limit: a run cut by ours reports a lower bound of everything it accumulates
#: (flight time, energy, collisions, coverage), so those are censored by the limit too and a
#: sweep of short runs is never judged against the paper's numbers.
CENSORED = (
    Censored("coverage_time", ends=("time limit", "stalled")),
    *(
        Censored(metric, ends=("time limit",))
        for metric in ("flight_time", "energy_total", "collisions", "coverage_area", "complete")
    ),
)

#: Faults (issue 13; not in the paper): coverage, completion, energy and coverage time
#: against the beacons' failure rate, with and without repair
#: (``experiments/faults_beacon_explorer.toml``).
FAULT_REPORT = ReportLayout(
    x="fault_rate",
    hue="repair",
    hue_order=(True, False),
    metrics=("coverage_area", "complete", "energy_total", "coverage_time", "n_failed"),
    labels={
        "fault_rate": "Beacon failure rate lambda (1/s)",
        "repair": "Repair",
        "coverage_area": "Coverage area (% of free area)",
        "complete": "Runs complete (fraction)",
        "energy_total": "Total swarm energy (kJ)",
        "coverage_time": "Run time (s)",
        "n_failed": "Robots failed per run",
    },
)

#: The paper's figure types: metrics against the inter-launch period, one line per complexity
#: (Figs. 6, 8, 10a), energy per mode stacked (Figs. 7, 9, 10b), hover vs attach, the optimal
#: period (Sect. 5) and Pearson's r of flight time vs energy.
REPORT = ReportLayout(
    x="launch_period",
    hue="complexity",
    hue_order=("low", "medium", "high"),
    metrics=("coverage_time", "flight_time", "collisions"),
    stacked=("energy_flight", "energy_beacon", "energy_ground"),
    total="energy_total",
    compare="hover_beacons",
    compare_metric="energy_total",
    optimum=("coverage_time", "collisions", "energy_total"),
    correlate=("flight_time", "energy_total"),
    alternatives=(FAULT_REPORT,),
    labels={
        "coverage_time": "Coverage time (s)",
        "coverage_area": "Coverage area (% of free area)",
        "flight_time": "Total swarm flight time (s)",
        "collisions": "Collisions per run",
        "energy_total": "Total swarm energy (kJ)",
        "energy_flight": "Flight energy (kJ)",
        "energy_beacon": "Beacon energy (kJ)",
        "energy_ground": "Ground energy (kJ)",
        "launch_period": "Inter-launch period (s)",
        "complexity": "Complexity",
    },
)

#: The wander/beacon recurrence of Arnaldo et al. (2018) read on this swarm: explorers are the
#: moving robots, beacons the settled ones; one explorer takes off per launch period until the
#: n robots on the ground are gone (a finite supply, plus the base beacon). Redeploying beacons
#: (b -> w) have no term in the recurrence. The paper (Stirling et al.) fits no such model.
MACRO = MacroSpec(
    moving="explorer",
    settled="beacon",
    step=1.0,
    arrival_period="launch_period",
    supply="robots",
    source="the recurrence of Arnaldo et al. (2018) on Stirling et al. (2010)'s swarm",
)
