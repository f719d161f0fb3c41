"""Writers: sampled motions out as CSV layouts, TUM, KITTI and MCAP.

Every writer takes a binary stream and an iterable of :class:`Chunk` (so a million samples
never sit in memory at once), writes, and never closes the stream. Numbers are written as
Python's ``repr`` (the shortest text that reads back bit for bit), formatted in bulk by
:mod:`a2b.io.floatrepr`, on every idle core (:mod:`a2b.io.parallel`); MCAP is built a chunk
at a time by :mod:`a2b.io.mcapwriter`. Each ``write_x`` has a ``read_x`` in
:mod:`a2b.io.readers`.

=========  ===========================================================================
format     layout
=========  ===========================================================================
csv        ``t,tx,ty,tz,qw,qx,qy,qz`` (header line, then one sample per line)
matrix     ``t,r11,r12,r13,tx,r21,r22,r23,ty,r31,r32,r33,tz``: the 3x4 ``[R | t]`` row by row
study      ``t,p0,p1,p2,p3,q0,q1,q2,q3``: unit Study parameters
tum        ``time tx ty tz qx qy qz qw``, space-separated (evo, TUM RGB-D tools)
kitti      12 numbers of ``[R | t]`` row by row, space-separated, no time
mcap       ``foxglove.PoseInFrame`` on ``/a2b/pose``, ``foxglove.FrameTransform`` on ``/tf``
=========  ===========================================================================

In ``tum`` and ``mcap`` the time of sample ``t`` is ``t · duration + start_time`` seconds.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from itertools import groupby
from typing import IO

import numpy as np

from ..errors import ParameterError
from .floatrepr import BLOCK, format_rows
from .parallel import in_order
from .readers import CSV_HEADER, MATRIX_HEADER, STUDY_HEADER

__all__ = [
    "FORMATS",
    "REPRESENTATION",
    "Chunk",
    "sample_chunks",
    "write_batch_csv",
    "write_csv",
    "write_kitti",
    "write_matrix_csv",
    "write_mcap",
    "write_samples",
    "write_study_csv",
    "write_tum",
]

#: Samples per chunk: about 10 MB of text for ``csv``.
CHUNK_SAMPLES = 65536


@dataclass
class Chunk:
    """Consecutive samples of one motion. Only the fields a format needs are filled.

    ``t (n,)``; ``quat_wxyz (n, 4)`` unit, continuous in t; ``trans (n, 3)``;
    ``matrices (n, 4, 4)`` robotics layout; ``study (n, 8)``; ``job`` names each row (batch).
    """

    t: np.ndarray
    quat_wxyz: np.ndarray | None = None
    trans: np.ndarray | None = None
    matrices: np.ndarray | None = None
    study: np.ndarray | None = None
    job: list[str] | None = None


#: What each format needs from the motion: ``quat_trans``, ``matrices`` or ``study``.
REPRESENTATION = {
    "csv": "quat_trans",
    "matrix": "matrices",
    "study": "study",
    "tum": "quat_trans",
    "kitti": "matrices",
    "mcap": "quat_trans",
}
FORMATS = tuple(REPRESENTATION)


def sample_chunks(
    motion, ts: np.ndarray, representation: str, size: int = CHUNK_SAMPLES
) -> Iterator[Chunk]:
    """Sample ``motion`` at ``ts`` in chunks of ``size``, in the representation a format needs.

    ``motion`` is an :class:`a2b.motions.base.Motion` (anything with ``quat_trans``,
    ``matrices`` and ``study`` methods of ``ts``).
    """
    for lo in range(0, len(ts), size):
        t = ts[lo : lo + size]
        if representation == "quat_trans":
            quat, trans = motion.quat_trans(t)
            yield Chunk(t, quat_wxyz=quat, trans=trans)
        elif representation == "matrices":
            yield Chunk(t, matrices=motion.matrices(t))
        elif representation == "study":
            yield Chunk(t, study=motion.study(t))
        else:
            raise ValueError(f"unknown representation {representation!r}")


def _rows(fmt: str, chunk: Chunk) -> np.ndarray:
    """The numeric columns of one chunk in the layout of ``fmt`` (without tum's time)."""
    n = len(chunk.t)
    if fmt == "csv":
        return np.column_stack([chunk.t, chunk.trans, chunk.quat_wxyz])
    if fmt in ("matrix", "kitti"):
        flat = chunk.matrices[:, :3, :].reshape(n, 12)
        return flat if fmt == "kitti" else np.column_stack([chunk.t, flat])
    if fmt == "study":
        return np.column_stack([chunk.t, chunk.study])
    raise ValueError(f"no table layout for {fmt!r}")


#: Numbers per task handed to a worker: a few of the formatter's blocks.
TASK = 8 * BLOCK


def _blocks(rows: np.ndarray, prefix: np.ndarray | None = None) -> Iterator[tuple]:
    """Slices of about :data:`TASK` numbers: the unit of work of one worker."""
    size = max(1, TASK // max(rows.shape[1], 1))
    for lo in range(0, len(rows), size):
        yield rows[lo : lo + size], None if prefix is None else prefix[lo : lo + size]


def _write_rows(stream: IO, tables: Iterable[tuple], sep: str = ",") -> None:
    """Write ``(rows, prefix)`` tables as text, formatted task by task on every idle core
    (:func:`a2b.io.parallel.in_order`)."""

    def blocks():
        for rows, prefix in tables:
            yield from _blocks(rows, prefix)

    def text(block):
        return format_rows(block[0], sep=sep, prefix=block[1])

    for piece in in_order(text, blocks()):  # noqa: FURB122 - write each block as it is done
        stream.write(piece)


def _write_table(
    stream: IO, fmt: str, header: str | None, chunks: Iterable[Chunk], sep: str = ","
) -> None:
    if header is not None:
        stream.write(header.encode() + b"\n")
    _write_rows(stream, ((_rows(fmt, chunk), None) for chunk in chunks), sep)


def write_csv(stream: IO, chunks: Iterable[Chunk]) -> None:
    """Write ``t,tx,ty,tz,qw,qx,qy,qz`` with a header line. Needs ``quat_wxyz`` and ``trans``."""
    _write_table(stream, "csv", CSV_HEADER, chunks)


def write_matrix_csv(stream: IO, chunks: Iterable[Chunk]) -> None:
    """Write ``t`` and the 12 entries of ``[R | t]`` row by row, with a header. Needs ``matrices``."""
    _write_table(stream, "matrix", MATRIX_HEADER, chunks)


def write_study_csv(stream: IO, chunks: Iterable[Chunk]) -> None:
    """Write ``t,p0,p1,p2,p3,q0,q1,q2,q3`` with a header. Needs ``study``."""
    _write_table(stream, "study", STUDY_HEADER, chunks)


def write_kitti(stream: IO, chunks: Iterable[Chunk]) -> None:
    """Write KITTI poses: 12 space-separated numbers per line, no time. Needs ``matrices``."""
    _write_table(stream, "kitti", None, chunks, sep=" ")


def _times(t: np.ndarray, duration: float, start_time: float) -> np.ndarray:
    return t * duration + start_time


def write_tum(
    stream: IO, chunks: Iterable[Chunk], duration: float = 1.0, start_time: float = 0.0
) -> None:
    """Write TUM ``time tx ty tz qx qy qz qw`` (space-separated, one ``#`` comment line).

    The quaternion is rolled from a2b's ``wxyz`` to TUM's ``xyzw`` here, at the edge.
    """
    stream.write(b"# time tx ty tz qx qy qz qw\n")
    tables = (
        (
            np.column_stack(
                [_times(c.t, duration, start_time), c.trans, c.quat_wxyz[:, [1, 2, 3, 0]]]
            ),
            None,
        )
        for c in chunks
    )
    _write_rows(stream, tables, sep=" ")


def _csv_field(name: str) -> str:
    if any(ch in name for ch in ',"\n\r') or name != name.strip():
        return '"' + name.replace('"', '""') + '"'
    return name


def _job_column(job: list[str]) -> np.ndarray:
    """The ``job`` field of every row, quoted as CSV needs and encoded, with its comma.

    Rows of one job come in runs, so each name is quoted and encoded once per run.
    """
    names, counts = [], []
    for name, run in groupby(job):
        if "\0" in name:
            raise ParameterError(f"job name {name!r} contains a NUL character")
        names.append(_csv_field(name).encode() + b",")
        counts.append(len(list(run)))
    return np.repeat(np.array(names, dtype=bytes), counts)


def write_batch_csv(stream: IO, chunks: Iterable[Chunk], fmt: str = "csv") -> None:
    """Write many motions into one CSV whose first column, ``job``, names the motion of each row.

    ``fmt`` is one of the CSV layouts ``csv``, ``matrix``, ``study``; every chunk needs
    ``job`` and the representation of that layout.
    """
    header = {"csv": CSV_HEADER, "matrix": MATRIX_HEADER, "study": STUDY_HEADER}[fmt]
    stream.write(b"job," + header.encode() + b"\n")
    _write_rows(stream, ((_rows(fmt, chunk), _job_column(chunk.job)) for chunk in chunks))


def _schema(name: str) -> bytes:
    from importlib.resources import files

    return (files("a2b") / "schemas" / f"{name}.json").read_bytes()


def write_mcap(
    stream: IO,
    chunks: Iterable[Chunk],
    duration: float = 1.0,
    start_time: float = 0.0,
    frame_id: str = "world",
    child_frame_id: str = "a2b",
    pose_topic: str = "/a2b/pose",
    tf_topic: str = "/tf",
) -> None:
    """Write an MCAP file that Foxglove opens without plugins.

    Each sample becomes a ``foxglove.PoseInFrame`` (in ``frame_id``) on ``pose_topic`` and a
    ``foxglove.FrameTransform`` (``frame_id`` → ``child_frame_id``) on ``tf_topic``, JSON-encoded
    with the JSON schemas shipped in ``a2b/schemas``. Log and publish times are
    ``t · duration + start_time`` in nanoseconds. The file is chunked (zstd) and carries only
    chunk and message indexes. The stream needs no ``seek`` or ``tell``: pipes work. The
    chunks are built in bulk by :mod:`a2b.io.mcapwriter`.

    Raises
    ------
    ParameterError
        If a time is negative (MCAP times are unsigned) or a pose is not finite.
    """
    from .. import __version__
    from .mcapwriter import write_pose_mcap

    names = ("foxglove.PoseInFrame", "foxglove.FrameTransform")
    write_pose_mcap(
        stream,
        ((c.t, c.trans, c.quat_wxyz) for c in chunks),
        duration=duration,
        start_time=start_time,
        frame_id=frame_id,
        child_frame_id=child_frame_id,
        pose_topic=pose_topic,
        tf_topic=tf_topic,
        schemas={name: _schema(name) for name in names},
        library=f"a2b {__version__}",
    )


_TABLE_WRITERS = {
    "csv": write_csv,
    "matrix": write_matrix_csv,
    "study": write_study_csv,
    "kitti": write_kitti,
}


def write_samples(stream: IO, fmt: str, chunks: Iterable[Chunk], **options) -> None:
    """Write ``chunks`` in format ``fmt`` (one of :data:`FORMATS`).

    ``options``: ``duration`` and ``start_time`` for ``tum`` and ``mcap``; ``frame_id`` and
    ``child_frame_id`` for ``mcap``. Options a format does not use are ignored.
    """
    if fmt in _TABLE_WRITERS:
        _TABLE_WRITERS[fmt](stream, chunks)
    elif fmt == "tum":
        write_tum(stream, chunks, options.get("duration", 1.0), options.get("start_time", 0.0))
    elif fmt == "mcap":
        keys = ("duration", "start_time", "frame_id", "child_frame_id")
        write_mcap(stream, chunks, **{k: options[k] for k in keys if k in options})
    else:
        raise ValueError(f"unknown format {fmt!r}; expected one of {', '.join(FORMATS)}")
