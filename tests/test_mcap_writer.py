"""The bulk MCAP writer, read back by the ``mcap`` package, the reference reader.

Schemas, channels, statistics, counts, times, sequence numbers and payloads (byte for byte
against messages formatted one at a time with ``repr``); every CRC; every chunk index,
message index and summary offset checked against the records they point to; pipes.
"""

from __future__ import annotations

import io
import json
import struct
import zlib

import numpy as np
import pytest
from mcap.reader import make_reader
from mcap.records import Chunk, ChunkIndex, DataEnd, Footer, MessageIndex, SummaryOffset
from mcap.stream_reader import StreamReader, breakup_chunk

from a2b.errors import A2bError, ParameterError
from a2b.io import mcapwriter, parallel, writers
from a2b.io.mcapreader import MAGIC
from a2b.output import stamped, write
from a2b.samples import Samples

from .conftest import NonSeekableStream


def _samples(rng, n, sizes):
    t = np.sort(rng.random(n))
    t[0], t[-1] = 0.0, 1.0
    quat = rng.normal(size=(n, 4))
    quat /= np.linalg.norm(quat, axis=1, keepdims=True)
    special = np.array([[1, 0, 0, 0], [0, 0, 0, 1], [-0.0, 0.5, -0.5, 1e-300]])  # zeros, -0.0, tiny
    quat[:3] = special[: min(n, 3)]
    trans = rng.normal(size=(n, 3)) * 10.0 ** rng.integers(-8, 8, (n, 3))
    chunks, lo = [], 0
    for size in sizes:
        chunks.append(
            Samples(t[lo : lo + size], quat_wxyz=quat[lo : lo + size], trans=trans[lo : lo + size])
        )
        lo += size
    assert lo == n
    return chunks, t, quat, trans


def _write(chunks, duration=1.0, start_time=0.0, **options) -> bytes:
    """MCAP of ``chunks`` through the library's pipeline, times ``t · duration + start_time``."""
    stream = io.BytesIO()
    write(list(stamped(chunks, duration, start_time)), stream, "mcap", **options)
    return stream.getvalue()


def _expected_payloads(t, quat, trans, duration, start_time, frame_id, child_frame_id):
    """The messages formatted one at a time, as the writer did before it worked in bulk."""
    frame, child = json.dumps(frame_id), json.dumps(child_frame_id)
    pose, tf = [], []
    for k in range(len(t)):
        ns = int(np.rint((t[k] * duration + start_time) * 1e9))
        sec, nsec = divmod(ns, 10**9)
        x, y, z = (repr(float(v)) for v in trans[k])
        qw, qx, qy, qz = (repr(float(v)) for v in quat[k])
        stamp = f'{{"timestamp":{{"sec":{sec},"nsec":{nsec}}}'
        pose.append(
            f'{stamp},"frame_id":{frame},"pose":{{"position":{{"x":{x},"y":{y},"z":{z}}},'
            f'"orientation":{{"x":{qx},"y":{qy},"z":{qz},"w":{qw}}}}}}}'.encode()
        )
        tf.append(
            f'{stamp},"parent_frame_id":{frame},"child_frame_id":{child},'
            f'"translation":{{"x":{x},"y":{y},"z":{z}}},"rotation":{{"x":{qx},"y":{qy},"z":{qz},"w":{qw}}}}}'.encode()
        )
    return pose, tf


