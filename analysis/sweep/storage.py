"""A sweep's dataset on disk: one Parquet file per finished run, written atomically.

::

    out/sweeps/corridor/
        sweep.json                 what was asked (model, grid, replications, seed)
        runs/<run_id>.parquet      one row per finished run (written at once, atomic rename)
        failed/<run_id>.parquet    one row per run that raised: error and traceback
        series/<run_id>.parquet    the run's state counts over time (when ``time_series``)
        samples/<run_id>.parquet   the model's own time series (when ``time_series`` and the
                                   model records one)
        changes/<run_id>.parquet   the run's state changes, removals and launches (when
                                   ``time_series``): what ``abm fit --rates --read`` fits
        set_aside/<folder>/        files that failed the check on restart, named
                                   ``<run_id>.<reason>.<time>.parquet`` (never deleted; see
                                   :mod:`analysis.sweep.integrity`)

Every file is written to a temporary name and renamed (atomic), with Parquet page checksums;
on restart every file is verified before its run counts as done, and reading
(:func:`load_results`) refuses a damaged file with a message naming it.
"""

import concurrent.futures as cf
import datetime
import json
import math
import os
import re
from pathlib import Path

import pandas as pd
import pyarrow as pa
import pyarrow.parquet as pq

from abm.errors import ABMError, ConfigError
from abm.targets import check_target
from analysis.sweep.integrity import (
    RESULT_FOLDERS,
    CorruptResultError,
    SetAside,
    first_row,
    read_table_verified,
    run_ids,
    set_aside,
)
from analysis.sweep.membership import PlanIndex
from analysis.sweep.spec import Sweep

__all__ = [
    "SweepError",
    "done_ids",
    "load_results",
    "prepare_out",
    "read_manifest",
    "store",
    "swept_keys",
]


class SweepError(ABMError):
    """A sweep cannot go on (its output folder belongs to another sweep, the executor broke)."""


def _write_atomic(data: pd.DataFrame | pa.Table, path: Path) -> None:
    """Write ``data`` to ``path`` whole or not at all: a temporary file renamed over ``path``
    (a killed writer leaves only the temporary file). Page checksums let a reader detect a file
    damaged later. No fsync (it doubled the write time): a file an operating-system crash
    leaves empty or torn fails the check on restart and its run runs again.
    """
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        _write_parquet(data, tmp)
        os.replace(tmp, path)
    except OSError as exc:  # full disk, read-only folder: no half file left, the error names it
        tmp.unlink(missing_ok=True)
        raise _named(exc, path) from exc


def _named(exc: OSError, path: Path) -> OSError:
    """``exc`` with its errno and the file named (pyarrow puts "[Errno 28]" only in its text),
    so the command line can say what to do.
    """
    code = exc.errno
    if code is None:
        found = re.search(r"\[errno (\d+)\]", str(exc), re.IGNORECASE)
        code = int(found.group(1)) if found else None
    if code is None:
        return OSError(f"cannot write {path}: {exc}")
    return OSError(code, os.strerror(code), str(path))


def _write_parquet(data: pd.DataFrame | pa.Table, path: Path) -> None:
    """The one place result files are written (Parquet with page checksums)."""
    if isinstance(data, pd.DataFrame):
        data.to_parquet(path, index=False, write_page_checksum=True)
    else:
        pq.write_table(data, path, write_page_checksum=True)


def _row_table(row: dict) -> pa.Table:
    """A run's row as a one-row Arrow table, built from the values themselves: read back, the
    same frame as ``pd.DataFrame([row])`` written by pandas, in a third of the time (the sweep's
    parent writes every run's row, so this bounds how many runs a second it can keep up with).
    """
    return pa.Table.from_pylist([row])


def store(out: Path, result: dict) -> None:
    """Write one run's result (its row, and its series when kept)."""
    row = result["row"]
    run_id = row["run_id"]
    if row["status"] == "ok":
        for kind in ("series", "samples", "changes"):
            if result.get(kind) is not None:
                _write_atomic(result[kind], out / kind / f"{run_id}.parquet")
        _write_atomic(_row_table(row), out / "runs" / f"{run_id}.parquet")
        (out / "failed" / f"{run_id}.parquet").unlink(missing_ok=True)
    else:
        _write_atomic(_row_table(row), out / "failed" / f"{run_id}.parquet")


