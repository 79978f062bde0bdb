"""The ABMFrameworksComparison flocking benchmark: our model beside Mesa 3.5 and Mesa 3.2.0.

The Mesa side is ``flocking_mesa.py`` (beside this script): Mesa's own ``boid_flockers``
example with its update replaced by the comparison's declared rule. It runs in worker
processes, one per Mesa: this environment's Mesa (3.5.1 here) and Mesa 3.2.0, the version of
the comparison's published table, installed by this script in a venv of its own
(``--venvs``, by default ``out/bench/venvs/mesa-3.2.0``) on first use; when pip cannot reach
PyPI it says so and the benchmark goes on without it. Ours is
``models.flocking.FlockingModel`` (Mesa agents, the SimPy clock, the compiled sequential
update), in this process, in two modes:

- *data collection off*: no position trace (``trace_interval=None``), as the comparison records
  nothing; the model still samples its two order parameters after every step (its
  ``samples()``, a few hundred nanoseconds per step);
- *defaults*: the constructor's defaults, which also trace every bird's position every second
  (``positions()``, what ``abm render`` draws). Mesa's example collects nothing by default, so
  the Mesa side is the same in both.

What is timed, as the comparison's current harnesses do (``Flocking/Agents/
benchmark_flocking.jl`` and ``Flocking/Mesa/benchmark_flocking.py``): one run is the model's
construction plus exactly 100 steps, from a seed drawn for the run; the median over the runs
is reported, with the quartiles of the CPU times beside it. Both wall time (what the
comparison reports) and CPU time of the process that ran it (fairer on a machine shared with
other work) are measured. All runs are interleaved: each round is one run of every Mesa, then
a few of ours in each mode, so all see the same load.

Run: ``.venv/bin/python benchmarks/bench_flocking.py`` (``--mesa-runs``, ``--our-runs``,
``--mesa``, ``--venvs``).
"""

import argparse
import datetime
import json
import os
import subprocess
import sys
import time
from collections.abc import Callable, Sequence
from pathlib import Path

import mesa
import numpy as np
from tqdm import tqdm

from models.flocking import LARGE, SMALL, FlockingModel
from models.flocking.published import SLOWER_THAN_AGENTS_JL

sys.path.insert(0, str(Path(__file__).resolve().parent))
from machine import load_average, machine  # noqa: E402  (benchmarks/machine.py, beside this script)

STEPS = 100  # the declaration: exactly 100 steps
CASES = {"small": SMALL, "large": LARGE}
SEED = 42  # seeds of the runs are drawn from this one, as the comparison draws them
TARGET = 400.0  # the goal: at least this many times faster than Mesa, on both cases
#: Our two modes: data collection off, and the constructor's defaults.
MODES = {"DC off": {"trace_interval": None}, "defaults": {}}
WORKER = Path(__file__).resolve().parent / "flocking_mesa.py"
ROOT = Path(__file__).resolve().parent.parent
#: The columns of one run's row (s, s, s, s, -).
FIELDS = ("wall", "cpu", "wall_steps", "cpu_steps", "polarisation")
#: The column of a run's CPU time in :data:`FIELDS`.
CPU = FIELDS.index("cpu")


class MesaUnavailableError(RuntimeError):
    """A Mesa version could not be installed (no network to PyPI, most likely)."""


def mesa_python(
    version: str, venvs: Path, run: Callable[..., subprocess.CompletedProcess] = subprocess.run
) -> Path:
    """The Python of a venv that holds ``mesa==version``, made under ``venvs`` on first use.

    Raises:
        MesaUnavailableError: the venv or pip failed (pip's last words in the message).

    """
    home = venvs / f"mesa-{version}"
    python = home / ("Scripts/python.exe" if os.name == "nt" else "bin/python")
    stamp = home / "installed.txt"
    if stamp.exists():
        return python
    print(
        f"Mesa {version}: making a venv of its own at {home} and installing mesa=={version} "
        "into it with pip (first use only; about a minute)",
        flush=True,
    )
    steps = (
        [sys.executable, "-m", "venv", "--clear", str(home)],
        [str(python), "-m", "pip", "install", "--quiet", "--disable-pip-version-check",
         "--timeout", "20", "--retries", "1", f"mesa=={version}"],
    )  # fmt: skip
    for command in steps:
        done = run(command, capture_output=True, text=True)
        if done.returncode != 0:
            said = (done.stderr or done.stdout or "").strip().splitlines()[-3:]
            raise MesaUnavailableError(
                f"Mesa {version} could not be installed ({' '.join(command[:4])} ... failed: "
                f"{' / '.join(said) or 'no message'}). pip needs PyPI (or a local index) for "
                f"mesa=={version} and its dependencies; the benchmark goes on without Mesa "
                f"{version}. Run it again once PyPI can be reached (or delete {home} to retry)."
            )
    stamp.write_text(f"mesa=={version}\n")
    return python


