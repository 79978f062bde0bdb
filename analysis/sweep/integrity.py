"""Checking a sweep folder on restart: every result file is verified before it counts as done.

A sweep killed with ``kill -9`` (or a full disk, a copy cut short, a stray file) can leave
behind files that must not be read as results. On every start of a sweep each file under
``runs/``, ``failed/``, ``series/``, ``samples/`` and ``changes/`` is opened and checked:

* it is a whole Parquet file whose page checksums hold (a truncated or overwritten file fails
  here: its footer is missing or a page's CRC is wrong);
* a run's row (``runs/``, ``failed/``) is exactly one row whose ``run_id`` is the file's name
  and whose ``status`` fits the folder, and it is a run of the folder's plan: its parameters
  are the plan's values, its ``run_id`` the one the plan gives them and its ``seed`` and
  ``rep`` the plan's (:class:`~analysis.sweep.membership.PlanIndex`) - a run of another
  sweep, another seed or with edited parameters is set aside, never counted;
* a series, samples or changes file's rows all carry the file's ``run_id``.

A file that fails is never deleted: it is moved to ``set_aside/<folder>/`` under a name that
says why (``<run_id>.<reason>.<time>.parquet``), reported, and its run is run again.
Temporary files a killed writer left (``.<name>.<pid>.tmp``) are set aside as
``half-written`` the same way.
"""

import concurrent.futures as cf
import datetime
import os
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import pyarrow as pa
import pyarrow.parquet as pq

if TYPE_CHECKING:
    from analysis.sweep.membership import PlanIndex

__all__ = [
    "RESULT_FOLDERS",
    "SET_ASIDE",
    "CorruptResultError",
    "SetAside",
    "first_row",
    "read_table_verified",
    "run_ids",
    "scan",
    "set_aside",
]

#: The folders of a sweep that hold result files, one per run.
RESULT_FOLDERS = ("runs", "failed", "series", "samples", "changes")

#: Where files that failed the check go (inside the sweep folder).
SET_ASIDE = "set_aside"


class CorruptResultError(Exception):
    """A result file failed a check; ``reason`` is the short word used in its new name."""

    def __init__(self, reason: str, detail: str) -> None:
        super().__init__(detail)
        self.reason = reason


@dataclass(frozen=True)
class SetAside:
    """A file moved out of the way.

    Attributes:
        source: where it was.
        target: where it is now.
        reason: one word: ``unreadable``, ``wrong-run-id``, ``wrong-seed``, ``wrong-params``,
            ``not-in-plan``, ``wrong-status``, ``not-one-row`` or ``half-written``.
        detail: what the check found.

    """

    source: Path
    target: Path
    reason: str
    detail: str

    def __str__(self) -> str:
        return f"set aside {self.source} -> {self.target} ({self.reason}: {self.detail})"


def read_table_verified(path: Path) -> pa.Table:
    """Read a result file as an Arrow table, checking its Parquet page checksums.

    Raises:
        CorruptResultError: the file is not a whole, intact Parquet file (reason ``unreadable``).

    """
    try:
        # one file through ParquetFile, single-threaded: the same table as pq.read_table's,
        # in under half its time for a one-row file (a report reads every run's file)
        with pq.ParquetFile(path, page_checksum_verification=True) as file:
            return file.read(use_threads=False)
    except Exception as exc:  # pyarrow raises ArrowInvalid, OSError, ... for damaged files
        raise CorruptResultError("unreadable", f"{type(exc).__name__}: {exc}") from exc


def first_row(table: pa.Table) -> dict:
    """A table's first row as plain Python values (None where a value is missing): what a
    run's row file holds, read without converting the file to pandas (a few milliseconds a
    file, which a report or a restart pays for every run).
    """
    return table.slice(0, 1).to_pylist()[0]


def run_ids(table: pa.Table) -> set[str]:
    """The run ids a result file's rows carry (as text; empty without a ``run_id`` column)."""
    if "run_id" not in table.column_names:
        return set()
    return {str(v) for v in table.column("run_id").to_pylist()}


