"""Local process pools that are safe to start from a process running numba's threads, and whose
workers never outlive the process that started them.

Forking a multi-threaded process can deadlock the child (Python warns about it once numba's
compiled kernels have run), so every local pool of the project starts its workers from a
forkserver. Workers import the models afresh; the compiled kernels come from numba's cache.
Each worker runs :mod:`abm.orphans`' watchdog: if the starting process dies (even by
SIGKILL, which runs no clean-up) the workers exit within a fraction of a second, and with them
the forkserver and the resource tracker.

A worker runs one run after another for as long as the pool lives, so before each run it
settles its heap (:func:`settle_worker_heap`): what the runs before left is collected, and the
rest, which lives as long as the worker (modules, numba's compiled functions, Mesa, pandas:
about 180,000-210,000 objects), is frozen out of the cyclic garbage collector's sight. Every
full collection walked all of them, about 0.1 s each, once a run or so in a hierarchy run
(5-6 % of its time; measured with ``gc.callbacks``).
"""

import gc
import multiprocessing
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor

from abm.orphans import identity, watch

__all__ = ["process_pool", "settle_worker_heap"]

#: True in a worker of :func:`process_pool` (its initializer sets it).
_in_worker = False


def process_pool(
    max_workers: int | None = None,
    initializer: Callable | None = None,
    initargs: tuple = (),
    **kwargs,
) -> ProcessPoolExecutor:
    """A ``ProcessPoolExecutor`` whose workers start from a forkserver and watch this process
    (then run ``initializer(*initargs)`` if given).
    """
    return ProcessPoolExecutor(
        max_workers=max_workers,
        mp_context=multiprocessing.get_context("forkserver"),
        initializer=_start_worker,
        initargs=(identity(), initializer, initargs),
        **kwargs,
    )


def _start_worker(parent: str, initializer: Callable | None, initargs: tuple) -> None:
    global _in_worker
    _in_worker = True
    watch(parent)
    if initializer is not None:
        initializer(*initargs)


def settle_worker_heap() -> None:
    """In a worker of :func:`process_pool`, before a run: collect the cyclic garbage of the
    runs before (a finished model is a web of cycles), then freeze what is left alive
    (``gc.freeze``), so that the collections during the run walk only the run's own objects.

    What is frozen is what lives on between runs, so the frozen set stops growing after the
    first runs (imports, compiled functions loaded); an object frozen and later dropped is
    still freed by its reference count, only a cycle of them would stay. Outside a pool
    worker it does nothing: that process's heap is its owner's. Runs decide nothing by the
    collector (``tests/test_pools.py`` runs digest cases in a settled worker against the
    digests on file).
    """
    if _in_worker:
        gc.collect()
        gc.freeze()
