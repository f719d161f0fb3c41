"""Trajectories in: the pose sequences users store, read as times and poses.

=======  ================================================================  ======================
format   layout                                                            times
=======  ================================================================  ======================
tum      ``time tx ty tz qx qy qz qw``, space-separated, ``#`` comments    seconds
kitti    12 numbers of ``[R | t]`` row by row per line                     none: the line index,
                                                                           or ``rate`` Hz
euroc    ``#timestamp [ns],p_x,p_y,p_z,q_w,q_x,q_y,q_z[,more]``            nanoseconds (integers)
csv      a2b's ``t,tx,ty,tz,qw,qx,qy,qz``                                  the ``t`` column
matrix   a2b's ``t,r11,r12,r13,tx,r21,…,tz``                               the ``t`` column
study    a2b's ``t,p0,p1,p2,p3,q0,q1,q2,q3``                               the ``t`` column
mcap     ``foxglove.PoseInFrame`` or ``foxglove.FrameTransform`` (JSON);   the message stamps
         ROS 2 ``PoseStamped``, ``TFMessage``, ``Odometry``, ``Path`` (CDR)
=======  ================================================================  ======================

The format comes from the caller, else the file's suffix (``.tum``, ``.kitti``, ``.mcap``),
else the content: an MCAP magic, one of a2b's CSV headers, a EuRoC ``#timestamp`` header, or
lines of 8 (TUM) or 12 (KITTI) numbers. Every pose is checked as in a pose file; times must
increase. A problem is one :class:`InputFileError` that starts ``FILE:LINE:COLUMN:``.

What a writer of :mod:`a2b.io.writers` wrote reads back bit for bit: ``quat_wxyz``, ``study``
and the matrices' entries are the numbers of the file as they stand (quaternions are not
normalised here; the matrices of a quaternion file are built from the normalised ones).
"""

from __future__ import annotations

import io
import os
import re
import warnings
from collections.abc import Iterator
from dataclasses import dataclass
from typing import IO

import numpy as np

from ..errors import A2bError, InputFileError
from .jobscan import stream_name
from .mcapposes import mcap_poses

__all__ = [
    "CSV_HEADER",
    "MATRIX_HEADER",
    "STUDY_HEADER",
    "TRAJECTORY_FORMATS",
    "Trajectory",
    "read_csv",
    "read_kitti",
    "read_matrix_csv",
    "read_study_csv",
    "opened",
    "read_trajectory",
    "read_tum",
    "sniff_format",
    "trajectory_pieces",
]

TRAJECTORY_FORMATS = ("tum", "kitti", "euroc", "csv", "matrix", "study", "mcap")
CSV_HEADER = "t,tx,ty,tz,qw,qx,qy,qz"
MATRIX_HEADER = "t,r11,r12,r13,tx,r21,r22,r23,ty,r31,r32,r33,tz"
STUDY_HEADER = "t,p0,p1,p2,p3,q0,q1,q2,q3"
_HEADERS = {"csv": CSV_HEADER, "matrix": MATRIX_HEADER, "study": STUDY_HEADER}
#: Columns of the poses in each text format (after the time, where there is one).
_COLUMNS = {"tum": 8, "kitti": 12, "euroc": 8, "csv": 8, "matrix": 13, "study": 9}
_SUFFIXES = {".tum": "tum", ".kitti": "kitti", ".mcap": "mcap"}
MCAP_MAGIC = b"\x89MCAP0\r\n"


@dataclass
class Trajectory:
    """Poses in time: ``times (N,)`` increasing seconds (for KITTI without a rate, the indices)
    and the numbers as the file holds them: ``quat_wxyz (N, 4)`` and ``trans (N, 3)`` for
    quaternion formats, ``study (N, 8)`` for study. :attr:`matrices` are the robotics
    matrices ``(N, 4, 4)``, built from the normalised quaternions when first asked for."""

    times: np.ndarray
    quat_wxyz: np.ndarray | None = None
    trans: np.ndarray | None = None
    study: np.ndarray | None = None
    name: str = "<trajectory>"
    fmt: str = ""
    #: With ``orthonormalize``: the largest ``max |R Rᵀ − I|`` repaired.
    repaired: float | None = None
    _matrices: np.ndarray | None = None

    @property
    def matrices(self) -> np.ndarray:
        if self._matrices is None:
            from ..poses import matrices_from_quat_trans

            out = np.empty((len(self.times), 4, 4))
            for lo in range(0, len(out), BLOCK):  # small temporaries for any length
                part = slice(lo, lo + BLOCK)
                out[part] = matrices_from_quat_trans(self.quat_wxyz[part], self.trans[part])
            self._matrices = out
        return self._matrices

    @property
    def translations(self) -> np.ndarray:
        return self.trans if self.trans is not None else self.matrices[:, :3, 3]

    def __len__(self) -> int:
        return len(self.times)


