"""Parameter sweeps: a model, a parameter grid and replications, run on any executor.

A sweep is the Cartesian product of its ``grid`` times ``replications``. Each run is the pure,
picklable function :func:`run_one` (model + parameters + seed -> tidy rows), handed to one of

* ``"serial"``: in this process, one run after the other;
* ``"processes"``: a local :class:`~concurrent.futures.ProcessPoolExecutor` (default: all cores);
* ``"dask"``: Dask distributed, on the scheduler at ``address`` or on a fresh ``LocalCluster``
  (pass a ``dask.distributed.Client`` as ``executor`` to use e.g. a dask-jobqueue SLURM cluster,
  see ``docs/cluster.md``);
* any ready :class:`concurrent.futures.Executor`.

Results live in one folder per sweep (the dataset)::

    out/sweeps/corridor/
        sweep.json                 what was asked (model, grid, replications, seed)
        runs/<run_id>.parquet      one row per finished run (written at once, atomic rename)
        failed/<run_id>.parquet    one row per run that raised: error and traceback
        series/<run_id>.parquet    the run's state counts over time (when ``time_series``)

The ``run_id`` is a hash of the run's parameters and replication index, so a restarted sweep
recognises (and skips) runs already on disk, and retries failed ones. The per-run seed is drawn
from ``numpy.random.SeedSequence(seed)`` with the spawn key ``(condition key, replication)``:
independent streams, the same for a run whatever executor runs it, unchanged when the grid
grows. It is recorded in the ``seed`` column (the integer the model got) and in ``spawn_key``.
"""

from __future__ import annotations

import concurrent.futures as cf
import datetime
import hashlib
import importlib
import inspect
import itertools
import json
import os
import signal
import socket
import sys
import time
import tomllib
import traceback
import types
import typing
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from abm.errors import ABMError, ConfigError
from analysis.pools import process_pool

__all__ = [
    "MODELS",
    "EXECUTORS",
    "Sweep",
    "RunSpec",
    "SweepError",
    "register_model",
    "resolve_model",
    "load_sweep",
    "plan",
    "run_one",
    "run_sweep",
    "execute",
    "load_results",
]

#: Model names usable in sweep files, mapped lazily to ``"module:Class"``.
MODELS: dict[str, str] = {"beacon-explorer": "models.beacon_explorer:BeaconExplorerModel"}

#: Executor names accepted by :func:`run_sweep`.
EXECUTORS = ("serial", "processes", "dask")

_TOML_KEYS = ("name", "description", "model", "seed", "replications", "time_series", "grid")
_RESERVED = ("seed", "rng")


class SweepError(ABMError):
    """A sweep cannot go on (its output folder belongs to another sweep, the executor broke)."""


def register_model(name: str, target: str) -> None:
    """Make ``name`` usable in sweep files; ``target`` is ``"package.module:ClassName"``."""
    if ":" not in target:
        raise ConfigError(f"model target must look like 'package.module:Class', got {target!r}")
    MODELS[name] = target


def resolve_model(model: str | type) -> type:
    """The model class for a registered name, a ``"module:Class"`` string, or a class."""
    if isinstance(model, type):
        return model
    if not isinstance(model, str):
        raise ConfigError(f"model must be a model class or a name, got {model!r}")
    target = MODELS.get(model, model)
    if ":" not in target:
        names = ", ".join(repr(n) for n in MODELS)
        raise ConfigError(f"model must be one of {names} or 'module:Class', got {model!r}")
    module, _, name = target.partition(":")
    try:
        return getattr(importlib.import_module(module), name)
    except (ImportError, AttributeError) as exc:
        raise ConfigError(f"model {model!r}: cannot import {target!r} ({exc})") from exc


def _target(model_cls: type) -> str:
    return f"{model_cls.__module__}:{model_cls.__qualname__}"


