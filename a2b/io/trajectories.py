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
rosbag2  a bag folder (``metadata.yaml``, SQLite or MCAP storage) or a     the message stamps
         ``.db3``: the ROS 2 messages of ``mcap``, each topic by its type
=======  ================================================================  ======================

Each text format is a module (:mod:`a2b.io.tum`, :mod:`a2b.io.kitti`, :mod:`a2b.io.euroc`,
:mod:`a2b.io.csvtable`) with a ``layout`` of its rows and a ``trajectory`` of them; this module
picks the format and hands the text to it in pieces. The format comes from the caller, else
the file's suffix (``.tum``, ``.kitti``, ``.mcap``, ``.db3``), else the content: a folder (a
rosbag2 bag, given as a stream named by its path: :func:`opened`), an MCAP or SQLite magic, a header
that names the columns of a2b's CSV layouts (in any order), a EuRoC ``#timestamp`` header, or
lines of 8 (TUM) or 12 (KITTI) numbers. Columns are read by the names a header gives them.
The topic of an MCAP file or a bag is ``--topic``, else the one topic with poses (a2b's own
``/a2b/pose`` among several; with ``child_frame``, the one ``TFMessage`` topic):
:func:`chosen_topic`, which says why in words. Every pose is checked as in a pose file; times
must increase. A problem is one
:class:`InputFileError` that starts ``FILE:LINE:COLUMN:``; an option that does not apply to
the format is an error too.

