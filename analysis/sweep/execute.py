"""Running a sweep: validate every grid point, skip what is on disk, run the rest, write each
run the moment it finishes, and survive Ctrl-C and failing runs.
"""

import concurrent.futures as cf
import sys
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path

import pandas as pd

from abm.errors import ConfigError
from analysis.sweep.executors import Executors
from analysis.sweep.folder import SweepLock, check_out
from analysis.sweep.integrity import SET_ASIDE, SetAside, scan
from analysis.sweep.membership import PlanIndex
from analysis.sweep.seeding import iter_plan
from analysis.sweep.spec import Sweep, check_name
from analysis.sweep.storage import load_results, prepare_out, read_manifest, store

__all__ = ["DRY_BUILD_POINTS", "execute", "run_sweep"]

#: Grid points built (not run) before any run starts. A model takes ~2-15 ms to build, so a
#: 1e6-point grid cannot be built first; beyond this many, each further point is built when
#: its runs start, and a bad combination becomes a recorded failure of its runs.
DRY_BUILD_POINTS = 200


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

    Before any run starts: the folder is checked (a sweep writes only into a new or empty
    folder or its own sweep folder, never through a link) and locked (a second sweep on it
    stops with one line naming the holder); grid points are built (not run) so that a bad
    combination fails at once (all of them up to :data:`DRY_BUILD_POINTS`, beyond that that
    many covering every value, the rest when their runs start); and every result file already
    in ``out`` is verified: one that is damaged, half-written, or not a run of the folder's
    plan (other parameters, seed or run id) is moved to ``out/set_aside/`` (named by the
    reason, reported on stderr) and never counted. Runs are planned lazily, so the first one
    starts at once even at the 1e6-run limit; each finished run is written immediately. On
    Ctrl-C queued runs are cancelled, runs in flight are finished and written (a second
    Ctrl-C abandons them), then KeyboardInterrupt propagates. A write that fails (full disk,
    read-only folder) stops the sweep with an OSError naming the file; finished runs stay.

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
    check_out(out)
    _dry_build(sweep)
    with SweepLock(out):
        manifest = prepare_out(out, sweep)
        done, failed_before, moved = scan(out, PlanIndex(read_manifest(out)))
        _report_set_aside(out, manifest + moved)
        own = PlanIndex.of(sweep)
        skip = set(done) | (set() if retry_failed else set(failed_before))
        skipped = sum(own.holds(*run) for run in done.values())
        if not retry_failed:
            skipped += sum(own.holds(*run) for k, run in failed_before.items() if k not in done)
        todo = (s for s in iter_plan(sweep) if s.run_id not in skip)
        if skipped < sweep.n_runs:
            _run_all(todo, sweep.n_runs - skipped, out, executor, address, workers, progress,
                     skipped)  # fmt: skip
        return load_results(out)


def _report_set_aside(out: Path, moved: list[SetAside]) -> None:
    """Say which files failed the check, why, and where they went (they are never deleted)."""
    for item in moved:
        print(str(item), file=sys.stderr)
    if moved:
        print(
            f"{len(moved)} damaged, half-written or foreign file(s) set aside in "
            f"{out / SET_ASIDE}; any run of this sweep among them runs again",
            file=sys.stderr,
        )


def _dry_build(sweep: Sweep) -> None:
    """Build grid points once (without running them) so bad values, and a model that cannot
    start (:meth:`~abm.model.SwarmModel.check_ready`), fail before any run.
    """
    for params in _points_to_build(sweep):
        try:
            sweep.model_cls(**params, seed=0).check_ready()
        except ConfigError as exc:
            shown = ", ".join(f"{k}={v!r}" for k, v in params.items())
            raise type(exc)(f"grid point ({shown}): {exc}") from exc  # a HookError stays one


def _points_to_build(sweep: Sweep) -> Iterator[dict]:
    """Every grid point when there are at most :data:`DRY_BUILD_POINTS`; else that many, the
    k-th taking the k-th value of every key (wrapping round), so every value of a key with at
    most that many values is built at least once.
    """
    if sweep.n_points <= DRY_BUILD_POINTS:
        yield from sweep.iter_conditions()
        return
    axes = [[{key: v} for v in values] for key, values in sweep.grid.items()]
    if sweep.points:
        axes.append([dict(p) for p in sweep.points])
    for k in range(min(DRY_BUILD_POINTS, max(len(a) for a in axes))):
        yield {key: v for axis in axes for key, v in axis[k % len(axis)].items()}


def _run_all(todo, total, out, executor, address, workers, progress, skipped) -> None:
    from tqdm.auto import tqdm

    bar = tqdm(total=total, unit="run", disable=not progress, smoothing=0.1)
    if skipped:
        bar.write(f"skipping {skipped} runs already in {out}", file=sys.stderr)
    n_ok = n_failed = 0
    pool = Executors(executor, workers, address)
    state: dict = {}
    stopped = False
    try:
        for result in pool.results(todo, state):
            store(out, result)
            if result["row"]["status"] == "ok":
                n_ok += 1
            else:
                n_failed += 1
            bar.set_postfix(done=n_ok, failed=n_failed, refresh=False)
            bar.update()
    except KeyboardInterrupt:
        stopped = True
        bar.write(
            f"interrupted: {n_ok + n_failed} runs written to {out}; "
            "finishing runs in flight (Ctrl-C again to abandon them)",
            file=sys.stderr,
        )
        _drain(list(state.get("futures", [])), out)
        raise
    except BaseException:
        stopped = True  # a failed write (full disk, read-only) or a broken executor
        raise
    finally:
        bar.close()
        pool.close(cancel=stopped)


def _drain(futures: list, out: Path) -> None:
    """After Ctrl-C: cancel queued runs, write the ones already running when they finish."""
    running = [f for f in futures if not f.cancel() and not f.cancelled()]
    try:
        for future in cf.as_completed(running):
            if future.exception() is None:
                store(out, future.result())
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
    name = _plain_or(Path(out).name, "sweep")
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


def _plain_or(name: str, default: str) -> str:
    """``name`` if it is a plain sweep name, else ``default`` (the folder is given: the name is
    only the sweep's label in ``sweep.json`` and reports).
    """
    try:
        check_name(name)
    except ConfigError:
        return default
    return name
