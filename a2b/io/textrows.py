"""Rows of numbers in text: what the text trajectory formats share.

A text trajectory is lines of numbers, separated by commas or by blanks, with ``#`` comments
and blank lines. :func:`read_rows` parses some of its lines in bulk (``numpy.loadtxt``) into
the columns a :class:`TextLayout` names; only when that fails, or a message needs the line of a
row, are the lines numbered one by one. A header that names its columns is read by the names
(:func:`named_layout`), never by where a column is expected to be.

Bytes are read with :func:`read_text_bytes`, which refuses what no text has (a NUL byte, as
from ``/dev/zero``) as soon as it arrives, so memory stays bounded by what a text file holds.
"""

from __future__ import annotations

import io
import os
import re
import stat
import warnings
from collections.abc import Iterator
from dataclasses import dataclass
from decimal import Decimal, InvalidOperation
from typing import IO

import numpy as np

from ..errors import InputFileError, listing, printable
from .documents import stream_name

__all__ = [
    "BOM",
    "NUMBER",
    "Lines",
    "TextLayout",
    "TextStream",
    "check_text",
    "first_line",
    "header_line",
    "named_layout",
    "role",
    "read_rows",
    "read_text_bytes",
    "read_times",
    "replayed",
    "whole_file",
    "written_times",
]

BOM = b"\xef\xbb\xbf"
#: The longest header line read.
HEADER_BYTES = 1 << 16
#: Bytes read at a time by :func:`read_text_bytes`.
READ_BYTES = 1 << 20
#: A number as numpy's text reader takes it (``nan`` and ``inf`` are then refused as such).
NUMBER = re.compile(
    r"[-+]?(?:(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][-+]?[0-9]+)?|nan|inf(?:inity)?)", re.I
)
#: A line whose first field is more than an optional sign and digits (nanosecond stamps).
_NOT_AN_INTEGER_STAMP = re.compile(rb"(?m)^(?![ \t]*#)[ \t]*[+-]?[0-9]*[^0-9,\r\n]")
_SHOWN = 5  # items a message names before it says how many more


def _few(items: list) -> str:
    """The first few items, quoted and escaped, and how many more
    (:func:`a2b.errors.listing`)."""
    return listing([f"'{str(item)[:40]}'" for item in items[:_SHOWN]] + items[_SHOWN:], _SHOWN, 42)


def read_text_bytes(stream: IO, name: str, head: bytes = b"", limit: int | None = None) -> bytes:
    """The text of a stream whose first bytes, ``head``, were read already. A NUL byte (no
    text has one: ``/dev/zero``, a binary file) is an error: in a regular file, whose bytes
    are all there, after reading it at once; in any other stream as soon as its piece
    arrives. With ``limit``, more bytes than ``limit`` are an error: a regular file's before
    any is read, any other stream's as soon as they arrive."""
    whole = whole_file(stream, head, limit, name)
    if whole is not None:
        _refuse_nul(whole, name, 0, 0)
        return whole
    parts, size = [head], len(head)
    _refuse_nul(head, name, 0, 0)
    _refuse_size(size, limit, name)
    while True:
        part = stream.read(READ_BYTES)
        if not part:
            break
        if isinstance(part, str):
            part = part.encode()
        _refuse_nul(part, name, size, parts)
        parts.append(part)
        size += len(part)
        _refuse_size(size, limit, name)
    return b"".join(parts)


def whole_file(
    stream: IO, head: bytes, limit: int | None = None, name: str = "the file"
) -> bytes | None:
    """All bytes of a regular file from where ``head`` started, read at once (without a copy
    of ``head`` joined to the rest), else ``None``; a file larger than ``limit`` bytes is an
    error before it is read."""
    size = _rewound(stream, head)
    if size is None:
        return None
    _refuse_size(size, limit, name)
    data = stream.read()
    return data.encode() if isinstance(data, str) else data