def done_ids(folder: Path) -> set[str]:
    """The run ids with a file in ``folder``."""
    return {p.stem for p in folder.glob("*.parquet")} if folder.is_dir() else set()


#: What to do about a result file that cannot be read as its run's.
_RUN_AGAIN = "run the sweep again: it sets the file aside and runs that run again"


def _read_one(path: Path, one_row: bool = False) -> pa.Table:
    """A run's result file, verified and holding that run's rows only, and exactly one row
    when ``one_row`` (a run's row file); SweepError if not.
    """
    try:
        table = read_table_verified(path)
    except CorruptResultError as exc:
        raise SweepError(f"{path} is damaged ({exc}); {_RUN_AGAIN}") from exc
    if run_ids(table) != {path.stem}:
        raise SweepError(f"{path} does not hold run {path.stem}; {_RUN_AGAIN}")
    if one_row and table.num_rows != 1:
        raise SweepError(f"{path} holds {table.num_rows} rows, a run has one; {_RUN_AGAIN}")
    return table


def _read_folder(folder: Path, one_row: bool = False) -> list[pa.Table]:
    files = sorted(folder.glob("*.parquet")) if folder.is_dir() else []
    with cf.ThreadPoolExecutor(max_workers=4) as pool:  # pyarrow reads without the GIL
        return list(pool.map(lambda path: _read_one(path, one_row), files))


def load_results(
    out: str | Path,
    *,
    failed: bool = True,
    series: bool = False,
    samples: bool = False,
    changes: bool = False,
) -> pd.DataFrame:
    """Read a sweep's dataset: one row per run (finished first, then failures).

    Args:
        out: the sweep's folder.
        failed: include the rows of runs that raised (``status == "failed"``).
        series: return the concatenated state counts over time (``series/``) instead.
        samples: return the concatenated model time series (``samples/``) instead.
        changes: return the concatenated lifecycle events (``changes/``) instead.

    """
    out = Path(out)
    if not out.is_dir():
        raise FileNotFoundError(f"no sweep folder {str(out)!r}")
    done = done_ids(out / "runs")
    if series or samples or changes:
        kind = "series" if series else "samples" if samples else "changes"
        frames = [
            t.to_pandas(use_threads=False)
            for t in _read_folder(out / kind)
            if first_row(t)["run_id"] in done
        ]
        return pd.concat(frames, ignore_index=True) if frames else pd.DataFrame()
    tables = _read_folder(out / "runs", one_row=True)
    if failed:
        tables += [
            t
            for t in _read_folder(out / "failed", one_row=True)
            if first_row(t)["run_id"] not in done
        ]
    rows = [first_row(t) for t in tables]
    _refuse_foreign(out, rows, PlanIndex(read_manifest(out)))
    if not tables:
        return pd.DataFrame(columns=["run_id", "seed", "status"])
    frame = pd.concat(_frames_by_shape(tables, rows), ignore_index=True)
    return frame.sort_values(["status", "run_id"], ignore_index=True)


def _frames_by_shape(tables: list[pa.Table], rows: list[dict]) -> list[pd.DataFrame]:
    """The runs' one-row tables as frames that ``pd.concat`` joins into the frame it makes of
    one frame per run without its empty columns (``frame.dropna(axis=1, how="all")``, so that
    rows of other shapes concatenate as they always did): the rows of one shape (the same
    columns and types) are joined in Arrow and converted to pandas once, not once a run (a
    few milliseconds each). Files written through pandas carry its metadata, which may shape
    the conversion: they are converted one by one, as before. ``rows`` holds each table's
    one row as plain values (:func:`first_row`).
    """
    shapes: dict[tuple, list[pa.Table]] = {}
    for table, first in zip(tables, rows, strict=True):
        table = _without_empty_columns(table, first)
        key = (table.schema, tuple(sorted((table.schema.metadata or {}).items())))
        shapes.setdefault(key, []).append(table)
    frames = []
    for (_schema, metadata), shape in shapes.items():
        if metadata:
            frames += [t.to_pandas(use_threads=False) for t in shape]
        else:
            frames.append(pa.concat_tables(shape).to_pandas(use_threads=False))
    return frames


