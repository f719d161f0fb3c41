"""Output that appears whole or not at all.

:func:`atomic_output` writes into a temporary file next to the target and renames it into
place only when the writer finished (:func:`atomic_directory` does the same for the files of a
directory). A failure, Ctrl-C, SIGTERM, SIGHUP or a full disk removes
the temporary file and leaves any existing target untouched. Standard output (``-``) and targets
that are no regular file (``/dev/null``, a named pipe, a terminal) are written directly: a
rename cannot replace them. A reader that goes away early (``a2b ... | head``) raises
:class:`BrokenPipeError`, which :func:`silence_stdout` turns into a quiet end; any other write
error (``ENOSPC``, ``EFBIG``, ``EIO``) is an :class:`OutputFileError` naming the target.
"""

from __future__ import annotations

import os
import re
import signal
import stat
import sys
import tempfile
import threading
from collections.abc import Iterator
from contextlib import contextmanager
from typing import IO

from ..errors import OutputFileError

__all__ = ["OutputFileError", "atomic_directory", "atomic_output", "silence_stdout"]


def _is_stdout(path) -> bool:
    return path is None or str(path) == "-"


#: The catchable signals that end a process by default (SIGINT raises KeyboardInterrupt).
_TERMINATING = ("SIGTERM", "SIGHUP", "SIGQUIT", "SIGUSR1", "SIGUSR2", "SIGALRM", "SIGPIPE")


