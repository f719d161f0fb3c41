"""Writers: sampled motions out as CSV layouts, TUM, KITTI and MCAP.

Every writer takes a binary stream and an iterable of :class:`a2b.samples.Samples` (so a
million samples never sit in memory at once), writes, and never closes the stream; which writer
serves which format is the table :mod:`a2b.formats`, and :func:`a2b.output.write` is the
pipeline that calls them (checks, times, atomic output). Numbers are written as
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

In ``tum``, ``mcap`` and ``ros2`` the time of a sample is :meth:`a2b.samples.Samples.seconds`
(:func:`a2b.output.write` forms it as ``t · duration + start_time``).
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Iterator
from functools import partial
from itertools import chain
from typing import IO

import numpy as np

from ..errors import ParameterError, quoted
from ..formats import BY_NAME
from ..samples import JobRuns, Samples
from .floatrepr import BLOCK, format_rows
from .parallel import in_order

__all__ = [
    "JobRuns",
    "chunk_text",
    "job_file_name",
    "write_batch_csv",
    "write_batch_files",
    "write_batch_mcap",
    "write_batch_sqlite_bag",
    "write_csv",
    "write_kitti",
    "write_matrix_csv",
    "write_mcap",
    "write_sqlite_bag",
    "write_study_csv",
    "write_tum",
]


def _rows(fmt: str, chunk: Samples) -> np.ndarray:
    """The numeric columns of one chunk in the layout of ``fmt`` (:mod:`a2b.formats`): ``t`` if
    it holds times, the pose in its representation, then twists and marks if it holds them
    (tum's time comes from :func:`_tum_rows`)."""
    row = BY_NAME[fmt]
    holds = row.holds
    columns = [chunk.t] if "times" in holds else []
    if row.representation == "matrices":
        columns.append(chunk.matrices[:, :3, :].reshape(len(chunk.t), 12))
    elif row.representation == "study":
        columns.append(chunk.study)
    else:
        columns += [chunk.trans, chunk.quat_wxyz]
    if chunk.twist is not None and "velocities" in holds:
        columns.append(chunk.twist)
    if chunk.original is not None and "mark" in holds:
        columns.append(chunk.original)
    return columns[0] if len(columns) == 1 else np.column_stack(columns)


#: Numbers per task handed to a worker: one of the formatter's blocks. Eight blocks a task
#: made each thread's working set eight times larger: the CSV of 10^6 samples took 1.07 to
#: 1.10 times as long as with one, and a batch of 10,000 jobs x 101 samples 1.10 times.
TASK = BLOCK


def _pieces(rows: np.ndarray) -> list[np.ndarray]:
    """``rows`` in pieces of at most :data:`TASK` numbers (views)."""
    size = max(1, TASK // max(rows.shape[1], 1))
    return [rows[lo : lo + size] for lo in range(0, len(rows), size)]


def _layout_rows(fmt: str, chunk: Samples) -> np.ndarray:
    return _tum_rows(chunk) if fmt == "tum" else _rows(fmt, chunk)


def chunk_text(fmt: str, chunk: Samples) -> tuple[str, list]:
    """The lines that the writer of the text table ``fmt`` (a format with a ``separator``)
    writes for ``chunk``, formatted in the calling thread: ``(fmt, pieces)``, arrays of bytes
    of :data:`TASK` numbers each, for :attr:`a2b.samples.Samples.text`.

    For a producer that makes its chunks on the writers' threads (``a2b resample``): the text
    is then made in the same task, while the samples are in that processor's cache, and the
    writing thread only writes it. Resampling 10^6 poses to 10^7 CSV rows took 0.94 times as
    long (medians of 7) as with the chunks formatted by the writer (docs/benchmarks.md).
    """
    sep = BY_NAME[fmt].separator
    return fmt, [format_rows(piece, sep, array=True) for piece in _pieces(_layout_rows(fmt, chunk))]


def _write_rows(stream: IO, fmt: str, chunks: Iterator[Samples]) -> None:
    """Write the rows of ``chunks`` in the text layout ``fmt``. Chunks whose text was made
    ahead (:func:`chunk_text`, as the first one says) are written as they are (one without is
    formatted here); else :data:`TASK` numbers at a time are formatted on a second thread
    (:func:`a2b.io.parallel.in_order`, which does a single task in this thread)."""
    first = next(chunks, None)
    if first is None:
        return
    chunks = chain([first], chunks)
    if first.text is not None:
        for chunk in chunks:
            made = chunk.text if chunk.text is not None and chunk.text[0] == fmt else None
            for piece in (made or chunk_text(fmt, chunk))[1]:
                stream.write(piece)
        return
    blocks = (piece for chunk in chunks for piece in _pieces(_layout_rows(fmt, chunk)))
    text = partial(format_rows, sep=BY_NAME[fmt].separator, array=True)  # as made, not copied
    for piece in in_order(text, blocks):  # noqa: FURB122 - each as it is done
        stream.write(piece)


def _marked(text: bytes) -> bytes:
    """Rows whose last column is resample's ``original`` (1.0 or 0.0) with it as 1 or 0: each
    line ends in the one ``.0\n`` of that column."""
    return text.replace(b".0\n", b"\n")


def _write_table(stream: IO, fmt: str, header: str | None, chunks: Iterable[Samples]) -> None:
    chunks = iter(chunks)
    first = next(chunks, None)
    mark = first is not None and first.original is not None and "mark" in BY_NAME[fmt].holds
    if header is not None:
        moving = first is not None and first.twist is not None
        stream.write(header.encode() + VELOCITY_HEADER * moving + b",original" * mark + b"\n")
    if first is not None:
        _write_rows(_Marking(stream) if mark else stream, fmt, chain([first], chunks))


class _Marking:
    """A stream that writes rows through :func:`_marked` (whole lines are written at a time)."""

    def __init__(self, stream: IO):
        self.stream = stream

    def write(self, text) -> None:
        self.stream.write(_marked(bytes(text)))


#: The velocity columns of the CSV layouts.
VELOCITY_HEADER = b",vx,vy,vz,wx,wy,wz"


def write_csv(stream: IO, chunks: Iterable[Samples]) -> None:
    """Write ``t,tx,ty,tz,qw,qx,qy,qz`` with a header line. Needs ``quat_wxyz`` and ``trans``."""
    _write_table(stream, "csv", BY_NAME["csv"].header, chunks)


def write_matrix_csv(stream: IO, chunks: Iterable[Samples]) -> None:
    """Write ``t`` and the 12 entries of ``[R | t]`` row by row, with a header. Needs
    ``matrices``."""
    _write_table(stream, "matrix", BY_NAME["matrix"].header, chunks)


def write_study_csv(stream: IO, chunks: Iterable[Samples]) -> None:
    """Write ``t,p0,p1,p2,p3,q0,q1,q2,q3`` with a header. Needs ``study``."""
    _write_table(stream, "study", BY_NAME["study"].header, chunks)


def write_kitti(stream: IO, chunks: Iterable[Samples]) -> None:
    """Write KITTI poses: 12 space-separated numbers per line, no time. Needs ``matrices``."""
    _write_table(stream, "kitti", None, chunks)


def write_tum(stream: IO, chunks: Iterable[Samples]) -> None:
    """Write TUM ``time tx ty tz qx qy qz qw`` (space-separated, one ``#`` comment line); the
    time is :meth:`a2b.samples.Samples.seconds`.

    The quaternion is rolled from a2b's ``wxyz`` to TUM's ``xyzw`` here, at the edge.
    """
    stream.write(TUM_HEADER)
    _write_rows(stream, "tum", iter(chunks))


TUM_HEADER = b"# " + BY_NAME["tum"].header.encode() + b"\n"


def _tum_rows(chunk: Samples) -> np.ndarray:
    return np.column_stack([chunk.seconds(), chunk.trans, chunk.quat_wxyz[:, [1, 2, 3, 0]]])


_QUOTED = frozenset(',"\n\r')


def _csv_field(name: str) -> str:
    if not _QUOTED.isdisjoint(name) or name != name.strip():
        return '"' + name.replace('"', '""') + '"'
    return name


#: Bytes of job names in one piece of a batch CSV: rows of a long name go out fewer at a time,
#: so memory stays bounded by the chunk size for any length of name.
NAME_BYTES = 1 << 22


def write_batch_csv(stream: IO, chunks: Iterable[Samples], fmt: str = "csv") -> None:
    """Write many motions into one CSV whose first column, ``job``, names the motion of each row.

    ``fmt`` is one of the CSV layouts ``csv``, ``matrix``, ``study``; every chunk needs
    ``job`` (a list of names, one per row, or :class:`JobRuns`) and the representation of
    that layout. The numbers of a piece of rows are formatted together and each name is put
    in front of its rows (quoted as CSV needs); a piece holds at most :data:`TASK` numbers and
    :data:`NAME_BYTES` of names.
    """
    header = BY_NAME[fmt].header
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


def job_file_name(name: str, fmt: str) -> str:
    """The file name of job ``name`` in a directory of ``fmt`` files: the name and a suffix.

    Raises
    ------
    ParameterError
        If the name cannot be a file name: empty, ``.`` or ``..``, with a ``/`` or a NUL
        character, not encodable for the file system, or longer than 255 bytes with the suffix.
    """
    from ..formats import BY_NAME

    file_name = name + BY_NAME[fmt].suffixes[0]
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
    chunks: Iterable[Samples],
    fmt: str,
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
            lines = format_rows(_layout_rows(fmt, chunk), sep=BY_NAME[fmt].separator).split(b"\n")
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


def _runs(chunk: Samples) -> tuple[list, list]:
    """The job names and row counts of a batch chunk, which must cover its rows exactly."""
    runs = JobRuns.of(chunk.job)
    if sum(runs.counts) != len(chunk.t):
        raise ValueError(f"a job column of {len(runs)} rows for {len(chunk.t)} samples")
    return runs.names, runs.counts


#: The topic of a job's poses in a batch MCAP file.
JOB_TOPIC = "/a2b/{name}/pose"


def write_batch_mcap(
    stream: IO, chunks: Iterable[Samples], fmt: str = "mcap", frame_id: str = "world"
) -> None:
    """Write an MCAP file with one topic per job: ``foxglove.PoseInFrame`` (``ros2``:
    ``geometry_msgs/msg/PoseStamped``) messages in ``frame_id`` on ``/a2b/NAME/pose``
    (:data:`JOB_TOPIC`). Otherwise as :func:`write_mcap`.

    Raises
    ------
    ParameterError
        ros2: if a job's topic is not a ROS 2 topic name, or ``frame_id`` not a frame id.
    """
    from .. import __version__
    from ..formats import BY_NAME
    from .mcapwriter import write_topic_mcap
    from .ros2 import check_frame_id, check_topic

    profile = BY_NAME[fmt].writer_options["profile"]
    if profile == "ros2":
        check_frame_id(frame_id)

    def topic(name: str) -> str:
        topic = JOB_TOPIC.format(name=name)
        if profile == "ros2":
            check_topic(topic, f"job {quoted(name)}: the topic")
        return topic

    def samples():
        for c in chunks:
            names, counts = _runs(c)
            yield c.nanoseconds(), c.trans, c.quat_wxyz, [topic(n) for n in names], counts

    write_topic_mcap(
        stream, samples(), frame_id=frame_id, profile=profile, library=f"a2b {__version__}"
    )


def write_mcap(
    stream: IO,
    chunks: Iterable[Samples],
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
    * ``protobuf``: the same Protobuf-encoded (:mod:`a2b.io.protobuf`, the extra
      ``a2b-motions[protobuf]``), as Foxglove's SDK writes them and rerun imports them;
    * ``ros2``: ``geometry_msgs/msg/PoseStamped`` and ``tf2_msgs/msg/TFMessage`` in CDR, and at
      the end one ``nav_msgs/msg/Path`` of every pose on ``/a2b/path`` at the first pose's
      time; the frame ids must be
      ROS 2 frame ids (:func:`a2b.io.ros2.check_frame_id`).

    Log and publish times (and stamps) are :meth:`a2b.samples.Samples.nanoseconds`, whose
    limits :func:`a2b.output.check_times` checks. The file is chunked (zstd) and carries only
    chunk and message indexes. The stream needs no ``seek`` or ``tell``: pipes work. The
    chunks are built in bulk by :mod:`a2b.io.mcapwriter`.

    Raises
    ------
    ParameterError
        If a pose is not finite, or a ros2 frame id has a leading ``/`` or whitespace.
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
            (c.nanoseconds(), c.trans, c.quat_wxyz, c.twist)
            for c in chain([first] * (first is not None), chunks)
        ),
        frame_id=frame_id,
        child_frame_id=child_frame_id,
        profile=profile,
        pose_topic=pose_topic,
        tf_topic=tf_topic,
        library=f"a2b {__version__}",
        count=count,
        twist_topic="/a2b/twist" if moving else None,
    )


def write_sqlite_bag(
    folder,
    chunks: Iterable[Samples],
    frame_id: str = "world",
    child_frame_id: str = "a2b",
    count: int | None = None,
) -> None:
    """Write the messages of :func:`write_mcap`'s ``ros2`` profile as a rosbag2 bag of SQLite
    storage: the folder ``folder`` with ``NAME_0.db3`` and ``metadata.yaml``
    (:func:`a2b.io.rosbag2.write_sqlite_bag`), which appears only when complete.

    ``geometry_msgs/msg/PoseStamped`` on ``/a2b/pose`` and ``tf2_msgs/msg/TFMessage`` on ``/tf``
    per sample (``geometry_msgs/msg/TwistStamped`` on ``/a2b/twist`` with velocities), then
    one ``nav_msgs/msg/Path`` of every pose on ``/a2b/path`` at the first pose's time. The
    CDR is :mod:`a2b.io.ros2`'s fixed layouts, as in the MCAP file; ``count`` is not needed.

    Raises
    ------
    ParameterError
        If a frame id is not a ROS 2 frame id.
    OutputFileError
        If the folder cannot be written, or exists and is no bag.
    """
    from .ros2 import check_frame_id, qos_profiles
    from .rosbag2 import write_sqlite_bag as write_bag

    check_frame_id(frame_id)
    check_frame_id(child_frame_id, "--child-frame-id")
    chunks = iter(chunks)
    first = next(chunks, None)
    moving = first is not None and first.twist is not None
    topics = [
        ("/a2b/pose", "geometry_msgs/msg/PoseStamped", qos_profiles(10)),
        ("/tf", "tf2_msgs/msg/TFMessage", qos_profiles(100)),
        *[("/a2b/twist", "geometry_msgs/msg/TwistStamped", qos_profiles(10))] * moving,
        ("/a2b/path", "nav_msgs/msg/Path", qos_profiles(1, 1)),
    ]
    every = chain([first] * (first is not None), chunks)
    write_bag(folder, topics, _bag_messages(every, frame_id, child_frame_id, moving))


def write_batch_sqlite_bag(
    folder, chunks: Iterable[Samples], fmt: str = "ros2", frame_id: str = "world"
) -> None:
    """Write a batch as a rosbag2 bag of SQLite storage: the messages of
    :func:`write_batch_mcap` (``geometry_msgs/msg/PoseStamped`` on ``/a2b/NAME/pose`` per
    job), built as an MCAP file in a temporary file, then stored in the bag's ``.db3`` in the
    order of their times (:func:`a2b.io.rosbag2.write_sqlite_bag`). The topics of a SQLite bag
    are listed before its messages, and a batch's are known only at its end: the messages are
    held in memory once, 70 bytes and a job name a sample.

    Raises
    ------
    ParameterError
        As :func:`write_batch_mcap`: a job name that makes no ROS 2 topic, a frame id.
    """
    import tempfile

    from .mcapreader import McapFile
    from .ros2 import qos_profiles
    from .rosbag2 import write_sqlite_bag as write_bag

    with tempfile.TemporaryFile() as f:
        write_batch_mcap(f, chunks, fmt, frame_id)
        f.seek(0)
        mcap = McapFile(f.read(), os.fspath(folder))
    channels = sorted(mcap.channels.values(), key=lambda channel: channel.id)
    found = mcap.messages([channel.id for channel in channels])
    parts = [found[channel.id] for channel in channels]
    times = np.concatenate([np.asarray(p.log_time, np.int64) for p in parts]
                           + [np.empty(0, np.int64)])  # fmt: skip
    index = np.repeat(np.arange(len(parts)), [len(p) for p in parts]).tolist()
    datas = [data for p in parts for data in p.as_bytes()]
    topics = [(channel.topic, channel.schema_name, qos_profiles(10)) for channel in channels]
    order = np.argsort(times, kind="stable").tolist()
    write_bag(folder, topics, ((index[k], int(times[k]), datas[k]) for k in order))


def _bag_messages(chunks: Iterable[Samples], frame_id: str, child_frame_id: str, moving: bool):
    """``(topic index, ns, CDR)`` of each sample's messages, then the Path's."""
    from . import ros2

    layouts = [ros2.pose_stamped(frame_id), ros2.tf_message(frame_id, child_frame_id)]
    layouts += [ros2.twist_stamped(frame_id)] * moving
    entry = ros2.pose_stamped(frame_id, phase=0)
    entries, first = [], None
    for chunk in chunks:
        ns = chunk.nanoseconds()
        numbers = np.column_stack([chunk.trans, np.asarray(chunk.quat_wxyz)[:, [1, 2, 3, 0]]]
                                  + ([chunk.twist] if moving else []))  # fmt: skip
        if not len(ns):
            continue
        first = first or (ns[:1], numbers[:1])
        made = [_cdr_rows(cdr, ns, numbers) for cdr in layouts]
        for k, stamp in enumerate(ns.tolist()):
            for index, rows in enumerate(made):
                yield index, stamp, rows[k].tobytes()
        entries.append(_cdr_rows(entry, ns, numbers))
    if first is None:
        return
    head, first_entry = ros2.path_message(frame_id, 0, sum(len(e) for e in entries))
    path = [_cdr_rows(head, *first).tobytes(), _cdr_rows(first_entry, *first).tobytes()]
    path += [rows.tobytes() for rows in entries]
    path[2] = entries[0][1:].tobytes()  # the first entry is made again after the head
    yield len(layouts), int(first[0][0]), b"".join(path)


def _cdr_rows(cdr, ns: np.ndarray, numbers: np.ndarray) -> np.ndarray:
    """The bytes of the messages of layout ``cdr`` (:class:`a2b.io.ros2.Cdr`) for times
    ``ns`` and ``numbers`` ``x y z qx qy qz qw [vx vy vz wx wy wz]``, one row each."""
    from .ros2 import stamp_words

    rows = np.tile(np.frombuffer(cdr.template, np.uint8), (len(ns), 1))
    values = {"stamp": stamp_words(ns), "pose": numbers[:, :7], "twist": numbers[:, 7:13]}
    for name, (offset, dtype) in cdr.columns.items():
        column = np.ascontiguousarray(values[name], dtype.base).reshape(len(ns), -1)
        rows[:, offset : offset + dtype.itemsize] = column.view(np.uint8)
    return rows
