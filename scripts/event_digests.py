"""Digests of the event log, state counts and summary of fixed seeded runs of every model.

A refactoring for speed must change no behaviour: the same seed must give the same event log,
event for event. This script runs short seeded cases of every model and compares a SHA-256 of
each run's event log, state counts and summary with the digests stored in
``tests/data/event_digests.json`` (the test ``tests/test_event_digests.py`` does the same on the
``quick`` cases).

    python scripts/event_digests.py            # compare every case with the stored digests
    python scripts/event_digests.py --quick    # only the cases the test suite checks
    python scripts/event_digests.py --write    # store this revision's digests (see below)

When a branch changes a model's behaviour on purpose (a rule fix, a new hook that draws from
the generator), the digests of that model change: check the change is the intended one, then
regenerate with ``--write`` on the merged revision and commit ``tests/data/event_digests.json``
with the change that explains it.
"""

import argparse
import hashlib
import json
import sys
from pathlib import Path

import numpy as np

from abm.registry import model_class
from abm.worlds import COMPLEXITIES

__all__ = ["CASES", "DIGESTS", "QUICK", "WORLDS", "digest", "stored", "world_digest"]

#: Where the digests live.
DIGESTS = Path(__file__).resolve().parent.parent / "tests" / "data" / "event_digests.json"

#: case -> (registered model, constructor keywords with the seed): short runs of every model.
CASES: dict[str, tuple[str, dict]] = {
    "be-corridor-low-1": ("beacon-explorer", {"world": "corridor", "complexity": "low", "seed": 1}),
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
    "be-open-crowd-11": (
        "beacon-explorer",
        {
            "world": "open",
            "complexity": "low",
            "seed": 11,
            "n_robots": 80,
            "launch_period": 1.0,
            "time_limit": 200.0,
        },
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
    "st-hall100-fast-4": (
        "stigmergy",
        {"map": "hall100", "launch_rate": 0.2, "seed": 4, "time_limit": 400.0},
    ),
    "sugarmap-1": ("sugarmap", {"seed": 1, "time_limit": 300.0}),
    "hierarchy-1": ("hierarchy", {"seed": 1, "time_limit": 600.0}),
    "tangible-pso-1": ("tangible-pso", {"seed": 1, "time_limit": 300.0}),
}
#: The cases the test suite checks (a few seconds in all).
QUICK = (
    "be-corridor-high-3",
    "be-open-high-5",
    "be-mixed-6",
    "be-open-crowd-11",
    "st-hall100-fast-4",
    "sugarmap-1",
    "hierarchy-1",
    "tangible-pso-1",
)


def _sha(text: str) -> str:
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def digest(case: str) -> dict:
    """Run one case: SHA-256 prefixes of its events, state counts and summary, and its size."""
    name, kwargs = CASES[case]
    model = model_class(name)(**kwargs).run()
    events = model.events()
    summary = {
        k: (v.item() if isinstance(v, np.generic) else v) for k, v in model.summary().items()
    }
    return {
        "events": _sha(events.to_csv(index=False)),
        "counts": _sha(model.state_counts().to_csv(index=False)),
        "summary": _sha(json.dumps(summary, sort_keys=True, default=str)),
        "n_events": len(events),
    }


#: The generated worlds checked besides the runs: every kind and level, seeds 0 to 19.
WORLDS = "worlds-default"


def world_digest() -> dict:
    """SHA-256 prefix of the paper-default generated worlds (walls, start, cells, branches)."""
    from abm.worlds import make_world

    parts = []
    for kind, levels in (("corridor", COMPLEXITIES), ("open", COMPLEXITIES), ("mixed", ["medium"])):
        for level in levels:
            for seed in range(20):
                world = make_world(kind, level, seed)
                parts.append(
                    f"{kind} {level} {seed} {world.arena.free.tobytes().hex()} "
                    f"{world.start.tolist()} {world.cells.tolist()} {world.branches}"
                )
    return {"worlds": _sha("\n".join(parts)), "n_worlds": len(parts)}


def stored() -> dict[str, dict]:
    """The digests on file (empty if none were written)."""
    return json.loads(DIGESTS.read_text()) if DIGESTS.exists() else {}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("cases", nargs="*", help="case names (default: all)")
    parser.add_argument("--quick", action="store_true", help="only the cases the tests check")
    parser.add_argument("--write", action="store_true", help="store the digests of this code")
    args = parser.parse_args()
    names = args.cases or [*(QUICK if args.quick else CASES), WORLDS]
    unknown = sorted(set(names) - CASES.keys() - {WORLDS})
    if unknown:
        parser.error(f"unknown cases {unknown}; known: {', '.join(CASES)}")
    on_file = stored()
    changed = 0
    for case in names:
        got = world_digest() if case == WORLDS else digest(case)
        want = on_file.get(case)
        verdict = "written" if args.write else ("same" if got == want else "CHANGED")
        changed += verdict == "CHANGED"
        print(f"{case:<24} {' '.join(str(v) for v in got.values())}  {verdict}", flush=True)
        on_file[case] = got
    if args.write:
        DIGESTS.parent.mkdir(parents=True, exist_ok=True)
        DIGESTS.write_text(json.dumps(dict(sorted(on_file.items())), indent=1) + "\n")
        print(f"wrote {DIGESTS}")
    return 1 if changed else 0


if __name__ == "__main__":
    sys.exit(main())