def _rewound(stream: IO, head: bytes) -> int | None:
    """The bytes of a regular binary file from where ``head`` started, with the stream put
    back there; ``None`` (and the stream as it was) for any other stream."""
    if isinstance(stream, io.TextIOBase):  # its positions are no byte counts
        return None
    try:
        status = os.fstat(stream.fileno())
        if not stat.S_ISREG(status.st_mode):
            return None
        start = stream.tell() - len(head)
        stream.seek(start)
    except (AttributeError, OSError, ValueError, io.UnsupportedOperation):
        return None
    return status.st_size - start


class TextStream:
    """A large regular text file (:data:`STREAM_FROM` bytes or more), read a piece at a time
    as it is parsed rather than whole first: the work on the first poses starts after one
    piece is read, and no page of a copy of the whole file is faulted in (75 ms for 150 MB
    before the first pose). :meth:`pieces` gives the bytes, once, while the stream is open;
    ``len()`` is the file's size when it was opened (a file written meanwhile is read as far
    as it has grown when each piece is read)."""

    def __init__(self, stream: IO, size: int):
        self.stream, self.size, self.read = stream, size, False

    @classmethod
    def of(cls, stream: IO, head: bytes) -> TextStream | None:
        """The stream whose first bytes, ``head``, were read already, if it is a large regular
        file (put back to its start), else ``None``."""
        size = _rewound(stream, head)
        if size is None:
            return None
        if size >= STREAM_FROM:
            return cls(stream, size)
        stream.seek(len(head), os.SEEK_CUR)  # as it was
        return None

    def __len__(self) -> int:
        return self.size

    def pieces(self, size: int, first: int) -> Iterator[bytes]:
        """The bytes in consecutive pieces: each ends at the first line end at or after
        ``size`` bytes into it (the first piece: ``first``), the last at the end; or, in a
        line without end, after the part where a NUL byte is (no text has one: the piece's
        check refuses it before more is read). The bytes can be taken only once."""
        if self.read:
            raise ValueError("the pieces of a TextStream are read once")
        self.read = True
        read, step, buffer = self.stream.read, first, b""
        while True:
            buffer = _filled(read, buffer, step + _AFTER)
            if len(buffer) <= step:  # all that is left
                if buffer:
                    yield buffer
                return
            cut = buffer.find(b"\n", step)
            if cut < 0:  # a line longer than what was read past the size
                buffer, cut = _to_line_end(read, buffer)
            cut = len(buffer) if cut < 0 else cut + 1
            yield buffer[:cut]
            buffer, step = buffer[cut:], size


def _filled(read, buffer: bytes, want: int) -> bytes:
    """``buffer`` and what follows it, up to ``want`` bytes (fewer: all that is left)."""
    parts, have = [buffer], len(buffer)
    while have < want:
        more = read(want - have)
        if not more:
            break
        parts.append(more)
        have += len(more)
    return b"".join(parts) if len(parts) > 1 else buffer


def _to_line_end(read, buffer: bytes) -> tuple[bytes, int]:
    """``buffer`` and what follows it up to the next line end (or all that is left, or up to
    a part with a NUL byte), read in parts twice as large each time, and where that line end
    is (−1: none)."""
    parts, have, chunk = [buffer], len(buffer), _AFTER
    while b"\0" not in parts[-1]:
        more = read(chunk)
        if not more:
            break
        parts.append(more)
        at = more.find(b"\n")
        if at >= 0:
            return b"".join(parts), have + at
        have, chunk = have + len(more), min(2 * chunk, 1 << 26)
    return b"".join(parts), -1


#: Bytes read past a piece's size, where its last line ends.
_AFTER = 1 << 16
#: Regular files from this many bytes are read as they are parsed (:class:`TextStream`).
STREAM_FROM = 1 << 24


def _refuse_size(size: int, limit: int | None, name: str) -> None:
    if limit is not None and size > limit:
        raise InputFileError(
            f"{name}: more than {limit // (1 << 20)} MiB, more than a2b reads from a file of "
            "this kind"
        )