def _without_empty_columns(table: pa.Table, row: dict) -> pa.Table:
    """The one-row ``table`` without the columns that hold no value in its ``row`` (read off
    the plain values: a compute call per column cost more than the rest of the join).
    """
    empty = [name for name, value in row.items() if _missing(value)]
    return table.drop_columns(empty) if empty else table


def _missing(value: object) -> bool:
    """None or NaN: what pandas' ``notna`` calls missing, of a plain value."""
    return value is None or (isinstance(value, float) and math.isnan(value))


def _refuse_foreign(out: Path, rows: list[dict], index: PlanIndex) -> None:
    """Raise SweepError naming the run files that are not runs of the folder's plan."""
    foreign = []
    for row in rows:
        try:
            index.match(row, str(row["run_id"]))
        except CorruptResultError as exc:
            folder = "runs" if row.get("status") == "ok" else "failed"
            foreign.append(f"{folder}/{row['run_id']}.parquet ({exc.reason}: {exc})")
    if foreign:
        shown = "; ".join(foreign[:3]) + ("; ..." if len(foreign) > 3 else "")
        raise SweepError(
            f"{out} holds {len(foreign)} run file(s) that are not runs of its sweep: {shown}; "
            f"run its sweep again with --out {out} (it sets them aside) or move them out"
        )


def prepare_out(out: Path, sweep: Sweep) -> list[SetAside]:
    """Create the folders and write (or merge into) ``sweep.json``; returns the damaged
    ``sweep.json`` set aside, if there was one.

    Raises:
        SweepError: the folder holds a sweep of another model or seed.

    """
    manifest = sweep.manifest()
    path = out / "sweep.json"
    old, moved = _read_manifest(out, path)
    if old is not None:
        for key in ("target", "seed"):
            if old.get(key) != manifest[key]:
                raise SweepError(
                    f"{out} holds a sweep with {key} {old.get(key)!r}, this one has "
                    f"{manifest[key]!r}: choose another output folder"
                )
        if not _design_kept(old, manifest):
            raise SweepError(
                f"{out} holds a sweep with another design (or a sample SALib drew otherwise): "
                "a design's sample is its plan, and it may only grow (a larger n whose sample "
                "starts with the folder's, as a Sobol' sample does); choose another output folder"
            )
        if "units" in old and old["units"] != manifest.get("units"):
            changed = sorted(
                k
                for k in {*old["units"], *manifest.get("units", {})}
                if old["units"].get(k) != manifest.get("units", {}).get(k)
            )
            raise SweepError(
                f"{out} holds runs whose summary units differ from today's code's "
                f"({', '.join(changed)}): choose another output folder"
            )
        if _keys(old) != _keys(manifest):
            raise SweepError(
                f"{out} holds a sweep over {', '.join(sorted(_keys(old))) or 'no keys'}, this one "
                f"sets {', '.join(sorted(_keys(manifest)))}: choose another output folder"
            )
        grid = {
            k: list(dict.fromkeys(old["grid"].get(k, []) + v)) for k, v in manifest["grid"].items()
        }
        manifest["grid"] = grid
        if "design" not in manifest:  # a design's points are its sample, checked above
            points = old.get("points", [])
            manifest["points"] = points + [p for p in manifest["points"] if p not in points]
        manifest["replications"] = max(old.get("replications", 1), manifest["replications"])
        manifest["created"] = old.get("created")
    manifest.setdefault("created", datetime.datetime.now().isoformat(timespec="seconds"))
    manifest["updated"] = datetime.datetime.now().isoformat(timespec="seconds")
    tmp = path.with_name(".sweep.json.tmp")
    tmp.write_text(json.dumps(manifest, indent=2, default=str))
    os.replace(tmp, path)
    for sub in RESULT_FOLDERS:
        (out / sub).mkdir(exist_ok=True)
    return moved


