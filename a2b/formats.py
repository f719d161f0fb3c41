"""The one table of file formats: what each holds, how it is laid out, who reads and writes it.

Free of numpy and of the rest of a2b, like :mod:`a2b.parameters`, so that the command line
builds its ``--format`` and ``--input-format`` choices, its suffix guesses and its help from it
without importing either. Readers and writers are named as ``"module:function"`` strings and
imported only when used (:func:`resolve`).

To add a format, add one :class:`Format` row to :data:`TABLE` and write its module (a writer
``write(stream, samples, **options)`` over :class:`a2b.samples.Samples`, a reader, or both);
then regenerate README's table (``tests/test_formats.py`` says how). docs/architecture.md walks
through an example.
"""

from __future__ import annotations

import importlib
import os
from dataclasses import dataclass, field

__all__ = [
    "BY_NAME",
    "INPUT_NAMES",
    "OUTPUT_NAMES",
    "TABLE",
    "Format",
    "Limits",
    "from_suffix",
    "markdown_table",
    "resolve",
]


@dataclass(frozen=True)
class Limits:
    """What a format's times and counts may be: checked once, by :mod:`a2b.output`.

    ``max_messages``: messages per topic (a uint32 sequence number); ``max_nanoseconds``: the
    latest time in integer nanoseconds (int64); ``non_negative``: times below 0 refused
    (unsigned times); ``stamps``: a function (``"module:function"``) that refuses integer
    nanoseconds its message stamps cannot hold; ``distinct_times``: consecutive times written
    as doubles must differ.
    """

    max_messages: int | None = None
    max_nanoseconds: int | None = None
    non_negative: bool = False
    stamps: str | None = None
    distinct_times: bool = False


#: MCAP numbers messages with a uint32 sequence number and logs unsigned int64 nanoseconds
#: (a2b forms them as int64: below 2**63, the year 2262).
MCAP_LIMITS = Limits(max_messages=2**32, max_nanoseconds=2**63 - 1, non_negative=True)


@dataclass(frozen=True)
class Format:
    """One row of :data:`TABLE`.

    name, suffixes
        The ``--format`` name and the file suffixes that name it (first: the usual one).
    layout
        What a line or message holds, one line of help; ``{times}`` stands for ``times``.
    times
        Where the layout says how its times follow from t (``--duration``,
        ``--start-time``): left out for commands whose times are their own (``resample``).
    holds
        Of ``poses``, ``times``, ``velocities``, ``mark`` (resample's ``original`` column).
    binary
        Binary (not written to a terminal) or text.
    representation
        What the writer needs from a motion: ``quat_trans``, ``matrices`` or ``study``.
    batch
        How ``a2b batch`` lays out many jobs: ``rows`` (a ``job`` column), ``files`` (one file
        per job in a directory) or ``topics`` (one topic per job), or ``None``.
    writer, batch_writer, reader
        ``"module:function"``, or ``None``. A reader takes a binary stream (``euroc``: through
        :func:`a2b.io.trajectories.read_trajectory`, which takes the format).
    options
        The output options the writer takes (others are refused): ``duration`` and
        ``start_time`` (times from t), ``frame_id``, ``child_frame_id``, ``storage`` (the
        storage of a ROS 2 bag: :data:`a2b.output.STORAGES`); ``motion``: the writer states
        the motion (a mapping: mode, parameters, …) in the file's metadata. ``motion`` is not a
        command option: the pipeline gives it, and formats without it are not given it.
    writer_options
        Fixed keyword arguments of the writer (``ros2``: the MCAP profile); ``count`` (the
        number of samples, if known) is passed where it is a key.
    limits, extra
        :class:`Limits`; the pip extra the format needs (``None``: the base install).
    read_as
        The format that reads it back, if not its own reader (``ros2``: ``mcap``).
    header
        The column names of a text table (tum: after ``# ``).
    separator
        The field separator of a text table that the writer formats row by row
        (:func:`a2b.io.writers.chunk_text`), else ``None``.
    trajectory
        What reads the format as a trajectory (``a2b resample``, ``view``, the pose lists of
        ``spline``): for a text format a module with ``layout(data, name, fmt)`` and
        ``trajectory(rows, lines, name, fmt, rate, orthonormalize, row)`` over the rows
        (:mod:`a2b.io.textrows`); for a binary one a ``"module:function"``, ``(source, name,
        topic, child_frame)`` → times, quaternions wxyz and translations, where ``source`` is
        the file's bytes (MCAP) or the path of a bag (rosbag2: a folder or a ``.db3``).
    input_options
        The options of :func:`a2b.io.trajectories.read_trajectory` the format takes (others
        are refused): ``rate`` (times for poses that have none), ``topic``, ``child_frame``,
        ``input_frame``.
    """

    name: str
    suffixes: tuple
    layout: str
    holds: frozenset
    binary: bool
    representation: str | None
    batch: str | None
    writer: str | None
    batch_writer: str | None
    reader: str | None
    options: frozenset = frozenset()
    writer_options: dict = field(default_factory=dict)
    limits: Limits = Limits()
    extra: str | None = None
    read_as: str | None = None
    header: str | None = None
    separator: str | None = None
    trajectory: str | None = None
    input_options: frozenset = frozenset()
    times: str = ""

    def described(self, durations: bool = True) -> str:
        """:attr:`layout`, with how its times follow from t where ``durations``."""
        return self.layout.format(times=self.times if durations else "")

    @property
    def timed(self) -> bool:
        """Whether the format writes times (``tum``, MCAP): ``duration`` and ``start_time``."""
        return "duration" in self.options