def _refuse_nul(part: bytes, name: str, offset: int, before: int | list) -> None:
    """A NUL byte in ``part``, ``offset`` bytes into the stream, is an error at its line:
    ``before`` is the number of lines before ``part``, or the parts before it (their lines
    counted only then)."""
    at = part.find(b"\0")
    if at < 0:
        return
    lines = before if isinstance(before, int) else sum(p.count(b"\n") for p in before)
    line = lines + part.count(b"\n", 0, at) + 1
    raise InputFileError(
        f"{name}:{line}: a NUL byte at byte {offset + at}, so this is no text file"
    )


def replayed(stream: IO, name: str, head: bytes = b"", text: bool = True) -> io.BufferedReader:
    """A binary stream of the bytes of ``stream`` from the start, when its first bytes,
    ``head``, were read already. With ``text``, a NUL byte is an error as soon as its piece
    arrives (as in :func:`read_text_bytes`): a reader of lines meets no endless line."""
    return io.BufferedReader(_Replayed(stream, name, head, text))


class _Replayed(io.RawIOBase):
    def __init__(self, stream: IO, name: str, head: bytes, text: bool):
        self.stream, self.name, self.head, self.text = stream, name, memoryview(head), text
        self.offset = self.lines = 0

    def readable(self) -> bool:
        return True

    def readinto(self, buffer) -> int:
        if len(self.head):
            count = min(len(buffer), len(self.head))
            part, self.head = bytes(self.head[:count]), self.head[count:]
        else:
            read = getattr(self.stream, "read1", self.stream.read)  # what has arrived: a pipe
            part = read(len(buffer))  # left open is not waited for
            part = part.encode() if isinstance(part, str) else part
        if self.text:
            _refuse_nul(part, self.name, self.offset, self.lines)
            self.lines += part.count(b"\n")
        self.offset += len(part)
        buffer[: len(part)] = part
        return len(part)


def check_text(data: bytes, name: str, piece: tuple[int, int] | None = None) -> bytes:
    """The text of a trajectory file without its byte-order mark; bytes that are not UTF-8,
    and a carriage return that ends no line feed (old Mac line ends), are errors at their
    line. ``piece``: ``data`` is a piece of a file read as it is parsed (:class:`TextStream`),
    after ``(lines, bytes)`` of it; then a NUL byte is an error too (a file read whole was
    checked for them as it was read), and a byte-order mark is one only at the file's start."""
    line, offset = piece or (0, 0)
    if piece is not None:
        _refuse_nul(data, name, offset, line)
    if data.startswith(BOM) and not offset:
        data = data[len(BOM) :]
    if not data.isascii():  # the common case needs no decoded copy
        try:
            data.decode("utf-8")
        except UnicodeDecodeError as e:
            line += data.count(b"\n", 0, e.start) + 1
            raise InputFileError(f"{name}:{line}: the file is not UTF-8 text") from None
    lone = re.search(rb"\r(?!\n)", data) if b"\r" in data else None  # a scan first: 8x faster
    if lone:
        line += data.count(b"\n", 0, lone.start()) + 1
        column = lone.start() - (data.rfind(b"\n", 0, lone.start()) + 1) + 1
        raise InputFileError(
            f"{name}:{line}:{column}: a carriage return ends no line feed (old Mac line ends?); "
            "a2b reads lines that end in LF or CR LF"
        )
    return data


def first_line(data: bytes) -> str:
    """The first line of a text (at most :data:`HEADER_BYTES` of it), without its line end."""
    end = data.find(b"\n", 0, HEADER_BYTES)
    return data[: end if end >= 0 else HEADER_BYTES].decode("utf-8", "replace").rstrip("\r")


