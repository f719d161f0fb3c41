"""Work for the writers on every core, results in order.

Formatting numbers and compressing MCAP chunks spend their time in numpy and zstd, which
release the GIL, so a few threads keep every core busy while the main thread writes.
"""

from __future__ import annotations

import os
from collections import deque
from collections.abc import Callable, Iterable, Iterator

__all__ = ["WORKERS", "in_order", "workers"]

#: Threads that format and compress; ``None``: one per processor available, at most 4.
WORKERS: int | None = None


def workers() -> int:
    """The number of threads :func:`in_order` uses: :data:`WORKERS`, else the processors."""
    if WORKERS is not None:
        return max(1, WORKERS)
    try:
        available = len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        available = os.cpu_count() or 1
    return max(1, min(available, 4))


def in_order(function: Callable, items: Iterable) -> Iterator:
    """``function(item)`` for every item, computed by :func:`workers` threads, in order.

    At most two items per thread are in flight, so memory stays bounded. An exception in
    ``function`` is raised here, at its item; items not yet started are then dropped.
    With one worker everything runs in the calling thread.
    """
    count = workers()
    if count == 1:
        yield from map(function, items)
        return
    from concurrent.futures import ThreadPoolExecutor

    pool = ThreadPoolExecutor(count, thread_name_prefix="a2b-writer")
    pending: deque = deque()
    try:
        for item in items:
            pending.append(pool.submit(function, item))
            if len(pending) > 2 * count:
                yield pending.popleft().result()
        while pending:
            yield pending.popleft().result()
    finally:
        pool.shutdown(wait=True, cancel_futures=True)