#: The output options that name frames, for the formats that hold them (``options``).
FRAME_OPTIONS = ("frame_id", "child_frame_id")

_TEXT = "a2b.io.writers"
_READ = "a2b.io.trajectories"
_STAMPED = frozenset({"duration", "start_time"})
_FRAMED = _STAMPED | set(FRAME_OPTIONS)

_TABLE_ROWS = frozenset({"poses", "times", "velocities", "mark"})
_MCAP = {"writer": f"{_TEXT}:write_mcap", "batch_writer": f"{_TEXT}:write_batch_mcap"}

#: Every format a2b reads or writes, in the order of ``--format``.
TABLE = (
    Format(
        name="csv", suffixes=(".csv",), layout="t,tx,ty,tz,qw,qx,qy,qz", holds=_TABLE_ROWS,
        binary=False, representation="quat_trans", batch="rows",
        writer=f"{_TEXT}:write_csv", batch_writer=f"{_TEXT}:write_batch_csv",
        reader=f"{_READ}:read_csv", header="t,tx,ty,tz,qw,qx,qy,qz", separator=",",
        trajectory="a2b.io.csvtable",
    ),
    Format(
        name="matrix", suffixes=(), layout="t and the 12 entries of [R | t], row by row",
        holds=_TABLE_ROWS, binary=False, representation="matrices", batch="rows",
        writer=f"{_TEXT}:write_matrix_csv", batch_writer=f"{_TEXT}:write_batch_csv",
        reader=f"{_READ}:read_matrix_csv", header="t,r11,r12,r13,tx,r21,r22,r23,ty,r31,r32,r33,tz",
        separator=",", trajectory="a2b.io.csvtable",
    ),
    Format(
        name="study", suffixes=(), layout="t,p0,p1,p2,p3,q0,q1,q2,q3 (unit Study parameters)",
        holds=_TABLE_ROWS, binary=False, representation="study", batch="rows",
        writer=f"{_TEXT}:write_study_csv", batch_writer=f"{_TEXT}:write_batch_csv",
        reader=f"{_READ}:read_study_csv", header="t,p0,p1,p2,p3,q0,q1,q2,q3", separator=",",
        trajectory="a2b.io.csvtable",
    ),
    Format(
        name="tum", suffixes=(".tum",),
        layout="time tx ty tz qx qy qz qw{times}", times=" (time = t · duration + start_time)",
        holds=frozenset({"poses", "times"}), binary=False, representation="quat_trans",
        batch="files", writer=f"{_TEXT}:write_tum", batch_writer=f"{_TEXT}:write_batch_files",
        reader=f"{_READ}:read_tum", options=_STAMPED, limits=Limits(distinct_times=True),
        header="time tx ty tz qx qy qz qw", separator=" ", trajectory="a2b.io.tum",
    ),
    Format(
        name="kitti", suffixes=(".kitti",), layout="12 numbers of [R | t] per line",
        holds=frozenset({"poses"}), binary=False, representation="matrices", batch="files",
        writer=f"{_TEXT}:write_kitti", batch_writer=f"{_TEXT}:write_batch_files",
        reader=f"{_READ}:read_kitti", separator=" ", trajectory="a2b.io.kitti",
        input_options=frozenset({"rate"}),
    ),
    Format(
        name="euroc", suffixes=(), layout="#timestamp [ns],p_x,p_y,p_z,q_w,q_x,q_y,q_z (read only)",
        holds=frozenset({"poses", "times"}), binary=False, representation=None, batch=None,
        writer=None, batch_writer=None, reader=f"{_READ}:read_trajectory",
        trajectory="a2b.io.euroc",
    ),
    Format(
        name="mcap", suffixes=(".mcap",),
        layout="foxglove.PoseInFrame on /a2b/pose and foxglove.FrameTransform on /tf",
        holds=frozenset({"poses", "times"}), binary=True, representation="quat_trans",
        batch="topics", **_MCAP, reader="a2b.io.mcapposes:read_mcap", options=_FRAMED,
        writer_options={"profile": "foxglove", "count": None}, limits=MCAP_LIMITS,
        trajectory="a2b.io.mcapposes:mcap_poses",
        input_options=frozenset({"topic", "child_frame", "input_frame"}),
    ),
    Format(
        name="ros2", suffixes=(),
        layout="MCAP for ROS 2: PoseStamped on /a2b/pose, TFMessage on /tf, a Path at the end",
        holds=frozenset({"poses", "times", "velocities"}), binary=True,
        representation="quat_trans", batch="topics", **_MCAP, reader=None,
        options=_FRAMED | {"storage"}, writer_options={"profile": "ros2", "count": None},
        limits=Limits(2**32, 2**63 - 1, True, "a2b.io.ros2:split_stamps"), read_as="mcap",
    ),
    Format(
        name="protobuf", suffixes=(),
        layout="MCAP of Protobuf foxglove.PoseInFrame on /a2b/pose, FrameTransform on /tf",
        holds=frozenset({"poses", "times"}), binary=True, representation="quat_trans",
        batch="topics", **_MCAP, reader=None, options=_FRAMED,
        writer_options={"profile": "protobuf", "count": None}, limits=MCAP_LIMITS,
        read_as="mcap",
    ),
    Format(
        name="rosbag2", suffixes=(".db3",),
        layout="a ROS 2 bag: a folder with metadata.yaml and its .db3 or .mcap files, or a .db3 "
        "(read only)", holds=frozenset({"poses", "times"}), binary=True, representation=None,
        batch=None, writer=None, batch_writer=None, reader=f"{_READ}:read_trajectory",
        trajectory="a2b.io.rosbag2:bag_poses",
        input_options=frozenset({"topic", "child_frame", "input_frame"}),
    ),
    Format(
        name="parquet", suffixes=(".parquet",),
        layout="columns t{times}, tx,ty,tz,qw,qx,qy,qz as in csv, vx … wz with --velocities, "
        "original with --mark (needs a2b-motions[parquet])",
        times=", time (t · duration + start_time)",
        holds=_TABLE_ROWS, binary=True, representation="quat_trans", batch="rows",
        writer="a2b.io.parquet:write_parquet", batch_writer="a2b.io.parquet:write_batch_parquet",
        reader=None, options=_STAMPED | {"motion"}, extra="parquet",
    ),
)  # fmt: skip