def header_line(data: bytes, name: str) -> str:
    """The first line of a text, a header: longer than :data:`HEADER_BYTES` is an error."""
    if len(data) > HEADER_BYTES and b"\n" not in data[:HEADER_BYTES]:
        raise InputFileError(
            f"{name}:1:1: the first line, a header, is longer than {HEADER_BYTES} bytes"
        )
    return first_line(data)


@dataclass(frozen=True)
class TextLayout:
    """How to read the rows of a text trajectory: the separator (``None``: blanks), the lines
    to skip at the top (a header), the fields per row (``width``; ``None``: at least those of
    ``columns``), and ``columns``: which fields, in the order the format's reader takes them.
    ``nanoseconds``: the first of ``columns`` is a whole number of nanoseconds."""

    sep: str | None
    skip: int
    width: int | None
    columns: tuple[int, ...]
    nanoseconds: bool = False
    #: The format's name, for messages.
    fmt: str = ""


def read_rows(
    data: bytes, name: str, layout: TextLayout, offset: int = 0, skip: bool = True,
    bulk: bool = False,
):  # fmt: skip
    """The numbers of some lines of a text trajectory ``(N, len(columns))``, and their
    :class:`Lines`; ``offset`` lines of the file come before ``data``, whose first
    ``layout.skip`` lines are skipped if ``skip``. ``bulk``: ``data`` is a piece of a large
    file, which pyarrow parses where it is installed (:func:`_arrow_rows`)."""
    first = layout.skip if skip else 0
    lines = Lines(data, first, offset)
    rows = _arrow_rows(data, layout, first) if bulk else None
    if rows is not None:
        start, rows = rows
        lines.plain = start, len(rows)
        return rows, lines
    body = io.BytesIO(data)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)  # "input contained no data"
            if layout.width is None:  # only the named columns, of rows that may have more
                rows = _loadtxt(body, layout, first, usecols=layout.columns)
            else:
                rows = _loadtxt(body, layout, first)
                if rows.size == 0:
                    rows = np.empty((0, layout.width))
                if rows.shape[1] != layout.width:
                    raise ValueError
                if layout.columns != tuple(range(layout.width)):
                    rows = rows[:, layout.columns]
            if layout.nanoseconds and len(rows):
                rows[:, 0] = _seconds(data, body, layout, first)
    except ValueError:
        rows = _rows_one_by_one(lines.numbered(), name, layout)
    bad = ~np.isfinite(rows).all(axis=1)
    if bad.any():
        i = int(np.argmax(bad))
        column = layout.columns[int(np.argmax(~np.isfinite(rows[i])))]
        _raise_at(lines.numbered()[i], layout.sep, column, name, "expected a finite number")
    return rows, lines


#: Files from this many bytes are read with :func:`_arrow_rows` (``bulk``), where pyarrow's
#: import (about 0.1 s) pays for itself.
ARROW_FROM = 1 << 24

#: Bytes that a plain text, which pyarrow and ``numpy.loadtxt`` read alike, has none of.
_NOT_PLAIN = (b"#", b"\r", b"\t", b"\x0b", b"\x0c", b'"')


