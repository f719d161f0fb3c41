"""Writers: sampled motions out as CSV layouts, TUM, KITTI and MCAP.

Every writer takes a binary stream and an iterable of :class:`Chunk` (so a million samples
never sit in memory at once), writes, and never closes the stream. Numbers are written as
Python's ``repr`` (the shortest text that reads back bit for bit), formatted in bulk by
:mod:`a2b.io.floatrepr`, on a second thread (:mod:`a2b.io.parallel`); MCAP is built a chunk
at a time by :mod:`a2b.io.mcapwriter`. Each ``write_x`` has a ``read_x`` in
:mod:`a2b.io.trajectories`.

=========  ===========================================================================
format     layout
=========  ===========================================================================
csv        ``t,tx,ty,tz,qw,qx,qy,qz`` (header line, then one sample per line)
matrix     ``t,r11,r12,r13,tx,r21,r22,r23,ty,r31,r32,r33,tz``: the 3x4 ``[R | t]`` row by row
study      ``t,p0,p1,p2,p3,q0,q1,q2,q3``: unit Study parameters
tum        ``time tx ty tz qx qy qz qw``, space-separated (evo, TUM RGB-D tools)
kitti      12 numbers of ``[R | t]`` row by row, space-separated, no time
mcap       ``foxglove.PoseInFrame`` on ``/a2b/pose``, ``foxglove.FrameTransform`` on ``/tf``
ros2       MCAP for ROS 2: ``geometry_msgs/msg/PoseStamped`` on ``/a2b/pose``,
           ``tf2_msgs/msg/TFMessage`` on ``/tf``, one ``nav_msgs/msg/Path`` on ``/a2b/path``
=========  ===========================================================================

In ``tum``, ``mcap`` and ``ros2`` the time of sample ``t`` is ``t · duration + start_time``
seconds.
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from functools import partial
from itertools import chain, groupby, repeat
from typing import IO

import numpy as np

from ..errors import ParameterError
from .floatrepr import BLOCK, format_rows
from .parallel import in_order
from .trajectories import CSV_HEADER, MATRIX_HEADER, STUDY_HEADER

__all__ = [
    "FORMATS",
    "REPRESENTATION",
    "Chunk",
    "JobRuns",
    "sample_chunks",
    "write_batch_csv",
    "write_batch_files",
    "write_batch_mcap",
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
    ``matrices (n, 4, 4)`` robotics layout; ``study (n, 8)``; ``job`` names each row (batch);
    ``original (n,)`` marks the rows that are poses of a resampled trajectory (written as a
    last column ``original``, 1 or 0, by the CSV layouts when given); ``twist (n, 6)``
    velocities ``vx vy vz wx wy wz`` (columns after the pose in the CSV layouts, a
    ``TwistStamped`` in ros2).
    """

    t: np.ndarray
    quat_wxyz: np.ndarray | None = None
    trans: np.ndarray | None = None
    matrices: np.ndarray | None = None
    study: np.ndarray | None = None
    job: list[str] | JobRuns | None = None
    original: np.ndarray | None = None
    twist: np.ndarray | None = None


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
    "ros2": "quat_trans",
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
    mark = [] if chunk.original is None or fmt == "kitti" else [chunk.original]
    if chunk.twist is not None and fmt != "kitti":
        mark = [chunk.twist, *mark]
    if fmt == "csv":
        return np.column_stack([*t, chunk.trans, chunk.quat_wxyz, *mark])
    if fmt in ("matrix", "kitti"):
        flat = chunk.matrices[:, :3, :].reshape(n, 12)
        return flat if fmt == "kitti" or not (time or mark) else np.column_stack([*t, flat, *mark])
    if fmt == "study":
        return np.column_stack([*t, chunk.study, *mark])
    raise ValueError(f"no table layout for {fmt!r}")


#: Numbers per task handed to a worker: a few of the formatter's blocks.
TASK = 8 * BLOCK