def _design_kept(old: dict, new: dict) -> bool:
    """Whether ``new`` keeps the folder's design: neither has one (a grid), or ``new``'s is
    ``old``'s with the same or a larger ``n`` and a sample that begins with ``old``'s, row for
    row. So every finished run stays a run of the plan, and a grown design's first rows are
    the smaller design's (a Sobol' sample's leading base points are the smaller sample; at the
    same ``n`` the samples are the same length, so they must be equal). Latin hypercubes and
    Morris trajectories drawn anew at a larger ``n`` do not begin with the smaller sample.
    """
    before, after = _plain_json(old.get("design")), _plain_json(new.get("design"))
    if before is None and after is None:
        return True
    if not (isinstance(before, dict) and isinstance(after, dict)):
        return False
    if {**before, "n": 0} != {**after, "n": 0} or after["n"] < before["n"]:
        return False
    rows = _plain_json(old.get("points", []))
    return _plain_json(new["points"][: len(rows)]) == rows


def _check_manifest(manifest: object) -> dict:
    """``manifest`` if it has the shape :meth:`Sweep.manifest` writes, else ValueError."""
    if not isinstance(manifest, dict):
        raise ValueError("not a table of a sweep's keys")
    grid, points = manifest.get("grid", {}), manifest.get("points", [])
    if not isinstance(grid, dict) or not all(isinstance(v, list) for v in grid.values()):
        raise ValueError("grid is not a table of lists")
    if not isinstance(points, list) or not all(isinstance(p, dict) for p in points):
        raise ValueError("points is not a list of tables")
    for key in ("seed", "replications"):
        value = manifest.get(key, 1)
        if isinstance(value, bool) or not isinstance(value, int) or value < 0:
            raise ValueError(f"{key} is not a whole number")
    return manifest


def _keys(manifest: dict) -> set[str]:
    """The parameters a sweep sets: its grid's keys and its points' keys."""
    return set(manifest.get("grid", {})) | {k for p in manifest.get("points", []) for k in p}


def read_manifest(out: str | Path) -> dict:
    """The ``sweep.json`` of the sweep folder ``out``.

    Raises:
        SweepError: no ``sweep.json``, or one that is not a sweep's (one line, naming it).

    """
    path = Path(out) / "sweep.json"
    if not path.is_file():
        raise SweepError(f"{out} is not a sweep folder (no sweep.json); run `abm sweep` first")
    try:
        manifest = _check_manifest(json.loads(path.read_bytes().decode("utf-8")))
    except (ValueError, TypeError, UnicodeDecodeError) as exc:
        raise SweepError(
            f"{path} is damaged ({type(exc).__name__}: {exc}); run the sweep again: it sets "
            "the file aside and writes it anew"
        ) from exc
    target = manifest.get("target")
    if isinstance(target, str):
        try:
            check_target(target)  # a report imports it: never a module that is not a model's
        except ConfigError as exc:
            raise SweepError(f"{path}: {exc}") from exc
    return manifest


def _read_manifest(out: Path, path: Path) -> tuple[dict | None, list[SetAside]]:
    """The ``sweep.json`` already in ``out`` (None if there is none, or it was damaged: then it
    is set aside and a new one is written; every run file is still checked against the plan).
    """
    if not path.is_file():
        return None, []
    try:
        old = _check_manifest(json.loads(path.read_bytes().decode("utf-8")))
    except (ValueError, TypeError, UnicodeDecodeError) as exc:
        return None, [set_aside(out, path, "unreadable", f"{type(exc).__name__}: {exc}")]
    return old, []


def swept_keys(manifest: dict, runs: pd.DataFrame) -> list[str]:
    """The parameters of a sweep's ``grid`` and ``points`` that take more than one value in
    ``runs``, in the file's order. A run where a points-only key is unset counts as a value of
    its own; values are compared as text, so a list-valued parameter is fine too.
    """
    keys = [*manifest.get("grid", {}), *(k for p in manifest.get("points", []) for k in p)]
    return [k for k in dict.fromkeys(keys) if k in runs and _as_text(runs[k]).nunique() > 1]


def _as_text(column: pd.Series) -> pd.Series:
    """Each value as text, a missing one as "None"/"nan" (``astype(str)`` keeps NA missing)."""
    return column.astype(object).map(str)


def _plain_json(value: object) -> object:
    """``value`` as JSON reads it back (tuples as lists), to compare a manifest with a plan."""
    return json.loads(json.dumps(value, default=str))