# ---------------------------------------------------------------------------------- the sweep
@dataclass(frozen=True)
class Sweep:
    """What to run: a model, a parameter grid, replications and the sweep seed.

    Attributes:
        model: a registered model name (see :data:`MODELS`), ``"module:Class"`` or a class.
        grid: constructor keyword -> list of values (a scalar means one value).
        replications: runs per grid point.
        seed: the sweep seed; per-run seeds are spawned from it.
        name: the sweep's name (default output folder ``out/sweeps/<name>``).
        time_series: also keep each run's state counts over time.
        description: free text, shown in reports.

    """

    model: str | type
    grid: Mapping[str, Sequence]
    replications: int = 1
    seed: int = 0
    name: str = "sweep"
    time_series: bool = False
    description: str = ""
    model_cls: type = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        cls = resolve_model(self.model)
        object.__setattr__(self, "model_cls", cls)
        _check_int("replications", self.replications, 1)
        _check_int("seed", self.seed, 0)
        if not isinstance(self.time_series, bool):
            raise ConfigError(f"time_series must be true or false, got {self.time_series!r}")
        object.__setattr__(self, "grid", _check_grid(cls, self.grid))

    @property
    def n_runs(self) -> int:
        """Grid points times replications."""
        return int(np.prod([len(v) for v in self.grid.values()])) * self.replications

    def conditions(self) -> list[dict]:
        """Every grid point as a dict of constructor keywords, in grid order."""
        keys = list(self.grid)
        return [
            dict(zip(keys, vals, strict=True)) for vals in itertools.product(*self.grid.values())
        ]

    def manifest(self) -> dict:
        """A JSON-able description (written as ``sweep.json`` beside the runs)."""
        return {
            "name": self.name,
            "description": self.description,
            "model": self.model if isinstance(self.model, str) else _target(self.model_cls),
            "target": _target(self.model_cls),
            "seed": self.seed,
            "replications": self.replications,
            "time_series": self.time_series,
            "grid": {k: list(v) for k, v in self.grid.items()},
        }


def _check_int(name: str, value, low: int) -> None:
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < low:
        raise ConfigError(f"{name} must be an integer >= {low}, got {value!r}")


def _check_grid(model_cls: type, grid: Mapping) -> dict[str, tuple]:
    """Validate keys against the constructor's signature and values against its annotations."""
    if not isinstance(grid, Mapping) or not grid:
        raise ConfigError("grid is empty: give at least one parameter and its values")
    signature = inspect.signature(model_cls.__init__)
    try:
        hints = typing.get_type_hints(model_cls.__init__)
    except Exception:  # unresolvable annotations: fall back to the defaults' types
        hints = {}
    accepted = [n for n in signature.parameters if n != "self" and n not in _RESERVED]
    checked = {}
    for key, values in grid.items():
        if key in _RESERVED:
            raise ConfigError(
                f"grid key {key!r} is not allowed: per-run seeds are spawned from the sweep seed"
            )
        if key not in signature.parameters or key == "self":
            raise ConfigError(
                f"grid key {key!r} is not a parameter of {model_cls.__name__}; "
                f"accepted: {', '.join(accepted)}"
            )
        if isinstance(values, str) or not isinstance(values, Sequence):
            values = [values]
        if len(values) == 0:
            raise ConfigError(f"grid key {key!r} has an empty list of values")
        default = signature.parameters[key].default
        expected = hints.get(key, type(default) if default is not inspect.Parameter.empty else None)
        clean = []
        for value in values:
            if expected is not None and not _accepts(value, expected):
                raise ConfigError(
                    f"grid key {key!r}: value {value!r} ({type(value).__name__}) does not match "
                    f"the parameter's type {_type_name(expected)}"
                )
            clean.append(float(value) if _is_float_param(expected) and value is not None else value)
        if len(set(map(repr, clean))) != len(clean):
            raise ConfigError(f"grid key {key!r} repeats a value: {list(values)!r}")
        checked[key] = tuple(clean)
    return checked


