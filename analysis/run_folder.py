"""Save a finished run to a folder, and load it back, so it can be drawn without re-running.

A run folder holds:

- ``events.parquet``: the event log;
- ``positions.parquet``: robot positions sampled every trace interval (time, robot, x, y, state,
  comm: whether the robot was a node of the comm network);
- ``state_counts.parquet``: robots per state after every change;
- ``summary.parquet``: the model's one-row summary;
- ``arena.npz``: the arena's free grid, its resolution (m) and, for a model that covers, the
  time (s) each coverage pixel was first covered (inf: never), which gives the covered area at
  any time; the points and rasters of the model's layers (:meth:`abm.model.SwarmModel.layers`,
  e.g. the base beacon's star) at the end of the run;
- ``run.json``: the model (name and class), its states and their styles, its parameters and
  seed, the comm range (m), the coverage raster's settings, the end time (s) and how each layer
  is drawn (label, colour, marker, size, drawing order, extent, whether it is still).

Everything a picture needs is in the folder: drawing a run imports no model code.
"""

import json
import os
import secrets
import shutil
import zipfile
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from abm.arena import Arena
from abm.checks import layers_of
from abm.errors import ABMError, HookError, OutputError
from abm.styles import Layer, StateStyle

__all__ = [
    "RUN_FILES",
    "RunFolderError",
    "SavedRun",
    "check_run_target",
    "load_run",
    "runs_in",
    "save_run",
]

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
        layers: the model's layers at the end of the run (none for a folder saved before
            layers were kept).

    """

    folder: Path
    arena: Arena
    events: pd.DataFrame
    positions: pd.DataFrame
    state_counts: pd.DataFrame
    summary: dict
    meta: dict
    first_covered: np.ndarray | None
    layers: list[Layer] = field(default_factory=list)

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

    The files are written into a temporary folder beside ``out_dir`` and moved into place only
    once all of them are written (``run.json`` last), so a failure while saving (a full disk,
    a read-only folder) never leaves a half-written run folder, nor half of a previous run
    replaced. The temporary folder is removed on failure, giving back the space it took.

    Args:
        model: a SwarmModel after ``run()``.
        out_dir: the run folder (created if missing; run files already in it are replaced,
            other files are left alone).

    Raises:
        OutputError: a file could not be written; the message names it (the model, still in
            memory, can be saved again elsewhere).
        HookError: the model's ``metrics()`` or ``layers()`` returned what no run file can
            hold (:mod:`abm.checks`); nothing is left behind.

    """
    out = Path(out_dir)
    check_run_target(out)
    # a name of its own beside the run folder (same file system: the move is a rename), made
    # as any folder is, so the run folder gets the usual permissions
    staging = out.parent / f".{out.name}.partial-{os.getpid()}-{secrets.token_hex(4)}"
    try:
        staging.mkdir(parents=True)
        _write_run(model, staging)
        if out.is_dir():
            for name in RUN_FILES:  # run.json last: a run folder is complete once it has one
                os.replace(staging / name, out / name)
            staging.rmdir()
        else:
            staging.rename(out)
    except HookError:  # a model's hook returned what no file can hold (abm.checks)
        shutil.rmtree(staging, ignore_errors=True)
        raise
    except OSError as exc:
        shutil.rmtree(staging, ignore_errors=True)
        where = exc.filename
        if where is not None and staging in (Path(where), Path(where).parent):
            where = (
                out / Path(where).name if Path(where) != staging else out
            )  # as the user knows it
        raise OutputError(exc.errno, exc.strerror or str(exc), str(where or out)) from exc
    return [out / name for name in RUN_FILES]


def check_run_target(out: Path) -> None:
    """Raise OutputError unless ``out`` can become a run folder: a missing path under
    folders (or under nothing), or a folder; never a file or a path through a file.
    """
    if out.exists() and not out.is_dir():
        raise OutputError(
            f"{str(out)!r} is a file, not a folder; give --out a folder (new or a run folder)"
        )
    for parent in out.parents:
        if parent.exists():
            if not parent.is_dir():
                raise OutputError(f"cannot make the folder {str(out)!r}: {str(parent)!r} is a file")
            break


def _write_run(model, folder: Path) -> None:
    """Write the run files of ``model`` into the existing, empty ``folder``."""
    from abm.registry import name_of

    summary = model.summary()
    layers = layers_of(model)  # the model's hooks are checked before any file is written

    def parquet(frame: pd.DataFrame, name: str) -> None:
        with _opened(folder / name, "wb") as file:
            frame.to_parquet(file)

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
    for i, layer in enumerate(layers):
        for part in ("points", "raster"):
            if getattr(layer, part) is not None:
                arrays[f"layer{i}_{part}"] = np.asarray(getattr(layer, part), dtype=float)
    with _opened(folder / "arena.npz", "wb") as file:
        np.savez_compressed(file, **arrays)
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
        "layers": [_layer_meta(layer) for layer in layers],
    }
    with _opened(folder / "run.json", "w") as file:
        file.write(json.dumps(meta, indent=2) + "\n")


def _layer_meta(layer: Layer) -> dict:
    """How ``layer`` is drawn, as plain data (its points and raster go to arena.npz)."""
    return {
        "label": layer.label,
        "colour": layer.colour,
        "size": float(layer.size),
        "marker": layer.marker,
        "layer": float(layer.layer),
        "extent": None if layer.extent is None else [float(v) for v in layer.extent],
        "still": bool(layer.still),
    }


