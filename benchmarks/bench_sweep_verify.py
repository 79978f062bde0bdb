"""What a sweep's integrity costs: the time to write one run's file (atomic rename, Parquet page
checksums) and to verify a folder of finished runs on restart (``analysis.sweep.integrity``).

Writes ``RUNS`` copies of one real run's row under fresh run ids and seeds, then times the
restart scan (each file is also matched against the plan). Usage:
``.venv/bin/python benchmarks/bench_sweep_verify.py [RUNS]``.
"""

import sys
import tempfile
import time
from pathlib import Path

from analysis.runner import run_one
from analysis.sweep import Sweep, plan
from analysis.sweep.integrity import RESULT_FOLDERS, scan
from analysis.sweep.membership import PlanIndex
from analysis.sweep.storage import store

RUNS = 1000  # run files written and verified


def main(runs: int = RUNS) -> None:
    sweep = Sweep("beacon-explorer", {"world": ["corridor"], "time_limit": [30.0]},
                  replications=runs, seed=1)  # fmt: skip
    specs = plan(sweep)
    row = run_one(specs[0])["row"]
    with tempfile.TemporaryDirectory() as folder:
        out = Path(folder)
        for sub in RESULT_FOLDERS:
            (out / sub).mkdir()
        start = time.perf_counter()
        for spec in specs:
            store(out, {"row": {**row, "run_id": spec.run_id, "seed": spec.seed, "rep": spec.rep}})
        write = time.perf_counter() - start
        start = time.perf_counter()
        done, _failed, moved = scan(out, PlanIndex.of(sweep))
        verify = time.perf_counter() - start
    assert len(done) == runs and not moved
    print(f"{runs} runs: write {1e3 * write / runs:.1f} ms a run, "
          f"verify on restart {verify:.2f} s ({1e3 * verify / runs:.2f} ms a run)")  # fmt: skip


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else RUNS)
