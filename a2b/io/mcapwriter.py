"""MCAP files of poses, built a whole chunk at a time with array operations.

The ``mcap`` package's writer costs about 10 µs per message in Python. Here the JSON
payloads of thousands of messages are formatted at once (:mod:`a2b.io.floatrepr`), the
binary record headers packed with numpy, and each chunk compressed with zstd in a thread of
its own, which gives several hundred thousand poses per second.

What is written, in the order of the MCAP specification (https://mcap.dev/spec):

* magic, Header (profile ``""``, library ``a2b <version>``);
* in the data section, one Schema and one Channel record per topic, then for each chunk of
  :data:`CHUNK_POSES` poses a Chunk record (zstd, with the CRC-32 of its records), followed
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
from functools import partial
from typing import IO

import numpy as np

from ..errors import ParameterError
from .floatrepr import integer_words, number_words
from .parallel import in_order

__all__ = ["CHUNK_POSES", "MAGIC", "write_pose_mcap"]

MAGIC = b"\x89MCAP0\r\n"
_HEADER, _FOOTER, _SCHEMA, _CHANNEL, _MESSAGE, _CHUNK = 0x01, 0x02, 0x03, 0x04, 0x05, 0x06
_MESSAGE_INDEX, _CHUNK_INDEX, _STATISTICS, _SUMMARY_OFFSET, _DATA_END = 0x07, 0x08, 0x0B, 0x0E, 0x0F

#: Poses per chunk: two JSON messages of about 280 bytes each, so chunks of about 2 MB.
CHUNK_POSES = 4096
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


def _string(text: str | bytes) -> bytes:
    data = text.encode() if isinstance(text, str) else text
    return struct.pack("<I", len(data)) + data


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
    """The two messages of a pose, side by side in one row of words."""

    pose: _Message
    tf: _Message

    @classmethod
    def create(cls, frame_id: str, child_frame_id: str) -> _Layout:
        frame, child = json.dumps(frame_id).encode(), json.dumps(child_frame_id).encode()
        stamp = [b'{"timestamp":{"sec":', "sec", b',"nsec":', "nsec"]
        xyz = [0, b',"y":', 1, b',"z":', 2]
        xyzw = [3, b',"y":', 4, b',"z":', 5, b',"w":', 6]
        pose = stamp + [b'},"frame_id":' + frame + b',"pose":{"position":{"x":', *xyz]
        pose += [b'},"orientation":{"x":', *xyzw, b"}}}"]
        tf = stamp + [b'},"parent_frame_id":' + frame + b',"child_frame_id":' + child]
        tf += [b',"translation":{"x":', *xyz, b'},"rotation":{"x":', *xyzw, b"}}"]
        first = _Message(pose)
        return cls(first, _Message(tf, start=len(first.row)))

    @property
    def row(self) -> np.ndarray:
        return np.concatenate([self.pose.row, self.tf.row])


@dataclass
class _Built:
    """One chunk, ready to write: its record in pieces, and what its indexes need."""

    pieces: list
    poses: int
    start: int
    end: int
    uncompressed_size: int
    compressed_size: int
    message_indexes: list  # (channel id, Message Index record body)


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


def _build_chunk(item, layout: _Layout, row: np.ndarray, channels: tuple[int, int]) -> _Built:
    """The Chunk record and the Message Index records of ``item = (sequence, ns, numbers)``."""
    sequence, ns, numbers = item
    n = len(ns)
    sec, nsec = np.divmod(ns, 1_000_000_000)
    number_cells, number_length = number_words(numbers.reshape(-1), lengths=True)
    number_cells = number_cells.reshape(n, 7, 4)
    sec_cells, sec_length = integer_words(sec, lengths=True)
    nsec_cells, nsec_length = integer_words(nsec, lengths=True)
    cells = np.empty((n, len(row)), _U64)
    cells[:] = row
    for message in (layout.pose, layout.tf):
        cells[:, message.sec : message.sec + 2] = sec_cells
        cells[:, message.nsec : message.nsec + 2] = nsec_cells
        for j, column in enumerate(message.numbers):
            cells[:, column : column + 4] = number_cells[:, j]
    records = np.frombuffer(cells.tobytes().translate(None, b"\0"), np.uint8).copy()
    variable = number_length.reshape(n, 7).sum(axis=1) + sec_length + nsec_length
    data_length = np.empty(2 * n, np.int64)  # messages in order: pose, tf, pose, tf, …
    data_length[0::2] = layout.pose.const_length + variable
    data_length[1::2] = layout.tf.const_length + variable
    record_length = data_length + _HEAD_SIZE
    offset = np.cumsum(record_length) - record_length
    if offset[-1] + record_length[-1] != records.size:  # pragma: no cover - a bug if it happens
        raise AssertionError("MCAP message lengths disagree with the formatted text")
    head = np.empty(2 * n, _MESSAGE_HEAD)
    head["opcode"] = _MESSAGE
    head["length"] = data_length + (_HEAD_SIZE - 9)
    head["channel"] = np.tile(channels, n)
    head["sequence"] = np.repeat(np.arange(sequence, sequence + n, dtype=np.uint64), 2)
    head["log_time"] = head["publish_time"] = np.repeat(ns, 2)
    records[offset[:, None] + np.arange(_HEAD_SIZE)] = head.view(np.uint8).reshape(
        2 * n, _HEAD_SIZE
    )
    crc = zlib.crc32(records)
    import zstandard

    compressed = zstandard.ZstdCompressor(level=ZSTD_LEVEL).compress(records)
    start, end = int(ns.min()), int(ns.max())
    chunk_head = struct.pack("<QQQI", start, end, records.size, crc) + _string("zstd")
    chunk_head += struct.pack("<Q", len(compressed))
    pieces = [
        struct.pack("<BQ", _CHUNK, len(chunk_head) + len(compressed)) + chunk_head,
        compressed,
    ]
    order = np.argsort(ns, kind="stable") if (np.diff(ns) < 0).any() else slice(None)
    message_indexes = []
    for k, channel in enumerate(channels):
        entries = np.empty(n, _INDEX_ENTRY)
        entries["log_time"] = ns[order]
        entries["offset"] = offset[k::2][order]
        body = struct.pack("<HI", channel, entries.nbytes) + entries.tobytes()
        message_indexes.append((channel, body))
    return _Built(pieces, n, start, end, int(records.size), len(compressed), message_indexes)


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
    out = _Output(stream)
    out.write(MAGIC)
    out.write(_record(_HEADER, _string(""), _string(library)))
    names = ("foxglove.PoseInFrame", "foxglove.FrameTransform")
    schema_records = [
        _record(
            _SCHEMA,
            struct.pack("<H", k + 1),
            _string(name),
            _string("jsonschema"),
            _string(schemas[name]),
        )
        for k, name in enumerate(names)
    ]
    channel_records = [
        _record(
            _CHANNEL,
            struct.pack("<HH", k + 1, k + 1),
            _string(topic),
            _string("json"),
            struct.pack("<I", 0),
        )
        for k, topic in enumerate((pose_topic, tf_topic))
    ]
    for record in schema_records + channel_records:
        out.write(record)
    layout = _Layout.create(frame_id, child_frame_id)
    build = partial(_build_chunk, layout=layout, row=layout.row, channels=(1, 2))
    chunk_indexes = []
    count, first, last = 0, None, None
    for built in in_order(build, _batches(samples, duration, start_time)):
        chunk_start = out.position
        for piece in built.pieces:
            out.write(piece)
        chunk_length = out.position - chunk_start
        index_offsets = []
        for channel, body in built.message_indexes:
            index_offsets.append(struct.pack("<HQ", channel, out.position))
            out.write(_record(_MESSAGE_INDEX, body))
        chunk_indexes.append(
            _record(
                _CHUNK_INDEX,
                struct.pack("<QQQQ", built.start, built.end, chunk_start, chunk_length),
                struct.pack("<I", 10 * len(index_offsets)),
                *index_offsets,
                struct.pack("<Q", out.position - chunk_start - chunk_length),
                _string("zstd"),
                struct.pack("<QQ", built.compressed_size, built.uncompressed_size),
            )
        )
        count += built.poses
        first = built.start if first is None else min(first, built.start)
        last = built.end if last is None else max(last, built.end)
    out.write(_record(_DATA_END, struct.pack("<I", out.crc)))
    statistics = _record(
        _STATISTICS,
        struct.pack("<QHIIIIQQ", 2 * count, 2, 2, 0, 0, len(chunk_indexes), first or 0, last or 0),
        struct.pack("<I", 20),
        struct.pack("<HQHQ", 1, count, 2, count),
    )
    summary_start = out.position
    summary = bytearray()
    offsets = []
    groups = [(_SCHEMA, schema_records), (_CHANNEL, channel_records), (_STATISTICS, [statistics])]
    groups += [(_CHUNK_INDEX, chunk_indexes)] if chunk_indexes else []
    for opcode, records in groups:
        group_start = summary_start + len(summary)
        for record in records:
            summary += record
        offsets.append(
            _record(
                _SUMMARY_OFFSET,
                struct.pack(
                    "<BQQ", opcode, group_start, summary_start + len(summary) - group_start
                ),
            )
        )
    summary_offset_start = summary_start + len(summary)
    for record in offsets:
        summary += record
    footer_head = struct.pack("<BQQQ", _FOOTER, 20, summary_start, summary_offset_start)
    summary_crc = zlib.crc32(footer_head, zlib.crc32(summary))
    out.write(bytes(summary))
    out.write(footer_head + struct.pack("<I", summary_crc))
    out.write(MAGIC)


def _batches(samples, duration: float, start_time: float) -> Iterator[tuple]:
    """``(first sequence number, log times in ns, numbers)`` of at most CHUNK_POSES poses."""
    sequence = 0
    for t, trans, quat_wxyz in samples:
        ns = _nanoseconds(np.asarray(t, float), duration, start_time)
        numbers = np.column_stack([trans, np.asarray(quat_wxyz)[:, [1, 2, 3, 0]]])
        if not np.isfinite(numbers).all():
            raise ParameterError("MCAP poses must be finite; a sample is NaN or infinite")
        if sequence + len(ns) > 2**32:
            raise ParameterError(
                "MCAP numbers messages with 32-bit sequence numbers: at most 2**32 samples"
            )
        for lo in range(0, len(ns), CHUNK_POSES):
            part = ns[lo : lo + CHUNK_POSES]
            yield sequence, part, numbers[lo : lo + CHUNK_POSES]
            sequence += len(part)