def _accepts(value, annotation) -> bool:
    if annotation is typing.Any or annotation is inspect.Parameter.empty:
        return True
    if annotation is type(None) or annotation is None:
        return value is None
    origin = typing.get_origin(annotation)
    if origin is typing.Union or origin is types.UnionType:
        return any(_accepts(value, arg) for arg in typing.get_args(annotation))
    if origin is not None:
        return isinstance(value, origin) or (origin is tuple and isinstance(value, list))
    if annotation is float:
        return isinstance(value, int | float | np.number) and not isinstance(value, bool)
    if annotation is int:
        return isinstance(value, int | np.integer) and not isinstance(value, bool)
    if isinstance(annotation, type):
        return isinstance(value, annotation)
    return True


def _is_float_param(annotation) -> bool:
    if annotation is float:
        return True
    origin = typing.get_origin(annotation)
    if origin is typing.Union or origin is types.UnionType:
        args = [a for a in typing.get_args(annotation) if a is not type(None)]
        return args == [float]
    return False


def _type_name(annotation) -> str:
    return getattr(annotation, "__name__", None) or str(annotation)


def load_sweep(path: str | Path, replications: int | None = None) -> Sweep:
    """Read and validate a sweep file (TOML); ``replications`` overrides the file's value.

    The file holds ``model``, ``seed``, ``replications``, optional ``name``, ``description`` and
    ``time_series``, and a ``[grid]`` table of constructor keyword -> list of values.
    """
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"no sweep file {str(path)!r}")
    try:
        data = tomllib.loads(path.read_text())
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"{path}: not valid TOML ({exc})") from exc
    unknown = [k for k in data if k not in _TOML_KEYS]
    if unknown:
        raise ConfigError(
            f"{path}: unknown key {unknown[0]!r}; accepted keys: {', '.join(_TOML_KEYS)}"
        )
    for key in ("model", "grid"):
        if key not in data:
            raise ConfigError(f"{path}: missing key {key!r}")
    if not isinstance(data["grid"], dict):
        raise ConfigError(f"{path}: 'grid' must be a table ([grid]), got {data['grid']!r}")
    try:
        return Sweep(
            model=data["model"],
            grid=data["grid"],
            replications=data.get("replications", 1) if replications is None else replications,
            seed=data.get("seed", 0),
            name=data.get("name", path.stem),
            time_series=data.get("time_series", False),
            description=data.get("description", ""),
        )
    except ConfigError as exc:
        raise ConfigError(f"{path}: {exc}") from exc


# ---------------------------------------------------------------------------------- the runs
@dataclass(frozen=True)
class RunSpec:
    """One run of a sweep: everything :func:`run_one` needs, picklable."""

    target: str
    params: dict
    rep: int
    seed: int
    spawn_key: tuple[int, int]
    run_id: str
    time_series: bool = False


def _condition_key(params: Mapping) -> str:
    return json.dumps(params, sort_keys=True, default=str)


def _run_id(params: Mapping, rep: int) -> str:
    text = f"{_condition_key(params)}#{rep}"
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def _spawned_seed(sweep_seed: int, params: Mapping, rep: int) -> tuple[int, tuple[int, int]]:
    """The run's seed: ``SeedSequence(sweep_seed)`` spawned at ``(condition key, rep)``."""
    digest = hashlib.sha256(_condition_key(params).encode()).digest()
    key = (int.from_bytes(digest[:4], "little"), int(rep))
    child = np.random.SeedSequence(sweep_seed, spawn_key=key)
    return int(child.generate_state(1, np.uint64)[0] >> np.uint64(1)), key


def plan(sweep: Sweep) -> list[RunSpec]:
    """Every run of the sweep, grid point by grid point, replications innermost."""
    target = _target(sweep.model_cls)
    specs = []
    for params in sweep.conditions():
        for rep in range(sweep.replications):
            seed, key = _spawned_seed(sweep.seed, params, rep)
            run_id = _run_id(params, rep)
            specs.append(RunSpec(target, params, rep, seed, key, run_id, sweep.time_series))
    return specs


