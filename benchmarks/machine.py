"""The machine a benchmark ran on, named the same way in every benchmark's output."""

import os
import platform
import subprocess


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