def _arrow_rows(data: bytes, layout: TextLayout, first: int) -> tuple | None:
    """The rows of a plain text as pyarrow's CSV reader parses them: the doubles of
    ``numpy.loadtxt`` (both round correctly), three to four times as fast, and without the GIL;
    as ``(start, rows)``, where the rows' lines start at byte ``start``.
    ``None`` where pyarrow is not installed (it comes with the ``parquet`` extra) or the text
    is not plain: other than ASCII numbers separated by one blank (or a comma) in rows of one
    width, after the ``first`` lines and the comment lines below them, with no other comment,
    no other blank and no non-finite number. Then :func:`read_rows` reads it with
    ``numpy.loadtxt``, and any error is its."""
    if layout.nanoseconds or layout.sep not in (None, ","):
        return None
    try:
        import pyarrow as pa
        import pyarrow.csv as csv
    except ImportError:
        return None
    start = 0
    for _ in range(first):
        start = data.find(b"\n", start) + 1
        if not start:
            return None
    while data.startswith(b"#", start):  # comments above the rows (a TUM header)
        start = data.find(b"\n", start) + 1
        if not start:
            return None
    body = data[start:]
    if not body.isascii() or any(byte in body for byte in _NOT_PLAIN):
        return None
    width = layout.width or max(layout.columns) + 1
    # A blank next to a blank or a line end: where every field is converted, pyarrow refuses
    # the row itself (a field too many, or an empty one, which is no double); where one is
    # not, a blank could stand in for its number. The scans cost 0.36 s for 10^6 TUM poses.
    if (
        layout.sep is None
        and len(set(layout.columns)) < width
        and (b"  " in body or b"\n " in body or b" \n" in body or body[:1] == b" "
             or body[-1:] == b" ")
    ):  # fmt: skip
        return None
    names = [f"f{k}" for k in range(width)]
    try:
        table = csv.read_csv(
            pa.py_buffer(body),
            read_options=csv.ReadOptions(column_names=names, use_threads=False),
            parse_options=csv.ParseOptions(
                delimiter=layout.sep or " ", quote_char=False, ignore_empty_lines=False
            ),  # a blank line is a row too short: not plain (then each line is one row)
            convert_options=csv.ConvertOptions(
                column_types=dict.fromkeys(names, pa.float64()),
                include_columns=[names[k] for k in layout.columns],
                null_values=[],
                strings_can_be_null=False,
            ),
        )
    except (pa.ArrowException, ValueError):  # not plain after all: a row of another width, …
        return None
    rows = np.empty((table.num_rows, table.num_columns))
    for k, column in enumerate(table.columns):
        lo = 0
        for chunk in column.chunks:  # the doubles as they are (to_numpy imports pandas)
            values = np.frombuffer(chunk.buffers()[1], dtype=np.float64)
            rows[lo : lo + len(chunk), k] = values[chunk.offset : chunk.offset + len(chunk)]
            lo += len(chunk)
    return (start, rows) if len(rows) and np.isfinite(rows).all() else None


def _loadtxt(body, layout: TextLayout, first: int, usecols=None) -> np.ndarray:
    body.seek(0)
    return np.loadtxt(
        body, delimiter=layout.sep, comments="#", ndmin=2, skiprows=first, usecols=usecols
    )


def _seconds(data: bytes, body, layout: TextLayout, first: int) -> np.ndarray:
    """The nanosecond stamps of the first column as seconds, read as integers (they exceed
    2**53)."""
    if _NOT_AN_INTEGER_STAMP.search(data):
        raise ValueError  # older numpy would truncate 1.5 to 1
    body.seek(0)
    stamps = np.loadtxt(
        body, delimiter=layout.sep, comments="#", usecols=layout.columns[0], dtype=np.int64,
        ndmin=1, skiprows=first,
    )  # fmt: skip
    seconds, nanoseconds = np.divmod(stamps, 10**9)
    return seconds + nanoseconds * 1e-9


class Lines:
    """The line number of each data row of a text, counted only when a message asks."""

    def __init__(self, data: bytes, first: int, offset: int = 0):
        self.data, self.first, self.offset = data, first, offset
        self._numbered: list | None = None
        #: ``(start, rows)`` where a plain text was parsed: its rows, one a line from byte
        #: ``start`` on (where the lines skipped and the comments at the top end).
        self.plain: tuple[int, int] | None = None

    def count(self) -> int:
        """The line ends of the text: counted, unless it is plain (then each line from
        ``start`` on is one row)."""
        data = self.data
        if self.plain is None:
            return data.count(b"\n")
        start, rows = self.plain
        return data.count(b"\n", 0, start) + rows - (not data.endswith(b"\n"))

    def numbered(self) -> list[tuple[int, str]]:
        """``(line number, line)`` of every row: not blank, not a ``#`` comment."""
        if self._numbered is None:
            self._numbered = [
                (self.offset + i + 1, line)
                for i, line in enumerate(self.data.decode("utf-8").split("\n"))
                if i >= self.first and line.strip() and not line.lstrip().startswith("#")
            ]
        return self._numbered

    def __getitem__(self, row: int) -> int:
        return self.numbered()[row][0]