def run_one(spec: RunSpec) -> dict:
    """Run one model to the end; never raises for the model's own errors.

    Returns:
        ``{"row": dict, "series": DataFrame | None}``. The row holds ``run_id``, ``rep``,
        ``seed``, ``spawn_key``, the parameters, the model's summary metrics, ``status``
        ("ok" or "failed"), ``error`` and ``traceback`` (failures only), ``wall_time`` (s) and
        ``worker`` (host:pid).

    """
    start = time.perf_counter()
    row = {
        "run_id": spec.run_id,
        "rep": spec.rep,
        "seed": spec.seed,
        "spawn_key": f"{spec.spawn_key[0]},{spec.spawn_key[1]}",
        **spec.params,
    }
    series = None
    try:
        model_cls = resolve_model(spec.target)
        model = model_cls(**spec.params, seed=spec.seed)
        model.run()
        summary = model.summary()
        summary.pop("seed", None)
        row.update(summary)
        row.update(status="ok", error=None, traceback=None)
        if spec.time_series:
            series = model.state_counts().assign(run_id=spec.run_id)
    except Exception as exc:  # a failing run is a result, not the end of the sweep
        row.update(
            status="failed",
            error=f"{type(exc).__name__}: {exc}",
            traceback=traceback.format_exc(),
        )
    row["wall_time"] = time.perf_counter() - start
    row["worker"] = f"{socket.gethostname()}:{os.getpid()}"
    return {"row": row, "series": series}


# ---------------------------------------------------------------------------------- storage
def _write_atomic(frame: pd.DataFrame, path: Path) -> None:
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    frame.to_parquet(tmp, index=False)
    os.replace(tmp, path)


def _store(out: Path, result: dict) -> None:
    row = result["row"]
    run_id = row["run_id"]
    if row["status"] == "ok":
        if result["series"] is not None:
            _write_atomic(result["series"], out / "series" / f"{run_id}.parquet")
        _write_atomic(pd.DataFrame([row]), out / "runs" / f"{run_id}.parquet")
        (out / "failed" / f"{run_id}.parquet").unlink(missing_ok=True)
    else:
        _write_atomic(pd.DataFrame([row]), out / "failed" / f"{run_id}.parquet")


def _ids(folder: Path) -> set[str]:
    return {p.stem for p in folder.glob("*.parquet")} if folder.is_dir() else set()


def _read_folder(folder: Path) -> list[pd.DataFrame]:
    files = sorted(folder.glob("*.parquet")) if folder.is_dir() else []
    with cf.ThreadPoolExecutor(max_workers=4) as pool:
        return list(pool.map(pd.read_parquet, files))


def load_results(out: str | Path, *, failed: bool = True, series: bool = False) -> pd.DataFrame:
    """Read a sweep's dataset: one row per run (finished first, then failures).

    Args:
        out: the sweep's folder.
        failed: include the rows of runs that raised (``status == "failed"``).
        series: return the concatenated time series (``series/``) instead of the run rows.

    """
    out = Path(out)
    if not out.is_dir():
        raise FileNotFoundError(f"no sweep folder {str(out)!r}")
    if series:
        frames = _read_folder(out / "series")
        return pd.concat(frames, ignore_index=True) if frames else pd.DataFrame()
    frames = _read_folder(out / "runs")
    if failed:
        done = _ids(out / "runs")
        frames += [f for f in _read_folder(out / "failed") if f["run_id"].iloc[0] not in done]
    frames = [f.dropna(axis=1, how="all") for f in frames]
    if not frames:
        return pd.DataFrame(columns=["run_id", "seed", "status"])
    return pd.concat(frames, ignore_index=True).sort_values(["status", "run_id"], ignore_index=True)