def read_trajectory(
    stream: IO,
    name: str | None = None,
    fmt: str | None = None,
    *,
    rate: float | None = None,
    topic: str | None = None,
    child_frame: str | None = None,
    orthonormalize: bool = False,
    minimum: int = 1,
) -> Trajectory:
    """Read a trajectory file (see the module's table) from a binary ``stream``.

    ``rate`` gives KITTI poses the times ``i / rate``; ``topic`` picks the MCAP topic when the
    file has several, and ``child_frame`` the transforms of a ROS 2 ``/tf`` topic when they go
    to several frames; ``orthonormalize`` repairs rotation blocks that are orthogonal only to a
    few digits (:func:`a2b.poses.orthonormalize`); ``minimum`` is the fewest poses accepted.
    """
    name, data, fmt = opened(stream, name, fmt)
    pieces = list(trajectory_pieces(data, name, fmt, rate=rate, topic=topic,
                                    child_frame=child_frame,
                                    orthonormalize=orthonormalize))  # fmt: skip
    trajectory = _joined(pieces, name, fmt)
    if len(trajectory) < minimum:
        raise InputFileError(
            f"{name}: expected at least {minimum} pose{'s' * (minimum != 1)}, got {len(trajectory)}"
        )
    return trajectory


def opened(stream: IO, name: str | None = None, fmt: str | None = None) -> tuple:
    """``(name, bytes, format)`` of a trajectory file: its name for messages, its content, and
    its format (given, else from the suffix or the content: :func:`sniff_format`)."""
    name = stream_name(stream, name)
    data = stream.read()
    if isinstance(data, str):
        data = data.encode()
    fmt = fmt or sniff_format(data, name)
    if fmt not in TRAJECTORY_FORMATS:
        raise InputFileError(f"{name}: unknown trajectory format {fmt!r}")
    return name, data, fmt


#: Bytes of text parsed at a time by :func:`trajectory_pieces`.
PIECE_BYTES = 1 << 22


def trajectory_pieces(
    data: bytes,
    name: str,
    fmt: str,
    *,
    rate: float | None = None,
    topic: str | None = None,
    child_frame: str | None = None,
    orthonormalize: bool = False,
    size: int = PIECE_BYTES,
) -> Iterator[Trajectory]:
    """The poses of a trajectory file's content, in consecutive pieces of about ``size`` bytes
    of text (MCAP: one piece), each checked as it is read; times increase across pieces too.

    A reader can start on the first poses while the rest is still text: ``a2b resample``
    computes the first segments while the file is parsed.
    """
    if fmt == "mcap":
        times, quat, trans = mcap_poses(data, name, topic, child_frame)
        piece = _from_quaternions(times, quat, trans, name, fmt, None)
        _check_times(piece.times, name, None)
        yield piece
        return
    skip, marked = _header(data, name, fmt)
    start, line, row, previous = 0, 0, 0, None
    while start < len(data):
        stop = data.find(b"\n", start + size) + 1 if len(data) - start > size else 0
        stop = stop or len(data)
        text = data[start:stop]
        table, lines = _table(text, name, fmt, skip if start == 0 else 0, marked, line)
        piece = _from_table(table, lines, name, fmt, rate, orthonormalize, row)
        _check_times(piece.times, name, lines, previous)
        if len(piece):
            yield piece
            previous = piece.times[-1]
        start, line, row = stop, line + text.count(b"\n"), row + len(piece)


def _joined(pieces: list, name: str, fmt: str) -> Trajectory:
    """One trajectory of consecutive pieces."""
    if len(pieces) == 1:
        return pieces[0]
    if not pieces:
        return Trajectory(np.empty(0), name=name, fmt=fmt, _matrices=np.empty((0, 4, 4)))

    def joined(field):
        parts = [getattr(p, field) for p in pieces]
        return None if parts[0] is None else np.concatenate(parts)

    repaired = [p.repaired for p in pieces if p.repaired is not None]
    return Trajectory(
        joined("times"),
        quat_wxyz=joined("quat_wxyz"),
        trans=joined("trans"),
        study=joined("study"),
        name=name,
        fmt=fmt,
        repaired=max(repaired) if repaired else None,
        _matrices=joined("_matrices"),
    )


