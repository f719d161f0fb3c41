"""Work for the writers on a second thread, results in order (``concurrent.futures``).

Formatting a block of numbers is a few hundred numpy calls, some of which release the GIL,
and zstd compression releases it throughout: a second thread gains a little (see
docs/benchmarks.md, "Home-made machinery"). A hand-made pool of forked processes over shared
memory gained 1.2× to 1.3× more, and computing in a forked process (``produced_apart``)
1.1× to 1.25×: both too little to be kept.

The threads are one pool per process, made at the first use and shared by every
:func:`in_order` at work: a stream of blocks made on the pool (``a2b resample`` computes its
samples there) feeds a writer that formats them there, and the two keep no more threads busy
than there are processors. (A pool per stream ran three busy threads on two processors: the
one holding the GIL was often the one descheduled: resampling 10^6 poses to 10^7 CSV rows took
1.1 to 1.15 times as long.)
"""

from __future__ import annotations

import os
import threading
from collections import deque
from collections.abc import Callable, Iterable, Iterator
from itertools import chain, islice

__all__ = ["WORKERS", "in_order"]

#: Threads that format and compress; ``None``: one per processor available, at most 2.
#: 1 does everything in the calling thread.
WORKERS: int | None = None


def workers() -> int:
    """The number of threads :func:`in_order` uses: :data:`WORKERS`, else the processors."""
    if WORKERS is not None:
        return max(1, WORKERS)
    try:
        available = len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        available = os.cpu_count() or 1
    return max(1, min(available, 2))


def in_order(function: Callable, items: Iterable, eager: bool = False) -> Iterator:
    """``function(item)`` for every item, on :func:`workers` threads, yielded in order.

    At most two items per thread are in flight, so memory stays bounded. An exception in
    ``function`` is raised here, at its item. A single item (a command of 101 samples) is
    done in the calling thread, with no thread started, and so is every item where the
    caller is a thread of the pool itself (a task that calls :func:`in_order` must not wait
    for the pool it occupies). ``eager``: the first item goes to the pool as it comes, not
    after the second (for items that are slow to make, such as a trajectory's pieces).
    """
    count = workers()
    items = iter(items)
    first = [] if eager else list(islice(items, 2))
    if count == 1 or (len(first) < 2 and not eager) or getattr(_IN_POOL, "busy", False):
        yield from map(function, chain(first, items))
        return
    pool = _pool(count)
    window: deque = deque()
    try:
        for item in chain(first, items):
            window.append(pool.submit(function, item))
            if len(window) > 2 * count:
                yield window.popleft().result()
        while window:
            yield window.popleft().result()
    finally:
        for future in window:
            future.cancel()


#: The pool of each size made so far in this process (:func:`_pool`).
_POOLS: dict = {}
_IN_POOL = threading.local()


def _pool(count: int):
    """The process's pool of ``count`` threads, made at the first call."""
    pool = _POOLS.get(count)
    if pool is None:
        from concurrent.futures import ThreadPoolExecutor

        pool = _POOLS[count] = ThreadPoolExecutor(
            count, thread_name_prefix="a2b-worker", initializer=_mark_pool_thread
        )
    return pool


def _mark_pool_thread() -> None:
    _IN_POOL.busy = True


if hasattr(os, "register_at_fork"):  # a forked child has none of its parent's threads
    os.register_at_fork(after_in_child=_POOLS.clear)
