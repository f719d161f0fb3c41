"""MCAP and CDR input under attack: every hostile file is one error line, in bounded memory.

Files are built here record by record (:class:`Mcap`) or written by a2b and the ``mcap``
package and then damaged. Through the command line, each case is ``a2b resample FILE``: status
1, one line on stderr, the output file untouched, the peak resident memory under
:data:`MEMORY_CAP_MB` and the run under a time limit (``timeout``, status 124 on expiry).
"""

from __future__ import annotations

import io
import json
import re
import struct
import subprocess
import zlib
from pathlib import Path

import numpy as np
import pytest
import zstandard

from a2b.errors import InputFileError
from a2b.io.trajectories import read_trajectory
from tests.test_hardening import MEMORY_CAP_MB, PRECIOUS, _peak_of_command, a2b_cmd, linux_only

ROOT = Path(__file__).resolve().parent.parent
QUARTER = ROOT / "samples" / "quarter-turn.yaml"
SECONDS = 120  # a run that takes longer has hung
GIB = 1 << 30
POSE = "geometry_msgs/msg/PoseStamped"
TF = "tf2_msgs/msg/TFMessage"
PATH = "nav_msgs/msg/Path"

# -- building files ------------------------------------------------------------------------------


def _record(opcode: int, body: bytes) -> bytes:
    return struct.pack("<BQ", opcode, len(body)) + body


def _string(text: str | bytes) -> bytes:
    raw = text.encode() if isinstance(text, str) else text
    return struct.pack("<I", len(raw)) + raw


class Mcap:
    """An MCAP file built record by record: schemas, channels, messages (in chunks or not),
    a Data End and a Footer; no summary unless asked."""

    def __init__(self):
        self.records = [_record(0x01, _string("") + _string("test"))]

    def schema(self, key: int, name: str, encoding: str = "ros2msg") -> Mcap:
        self.records.append(_record(0x03, struct.pack("<H", key) + _string(name)
                                    + _string(encoding) + _string(b"")))  # fmt: skip
        return self

    def channel(self, key: int, schema: int, topic: str, encoding: str = "cdr") -> Mcap:
        body = struct.pack("<HH", key, schema) + _string(topic) + _string(encoding)
        self.records.append(_record(0x04, body + struct.pack("<I", 0)))
        return self

    @staticmethod
    def message(channel: int, log_time: int, data: bytes) -> bytes:
        return _record(0x05, struct.pack("<HIQQ", channel, 0, log_time, log_time) + data)

    def add(self, *records: bytes) -> Mcap:
        self.records += records
        return self

    @staticmethod
    def chunk(records: bytes, compression: str = "", size=None, crc=None, raw=None) -> bytes:
        data = raw if raw is not None else records
        if raw is None and compression == "zstd":
            data = zstandard.ZstdCompressor().compress(records)
        body = struct.pack("<QQQI", 0, 0, len(records) if size is None else size,
                           zlib.crc32(records) if crc is None else crc)  # fmt: skip
        body += _string(compression) + struct.pack("<Q", len(data)) + data
        return _record(0x06, body)

    def bytes(self) -> bytes:
        data = b"\x89MCAP0\r\n" + b"".join(self.records) + _record(0x0F, struct.pack("<I", 0))
        return data + _record(0x02, struct.pack("<QQI", 0, 0, 0)) + b"\x89MCAP0\r\n"


class Cdr:
    """A CDR message, little endian, aligned from after its 4-byte encapsulation header."""

    def __init__(self):
        self.data = bytearray()

    def align(self, size: int) -> Cdr:
        self.data += bytes(-len(self.data) % size)
        return self

    def u32(self, value: int) -> Cdr:
        self.align(4).data += struct.pack("<I", value)
        return self

    def string(self, text: bytes, length: int | None = None) -> Cdr:
        self.u32(len(text) + 1 if length is None else length).data += text + b"\0"
        return self

    def header(self, sec: int, nanosec: int, frame: bytes = b"world") -> Cdr:
        self.align(4).data += struct.pack("<iI", sec, nanosec)
        return self.string(frame)

    def pose(self, numbers) -> Cdr:
        self.align(8).data += struct.pack("<7d", *numbers)
        return self

    def bytes(self) -> bytes:
        return b"\x00\x01\x00\x00" + bytes(self.data)