@pytest.mark.parametrize("workers", [1, 2])
@pytest.mark.parametrize("sizes", [[1], [5, 3], [4096], [3000, 6000, 1]])
def test_official_reader_sees_every_message(rng, monkeypatch, workers, sizes):
    monkeypatch.setattr(parallel, "WORKERS", workers)
    n = sum(sizes)
    chunks, t, quat, trans = _samples(rng, n, sizes)
    data = _write(
        chunks, duration=2.5, start_time=1.7e9, frame_id='odom "1"', child_frame_id="bödy"
    )
    want_pose, want_tf = _expected_payloads(t, quat, trans, 2.5, 1.7e9, 'odom "1"', "bödy")
    want_ns = np.rint((t * 2.5 + 1.7e9) * 1e9).astype(np.int64)

    reader = make_reader(io.BytesIO(data))
    summary = reader.get_summary()
    schemas = {s.id: s for s in summary.schemas.values()}
    channels = {c.topic: c for c in summary.channels.values()}
    assert set(channels) == {"/a2b/pose", "/tf"}
    assert {c.message_encoding for c in channels.values()} == {"json"}
    assert schemas[channels["/a2b/pose"].schema_id].name == "foxglove.PoseInFrame"
    assert schemas[channels["/tf"].schema_id].name == "foxglove.FrameTransform"
    for schema in schemas.values():
        assert schema.encoding == "jsonschema"
        assert schema.data == mcapwriter._json_schema(schema.name)
    stats = summary.statistics
    assert stats.message_count == 2 * n and stats.chunk_count == len(summary.chunk_indexes)
    assert stats.channel_message_counts == {c.id: n for c in channels.values()}
    assert (stats.message_start_time, stats.message_end_time) == (want_ns.min(), want_ns.max())
    assert stats.schema_count == 2 and stats.channel_count == 2
    assert not summary.attachment_indexes and not summary.metadata_indexes

    got = {"/a2b/pose": [], "/tf": []}
    for schema, channel, message in reader.iter_messages(log_time_order=False):
        got[channel.topic].append(
            (message.log_time, message.publish_time, message.sequence, message.data)
        )
    for topic, want in (("/a2b/pose", want_pose), ("/tf", want_tf)):
        assert [g[3] for g in got[topic]] == want
        assert [g[0] for g in got[topic]] == want_ns.tolist()
        assert [g[1] for g in got[topic]] == want_ns.tolist()
        assert [g[2] for g in got[topic]] == list(range(n))
    parsed = json.loads(got["/tf"][-1][3])
    assert parsed["child_frame_id"] == "bödy" and parsed["parent_frame_id"] == 'odom "1"'
    assert parsed["rotation"]["w"] == quat[-1, 0]  # bit for bit


def _records(data: bytes):
    """Every record of the file with its offset; the reference reader checks the CRCs."""
    parsed = list(StreamReader(io.BytesIO(data), emit_chunks=True, validate_crcs=True).records)
    offsets, position = [], len(MAGIC)
    while position < len(data) - len(MAGIC):
        offsets.append(position)
        position += 1 + 8 + struct.unpack_from("<Q", data, position + 1)[0]
    assert position == len(data) - len(MAGIC) and len(offsets) == len(parsed)
    return list(zip(offsets, parsed))


