"""Check that fixed seeded runs of every model still decide what they decided: the guarantee.

The reproducibility guarantee (``docs/reproducibility.md``): the same seed gives the same
*decisions* -- every event, its kind, robot and other labels, its order, every state count,
every non-float summary value -- on any machine with the same package versions, and every
*float* (event times and positions, count times, summary floats) equal to a relative tolerance
:data:`RTOL`. This script runs short seeded cases of every model and checks exactly that
against what is on file:

- a SHA-256 of each run's decisions (non-float columns verbatim, and which rows of each float
  column hold a value) for its event log, state counts and summary, in
  ``tests/data/event_digests.json``;
- every float of those tables, in ``tests/data/event_digests_floats.npz``, compared with
  :data:`RTOL`.

The test ``tests/test_event_digests.py`` does the same on the ``quick`` cases.

    python scripts/event_digests.py            # compare every case with what is on file
    python scripts/event_digests.py --quick    # only the cases the test suite checks
    python scripts/event_digests.py --write    # store this revision's results (see below)

Each line names the case, its three decision digests and its number of events, then "same"
or "CHANGED" (followed by what changed). When a branch changes a model's behaviour on purpose
(a rule fix, a new hook that draws from the generator), check the change is the intended one,
then regenerate with ``--write`` on the merged revision and commit both files with the change
that explains it.
"""

import argparse
import hashlib
import json
import math
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from abm.registry import model_class
from models.environments import COMPLEXITIES

__all__ = [
    "CASES",
    "DIGESTS",
    "FLOATS",
    "QUICK",
    "RTOL",
    "WORLDS",
    "Outcome",
    "compare",
    "digest",
    "fingerprint",
    "load_floats",
    "outcome",
    "split",
    "stored",
    "world_digest",
]

_DATA = Path(__file__).resolve().parent.parent / "tests" / "data"
#: Where the decision digests live.
DIGESTS = _DATA / "event_digests.json"
#: Where the floats of every case live (``<case>/<table>/<column>`` -> array).
FLOATS = _DATA / "event_digests_floats.npz"

#: Relative tolerance of the guarantee's floats: ``|a - b| <= RTOL * max(|a|, |b|, 1)`` (below
#: 1 in the column's unit, m or s, an absolute 1e-9). The decision paths are bit-exact, so the
#: floats of the log are too; the tolerance is room for floats computed beside them (a summary
#: statistic through a vectorised numpy reduction or logarithm), seven orders above their
#: last-bit noise (~1e-16) and far below any difference a model change makes.
RTOL = 1e-9

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
    "flocking-small-1": ("flocking", {"seed": 1}),
    "flocking-large-2": (
        "flocking",
        {"seed": 2, "birds": 400, "extent": 150.0, "visual_distance": 15.0},
    ),
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
    "flocking-small-1",
    "flocking-large-2",
)


def _sha(text: str) -> str:
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def split(frame: pd.DataFrame) -> tuple[str, dict[str, np.ndarray]]:
    """A table's decisions and floats.

    The decisions are the column names, every value that is not a float verbatim and, for
    each float, only that there is one, as CSV text; the floats are each column's float
    values (NaN in the rows that hold none), for every column that holds any.
    """
    decisions = pd.DataFrame(index=frame.index)
    floats = {}
    for name in frame.columns:
        column = frame[name]
        if pd.api.types.is_float_dtype(column.dtype):
            floats[str(name)] = column.to_numpy(dtype=float)
            decisions[name] = column.notna()
            continue
        is_float = column.map(lambda v: isinstance(v, float) and not math.isnan(v)).to_numpy(bool)
        if is_float.any():
            floats[str(name)] = column.where(is_float, np.nan).to_numpy(dtype=float)
            column = column.where(~is_float, "<float>")
        decisions[name] = column
    return decisions.to_csv(index=False), floats


def _summary_frame(summary: dict) -> pd.DataFrame:
    """The summary as a one-row table (numpy scalars as Python values, others by ``str``)."""
    row = {}
    for key, value in summary.items():
        value = value.item() if isinstance(value, np.generic) else value
        row[key] = value if isinstance(value, bool | int | float | str | None) else str(value)
    return pd.DataFrame([row])


def fingerprint(case: str) -> tuple[dict, dict[str, np.ndarray]]:
    """Run one case: its decision digests (events, counts, summary) and number of events, and
    its floats (``<table>/<column>`` -> array).
    """
    name, kwargs = CASES[case]
    model = model_class(name)(**kwargs).run()
    events = model.events()
    tables = {
        "events": events,
        "counts": model.state_counts(),
        "summary": _summary_frame(model.summary()),
    }
    digests, floats = {}, {}
    for table, frame in tables.items():
        text, columns = split(frame)
        digests[table] = _sha(text)
        floats.update({f"{table}/{column}": values for column, values in columns.items()})
    digests["n_events"] = len(events)
    return digests, floats