class MesaWorker:
    """A worker process running ``flocking_mesa.py`` under one Python (one Mesa)."""

    def __init__(self, python: str | Path) -> None:
        self.process = subprocess.Popen(
            [str(python), str(WORKER), "--worker"],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            text=True,
            cwd=WORKER.parent,
        )
        #: What the worker runs: {"mesa": .., "numpy": .., "python": ..}.
        self.versions = json.loads(self._read())

    def _read(self) -> str:
        line = self.process.stdout.readline()
        if not line:
            raise RuntimeError(f"the Mesa worker {self.process.args} ended without answering")
        return line

    def run(self, seed: int, case: dict, steps: int = STEPS) -> tuple[float, ...]:
        """One timed Mesa run (:data:`FIELDS`)."""
        self.process.stdin.write(json.dumps({"seed": seed, "steps": steps, **case}) + "\n")
        self.process.stdin.flush()
        answer = json.loads(self._read())
        return tuple(answer[f] for f in FIELDS)

    def close(self) -> None:
        """End the worker."""
        self.process.stdin.close()
        self.process.wait(timeout=30)


def our_run(seed: int, case: dict, mode: dict, steps: int = STEPS) -> tuple[float, ...]:
    """One timed run of ours (:data:`FIELDS`)."""
    w0, c0 = time.perf_counter(), time.process_time()
    model = FlockingModel(seed=seed, steps=steps, **mode, **case)
    w1, c1 = time.perf_counter(), time.process_time()
    model.run()
    w2, c2 = time.perf_counter(), time.process_time()
    return w2 - w0, c2 - c0, w2 - w1, c2 - c1, model.summary()["polarisation"]


def summarise(rows: dict[str, Sequence[tuple[float, ...]]], mesa_names: Sequence[str]) -> dict:
    """Medians of every framework's rows, the quartiles of its CPU times, and Mesa's medians
    over ours (times faster than each Mesa) for each of our modes: ``{"median": {name:
    array}, "cpu_quartiles": {name: (25th, 75th percentile)}, "ratio": {(mesa, mode): array
    of wall, cpu, wall of the steps, cpu of the steps}}``. The quartiles show how far a median
    can be trusted on a shared machine: work on the other core moves short runs by up to 1.5x.
    """
    table = {name: np.asarray(r, dtype=float) for name, r in rows.items()}
    median = {name: np.median(t, axis=0) for name, t in table.items()}
    quartiles = {name: tuple(np.percentile(t[:, CPU], [25, 75])) for name, t in table.items()}
    ours = [name for name in rows if name not in mesa_names]
    ratio = {(m, o): median[m][:4] / median[o][:4] for m in mesa_names for o in ours}
    return {"median": median, "cpu_quartiles": quartiles, "ratio": ratio}


