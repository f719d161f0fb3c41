"""MCAP files of poses, built a whole chunk at a time with array operations.

The ``mcap`` package's writer costs about 10 µs per message in Python. Here the messages of
thousands of poses are made at once, in one of two profiles:

* ``foxglove``: JSON ``foxglove.PoseInFrame`` and ``foxglove.FrameTransform``, their text
  formatted in bulk (:mod:`a2b.io.floatrepr`) — several hundred thousand poses per second;
* ``ros2``: CDR ``geometry_msgs/msg/PoseStamped``, ``tf2_msgs/msg/TFMessage`` and, once,
  ``nav_msgs/msg/Path``, whose layout is fixed, so that a chunk is a numpy structured array
  filled column by column (:mod:`a2b.io.ros2`) — over a million poses per second.

The headers of the Message records and the entries of the Message Index records are packed
with numpy, and each chunk is compressed with zstd in a thread of its own
(docs/benchmarks.md). The Chunk records' heads are packed here too (so that the compressed
data is written without a copy); every other record (Header, Schema, Channel, Chunk Index,
Statistics, Summary Offset, Data End, Footer) is one of the ``mcap`` package's record classes,
serialised by its own code.

What is written, in the order of the MCAP specification (https://mcap.dev/spec):

* magic, Header (profile ``""`` or ``ros2``, library ``a2b <version>``);
* in the data section, one Schema record per message type and one Channel record per topic
  (:func:`write_topic_mcap`: each just before the chunk of its first message), then for each
  chunk of :data:`CHUNK_POSES` (JSON) or :data:`CDR_CHUNK_POSES` poses a Chunk record (zstd,
  with the CRC-32 of its records), followed by one Message Index record per channel; ros2:
  last, the Path's chunk (its log time is the first pose's, so chunks are not in time order,
  which the chunk indexes allow); then Data End, without a CRC of the data section (0, as the
  MCAP C++ writer that rosbag2 uses writes by default: each chunk has its own);
* in the summary section: the Schema and Channel records again, a Statistics record, and a
  Chunk Index record per chunk; then one Summary Offset record per group of the summary;
* Footer (with the CRC-32 of the summary) and magic.

Nothing is ever sought or told: every offset is counted while writing, so the output may
be a pipe. No attachment or metadata indexes are written.
"""

from __future__ import annotations

import json
import struct
import zlib
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from typing import IO

import numpy as np

from ..errors import ParameterError
from .floatrepr import integer_words, number_words, without_zero_bytes
from .mcapreader import MAGIC, MESSAGE_HEAD
from .parallel import in_order

__all__ = ["CHUNK_POSES", "write_pose_mcap", "write_topic_mcap"]

_HEADER, _FOOTER, _SCHEMA, _CHANNEL, _MESSAGE, _CHUNK = 0x01, 0x02, 0x03, 0x04, 0x05, 0x06
_MESSAGE_INDEX, _CHUNK_INDEX, _STATISTICS, _SUMMARY_OFFSET, _DATA_END = 0x07, 0x08, 0x0B, 0x0E, 0x0F

#: Poses per chunk of JSON: two messages of about 280 bytes each, so chunks of about 2 MB.
CHUNK_POSES = 4096
#: Poses per chunk of CDR: about 4 MB (240 bytes a pose); 1.15x faster than 4096, for fewer
#: chunks to handle.
CDR_CHUNK_POSES = 16384
#: At most this many bytes of message text in one chunk: a long frame id means fewer poses.
CHUNK_BYTES = 8 << 20
#: CDR is compressed at zstd's fast level -1: 1.3x faster than level 1 on these messages, for
#: 5% more bytes.
CDR_ZSTD_LEVEL = -1
#: Chunks of more bytes (a long Path) are compressed on two threads.
BIG_CHUNK = 16 << 20
#: zstd's fastest regular level; on these messages it also compresses best (about 10:1).
ZSTD_LEVEL = 1

_MESSAGE_HEAD = MESSAGE_HEAD
_HEAD_SIZE = _MESSAGE_HEAD.itemsize  # 31
_INDEX_ENTRY = np.dtype([("log_time", "<u8"), ("offset", "<u8")])
_U64 = np.uint64


