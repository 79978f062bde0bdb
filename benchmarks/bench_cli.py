"""How fast the ``abm`` command answers: help, every model's help and a bad parameter, a run.

Times these commands end to end, each run as a fresh process (what a user waits for, start-up
and imports included), and prints each one's median over ``--repeats`` runs:

- ``abm --help``
- ``abm run MODEL --help`` for every model of the project
- ``abm run MODEL --trace-interval -1`` for every model (a parameter every model has, refused
  before any work: exit code 2), and the issue's ``abm run beacon-explorer --launch-period -3``
- ``abm run flocking`` (a whole run, saved, with its PNG)

then the slowest model's help and bad parameter, the figures the goal (under 1 s on a quiet
machine, for every model) is about.

Each command runs once untimed first, which fills numba's cache: the times are warm.

Give ``--abm`` once per installation to compare them side by side (e.g. main's checkout and
this one); their runs alternate, so a change in the machine's load hits both alike. Each
installation gets a numba cache folder of its own in a temporary folder
(``NUMBA_CACHE_DIR``) and writes no byte code, so timing another checkout writes nothing in
it; the runs' folders go to a temporary folder too. Prints the machine and the load average
before and after: on a loaded machine read the ratio, and name the machine beside any
absolute figure.

Usage: python benchmarks/bench_cli.py [--abm PATH/TO/bin/abm ...] [--repeats 5]
"""

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from importlib.metadata import entry_points
from pathlib import Path

from machine import machine  # benchmarks/machine.py, beside this script

#: The project's models (the entry points of this interpreter's installation).
MODELS = sorted(
    ep.name for ep in entry_points(group="swarm_abm.models") if ep.value.startswith("models.")
)
#: The commands timed, by label: arguments to ``abm`` and the exit code each must end with.
COMMANDS = {
    "abm --help": (["--help"], 0),
    **{f"abm run {m} --help": (["run", m, "--help"], 0) for m in MODELS},
    **{
        f"abm run {m} --trace-interval -1": (["run", m, "--trace-interval", "-1"], 2)
        for m in MODELS
    },
    "abm run beacon-explorer --launch-period -3": (
        ["run", "beacon-explorer", "--launch-period", "-3"],
        2,
    ),
    "abm run flocking": (["run", "flocking"], 0),
}
#: The slowest of these commands is printed apart: the goal holds for every model.
SLOWEST = {
    "slowest model's --help": [f"abm run {m} --help" for m in MODELS],
    "slowest model's bad parameter": [f"abm run {m} --trace-interval -1" for m in MODELS],
}


def timed(abm: Path, argv: list[str], expect: int, env: dict, cwd: Path) -> float:
    """Seconds one ``abm ARGV`` took as a fresh process; its exit code must be ``expect``."""
    start = time.perf_counter()
    done = subprocess.run([str(abm), *argv], env=env, cwd=cwd, capture_output=True, text=True)
    took = time.perf_counter() - start
    if done.returncode != expect:
        sys.exit(
            f"{abm} {' '.join(argv)}: exit code {done.returncode}, expected {expect}:\n"
            f"{done.stderr.strip()}"
        )
    return took


def main() -> int:
    """Time every command for every installation; print the medians side by side."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--abm",
        type=Path,
        action="append",
        help="an installation's abm script (repeatable) [this interpreter's]",
    )
    parser.add_argument("--repeats", type=int, default=5, help="runs per command [5]")
    args = parser.parse_args()
    installs = [p.absolute() for p in args.abm or [Path(sys.executable).parent / "abm"]]
    for abm in installs:
        if not abm.is_file():
            sys.exit(f"--abm {abm}: no such file")
    print(f"machine: {machine()}")
    print(f"load average before: {os.getloadavg()[0]:.2f}")
    times: dict[tuple[Path, str], list[float]] = {}
    with tempfile.TemporaryDirectory(prefix="bench-cli-") as scratch:
        envs, cwds = {}, {}
        for i, abm in enumerate(installs):
            envs[abm] = dict(
                os.environ,
                NUMBA_CACHE_DIR=str(Path(scratch) / f"numba-{i}"),
                PYTHONDONTWRITEBYTECODE="1",
            )
            cwds[abm] = Path(scratch) / f"runs-{i}"
            cwds[abm].mkdir()
            for argv, expect in COMMANDS.values():  # untimed: fills numba's cache
                timed(abm, argv, expect, envs[abm], cwds[abm])
        for label, (argv, expect) in COMMANDS.items():
            for _ in range(args.repeats):
                for abm in installs:
                    took = timed(abm, argv, expect, envs[abm], cwds[abm])
                    times.setdefault((abm, label), []).append(took)
    print(f"load average after: {os.getloadavg()[0]:.2f}")
    print(f"median of {args.repeats} fresh processes, seconds:")
    print(f"  {'command':<50}" + "".join(f"{f'[{i}]':>9}" for i in range(len(installs))))
    for label in COMMANDS:
        medians = [statistics.median(times[abm, label]) for abm in installs]
        print(f"  {label:<50}" + "".join(f"{m:>9.2f}" for m in medians))
    for label, among in SLOWEST.items():
        worst = [max(statistics.median(times[abm, c]) for c in among) for abm in installs]
        print(f"  {label:<50}" + "".join(f"{m:>9.2f}" for m in worst))
    for i, abm in enumerate(installs):
        print(f"  [{i}] {abm}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