def written_times(lines: Lines, layout: TextLayout):
    """``time(i)``: the time of row ``i`` as the file writes it, in seconds (for
    :func:`a2b.io.trajectory.check_times`)."""

    def time(i: int) -> str | None:
        if i < 0:
            return None
        field = _field(lines.numbered()[i][1], layout.sep, layout.columns[0])
        if not layout.nanoseconds:
            return field
        try:
            return str(Decimal(field).scaleb(-9))
        except InvalidOperation:
            return field

    return time


def _field(line: str, sep: str | None, column: int) -> str:
    parts = line.split(sep, column + 1)
    return parts[column].strip() if column < len(parts) else ""


def _fields(line: str, sep: str | None, limit: int) -> list[tuple[int, str]]:
    """The first ``limit`` fields of a line, each with the 1-based column where it starts."""
    out = []
    if sep is None:
        for m in re.finditer(r"\S+", line):
            if len(out) == limit:
                break
            out.append((m.start() + 1, m.group()))
        return out
    pos = 0
    for part in line.split(sep, limit)[:limit]:
        out.append((pos + len(part) - len(part.lstrip()) + 1, part.strip()))
        pos += len(part) + len(sep)
    return out


def _count_fields(line: str, sep: str | None) -> int:
    """The count of fields of a line, without a list of them (a line may hold millions)."""
    if sep is not None:
        return line.count(sep) + 1
    return sum(1 for _ in re.finditer(r"\S+", line))


def _raise_at(numbered: tuple[int, str], sep, column: int, name: str, message: str) -> None:
    number, line = numbered
    fields = _fields(line, sep, column + 1)
    col, token = fields[column] if column < len(fields) else (len(line) + 1, "")
    shown = token if len(token) <= 40 else token[:37] + "..."
    raise InputFileError(f"{name}:{number}:{col}: {message}, got {printable(shown)!r}")


def _rows_one_by_one(numbers: list, name: str, layout: TextLayout) -> np.ndarray:
    """The rows line by line, to locate what the bulk reading refused: the first line whose
    count of fields is wrong or whose field is no number is an error."""
    need = max(layout.columns) + 1
    rows = np.empty((len(numbers), len(layout.columns)))
    for i, numbered in enumerate(numbers):
        count = _count_fields(numbered[1], layout.sep)
        if count != layout.width and (layout.width is not None or count < need):
            expected = (
                f"{layout.width} number{'s' * (layout.width != 1)}"
                if layout.width
                else f"at least {need} fields"
            )
            raise InputFileError(
                f"{name}:{numbered[0]}:1: expected {expected} per line ({layout.fmt}), got {count}"
            )
        fields = _fields(numbered[1], layout.sep, need)
        for k, column in enumerate(layout.columns):
            token = fields[column][1]
            if k == 0 and layout.nanoseconds:
                if not re.fullmatch(r"[-+]?[0-9]+", token):
                    _raise_at(
                        numbered, layout.sep, column, name, "expected a whole number of nanoseconds"
                    )
                seconds, nanoseconds = divmod(int(token), 10**9)
                rows[i, k] = seconds + nanoseconds * 1e-9
                continue
            if not NUMBER.fullmatch(token):
                _raise_at(numbered, layout.sep, column, name, "expected a number")
            rows[i, k] = float(token)
    return rows


# -- headers that name their columns ------------------------------------------------------------

