"""Local process pools that are safe to start from a process running numba's threads.

Forking a multi-threaded process can deadlock the child (Python warns about it once numba's
compiled kernels have run), so every local pool of the project starts its workers from a
forkserver. Workers import the models afresh; the compiled kernels come from numba's cache.
"""

import multiprocessing
from concurrent.futures import ProcessPoolExecutor

__all__ = ["process_pool"]


def process_pool(max_workers: int | None = None, **kwargs) -> ProcessPoolExecutor:
    """A ``ProcessPoolExecutor`` whose workers start from a forkserver."""
    return ProcessPoolExecutor(
        max_workers=max_workers, mp_context=multiprocessing.get_context("forkserver"), **kwargs
    )
