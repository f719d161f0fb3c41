"""a2b's CSV layouts: ``csv``, ``matrix`` and ``study``, and the batch CSV with a job column.

=======  ===========================================  =====================================
layout   header                                        after the pose (when written)
=======  ===========================================  =====================================
csv      ``t,tx,ty,tz,qw,qx,qy,qz``                    ``vx,vy,vz,wx,wy,wz`` (``--velocities``),
matrix   ``t,r11,r12,r13,tx,r21,…,r33,tz``             ``original`` (``--mark``)
study    ``t,p0,p1,p2,p3,q0,q1,q2,q3``
=======  ===========================================  =====================================

The header names the columns, and they are read by their names, in any order
(:func:`a2b.io.textrows.named_layout`): a CSV of another tool that writes
``#timestamp,tx,ty,tz,qx,qy,qz,qw`` is read as it says, not as a2b would have written it.
"""

from __future__ import annotations

import io
from typing import IO

import numpy as np

from ..errors import A2bError, InputFileError, printable
from ..formats import BY_NAME, TABLE
from .textrows import NUMBER, TextLayout, header_line, named_layout, role
from .trajectory import Trajectory, from_matrices, from_quaternions

__all__ = [
    "CSV_HEADER",
    "MATRIX_HEADER",
    "STUDY_HEADER",
    "fmt_from_header",
    "layout",
    "read_batch_csv",
    "trajectory",
]

#: The headers of the three layouts this module reads, from the table of formats.
CSV_HEADER = BY_NAME["csv"].header
MATRIX_HEADER = BY_NAME["matrix"].header
STUDY_HEADER = BY_NAME["study"].header
#: The columns of each layout, in the order its reader takes them; the widest first, as
#: :func:`fmt_from_header` tries them (a csv header's columns are also a matrix header's).
COLUMNS = {
    row.name: tuple(row.header.split(","))
    for row in sorted(TABLE, key=lambda row: -len(row.header or ""))
    if row.trajectory == __name__
}


def fmt_from_header(head: str) -> str | None:
    """The layout whose columns a header line names (in any order), else ``None``."""
    if "," not in head:
        return None
    roles = {role(column.strip()) for column in head.split(",")}
    for fmt, columns in COLUMNS.items():
        if roles.issuperset(columns):
            return fmt
    return None


def layout(data: bytes, name: str, fmt: str) -> TextLayout:
    """The layout the header line names."""
    head = header_line(data, name)
    if not head.strip() or all(NUMBER.fullmatch(f.strip()) for f in head.split(",")):
        got = "an empty file" if not data.strip() else f"'{printable(head[:80])}'"
        raise InputFileError(
            f"{name}:1:1: expected the {fmt} header {','.join(COLUMNS[fmt])!r}, got {got}"
        )
    if role(head.split(",")[0]) == "job":
        raise InputFileError(
            f"{name}:1:1: a batch CSV (its first column is 'job'): read it with "
            "a2b.io.csvtable.read_batch_csv, or write one file per job (a2b batch -o DIR/)"
        )
    return named_layout(head, name, fmt, COLUMNS[fmt], nanoseconds=False)


def trajectory(rows, lines, name: str, fmt: str, rate, orthonormalize, row: int) -> Trajectory:
    """The poses of rows in the order of :data:`COLUMNS` ``[fmt]``."""
    times = rows[:, 0]
    if fmt == "csv":
        return from_quaternions(times, rows[:, 4:8], rows[:, 1:4], name, fmt, lines)
    if fmt == "matrix":
        return from_matrices(times, rows[:, 1:13], lines, name, fmt, orthonormalize)
    from ..poses import matrices_from_study

    study = np.ascontiguousarray(rows[:, 1:9])
    try:
        matrices = matrices_from_study(study)
    except A2bError:
        for i in range(len(study)):  # the first failing row, for its line
            try:
                matrices_from_study(study[i])
            except A2bError as e:
                raise InputFileError(f"{name}:{lines[i]}:1: {e}") from None
        raise
    return Trajectory(times, study=study, name=name, fmt=fmt, _matrices=matrices)


def _text_stream(stream: IO):
    if isinstance(stream, io.TextIOBase):
        return stream
    return io.TextIOWrapper(stream, encoding="utf-8", newline="")


def read_batch_csv(stream: IO, name: str = "batch csv") -> tuple[list[str], np.ndarray]:
    """Read ``a2b batch`` output: the ``job`` column and the remaining columns as floats.

    Raises
    ------
    InputFileError
        For a file that is no batch CSV, at the line of the first problem.
    """
    import csv

    reader = csv.reader(_text_stream(stream))
    try:
        header = next(reader, [""])
        if header[0] != "job":
            raise InputFileError(f"{name}:1:1: the first column must be 'job'")
        jobs, values = [], []
        for row in reader:
            if len(row) != len(header):
                raise InputFileError(
                    f"{name}:{reader.line_num}: expected {len(header)} fields, got {len(row)}"
                )
            jobs.append(row[0])
            values.append([_finite(x, name, reader.line_num) for x in row[1:]])
    except (csv.Error, UnicodeDecodeError) as e:
        raise InputFileError(f"{name}:{reader.line_num + 1}: not a batch CSV ({e})") from None
    return jobs, np.array(values, dtype=float).reshape(len(values), len(header) - 1)


def _finite(text: str, name: str, line: int) -> float:
    try:
        value = float(text)
    except ValueError:
        value = float("nan")
    if not np.isfinite(value):
        raise InputFileError(
            f"{name}:{line}: expected a finite number, got '{printable(text[:40])}'"
        )
    return value
