"""Save a finished run to a folder, and load it back, so it can be drawn without re-running.

A run folder holds:

- ``events.parquet``: the event log (attach rows carry the beacon's x, y in m);
- ``positions.parquet``: robot positions sampled every trace interval (time, robot, x, y, state);
- ``state_counts.parquet``: robots per state after every change;
- ``summary.parquet``: the model's one-row summary;
- ``arena.npz``: the arena's free grid, its resolution (m) and the final coverage raster;
- ``run.json``: the model class, its states, the constructor parameters, comm range (m),
  coverage radius and pixel (m) and the end time (s).
"""

import inspect
import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from abm.arena import Arena
from abm.errors import ABMError

__all__ = ["RUN_FILES", "RunFolderError", "SavedRun", "load_run", "save_run"]

#: Files a complete run folder holds.
RUN_FILES = (
    "events.parquet",
    "positions.parquet",
    "state_counts.parquet",
    "summary.parquet",
    "arena.npz",
    "run.json",
)


class RunFolderError(ABMError):
    """A run folder is missing or incomplete."""


@dataclass
class SavedRun:
    """A run loaded from its folder.

    Attributes:
        folder: where it was loaded from.
        arena: the world (walls).
        events: event log.
        positions: sampled positions (time, robot, x, y, state).
        state_counts: robots per state after every change.
        summary: the model's summary.
        meta: the contents of run.json.
        covered_final: the coverage raster at the end of the run, if the model kept one.

    """

    folder: Path
    arena: Arena
    events: pd.DataFrame
    positions: pd.DataFrame
    state_counts: pd.DataFrame
    summary: dict
    meta: dict
    covered_final: np.ndarray | None

    @property
    def states(self) -> tuple[str, ...]:
        """The model's robot states."""
        return tuple(self.meta["states"])

    @property
    def end_time(self) -> float:
        """Simulated time at the end of the run (s)."""
        return float(self.meta["end_time"])


def _plain(value):
    """``value`` if it is JSON-friendly (number, string, bool, None), else None."""
    if isinstance(value, np.generic):
        value = value.item()
    if value is None or isinstance(value, bool | int | float | str):
        return value
    return None


def _parameters(model, summary: dict) -> dict:
    """The constructor parameters of ``model`` that have a plain value."""
    params = {}
    for name in inspect.signature(type(model).__init__).parameters:
        if name == "self":
            continue
        value = _plain(getattr(model, name, None))
        if value is None and name in summary:
            value = _plain(summary[name])
        if value is not None or hasattr(model, name):
            params[name] = value
    return params


def save_run(model, out_dir: str | Path) -> list[Path]:
    """Write everything ``abm render`` needs about a finished SwarmModel run; return the paths.

    Args:
        model: a SwarmModel after ``run()`` (must implement ``summary()``).
        out_dir: the run folder (created if missing).

    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    summary = model.summary()
    written = []

    def parquet(frame: pd.DataFrame, name: str) -> None:
        path = out / name
        frame.to_parquet(path)
        written.append(path)

    parquet(model.events(), "events.parquet")
    parquet(model.positions(), "positions.parquet")
    parquet(model.state_counts(), "state_counts.parquet")
    parquet(pd.DataFrame([summary]), "summary.parquet")
    coverage = getattr(model, "coverage", None)
    arrays = {
        "free": model.arena.free,
        "resolution": np.float64(model.arena.resolution),
        "name": np.str_(model.arena.name),
    }
    if coverage is not None:
        arrays["covered"] = coverage.covered
    arena_path = out / "arena.npz"
    np.savez_compressed(arena_path, **arrays)
    written.append(arena_path)
    meta = {
        "model": f"{type(model).__module__}:{type(model).__name__}",
        "states": list(model.STATES),
        "parameters": _parameters(model, summary),
        "comm_range": float(model.comms.comm_range),
        "coverage_radius": None if coverage is None else float(coverage.radius),
        "coverage_pixel": None if coverage is None else float(coverage.pixel),
        "coverage_line_of_sight": None if coverage is None else bool(coverage.line_of_sight),
        "end_time": float(model.time),
        "end_reason": model.end_reason,
    }
    json_path = out / "run.json"
    json_path.write_text(json.dumps(meta, indent=2) + "\n")
    written.append(json_path)
    return written


def load_run(out_dir: str | Path) -> SavedRun:
    """Load a run folder written by :func:`save_run`.

    Raises:
        RunFolderError: the folder does not exist or lacks one of :data:`RUN_FILES`.

    """
    folder = Path(out_dir)
    if not folder.is_dir():
        raise RunFolderError(
            f"run folder {str(folder)!r} does not exist; make one with `abm run --out {folder}`"
        )
    missing = [name for name in RUN_FILES if not (folder / name).is_file()]
    if missing:
        raise RunFolderError(
            f"run folder {str(folder)!r} lacks {', '.join(missing)}; "
            f"re-run it with `abm run --out {folder}` (which saves them)"
        )
    meta = json.loads((folder / "run.json").read_text())
    with np.load(folder / "arena.npz", allow_pickle=False) as data:
        arena = Arena(data["free"].astype(bool), float(data["resolution"]), name=str(data["name"]))
        covered = data["covered"].astype(bool) if "covered" in data.files else None
    summary = pd.read_parquet(folder / "summary.parquet").iloc[0].to_dict()
    return SavedRun(
        folder=folder,
        arena=arena,
        events=pd.read_parquet(folder / "events.parquet"),
        positions=pd.read_parquet(folder / "positions.parquet"),
        state_counts=pd.read_parquet(folder / "state_counts.parquet"),
        summary=summary,
        meta=meta,
        covered_final=covered,
    )
