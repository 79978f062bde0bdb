"""Where a sweep's runs execute: in this process, a local process pool, or Dask.

* ``"serial"``: in this process, one run after the other;
* ``"processes"``: a local process pool (default: all cores), started from a forkserver;
* ``"dask"``: Dask distributed, on the scheduler at ``address`` or on a fresh ``LocalCluster``
  (pass a ``dask.distributed.Client`` to use e.g. a dask-jobqueue SLURM cluster, see
  ``docs/cluster.md``);
* any ready :class:`concurrent.futures.Executor`.
"""

import concurrent.futures as cf
import os
import signal
from collections.abc import Iterable, Iterator

from abm.errors import ConfigError
from abm.pools import process_pool
from analysis.runner import RunSpec, run_one
from analysis.sweep.spec import check_int
from analysis.sweep.storage import SweepError

__all__ = ["EXECUTORS", "Executors"]

#: Executor names accepted by :func:`analysis.sweep.execute`.
EXECUTORS = ("serial", "processes", "dask")


def _ignore_sigint() -> None:
    signal.signal(signal.SIGINT, signal.SIG_IGN)


class Executors:
    """Open the requested executor; closes what it opened."""

    def __init__(self, executor, workers: int | None, address: str | None) -> None:
        self.closers: list = []
        self.kind = executor if isinstance(executor, str) else type(executor).__name__
        if workers is not None:
            check_int("workers", workers, 1)
        slots = workers or os.cpu_count() or 1
        if isinstance(executor, cf.Executor):
            self.pool = executor
        elif _is_dask_client(executor):
            self.pool = executor.get_executor(pure=False)
            slots = workers or sum(executor.nthreads().values()) or slots
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
            slots = workers or sum(client.nthreads().values()) or slots
        else:
            names = ", ".join(repr(e) for e in EXECUTORS)
            raise ConfigError(
                f"executor must be one of {names}, a concurrent.futures Executor or a dask "
                f"Client, got {executor!r}"
            )
        if address and executor != "dask":
            raise ConfigError(f"address is only used with executor='dask', got {address!r}")
        #: Runs in the executor at a time: two per worker keeps every worker busy.
        self.window = 2 * slots

    def results(self, specs: Iterable[RunSpec], state: dict) -> Iterator[dict]:
        """Yield run results as they finish (serial: in order).

        Runs are taken from ``specs`` as they are needed, with at most :attr:`window` in the
        executor at a time, so a plan of a million runs is never held (or submitted) at once.
        ``state["futures"]`` is the set of runs in the executor (for Ctrl-C).
        """
        if self.pool is None:
            for spec in specs:
                yield run_one(spec)
            return
        specs = iter(specs)
        pending: set = set()
        state["futures"] = pending
        self._fill(pending, specs)
        while pending:
            finished, _ = cf.wait(pending, return_when=cf.FIRST_COMPLETED)
            for future in finished:
                exc = future.exception()
                if exc is not None:
                    raise SweepError(
                        f"the {self.kind} executor failed ({type(exc).__name__}: {exc}); "
                        "finished runs are on disk, run the sweep again to resume"
                    ) from exc
                result = future.result()
                pending.discard(future)
                yield result
            self._fill(pending, specs)

    def _fill(self, pending: set, specs: Iterator[RunSpec]) -> None:
        while len(pending) < self.window:
            spec = next(specs, None)
            if spec is None:
                return
            pending.add(self.pool.submit(run_one, spec))

    def close(self, cancel: bool = False) -> None:
        """Shut down what this object opened (cancelling queued runs when asked)."""
        for closer in self.closers:
            if isinstance(closer, cf.Executor):
                closer.shutdown(wait=True, cancel_futures=cancel)
            else:
                closer.close()


def _is_dask_client(obj) -> bool:
    return type(obj).__name__ == "Client" and hasattr(obj, "get_executor")