#: What a column's name says, after its unit (``[m]``), a leading ``#`` and the case are
#: dropped: spellings of the time, the position and the orientation quaternion in the CSV
#: files of a2b, EuRoC and common exports.
_ROLES = {
    **{k: "t" for k in ("t", "time", "timestamp", "stamp")},
    **{
        f"{prefix}{axis}": f"t{axis}"
        for axis in "xyz"
        for prefix in ("t", "", "p", "p_", "p_rs_r_", "pos_", "position_", "position.", "t_")
    },
    **{
        f"{prefix}{axis}": f"q{axis}"
        for axis in "wxyz"
        for prefix in ("q", "q_", "q_rs_", "quat_", "orientation_", "orientation.", "rot_")
    },
}
#: Columns a2b writes after a pose: velocities (``--velocities``) and ``original`` (``--mark``).
EXTRA_COLUMNS = ("vx", "vy", "vz", "wx", "wy", "wz", "original")
#: Columns of EuRoC's ground truth besides the pose: velocities and biases, not read.
_IGNORED = re.compile(r"(?:v_rs_r_|b_w_rs_s_|b_a_rs_s_)[xyz]")


def role(column: str) -> str:
    """What a column's name says: ``tx`` for ``p_RS_R_x [m]``; a name it does not know."""
    text = re.sub(r"\[[^\]]*\]", "", column).strip().lstrip("#").strip().lower()
    return _ROLES.get(text, text)


def named_layout(head: str, name: str, fmt: str, needed: tuple, nanoseconds: bool) -> TextLayout:
    """The layout of a comma-separated text whose first line names its columns: the columns of
    ``needed`` (roles, e.g. ``t, tx, …``) found by their names, in that order.

    Names a2b writes after a pose (:data:`EXTRA_COLUMNS`) and EuRoC's velocity and bias
    columns are allowed and not read; any other name, and a missing one, is an error naming
    them. The time is in nanoseconds if its name says ``[ns]``, else if ``nanoseconds``.
    """
    columns = [c.strip() for c in head.split(",")]
    roles = [role(c) for c in columns]
    unknown = [
        c for c, r in zip(columns, roles) if r not in needed and r not in EXTRA_COLUMNS
        and not _IGNORED.fullmatch(r)
    ]  # fmt: skip
    missing = [r for r in needed if r not in roles]
    repeated = sorted({r for r in roles if r in needed and roles.count(r) > 1})
    problems = []
    if unknown:
        problems.append(f"unknown column{'s' * (len(unknown) > 1)} {_few(unknown)}")
    if missing:
        problems.append(f"no column for {_few(missing)}")
    if repeated:
        problems.append(f"more than one column for {_few(repeated)}")
    if problems:
        raise InputFileError(
            f"{name}:1:1: the header of this {fmt} file names its columns, and a2b reads them "
            f"by name: {'; '.join(problems)} (expected {', '.join(needed)}, optionally "
            f"{', '.join(EXTRA_COLUMNS)})"
        )
    time = columns[roles.index(needed[0])]
    ns = "[ns]" in time.replace(" ", "").lower() or (nanoseconds and "[s]" not in time)
    ignored = any(_IGNORED.fullmatch(r) for r in roles)
    at = tuple(roles.index(r) for r in needed)
    return TextLayout(",", 1, None if ignored else len(columns), at, ns, fmt)


# -- a list of times ------------------------------------------------------------------------------


def read_times(stream: IO, name: str | None = None) -> np.ndarray:
    """Read a list of times: one number of seconds per line, increasing; ``#`` starts a
    comment. Memory stays bounded by the bytes of the file (``/dev/zero`` is refused at
    once); an error names the line.

    Raises
    ------
    InputFileError
    """
    from .trajectory import check_times

    name = stream_name(stream, name)
    data = check_text(read_text_bytes(stream, name), name)
    layout = TextLayout(None, 0, 1, (0,), fmt="times")
    times, lines = read_rows(data, name, layout)
    times = times[:, 0]
    if not len(times):
        raise InputFileError(f"{name}: no times")
    check_times(times, name, lines, written=written_times(lines, layout))
    return times