BY_NAME = {row.name: row for row in TABLE}
#: The formats a2b writes (``--format``) and reads as trajectories (``--input-format``).
OUTPUT_NAMES = tuple(row.name for row in TABLE if row.writer is not None)
INPUT_NAMES = tuple(row.name for row in TABLE if row.trajectory is not None)
#: Suffix → format, for guesses from a file name (``.csv`` names the default anyway: left out).
SUFFIXES = {s: row.name for row in TABLE for s in row.suffixes if s != ".csv"}


def from_suffix(path, batch: bool = False) -> tuple[str, str] | None:
    """``(format, suffix)`` of the output format that the suffix of ``path`` names, else
    ``None`` (a format a2b only reads names none).

    With ``batch``, only formats that a batch writes into one file (not a file per job).
    """
    suffix = os.path.splitext(os.fspath(path))[1].lower()
    name = SUFFIXES.get(suffix)
    if name is None or BY_NAME[name].writer is None or (batch and BY_NAME[name].batch == "files"):
        return None
    return name, suffix


def suffix_names(batch: bool = False) -> list[str]:
    """The suffixes that choose an output format (``.tum``), for help texts."""
    return [s for s in SUFFIXES if from_suffix("file" + s, batch)]


def resolve(reference: str):
    """The function that ``"module:function"`` names, imported now."""
    module, _, name = reference.partition(":")
    return getattr(importlib.import_module(module), name)


def markdown_table() -> str:
    """README's table of formats, from :data:`TABLE`."""
    lines = [
        "| format | suffix | holds | kind | `a2b batch` | written | read |",
        "| --- | --- | --- | --- | --- | --- | --- |",
    ]
    batch = {"rows": "a `job` column", "files": "a file per job", "topics": "a topic per job"}
    for row in TABLE:
        holds = ", ".join(h for h in ("poses", "times", "velocities", "mark") if h in row.holds)
        lines.append(
            f"| `{row.name}` | {' '.join(f'`{s}`' for s in row.suffixes) or '–'} | {holds} | "
            f"{'binary' if row.binary else 'text'} | {batch.get(row.batch, '–')} | "
            f"{'yes' if row.writer else 'no'} | "
            f"{'yes' if row.reader else f'as `{row.read_as}`' if row.read_as else 'no'} |"
        )
    return "\n".join(lines) + "\n"
