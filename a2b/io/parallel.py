"""Work for the writers on a second thread, results in order (``concurrent.futures``).

Formatting a block of numbers is a few hundred numpy calls, some of which release the GIL,
and zstd compression releases it throughout: a second thread gains a little (see
docs/benchmarks.md, "Home-made machinery"). A hand-made pool of forked processes over shared
memory gained 1.2× to 1.3× more, too little to be kept.
"""

from __future__ import annotations

import contextlib
import os
import pickle
import sys
import warnings
from collections import deque
from collections.abc import Callable, Iterable, Iterator

__all__ = ["WORKERS", "in_order", "produced_apart"]

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
    ``function`` is raised here, at its item.
    """
    count = workers()
    if count == 1:
        yield from map(function, items)
        return
    from concurrent.futures import ThreadPoolExecutor

    with ThreadPoolExecutor(count, thread_name_prefix="a2b-writer") as pool:
        window: deque = deque()
        try:
            for item in items:
                window.append(pool.submit(function, item))
                if len(window) > 2 * count:
                    yield window.popleft().result()
            while window:
                yield window.popleft().result()
        finally:
            for future in window:
                future.cancel()


def produced_apart(items: Callable[[], Iterable]) -> Iterator:
    """The items of ``items()``, computed in a forked child process and yielded here in order.

    Computing (numpy calls that hold the GIL between them) and formatting then run on two
    processors instead of taking turns for one interpreter lock. The child holds at most the
    item it is sending: a pipe's send blocks until this side reads. An exception in the child
    is raised here, at its item, and its warnings are issued here, before the item that
    followed them. Where ``fork`` is not available (or unsafe: not Linux), the
    items are computed here. The child inherits everything read so far, so nothing is pickled
    but the items. Close the generator when done with it (a ``finally``), so that the child
    is stopped at once on an error.
    """
    import multiprocessing

    if sys.platform != "linux" or "fork" not in multiprocessing.get_all_start_methods():
        yield from items()
        return
    context = multiprocessing.get_context("fork")
    receiver, sender = context.Pipe(duplex=False)
    child = context.Process(target=_produce, args=(items, sender), daemon=True)
    stdin, sys.stdin = sys.stdin, None  # else the child closes it: it may read the input
    try:
        child.start()
    finally:
        sys.stdin = stdin
    sender.close()
    try:
        while True:
            try:
                kind, value = _receive(receiver)
            except EOFError:
                raise RuntimeError(
                    f"the computing process ended without a word (exit code {child.exitcode})"
                ) from None
            if kind == "error":
                raise value
            if kind == "done":
                return
            if kind == "warning":  # issued here, where the user's stderr is watched
                warnings.warn_explicit(*value)
                continue
            yield value
    finally:
        with contextlib.suppress(OSError):  # already closed at interpreter exit
            receiver.close()
        if child.is_alive():
            child.terminate()
        child.join()


def _produce(items: Callable[[], Iterable], sender) -> None:
    """The child's side of :func:`produced_apart`."""
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)  # the parent answers Ctrl-C and cleans up
    for name in ("SIGTERM", "SIGHUP", "SIGQUIT", "SIGUSR1", "SIGUSR2", "SIGALRM"):
        if hasattr(signal, name):  # not the parent's handlers: terminate() ends the child now
            signal.signal(getattr(signal, name), signal.SIG_DFL)
    caught: list = []

    def forward(message, category, filename, lineno, file=None, line=None):
        caught.append((message, category, filename, lineno))

    warnings.showwarning = forward  # the child's warnings are sent to the parent, in order
    try:
        for item in items():
            for warning in caught:
                _send(sender, ("warning", warning))
            caught.clear()
            _send(sender, ("item", item))
        for warning in caught:
            _send(sender, ("warning", warning))
        _send(sender, ("done", None))
    except BrokenPipeError:  # the parent stopped reading
        pass
    except Exception as e:  # handed to the parent, raised there at its item
        _send(sender, ("error", e))
    finally:
        sender.close()


def _send(sender, message) -> None:
    """Send ``message`` with its arrays' memory out of band (pickle protocol 5): the pickle,
    then each buffer as it lies in memory, with no copy made for the pickle (a chunk of
    numbers costs a third of the processor time of a pickled copy on each side)."""
    buffers: list = []
    head = pickle.dumps(message, protocol=5, buffer_callback=buffers.append)
    raw = [buffer.raw() for buffer in buffers]
    sender.send_bytes(pickle.dumps((head, [len(r) for r in raw]), protocol=5))
    for part in raw:
        sender.send_bytes(part)


def _receive(receiver):
    """The message :func:`_send` sent, its arrays writable."""
    head, sizes = pickle.loads(receiver.recv_bytes())
    buffers = []
    for size in sizes:
        buffer = bytearray(size)
        receiver.recv_bytes_into(buffer)
        buffers.append(buffer)
    return pickle.loads(head, buffers=buffers)