def _numbers(k: int) -> list:
    """Position x = k, the identity rotation (x y z w)."""
    return [float(k), 0.0, 0.0, 0.0, 0.0, 0.0, 1.0]


def pose_stamped(k: int, frame: bytes = b"world") -> bytes:
    return Cdr().header(k, 0, frame).pose(_numbers(k)).bytes()


def tf_message(k: int, children: list, count: int | None = None) -> bytes:
    cdr = Cdr().u32(len(children) if count is None else count)
    for child in children:
        cdr.header(k, 0).string(child).pose(_numbers(k))
    return cdr.bytes()


def path_message(n: int, count: int | None = None) -> bytes:
    cdr = Cdr().header(0, 0).u32(n if count is None else count)
    for k in range(n):
        cdr.header(k, 0).pose(_numbers(k))
    return cdr.bytes()


def ros2_file(tmp_path, n: int = 20, **options) -> bytes:
    """An MCAP file of a2b's ``--format ros2``: ``/a2b/pose``, ``/tf`` and ``/a2b/path``."""
    out = tmp_path / "a2b.mcap"
    args = [QUARTER, "--samples", n, "--format", "ros2", "-o", out]
    done = subprocess.run(a2b_cmd("interpolate", *args), capture_output=True)
    assert done.returncode == 0, done.stderr.decode()
    return out.read_bytes()


# -- running a2b on them -------------------------------------------------------------------------


def refused(tmp_path, data: bytes, *options, seconds: float = SECONDS) -> str:
    """The one error line of ``a2b resample`` on the MCAP ``data``, checked as the module says."""
    path, out = tmp_path / "hostile.mcap", tmp_path / "out.csv"
    path.write_bytes(data)
    out.write_bytes(PRECIOUS)
    argv = ["timeout", str(seconds), *a2b_cmd("resample", path, "--rate", 10, *options, "-o", out)]
    peak, done = _peak_of_command(argv)
    lines = done.stderr.decode(errors="replace").splitlines()
    assert done.returncode == 1 and len(lines) == 1, (done.returncode, lines[-3:])
    assert lines[0].startswith("Error: ") and len(lines[0]) < 600, lines[0][:2000]
    assert peak < MEMORY_CAP_MB, peak
    assert out.read_bytes() == PRECIOUS
    return lines[0]


def read(data: bytes, **options):
    return read_trajectory(io.BytesIO(data), name="f.mcap", fmt="mcap", **options)


# -- decompression bombs -------------------------------------------------------------------------


@pytest.mark.slow
@linux_only
@pytest.mark.parametrize("compression", ["zstd", "lz4"])
def test_a_chunk_that_inflates_to_a_gibibyte_is_refused_before_inflating(tmp_path, compression):
    """33 kB of zstd that inflates to 1 GiB; lz4 declaring 1 GiB from as many bytes."""
    zeros = zstandard.ZstdCompressor(level=19).compress(bytes(GIB))
    assert len(zeros) < 40_000
    raw = zeros if compression == "zstd" else b"\x04\x22\x4d\x18" + bytes(len(zeros) - 4)
    chunk = Mcap.chunk(b"", compression, size=GIB, crc=0, raw=raw)
    data = Mcap().schema(1, POSE).channel(1, 1, "/p").add(chunk).bytes()
    line = refused(tmp_path, data)
    assert f"declares {GIB} bytes from {len(raw)} compressed: more than the 33554432" in line


def test_a_chunk_that_inflates_past_its_declared_size_is_refused():
    records = b"".join(Mcap.message(1, k, pose_stamped(k)) for k in range(50))
    chunk = Mcap.chunk(records, "zstd", size=len(records) - 100)
    data = Mcap().schema(1, POSE).channel(1, 1, "/p").add(chunk).bytes()
    with pytest.raises(InputFileError, match=rf"declares {len(records) - 100} bytes and "
                       "inflates to more"):  # fmt: skip
        read(data)


