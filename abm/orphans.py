"""Worker processes that cannot outlive the process that started them.

A sweep killed with SIGKILL runs no clean-up, so its pool workers (and, through them, the
forkserver and multiprocessing's resource tracker, which live as long as a worker holds their
pipes) would idle for ever, re-parented to init. Every worker the project starts therefore runs
a watchdog: a daemon thread that checks the starting process every ``PERIOD`` seconds and ends
the worker at once (``os._exit``) when it has gone. A pool worker's own parent is the forkserver,
not the sweep, so the watchdog follows the sweep's pid, checked against the start time the
kernel recorded for it (a pid reused by a new process does not fool it; a zombie counts as
gone). Where ``/proc`` is missing it falls back to ``os.kill(pid, 0)``.

Local pools pass the guard as their initializer (:func:`abm.pools.process_pool`). Dask's
LocalCluster needs none: its nannies and workers already exit within 0.1 s of their parent's
SIGKILL (measured; ``tests/test_orphans.py`` checks both).

How soon: a worker notices within ``PERIOD`` (when the busy machine schedules its thread) and
then takes the time its exit takes. Measured with a 2-worker sweep killed mid-run on a 2-core
machine busy with 4 or 12 spinning processes besides other work (kernel-timed with pidfds, 8
kills each): with ``PERIOD`` 0.25 s the workers were gone after 0.08-0.30 s and the whole
session after 0.15-0.33 s; with 0.05 s, 0.045-0.14 s and 0.06-0.17 s. A check costs one read
of ``/proc/<pid>/stat`` (microseconds), so the shorter period is kept. A machine swapping or
starved for CPU can take longer (1-1.5 s was seen under heavier load).
"""

import os
import threading
import time
from pathlib import Path

__all__ = ["PERIOD", "alive", "identity", "watch"]

#: Seconds between two checks of the parent (see the module's docstring for what it buys).
PERIOD = 0.05


def identity(pid: int | None = None) -> str:
    """``"pid:start"`` of a process (this one by default): its pid and the kernel's start time
    of it (empty where ``/proc`` is missing).
    """
    pid = os.getpid() if pid is None else pid
    return f"{pid}:{_start_time(pid) or ''}"


def alive(parent: str) -> bool:
    """Whether the process named by :func:`identity` still runs (not a zombie, not reused)."""
    pid_text, _, started = parent.partition(":")
    pid = int(pid_text)
    stat = _stat(pid)
    if stat is None:  # no /proc: ask the kernel whether the pid exists
        try:
            os.kill(pid, 0)
        except ProcessLookupError:
            return False
        except PermissionError:
            return True
        return True
    if stat is False:
        return False
    state, start = stat
    return state not in ("Z", "X") and (not started or start == started)


def watch(parent: str, period: float = PERIOD) -> threading.Thread:
    """Start the watchdog thread of this process: it exits the process when ``parent`` (an
    :func:`identity`) has gone. Returns the thread (a daemon).
    """
    thread = threading.Thread(
        target=_watch, args=(parent, period), name="abm-orphan-watchdog", daemon=True
    )
    thread.start()
    return thread


def _watch(parent: str, period: float) -> None:
    while alive(parent):
        time.sleep(period)
    os._exit(1)


def _stat(pid: int) -> tuple[str, str] | bool | None:
    """(state, start time) from ``/proc/<pid>/stat``; False if the pid is gone; None without
    ``/proc``.
    """
    if not Path("/proc/self/stat").exists():
        return None
    try:
        text = Path(f"/proc/{pid}/stat").read_text()
    except (FileNotFoundError, ProcessLookupError):
        return False
    fields = text[text.rindex(")") + 2 :].split()  # after "pid (comm) "
    return fields[0], fields[19]


def _start_time(pid: int) -> str | None:
    stat = _stat(pid)
    return stat[1] if isinstance(stat, tuple) else None
