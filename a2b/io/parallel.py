"""Work for the writers on every core, results in order.

Formatting a block of numbers is a few hundred numpy calls on small arrays: each is quick,
and the GIL is taken between them, so threads barely help. On Linux the other cores are used
by forking helper processes that format blocks while the main process formats others;
blocks go to them and text comes back through shared memory (a pipe says when), and the main
process writes everything in order. A helper is forked only for a core that has nothing else to run at the time.
Elsewhere (no ``fork``, or other threads running, where forking is unsafe) threads do the
work; zstd compression, which releases the GIL, still gains from them.
"""

from __future__ import annotations

import contextlib
import os
import sys
import threading
from collections import deque
from collections.abc import Callable, Iterable, Iterator

__all__ = ["WORKERS", "in_order", "workers"]

#: Processes (or threads) that format and compress; ``None``: one per processor available,
#: at most 4. 1 does everything in the calling thread.
WORKERS: int | None = None


def workers() -> int:
    """The number of workers :func:`in_order` uses: :data:`WORKERS`, else the processors."""
    if WORKERS is not None:
        return max(1, WORKERS)
    try:
        available = len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        available = os.cpu_count() or 1
    return max(1, min(available, 4))


def in_order(function: Callable, items: Iterable) -> Iterator:
    """``function(item)`` for every item, spread over :func:`workers` cores, yielded in order.

    Items and results must pickle (helper processes get them through shared memory or a
    pipe). At most two
    items per worker are in flight, so memory stays bounded. An exception in ``function``
    is raised here, at its item. Helpers start only once a second item arrives, so a single
    small item costs no fork.
    """
    count = workers()
    if count == 1:
        yield from map(function, items)
    elif _can_fork():
        yield from _with_helpers(function, items, count - 1)
    else:
        yield from _with_threads(function, items, count)


def _idle_processors() -> int:
    """Processors that other programs leave idle, now (the most of three looks).

    A helper on a processor that another program keeps busy only adds the cost of the
    pipes (about 10%); on an idle one it takes half the work. So a processor counts as idle
    if any of three looks, 2 ms apart, finds it so (the first that does ends the looking): a
    task that runs for a moment (the kernel writing a file back to disk) must not cost half
    the speed. The kernel's count of runnable tasks (``/proc/loadavg``) says which, at once
    (the load average would remember the last minute); this process's own runnable threads,
    such as a BLAS thread still spinning after a product, and its children, such as the one
    scanning the jobs of ``a2b batch`` (:mod:`a2b.io.jobscan`), which will soon be done, are
    not counted. Setting :data:`WORKERS` skips this judgement.
    """
    import time

    fewest = None  # the fewest processors other programs kept busy in a look
    for look in range(3):
        if look:
            time.sleep(0.002)
        try:
            with open("/proc/loadavg") as f:
                running = int(f.read().split()[3].split("/")[0])
            own = _runnable_own_tasks()
        except (OSError, ValueError, IndexError):  # pragma: no cover - no such files
            return workers()
        others = max(0, running - max(own, 1))
        fewest = others if fewest is None else min(fewest, others)
        if fewest == 0:
            break
    return max(0, workers() - 1 - fewest)


def _runnable_own_tasks() -> int:
    """This process's runnable threads and its runnable children."""
    own = 0
    for task in os.listdir("/proc/self/task"):
        own += _runnable(f"/proc/self/task/{task}/stat")
        try:
            with open(f"/proc/self/task/{task}/children") as f:
                children = f.read().split()
        except OSError:  # pragma: no cover - a kernel without the list of children
            children = []
        for child in children:
            own += _runnable(f"/proc/{child}/stat")
    return own


def _runnable(stat: str) -> bool:
    try:
        with open(stat) as f:
            return f.read().rpartition(")")[2].split()[0] == "R"
    except (OSError, IndexError):  # the task has just ended
        return False


def _can_fork() -> bool:
    # fork copies only the calling thread: a lock another thread holds would stay locked
    return sys.platform.startswith("linux") and threading.active_count() == 1


def _with_threads(function: Callable, items: Iterable, count: int) -> Iterator:
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