# -- CRCs --------------------------------------------------------------------------------------


def _chunked_file(crc=None) -> tuple[bytes, bytes]:
    records = b"".join(Mcap.message(1, k, pose_stamped(k)) for k in range(1, 30))
    return Mcap().schema(1, POSE).channel(1, 1, "/p").add(Mcap.chunk(records, crc=crc)).bytes()


def test_a_chunk_whose_crc_does_not_match_is_refused(tmp_path):
    data = bytearray(_chunked_file())
    assert data.count(struct.pack("<d", 7.0)) == 1
    at = data.index(struct.pack("<d", 7.0))  # pose 7's x becomes 7.000000000000001
    data[at] ^= 1
    line = refused(tmp_path, bytes(data))
    assert "f.mcap" not in line and "the CRC of its records does not match" in line
    assert len(read(_chunked_file())) == 29  # the file as written reads


def test_a_wrong_crc_in_a_zstd_chunk_of_a2b_is_refused(tmp_path):
    from mcap.reader import make_reader

    data = bytearray(ros2_file(tmp_path))
    index = make_reader(io.BytesIO(bytes(data))).get_summary().chunk_indexes[0]
    at = index.chunk_start_offset + 9 + 24  # the chunk's uncompressed CRC
    assert data[at : at + 4] != bytes(4)
    data[at] ^= 0x40
    assert "the CRC of its records does not match" in refused(tmp_path, bytes(data))


def _package_file(tmp_path, **options) -> bytes:
    """Poses written by the mcap package with data-section and summary CRCs."""
    from mcap.writer import Writer

    stream = io.BytesIO()
    writer = Writer(stream, enable_data_crcs=True, **options)
    writer.start(profile="ros2", library="test")
    schema = writer.register_schema(POSE, "ros2msg", b"")
    channel = writer.register_channel("/p", "cdr", schema)
    for k in range(1, 30):
        writer.add_message(channel, k, pose_stamped(k), k)
    writer.finish()
    return stream.getvalue()


@pytest.mark.parametrize("where", ["data", "summary"])
def test_a_data_section_or_summary_whose_crc_does_not_match_is_refused(tmp_path, where):
    data = bytearray(_package_file(tmp_path, use_chunking=False))
    assert len(read(bytes(data))) == 29
    if where == "data":
        at = data.index(struct.pack("<d", 7.0))
        data[at] ^= 1
    else:
        at = data.rindex(b"/p")  # the channel in the summary: /p becomes /q
        data[at + 1] = ord("q")
    assert f"the CRC of the {where}" in refused(tmp_path, bytes(data))


# -- one channel, one schema -------------------------------------------------------------------


def test_each_channel_of_a_topic_is_decoded_by_its_own_schema():
    """/p is carried by a PoseStamped channel, a JSON PoseInFrame channel and an Odometry
    channel, their messages interleaved in log time."""
    mcap = Mcap().schema(1, POSE).schema(2, "foxglove.PoseInFrame", "jsonschema")
    mcap.schema(3, "nav_msgs/msg/Odometry")
    mcap.channel(1, 1, "/p").channel(2, 2, "/p", "json").channel(3, 3, "/p")
    messages = []
    for k in range(1, 31):
        if k % 3 == 0:
            pose = {"position": {"x": k, "y": 0, "z": 0},
                    "orientation": {"x": 0, "y": 0, "z": 0, "w": 1}}  # fmt: skip
            msg = {"timestamp": {"sec": k, "nsec": 0}, "frame_id": "w", "pose": pose}
            messages.append(Mcap.message(2, k, json.dumps(msg).encode()))
        elif k % 3 == 1:
            messages.append(Mcap.message(1, k, pose_stamped(k)))
        else:
            odometry = Cdr().header(k, 0).string(b"base").pose(_numbers(k)).bytes()
            messages.append(Mcap.message(3, k, odometry + bytes(36 * 8 + 6 * 8 + 36 * 8)))
    tr = read(mcap.add(Mcap.chunk(b"".join(messages), "zstd")).bytes(), topic="/p")
    assert tr.times.tolist() == list(range(1, 31))
    assert tr.translations[:, 0].tolist() == list(range(1, 31))
    assert (tr.quat_wxyz == [1, 0, 0, 0]).all()


