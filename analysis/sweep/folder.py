"""A sweep's folder is the sweep's alone: checked before use, and locked while a sweep runs.

* :func:`check_out` refuses a folder that holds anything but a sweep (a user's folder with
  files of its own and no ``sweep.json``), a file where the folder should be, and result
  folders that are links to elsewhere: a sweep writes only inside the folder it is given.
* :class:`SweepLock` is a lock file (``.lock``: the holder's pid, host and start) taken
  atomically; a second sweep on the same folder stops with one line naming the holder. A lock
  is broken only when its holder is gone (same host, the process no longer exists or is
  another process that reused the pid), and breaking it is said on stderr. A lock held from
  another host is never broken: the message says how to remove it by hand.
"""

import datetime
import json
import os
import socket
import sys
from pathlib import Path

from abm.errors import OutputError
from abm.orphans import alive, identity
from analysis.sweep.integrity import RESULT_FOLDERS, SET_ASIDE

__all__ = ["LOCK", "SweepLock", "check_out", "refuse_while_running"]

#: The lock file inside a sweep folder.
LOCK = ".lock"

#: What a sweep's start leaves before its ``sweep.json`` exists (a start killed early).
_START_ENTRIES = {LOCK, ".sweep.json.tmp"}


def check_out(out: Path) -> None:
    """Raise OutputError unless ``out`` is a place this sweep may write: new, empty, a sweep
    folder, or what a sweep killed at start-up left.
    """
    if out.exists() and not out.is_dir():
        raise OutputError(f"{out} is a file, not a folder: choose a folder for the sweep (--out)")
    if not out.is_dir():
        return
    for sub in (*RESULT_FOLDERS, SET_ASIDE):
        if (out / sub).is_symlink():
            raise OutputError(
                f"{out / sub} is a link: a sweep writes only inside its own folder; "
                "choose another folder (--out)"
            )
    if (out / "sweep.json").is_file():
        return
    foreign = [
        p.name
        for p in sorted(out.iterdir())
        if p.name not in _START_ENTRIES
        and not p.name.startswith(".lock.")
        and not (p.name in (*RESULT_FOLDERS, SET_ASIDE) and p.is_dir() and not any(p.iterdir()))
    ]
    if foreign:
        shown = ", ".join(foreign[:3]) + (", ..." if len(foreign) > 3 else "")
        raise OutputError(
            f"{out} is not a sweep folder (no sweep.json) and holds {shown}: a sweep writes "
            "only into a new or empty folder or its own; choose another folder (--out)"
        )


def refuse_while_running(out: Path, what: str) -> None:
    """Raise OutputError (one line) while a sweep that may still be running holds ``out``'s
    lock: ``what`` (e.g. "a report") would read the runs finished so far as the whole sweep.
    """
    lock = SweepLock(out)
    holder = lock.holder()
    if holder and lock.running(holder):
        raise OutputError(
            f"{out} is being written by a running sweep (pid {holder['pid']} on "
            f"{holder['host']}, since {holder.get('since')}): {what} would read only the runs "
            "finished so far; run it when the sweep has ended"
        )


class SweepLock:
    """The lock of a sweep folder, held while a sweep writes there (a context manager)."""

    def __init__(self, out: Path) -> None:
        self.out = out
        self.path = out / LOCK
        self.me = {
            "pid": os.getpid(),
            "host": socket.gethostname(),
            "start": identity().partition(":")[2] or None,
            "since": datetime.datetime.now().isoformat(timespec="seconds"),
        }

    def __enter__(self) -> "SweepLock":
        self.out.mkdir(parents=True, exist_ok=True)
        tmp = self.out / f".lock.{os.getpid()}.tmp"
        tmp.write_text(json.dumps(self.me))
        try:
            for _attempt in range(3):
                try:
                    os.link(tmp, self.path)  # atomic: fails if a lock exists
                    return self
                except FileExistsError:
                    self._break_or_refuse()
            raise OutputError(f"{self.path}: could not take the lock; run the command again")
        finally:
            tmp.unlink(missing_ok=True)

    def __exit__(self, *exc: object) -> None:
        try:
            if self.holder() == self.me:
                self.path.unlink(missing_ok=True)
        except OSError:
            pass  # a folder gone read-only: the next sweep sees this process gone and breaks it

    def holder(self) -> dict | None:
        """The lock file's holder (pid, host, start, since); None without a lock, {} for a
        damaged one.
        """
        try:
            holder = json.loads(self.path.read_text())
        except FileNotFoundError:
            return None
        except (ValueError, UnicodeDecodeError):
            return {}
        return holder if isinstance(holder, dict) else {}

    def running(self, holder: dict) -> bool:
        """Whether the lock's holder may still run: alive on this host, or on another host
        (which this one cannot look into).
        """
        pid, host = holder.get("pid"), holder.get("host")
        if not isinstance(pid, int) or not isinstance(host, str):
            return False
        return host != self.me["host"] or alive(f"{pid}:{holder.get('start') or ''}")

    def _break_or_refuse(self) -> None:
        """Remove the lock of a holder that is gone; refuse (one line) if it may be running."""
        holder = self.holder()
        if holder is None:
            return  # released meanwhile: try again
        pid, host = holder.get("pid"), holder.get("host")
        if not isinstance(pid, int) or not isinstance(host, str):
            raise OutputError(
                f"{self.path} is a damaged lock file; if no sweep runs in {self.out}, delete "
                "it and run the command again"
            )
        if self.running(holder):
            where = "" if host == self.me["host"] else f" (if it is gone, delete {self.path})"
            raise OutputError(
                f"{self.out} is in use by another sweep: pid {pid} on {host}, since "
                f"{holder.get('since')}; wait for it to end or choose another folder "
                f"(--out){where}"
            )
        stale = self.out / f".lock.stale.{os.getpid()}"
        try:
            os.replace(self.path, stale)
        except FileNotFoundError:
            return
        if self._read(stale) != holder:  # another sweep took the lock meanwhile: give it back
            try:
                os.link(stale, self.path)
            except FileExistsError:
                pass
            stale.unlink(missing_ok=True)
            return
        stale.unlink(missing_ok=True)
        print(
            f"broke the lock of a sweep that is gone (pid {pid} on {host}, since "
            f"{holder.get('since')})",
            file=sys.stderr,
        )

    @staticmethod
    def _read(path: Path) -> dict | None:
        try:
            return json.loads(path.read_text())
        except (OSError, ValueError, UnicodeDecodeError):
            return None
