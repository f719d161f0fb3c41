"""Work for the writers on a second thread, results in order (``concurrent.futures``).

Formatting a block of numbers is a few hundred numpy calls, some of which release the GIL,
and zstd compression releases it throughout: a second thread gains a little (see
docs/benchmarks.md, "Home-made machinery"). A hand-made pool of forked processes over shared
memory gained 1.2× to 1.3× more, and computing in a forked process (``produced_apart``)
1.1× to 1.25×: both too little to be kept.
"""

from __future__ import annotations

import os
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


def in_order(function: Callable, items: Iterable) -> Iterator:
    """``function(item)`` for every item, on :func:`workers` threads, yielded in order.

    At most two items per thread are in flight, so memory stays bounded. An exception in
    ``function`` is raised here, at its item. A single item (a command of 101 samples) is
    done in the calling thread, with no thread started.
    """
    count = workers()
    items = iter(items)
    first = list(islice(items, 2))
    if count == 1 or len(first) < 2:
        yield from map(function, chain(first, items))
        return
    from concurrent.futures import ThreadPoolExecutor

    with ThreadPoolExecutor(count, thread_name_prefix="a2b-writer") as pool:
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