def _json_file(*messages) -> bytes:
    mcap = Mcap().schema(1, "foxglove.PoseInFrame", "jsonschema").channel(1, 1, "/p", "json")
    return mcap.add(*(Mcap.message(1, k, m) for k, m in enumerate(messages, 1))).bytes()


def _pose_in_frame(sec, nsec=0) -> bytes:
    pose = {"position": {"x": 1, "y": 2, "z": 3}, "orientation": {"x": 0, "y": 0, "z": 0, "w": 1}}
    return json.dumps({"timestamp": {"sec": sec, "nsec": nsec}, "pose": pose}).encode()


@pytest.mark.parametrize(
    ("message", "expected"),
    [
        (_pose_in_frame(2.5), "message 2: not a PoseInFrame message (ValueErr"),
        (_pose_in_frame(3, "5"), "the stamp 3, '5' is not two whole numbers"),
        (_pose_in_frame(-3), "the stamp -3, 0 is not two whole numbers"),
        (_pose_in_frame(3) + b"," + _pose_in_frame(4), "message 2: not a PoseInFrame message"),
        (b"[" * 100_000 + b"]" * 100_000, "(RecursionError: maximum recursion depth"),
        (b"", "message 2: not a PoseInFrame message (JSONDecodeError: Exp"),
    ],
)
def test_json_messages_are_whole_stamps_and_one_value_each(message, expected):
    """A stamp of 2.5 s was read as 2 s; two values in one message, each a message."""
    data = _json_file(_pose_in_frame(1), message, _pose_in_frame(9))
    with pytest.raises(InputFileError, match=re.escape(expected)):
        read(data)
    tr = read(_json_file(*(_pose_in_frame(k, 5) for k in range(1, 5000))))
    assert np.array_equal(tr.times, np.arange(1, 5000) + 5e-9)
    assert (tr.translations == [1, 2, 3]).all() and (tr.quat_wxyz == [1, 0, 0, 0]).all()


def test_a_bad_json_message_is_named_by_its_number():
    good = [_pose_in_frame(k) for k in range(1, 200)]
    for bad in (b"{", _pose_in_frame(2.5)):
        with pytest.raises(InputFileError, match=r"/p message 150: not a PoseInFrame"):
            read(_json_file(*good[:149], bad, *good[150:]))


# -- counts and lengths that lie ---------------------------------------------------------------


def _one_message_file(schema: str, *datas: bytes, topic: str = "/p") -> bytes:
    mcap = Mcap().schema(1, schema).channel(1, 1, topic)
    return mcap.add(*(Mcap.message(1, k, d) for k, d in enumerate(datas, 1))).bytes()


@linux_only
@pytest.mark.parametrize(
    ("schema", "message", "expected"),
    [
        (PATH, path_message(3, count=10**8), "100000000 poses declared in the"),
        (TF, tf_message(1, [b"a"], count=10**8), "100000000 transforms declared in the"),
        (POSE, Cdr().u32(1).u32(0).string(b"w", length=2**32 - 1).bytes(), "a string overruns"),
    ],
)
def test_counts_and_lengths_are_bounded_by_the_bytes_present(tmp_path, schema, message, expected):
    assert expected in refused(tmp_path, _one_message_file(schema, message))


