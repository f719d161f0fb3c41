"""The exceptions a2b raises.

Every error that a user can cause with input (a malformed pose, a parameter that has no
solution, a motion that passes through a singularity) is an :class:`A2bError`. The command line
turns exactly these into a one-line message and exit status 1; anything else is a bug and keeps
its traceback.
"""

from __future__ import annotations


class A2bError(ValueError):
    """Base class of every error a2b raises on purpose."""


class PoseError(A2bError):
    """A pose (matrix, quaternion, Study vector) fails validation."""


class ParameterError(A2bError):
    """A motion parameter is invalid, or a parameter solver has no solution."""


class SingularMotionError(A2bError):
    """The requested motion passes through a singularity (infinity, ``p(t) = 0``)."""


class InputFileError(A2bError):
    """An input file cannot be read or does not have the expected structure."""


class OptionError(A2bError):
    """An option that does not apply (``frame_id`` for CSV) or conflicts with another; the
    command line reports it as a usage error (status 2)."""


class OutputFileError(A2bError):
    """The output file cannot be created, written or renamed into place."""


class MissingDependencyError(A2bError, ImportError):
    """An optional dependency (matplotlib for ``a2b plot``, plotly for ``a2b view``) is not
    installed. An :class:`A2bError` (the CLI reports it in one line) and an
    :class:`ImportError` (for library callers who test for it)."""


class DuplicateKey(Exception):
    """A key seen twice in one JSON or YAML mapping: raised while parsing and turned into an
    :class:`InputFileError` that names the key and its line (:mod:`a2b.io.documents`)."""

    def __init__(self, key: str, mark: tuple[int, int] | None = None):
        super().__init__(key)
        self.key = key
        self.mark = mark


class A2bWarning(UserWarning):
    """A result that a2b computes but that is sensitive to rounding of the input (near a
    singularity)."""


_ESCAPES = {"\n": "\\n", "\r": "\\r", "\t": "\\t"}


def printable(text: str) -> str:
    """``text`` with every character that is not printable escaped (``\\n``, ``\\x1b``,
    ``\\u202e``), so that a name or value from the user cannot break a one-line message or
    send a terminal escape sequence. Spaces and printable text are kept as they are."""
    if text.isprintable():
        return text
    out = []
    for ch in text:
        if ch.isprintable():
            out.append(ch)
        elif ch in _ESCAPES:
            out.append(_ESCAPES[ch])
        else:
            out.append(ascii(ch)[1:-1])
    return "".join(out)


def quoted(text, most: int = 60) -> str:
    """``text`` quoted for a one-line message: :func:`printable` within quotes, cut after
    ``most`` characters with their count, ``'abc…' (1000000 characters)``."""
    text = str(text)
    if len(text) <= most:
        return f"'{printable(text)}'"
    return f"'{printable(text[:most])}…' ({len(text)} characters)"


def listing(items, limit: int = 4, width: int = 60, empty: str = "") -> str:
    """``items`` for a one-line message: the first ``limit``, each escaped (:func:`printable`)
    and cut to ``width`` characters, then how many more there are (``a, b, c, d and 12
    more``), so that a file of thousands of names or a name of a megabyte still makes a short
    line; ``empty`` if there are none. The one bounded list of a2b's messages."""
    items = list(items)
    shown = [str(item)[: width + 1] for item in items[:limit]]
    shown = [printable(s) if len(s) <= width else printable(s[: width - 1]) + "…" for s in shown]
    more = len(items) - len(shown)
    return (", ".join(shown) or empty) + (f" and {more} more" if more else "")