@contextmanager
def _terminate_as_exit() -> Iterator[None]:
    """Turn every catchable terminating signal (:data:`_TERMINATING`) into
    ``SystemExit(128 + signal)`` for the duration, so ``finally`` blocks run."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def handler(signum, frame):
        raise SystemExit(128 + signum)

    signals = [getattr(signal, name) for name in _TERMINATING if hasattr(signal, name)]
    previous = {number: signal.signal(number, handler) for number in signals}
    try:
        yield
    finally:
        for number, handler_before in previous.items():
            signal.signal(number, handler_before)


#: Paths that name an open file descriptor of this process: written through that descriptor.
_DESCRIPTOR_PATH = re.compile(r"/dev/(stdin|stdout|stderr)|/dev/fd/(\d+)|/proc/self/fd/(\d+)")
_STANDARD = {"stdin": 0, "stdout": 1, "stderr": 2}


def _descriptor(path: str) -> int | None:
    """The file descriptor that ``path`` names (``/dev/stdout``, ``/dev/fd/3``), else None."""
    match = _DESCRIPTOR_PATH.fullmatch(os.path.normpath(path))
    if match is None:
        return None
    standard, fd, proc_fd = match.groups()
    return _STANDARD[standard] if standard else int(fd or proc_fd)


def _default_mode() -> int:
    umask = os.umask(0)
    os.umask(umask)
    return 0o666 & ~umask


@contextmanager
def atomic_output(path: str | os.PathLike | None) -> Iterator[IO[bytes]]:
    """A binary stream for ``path``; ``None`` or ``"-"`` is standard output.

    For a file, the stream is a temporary file in the same directory, renamed to ``path``
    when the block ends normally (keeping the mode of an existing target without its set-uid
    and set-gid bits, else the umask's;
    a symbolic link is followed, so the file it points to is replaced). If the block raises
    (including ``KeyboardInterrupt``, SIGTERM and a failed write), the temporary file is
    removed and ``path`` is left as it was. Standard output and targets that are no regular
    file, such as ``/dev/null`` or a named pipe, are written directly; ``/dev/stdout``,
    ``/dev/stderr``, ``/dev/fd/N`` and ``/proc/self/fd/N`` through that descriptor, so a
    shell's ``>> log`` appends. A path that ends in ``/`` names a directory and is refused.

    Raises
    ------
    OutputFileError
        If the temporary file cannot be created, written or renamed (a missing directory, no
        permission, a full disk, a file-size limit), or standard output cannot be written.
    """
    if _is_stdout(path):
        if sys.stdout is None:  # the shell closed it: `a2b ... >&-`
            raise OutputFileError("cannot write standard output: it is closed (give -o FILE)")
        with _write_errors("standard output", on_error=silence_stdout):
            out = sys.stdout.buffer
            yield out
            out.flush()
        return
    if not os.fspath(path):
        raise OutputFileError("cannot write to an empty file name")
    if os.fspath(path).endswith(("/", os.sep)):
        raise OutputFileError(f"cannot write {path}: a path ending in / names a directory")
    fd = _descriptor(os.fspath(path))
    if fd is not None:
        with _through_descriptor(path, fd) as stream:
            yield stream
        return
    target = os.path.realpath(os.fspath(path))
    try:
        info = os.stat(target)
    except FileNotFoundError:
        mode = _default_mode()
    except OSError as e:
        raise OutputFileError(f"cannot write {path}: {e.strerror}") from e
    else:
        if not stat.S_ISREG(info.st_mode) and not stat.S_ISDIR(info.st_mode):
            # A device, a named pipe or a socket: a rename would replace it, not write to it.
            with _write_errors(os.fspath(path)), open(target, "wb") as stream:
                yield stream
            return
        if stat.S_ISREG(info.st_mode) and (
            not os.access(target, os.W_OK)
            or not info.st_mode & (stat.S_IWUSR | stat.S_IWGRP | stat.S_IWOTH)
        ):
            # A rename would replace a file its owner made read-only; a write would fail. The mode
            # bits count even for root, who may write anything: read-only means "keep this".
            raise OutputFileError(f"cannot write {path}: Permission denied (the file is read-only)")
        mode = info.st_mode & 0o7777 & ~(stat.S_ISUID | stat.S_ISGID)  # never set-id bits
    with _renamed_into_place(path, target, mode) as stream:
        yield stream


@contextmanager
def _through_descriptor(path, fd: int) -> Iterator[IO[bytes]]:
    """The descriptor itself, not the file it points to: `-o /dev/stdout >> log` appends."""
    with _write_errors(os.fspath(path), on_error=silence_stdout if fd == 1 else None):
        try:
            stream = os.fdopen(os.dup(fd), "wb")
        except OSError as e:
            raise OutputFileError(f"cannot write {path}: {e.strerror or e}") from e
        with stream:
            if fd == 1:
                sys.stdout.flush()
            yield stream


@contextmanager
def _renamed_into_place(path, target: str, mode: int) -> Iterator[IO[bytes]]:
    """A temporary file beside ``target``, given ``mode`` and renamed to ``target`` when the
    block ends normally, removed if it raises (a terminating signal included)."""
    with _terminate_as_exit():
        try:
            fd, tmp = tempfile.mkstemp(
                prefix=f".{os.path.basename(target)}.", suffix=".tmp", dir=os.path.dirname(target)
            )
        except OSError as e:
            raise OutputFileError(f"cannot write {path}: {e.strerror or e}") from e
        try:
            with _write_errors(os.fspath(path)):
                with os.fdopen(fd, "wb", buffering=1 << 20) as stream:
                    yield stream
                os.chmod(tmp, mode)
                os.replace(tmp, target)
        except BaseException:
            try:
                os.unlink(tmp)
            except FileNotFoundError:
                pass
            raise


@contextmanager
def atomic_directory(path: str | os.PathLike | None) -> Iterator[str]:
    """A temporary directory whose files are moved into the directory ``path`` at the end.

    The files are written into a temporary directory beside ``path``. When the block ends
    normally, ``path`` is created if it does not exist, and each file is renamed into it,
    replacing a file of the same name; other files in ``path`` are left alone. The moves are
    all or none: a name taken by a directory is refused before any, and if a move fails the
    files moved so far are taken back and the replaced ones restored. If the block raises
    (including ``KeyboardInterrupt``, SIGTERM and a failed write), the temporary directory is
    removed and ``path`` is left as it was.

    Raises
    ------
    OutputFileError
        If ``path`` is standard output or an existing file that is no directory, or the
        temporary directory cannot be made or its files renamed into place.
    """
    import shutil

    if _is_stdout(path) or not os.fspath(path):
        raise OutputFileError("this format writes one file per job: give a directory with -o DIR")
    target = os.path.realpath(os.fspath(path))
    if os.path.exists(target) and not os.path.isdir(target):
        raise OutputFileError(f"cannot write into {path}: it is a file, not a directory")
    parent = os.path.dirname(target)
    with _terminate_as_exit():
        try:
            tmp = tempfile.mkdtemp(
                prefix=f".{os.path.basename(target)}.", suffix=".tmp", dir=parent
            )
        except OSError as e:
            raise OutputFileError(f"cannot write {path}: {e.strerror or e}") from e
        try:
            with _write_errors(os.fspath(path)):
                yield tmp
                _move_all(tmp, target, os.fspath(path))
        finally:
            shutil.rmtree(tmp, ignore_errors=True)


def _move_all(source: str, target: str, path: str) -> None:
    """Move every file of ``source`` into ``target``, all or none: the files they replace are
    first moved aside (into ``source``), and put back if any move fails."""
    names = sorted(os.listdir(source))
    blocked = [n for n in names if os.path.isdir(os.path.join(target, n))]
    if blocked:
        more = f" and {len(blocked) - 3} more" if len(blocked) > 3 else ""
        shown = ", ".join(repr(n) for n in blocked[:3])
        raise OutputFileError(
            f"cannot write into {path}: {shown}{more} already there as a directory"
        )
    made = not os.path.isdir(target)
    os.makedirs(target, exist_ok=True)
    aside = tempfile.mkdtemp(prefix=".old.", dir=source)
    mode = _default_mode()
    kept, placed = [], []
    try:
        for name in names:
            if os.path.lexists(os.path.join(target, name)):
                os.replace(os.path.join(target, name), os.path.join(aside, name))
                kept.append(name)
        for name in names:
            os.chmod(os.path.join(source, name), mode)
            os.replace(os.path.join(source, name), os.path.join(target, name))
            placed.append(name)
    except BaseException:
        for name in placed:
            os.unlink(os.path.join(target, name))
        for name in kept:
            os.replace(os.path.join(aside, name), os.path.join(target, name))
        if made:
            os.rmdir(target)
        raise


@contextmanager
def _write_errors(what: str, on_error=None) -> Iterator[None]:
    """Turn an :class:`OSError` of writing (not a closed pipe) into an :class:`OutputFileError`."""
    try:
        yield
    except BrokenPipeError:
        raise
    except OSError as e:
        if on_error is not None:
            on_error()
        raise OutputFileError(f"cannot write {what}: {e.strerror or e}") from e


@contextmanager
def writing_stdout() -> Iterator[None]:
    """Text printed to standard output within (a table, JSON): a failed write is an
    :class:`OutputFileError` ``cannot write standard output: …``, what is left goes to
    ``/dev/null``; a closed pipe stays a :class:`BrokenPipeError`, which ``a2b.cli`` ends
    quietly with status 0."""
    with _write_errors("standard output", on_error=silence_stdout):
        yield


def silence_stdout() -> None:
    """After a :class:`BrokenPipeError` or a failed write on stdout: send what is left to
    ``/dev/null``.

    Python flushes stdout at exit; into a closed pipe or a full disk that would print a second
    error.
    Pointing the file descriptor at ``/dev/null`` makes the exit quiet.
    """
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
    except (OSError, ValueError):  # stdout has no file descriptor (tests, embedding)
        pass
