"""The machine a benchmark ran on and its load, named the same way in every benchmark's output."""

import os
import platform
import subprocess
import time


def machine() -> str:
    """CPU model and core count (from lscpu where there is one)."""
    name = platform.processor() or platform.machine()
    try:
        for line in subprocess.run(["lscpu"], capture_output=True, text=True).stdout.splitlines():
            if line.startswith("Model name:"):
                name = line.split(":", 1)[1].strip()
    except OSError:
        pass
    return f"{name}, {os.cpu_count()} logical CPUs, Python {platform.python_version()}"


def load_average() -> str:
    """The load average over 1, 5 and 15 minutes, and the core count: a benchmark prints it
    before and after, since the cores may be shared.
    """
    try:
        one, five, fifteen = os.getloadavg()
    except OSError:  # a platform without it
        return f"load average unknown, {os.cpu_count()} cores"
    return f"load average {one:.2f} {five:.2f} {fifteen:.2f} on {os.cpu_count()} cores"


def speed_probe() -> str:
    """CPU seconds of a fixed pure-Python loop, ``sum(range(30_000_000))``: interpreter work,
    as much of a run's is. These machines' speed drifts from one hour to the next (shared
    hosts: 1.24 s, then 0.72-0.93 s 90 minutes later on the 2.0 GHz Intel Xeon on 2026-12-02;
    0.38-0.58 s on a Zen 5 EPYC the same day), so a benchmark that states minutes prints this
    beside them. It is a rough guide: the figure sets' runs took 0.48-0.87x the time the
    second time, not all the probe's 0.6-0.75x.
    """
    start = time.process_time()
    sum(range(30_000_000))
    return f"speed probe {time.process_time() - start:.2f} s of CPU"
