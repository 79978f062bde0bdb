"""Print a digest of the event log, state counts and summary of fixed seeded runs of every model.

Used to show that a refactoring changes no behaviour: run it before and after and compare the
lines (``python scripts/event_digests.py > before.txt``). Each line is
``<case> <events sha> <counts sha> <summary sha> <n events>``.
"""

import hashlib
import json
import sys

import numpy as np

CASES = {
    "be-corridor-low-1": ("beacon-explorer", {"world": "corridor", "complexity": "low", "seed": 1}),
    "be-corridor-medium-2": (
        "beacon-explorer",
        {"world": "corridor", "complexity": "medium", "seed": 2},
    ),
    "be-corridor-high-3": (
        "beacon-explorer",
        {"world": "corridor", "complexity": "high", "seed": 3},
    ),
    "be-corridor-high-24s-7": (
        "beacon-explorer",
        {"world": "corridor", "complexity": "high", "seed": 7, "launch_period": 24.0},
    ),
    "be-open-low-4": ("beacon-explorer", {"world": "open", "complexity": "low", "seed": 4}),
    "be-open-high-5": ("beacon-explorer", {"world": "open", "complexity": "high", "seed": 5}),
    "be-mixed-6": ("beacon-explorer", {"world": "mixed", "seed": 6}),
    "be-mixed-hover-8": ("beacon-explorer", {"world": "mixed", "seed": 8, "hover_beacons": True}),
    "be-battery-9": (
        "beacon-explorer",
        {"world": "corridor", "complexity": "high", "seed": 9, "battery_capacity": 8000.0},
    ),
    "st-hall100-30-1": (
        "stigmergy",
        {"map": "hall100", "pheromone_radius": 30.0, "seed": 1, "time_limit": 1500.0},
    ),
    "st-divided-20-2": (
        "stigmergy",
        {"map": "divided", "pheromone_radius": 20.0, "seed": 2, "time_limit": 1200.0},
    ),
    "st-complex-40-3": (
        "stigmergy",
        {"map": "complex", "pheromone_radius": 40.0, "seed": 3, "time_limit": 1000.0},
    ),
}


def _sha(text: str) -> str:
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def _model(name: str):
    if name == "beacon-explorer":
        from models.beacon_explorer import BeaconExplorerModel

        return BeaconExplorerModel
    from models.stigmergy import StigmergyModel

    return StigmergyModel


def main(names: list[str]) -> None:
    """Print one line per case (all cases, or those named)."""
    for case, (model_name, kwargs) in CASES.items():
        if names and case not in names:
            continue
        model = _model(model_name)(**kwargs).run()
        events = model.events()
        summary = {
            k: (v.item() if isinstance(v, np.generic) else v) for k, v in model.summary().items()
        }
        print(
            case,
            _sha(events.to_csv(index=False)),
            _sha(model.state_counts().to_csv(index=False)),
            _sha(json.dumps(summary, sort_keys=True, default=str)),
            len(events),
            flush=True,
        )


if __name__ == "__main__":
    main(sys.argv[1:])