def _record(opcode: int, *fields: bytes) -> bytes:
    body = b"".join(fields)
    return struct.pack("<BQ", opcode, len(body)) + body


def _words(text: bytes) -> np.ndarray:
    """``text`` padded with zero bytes to whole little-endian 64-bit words."""
    return np.frombuffer(text.ljust(-(-len(text) // 8) * 8, b"\0"), "<u8")


class _Message:
    """Where the parts of one JSON message sit in a row of 64-bit words.

    ``parts`` alternate constant text and the names ``sec``, ``nsec`` or a number's index
    0 … 6; the message begins with room for its record header.
    """

    def __init__(self, parts: list, start: int = 0):
        row = [_words(b"\x01" * _HEAD_SIZE)]  # placeholder bytes for the record header
        self.const_length = 0  # characters of constant text
        self.sec = self.nsec = 0
        self.numbers = []
        width = start + len(row[0])  # the column of the next part in the row of the pose
        for part in parts:
            if isinstance(part, bytes):
                row.append(_words(part))
                self.const_length += len(part)
                width += len(row[-1])
            elif part in ("sec", "nsec"):
                setattr(self, part, width)
                row.append(np.zeros(2, _U64))
                width += 2
            else:
                self.numbers.append(width)
                row.append(np.zeros(4, _U64))
                width += 4
        self.row = np.concatenate(row)


class JsonLayout:
    """The messages of a pose as JSON text, side by side in one row of words.

    ``pose`` (a ``foxglove.PoseInFrame``) and, when there is a child frame, ``tf`` (a
    ``foxglove.FrameTransform`` from the fixed frame to it).
    """

    profile = ""
    encoding = "json"
    zstd_level = ZSTD_LEVEL

    def __init__(self, frame_id: str, child_frame_id: str | None):
        frame = json.dumps(frame_id).encode()
        stamp = [b'{"timestamp":{"sec":', "sec", b',"nsec":', "nsec"]
        xyz = [0, b',"y":', 1, b',"z":', 2]
        xyzw = [3, b',"y":', 4, b',"z":', 5, b',"w":', 6]
        pose = stamp + [b'},"frame_id":' + frame + b',"pose":{"position":{"x":', *xyz]
        pose += [b'},"orientation":{"x":', *xyzw, b"}}}"]
        self.messages = [_Message(pose)]
        names = ["foxglove.PoseInFrame"]
        if child_frame_id is not None:
            child = json.dumps(child_frame_id).encode()
            tf = stamp + [b'},"parent_frame_id":' + frame + b',"child_frame_id":' + child]
            tf += [b',"translation":{"x":', *xyz, b'},"rotation":{"x":', *xyzw, b"}}"]
            self.messages.append(_Message(tf, start=len(self.messages[0].row)))
            names.append("foxglove.FrameTransform")
        self.row = np.concatenate([message.row for message in self.messages])
        self.schemas = [(name, "jsonschema", _json_schema(name)) for name in names]
        self.chunk_poses = max(1, min(CHUNK_POSES, CHUNK_BYTES // self.row.nbytes))

    def records(self, sequence, ns, numbers, channels):
        """The Message records of a chunk: their bytes, and per message its offset in them
        and its log time."""
        n, per = len(ns), len(self.messages)
        sec, nsec = np.divmod(ns, 1_000_000_000)
        number_cells, number_length = number_words(numbers.reshape(-1), lengths=True)
        number_cells = number_cells.reshape(n, 7, 4)
        sec_cells, sec_length = integer_words(sec, lengths=True)
        nsec_cells, nsec_length = integer_words(nsec, lengths=True)
        cells = np.empty((n, len(self.row)), _U64)
        cells[:] = self.row
        for message in self.messages:
            cells[:, message.sec : message.sec + 2] = sec_cells
            cells[:, message.nsec : message.nsec + 2] = nsec_cells
            for j, column in enumerate(message.numbers):
                cells[:, column : column + 4] = number_cells[:, j]
        records = np.frombuffer(without_zero_bytes(cells), np.uint8).copy()
        variable = number_length.reshape(n, 7).sum(axis=1) + sec_length + nsec_length
        data_length = np.empty((n, per), np.int64)  # messages in order: pose, tf, pose, tf, …
        for k, message in enumerate(self.messages):
            data_length[:, k] = message.const_length + variable
        data_length = data_length.reshape(-1)
        record_length = data_length + _HEAD_SIZE
        offset = np.cumsum(record_length) - record_length
        if offset[-1] + record_length[-1] != records.size:  # pragma: no cover - a bug if so
            raise AssertionError("MCAP message lengths disagree with the formatted text")
        head = np.empty(n * per, _MESSAGE_HEAD)
        head["opcode"] = _MESSAGE
        head["length"] = data_length + (_HEAD_SIZE - 9)
        head["channel"] = channels.reshape(-1)
        head["sequence"] = np.repeat(sequence, per)
        head["log_time"] = head["publish_time"] = np.repeat(ns, per)
        records[offset[:, None] + np.arange(_HEAD_SIZE)] = head.view(np.uint8).reshape(
            n * per, _HEAD_SIZE
        )
        return records, offset, head["log_time"]


def _json_schema(name: str) -> bytes:
    from importlib.resources import files

    return (files("a2b") / "schemas" / f"{name}.json").read_bytes()


def _record_dtype(parts: list) -> tuple[np.dtype, bytes]:
    """A structured dtype over consecutive MCAP Message records with CDR data, and the bytes
    of one row: ``parts`` are :class:`a2b.io.ros2.Cdr` layouts with room for the record head.

    The fields of record ``k`` are ``k`` + the head's names and the layout's columns.
    """
    fields, template, shift = {}, bytearray(), 0
    for k, cdr in enumerate(parts):
        head = np.zeros((), _MESSAGE_HEAD)
        head["opcode"] = _MESSAGE
        head["length"] = len(cdr.template) - 9
        for name in _MESSAGE_HEAD.names[1:]:
            dtype, offset = _MESSAGE_HEAD.fields[name][:2]
            fields[f"{k}{name}"] = (dtype, shift + offset)
        fields.update(cdr.fields(shift, prefix=str(k)))
        template += head.tobytes() + cdr.template[_HEAD_SIZE:]
        shift += len(cdr.template)
    return _structured(fields, shift), bytes(template)


def _rows(template: bytes, dtype: np.dtype, n: int) -> np.ndarray:
    """``n`` copies of ``template``, as a structured array of ``dtype`` over fresh bytes."""
    return np.tile(np.frombuffer(template, np.uint8), n).view(dtype)


def _fill(rows: np.ndarray, prefix: str, ns: np.ndarray, numbers: np.ndarray) -> None:
    """The ``stamp`` and ``pose`` columns of ``rows``: times ``ns`` and ``numbers``."""
    _fill_stamp(rows, prefix, ns)
    if prefix + "twist" in rows.dtype.names:
        rows[prefix + "twist"] = numbers[:, 7:]
    else:
        rows[prefix + "pose"] = numbers[:, :7]


def _fill_stamp(rows: np.ndarray, prefix: str, ns: np.ndarray) -> None:
    from .ros2 import stamp_words

    rows[prefix + "stamp"] = stamp_words(ns)


def _fill_head(rows: np.ndarray, prefix: str, sequence, ns, channel) -> None:
    rows[prefix + "channel"] = channel
    rows[prefix + "sequence"] = sequence
    rows[prefix + "log_time"] = rows[prefix + "publish_time"] = ns


class CdrLayout:
    """The messages of a pose as ROS 2 CDR: ``geometry_msgs/msg/PoseStamped`` and, when there
    is a child frame, ``tf2_msgs/msg/TFMessage`` with one transform to it. With a ``path``
    (:class:`PathLayout`), each chunk also makes the Path's entries of its poses."""

    profile = "ros2"
    encoding = "cdr"
    zstd_level = CDR_ZSTD_LEVEL

    def __init__(
        self,
        frame_id: str,
        child_frame_id: str | None,
        path: PathLayout | None = None,
        twist: bool = False,
    ):
        from . import ros2

        parts = [ros2.pose_stamped(frame_id, lead=_HEAD_SIZE)]
        types = ["geometry_msgs/PoseStamped"]
        if child_frame_id is not None:
            parts.append(ros2.tf_message(frame_id, child_frame_id, lead=_HEAD_SIZE))
            types.append("tf2_msgs/TFMessage")
        if twist:  # numbers 7 … 12 of a sample: vx vy vz wx wy wz
            parts.append(ros2.twist_stamped(frame_id, lead=_HEAD_SIZE))
            types.append("geometry_msgs/TwistStamped")
        self.dtype, self.template = _record_dtype(parts)
        self.starts = np.cumsum([0] + [len(p.template) for p in parts[:-1]])
        self.schemas = _ros2_schemas(types) + (path.schemas if path else [])
        self.chunk_poses = max(1, min(CDR_CHUNK_POSES, CHUNK_BYTES // len(self.template)))
        self.path = path

    def records(self, sequence, ns, numbers, channels):
        """As :meth:`JsonLayout.records`."""
        rows = _rows(self.template, self.dtype, len(ns))
        for k in range(len(self.starts)):
            _fill_head(rows, str(k), sequence, ns, channels[:, k])
            _fill(rows, str(k), ns, numbers)
        offset = (np.arange(len(ns))[:, None] * self.dtype.itemsize + self.starts).reshape(-1)
        return rows.view(np.uint8), offset, np.repeat(ns, len(self.starts))


def _ros2_schemas(types: list) -> list:
    from .ros2 import schema_name, schema_text

    return [(schema_name(name), "ros2msg", schema_text(name)) for name in types]


class PathLayout:
    """One ``nav_msgs/msg/Path`` of all the poses, at the first pose's time, in a chunk of its
    own at the end of the data.

    Each chunk's PoseStamped entries are made with the chunk (:meth:`entries`, in the
    writer's threads) and handed over in order (:meth:`add`). Once the number of poses is
    known (``count``, given in advance, else at :meth:`finish`), the message's head is made
    and the entries are compressed as they come, one zstd stream, without joining them.
    Every entry but the first starts 8-aligned; the first, whose alignment depends on the
    length of the frame id, is made again with the head.
    """

    profile = "ros2"
    encoding = "cdr"
    zstd_level = CDR_ZSTD_LEVEL

    def __init__(self, frame_id: str, channel: int, count: int | None = None):
        from .ros2 import pose_stamped

        self.frame_id = frame_id
        self.channel = channel
        self.expected = count
        self.schemas = _ros2_schemas(["nav_msgs/Path"])
        self.entry = pose_stamped(frame_id, phase=0)
        self.entry_dtype = _structured(self.entry.fields(), len(self.entry.template))
        self.first = None  # (ns, numbers) of the first pose
        self.count = 0  # poses added
        self.waiting: list = []  # entries added before the head could be made
        self.compressor = None
        self.compressed: list = []
        self.size = self.crc = 0

    def entries(self, ns: np.ndarray, numbers: np.ndarray) -> np.ndarray:
        """The bytes of the 8-aligned PoseStamped entries of poses ``ns``, ``numbers``."""
        rows = _rows(self.entry.template, self.entry_dtype, len(ns))
        _fill(rows, "", ns, numbers)
        return rows.view(np.uint8)

    def add(self, ns: np.ndarray, numbers: np.ndarray, entries: np.ndarray) -> None:
        """The entries of the next poses, ``ns`` and ``numbers``, made by :meth:`entries`."""
        if self.first is None:
            self.first = (ns[:1], numbers[:1])
            entries = entries[len(self.entry.template) :]  # made again with the head
            if self.expected is not None:
                self._start(self.expected)
        self.count += len(ns)
        if self.compressor is None:
            self.waiting.append(entries)
        else:
            self._feed(entries)

    def _start(self, count: int) -> None:
        """Begin the message: the record head, the Path's header and the first entry."""
        import zstandard

        from .ros2 import path_message

        head, first = path_message(self.frame_id, _HEAD_SIZE, count)
        head_dtype, head_template = _record_dtype([head])
        first_row = _rows(first.template, _structured(first.fields(), len(first.template)), 1)
        _fill(first_row, "", *self.first)
        length = len(head_template) + len(first.template) + (count - 1) * len(self.entry.template)
        head_row = _rows(head_template, head_dtype, 1)
        head_row["0length"] = length - 9
        _fill_head(head_row, "0", 0, self.first[0], self.channel)
        _fill_stamp(head_row, "0", self.first[0])
        threads = 2 if length > BIG_CHUNK else 0
        compressor = zstandard.ZstdCompressor(level=self.zstd_level, threads=threads)
        self.compressor = compressor.compressobj(size=length)
        self.start, self.length = int(self.first[0][0]), length
        for part in (head_row.view(np.uint8), first_row.view(np.uint8), *self.waiting):
            self._feed(part)
        self.waiting.clear()

    def _feed(self, data: np.ndarray) -> None:
        self.size += data.size
        self.crc = zlib.crc32(data, self.crc)
        self.compressed.append(self.compressor.compress(data))

    def finish(self) -> _Built | None:
        """The Path's chunk, or None without poses."""
        if self.first is None:
            return None
        if self.compressor is None:
            self._start(self.count)
        self.compressed.append(self.compressor.flush())
        if self.count != (self.expected or self.count) or self.size != self.length:
            raise AssertionError(
                f"a Path of {self.expected} poses was announced, {self.count} came"
            )
        size, start = sum(map(len, self.compressed)), self.start
        index = _message_index(self.channel, np.array([start]), np.zeros(1, np.int64))
        return _Built(
            _chunk_head(start, start, self.size, self.crc, size),
            self.compressed,
            1,
            start,
            start,
            self.size,
            size,
            [(self.channel, index)],
            {self.channel: 1},
        )


def _structured(fields: dict, itemsize: int) -> np.dtype:
    """The numpy dtype of ``fields`` ``{name: (dtype, offset)}`` in rows of ``itemsize``."""
    names = list(fields)
    return np.dtype(
        {
            "names": names,
            "formats": [fields[n][0] for n in names],
            "offsets": [fields[n][1] for n in names],
            "itemsize": itemsize,
        }
    )


@dataclass
class _Built:
    """One chunk, ready to write: its record (a head, then the compressed records), and what
    its indexes need."""

    head: bytes
    data: list  # the compressed records, in pieces
    poses: int
    start: int
    end: int
    uncompressed_size: int
    compressed_size: int
    message_indexes: list  # (channel id, Message Index record)
    message_counts: dict  # channel id: messages
    path_entries: tuple | None = None  # ros2: (ns, numbers, the Path's entries) of the poses

    @property
    def length(self) -> int:
        return len(self.head) + self.compressed_size


def _serialise(record) -> bytes:
    """The bytes of one of the ``mcap`` package's record objects."""
    from mcap.data_stream import RecordBuilder

    builder = RecordBuilder()
    record.write(builder)
    return builder.end()


def _message_index(channel: int, log_time: np.ndarray, offset: np.ndarray) -> bytes:
    """A Message Index record, its entries packed with numpy (the ``mcap`` package's
    ``MessageIndex`` writes them one by one in Python, about 1 µs each)."""
    entries = np.empty(len(log_time), _INDEX_ENTRY)
    entries["log_time"] = log_time
    entries["offset"] = offset
    return _record(_MESSAGE_INDEX, struct.pack("<HI", channel, entries.nbytes), entries.tobytes())


def _chunk_head(start: int, end: int, size: int, crc: int, compressed: int) -> bytes:
    """A zstd Chunk record up to its data, which is written after it without another copy."""
    head = struct.pack("<QQQI", start, end, size, crc)
    head += struct.pack("<I", 4) + b"zstd" + struct.pack("<Q", compressed)
    return struct.pack("<BQ", _CHUNK, len(head) + compressed) + head


def _build_chunk(item) -> _Built:
    """The Chunk record and the Message Index records of ``item``.

    ``item = (layout, sequence, ns, numbers, channels)``: per pose its sequence number, log
    time, the 7 numbers ``x y z qx qy qz qw`` and the channel id of each message of the layout.
    """
    layout, sequence, ns, numbers, channels = item
    records, offset, log_time = layout.records(sequence, ns, numbers, channels)
    channel = np.asarray(channels).reshape(-1)
    import zstandard

    threads = 2 if records.size > BIG_CHUNK else 0  # a Path of many poses: zstd's own threads
    level = layout.zstd_level
    compressed = zstandard.ZstdCompressor(level=level, threads=threads).compress(records)
    start, end = int(log_time.min()), int(log_time.max())
    path = getattr(layout, "path", None)
    head = _chunk_head(start, end, records.size, zlib.crc32(records), len(compressed))
    order = np.argsort(log_time, kind="stable")  # Message Index entries go by log time
    ids, counts = np.unique(channel, return_counts=True)
    by_channel = channel[order]
    message_indexes = []
    for k in ids.tolist():
        mine = order[by_channel == k]
        message_indexes.append((k, _message_index(k, log_time[mine], offset[mine])))
    return _Built(
        head,
        [compressed],
        len(ns),
        start,
        end,
        int(records.size),
        len(compressed),
        message_indexes,
        dict(zip(ids.tolist(), counts.tolist())),
        None if path is None else (ns, numbers, path.entries(ns, numbers)),
    )


class _Output:
    """A stream that counts its bytes: offsets without ``tell``."""

    def __init__(self, stream: IO):
        self.stream = stream
        self.position = 0

    def write(self, data) -> None:
        self.stream.write(data)
        self.position += len(data)


def write_pose_mcap(
    stream: IO,
    samples: Iterable[tuple[np.ndarray, np.ndarray, np.ndarray]],
    *,
    frame_id: str = "world",
    child_frame_id: str = "a2b",
    profile: str = "foxglove",
    pose_topic: str = "/a2b/pose",
    tf_topic: str = "/tf",
    path_topic: str = "/a2b/path",
    twist_topic: str | None = None,
    library: str = "a2b",
    count: int | None = None,
) -> None:
    """Write each pose as a message on ``pose_topic`` and a transform on ``tf_topic``.

    Parameters
    ----------
    stream : binary file-like
        Written in order, never sought; not closed.
    samples : iterable of (ns, trans, quat_wxyz) or (ns, trans, quat_wxyz, twist)
        Arrays of shapes ``(n,)``, ``(n, 3)``, ``(n, 4)`` and ``(n, 6)``: ``ns`` the log and
        publish time (and stamp) in integer nanoseconds, within the limits of the format
        (:func:`a2b.output.check_times`); the twist (ros2 with ``twist_topic`` only) becomes
        a ``geometry_msgs/msg/TwistStamped`` in ``frame_id``.
    frame_id, child_frame_id : str
        The pose's frame (also the transform's parent) and the transform's child frame.
    profile : str
        ``foxglove``: JSON ``foxglove.PoseInFrame`` and ``foxglove.FrameTransform``;
        ``protobuf``: the same Protobuf-encoded (:class:`a2b.io.protobuf.ProtobufLayout`). ``ros2``:
        CDR ``geometry_msgs/msg/PoseStamped`` and ``tf2_msgs/msg/TFMessage``, and one
        ``nav_msgs/msg/Path`` of every pose on ``path_topic`` at the first pose's time, in a
        last chunk (:class:`PathLayout`).
    pose_topic, tf_topic, path_topic : str
        The topics; the messages of one sample share its sequence number.
    library : str
        The Header record's library field.
    count : int, optional
        ros2: the number of poses, if known in advance: the Path is then compressed as the
        poses come; else its entries wait in memory, 80 bytes a pose, until the end.

    Raises
    ------
    ParameterError
        If a pose is not finite.
    """
    ros2 = profile == "ros2"
    if twist_topic is not None and not ros2:
        raise ParameterError("velocities go into MCAP as ROS 2 TwistStamped: use the ros2 profile")
    moving = twist_topic is not None
    path = PathLayout(frame_id, 3 + moving, count) if ros2 else None
    layout = CdrLayout(frame_id, child_frame_id, path, twist=moving) if ros2 else None
    layout = layout or _layout(profile)(frame_id, child_frame_id)
    topics = [(pose_topic, 10, 2), (tf_topic, 100, 2)] + [(twist_topic, 10, 2)] * moving
    topics += [(path_topic, 1, 1)] * ros2
    channels = _channels(layout, topics)
    own = np.arange(1, 3 + moving, dtype=np.uint16)

    def items():
        sequence = 0
        for sample in samples:
            t, trans, quat_wxyz = sample[:3]
            twist = sample[3] if moving else None
            for ns, numbers in _pieces(t, trans, quat_wxyz, layout, twist):
                n = len(ns)
                ids = np.broadcast_to(own, (n, len(own)))
                yield layout, np.arange(sequence, sequence + n, dtype=np.uint64), ns, numbers, ids
                sequence += n

    _write_file(stream, layout, library, channels, ((item, []) for item in items()))


def _layout(profile: str):
    """The layout of the JSON (``foxglove``) or ``protobuf`` profile."""
    if profile == "protobuf":
        from .protobuf import ProtobufLayout

        return ProtobufLayout
    return JsonLayout


def _channels(layout, topics: list) -> list:
    """The Channel records of ``topics``, ``(topic, QoS depth, durability)`` (ros2), one per
    schema of the layout, in order."""
    from mcap.records import Channel

    from .ros2 import qos_profiles

    channels = []
    for k, (topic, depth, durability) in enumerate(topics):
        metadata = {}
        if layout.profile == "ros2":
            metadata = {"offered_qos_profiles": qos_profiles(depth, durability)}
        channels.append(
            Channel(
                id=k + 1,
                schema_id=k + 1,
                topic=topic,
                message_encoding=layout.encoding,
                metadata=metadata,
            )
        )
    return channels


def write_topic_mcap(
    stream: IO,
    samples: Iterable[tuple],
    *,
    frame_id: str = "world",
    profile: str = "foxglove",
    library: str = "a2b",
) -> None:
    """Write poses as ``foxglove.PoseInFrame`` (JSON) or ``geometry_msgs/msg/PoseStamped``
    (ros2) messages, each run of rows on its topic.

    ``samples`` yields ``(ns, trans, quat_wxyz, topics, counts)``: the first ``counts[0]``
    rows go to ``topics[0]``, the next ``counts[1]`` to ``topics[1]``, and so on. A topic's
    Channel record is written before its first message, and each topic counts its own
    sequence numbers from 0. Otherwise as :func:`write_pose_mcap` (no ``/tf``, no Path).
    """
    layout = (CdrLayout if profile == "ros2" else _layout(profile))(frame_id, None)
    ids: dict[str, int] = {}  # topic: channel id
    sequences: dict[str, int] = {}  # topic: messages so far

    def items():
        for t, trans, quat_wxyz, topics, counts in samples:
            new, first = [], []
            for topic, count in zip(topics, counts):
                if topic not in ids:
                    if len(ids) >= 65535:
                        raise ParameterError("MCAP has room for at most 65535 topics")
                    ids[topic] = len(ids) + 1
                    sequences[topic] = 0
                    channel = _channels(layout, [(topic, 10, 2)])[0]
                    channel.id = ids[topic]
                    new.append(channel)
                first.append(sequences[topic])
                sequences[topic] += count
            counts = np.asarray(counts, np.int64)
            channel = np.repeat(np.array([ids[topic] for topic in topics], np.uint16), counts)
            offset = np.asarray(first, np.int64) - (np.cumsum(counts) - counts)
            sequence = (np.arange(len(channel)) + np.repeat(offset, counts)).astype(np.uint64)
            lo = 0
            for ns, numbers in _pieces(t, trans, quat_wxyz, layout):
                n = len(ns)
                item = (layout, sequence[lo : lo + n], ns, numbers, channel[lo : lo + n, None])
                yield item, new
                new, lo = [], lo + n

    _write_file(stream, layout, library, [], items())


def _write_file(stream: IO, layout, library: str, channels, items):
    """Header, the schemas of ``layout``, ``channels``, then a chunk of each of ``items``
    (after the channels it brings), then (ros2) the Path's chunk, the summary and the footer.

    ``items`` yields ``((layout, sequence, ns, numbers, channel ids), new Channel records)``.
    """
    from mcap.records import Header, Schema

    out = _Output(stream)
    out.write(MAGIC)
    out.write(_serialise(Header(profile=layout.profile, library=library)))
    schema_records = [
        _serialise(Schema(id=k + 1, name=name, encoding=encoding, data=data))
        for k, (name, encoding, data) in enumerate(layout.schemas)
    ]
    channel_records = [_serialise(channel) for channel in channels]
    for record in schema_records + channel_records:
        out.write(record)
    data = _write_chunks(out, layout, items, channel_records)
    _write_summary(out, schema_records, channel_records, *data)


def _write_chunks(out: _Output, layout, items, channel_records: list) -> tuple:
    """The data section: each chunk built from ``items`` (on a second thread), after the new
    channels it brings (added to ``channel_records``), with its message indexes; then
    DataEnd. Returns ``(chunk indexes, message counts by channel, first and last time)``."""
    from mcap.records import ChunkIndex, DataEnd

    def build(item):
        chunk, new = item
        return [_serialise(channel) for channel in new], _build_chunk(chunk)

    def built_chunks():
        path = getattr(layout, "path", None)
        for new, built in in_order(build, items):
            if path is not None:
                path.add(*built.path_entries)
            yield new, built
        last = path.finish() if path is not None else None
        if last is not None:
            yield [], last

    chunk_indexes = []
    counts: dict[int, int] = {}
    first, last = None, None
    for new, built in built_chunks():
        for record in new:
            out.write(record)
        channel_records += new
        chunk_start = out.position
        out.write(built.head)
        for piece in built.data:
            out.write(piece)
        index_offsets = {}
        for channel, record in built.message_indexes:
            index_offsets[channel] = out.position
            out.write(record)
        chunk_indexes.append(
            ChunkIndex(
                message_start_time=built.start,
                message_end_time=built.end,
                chunk_start_offset=chunk_start,
                chunk_length=built.length,
                message_index_offsets=index_offsets,
                message_index_length=out.position - chunk_start - built.length,
                compression="zstd",
                compressed_size=built.compressed_size,
                uncompressed_size=built.uncompressed_size,
            )
        )
        for channel, count in built.message_counts.items():
            counts[channel] = counts.get(channel, 0) + count
        first = built.start if first is None else min(first, built.start)
        last = built.end if last is None else max(last, built.end)
    out.write(_serialise(DataEnd(data_section_crc=0)))  # not computed: each chunk has its CRC
    return chunk_indexes, counts, first, last


def _write_summary(out: _Output, schema_records, channel_records, chunk_indexes, counts,
                   first, last) -> None:  # fmt: skip
    """The summary section (schemas, channels, statistics, chunk indexes), its offsets, the
    footer with the summary's CRC, and the closing magic."""
    from mcap.records import Footer, Statistics, SummaryOffset

    statistics = Statistics(
        message_count=sum(counts.values()),
        schema_count=len(schema_records),
        channel_count=len(channel_records),
        attachment_count=0,
        metadata_count=0,
        chunk_count=len(chunk_indexes),
        message_start_time=first or 0,
        message_end_time=last or 0,
        channel_message_counts=counts,
    )
    summary_start = out.position
    summary = bytearray()
    offsets = []
    groups = [(_SCHEMA, schema_records), (_CHANNEL, channel_records)]
    groups += [(_STATISTICS, [_serialise(statistics)])]
    groups += [(_CHUNK_INDEX, [_serialise(c) for c in chunk_indexes])] if chunk_indexes else []
    for opcode, records in groups:
        group_start = summary_start + len(summary)
        for record in records:
            summary += record
        offsets.append(
            SummaryOffset(
                group_opcode=opcode,
                group_start=group_start,
                group_length=summary_start + len(summary) - group_start,
            )
        )
    summary_offset_start = summary_start + len(summary)
    for record in offsets:
        summary += _serialise(record)
    footer = Footer(
        summary_start=summary_start, summary_offset_start=summary_offset_start, summary_crc=0
    )
    head = _serialise(footer)[:-4]  # the CRC covers the summary and the footer up to itself
    footer.summary_crc = zlib.crc32(head, zlib.crc32(summary))
    out.write(bytes(summary))
    out.write(_serialise(footer))
    out.write(MAGIC)


def _pieces(ns, trans, quat_wxyz, layout, twist=None) -> Iterator[tuple]:
    """``(log times in ns, numbers x y z qx qy qz qw [vx vy vz wx wy wz])`` of at most
    ``layout.chunk_poses`` poses."""
    numbers = np.column_stack(
        [trans, np.asarray(quat_wxyz)[:, [1, 2, 3, 0]]] + ([] if twist is None else [twist])
    )
    if not np.isfinite(numbers).all():
        raise ParameterError("MCAP poses must be finite; a sample is NaN or infinite")
    size = layout.chunk_poses
    for lo in range(0, len(ns), size):
        yield ns[lo : lo + size], numbers[lo : lo + size]