def _write_rows(stream: IO, tables: Iterable[np.ndarray], sep: str = ",") -> None:
    """Write tables of numbers as text, :data:`TASK` numbers at a time, formatted on a second
    thread (:func:`a2b.io.parallel.in_order`)."""

    def blocks():
        for rows in tables:
            size = max(1, TASK // max(rows.shape[1], 1))
            for lo in range(0, len(rows), size):
                yield rows[lo : lo + size]

    for piece in in_order(partial(format_rows, sep=sep), blocks()):  # noqa: FURB122
        stream.write(piece)


def _write_table(
    stream: IO, fmt: str, header: str | None, chunks: Iterable[Chunk], sep: str = ","
) -> None:
    chunks = iter(chunks)
    first = next(chunks, None)
    if header is not None:
        mark = first is not None and first.original is not None
        moving = first is not None and first.twist is not None
        stream.write(header.encode() + VELOCITY_HEADER * moving + b",original" * mark + b"\n")
    if first is not None:
        _write_rows(stream, (_rows(fmt, chunk) for chunk in chain([first], chunks)), sep)


#: The velocity columns of the CSV layouts.
VELOCITY_HEADER = b",vx,vy,vz,wx,wy,wz"


def write_csv(stream: IO, chunks: Iterable[Chunk]) -> None:
    """Write ``t,tx,ty,tz,qw,qx,qy,qz`` with a header line. Needs ``quat_wxyz`` and ``trans``."""
    _write_table(stream, "csv", CSV_HEADER, chunks)


def write_matrix_csv(stream: IO, chunks: Iterable[Chunk]) -> None:
    """Write ``t`` and the 12 entries of ``[R | t]`` row by row, with a header. Needs
    ``matrices``."""
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
    stream.write(TUM_HEADER)
    _write_rows(stream, (_tum_rows(c, duration, start_time) for c in chunks), sep=" ")


TUM_HEADER = b"# time tx ty tz qx qy qz qw\n"


def _tum_rows(chunk: Chunk, duration: float, start_time: float) -> np.ndarray:
    times = _times(chunk.t, duration, start_time)
    return np.column_stack([times, chunk.trans, chunk.quat_wxyz[:, [1, 2, 3, 0]]])


_QUOTED = frozenset(',"\n\r')


def _csv_field(name: str) -> str:
    if not _QUOTED.isdisjoint(name) or name != name.strip():
        return '"' + name.replace('"', '""') + '"'
    return name


#: Bytes of job names in one piece of a batch CSV: rows of a long name go out fewer at a time,
#: so memory stays bounded by the chunk size for any length of name.
NAME_BYTES = 1 << 22


def write_batch_csv(stream: IO, chunks: Iterable[Chunk], fmt: str = "csv") -> None:
    """Write many motions into one CSV whose first column, ``job``, names the motion of each row.

    ``fmt`` is one of the CSV layouts ``csv``, ``matrix``, ``study``; every chunk needs
    ``job`` (a list of names, one per row, or :class:`JobRuns`) and the representation of
    that layout. The numbers of a piece of rows are formatted together and each name is put
    in front of its rows (quoted as CSV needs); a piece holds at most :data:`TASK` numbers and
    :data:`NAME_BYTES` of names.
    """
    header = {"csv": CSV_HEADER, "matrix": MATRIX_HEADER, "study": STUDY_HEADER}[fmt]
    stream.write(b"job," + header.encode() + b"\n")

    def pieces():
        for chunk in chunks:
            if len(chunk.t):
                yield from _batch_pieces(_rows(fmt, chunk), JobRuns(*_runs(chunk)))

    for text in in_order(_batch_text, pieces()):  # noqa: FURB122 - each piece as it is done
        stream.write(text)


def _batch_pieces(rows: np.ndarray, runs: JobRuns) -> Iterator[tuple]:
    """``(rows, leads, counts)`` pieces of a batch chunk, bounded in numbers and name bytes.

    ``runs`` covers ``rows`` exactly (:func:`_runs` checks it).
    """
    most_rows = max(1, TASK // max(rows.shape[1], 1))
    leads: list = []
    counts: list = []
    lo = taken = weight = 0
    for name, count in zip(runs.names, runs.counts):
        if "\0" in name:
            raise ParameterError(f"job name {name!r} contains a NUL character")
        lead = _csv_field(name).encode() + b","
        while count:
            room = min(most_rows - taken, (NAME_BYTES - weight) // len(lead))
            if room <= 0 and taken:
                yield rows[lo : lo + taken], leads, counts
                lo, taken, weight, leads, counts = lo + taken, 0, 0, [], []
                continue
            take = min(count, max(room, 1))
            leads.append(lead)
            counts.append(take)
            taken += take
            weight += take * len(lead)
            count -= take
    if taken:
        yield rows[lo : lo + taken], leads, counts


#: Job names up to this many bytes go before their rows as words of the formatter, in one pass
#: with the numbers; longer ones are joined to the formatted lines one by one.
SHORT_NAME = 64


def _batch_text(piece: tuple) -> bytes:
    """The text of a piece: each line of the formatted numbers after its job's name."""
    rows, leads, counts = piece
    width = max(len(lead) for lead in leads)
    if width <= SHORT_NAME:  # the common case: about 1.3x faster, and it keeps off the GIL
        return format_rows(rows, prefix=np.repeat(np.array(leads, dtype=f"S{width}"), counts))
    lines = format_rows(rows).split(b"\n")
    out = []
    lo = 0
    for lead, count in zip(leads, counts):
        out.append(lead + (b"\n" + lead).join(lines[lo : lo + count]) + b"\n")
        lo += count
    return b"".join(out)


#: The suffix of the file of each job in a directory of tum or kitti files.
FILE_SUFFIXES = {"tum": ".tum", "kitti": ".kitti"}


def job_file_name(name: str, fmt: str) -> str:
    """The file name of job ``name`` in a directory of ``fmt`` files: the name and a suffix.

    Raises
    ------
    ParameterError
        If the name cannot be a file name: empty, ``.`` or ``..``, with a ``/`` or a NUL
        character, not encodable for the file system, or longer than 255 bytes with the suffix.
    """
    file_name = name + FILE_SUFFIXES[fmt]
    why = None
    if name in ("", ".", "..") or "/" in name or "\0" in name or os.sep in name:
        why = "it is empty, . or .., or holds a / or a NUL character"
    else:
        try:
            if len(os.fsencode(file_name)) > 255:
                why = "it is longer than the 255 bytes a file name may have"
        except UnicodeEncodeError:
            why = "the file system cannot encode it"
    if why is not None:
        raise ParameterError(
            f"job {name!r}: {fmt} writes one file per job, named after the job, and this name "
            f"cannot be a file name ({why}); rename the job"
        )
    return file_name


def write_batch_files(
    directory: str,
    chunks: Iterable[Chunk],
    fmt: str,
    duration: float = 1.0,
    start_time: float = 0.0,
) -> None:
    """Write each job of ``chunks`` into a file of its own in ``directory``: ``NAME.tum`` or
    ``NAME.kitti`` (:func:`job_file_name`), as :func:`write_tum` or :func:`write_kitti` would.

    The rows of one job are consecutive (they may span chunks). A file that exists already is
    an error (two jobs of one name); write into a new directory, as
    :func:`a2b.io.atomic.atomic_directory` provides.
    """
    current, stream = None, None
    try:
        for chunk in chunks:
            if not len(chunk.t):
                continue
            rows = _tum_rows(chunk, duration, start_time) if fmt == "tum" else _rows(fmt, chunk)
            lines = format_rows(rows, sep=" ").split(b"\n")
            lo = 0
            for name, count in zip(*_runs(chunk)):
                if name != current:
                    if stream is not None:
                        stream.close()
                    path = os.path.join(directory, job_file_name(name, fmt))
                    try:
                        stream = open(path, "xb")
                    except FileExistsError:
                        raise ParameterError(
                            f"job {name!r}: a second job of this name; each job writes the "
                            "file named after it, so names must differ"
                        ) from None
                    current = name
                    if fmt == "tum":
                        stream.write(TUM_HEADER)
                stream.write(b"\n".join(lines[lo : lo + count]) + b"\n")
                lo += count
    finally:
        if stream is not None:
            stream.close()


def _runs(chunk: Chunk) -> tuple[list, list]:
    """The job names and row counts of a batch chunk, which must cover its rows exactly."""
    runs = JobRuns.of(chunk.job)
    if sum(runs.counts) != len(chunk.t):
        raise ValueError(f"a job column of {len(runs)} rows for {len(chunk.t)} samples")
    return runs.names, runs.counts


#: The topic of a job's poses in a batch MCAP file.
JOB_TOPIC = "/a2b/{name}/pose"


def write_batch_mcap(
    stream: IO,
    chunks: Iterable[Chunk],
    duration: float = 1.0,
    start_time: float = 0.0,
    frame_id: str = "world",
    profile: str = "foxglove",
) -> None:
    """Write an MCAP file with one topic per job: ``foxglove.PoseInFrame`` (``ros2``:
    ``geometry_msgs/msg/PoseStamped``) messages in ``frame_id`` on ``/a2b/NAME/pose``
    (:data:`JOB_TOPIC`), each job's times ``t · duration + start_time``. Otherwise as
    :func:`write_mcap`.

    Raises
    ------
    ParameterError
        ros2: if a job's topic is not a ROS 2 topic name, or ``frame_id`` not a frame id.
    """
    from .. import __version__
    from .mcapwriter import write_topic_mcap
    from .ros2 import check_frame_id, check_topic

    if profile == "ros2":
        check_frame_id(frame_id)

    def topic(name: str) -> str:
        topic = JOB_TOPIC.format(name=name)
        if profile == "ros2":
            check_topic(topic, f"job {name!r}: the topic")
        return topic

    def samples():
        for c in chunks:
            names, counts = _runs(c)
            yield c.t, c.trans, c.quat_wxyz, [topic(n) for n in names], counts

    write_topic_mcap(
        stream,
        samples(),
        duration=duration,
        start_time=start_time,
        frame_id=frame_id,
        profile=profile,
        library=f"a2b {__version__}",
    )


def write_mcap(
    stream: IO,
    chunks: Iterable[Chunk],
    duration: float = 1.0,
    start_time: float = 0.0,
    frame_id: str = "world",
    child_frame_id: str = "a2b",
    pose_topic: str = "/a2b/pose",
    tf_topic: str = "/tf",
    profile: str = "foxglove",
    count: int | None = None,
) -> None:
    """Write an MCAP file that Foxglove opens without plugins, or (``profile="ros2"``) that
    ``ros2 bag``, rosbags and evo read. ``count``, the number of samples if known in advance,
    lets the ros2 Path be compressed as the samples come.

    Each sample becomes a pose in ``frame_id`` on ``pose_topic`` and a transform ``frame_id``
    → ``child_frame_id`` on ``tf_topic``:

    * ``foxglove``: ``foxglove.PoseInFrame`` and ``foxglove.FrameTransform``, JSON-encoded with
      the JSON schemas shipped in ``a2b/schemas``;
    * ``ros2``: ``geometry_msgs/msg/PoseStamped`` and ``tf2_msgs/msg/TFMessage`` in CDR, and at
      the end one ``nav_msgs/msg/Path`` of every pose on ``/a2b/path`` at the first pose's
      time; the frame ids must be
      ROS 2 frame ids (:func:`a2b.io.ros2.check_frame_id`).

    Log and publish times (and stamps) are ``t · duration + start_time`` in nanoseconds. The
    file is chunked (zstd) and carries only chunk and message indexes. The stream needs no
    ``seek`` or ``tell``: pipes work. The chunks are built in bulk by :mod:`a2b.io.mcapwriter`.

    Raises
    ------
    ParameterError
        If a time is negative (MCAP times are unsigned) or, for ros2, past 2**31 − 1 s, a pose
        is not finite, or a ros2 frame id has a leading ``/`` or whitespace.
    """
    from .. import __version__
    from .mcapwriter import write_pose_mcap

    if profile == "ros2":
        from .ros2 import check_frame_id

        check_frame_id(frame_id)
        check_frame_id(child_frame_id, "--child-frame-id")
    chunks = iter(chunks)
    first = next(chunks, None)
    moving = first is not None and first.twist is not None
    write_pose_mcap(
        stream,
        (
            (c.t, c.trans, c.quat_wxyz, c.twist)
            for c in chain([first] * (first is not None), chunks)
        ),
        duration=duration,
        start_time=start_time,
        frame_id=frame_id,
        child_frame_id=child_frame_id,
        profile=profile,
        pose_topic=pose_topic,
        tf_topic=tf_topic,
        library=f"a2b {__version__}",
        count=count,
        twist_topic="/a2b/twist" if moving else None,
    )


_TABLE_WRITERS = {
    "csv": write_csv,
    "matrix": write_matrix_csv,
    "study": write_study_csv,
    "kitti": write_kitti,
}


def write_samples(stream: IO, fmt: str, chunks: Iterable[Chunk], **options) -> None:
    """Write ``chunks`` in format ``fmt`` (one of :data:`FORMATS`).

    ``options``: ``duration`` and ``start_time`` for ``tum``, ``mcap`` and ``ros2``;
    ``frame_id``, ``child_frame_id`` and ``count`` (of samples, if known) for ``mcap`` and
    ``ros2``. Options a format does not use are ignored.
    """
    if fmt in _TABLE_WRITERS:
        _TABLE_WRITERS[fmt](stream, chunks)
    elif fmt == "tum":
        write_tum(stream, chunks, options.get("duration", 1.0), options.get("start_time", 0.0))
    elif fmt in ("mcap", "ros2"):
        keys = ("duration", "start_time", "frame_id", "child_frame_id", "count")
        profile = "ros2" if fmt == "ros2" else "foxglove"
        write_mcap(stream, chunks, profile=profile, **{k: options[k] for k in keys if k in options})
    else:
        raise ValueError(f"unknown format {fmt!r}; expected one of {', '.join(FORMATS)}")