@linux_only
def test_a_200_kb_frame_id_among_short_ones_reads_in_bounded_memory(tmp_path):
    datas = [pose_stamped(k, b"w" * (200_000 if k == 5 else 1)) for k in range(1, 20_001)]
    data = _one_message_file(POSE, *datas)
    path, out = tmp_path / "frames.mcap", tmp_path / "out.csv"
    path.write_bytes(data)
    argv = ["timeout", str(SECONDS), *a2b_cmd("resample", path, "--rate", 1, "-o", out)]
    peak, done = _peak_of_command(argv)
    assert done.returncode == 0, done.stderr.decode()[-500:]
    assert peak < MEMORY_CAP_MB, peak
    tfs = [tf_message(k, [b"c" * (200_000 if k == 5 else 1)]) for k in range(1, 2001)]
    tr = read(_one_message_file(TF, *tfs), child_frame="c")
    assert tr.times.tolist() == [k for k in range(1, 2001) if k != 5]


def test_transforms_of_many_per_message_are_placed_message_by_message():
    """Messages of 1, 3 and 20 transforms (child frame ids of 1 to 11 characters), read
    transform by transform and message by message alike."""
    frames = [b"base", b"camera_link", b"a", b"cam"]
    datas, want = [], []
    for k in range(1, 40):
        cdr = Cdr().u32(1 if k % 3 == 0 else 3 if k % 3 == 1 else 20)
        for i in range(int(struct.unpack_from("<I", cdr.data)[0])):
            child = frames[(k + i) % 4]
            numbers = [k + i / 100, float(i), 0.0, 0.0, 0.0, 0.0, 1.0]
            cdr.align(4).data += struct.pack("<iI", k, i) + struct.pack("<I", 6) + b"world\0"
            cdr.string(child).pose(numbers)
            if child == b"cam":
                want.append((k + i * 1e-9, k + i / 100, float(i)))
        datas.append(cdr.bytes())
    tr = read(_one_message_file(TF, *datas), child_frame="cam")
    assert list(zip(tr.times, tr.translations[:, 0], tr.translations[:, 1])) == want


@pytest.mark.slow
@linux_only
def test_300_000_transforms_in_a_4_kb_file_take_seconds(tmp_path):
    message = Mcap.message(1, 1, tf_message(1, [b"c"] * 300_000))
    data = Mcap().schema(1, TF).channel(1, 1, "/tf").add(Mcap.chunk(message, "zstd")).bytes()
    assert len(data) < 10_000
    assert "the time 1.0 repeats" in refused(tmp_path, data, seconds=60)


# -- bounded messages --------------------------------------------------------------------------


def test_ten_thousand_child_frames_make_a_short_line(tmp_path):
    children = [f"frame_{i:05d}_with_a_longer_name".encode() for i in range(10_000)]
    line = refused(tmp_path, _one_message_file(TF, tf_message(1, children)))
    assert "transforms to 10000 child frames (frame_00000_with_a_longer_name, " in line
    assert "and 9996 more); choose one with --input-child-frame" in line
    assert "no transform to the child frame 'x'; the frames are frame_00000" in refused(
        tmp_path, _one_message_file(TF, tf_message(1, children)), "--input-child-frame", "x"
    )


def test_five_thousand_pose_topics_make_a_short_line(tmp_path):
    mcap = Mcap().schema(1, POSE)
    for key in range(1, 5001):
        mcap.channel(key, 1, f"/robot_{key:04d}/pose").add(Mcap.message(key, key, pose_stamped(1)))
    line = refused(tmp_path, mcap.bytes())
    assert "several pose topics (/robot_0001/pose, /robot_0002/pose, /robot_0003/pose, " in line
    assert "and 4996 more); choose one with --topic" in line
    line = refused(tmp_path, mcap.bytes(), "--topic", "/x" * 10_000)
    assert "no topic '/x/x/x" in line and "the file has /robot_0001/pose" in line


def test_a_megabyte_topic_and_schema_name_make_a_short_line(tmp_path):
    data = Mcap().schema(1, "s" * 10**6).channel(1, 1, "/" + "t" * 100_000).bytes()
    assert "no pose topics (/tttt" in refused(tmp_path, data)
    assert "carries ssss" in refused(tmp_path, data, "--topic", "/" + "t" * 100_000)


# -- options that do not apply ---------------------------------------------------------------


