"""Local process pools that are safe to start from a process running numba's threads, and whose
workers never outlive the process that started them.

Forking a multi-threaded process can deadlock the child (Python warns about it once numba's
compiled kernels have run), so every local pool of the project starts its workers from a
forkserver. Workers import the models afresh; the compiled kernels come from numba's cache.
Each worker runs :mod:`abm.orphans`' watchdog: if the starting process dies (even by
SIGKILL, which runs no clean-up) the workers exit within a fraction of a second, and with them
the forkserver and the resource tracker.
"""

import multiprocessing
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor

from abm.orphans import identity, watch

__all__ = ["process_pool"]


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
    watch(parent)
    if initializer is not None:
        initializer(*initargs)