#: Bytes of each helper's two shared buffers (items in, results out). Larger items and
#: results go through the pipe as pickles.
BOX = 16 << 20


class _Helper:
    """A forked process that applies ``function`` to the items it is sent, one at a time.

    Items and results cross in two shared-memory buffers, so only a few bytes go through the
    pipe: an item's arrays are copied into the inbox (pickle protocol 5, out of band) and the
    helper formats from views of it; a result comes back in the outbox, as it is if it is
    bytes, else pickled (an exception comes through the pipe). Through a pipe they would cross
    in 64 KiB pieces, each of which the main process's feeding thread takes only when it gets
    the GIL, leaving the helper waiting.
    """

    def __init__(self, function: Callable, others: list[_Helper]):
        import mmap
        from multiprocessing.connection import Pipe

        self.inbox = mmap.mmap(-1, BOX)  # anonymous and shared: the child sees the same pages
        self.outbox = mmap.mmap(-1, BOX)
        self.connection, theirs = Pipe()
        self.pid = os.fork()
        if self.pid == 0:  # pragma: no cover - runs in the child; its results are tested
            for other in (self, *others):  # or the other helpers would never see end-of-file
                other.connection.close()
            _serve(function, theirs, self.inbox, self.outbox)
        theirs.close()

    def run(self, item) -> tuple[str, object]:
        """``("ok", function(item))`` or ``("error", exception)``, computed by the helper; an
        item that does not pickle or a result that does not unpickle is an error too, so that
        the thread feeding the helper never dies with the main process waiting for it."""
        try:
            message = _pack(item, self.inbox)
        except Exception as e:  # noqa: BLE001 - raised in the main process, at its item
            return "error", e
        try:
            self.connection.send_bytes(message)
            reply = self.connection.recv_bytes()
        except (OSError, EOFError) as e:
            return "error", RuntimeError(f"a writer's helper process ended unexpectedly: {e!r}")
        try:
            if reply[:1] == b"B":  # bytes in the outbox
                return "ok", self.outbox[: int(reply[1:])]
            if reply[:1] == b"P":  # a pickle in the outbox
                return _loads(self.outbox[: int(reply[1:])])
            return _loads(reply[1:])
        except Exception as e:  # noqa: BLE001 - e.g. an exception whose __init__ takes more
            return "error", RuntimeError(f"a writer's helper sent what cannot be read: {e!r}")

    def close(self) -> None:
        self.connection.close()  # the helper reads end-of-file and exits
        os.waitpid(self.pid, 0)
        self.inbox.close()
        self.outbox.close()


def _pack(item, box) -> bytes:
    """The message that sends ``item``: its pickle, its large buffers copied into ``box``."""
    import pickle

    buffers: list = []
    data = pickle.dumps(item, protocol=5, buffer_callback=buffers.append)
    views = [b.raw() for b in buffers]
    if sum(v.nbytes for v in views) > len(box):
        return b"P" + pickle.dumps(item, protocol=5)  # too large: all through the pipe
    offset, sizes = 0, []
    for view in views:
        box[offset : offset + view.nbytes] = view
        offset += view.nbytes
        sizes.append(view.nbytes)
    return b"O" + pickle.dumps((data, sizes), protocol=5)


def _unpack(message: bytes, box):
    """The item of a :func:`_pack` message; its buffers are views of ``box``."""
    import pickle

    if message[:1] == b"P":
        return pickle.loads(message[1:])
    data, sizes = pickle.loads(message[1:])
    whole = memoryview(box)
    views, offset = [], 0
    for size in sizes:
        views.append(whole[offset : offset + size])
        offset += size
    return pickle.loads(data, buffers=views)


def _loads(data: bytes):
    import pickle

    return pickle.loads(data)


