"""Save a finished run to a folder, and load it back, so it can be drawn without re-running.

A run folder holds:

- ``events.parquet``: the event log;
- ``positions.parquet``: robot positions sampled every trace interval (time, robot, x, y, state,
  comm: whether the robot was a node of the comm network);
- ``state_counts.parquet``: robots per state after every change;
- ``summary.parquet``: the model's one-row summary;
- ``arena.npz``: the arena's free grid, its resolution (m) and, for a model that covers, the
  time (s) each coverage pixel was first covered (inf: never), which gives the covered area at
  any time;
- ``run.json``: the model (name and class), its states and their styles, its parameters and
  seed, the comm range (m), the coverage raster's settings and the end time (s).

Everything a picture needs is in the folder: drawing a run imports no model code.
"""

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from abm.arena import Arena
from abm.errors import ABMError
from abm.styles import StateStyle

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
        positions: sampled positions (time, robot, x, y, state, comm).
        state_counts: robots per state after every change.
        summary: the model's summary.
        meta: the contents of run.json.
        first_covered: per coverage pixel, when it was first covered (s; inf: never), or None
            for a model that does not cover.

    """

    folder: Path
    arena: Arena
    events: pd.DataFrame
    positions: pd.DataFrame
    state_counts: pd.DataFrame
    summary: dict
    meta: dict
    first_covered: np.ndarray | None

    @property
    def states(self) -> tuple[str, ...]:
        """The model's robot states."""
        return tuple(self.meta["states"])

    @property
    def styles(self) -> dict[str, StateStyle]:
        """Each state's style, as the model declared it."""
        return {state: StateStyle(**style) for state, style in self.meta["styles"].items()}

    @property
    def end_time(self) -> float:
        """Simulated time at the end of the run (s)."""
        return float(self.meta["end_time"])

    @property
    def coverage_pixel(self) -> float | None:
        """Side of a coverage pixel (m), or None without coverage."""
        coverage = self.meta.get("coverage")
        return None if coverage is None else float(coverage["pixel"])


def save_run(model, out_dir: str | Path) -> list[Path]:
    """Write everything ``abm render`` needs about a finished SwarmModel run; return the paths.

    Args:
        model: a SwarmModel after ``run()``.
        out_dir: the run folder (created if missing).

    """
    from abm.registry import name_of

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
    coverage = model.coverage
    arrays = {
        "free": model.arena.free,
        "resolution": np.float64(model.arena.resolution),
        "name": np.str_(model.arena.name),
    }
    if coverage is not None:
        arrays["first_covered"] = coverage.first_covered
    arena_path = out / "arena.npz"
    np.savez_compressed(arena_path, **arrays)
    written.append(arena_path)
    cls = type(model)
    meta = {
        "model": name_of(cls) or f"{cls.__module__}:{cls.__qualname__}",
        "target": f"{cls.__module__}:{cls.__qualname__}",
        "seed": model.seed,
        "states": list(model.STATES),
        "styles": {state: style.as_dict() for state, style in model.state_styles.items()},
        "parameters": model.params.plain(),
        "comm_range": float(model.comms.comm_range),
        "coverage": None
        if coverage is None
        else {
            "radius": coverage.radius,
            "pixel": coverage.pixel,
            "line_of_sight": coverage.line_of_sight,
            "around": coverage.around,
        },
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
            f"run folder {str(folder)!r} does not exist; make one with "
            f"`abm run MODEL --out {folder}`"
        )
    missing = [name for name in RUN_FILES if not (folder / name).is_file()]
    if missing:
        raise RunFolderError(
            f"run folder {str(folder)!r} lacks {', '.join(missing)}; "
            f"re-run it with `abm run MODEL --out {folder}` (which saves them)"
        )
    meta = json.loads((folder / "run.json").read_text())
    if "styles" not in meta:
        raise RunFolderError(
            f"run folder {str(folder)!r} was saved by an older version (no state styles); "
            f"re-run it with `abm run MODEL --out {folder}`"
        )
    with np.load(folder / "arena.npz", allow_pickle=False) as data:
        arena = Arena(data["free"].astype(bool), float(data["resolution"]), name=str(data["name"]))
        first = data["first_covered"] if "first_covered" in data.files else None
    summary = pd.read_parquet(folder / "summary.parquet").iloc[0].to_dict()
    return SavedRun(
        folder=folder,
        arena=arena,
        events=pd.read_parquet(folder / "events.parquet"),
        positions=pd.read_parquet(folder / "positions.parquet"),
        state_counts=pd.read_parquet(folder / "state_counts.parquet"),
        summary=summary,
        meta=meta,
        first_covered=first,
    )
