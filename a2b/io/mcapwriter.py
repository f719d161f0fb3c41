"""MCAP files of poses, built a whole chunk at a time with array operations.

The ``mcap`` package's writer costs about 10 µs per message in Python. Here the JSON
payloads of thousands of messages are formatted at once (:mod:`a2b.io.floatrepr`), the
headers of the Message records and the entries of the Message Index records packed with
numpy, and each chunk compressed with zstd in a thread of its own, which gives several hundred
thousand poses per second (docs/benchmarks.md). Every other record (Header, Schema, Channel,
Chunk, Chunk Index, Statistics, Summary Offset, Data End, Footer) is one of the ``mcap``
package's record classes, serialised by its own code.

What is written, in the order of the MCAP specification (https://mcap.dev/spec):

* magic, Header (profile ``""``, library ``a2b <version>``);
* in the data section, one Schema record per message type and one Channel record per topic
  (:func:`write_topic_mcap`: each just before the chunk of its first message), then for each
  chunk of :data:`CHUNK_POSES` poses a Chunk record (zstd, with the CRC-32 of its records), followed
  by one Message Index record per channel; then Data End with the CRC-32 of the data section;
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
from .parallel import in_order

__all__ = ["CHUNK_POSES", "MAGIC", "write_pose_mcap", "write_topic_mcap"]

MAGIC = b"\x89MCAP0\r\n"
_HEADER, _FOOTER, _SCHEMA, _CHANNEL, _MESSAGE, _CHUNK = 0x01, 0x02, 0x03, 0x04, 0x05, 0x06
_MESSAGE_INDEX, _CHUNK_INDEX, _STATISTICS, _SUMMARY_OFFSET, _DATA_END = 0x07, 0x08, 0x0B, 0x0E, 0x0F

#: Poses per chunk: two JSON messages of about 280 bytes each, so chunks of about 2 MB.
CHUNK_POSES = 4096
#: At most this many bytes of message text in one chunk: a long frame id means fewer poses.
CHUNK_BYTES = 8 << 20
#: zstd's fastest regular level; on these messages it also compresses best (about 10:1).
ZSTD_LEVEL = 1

#: A Message record up to its data: opcode, record length, channel id, sequence, log time,
#: publish time.
_MESSAGE_HEAD = np.dtype(
    [("opcode", "u1"), ("length", "<u8"), ("channel", "<u2"), ("sequence", "<u4"),
     ("log_time", "<u8"), ("publish_time", "<u8")]
)  # fmt: skip
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


@dataclass
class _Layout:
    """The messages of a pose, side by side in one row of words.

    ``pose`` (a ``foxglove.PoseInFrame``) and, when there is a child frame, ``tf`` (a
    ``foxglove.FrameTransform`` from the fixed frame to it).
    """

    messages: list

    @classmethod
    def create(cls, frame_id: str, child_frame_id: str | None) -> _Layout:
        frame = json.dumps(frame_id).encode()
        stamp = [b'{"timestamp":{"sec":', "sec", b',"nsec":', "nsec"]
        xyz = [0, b',"y":', 1, b',"z":', 2]
        xyzw = [3, b',"y":', 4, b',"z":', 5, b',"w":', 6]
        pose = stamp + [b'},"frame_id":' + frame + b',"pose":{"position":{"x":', *xyz]
        pose += [b'},"orientation":{"x":', *xyzw, b"}}}"]
        messages = [_Message(pose)]
        if child_frame_id is not None:
            child = json.dumps(child_frame_id).encode()
            tf = stamp + [b'},"parent_frame_id":' + frame + b',"child_frame_id":' + child]
            tf += [b',"translation":{"x":', *xyz, b'},"rotation":{"x":', *xyzw, b"}}"]
            messages.append(_Message(tf, start=len(messages[0].row)))
        return cls(messages)

    @property
    def row(self) -> np.ndarray:
        return np.concatenate([message.row for message in self.messages])


@dataclass
class _Built:
    """One chunk, ready to write: its record, and what its indexes need."""

    record: bytes
    poses: int
    start: int
    end: int
    uncompressed_size: int
    compressed_size: int
    message_indexes: list  # (channel id, Message Index record)
    message_counts: dict  # channel id: messages


def _nanoseconds(t, duration: float, start_time: float) -> np.ndarray:
    times = t * duration + start_time
    if times.size and not (np.isfinite(times).all() and times.min() >= 0):
        bad = times[~(np.isfinite(times) & (times >= 0))][0]
        raise ParameterError(
            f"MCAP times must be finite and not negative; t · duration + start_time reaches "
            f"{bad:g} s"
        )
    ns = np.rint(times * 1e9)
    if ns.size and ns.max() >= 2.0**63:
        raise ParameterError(
            f"MCAP log times must stay below 2**63 ns; {ns.max() / 1e9:g} s is later"
        )
    return ns.astype(np.int64)


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


def _build_chunk(item, layout: _Layout, row: np.ndarray) -> _Built:
    """The Chunk record and the Message Index records of ``item``.

    ``item = (sequence, ns, numbers, channels)``: per pose its sequence number, log time,
    the 7 numbers ``x y z qx qy qz qw`` and the channel id of each message of the layout.
    """
    from mcap.records import Chunk

    sequence, ns, numbers, channels = item
    n, per = len(ns), len(layout.messages)
    sec, nsec = np.divmod(ns, 1_000_000_000)
    number_cells, number_length = number_words(numbers.reshape(-1), lengths=True)
    number_cells = number_cells.reshape(n, 7, 4)
    sec_cells, sec_length = integer_words(sec, lengths=True)
    nsec_cells, nsec_length = integer_words(nsec, lengths=True)
    cells = np.empty((n, len(row)), _U64)
    cells[:] = row
    for message in layout.messages:
        cells[:, message.sec : message.sec + 2] = sec_cells
        cells[:, message.nsec : message.nsec + 2] = nsec_cells
        for j, column in enumerate(message.numbers):
            cells[:, column : column + 4] = number_cells[:, j]
    records = np.frombuffer(without_zero_bytes(cells), np.uint8).copy()
    variable = number_length.reshape(n, 7).sum(axis=1) + sec_length + nsec_length
    data_length = np.empty((n, per), np.int64)  # messages in order: pose, tf, pose, tf, …
    for k, message in enumerate(layout.messages):
        data_length[:, k] = message.const_length + variable
    data_length = data_length.reshape(-1)
    record_length = data_length + _HEAD_SIZE
    offset = np.cumsum(record_length) - record_length
    if offset[-1] + record_length[-1] != records.size:  # pragma: no cover - a bug if it happens
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
    import zstandard

    compressed = zstandard.ZstdCompressor(level=ZSTD_LEVEL).compress(records)
    start, end = int(ns.min()), int(ns.max())
    record = Chunk(
        message_start_time=start,
        message_end_time=end,
        uncompressed_size=int(records.size),
        uncompressed_crc=zlib.crc32(records),
        compression="zstd",
        data=compressed,
    )
    log_time = head["log_time"]
    order = np.argsort(log_time, kind="stable")  # Message Index entries go by log time
    ids, counts = np.unique(head["channel"], return_counts=True)
    by_channel = head["channel"][order]
    message_indexes = []
    for channel in ids.tolist():
        mine = order[by_channel == channel]
        message_indexes.append((channel, _message_index(channel, log_time[mine], offset[mine])))
    return _Built(
        _serialise(record),
        n,
        start,
        end,
        int(records.size),
        len(compressed),
        message_indexes,
        dict(zip(ids.tolist(), counts.tolist())),
    )


class _Output:
    """A stream that counts its bytes and their CRC-32: offsets without ``tell``."""

    def __init__(self, stream: IO):
        self.stream = stream
        self.position = 0
        self.crc = 0

    def write(self, data) -> None:
        self.stream.write(data)
        self.position += len(data)
        self.crc = zlib.crc32(data, self.crc)


def write_pose_mcap(
    stream: IO,
    samples: Iterable[tuple[np.ndarray, np.ndarray, np.ndarray]],
    *,
    duration: float = 1.0,
    start_time: float = 0.0,
    frame_id: str = "world",
    child_frame_id: str = "a2b",
    pose_topic: str = "/a2b/pose",
    tf_topic: str = "/tf",
    schemas: dict[str, bytes],
    library: str = "a2b",
) -> None:
    """Write poses as ``foxglove.PoseInFrame`` and ``foxglove.FrameTransform`` JSON messages.

    Parameters
    ----------
    stream : binary file-like
        Written in order, never sought; not closed.
    samples : iterable of (t, trans, quat_wxyz)
        Arrays of shapes ``(n,)``, ``(n, 3)`` and ``(n, 4)``.
    duration, start_time : float
        Log and publish time of sample ``t``: ``t · duration + start_time`` seconds.
    frame_id, child_frame_id : str
        The pose's frame (also the transform's parent) and the transform's child frame.
    pose_topic, tf_topic : str
        The topics; the messages of one sample share its sequence number.
    schemas : dict
        JSON schema text of ``foxglove.PoseInFrame`` and ``foxglove.FrameTransform``.
    library : str
        The Header record's library field.

    Raises
    ------
    ParameterError
        If a time is negative, not finite, or beyond 2**63 ns, or a pose is not finite.
    """
    from mcap.records import Channel

    channels = [
        Channel(id=1, schema_id=1, topic=pose_topic, message_encoding="json", metadata={}),
        Channel(id=2, schema_id=2, topic=tf_topic, message_encoding="json", metadata={}),
    ]

    layout = _Layout.create(frame_id, child_frame_id)
    size = _chunk_poses(layout)

    def items():
        sequence = 0
        for t, trans, quat_wxyz in samples:
            for ns, numbers in _pieces(t, trans, quat_wxyz, duration, start_time, size):
                n = len(ns)
                if sequence + n > 2**32:
                    raise ParameterError(
                        "MCAP numbers messages with 32-bit sequence numbers: at most 2**32 samples"
                    )
                ids = np.broadcast_to(np.array([1, 2], np.uint16), (n, 2))
                yield np.arange(sequence, sequence + n, dtype=np.uint64), ns, numbers, ids, []
                sequence += n

    _write_file(stream, layout, schemas, library, channels, items())


def write_topic_mcap(
    stream: IO,
    samples: Iterable[tuple],
    *,
    duration: float = 1.0,
    start_time: float = 0.0,
    frame_id: str = "world",
    schemas: dict[str, bytes],
    library: str = "a2b",
) -> None:
    """Write poses as ``foxglove.PoseInFrame`` JSON messages, each run of rows on its topic.

    ``samples`` yields ``(t, trans, quat_wxyz, topics, counts)``: the first ``counts[0]``
    rows go to ``topics[0]``, the next ``counts[1]`` to ``topics[1]``, and so on. A topic's
    Channel record is written before its first message, and each topic counts its own
    sequence numbers from 0. Otherwise as :func:`write_pose_mcap` (no ``/tf``).
    """
    from mcap.records import Channel

    layout = _Layout.create(frame_id, None)
    size = _chunk_poses(layout)
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
                    new.append(
                        Channel(
                            id=ids[topic],
                            schema_id=1,
                            topic=topic,
                            message_encoding="json",
                            metadata={},
                        )
                    )
                first.append(sequences[topic])
                sequences[topic] += count
            counts = np.asarray(counts, np.int64)
            channel = np.repeat(np.array([ids[topic] for topic in topics], np.uint16), counts)
            offset = np.asarray(first, np.int64) - (np.cumsum(counts) - counts)
            sequence = (np.arange(len(channel)) + np.repeat(offset, counts)).astype(np.uint64)
            lo = 0
            for ns, numbers in _pieces(t, trans, quat_wxyz, duration, start_time, size):
                n = len(ns)
                yield sequence[lo : lo + n], ns, numbers, channel[lo : lo + n, None], new
                new, lo = [], lo + n

    _write_file(stream, layout, schemas, library, [], items())


def _write_file(stream: IO, layout: _Layout, schemas: dict, library: str, channels, items):
    """Header, the schemas of ``layout``, ``channels``, then a chunk of each of ``items``
    (after the channels it brings), then the summary and the footer.

    ``items`` yields ``(sequence, ns, numbers, channel ids, new Channel records)``.
    """
    from mcap.records import (
        ChunkIndex,
        DataEnd,
        Footer,
        Header,
        Schema,
        Statistics,
        SummaryOffset,
    )

    out = _Output(stream)
    out.write(MAGIC)
    out.write(_serialise(Header(profile="", library=library)))
    names = ("foxglove.PoseInFrame", "foxglove.FrameTransform")[: len(layout.messages)]
    schema_records = [
        _serialise(Schema(id=k + 1, name=name, encoding="jsonschema", data=schemas[name]))
        for k, name in enumerate(names)
    ]
    channel_records = [_serialise(channel) for channel in channels]
    for record in schema_records + channel_records:
        out.write(record)

    def build(item):
        *chunk, new = item
        return [_serialise(channel) for channel in new], _build_chunk(chunk, layout, layout.row)

    chunk_indexes = []
    counts: dict[int, int] = {}
    first, last = None, None
    for new, built in in_order(build, items):
        for record in new:
            out.write(record)
        channel_records += new
        chunk_start = out.position
        out.write(built.record)
        index_offsets = {}
        for channel, record in built.message_indexes:
            index_offsets[channel] = out.position
            out.write(record)
        chunk_indexes.append(
            ChunkIndex(
                message_start_time=built.start,
                message_end_time=built.end,
                chunk_start_offset=chunk_start,
                chunk_length=len(built.record),
                message_index_offsets=index_offsets,
                message_index_length=out.position - chunk_start - len(built.record),
                compression="zstd",
                compressed_size=built.compressed_size,
                uncompressed_size=built.uncompressed_size,
            )
        )
        for channel, count in built.message_counts.items():
            counts[channel] = counts.get(channel, 0) + count
        first = built.start if first is None else min(first, built.start)
        last = built.end if last is None else max(last, built.end)
    out.write(_serialise(DataEnd(data_section_crc=out.crc)))
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


def _pieces(t, trans, quat_wxyz, duration: float, start_time: float, size: int) -> Iterator[tuple]:
    """``(log times in ns, numbers x y z qx qy qz qw)`` of at most ``size`` poses."""
    ns = _nanoseconds(np.asarray(t, float), duration, start_time)
    numbers = np.column_stack([trans, np.asarray(quat_wxyz)[:, [1, 2, 3, 0]]])
    if not np.isfinite(numbers).all():
        raise ParameterError("MCAP poses must be finite; a sample is NaN or infinite")
    for lo in range(0, len(ns), size):
        yield ns[lo : lo + size], numbers[lo : lo + size]


def _chunk_poses(layout: _Layout) -> int:
    """Poses per chunk: :data:`CHUNK_POSES`, fewer where the messages are long (a long frame
    id), so that a chunk's text stays within :data:`CHUNK_BYTES`."""
    return max(1, min(CHUNK_POSES, CHUNK_BYTES // layout.row.nbytes))
