"""Output that appears whole or not at all.

:func:`atomic_output` writes into a temporary file next to the target and renames it into
place only when the writer finished. A failure, Ctrl-C or SIGTERM removes the temporary file
and leaves any existing target untouched. Standard output (``-``) is written directly; a reader
that goes away early (``a2b ... | head``) raises :class:`BrokenPipeError`, which
:func:`silence_stdout` turns into a quiet end.
"""

from __future__ import annotations

import os
import signal
import sys
import tempfile
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from typing import IO

from ..errors import A2bError

__all__ = ["OutputFileError", "atomic_output", "silence_stdout"]


class OutputFileError(A2bError):
    """The output file cannot be created or renamed into place."""


def _is_stdout(path) -> bool:
    return path is None or str(path) == "-"


@contextmanager
def _terminate_as_exit() -> Iterator[None]:
    """Turn SIGTERM into ``SystemExit(143)`` for the duration, so ``finally`` blocks run."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def handler(signum, frame):
        raise SystemExit(128 + signum)

    previous = signal.signal(signal.SIGTERM, handler)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


def _default_mode() -> int:
    umask = os.umask(0)
    os.umask(umask)
    return 0o666 & ~umask


@contextmanager
def atomic_output(path: str | os.PathLike | None) -> Iterator[IO[bytes]]:
    """A binary stream for ``path``; ``None`` or ``"-"`` is standard output.

    For a file, the stream is a temporary file in the same directory, renamed to ``path``
    when the block ends normally (keeping the mode of an existing target, else the umask's).
    If the block raises (including ``KeyboardInterrupt`` and SIGTERM), the temporary file is
    removed and ``path`` is left as it was.

    Raises
    ------
    OutputFileError
        If the temporary file cannot be created or renamed (a missing directory, no
        permission).
    """
    if _is_stdout(path):
        out = sys.stdout.buffer
        yield out
        out.flush()
        return
    target = os.fspath(path)
    directory = os.path.dirname(os.path.abspath(target))
    try:
        mode = os.stat(target).st_mode & 0o7777
    except FileNotFoundError:
        mode = _default_mode()
    except OSError as e:
        raise OutputFileError(f"cannot write {target}: {e.strerror}") from e
    with _terminate_as_exit():
        try:
            fd, tmp = tempfile.mkstemp(prefix=f".{os.path.basename(target)}.", suffix=".tmp", dir=directory)
        except OSError as e:
            raise OutputFileError(f"cannot write {target}: {e.strerror or e}") from e
        try:
            with os.fdopen(fd, "wb", buffering=1 << 20) as stream:
                yield stream
            os.chmod(tmp, mode)
            os.replace(tmp, target)
        except BaseException as e:
            try:
                os.unlink(tmp)
            except FileNotFoundError:
                pass
            if isinstance(e, IsADirectoryError) or (isinstance(e, OSError) and e.filename == target):
                raise OutputFileError(f"cannot write {target}: {e.strerror}") from e
            raise


def silence_stdout() -> None:
    """After a :class:`BrokenPipeError` on stdout: send what is left to ``/dev/null``.

    Python flushes stdout at exit; into a closed pipe that would print a second error.
    Pointing the file descriptor at ``/dev/null`` makes the exit quiet.
    """
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
    except (OSError, ValueError):  # stdout has no file descriptor (tests, embedding)
        pass