def digest(case: str) -> dict:
    """Run one case: its decision digests and number of events (:func:`fingerprint`)."""
    return fingerprint(case)[0]


def compare(got: dict[str, np.ndarray], want: dict[str, np.ndarray], rtol: float = RTOL) -> list:
    """What differs between two cases' floats beyond ``rtol``: one line per column (empty when
    they agree). NaN matches NaN; infinities must be equal.
    """
    problems = []
    for key in sorted(got.keys() | want.keys()):
        if key not in got or key not in want:
            problems.append(f"{key}: only in the {'run' if key in got else 'file'}")
            continue
        a, b = got[key], want[key]
        if a.shape != b.shape:
            problems.append(f"{key}: {a.shape[0]} values against {b.shape[0]} on file")
            continue
        scale = np.maximum(1.0, np.maximum(np.abs(a), np.abs(b)))
        with np.errstate(invalid="ignore"):
            ok = (a == b) | (np.isnan(a) & np.isnan(b)) | (np.abs(a - b) <= rtol * scale)
        if not ok.all():
            worst = np.nanmax(np.where(ok, 0.0, np.abs(a - b) / scale))
            problems.append(
                f"{key}: {int((~ok).sum())} of {a.size} beyond {rtol:g} "
                f"(first row {int(np.argmin(ok))}, largest relative difference {worst:.3g})"
            )
    return problems


@dataclass(frozen=True)
class Outcome:
    """One case checked against the files: its digests, its floats and what differs (empty
    when the run keeps the guarantee).
    """

    digests: dict
    floats: dict[str, np.ndarray]
    problems: list[str]

    @property
    def same(self) -> bool:
        """True when the run keeps the guarantee against what is on file."""
        return not self.problems


def outcome(case: str, on_file: dict, floats_on_file: dict[str, np.ndarray]) -> Outcome:
    """Run ``case`` and check it against the stored digests and floats."""
    digests, floats = fingerprint(case)
    want = on_file.get(case)
    if want is None:
        return Outcome(digests, floats, ["nothing on file: run scripts/event_digests.py --write"])
    problems = [
        f"{key}: {want.get(key)} on file, {value} now"
        for key, value in digests.items()
        if want.get(key) != value
    ]
    prefix = f"{case}/"
    stored_floats = {k[len(prefix) :]: v for k, v in floats_on_file.items() if k.startswith(prefix)}
    problems += compare(floats, stored_floats)
    return Outcome(digests, floats, problems)


#: The generated worlds checked besides the runs: every kind and level, seeds 0 to 19.
WORLDS = "worlds-default"


def world_digest() -> dict:
    """SHA-256 prefix of the paper-default generated worlds (walls, start, cells, branches)."""
    from models.environments import make_world

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


def load_floats() -> dict[str, np.ndarray]:
    """The floats on file, ``<case>/<table>/<column>`` -> array (empty if none were written)."""
    if not FLOATS.exists():
        return {}
    with np.load(FLOATS) as data:
        return {key: data[key] for key in data.files}


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("cases", nargs="*", help="case names (default: all)")
    parser.add_argument("--quick", action="store_true", help="only the cases the tests check")
    parser.add_argument("--write", action="store_true", help="store the results of this code")
    args = parser.parse_args()
    names = args.cases or [*(QUICK if args.quick else CASES), WORLDS]
    unknown = sorted(set(names) - CASES.keys() - {WORLDS})
    if unknown:
        parser.error(f"unknown cases {unknown}; known: {', '.join(CASES)}")
    on_file, floats_on_file = stored(), load_floats()
    changed = 0
    for case in names:
        if case == WORLDS:
            got, problems = world_digest(), []
            if on_file.get(case) != got:
                problems = [f"worlds: {on_file.get(case)} on file"]
        else:
            result = outcome(case, on_file, floats_on_file)
            got, problems = result.digests, result.problems
            kept = {k: v for k, v in floats_on_file.items() if not k.startswith(f"{case}/")}
            floats_on_file = kept | {f"{case}/{k}": v for k, v in result.floats.items()}
        verdict = "written" if args.write else ("CHANGED" if problems else "same")
        changed += verdict == "CHANGED"
        print(f"{case:<24} {' '.join(str(v) for v in got.values())}  {verdict}", flush=True)
        if verdict == "CHANGED":
            for line in problems:
                print(f"    {line}", flush=True)
        on_file[case] = got
    if args.write:
        DIGESTS.parent.mkdir(parents=True, exist_ok=True)
        DIGESTS.write_text(json.dumps(dict(sorted(on_file.items())), indent=1) + "\n")
        np.savez_compressed(FLOATS, **dict(sorted(floats_on_file.items())))
        print(f"wrote {DIGESTS} and {FLOATS}")
    return 1 if changed else 0


if __name__ == "__main__":
    sys.exit(main())