def _serve(function: Callable, connection, inbox, outbox) -> None:  # pragma: no cover - child
    """The helper's life: items in, results out, until the pipe closes; then ``_exit``.

    Ctrl-C goes to the whole process group; the main process handles it, the helper ignores
    it. ``os._exit`` skips the parent's atexit handlers and stdio buffers, which the fork
    copied and which are not the helper's to flush.
    """
    import pickle
    import signal

    signal.signal(signal.SIGINT, signal.SIG_IGN)
    with contextlib.suppress(BaseException):  # the main process went away
        while True:
            try:
                message = connection.recv_bytes()
            except EOFError:
                break
            try:
                result = function(_unpack(message, inbox))
            except Exception as e:  # noqa: BLE001 - handed to the main process to raise
                reply = b"R" + _dumps_error(e)
            else:
                if type(result) is bytes and len(result) <= len(outbox):
                    outbox[: len(result)] = result
                    reply = b"B%d" % len(result)
                else:
                    try:
                        reply = b"R" + pickle.dumps(("ok", result), protocol=5)
                    except Exception as e:  # noqa: BLE001 - a result that does not pickle
                        reply = b"R" + _dumps_error(e)
                    if len(reply) - 1 <= len(outbox):  # a pickle in the outbox
                        outbox[: len(reply) - 1] = memoryview(reply)[1:]
                        reply = b"P%d" % (len(reply) - 1)
            connection.send_bytes(reply)
    os._exit(0)


def _dumps_error(e: Exception) -> bytes:
    """``("error", e)`` pickled, or a ``RuntimeError`` that says what ``e`` was."""
    import pickle

    try:
        return pickle.dumps(("error", e), protocol=5)
    except Exception:  # noqa: BLE001 - an exception that does not pickle
        return pickle.dumps(("error", RuntimeError(f"{type(e).__name__}: {e}")), protocol=5)


def _with_helpers(function: Callable, items: Iterable, count: int) -> Iterator:
    """The main process and ``count`` helpers take items from one queue as they get free.

    A thread per helper hands it the next waiting item as soon as it is done with the last
    (blocking on its pipe, without the GIL), so helpers never wait for the main process,
    which formats waiting items itself and yields every result in order.
    """
    iterator = iter(items)
    first = next(iterator, _END)
    if first is _END:
        return
    second = next(iterator, _END)
    if second is _END:
        yield function(first)
        return
    iterator = _chain(first, second, iterator)
    if WORKERS is None:
        count = min(count, _idle_processors())
        if count == 0:
            yield from map(function, iterator)
            return
    lock = threading.Condition()
    waiting: deque = deque()  # (index, item) not taken yet
    done: dict = {}  # index -> (status, value)
    state = {"stop": False}

    def feed(helper: _Helper) -> None:
        while True:
            with lock:
                while not waiting and not state["stop"]:
                    lock.wait()
                if state["stop"]:
                    return
                index, item = waiting.popleft()
            result = helper.run(item)
            with lock:
                done[index] = result
                lock.notify_all()

    helpers: list[_Helper] = []
    threads: list[threading.Thread] = []
    try:
        for _ in range(count):  # fork before any thread starts
            helpers.append(_Helper(function, helpers))
        for helper in helpers:
            threads.append(threading.Thread(target=feed, args=(helper,), daemon=True))
            threads[-1].start()
        pulled = taken = 0  # items taken from ``items``, results yielded
        exhausted = False
        while True:
            with lock:
                result = done.pop(taken, None)
            if result is not None:
                status, value = result
                if status == "error":
                    raise value
                yield value
                taken += 1
                continue
            if not exhausted and len(waiting) < count + 1 and pulled - taken < 4 * (count + 1):
                item = next(iterator, _END)
                if item is _END:
                    exhausted = True
                else:
                    with lock:
                        waiting.append((pulled, item))
                        lock.notify_all()
                    pulled += 1
                continue
            if exhausted and taken == pulled:
                return
            with lock:
                job = waiting.popleft() if waiting else None
                while job is None and taken not in done:
                    lock.wait()
            if job is not None:
                index, item = job
                try:
                    result = ("ok", function(item))
                except Exception as e:  # noqa: BLE001 - raised when its turn comes
                    result = ("error", e)
                with lock:
                    done[index] = result
    finally:
        with lock:
            state["stop"] = True
            waiting.clear()
            lock.notify_all()
        for thread in threads:
            thread.join()  # each finishes the item its helper has
        for helper in helpers:
            helper.close()


_END = object()


def _chain(first, second, rest: Iterator) -> Iterator:
    yield first
    yield second
    yield from rest
