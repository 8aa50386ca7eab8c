"""Numba kernels run over index ranges on several threads.

A kernel written as ``kernel(lo, hi, *args)``, compiled ``nogil=True`` and looping over
``range(lo, hi)``, is run here on chunks of ``range(n)`` by a pool of Python threads: the
same use of the cores as numba's ``parallel=True`` with ``prange``, at a fraction of the
compile time (a parallel kernel's loop body is compiled a second time as a gufunc, which
made the first run after an install three times slower). The number of threads is
numba's (``NUMBA_NUM_THREADS``, or :func:`numba.set_num_threads` in the calling thread).
"""

from __future__ import annotations

import threading
from concurrent.futures import ThreadPoolExecutor
from typing import Callable

import numba

_POOLS: dict[int, ThreadPoolExecutor] = {}
_LOCK = threading.Lock()


def threads() -> int:
    """Threads a kernel may use from the calling thread."""
    return max(1, int(numba.get_num_threads()))


def _pool(n: int) -> ThreadPoolExecutor:
    with _LOCK:
        if n not in _POOLS:
            _POOLS[n] = ThreadPoolExecutor(n, thread_name_prefix="millpath-kernel")
        return _POOLS[n]


def over_range(kernel: Callable, n: int, *args, chunks_per_thread: int = 4,
               smallest: int = 1) -> None:
    """Call ``kernel(lo, hi, *args)`` on chunks covering ``range(n)``, in parallel.

    ``chunks_per_thread`` chunks per thread balance uneven work; a range of fewer than
    ``2 * smallest`` items (or one thread) runs in the calling thread. The kernel must
    write only to the items of its own chunk. An exception in any chunk is raised here
    once every chunk has ended."""
    t = threads()
    if n <= 0:
        return
    if t == 1 or n < 2 * smallest:
        kernel(0, n, *args)
        return
    k = min(t * chunks_per_thread, max(1, n // smallest))
    bounds = [(n * i) // k for i in range(k + 1)]
    futures = [_pool(t).submit(kernel, a, b, *args)
               for a, b in zip(bounds[:-1], bounds[1:]) if b > a]
    for f in futures:
        f.exception()
    for f in futures:
        f.result()


def per_thread(kernel: Callable, *args) -> None:
    """Call ``kernel(t, nthreads, *args)`` once for each thread ``t`` in parallel (for
    kernels that split their work by stride themselves)."""
    t = threads()
    if t == 1:
        kernel(0, 1, *args)
        return
    futures = [_pool(t).submit(kernel, i, t, *args) for i in range(t)]
    for f in futures:
        f.exception()
    for f in futures:
        f.result()