def sniff_format(data: bytes, name: str) -> str:
    """The trajectory format of a file's content: from its suffix, else its content.

    Raises
    ------
    InputFileError
        If neither tells (the file is no trajectory).
    """
    by_suffix = _SUFFIXES.get(os.path.splitext(name)[1].lower())
    if by_suffix:
        return by_suffix
    if data.startswith(MCAP_MAGIC):
        return "mcap"
    head = data[:4096].decode("utf-8", "replace").splitlines()
    first = head[0].strip() if head else ""
    for fmt, header in _HEADERS.items():
        if first == header:
            return fmt
    if first.startswith("#") and "," in first and "timestamp" in first.lower():
        return "euroc"
    for line in head:
        if line.strip() and not line.lstrip().startswith("#"):
            count = len(line.replace(",", " ").split())
            if count == 8 and "," not in line:
                return "tum"
            if count == 12:
                return "kitti"
            break
    hint = ""
    if any(key in data[:65536] for key in (b"start", b"controls", b"poses")):
        hint = " (a pose file? a2b interpolate, bezier and spline read those)"
    raise InputFileError(
        f"{name}: cannot tell the trajectory format (expected TUM, KITTI, EuRoC, a2b's csv, "
        f"matrix or study, or MCAP); give it with --input-format{hint}"
    )


# -- text formats ------------------------------------------------------------------------------


def _header(data: bytes, name: str, fmt: str) -> tuple[int, bool]:
    """Check the text and the first line of a trajectory file: ``(lines to skip, whether a2b's
    ``original`` column follows the pose columns)``."""
    if not data.isascii():  # the common case needs no decoded copy
        try:
            data.decode("utf-8")
        except UnicodeDecodeError as e:
            line = data.count(b"\n", 0, e.start) + 1
            raise InputFileError(f"{name}:{line}: the file is not UTF-8 text") from None
    head = data[: data.find(b"\n") if b"\n" in data[:65536] else 65536].decode("utf-8", "replace")
    head = head.rstrip("\r")
    if fmt in _HEADERS:
        marked = head.strip() == _HEADERS[fmt] + ",original"
        if head.strip() != _HEADERS[fmt] and not marked:
            got = repr(head[:80]) if data else "an empty file"
            raise InputFileError(
                f"{name}:1:1: expected the {fmt} header {_HEADERS[fmt]!r}, got {got}"
            )
        return 1, marked
    if fmt == "euroc":
        if not head.startswith("#"):
            raise InputFileError(f"{name}:1:1: expected EuRoC's '#timestamp [ns],…' header line")
        return 1, False
    return 0, False


def _table(
    data: bytes, name: str, fmt: str, first: int, marked: bool, offset: int
) -> tuple[np.ndarray, _Lines]:
    """The numbers of some lines of a text trajectory ``(N, columns)`` and the line of each row.

    ``first`` lines are skipped (a header); ``offset`` lines of the file come before ``data``.
    The numbers are parsed in bulk by ``numpy.loadtxt``; only when that fails, or a check
    needs the line of a row for its message, are the lines numbered one by one.
    """
    lines = _Lines(data, first, offset)
    sep = "," if fmt in _HEADERS or fmt == "euroc" else None
    width = _COLUMNS[fmt] + marked  # a2b resample's original column
    body = io.BytesIO(data)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", UserWarning)  # "input contained no data"
            if fmt == "euroc":  # nanosecond stamps exceed 2**53: read them as integers
                if _NOT_AN_INTEGER_STAMP.search(data):
                    raise ValueError  # older numpy would truncate 1.5 to 1
                stamps = np.loadtxt(
                    body, delimiter=",", usecols=0, dtype=np.int64, ndmin=1, skiprows=first
                )
                body.seek(0)
                rows = np.loadtxt(body, delimiter=",", usecols=range(8), ndmin=2, skiprows=first)
                seconds, nanoseconds = np.divmod(stamps, 10**9)
                rows[:, 0] = seconds + nanoseconds * 1e-9
            else:
                rows = np.loadtxt(body, delimiter=sep, comments="#", ndmin=2, skiprows=first)
        if rows.size == 0:
            rows = np.empty((0, width))
        if rows.shape[1] != width:
            raise ValueError
    except ValueError:
        if fmt == "euroc":
            return _euroc(lines.numbered(), name), lines
        _locate_bad_number(lines.numbered(), sep, width, name, fmt)
        raise  # pragma: no cover - _locate_bad_number raises
    bad = ~np.isfinite(rows).all(axis=1)
    if bad.any():
        i = int(np.argmax(bad))
        column = int(np.argmax(~np.isfinite(rows[i])))
        _raise_at(lines.numbered()[i], sep, column, name, "expected a finite number")
    return rows, lines