def test_a_child_frame_on_a_pose_stamped_topic_is_refused(tmp_path):
    data = ros2_file(tmp_path)
    line = refused(tmp_path, data, "--topic", "/a2b/pose", "--input-child-frame", "a2b")
    assert line.endswith(
        f"/a2b/pose carries {POSE}: --input-child-frame is for topics of {TF}, "
        "foxglove.FrameTransform, foxglove.FrameTransforms"
    )
    tr = read(data, child_frame="a2b")  # without --topic: the one TFMessage topic
    assert len(tr) == 20 and np.array_equal(tr.translations, read(data).translations)


def test_a_topic_without_poses_is_refused(tmp_path):
    mcap = Mcap().schema(1, "foxglove.Log", "jsonschema").channel(1, 1, "/log", "json")
    log = {"timestamp": {"sec": 1, "nsec": 0}, "pose": {"position": {}}, "message": "hi"}
    data = mcap.add(Mcap.message(1, 1, json.dumps(log).encode())).bytes()
    line = refused(tmp_path, data, "--topic", "/log")
    assert "/log carries foxglove.Log; a2b reads poses from CDR geometry_msgs/msg/Pose" in line


# -- damaged structure: one clear error each ---------------------------------------------------


def _summary(data: bytes):
    from mcap.reader import make_reader

    return make_reader(io.BytesIO(data)).get_summary()


def _put(data: bytes, at: int, value: bytes) -> bytes:
    """``data`` with ``value`` at ``at``, and the summary's CRC made to match again (as an
    attacker would), so that the reader's own checks of the summary's content are reached."""
    data = data[:at] + value + data[at + len(value) :]
    footer = len(data) - 8 - 29
    start = struct.unpack_from("<Q", data, footer + 9)[0]
    if start > footer:
        return data
    crc = struct.pack("<I", zlib.crc32(data[start : footer + 25]))
    return data[: footer + 25] + crc + data[-8:]


def _without_data_crc(data: bytes) -> bytes:
    """``data`` with the CRC of its data section set to 0 (not computed), where it has one."""
    footer = len(data) - 8 - 29
    start = struct.unpack_from("<Q", data, footer + 9)[0] if footer > 8 else 0
    at = (start or footer) - 13
    if 8 < at < len(data) - 13 and data[at] == 0x0F:
        return data[: at + 9] + bytes(4) + data[at + 13 :]
    return data


