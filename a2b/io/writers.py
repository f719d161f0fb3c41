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
from itertools import groupby, repeat
from typing import IO

import numpy as np

from ..errors import ParameterError
from .floatrepr import BLOCK, format_rows, number_words, text_words
from .parallel import in_order
from .readers import CSV_HEADER, MATRIX_HEADER, STUDY_HEADER

__all__ = [
    "FORMATS",
    "REPRESENTATION",
    "Chunk",
    "JobRuns",
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
    job: list[str] | JobRuns | None = None


class JobRuns:
    """A ``job`` column in runs: ``names[0]`` for ``counts[0]`` rows, then ``names[1]`` …

    Iterating gives the name of every row, as the list it stands for would.
    """

    __slots__ = ("counts", "names")

    def __init__(self, names: list[str], counts: list[int]):
        if len(names) != len(counts):
            raise ValueError(f"{len(names)} names for {len(counts)} runs")
        self.names = names
        self.counts = counts

    @classmethod
    def of(cls, job: Iterable[str]) -> JobRuns:
        """``job`` as runs (a :class:`JobRuns` is returned as it is)."""
        if isinstance(job, JobRuns):
            return job
        names, counts = [], []
        for name, run in groupby(job):
            names.append(name)
            counts.append(sum(1 for _ in run))
        return cls(names, counts)

    @classmethod
    def join(cls, parts: Iterable[JobRuns]) -> JobRuns:
        """The runs of ``parts`` one after the other."""
        names: list[str] = []
        counts: list[int] = []
        for part in parts:
            names += part.names
            counts += part.counts
        return cls(names, counts)

    def __len__(self) -> int:
        return sum(self.counts)

    def __iter__(self) -> Iterator[str]:
        for name, count in zip(self.names, self.counts):
            yield from repeat(name, count)

    def __repr__(self) -> str:
        return f"JobRuns({self.names!r}, {self.counts!r})"


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


def _rows(fmt: str, chunk: Chunk, time: bool = True) -> np.ndarray:
    """The numeric columns of one chunk in the layout of ``fmt`` (without tum's time, and
    without ``t`` if not ``time``)."""
    n = len(chunk.t)
    t = [chunk.t] if time else []
    if fmt == "csv":
        return np.column_stack([*t, chunk.trans, chunk.quat_wxyz])
    if fmt in ("matrix", "kitti"):
        flat = chunk.matrices[:, :3, :].reshape(n, 12)
        return flat if fmt == "kitti" or not time else np.column_stack([*t, flat])
    if fmt == "study":
        return np.column_stack([*t, chunk.study])
    raise ValueError(f"no table layout for {fmt!r}")


#: Numbers per task handed to a worker: a few of the formatter's blocks.
TASK = 8 * BLOCK


def _blocks(rows: np.ndarray, lead: _Lead | None = None) -> Iterator[tuple]:
    """Slices of about :data:`TASK` numbers, the unit of work of one worker, with the part of
    the ``lead`` of their rows."""
    size = max(1, TASK // max(rows.shape[1], 1))
    for lo in range(0, len(rows), size):
        hi = min(lo + size, len(rows))
        yield rows[lo:hi], None if lead is None else lead.part(lo, hi)


def _write_rows(stream: IO, tables: Iterable[tuple], sep: str = ",") -> None:
    """Write ``(rows, lead)`` tables as text, formatted task by task on every idle core
    (:func:`a2b.io.parallel.in_order`); ``lead`` (a :class:`_Lead` or ``None``) gives the
    first fields of each row."""

    def blocks():
        for rows, lead in tables:
            yield from _blocks(rows, lead)

    def text(block):
        rows, lead = block
        return format_rows(rows, sep=sep, prefix=None if lead is None else lead.words())

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


_QUOTED = frozenset(',"\n\r')


def _csv_field(name: str) -> str:
    if not _QUOTED.isdisjoint(name) or name != name.strip():
        return '"' + name.replace('"', '""') + '"'
    return name


@dataclass
class _Lead:
    """The first fields of a batch chunk's rows, as text words (:mod:`a2b.io.floatrepr`):
    the job, and ``t`` too when every job repeats the same times.

    Runs of rows share a job, and the jobs of a chunk mostly share their times, so each name
    and each ``t`` is formatted once, not once per row. A task gets the :meth:`part` of its
    rows (its own names only, as wide as the widest of them), and its worker spells the rows
    out (:meth:`words`). ``t`` is taken out of the columns only if the chunk has two runs or
    more, all of the same times, bit for bit.
    """

    names: np.ndarray  # (runs, w): "name," of each run
    ends: np.ndarray  # (runs,): the row after each run
    times: np.ndarray | None  # (c, 4): "t," of each row of a run; None: t is a column

    def part(self, lo: int, hi: int) -> _Lead:
        """The lead of rows ``lo`` to ``hi``, numbered from 0."""
        first, last = np.searchsorted(self.ends, [lo, hi - 1], side="right").tolist()
        names = self.names[first : last + 1]
        used = np.flatnonzero(names.any(axis=0))  # text is followed by zero words only
        names = np.ascontiguousarray(names[:, : used[-1] + 1 if len(used) else 1])
        ends = np.minimum(self.ends[first : last + 1], hi) - lo
        times = self.times
        if times is not None:  # row lo is at lo mod c in its run: every run has c rows
            times = np.roll(times, -(lo % len(times)), axis=0)
        return _Lead(names, ends, times)

    def words(self) -> np.ndarray:
        """The words of every row, ``(rows, w [+ 4])``."""
        names = np.repeat(self.names, np.diff(self.ends, prepend=0), axis=0)
        if self.times is None:
            return names
        times = self.times.take(np.arange(len(names)) % len(self.times), axis=0)
        return np.concatenate([names, times], axis=1)


def _lead(chunk: Chunk) -> _Lead:
    """The :class:`_Lead` of a batch chunk: names quoted as CSV needs, with their commas."""
    runs = JobRuns.of(chunk.job)
    if any("\0" in name for name in runs.names):
        name = next(name for name in runs.names if "\0" in name)
        raise ParameterError(f"job name {name!r} contains a NUL character")
    names = text_words(np.array([_csv_field(name).encode() + b"," for name in runs.names]))
    ends = np.cumsum(runs.counts)
    if len(ends) == 0 or ends[-1] != len(chunk.t):
        raise ValueError(f"a job column of {len(runs)} rows for {len(chunk.t)} samples")
    times = None
    count = runs.counts[0]
    if len(runs.counts) > 1 and all(c == count for c in runs.counts):
        t = np.ascontiguousarray(chunk.t, dtype=np.float64)
        bits = t.view(np.uint64).reshape(-1, count)  # bit for bit: -0.0 is not 0.0
        if (bits == bits[0]).all():
            times = number_words(t[:count])
            times[:, 3] |= np.uint64(ord(",")) << np.uint64(56)
    return _Lead(names, ends, times)


def write_batch_csv(stream: IO, chunks: Iterable[Chunk], fmt: str = "csv") -> None:
    """Write many motions into one CSV whose first column, ``job``, names the motion of each row.

    ``fmt`` is one of the CSV layouts ``csv``, ``matrix``, ``study``; every chunk needs
    ``job`` (a list of names, one per row, or :class:`JobRuns`) and the representation of
    that layout.
    """
    header = {"csv": CSV_HEADER, "matrix": MATRIX_HEADER, "study": STUDY_HEADER}[fmt]
    stream.write(b"job," + header.encode() + b"\n")

    def tables():
        for chunk in chunks:
            if not len(chunk.t):
                continue
            lead = _lead(chunk)
            yield _rows(fmt, chunk, time=lead.times is None), lead

    _write_rows(stream, tables())


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