def _check(path: Path, folder: str, index: "PlanIndex") -> tuple[dict, int] | None:
    """Raise CorruptResultError unless ``path`` holds what its name and folder promise; a
    run's row must also be the plan's (its parameters, replication and seed). Returns the
    run's plan parameters and replication (None for a series or samples file).
    """
    table = read_table_verified(path)
    run_id = path.stem
    if "run_id" not in table.column_names:
        raise CorruptResultError("wrong-run-id", "no run_id column")
    ids = run_ids(table)
    if ids != {run_id}:
        shown = ", ".join(sorted(ids)[:3]) or "no rows"
        raise CorruptResultError("wrong-run-id", f"the file is named {run_id} but holds {shown}")
    if folder not in ("runs", "failed"):
        return None
    if table.num_rows != 1:
        raise CorruptResultError("not-one-row", f"{table.num_rows} rows, a run has one")
    row = first_row(table)
    status = "ok" if folder == "runs" else "failed"
    if row.get("status") != status:
        raise CorruptResultError("wrong-status", f"status {row.get('status')!r} in {folder}/")
    return index.match(row, run_id)


def _problem(
    path: Path, folder: str, index: "PlanIndex"
) -> tuple[dict, int] | CorruptResultError | None:
    """What is wrong with ``path`` (a CorruptResultError), else what :func:`_check` gives."""
    try:
        return _check(path, folder, index)
    except CorruptResultError as exc:
        return exc


def _stamp() -> str:
    return datetime.datetime.now().strftime("%Y%m%dT%H%M%S%f")


def set_aside(out: Path, path: Path, reason: str, detail: str) -> SetAside:
    """Move ``path`` to ``out/set_aside/<its folder>/`` under a name saying ``reason``."""
    folder = out / SET_ASIDE / path.parent.relative_to(out)
    folder.mkdir(parents=True, exist_ok=True)
    stem = path.name.lstrip(".").split(".")[0] if path.suffix == ".tmp" else path.stem
    target = folder / f"{stem}.{reason}.{_stamp()}{'.parquet' if reason != 'half-written' else ''}"
    os.replace(path, target)
    return SetAside(path, target, reason, detail)


def scan(out: Path, index: "PlanIndex") -> tuple[dict, dict, list[SetAside]]:
    """Verify every result file of the sweep folder ``out``; set aside the ones that fail.

    Args:
        out: the sweep folder.
        index: the folder's plan (every run file must be one of its runs).

    Returns:
        ``(done, failed, moved)``: run id -> (parameters, replication) of the verified rows in
        ``runs/`` and in ``failed/``, and the files set aside. A run whose series, samples or
        changes file was set aside is not in ``done`` (it runs again and writes them anew).

    """
    found: dict[str, dict] = {}
    moved: list[SetAside] = []
    for folder in RESULT_FOLDERS:
        path_folder = out / folder
        ok: dict = {}
        if path_folder.is_dir():
            for tmp in sorted(path_folder.glob(".*.tmp")):
                moved.append(set_aside(out, tmp, "half-written", "a write a killed sweep cut"))
            paths = sorted(path_folder.glob("*.parquet"))
            with cf.ThreadPoolExecutor(max_workers=4) as pool:  # pyarrow reads without the GIL
                problems = pool.map(lambda p, f=folder: _problem(p, f, index), paths)
                for path, problem in zip(paths, problems, strict=True):
                    if isinstance(problem, CorruptResultError):
                        moved.append(set_aside(out, path, problem.reason, str(problem)))
                    else:
                        ok[path.stem] = problem
        found[folder] = ok
    damaged = {
        m.source.stem for m in moved if m.source.parent.name in ("series", "samples", "changes")
    }
    done = {k: v for k, v in found["runs"].items() if k not in damaged}
    return done, found["failed"], moved