def _bench(case: dict, workers: dict, mesa_runs: int, our_runs: int, bar: tqdm) -> dict:
    seeds = np.random.default_rng(SEED).integers(1, 10_001, size=max(mesa_runs, our_runs))
    per_round = -(-our_runs // mesa_runs)
    rows = {name: [] for name in (*workers, *MODES)}
    for r in range(mesa_runs):  # one run of every Mesa, then a few of ours in each mode
        for name, worker in workers.items():
            rows[name].append(worker.run(int(seeds[r]), case))
            bar.update(1)
        for k in range(r * per_round, min((r + 1) * per_round, our_runs)):
            for mode, keywords in MODES.items():
                rows[mode].append(our_run(int(seeds[k]), case, keywords))
    return summarise(rows, list(workers))


def _report(results: dict, workers: dict, args: argparse.Namespace, load: tuple) -> None:
    print(
        f"\nFlocking, construction + {STEPS} steps: medians of {args.mesa_runs} runs per Mesa "
        f"and {args.our_runs} of ours per mode (seeds from {SEED}), "
        f"{datetime.date.today().isoformat()}\n{machine()}; {load[0]} before, {load[1]} after"
    )
    for name, worker in workers.items():
        v = worker.versions
        print(f"  {name}: Mesa {v['mesa']}, numpy {v['numpy']}, Python {v['python']}")
    print(
        f"\n{'case':6} {'Mesa':7} {'Mesa wall':>10} {'Mesa CPU':>10} | {'ours':9}"
        f"{'wall':>9} {'CPU':>9} {'x wall':>7} {'x CPU':>7}  >= {TARGET:.0f}x (CPU)"
    )
    for case, res in results.items():
        for name in workers:
            m = res["median"][name]
            for mode in MODES:
                o, x = res["median"][mode], res["ratio"][(name, mode)]
                print(
                    f"{case:6} {name:7} {m[0] * 1e3:8.1f}ms {m[1] * 1e3:8.1f}ms | {mode:9}"
                    f"{o[0] * 1e3:7.2f}ms {o[1] * 1e3:7.2f}ms {x[0]:6.0f}x {x[1]:6.0f}x  "
                    f"{'yes' if x[1] >= TARGET else 'no'}"
                )
    print("\nSpread: CPU time of a run, 25th / 50th / 75th percentile")
    for case, res in results.items():
        for name in res["median"]:
            low, high = res["cpu_quartiles"][name]
            middle = res["median"][name][CPU]
            said = " / ".join(f"{t * 1e3:8.2f}" for t in (low, middle, high))
            print(f"{case:6} {name:9} {said} ms")
    print(f"\nThe {STEPS} steps alone (construction excluded), ratios wall / CPU")
    for case, res in results.items():
        for name in workers:
            ratios = {mode: res["ratio"][(name, mode)] for mode in MODES}
            parts = [f"{mode} {x[2]:.0f}x / {x[3]:.0f}x" for mode, x in ratios.items()]
            print(f"{case:6} {name:7} " + "   ".join(parts))
    print(f"\nSame rules: median polarisation after {STEPS} steps")
    for case, res in results.items():
        said = "   ".join(f"{name} {res['median'][name][4]:.2f}" for name in res["median"])
        print(f"{case:6} {said}")
    print("\nPublished (ABMFrameworksComparison): times slower than Agents.jl, small / large")
    for framework, (small, large) in SLOWER_THAN_AGENTS_JL.items():
        print(f"  {framework:9} {small:6.2f} / {large:5.2f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--mesa-runs", type=int, default=10, help="seeded runs per Mesa and case")
    parser.add_argument("--our-runs", type=int, default=100, help="seeded runs of ours per mode")
    parser.add_argument(
        "--mesa",
        action="append",
        help="a Mesa version to time in a venv of its own, besides this environment's "
        "(repeatable; default 3.2.0, the published table's; 'none' for this one alone)",
    )
    parser.add_argument(
        "--venvs",
        type=Path,
        default=ROOT / "out" / "bench" / "venvs",
        help="where the other Mesa versions' venvs are made (default out/bench/venvs)",
    )
    args = parser.parse_args()
    if args.mesa_runs < 1 or args.our_runs < 1:
        parser.error("--mesa-runs and --our-runs must be at least 1")
    versions = [v for v in (args.mesa or ["3.2.0"]) if v != "none"]
    pythons = {mesa.__version__: Path(sys.executable)}
    for version in versions:
        try:
            pythons.setdefault(version, mesa_python(version, args.venvs))
        except MesaUnavailableError as why:
            print(f"note: {why}", file=sys.stderr, flush=True)
    workers = {version: MesaWorker(python) for version, python in pythons.items()}
    for mode in MODES.values():  # compile the kernel, warm the caches
        our_run(1, {"birds": 20, "extent": 30.0, "visual_distance": 5.0}, mode)
    load_before = load_average()
    results = {}
    total = len(CASES) * args.mesa_runs * len(workers)
    with tqdm(total=total, desc="Mesa runs (ours interleaved)") as bar:
        for name, case in CASES.items():
            results[name] = _bench(case, workers, args.mesa_runs, args.our_runs, bar)
    for worker in workers.values():
        worker.close()
    _report(results, workers, args, (load_before, load_average()))


if __name__ == "__main__":
    main()