def _layer(spec: dict, i: int, data) -> Layer:
    """Layer ``i`` of a saved run: its spec from run.json, its arrays from arena.npz."""
    arrays = {
        part: data[f"layer{i}_{part}"] if f"layer{i}_{part}" in data.files else None
        for part in ("points", "raster")
    }
    extent = spec["extent"]
    return Layer(
        str(spec["label"]),
        colour=str(spec["colour"]),
        size=float(spec["size"]),
        marker=str(spec["marker"]),
        layer=float(spec["layer"]),
        extent=None if extent is None else tuple(float(v) for v in extent),
        still=bool(spec["still"]),
        **arrays,
    )


@contextmanager
def _opened(path: Path, mode: str) -> Iterator:
    """``open(path, mode)``, with any OSError raised while it is open naming ``path``.

    Writers given an open file (pyarrow, numpy) raise an OSError without a file name, and a
    path given to pyarrow as text must be valid UTF-8: opening it here takes any name the
    file system does.
    """
    try:
        with open(path, mode, **({} if "b" in mode else {"encoding": "utf-8"})) as file:
            yield file
    except OSError as exc:
        if exc.filename is None:
            raise OSError(exc.errno, exc.strerror or str(exc), str(path)) from exc
        raise


def load_run(out_dir: str | Path) -> SavedRun:
    """Load a run folder written by :func:`save_run`.

    Raises:
        RunFolderError: the path does not exist, is a file, is a folder of runs or any other
            folder than a run folder, lacks one of :data:`RUN_FILES` or holds a damaged one;
            the message says which, and what is accepted.

    """
    folder = Path(out_dir)
    _check_run_folder(folder)
    try:
        meta = json.loads((folder / "run.json").read_text(encoding="utf-8"))
        if not isinstance(meta, dict):
            raise ValueError("run.json holds no JSON object")
        if "styles" not in meta:
            raise RunFolderError(
                f"run folder {str(folder)!r} was saved by an older version (no state styles); "
                f"re-run it with `abm run MODEL --out {folder}`"
            )
        with _opened(folder / "arena.npz", "rb") as file, np.load(file, allow_pickle=False) as data:
            arena = Arena(
                data["free"].astype(bool), float(data["resolution"]), name=str(data["name"])
            )
            first = data["first_covered"] if "first_covered" in data.files else None
            specs = meta.get("layers", [])
            if not isinstance(specs, list) or not all(isinstance(x, dict) for x in specs):
                raise ValueError("run.json's layers are not a list of objects")
            layers = [_layer(spec, i, data) for i, spec in enumerate(specs)]
        summary = _parquet(folder / "summary.parquet").iloc[0].to_dict()
        return SavedRun(
            folder=folder,
            arena=arena,
            events=_parquet(folder / "events.parquet"),
            positions=_parquet(folder / "positions.parquet"),
            state_counts=_parquet(folder / "state_counts.parquet"),
            summary=summary,
            meta=meta,
            first_covered=first,
            layers=layers,
        )
    except (ValueError, KeyError, IndexError, EOFError, zipfile.BadZipFile) as exc:  # cut short
        raise RunFolderError(
            f"run folder {str(folder)!r} is damaged ({type(exc).__name__}: "
            f"{str(exc).splitlines()[0] if str(exc) else 'unreadable'}); "
            f"re-run it with `abm run MODEL --out {folder}`"
        ) from exc


def _parquet(path: Path) -> pd.DataFrame:
    """A Parquet file read through Python's ``open`` (any name the file system takes)."""
    with _opened(path, "rb") as file:
        return pd.read_parquet(file)


def runs_in(folder: str | Path) -> list[Path]:
    """The run folders directly inside ``folder`` (such as ``out/runs``), oldest first."""
    root = Path(folder)
    if not root.is_dir():
        return []
    runs = [p for p in root.iterdir() if p.is_dir() and (p / "run.json").is_file()]
    return sorted(runs, key=lambda p: ((p / "run.json").stat().st_mtime, p.name))


def _check_run_folder(folder: Path) -> None:
    """Raise RunFolderError, saying what ``folder`` is instead, unless it is a run folder."""
    accepted = "a run folder written by `abm run` (holding run.json, events.parquet, ...)"
    if not folder.exists():
        raise RunFolderError(
            f"run folder {str(folder)!r} does not exist; make one with "
            f"`abm run MODEL --out {folder}`"
        )
    if not folder.is_dir():
        raise RunFolderError(f"{str(folder)!r} is a file, not a run folder; give {accepted}")
    if not any((folder / name).is_file() for name in RUN_FILES):
        inside = runs_in(folder)
        if inside:
            raise RunFolderError(
                f"{str(folder)!r} holds {len(inside)} run folder(s), not one run; name one, "
                f"e.g. the newest: {inside[-1]}"
            )
        raise RunFolderError(f"{str(folder)!r} is not a run folder (no run.json); give {accepted}")
    missing = [name for name in RUN_FILES if not (folder / name).is_file()]
    if missing:
        raise RunFolderError(
            f"run folder {str(folder)!r} lacks {', '.join(missing)}; "
            f"re-run it with `abm run MODEL --out {folder}` (which saves them)"
        )