What a writer of :mod:`a2b.io.writers` wrote reads back bit for bit: ``quat_wxyz``, ``study``
and the matrices' entries are the numbers of the file as they stand (quaternions are not
normalised here; the matrices of a quaternion file are built from the normalised ones).
"""

from __future__ import annotations

import importlib
import io
import os
from collections.abc import Iterator
from typing import IO

import numpy as np

from ..errors import InputFileError, listing, printable
from ..formats import BY_NAME, INPUT_NAMES, SUFFIXES, TABLE, resolve
from .csvtable import CSV_HEADER, MATRIX_HEADER, STUDY_HEADER, fmt_from_header
from .documents import stream_name
from .mcapposes import channel_topics, mcap_tf_poses, pick_topic
from .mcapreader import MAGIC, McapFile
from .sqlitebag import SQLITE_MAGIC
from .textrows import (
    ARROW_FROM,
    BOM,
    TextStream,
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
    "chosen_topic",
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
    "topic": ("--topic", "the topic of an MCAP file or a bag"),
    "child_frame": ("--input-child-frame", "the frame of a /tf topic"),
    "input_frame": ("--input-frame", "the parent frame of a TF chain"),
}
#: Bytes read to tell the format before the rest.
HEAD_BYTES = 1 << 16
#: The format of ROS 2 bags, read by their path (:func:`opened`).
BAG = "rosbag2"


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
    choices: list | None = None,
) -> Trajectory:
    """Read a trajectory file (see the module's table) from a binary ``stream`` (a bag: a
    stream named by its path, :func:`opened`).

    ``rate`` gives KITTI poses the times ``i / rate``; ``topic`` picks the topic of an MCAP
    file or a bag when it has several, and ``child_frame`` the transforms of a ROS 2 ``/tf``
    topic when they go to several frames; ``input_frame`` with ``child_frame`` composes the
    pose of ``child_frame`` in ``input_frame`` through the TF tree of ``/tf`` and
    ``/tf_static``, each dynamic link interpolated by ``mode``
    (:func:`a2b.io.mcapposes.mcap_tf_poses`, :func:`a2b.io.rosbag2.bag_tf_poses`; the chain is
    stated in :attr:`Trajectory.notes`);
    ``orthonormalize`` repairs rotation blocks that are orthogonal only to a few digits
    (:func:`a2b.poses.orthonormalize`); ``minimum`` is the fewest poses accepted.
    ``choices``: the topic and storage chosen, in words, appended.

    Raises
    ------
    InputFileError
        For a malformed file, and for ``rate``, ``topic`` or ``child_frame`` given for a
        format they do not apply to (:data:`INPUT_OPTIONS`).
    """
    name, data, fmt = opened(stream, name, fmt)
    pieces = list(trajectory_pieces(data, name, fmt, rate=rate, topic=topic,
                                    child_frame=child_frame, input_frame=input_frame,
                                    mode=mode, orthonormalize=orthonormalize,
                                    choices=choices))  # fmt: skip
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
    """``(name, content, format)`` of a trajectory file: its name for messages, its content
    (bytes; a large regular text file's :class:`~a2b.io.textrows.TextStream`, read as it is
    parsed; a rosbag2 bag's path), and its format (given, else from the suffix or the
    content: :func:`sniff_format`).

    A bag is read by its path, not through the stream: a folder is given as a stream named
    by the folder's path (the command line passes an empty one), a ``.db3`` as its file.
    Else the format is told from the first :data:`HEAD_BYTES`; then the rest is read, a text
    file's with every NUL byte refused as it arrives and an MCAP file's only after its
    magic, so that a stream without end (``/dev/zero``) is an error in bounded memory.
    """
    path = name or getattr(stream, "name", None)
    name = stream_name(stream, name)
    folder = isinstance(path, str) and os.path.isdir(path)
    if folder and fmt not in (None, BAG):
        raise InputFileError(f"{name}: a folder; a2b reads folders as {BAG} bags, not as {fmt}")
    head = b"" if folder or fmt == BAG else _head(stream)
    fmt = fmt or (BAG if folder else sniff_format(head, name))
    if fmt not in TRAJECTORY_FORMATS:
        raise InputFileError(
            f"{name}: unknown trajectory format '{printable(str(fmt)[:40])}' (expected one of "
            f"{', '.join(TRAJECTORY_FORMATS)})"
        )
    if fmt == BAG:
        if not (isinstance(path, str) and os.path.exists(path)):
            raise InputFileError(
                f"{name}: a {BAG} bag is read by its path (a folder or a .db3 file), not from "
                "a stream"
            )
        return name, path, fmt
    if not BY_NAME[fmt].binary:
        large = TextStream.of(stream, head)  # read as it is parsed
        return name, read_text_bytes(stream, name, head) if large is None else large, fmt
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


#: Bytes of text parsed at a time by :func:`trajectory_pieces` (the first piece of a longer
#: text: a sixteenth, so that the work on its poses starts sooner).
PIECE_BYTES = 1 << 22


def trajectory_pieces(
    data: bytes | TextStream | str,
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
    choices: list | None = None,
) -> Iterator[Trajectory]:
    """The poses of a trajectory file's content (:func:`opened`), in consecutive pieces of
    about ``size`` bytes of text (MCAP, a bag: one piece), each checked as it is read; times
    increase across pieces too. A :class:`~a2b.io.textrows.TextStream` is read as the pieces
    are taken, once, from its stream, which must stay open until then.

    A reader can start on the first poses while the rest is still text: ``a2b resample``
    computes the first segments while the file is parsed. The options are checked and the
    topic chosen (and stated in ``choices``) at the call, before the first piece.
    """
    check_input_options(name, fmt, rate=rate, topic=topic, child_frame=child_frame,
                        input_frame=input_frame)  # fmt: skip
    if not BY_NAME[fmt].binary:
        return _text_pieces(data, name, fmt, rate, orthonormalize, size)
    if fmt == BAG:
        from .rosbag2 import bag_files

        storage, files = bag_files(data)
        how = f"{len(files)} file{'s' * (len(files) != 1)} that metadata.yaml lists"
        _say(choices, f"storage {storage}: " + (how if os.path.isdir(data) else "a .db3 alone"))
    if input_frame is not None:
        return _tree_pieces(data, name, fmt, topic, input_frame, child_frame, mode)
    topic = chosen_topic(data, name, topic, child_frame, choices)
    return _binary_pieces(data, name, fmt, topic, child_frame)


def _tree_pieces(data, name: str, fmt: str, topic, input_frame: str, child_frame, mode: str):
    """The pose of ``child_frame`` in ``input_frame`` through the TF tree, one piece; the chain
    in its :attr:`Trajectory.notes`."""
    if child_frame is None:
        raise InputFileError(f"{name}: --input-frame needs --input-child-frame")
    if fmt == BAG:
        from .rosbag2 import bag_tf_poses

        *poses, chain = bag_tf_poses(data, name, topic, input_frame, child_frame, mode)
    else:
        *poses, chain = mcap_tf_poses(data, name, topic, input_frame, child_frame, mode)
    piece = from_quaternions(*poses, name, fmt, None)
    piece.notes = (chain,)
    check_times(piece.times, name, None)
    yield piece


def _binary_pieces(data, name: str, fmt: str, topic, child_frame) -> Iterator[Trajectory]:
    times, quat, trans = resolve(BY_NAME[fmt].trajectory)(data, name, topic, child_frame)
    piece = from_quaternions(times, quat, trans, name, fmt, None)
    check_times(piece.times, name, None)
    yield piece


def _say(choices: list | None, choice: str) -> None:
    if choices is not None:
        choices.append(choice)


def chosen_topic(
    data, name: str, topic: str | None, child_frame: str | None, choices: list | None = None
) -> str | None:
    """The topic to read from an MCAP file's bytes or a bag's path ``data``: ``topic`` if
    given, else the one topic whose messages a2b reads poses from (``/a2b/pose`` among
    several; with ``child_frame``, the one ``TFMessage`` topic). Why, in words, is appended to
    ``choices``. An MCAP file is opened here only when ``topic`` is not given.

    Raises
    ------
    InputFileError
        If the topic given is not there, or no topic or several qualify.
    """
    if topic is not None and isinstance(data, bytes):
        _say(choices, f"topic {listing([topic], width=80)}: given with --topic")
        return topic
    holder = "file" if isinstance(data, bytes) else "bag"
    topic, why = pick_topic(_topics(data, name), name, topic, child_frame, holder)
    change = "" if why.startswith("given") else " (--topic to change)"
    _say(choices, f"topic {listing([topic], width=80)}: {why}{change}")
    return topic


def _topics(data, name: str) -> list[tuple[str, str, bool]]:
    """``(topic, type or schema, whether a2b reads poses from it)`` of each channel of an MCAP
    file's bytes, or each topic of a bag's path."""
    if isinstance(data, bytes):
        return channel_topics(McapFile(data, name).channels.values())
    from .ros2 import POSE_TYPES
    from .rosbag2 import bag_topics

    return [
        (topic.name, topic.type_name,
         topic.serialization_format == "cdr" and topic.type_name in POSE_TYPES)
        for topic in bag_topics(data)
    ]  # fmt: skip


def _text_pieces(data, name: str, fmt: str, rate, orthonormalize, size):
    """:func:`trajectory_pieces` of a text format: ``data`` is bytes, checked whole first, or
    a :class:`~a2b.io.textrows.TextStream`, each piece checked as it is read."""
    reader = importlib.import_module(BY_NAME[fmt].trajectory)
    streamed = isinstance(data, TextStream)
    first = size if size >= len(data) else max(size >> 4, 1)
    if streamed:
        texts = data.pieces(size, first)
        raw = next(texts, b"")
        while raw and not raw.strip():  # blank lines only: a header is looked for after them
            more = next(texts, b"")
            if not more:
                break
            raw += more
        text = check_text(raw, name, (0, 0))
        layout = reader.layout(text, name, fmt)
    else:
        data = check_text(data, name)
        layout = reader.layout(data, name, fmt)
        texts = TextStream(io.BytesIO(data), len(data)).pieces(size, first)
        raw = text = next(texts, b"")
    offset, line, row, previous = 0, 0, 0, None
    while raw:
        rows, lines = read_rows(
            text, name, layout, line, skip=not offset, bulk=len(data) >= ARROW_FROM
        )
        piece = reader.trajectory(rows, lines, name, fmt, rate, orthonormalize, row)
        written = written_times(lines, layout) if "times" in BY_NAME[fmt].holds else None
        check_times(piece.times, name, lines, previous, written)
        if len(piece):
            yield piece
            previous = piece.times[-1]
        offset, line, row = offset + len(raw), line + lines.count(), row + len(piece)
        raw = text = next(texts, b"")
        if streamed and raw:
            text = check_text(raw, name, (line, offset))


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
    if data.startswith(SQLITE_MAGIC) or os.path.isdir(name):
        return BAG
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
        f"matrix or study, MCAP or a ROS 2 bag); give it with --input-format{hint}"
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