def _damaged(data: bytes) -> dict:
    """Ways to damage an a2b ros2 file, each with the words of its error."""
    summary = _summary(data)
    index = summary.chunk_indexes[0]
    footer = len(data) - 8 - 29
    summary_start = struct.unpack_from("<Q", data, footer + 9)[0]
    mi = index.message_index_offsets[1]
    ci = data.index(struct.pack("<Q", index.chunk_start_offset), summary_start)
    second = summary.chunk_indexes[1].chunk_start_offset
    ci2 = data.index(struct.pack("<Q", second), summary_start)
    return {
        "cut in half": (data[: len(data) // 2], "ends without MCAP's Footer"),
        "no magic": (b"\0" + data[1:], "no MCAP magic"),
        "summary past the end": (_put(data, footer + 9, struct.pack("<Q", 2**63)),
                                 "puts the summary at byte"),
        "record of 2**64 - 1 bytes": (_put(data, summary_start + 1, b"\xff" * 8),
                                      "declares 18446744073709551615 bytes"),
        "chunk offset past the end": (_put(data, ci, struct.pack("<Q", 2**62)),
                                      "a chunk index points at bytes"),
        "chunk offset at a non-chunk": (_put(data, ci, struct.pack("<Q", 8)),
                                        "where no chunk of"),
        "message index offset lies": (_put(data, ci + 16 + 4 + 2, struct.pack("<Q", 9)),
                                      "the message index of channel 1 points at byte 9"),
        "message index entries lie": (_put(data, mi + 11, struct.pack("<I", 2**31)),
                                      "declares 2147483648 bytes of entries"),
        "message offset of 2**63": (_put(data, mi + 15 + 8, struct.pack("<Q", 2**63)),
                                    "points past the chunk"),
        "unknown compression": (_put(data, index.chunk_start_offset + 9 + 28 + 4, b"zstX"),
                                "compressed with 'zstX'"),
        "one message indexed twice": (_put(data, mi + 15 + 16, data[mi + 15 : mi + 31]),
                                      "points at messages that overlap"),
        "two indexes of one chunk": (_put(data, ci2, data[ci : ci + 16]),
                                     "two chunk indexes point at one chunk"),
    }  # fmt: skip


def test_a_channel_or_schema_defined_twice_differently_is_refused():
    """The second /p record of channel 1 would make its messages poses of /q."""
    pose = Mcap.message(1, 1, pose_stamped(1))
    data = Mcap().schema(1, POSE).channel(1, 1, "/p").add(pose).channel(1, 1, "/q").bytes()
    with pytest.raises(InputFileError, match="f.mcap: two channel records of id 1 differ"):
        read(data)
    data = Mcap().schema(1, POSE).channel(1, 1, "/p").add(pose).schema(1, TF).bytes()
    with pytest.raises(InputFileError, match="f.mcap: two schema records of id 1 differ"):
        read(data)


def test_damaged_structure_is_one_clear_error_each(tmp_path):
    data = ros2_file(tmp_path)
    assert len(read(data)) == 20
    for what, (damaged, words) in _damaged(data).items():
        with pytest.raises(InputFileError) as caught:
            read(damaged)
        message = str(caught.value)
        assert words in message and "\n" not in message and len(message) < 400, (what, message)


@linux_only
def test_damaged_structure_through_the_command_line(tmp_path):
    damaged = _damaged(ros2_file(tmp_path))
    for what in ("chunk offset past the end", "message offset of 2**63"):
        data, words = damaged[what]
        assert words in refused(tmp_path, data), what


def test_random_damage_is_an_input_error_or_a_reading(tmp_path, rng):
    """Bytes overwritten at random places of small files: the reader never fails otherwise."""
    files = [ros2_file(tmp_path, 5), _package_file(tmp_path, use_chunking=False),
             _package_file(tmp_path, chunk_size=200)]  # fmt: skip
    for _ in range(300):
        data = bytearray(files[rng.integers(len(files))])
        for at in rng.integers(0, len(data), rng.integers(1, 4)):
            data[at] = rng.integers(256)
        if rng.random() < 0.5:  # CRCs made to match, as an attacker would: the parsing is hit
            data = bytearray(_without_data_crc(_put(bytes(data), 0, data[:1])))
        try:
            read(bytes(data), topic=None if rng.random() < 0.5 else "/a2b/pose")
        except InputFileError as e:
            assert "\n" not in str(e) and len(str(e)) < 600


def test_random_damage_to_cdr_is_an_input_error_or_a_reading(rng):
    """Every message type a2b decodes, with bytes overwritten at random and cut at random."""
    from a2b.io.ros2 import decode_poses

    odometry = Cdr().header(1, 0).string(b"base").pose(_numbers(1)).bytes() + bytes(672)
    valid = {POSE: [pose_stamped(1), pose_stamped(2, b"wx")], PATH: [path_message(5)],
             TF: [tf_message(1, [b"a", b"bb"]), tf_message(2, [b"a"] * 12)],
             "nav_msgs/msg/Odometry": [odometry]}  # fmt: skip
    for _ in range(2000):
        schema = list(valid)[rng.integers(len(valid))]
        datas = [bytearray(data) for data in valid[schema]]
        for data in datas:
            for at in rng.integers(0, len(data), rng.integers(0, 4)):
                data[at] = rng.choice([0, 1, 255, rng.integers(256)])
        k = rng.integers(len(datas))
        datas[k] = datas[k][: rng.integers(len(datas[k]) + 1)]
        child = None if rng.random() < 0.5 or schema != TF else "a"
        try:
            times, quat, trans, message = decode_poses(schema, [bytes(d) for d in datas], "w",
                                                       child)  # fmt: skip
            assert len(times) == len(quat) == len(trans) == len(message)
        except InputFileError as e:
            assert "\n" not in str(e) and len(str(e)) < 400