#: A number as numpy's text reader takes it (``nan`` and ``inf`` are then refused as such).
_NUMBER = re.compile(
    r"[-+]?(?:(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][-+]?[0-9]+)?|nan|inf(?:inity)?)", re.I
)
#: A EuRoC line whose first field is more than an optional sign and digits.
_NOT_AN_INTEGER_STAMP = re.compile(rb"(?m)^(?![ \t]*#)[ \t]*[+-]?[0-9]*[^0-9,\r\n]")


class _Lines:
    """The line number of each data row of a text, counted only when a message asks."""

    def __init__(self, data: bytes, first: int, offset: int = 0):
        self.data, self.first, self.offset = data, first, offset
        self._numbered: list | None = None

    def numbered(self) -> list[tuple[int, str]]:
        """``(line number, line)`` of every row: not blank, not a ``#`` comment."""
        if self._numbered is None:
            self._numbered = [
                (self.offset + i + 1, line)
                for i, line in enumerate(self.data.decode("utf-8").splitlines())
                if i >= self.first and line.strip() and not line.lstrip().startswith("#")
            ]
        return self._numbered

    def __getitem__(self, row: int) -> int:
        return self.numbered()[row][0]


def _fields(line: str, sep: str | None) -> list[tuple[int, str]]:
    """The fields of a line, each with the 1-based column where it starts."""
    if sep is None:
        return [(m.start() + 1, m.group()) for m in re.finditer(r"\S+", line)]
    out, pos = [], 0
    for part in line.split(sep):
        out.append((pos + len(part) - len(part.lstrip()) + 1, part.strip()))
        pos += len(part) + len(sep)
    return out


def _raise_at(numbered: tuple[int, str], sep, column: int, name: str, message: str) -> None:
    number, line = numbered
    fields = _fields(line, sep)
    col, token = fields[column] if column < len(fields) else (len(line) + 1, "")
    shown = token if len(token) <= 40 else token[:37] + "..."
    raise InputFileError(f"{name}:{number}:{col}: {message}, got {shown!r}")


def _locate_bad_number(numbers: list, sep, width: int, name: str, fmt: str) -> None:
    """Raise for the first line that is not ``width`` finite numbers."""
    for numbered in numbers:
        fields = _fields(numbered[1], sep)
        if len(fields) != width:
            raise InputFileError(
                f"{name}:{numbered[0]}:1: expected {width} numbers per line ({fmt}), got "
                f"{len(fields)}"
            )
        for column, (_, token) in enumerate(fields):
            if not _NUMBER.fullmatch(token):
                _raise_at(numbered, sep, column, name, "expected a number")
    raise InputFileError(f"{name}: cannot read the numbers of this {fmt} file")


def _euroc(numbers: list, name: str) -> np.ndarray:
    """EuRoC rows line by line, to locate what the bulk reading refused."""
    rows = np.empty((len(numbers), 8))
    for i, numbered in enumerate(numbers):
        fields = _fields(numbered[1], ",")
        if len(fields) < 8:
            raise InputFileError(
                f"{name}:{numbered[0]}:1: expected at least 8 fields (timestamp [ns], p_x, p_y, "
                f"p_z, q_w, q_x, q_y, q_z), got {len(fields)}"
            )
        try:
            stamp = int(fields[0][1])
        except ValueError:
            _raise_at(numbered, ",", 0, name, "expected a whole number of nanoseconds")
        seconds, nanoseconds = divmod(stamp, 10**9)
        rows[i, 0] = seconds + nanoseconds * 1e-9
        for column in range(1, 8):
            try:
                rows[i, column] = float(fields[column][1])
            except ValueError:
                _raise_at(numbered, ",", column, name, "expected a number")
        if not np.isfinite(rows[i]).all():
            column = int(np.argmax(~np.isfinite(rows[i])))
            _raise_at(numbered, ",", column, name, "expected a finite number")
    return rows


def _from_table(table, lines, name, fmt, rate, orthonormalize, row: int = 0) -> Trajectory:
    if fmt == "kitti":  # the index in the file (``row`` poses came before these)
        times = np.arange(row, row + len(table), dtype=float)
        if rate is not None:
            times /= rate
        return _from_matrices(times, table, lines, name, fmt, orthonormalize)
    times = table[:, 0]
    if fmt == "tum":
        return _from_quaternions(times, table[:, [7, 4, 5, 6]], table[:, 1:4], name, fmt, lines)
    if fmt in ("csv", "euroc"):
        return _from_quaternions(times, table[:, 4:8], table[:, 1:4], name, fmt, lines)
    if fmt == "matrix":
        return _from_matrices(times, table[:, 1:13], lines, name, fmt, orthonormalize)
    from ..poses import matrices_from_study

    study = table[:, 1:9]
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