def test_indexes_crcs_and_summary_offsets_point_at_their_records(rng):
    chunks, *_ = _samples(rng, 9000, [9000])
    data = _write(chunks, duration=3.0)
    assert data.startswith(MAGIC) and data.endswith(MAGIC)
    records = _records(data)  # validates the chunk CRCs
    by_offset = dict(records)
    data_end = next(p for p, r in records if isinstance(r, DataEnd))
    assert by_offset[data_end].data_section_crc == 0  # not computed, as libmcap's default
    chunks = [r for _, r in records if isinstance(r, Chunk)]
    assert chunks and all(c.uncompressed_crc != 0 for c in chunks)
    footer = records[-1][1]
    assert isinstance(footer, Footer)
    footer_at = len(data) - len(MAGIC) - (1 + 8 + 20)
    tail = data[footer.summary_start : footer_at] + data[footer_at : footer_at + 1 + 8 + 16]
    assert footer.summary_crc == zlib.crc32(tail)

    chunk_indexes = [r for _, r in records if isinstance(r, ChunkIndex)]
    assert len(chunk_indexes) == -(-9000 // mcapwriter.CHUNK_POSES)
    for index in chunk_indexes:
        chunk = by_offset[index.chunk_start_offset]
        assert isinstance(chunk, Chunk) and chunk.compression == "zstd"
        assert index.chunk_length == 1 + 8 + len(_body(data, index.chunk_start_offset))
        assert (index.message_start_time, index.message_end_time) == (
            chunk.message_start_time,
            chunk.message_end_time,
        )
        assert (
            index.compressed_size == len(chunk.data)
            and index.uncompressed_size == chunk.uncompressed_size
        )
        messages = {}
        position = 0
        for record in breakup_chunk(chunk, validate_crc=True):
            messages[position] = record
            position += 1 + 8 + 2 + 4 + 8 + 8 + len(record.data)  # a Message record
        assert position == chunk.uncompressed_size
        times = [m.log_time for m in messages.values()]
        assert (min(times), max(times)) == (chunk.message_start_time, chunk.message_end_time)
        total = 0
        for channel, offset in index.message_index_offsets.items():
            message_index = by_offset[offset]
            assert isinstance(message_index, MessageIndex) and message_index.channel_id == channel
            total += 1 + 8 + len(_body(data, offset))
            times = [time for time, _ in message_index.records]
            assert times == sorted(times)
            for time, at in message_index.records:
                assert messages[at].channel_id == channel and messages[at].log_time == time
            assert len(message_index.records) == len(messages) // 2
        assert index.message_index_length == total

    # as `mcap doctor` checks: a library named, schemas and channels of the summary repeat
    # those of the data section, before any message
    assert records[0][1].library.startswith("a2b ")
    kinds = [type(r).__name__ for _, r in records]
    data_end_index = kinds.index("DataEnd")
    assert kinds[1:5] == ["Schema", "Schema", "Channel", "Channel"]
    assert kinds[data_end_index + 1 : data_end_index + 5] == [
        "Schema",
        "Schema",
        "Channel",
        "Channel",
    ]
    for k in range(1, 5):
        first, again = records[k][0], records[data_end_index + k][0]
        assert _body(data, first) == _body(data, again)
    assert all(r.id != 0 and r.encoding for _, r in records[1:3])

    offsets = [r for _, r in records if isinstance(r, SummaryOffset)]
    assert [o.group_opcode for o in offsets] == [0x03, 0x04, 0x0B, 0x08]
    for group in offsets:
        position = group.group_start
        while position < group.group_start + group.group_length:
            assert data[position] == group.group_opcode
            position += 1 + 8 + struct.unpack_from("<Q", data, position + 1)[0]
        assert position == group.group_start + group.group_length


def _body(data: bytes, offset: int) -> bytes:
    (length,) = struct.unpack_from("<Q", data, offset + 1)
    return data[offset + 9 : offset + 9 + length]


def test_into_a_non_seekable_stream(rng):
    chunks, _, quat, _ = _samples(rng, 5000, [5000])
    pipe = NonSeekableStream()
    writers.write_mcap(pipe, chunks)
    assert bytes(pipe.data) == _write(chunks)
    reader = make_reader(io.BufferedReader(io.BytesIO(bytes(pipe.data))))
    messages = list(reader.iter_messages(topics=["/a2b/pose"]))
    assert len(messages) == 5000
    assert json.loads(messages[7][2].data)["pose"]["orientation"]["w"] == quat[7, 0]


def test_no_samples_is_a_valid_file():
    data = _write([])
    reader = make_reader(io.BytesIO(data))
    summary = reader.get_summary()
    assert summary.statistics.message_count == 0 and not summary.chunk_indexes
    assert {c.topic for c in summary.channels.values()} == {"/a2b/pose", "/tf"}
    assert list(reader.iter_messages()) == []
    _records(data)


def test_refuses_negative_times_and_non_finite_poses(rng):
    chunks, *_ = _samples(rng, 10, [10])
    with pytest.raises(ParameterError, match="must be finite and not negative"):
        _write(chunks, start_time=-1.0)
    chunks[0].trans[3, 1] = np.nan
    with pytest.raises(A2bError, match="is not finite"):  # the pipeline's one finite check
        _write(chunks)