def _prepare_out(out: Path, sweep: Sweep) -> None:
    manifest = sweep.manifest()
    path = out / "sweep.json"
    if path.is_file():
        old = json.loads(path.read_text())
        for key in ("target", "seed"):
            if old.get(key) != manifest[key]:
                raise SweepError(
                    f"{out} holds a sweep with {key} {old.get(key)!r}, this one has "
                    f"{manifest[key]!r}: choose another output folder"
                )
        grid = {
            k: list(dict.fromkeys(old["grid"].get(k, []) + v)) for k, v in manifest["grid"].items()
        }
        manifest["grid"] = grid
        manifest["replications"] = max(old.get("replications", 1), manifest["replications"])
        manifest["created"] = old.get("created")
    for sub in ("runs", "failed", "series"):
        (out / sub).mkdir(parents=True, exist_ok=True)
        for tmp in (out / sub).glob(".*.tmp"):  # left by a killed sweep
            tmp.unlink(missing_ok=True)
    manifest.setdefault("created", datetime.datetime.now().isoformat(timespec="seconds"))
    manifest["updated"] = datetime.datetime.now().isoformat(timespec="seconds")
    tmp = path.with_name(".sweep.json.tmp")
    tmp.write_text(json.dumps(manifest, indent=2, default=str))
    os.replace(tmp, path)


# ---------------------------------------------------------------------------------- executors
def _ignore_sigint() -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)


class _Executors:
    """Open the requested executor; closes what it opened."""

    def __init__(self, executor, workers: int | None, address: str | None) -> None:
        self.closers: list = []
        self.kind = executor if isinstance(executor, str) else type(executor).__name__
        if workers is not None:
            _check_int("workers", workers, 1)
        if isinstance(executor, cf.Executor):
            self.pool = executor
        elif _is_dask_client(executor):
            self.pool = executor.get_executor(pure=False)
        elif executor == "serial":
            self.pool = None
        elif executor == "processes":
            self.pool = process_pool(workers or os.cpu_count() or 1, initializer=_ignore_sigint)
            self.closers.append(self.pool)
        elif executor == "dask":
            from dask.distributed import Client, LocalCluster

            if address:
                client = Client(address)
            else:
                cluster = LocalCluster(
                    n_workers=workers or os.cpu_count() or 1,
                    threads_per_worker=1,
                    processes=True,
                    dashboard_address=None,
                )
                self.closers.append(cluster)
                client = Client(cluster)
            self.closers.insert(0, client)
            self.pool = client.get_executor(pure=False)
        else:
            names = ", ".join(repr(e) for e in EXECUTORS)
            raise ConfigError(
                f"executor must be one of {names}, a concurrent.futures Executor or a dask "
                f"Client, got {executor!r}"
            )
        if address and executor != "dask":
            raise ConfigError(f"address is only used with executor='dask', got {address!r}")

    def results(self, specs: Sequence[RunSpec], state: dict) -> Iterator[dict]:
        """Yield run results as they finish (serial: in order)."""
        if self.pool is None:
            for spec in specs:
                yield run_one(spec)
            return
        futures = [self.pool.submit(run_one, spec) for spec in specs]
        state["futures"] = futures
        for future in cf.as_completed(futures):
            exc = future.exception()
            if exc is not None:
                raise SweepError(
                    f"the {self.kind} executor failed ({type(exc).__name__}: {exc}); "
                    "finished runs are on disk, run the sweep again to resume"
                ) from exc
            yield future.result()

    def close(self, cancel: bool = False) -> None:
        """Shut down what this object opened (cancelling queued runs when asked)."""
        for closer in self.closers:
            if isinstance(closer, cf.Executor):
                closer.shutdown(wait=True, cancel_futures=cancel)
            else:
                closer.close()


def _is_dask_client(obj) -> bool:
    return type(obj).__name__ == "Client" and hasattr(obj, "get_executor")