#: Poses converted at a time: the temporaries of a block stay small for any file.
BLOCK = 65536


def _from_quaternions(times, quat, trans, name, fmt, lines) -> Trajectory:
    quat, trans = np.ascontiguousarray(quat), np.ascontiguousarray(trans)
    bad = ~(np.einsum("ij,ij->i", quat, quat) > 0.0)
    if bad.any():
        i = int(np.argmax(bad))
        where = f"{name}:{lines[i]}:1" if lines is not None else f"{name}: message {i + 1}"
        raise InputFileError(f"{where}: the quaternion is zero; a rotation needs a non-zero one")
    return Trajectory(times, quat_wxyz=quat, trans=trans, name=name, fmt=fmt)


def _from_matrices(times, rows, lines, name, fmt, orthonormalize) -> Trajectory:
    from ..poses import ORTHO_TOL, REPAIR_TOL, determinants, orthogonality_residuals
    from ..poses import orthonormalize as project

    matrices = np.zeros((len(rows), 4, 4))
    matrices[:, :3, :] = rows.reshape(-1, 3, 4)
    matrices[:, 3, 3] = 1.0
    rotations = matrices[:, :3, :3]
    residual = orthogonality_residuals(rotations)
    tol = REPAIR_TOL if orthonormalize else ORTHO_TOL
    bad = ~(residual <= tol) | (determinants(rotations) < 0)
    if bad.any():
        i = int(np.argmax(bad))
        if determinants(rotations[i]) < 0:
            message = "the rotation block is a reflection (det R < 0), not a rotation"
        else:
            message = (
                f"the rotation block is not orthogonal: max |R Rᵀ − I| = {residual[i]:.3g} "
                f"exceeds tolerance {tol:g}"
            )
            if not orthonormalize and residual[i] <= REPAIR_TOL:
                message += (
                    "; if the file rounds its rotations to a few digits, --orthonormalize "
                    f"projects each onto the nearest rotation (up to {REPAIR_TOL:g})"
                )
        raise InputFileError(f"{name}:{lines[i]}:1: {message}")
    trajectory = Trajectory(times, name=name, fmt=fmt, _matrices=matrices)
    if orthonormalize:
        trajectory.repaired = float(residual.max(initial=0.0))
        trajectory._matrices = project(matrices)
    return trajectory


def _check_times(times: np.ndarray, name: str, lines, previous: float | None = None) -> None:
    """Times must increase (``previous``: the time before the first of these)."""
    before = np.concatenate([[previous], times]) if previous is not None else times
    steps = np.diff(before)
    bad = ~(steps > 0.0)
    if bad.any():
        i = int(np.argmax(bad)) + 1
        what = "repeats" if steps[i - 1] == 0.0 else "goes back from"
        row = i - (previous is not None)  # the row of these times
        where = f"{name}:{lines[row]}:1" if lines is not None else f"{name}: message {row + 1}"
        raise InputFileError(
            f"{where}: the time {float(before[i])!r} {what} the previous one, "
            f"{float(before[i - 1])!r}; "
            "times must increase (sort the file, or drop the repeated pose)"
        )


# -- the layouts of the writers, for tests and scripts ------------------------------------------


def read_csv(stream: IO) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Read ``csv`` output: ``t (N,)``, ``quat_wxyz (N, 4)``, ``translations (N, 3)``."""
    tr = read_trajectory(stream, fmt="csv", minimum=0)
    return tr.times, tr.quat_wxyz, tr.translations


def read_matrix_csv(stream: IO) -> tuple[np.ndarray, np.ndarray]:
    """Read ``matrix`` output: ``t (N,)`` and robotics matrices ``(N, 4, 4)``."""
    tr = read_trajectory(stream, fmt="matrix", minimum=0)
    return tr.times, tr.matrices


def read_study_csv(stream: IO) -> tuple[np.ndarray, np.ndarray]:
    """Read ``study`` output: ``t (N,)`` and Study parameters ``(N, 8)``."""
    tr = read_trajectory(stream, fmt="study", minimum=0)
    return tr.times, tr.study


def read_tum(stream: IO) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Read TUM: ``time``, ``quat_wxyz`` (rolled from xyzw here) and ``translations``."""
    tr = read_trajectory(stream, fmt="tum", minimum=0)
    return tr.times, tr.quat_wxyz, tr.translations


def read_kitti(stream: IO) -> np.ndarray:
    """Read KITTI poses: matrices ``(N, 4, 4)``."""
    return read_trajectory(stream, fmt="kitti", minimum=0).matrices
