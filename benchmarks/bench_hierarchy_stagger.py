"""Where the hierarchy's remaining robot-robot contacts happen (claim C12, issue 30): re-runs
the runs of a ``hierarchy_stagger`` sweep (same seeds, same parameters) and sorts every contact
by who touched whom and what each was doing.

Who: ``siblings`` (scouts of one worker), ``cousins`` (scouts of different workers),
``worker-own-scout``, ``worker-other-scout``, ``workers``. What, read from the message log
(zero latency, so message times are the moments things happen):

- a scout is in ``transit`` from the queen's SCAN to its worker until the worker first orders a
  scout to scan (its scouts have driven into the new bubble), else ``in-bubble`` (a later round
  of its worker's bubble, or an idle move);
- a worker is ``moving`` from the queen's MOVE to its ARRIVED.

    python benchmarks/bench_hierarchy_stagger.py            # runs the sweep first if missing
    python benchmarks/bench_hierarchy_stagger.py --sweep out/sweeps/hierarchy_stagger --n 64

It prints one table per arm (``subtree_transits``) and writes it as CSV beside the sweep.
"""

import argparse
import json
import sys
import time
from collections import Counter
from pathlib import Path

import pandas as pd

from models.hierarchy import HierarchyModel
from models.hierarchy.model import QUEEN

EXPERIMENT = Path(__file__).resolve().parent.parent / "experiments" / "hierarchy_stagger.toml"


def windows(log: pd.DataFrame, open_kind: str, close) -> dict[object, list[tuple[float, float]]]:
    """Per robot, the time windows from a queen's ``open_kind`` to it until ``close``'s first
    message after it (``close(after, robot)`` selects the closing rows).
    """
    log = log.reset_index(drop=True)
    out: dict[object, list[tuple[float, float]]] = {}
    for row in log.index[(log["src"] == QUEEN) & (log["kind"] == open_kind)]:
        robot = log.at[row, "dst"]
        after = log.loc[row + 1 :]
        ends = after[close(after, robot)]
        end = float(ends["time"].iloc[0]) if len(ends) else float("inf")
        out.setdefault(robot, []).append((float(log.at[row, "time"]), end))
    return out


def _inside(t: float, spans: list[tuple[float, float]]) -> bool:
    return any(a <= t <= b for a, b in spans)


def classify(model: HierarchyModel) -> Counter:
    """Every robot-robot contact of a finished run as (who, what the lower id did, the other)."""
    log = model.comms.log.frame()
    transit = windows(
        log,
        "SCAN",
        lambda after, w: (
            (after["src"] == w)
            & (
                ((after["kind"] == "SCAN") & (after["dst"] != QUEEN))
                | (after["kind"] == "MAP_REPORT")
            )
        ),
    )
    moving = windows(
        log, "MOVE", lambda after, w: (after["src"] == w) & (after["kind"] == "ARRIVED")
    )
    parent = model.tree.parent
    workers = {w.id for w in model.workers()}
    events = model.events()
    out: Counter = Counter()
    if "other" not in events:  # no contact of any kind in this run
        return out
    touches = events.loc[events["event"] == "collision", ["time", "robot", "other"]]
    for t, a, b in touches.dropna().itertuples(index=False):
        a, b = int(a), int(b)
        if a in workers and b in workers:
            who = "workers"
        elif a in workers or b in workers:
            w, s = (a, b) if a in workers else (b, a)
            who = "worker-own-scout" if parent[s] == w else "worker-other-scout"
        else:
            who = "siblings" if parent[a] == parent[b] else "cousins"
        doing = sorted(
            ("moving" if _inside(t, moving.get(r, [])) else "other")
            if r in workers
            else ("transit" if _inside(t, transit.get(parent[r], [])) else "in-bubble")
            for r in (a, b)
        )
        out[(who, *doing)] += 1
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sweep", type=Path, default=Path("out/sweeps/hierarchy_stagger"))
    ap.add_argument("--n", type=int, default=64, help="swarm size N of the runs to re-run")
    args = ap.parse_args(argv)
    runs_dir = args.sweep / "runs"
    if not runs_dir.is_dir():
        from analysis.cli import main as abm

        code = abm(["sweep", str(EXPERIMENT), "--out", str(args.sweep), "--workers", "1"])
        if code:
            return code
    runs = pd.concat([pd.read_parquet(f) for f in sorted(runs_dir.glob("*.parquet"))])
    runs = runs[(runs["N"] == args.n) & runs["scout_scan_area"].notna()]
    runs = runs[runs["robot_collisions"] > 0]  # the others have nothing to sort
    if runs.empty:
        print(f"no finished run with N = {args.n} and a contact in {args.sweep}", file=sys.stderr)
        return 2
    spec = json.loads((args.sweep / "sweep.json").read_text())
    params = [*spec["grid"], *(k for point in spec.get("points", []) for k in point)]
    rows = []
    for run in runs.sort_values(["subtree_transits", "seed"]).itertuples(index=False):
        kw = {p: getattr(run, p) for p in dict.fromkeys(params)}
        start = time.perf_counter()
        model = HierarchyModel(seed=int(run.seed), **kw).run()
        found = classify(model)
        assert (
            sum(found.values()) * 2 == model.summary()["robot_collisions"] == run.robot_collisions
        )
        for (who, one, other), n in found.items():
            rows.append({"subtree_transits": run.subtree_transits, "seed": run.seed,
                         "who": who, "doing": f"{one} / {other}", "contacts": n})  # fmt: skip
        print(f"{run.subtree_transits:10s} seed {run.seed}: {sum(found.values())} contacts "
              f"({time.perf_counter() - start:.1f} s)")  # fmt: skip
    table = pd.DataFrame(rows, columns=["subtree_transits", "seed", "who", "doing", "contacts"])
    summary = table.groupby(["subtree_transits", "who", "doing"])["contacts"].sum()
    print(summary.to_string())
    out = args.sweep / f"contacts_N{args.n}.csv"
    table.to_csv(out, index=False)
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