# ---------------------------------------------------------------------------------- entry points
def execute(
    sweep: Sweep,
    out: str | Path | None = None,
    *,
    executor="processes",
    address: str | None = None,
    workers: int | None = None,
    progress: bool = True,
    retry_failed: bool = True,
) -> pd.DataFrame:
    """Run every run of ``sweep`` not already on disk in ``out``; return the whole dataset.

    Before any run starts, every grid point is built once (not run) so that a bad value fails
    at once. Each finished run is written immediately; on Ctrl-C queued runs are cancelled,
    runs in flight are finished and written (a second Ctrl-C abandons them), then
    KeyboardInterrupt propagates.

    Args:
        sweep: what to run.
        out: the sweep's folder (default ``out/sweeps/<sweep.name>``).
        executor: "serial", "processes", "dask", a concurrent.futures Executor or a dask Client.
        address: the Dask scheduler's address (``executor="dask"``); None = a LocalCluster.
        workers: processes (local executors; default: all cores).
        progress: show a progress bar (tqdm) with runs done, failed and the ETA.
        retry_failed: run again the runs recorded as failed.

    Returns:
        :func:`load_results` of ``out``: parameter columns, ``seed``, ``run_id``, metrics.

    """
    out = Path(out) if out is not None else Path("out/sweeps") / sweep.name
    specs = plan(sweep)
    _dry_build(sweep)
    _prepare_out(out, sweep)
    done = _ids(out / "runs")
    failed_before = _ids(out / "failed")
    todo = [
        s for s in specs if s.run_id not in done and (retry_failed or s.run_id not in failed_before)
    ]
    skipped = len(specs) - len(todo)
    if todo:
        _run_all(todo, out, executor, address, workers, progress, skipped)
    return load_results(out)


def _dry_build(sweep: Sweep) -> None:
    """Build every grid point once (without running it) so bad values fail before any run."""
    for params in sweep.conditions():
        try:
            sweep.model_cls(**params, seed=0)
        except ConfigError as exc:
            shown = ", ".join(f"{k}={v!r}" for k, v in params.items())
            raise ConfigError(f"grid point ({shown}): {exc}") from exc


def _run_all(todo, out, executor, address, workers, progress, skipped) -> None:
    from tqdm.auto import tqdm

    bar = tqdm(total=len(todo), unit="run", disable=not progress, smoothing=0.1)
    if skipped:
        bar.write(f"skipping {skipped} runs already in {out}", file=sys.stderr)
    n_ok = n_failed = 0
    pool = _Executors(executor, workers, address)
    state: dict = {}
    interrupted = False
    try:
        for result in pool.results(todo, state):
            _store(out, result)
            if result["row"]["status"] == "ok":
                n_ok += 1
            else:
                n_failed += 1
            bar.set_postfix(done=n_ok, failed=n_failed, refresh=False)
            bar.update()
    except KeyboardInterrupt:
        interrupted = True
        bar.write(
            f"interrupted: {n_ok + n_failed} runs written to {out}; "
            "finishing runs in flight (Ctrl-C again to abandon them)",
            file=sys.stderr,
        )
        _drain(state.get("futures", []), out)
        raise
    finally:
        bar.close()
        pool.close(cancel=interrupted)


def _drain(futures: list, out: Path) -> None:
    """After Ctrl-C: cancel queued runs, write the ones already running when they finish."""
    running = [f for f in futures if not f.cancel() and not f.cancelled()]
    try:
        for future in cf.as_completed(running):
            if future.exception() is None:
                _store(out, future.result())
    except KeyboardInterrupt:
        pass


def run_sweep(
    model_cls: str | type,
    grid: Mapping[str, Sequence],
    replications: int,
    seed: int,
    out: str | Path,
    executor="processes",
    address: str | None = None,
    *,
    workers: int | None = None,
    time_series: bool = False,
    progress: bool = True,
    retry_failed: bool = True,
) -> pd.DataFrame:
    """Run ``model_cls`` over ``grid`` x ``replications``; results go to ``out`` (Parquet).

    Example:
        >>> from models.beacon_explorer import BeaconExplorerModel
        >>> df = run_sweep(BeaconExplorerModel, {"world": ["corridor"],
        ...     "launch_period": [6, 24]}, replications=3, seed=2010,
        ...     out="out/sweeps/demo", executor="serial")  # doctest: +SKIP

    Returns:
        One row per run: parameter columns, ``seed``, ``run_id``, ``rep``, the model's summary
        metrics and ``status`` ("ok" / "failed", with ``error`` and ``traceback``).

    """
    name = Path(out).name or "sweep"
    sweep = Sweep(model_cls, grid, replications, seed, name=name, time_series=time_series)
    return execute(
        sweep,
        out,
        executor=executor,
        address=address,
        workers=workers,
        progress=progress,
        retry_failed=retry_failed,
    )
