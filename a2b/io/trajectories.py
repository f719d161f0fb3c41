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

Each text format is a module (:mod:`a2b.io.tum`, :mod:`a2b.io.kitti`, :mod:`a2b.io.euroc`,
:mod:`a2b.io.csvtable`) with a ``layout`` of its rows and a ``trajectory`` of them; this module
picks the format and hands the text to it in pieces. The format comes from the caller, else
the file's suffix (``.tum``, ``.kitti``, ``.mcap``), else the content: an MCAP magic, a header
that names the columns of a2b's CSV layouts (in any order), a EuRoC ``#timestamp`` header, or
lines of 8 (TUM) or 12 (KITTI) numbers. Columns are read by the names a header gives them.
Every pose is checked as in a pose file; times must increase. A problem is one
:class:`InputFileError` that starts ``FILE:LINE:COLUMN:``; an option that does not apply to
the format is an error too.

What a writer of :mod:`a2b.io.writers` wrote reads back bit for bit: ``quat_wxyz``, ``study``
and the matrices' entries are the numbers of the file as they stand (quaternions are not
normalised here; the matrices of a quaternion file are built from the normalised ones).
"""

from __future__ import annotations

import importlib
import os
from collections.abc import Iterator
from typing import IO

import numpy as np

from ..errors import InputFileError, printable
from ..formats import BY_NAME, INPUT_NAMES, SUFFIXES, TABLE
from .csvtable import CSV_HEADER, MATRIX_HEADER, STUDY_HEADER, fmt_from_header
from .documents import stream_name
from .mcapposes import mcap_poses, mcap_tf_poses
from .mcapreader import MAGIC
from .textrows import (
    BOM,
    check_text,
    first_line,
    read_rows,
    read_text_bytes,
    whole_file,
    written_times,
)
from .trajectory import Trajectory, check_times, from_quaternions, joined

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

#: The trajectory formats and their readers come from the table of formats
#: (:attr:`a2b.formats.Format.trajectory`): a text format's module has ``layout(data, name,
#: fmt)`` and ``trajectory(rows, lines, name, fmt, rate, orthonormalize, row)``; MCAP is read
#: by :func:`a2b.io.mcapposes.mcap_poses`.
TRAJECTORY_FORMATS = INPUT_NAMES
#: The options of :func:`read_trajectory` that some formats take
#: (:attr:`a2b.formats.Format.input_options`): keyword -> (the command line's option, what
#: it is for).
INPUT_OPTIONS = {
    "rate": ("--input-rate", "the times of poses that have none"),
    "topic": ("--topic", "the topic of an MCAP file"),
    "child_frame": ("--input-child-frame", "the frame of an MCAP /tf topic"),
    "input_frame": ("--input-frame", "the parent frame of a TF chain"),
}
#: Bytes read to tell the format before the rest.
HEAD_BYTES = 1 << 16


def read_trajectory(
    stream: IO,
    name: str | None = None,
    fmt: str | None = None,
    *,
    rate: float | None = None,
    topic: str | None = None,
    child_frame: str | None = None,
    input_frame: str | None = None,
    mode: str = "screw",
    orthonormalize: bool = False,
    minimum: int = 1,
) -> Trajectory:
    """Read a trajectory file (see the module's table) from a binary ``stream``.

    ``rate`` gives KITTI poses the times ``i / rate``; ``topic`` picks the MCAP topic when the
    file has several, and ``child_frame`` the transforms of a ROS 2 ``/tf`` topic when they go
    to several frames; ``input_frame`` with ``child_frame`` composes the pose of
    ``child_frame`` in ``input_frame`` through the TF tree of ``/tf`` and ``/tf_static``, each
    dynamic link interpolated by ``mode`` (:func:`a2b.io.mcapposes.mcap_tf_poses`; the chain
    is stated in :attr:`Trajectory.notes`); ``orthonormalize`` repairs rotation blocks that
    are orthogonal only to a few digits (:func:`a2b.poses.orthonormalize`); ``minimum`` is the
    fewest poses accepted.

    Raises
    ------
    InputFileError
        For a malformed file, and for ``rate``, ``topic`` or ``child_frame`` given for a
        format they do not apply to (:data:`INPUT_OPTIONS`).
    """
    name, data, fmt = opened(stream, name, fmt)
    pieces = list(trajectory_pieces(data, name, fmt, rate=rate, topic=topic,
                                    child_frame=child_frame, input_frame=input_frame,
                                    mode=mode, orthonormalize=orthonormalize))  # fmt: skip
    trajectory = joined(pieces, name, fmt)
    if len(trajectory) < minimum:
        raise InputFileError(
            f"{name}: expected at least {minimum} pose{'s' * (minimum != 1)}, got {len(trajectory)}"
        )
    return trajectory


def check_input_options(name: str, fmt: str, **given) -> None:
    """Refuse an option of :data:`INPUT_OPTIONS` given for a format it does not apply to."""
    for key, value in given.items():
        option, purpose = INPUT_OPTIONS[key]
        if value is not None and key not in BY_NAME[fmt].input_options:
            takes = [row.name for row in TABLE if key in row.input_options]
            raise InputFileError(
                f"{name}: {option} does not apply to {fmt} input; it gives {purpose} "
                f"({', '.join(takes)} only)"
            )


def opened(stream: IO, name: str | None = None, fmt: str | None = None) -> tuple:
    """``(name, bytes, format)`` of a trajectory file: its name for messages, its content, and
    its format (given, else from the suffix or the content: :func:`sniff_format`).

    The format is told from the first :data:`HEAD_BYTES`; then the rest is read, a text file's
    with every NUL byte refused as it arrives and an MCAP file's only after its magic, so
    that a stream without end (``/dev/zero``) is an error in bounded memory.
    """
    name = stream_name(stream, name)
    head = _head(stream)
    fmt = fmt or sniff_format(head, name)
    if fmt not in TRAJECTORY_FORMATS:
        raise InputFileError(
            f"{name}: unknown trajectory format '{printable(str(fmt)[:40])}' (expected one of "
            f"{', '.join(TRAJECTORY_FORMATS)})"
        )
    if not BY_NAME[fmt].binary:
        return name, read_text_bytes(stream, name, head), fmt
    if not head.startswith(MAGIC):
        raise InputFileError(f"{name}: not an MCAP file (no MCAP magic at its start)")
    whole = whole_file(stream, head)
    if whole is not None:
        return name, whole, fmt
    rest = stream.read()
    return name, head + (rest.encode() if isinstance(rest, str) else rest), fmt


def _head(stream: IO) -> bytes:
    parts, size = [], 0
    while size < HEAD_BYTES:
        part = stream.read(HEAD_BYTES - size)
        if not part:
            break
        parts.append(part.encode() if isinstance(part, str) else part)
        size += len(parts[-1])
    return b"".join(parts)


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
    input_frame: str | None = None,
    mode: str = "screw",
    orthonormalize: bool = False,
    size: int = PIECE_BYTES,
) -> Iterator[Trajectory]:
    """The poses of a trajectory file's content, in consecutive pieces of about ``size`` bytes
    of text (MCAP: one piece), each checked as it is read; times increase across pieces too.

    A reader can start on the first poses while the rest is still text: ``a2b resample``
    computes the first segments while the file is parsed.
    """
    check_input_options(name, fmt, rate=rate, topic=topic, child_frame=child_frame,
                        input_frame=input_frame)  # fmt: skip
    if BY_NAME[fmt].binary:
        notes: tuple = ()
        if input_frame is not None:
            if child_frame is None:
                raise InputFileError(f"{name}: --input-frame needs --input-child-frame")
            *poses, chain = mcap_tf_poses(data, name, topic, input_frame, child_frame, mode)
            notes = (chain,)
        else:
            poses = mcap_poses(data, name, topic, child_frame)
        piece = from_quaternions(*poses, name, fmt, None)
        piece.notes = notes
        check_times(piece.times, name, None)
        yield piece
        return
    data = check_text(data, name)
    reader = importlib.import_module(BY_NAME[fmt].trajectory)
    layout = reader.layout(data, name, fmt)
    start, line, row, previous = 0, 0, 0, None
    while start < len(data):
        stop = data.find(b"\n", start + size) + 1 if len(data) - start > size else 0
        stop = stop or len(data)
        text = data[start:stop]
        rows, lines = read_rows(text, name, layout, line, skip=start == 0)
        piece = reader.trajectory(rows, lines, name, fmt, rate, orthonormalize, row)
        written = written_times(lines, layout) if "times" in BY_NAME[fmt].holds else None
        check_times(piece.times, name, lines, previous, written)
        if len(piece):
            yield piece
            previous = piece.times[-1]
        start, line, row = stop, line + text.count(b"\n"), row + len(piece)


def sniff_format(data: bytes, name: str) -> str:
    """The trajectory format of a file's content: from its suffix, else its content.

    Raises
    ------
    InputFileError
        If neither tells (the file is no trajectory).
    """
    by_suffix = SUFFIXES.get(os.path.splitext(name)[1].lower())
    if by_suffix in INPUT_NAMES:
        return by_suffix
    if data.startswith(MAGIC):
        return "mcap"
    head = data[:4096].removeprefix(BOM)
    first = first_line(head).strip()
    if first.startswith("#") and "," in first and "timestamp" in first.lower():
        return "euroc"
    by_header = fmt_from_header(first)
    if by_header:
        return by_header
    for line in head.decode("utf-8", "replace").splitlines():
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
