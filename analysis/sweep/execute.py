"""Running a sweep: validate every grid point, skip what is on disk, run the rest, write each
run the moment it finishes, and survive Ctrl-C and failing runs.
"""

import concurrent.futures as cf
import sys
from collections.abc import Mapping, Sequence
from pathlib import Path

import pandas as pd

from abm.errors import ConfigError
from analysis.sweep.executors import Executors
from analysis.sweep.integrity import SET_ASIDE, SetAside, scan
from analysis.sweep.seeding import plan
from analysis.sweep.spec import Sweep
from analysis.sweep.storage import load_results, prepare_out, store

__all__ = ["execute", "run_sweep"]


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
    at once, and every result file already in ``out`` is verified: one that is damaged,
    half-written or holds another run is moved to ``out/set_aside/`` (named by the reason,
    reported on stderr) and its run runs again. Each finished run is written immediately; on
    Ctrl-C queued runs are cancelled, runs in flight are finished and written (a second
    Ctrl-C abandons them), then KeyboardInterrupt propagates.

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
    manifest = prepare_out(out, sweep)
    done, failed_before, moved = scan(out, specs)
    _report_set_aside(out, manifest + moved)
    todo = [
        s for s in specs if s.run_id not in done and (retry_failed or s.run_id not in failed_before)
    ]
    skipped = len(specs) - len(todo)
    if todo:
        _run_all(todo, out, executor, address, workers, progress, skipped)
    return load_results(out)


def _report_set_aside(out: Path, moved: list[SetAside]) -> None:
    """Say which files failed the check, why, and where they went (they are never deleted)."""
    for item in moved:
        print(str(item), file=sys.stderr)
    if moved:
        print(
            f"{len(moved)} damaged or half-written file(s) set aside in {out / SET_ASIDE}; "
            "any run of this sweep among them runs again",
            file=sys.stderr,
        )


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
    pool = Executors(executor, workers, address)
    state: dict = {}
    interrupted = False
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
