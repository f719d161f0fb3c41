"""ROS 2 bags: `--format ros2` read by the clients ROS 2 users run, and ROS 2 messages read back.

The independent readers (rosbags, mcap + mcap-ros2-support, evo) run in a venv of their own
(conftest.py ``clients``) through ``ros2_clients.py``; Foxglove's decoder runs under node.
"""

from __future__ import annotations

import io
import json
import os
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

import a2b
from a2b.cli import cli
from a2b.errors import InputFileError, ParameterError
from a2b.io import ros2
from a2b.io.trajectories import read_trajectory
from a2b.io.writers import write_batch_mcap
from a2b.samples import Samples
from tests.conftest import TOOLS, NonSeekableStream, evo_full_check, random_pose

HERE = Path(__file__).parent
SAMPLES = HERE.parent / "samples"


def run(*args):
    return CliRunner().invoke(cli, [str(a) for a in args])


def _motion(rng):
    return a2b.motion(random_pose(rng), random_pose(rng), "darboux")


def _write(path, motion, n, **options):
    ts = np.linspace(0, 1, n)
    a2b.write(motion, path, "ros2", samples=n, **options)
    quat, trans = motion.quat_trans(ts)
    trans[[0, -1]] = motion.start[:3, 3], motion.end[:3, 3]  # t = 0 and 1: A and B as given
    return quat, trans


def _clients(clients, *args):
    done = subprocess.run(
        [str(clients / "python"), str(HERE / "ros2_clients.py"), *map(str, args)],
        capture_output=True, text=True, timeout=600,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout)


def _hex(values) -> list:
    return [float(v).hex() for v in values]


# -- what the clients read ---------------------------------------------------------------------


@pytest.mark.parametrize("frames", [("world", "a2b"), ("m", "bödy_1"), ("odom_frame", "xy")])
def test_rosbags_and_mcap_ros2_read_every_message_bit_for_bit(tmp_path, clients, rng, frames):
    """Frame ids of several lengths: the padding before the doubles differs."""
    frame_id, child = frames
    n, duration, start = 300, 7.25, 1_700_000_000.123
    quat, trans = _write(tmp_path / "m.mcap", _motion(rng), n, duration=duration,
                         start_time=start, frame_id=frame_id, child_frame_id=child)  # fmt: skip
    got = _clients(clients, "read", tmp_path / "m.mcap")[str(tmp_path / "m.mcap")]
    ns = np.rint((np.linspace(0, 1, n) * duration + start) * 1e9).astype(np.int64)
    sec, nanosec = ns // 10**9, ns % 10**9
    numbers = np.column_stack([trans, quat[:, [1, 2, 3, 0]]])
    poses = [[[int(s), int(c), frame_id], _hex(v)] for s, c, v in zip(sec, nanosec, numbers)]
    want = []
    for k in range(n):
        want.append(["/a2b/pose", int(ns[k]), poses[k]])
        want.append(["/tf", int(ns[k]), [[poses[k][0], child, poses[k][1]]]])
    want.append(["/a2b/path", int(ns[0]), [[int(sec[0]), int(nanosec[0]), frame_id], poses]])
    by_topic = sorted(got["rosbags"], key=lambda m: (m[1], m[0] != "/a2b/pose", m[0]))
    assert by_topic == sorted(want, key=lambda m: (m[1], m[0] != "/a2b/pose", m[0]))
    assert sorted(got["mcap_ros2"]) == sorted(want)
    assert all(got["same_bytes"])  # rosbags serialises each message to the bytes a2b wrote
    assert got["qos"] == {"/a2b/pose": [[1, 10, 1, 2]], "/tf": [[1, 100, 1, 2]],
                          "/a2b/path": [[1, 1, 1, 1]]}  # fmt: skip


def test_schemas_are_the_full_definitions_rosbags_writes(clients):
    script = (
        "import json, sys\n"
        "from rosbags.typesys import Stores, get_typestore\n"
        "store = get_typestore(Stores.ROS2_HUMBLE)\n"
        "names = sys.argv[1:]\n"
        "print(json.dumps({n: store.generate_msgdef(n, ros_version=2)[0] for n in names}))\n"
    )
    names = ["geometry_msgs/PoseStamped", "tf2_msgs/TFMessage", "nav_msgs/Path"]
    done = subprocess.run([str(clients / "python"), "-c", script,
                           *map(ros2.schema_name, names)],
                          capture_output=True, text=True, check=True)  # fmt: skip
    theirs = json.loads(done.stdout)
    for name in names:
        assert ros2.schema_text(name).decode() == theirs[ros2.schema_name(name)]


def test_evo_reads_the_bag_with_a_full_check(tmp_path, clients, rng):
    _write(tmp_path / "turn.mcap", _motion(rng), 200, duration=4.0)
    out = evo_full_check(clients, str(tmp_path / "turn.mcap"), tmp_path)
    assert "nr. of poses\t200" in out and "duration (s)\t4.0" in out


def test_batch_writes_one_pose_topic_per_job(tmp_path, clients):
    jobs = tmp_path / "jobs.yaml"
    shutil.copy(SAMPLES / "jobs.yaml", jobs)
    result = run("batch", jobs, "--format", "ros2", "--samples", 5, "-o", tmp_path / "j.mcap")
    assert result.exit_code == 0, result.output
    got = _clients(clients, "read", tmp_path / "j.mcap")[str(tmp_path / "j.mcap")]
    topics = {m[0] for m in got["rosbags"]}
    names = ("lift", "lift_offset", "lift_cubic", "slide")
    assert topics == {f"/a2b/{name}/pose" for name in names} and all(got["same_bytes"])
    for topic in topics:
        with open(tmp_path / "j.mcap", "rb") as f:
            ours = read_trajectory(f, topic=topic)
        theirs = [m[2][1] for m in got["rosbags"] if m[0] == topic]
        numbers = np.column_stack([ours.translations, ours.quat_wxyz[:, [1, 2, 3, 0]]])
        assert [_hex(v) for v in numbers] == theirs and len(theirs) >= 5


# -- Foxglove's decoder, under node -------------------------------------------------------------

NODE_PACKAGES = ("@foxglove/rosmsg2-serialization", "@foxglove/rosmsg")
NODE_SCRIPT = r"""
const fs = require("fs");
const { parse } = require("@foxglove/rosmsg");
const { MessageReader } = require("@foxglove/rosmsg2-serialization");
const input = JSON.parse(fs.readFileSync(0, "utf8"));
const out = [];
for (const [schema, data] of input) {
  const reader = new MessageReader(parse(schema, { ros2: true }));
  out.push(reader.readMessage(Buffer.from(data, "hex")));
}
process.stdout.write(JSON.stringify(out, (k, v) => typeof v === "bigint" ? Number(v) : v));
"""


@pytest.fixture(scope="session")
def node_decoder() -> Path:
    """A directory with Foxglove's ROS 2 decoders from npm, for node."""
    node, npm = shutil.which("node"), shutil.which("npm")
    if node is None or npm is None:
        pytest.skip("node and npm are not installed: Foxglove's decoder runs under node")
    home = TOOLS / "node"
    if not (home / "node_modules" / "@foxglove" / "rosmsg2-serialization").exists():
        home.mkdir(parents=True, exist_ok=True)
        done = subprocess.run([npm, "install", "--prefix", str(home), *NODE_PACKAGES],
                              capture_output=True, text=True, timeout=600)  # fmt: skip
        if done.returncode != 0:
            pytest.skip(f"npm could not install {', '.join(NODE_PACKAGES)}: {done.stderr[-300:]}")
    (home / "decode.js").write_text(NODE_SCRIPT)
    return home


def test_foxglove_decodes_every_message(tmp_path, node_decoder, rng):
    from mcap.reader import make_reader

    n = 50
    quat, trans = _write(tmp_path / "m.mcap", _motion(rng), n, start_time=3.5)
    with open(tmp_path / "m.mcap", "rb") as f:
        records = [(s.data.decode(), m.data.hex(), c.topic)
                   for s, c, m in make_reader(f).iter_messages(log_time_order=True)]  # fmt: skip
    done = subprocess.run(
        ["node", str(node_decoder / "decode.js")],
        input=json.dumps([r[:2] for r in records]), capture_output=True, text=True,
        timeout=120, env=dict(os.environ, NODE_PATH=str(node_decoder / "node_modules")),
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    decoded = json.loads(done.stdout)
    assert len(decoded) == 2 * n + 1
    poses = [m for m, r in zip(decoded, records) if r[2] == "/a2b/pose"]
    tfs = [m for m, r in zip(decoded, records) if r[2] == "/tf"]
    path = next(m for m, r in zip(decoded, records) if r[2] == "/a2b/path")
    for k in range(n):
        position, orientation = poses[k]["pose"]["position"], poses[k]["pose"]["orientation"]
        assert [position[a] for a in "xyz"] == trans[k].tolist()
        assert [orientation[a] for a in "wxyz"] == quat[k].tolist()
        transform = tfs[k]["transforms"][0]
        assert transform["child_frame_id"] == "a2b" and transform["header"]["frame_id"] == "world"
        assert [transform["transform"]["translation"][a] for a in "xyz"] == trans[k].tolist()
        assert path["poses"][k]["pose"] == poses[k]["pose"]
    stamp = poses[-1]["header"]["stamp"]
    assert (stamp["sec"], stamp["nanosec"]) == (4, 500_000_000)


# -- reading ROS 2 messages --------------------------------------------------------------------


def test_every_pose_topic_reads_back(tmp_path, rng):
    n = 257
    quat, trans = _write(tmp_path / "m.mcap", _motion(rng), n, duration=2.0, start_time=10.0,
                         frame_id="w", child_frame_id="body")  # fmt: skip
    for topic in ("/a2b/pose", "/tf", "/a2b/path", None):
        with open(tmp_path / "m.mcap", "rb") as f:
            tr = read_trajectory(f, topic=topic)
        assert np.array_equal(tr.quat_wxyz, quat) and np.array_equal(tr.translations, trans)
        ns = np.rint((np.linspace(0, 1, n) * 2.0 + 10.0) * 1e9).astype(np.int64)
        assert np.array_equal(tr.times, (ns // 10**9) + (ns % 10**9) * 1e-9)
    result = run("resample", tmp_path / "m.mcap", "--topic", "/tf", "--input-child-frame",
                 "elbow", "--rate", 10)  # fmt: skip
    assert result.exit_code == 1
    assert "no transform to the child frame 'elbow'; the frames are body" in result.output


def test_messages_of_other_writers_read_back(tmp_path, clients):
    """A bag from rosbags' Writer: frame ids of 1 to 7 characters, an Odometry, a /tf of two
    child frames, two Paths (the last is read)."""
    want = _clients(clients, "write", tmp_path / "bag")
    path = want["file"]

    def read(topic, **kwargs):
        with open(path, "rb") as f:
            tr = read_trajectory(f, topic=topic, **kwargs)
        numbers = np.column_stack([tr.translations, tr.quat_wxyz[:, [1, 2, 3, 0]]])
        return tr.times, [_hex(v) for v in numbers]

    for topic, key, options in (("/pose", "pose", {}), ("/odom", "odom", {}),
                                ("/plan", "plan", {}),
                                ("/tf", "tf", {"child_frame": "camera_link"})):  # fmt: skip
        times, numbers = read(topic, **options)
        assert numbers == [w[2] for w in want[key]], topic
        assert times.tolist() == [s + c * 1e-9 for s, c, _ in want[key]], topic
    with pytest.raises(InputFileError, match=r"transforms to 2 child frames \(base, camera_link\)"):
        read("/tf")
    result = run("resample", path, "--rate", 2)
    assert result.exit_code == 1 and "several pose topics" in result.output
    result = run("spline", path, "--topic", "/odom", "--space", "study", "--samples", 3)
    assert result.exit_code == 0, result.output


def test_damaged_cdr_is_one_error_at_its_message():
    good = ros2.pose_stamped("world").template
    with pytest.raises(InputFileError, match="f: /p message 2: the message ends too soon"):
        ros2.decode_poses("geometry_msgs/msg/PoseStamped", [good, good[:30]], "f: /p")
    big_endian = b"\x00\x00" + good[2:]
    with pytest.raises(InputFileError, match=r"message 1: not little-endian plain CDR \(enc"):
        ros2.decode_poses("geometry_msgs/msg/PoseStamped", [big_endian], "f: /p")
    overrun = bytearray(good)
    overrun[12:16] = (1000).to_bytes(4, "little")
    with pytest.raises(InputFileError, match="message 1: a string overruns the message"):
        ros2.decode_poses("geometry_msgs/msg/PoseStamped", [bytes(overrun)], "f: /p")
    with pytest.raises(InputFileError, match="a2b reads geometry_msgs/msg/PoseStamped"):
        ros2.decode_poses("sensor_msgs/msg/Imu", [good], "f: /p")


# -- bad requests: one line each, nothing written ----------------------------------------------


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--start-time", 2**31], "ROS 2 stamps hold seconds in an int32: at most 2**31 − 1"),
        (["--frame-id", "/world"], "--frame-id '/world' is not a ROS 2 frame id"),
        (["--child-frame-id", "my body"], "--child-frame-id 'my body' is not a ROS 2 frame id"),
        (["--frame-id", ""], "--frame-id '' is not a ROS 2 frame id"),
        (["--profile", "foxglove"], "--format ros2 writes the ros2 profile, not foxglove"),
    ],
)
def test_a_bad_request_is_one_line_and_writes_nothing(tmp_path, args, message):
    out = tmp_path / "x.mcap"
    result = run("interpolate", SAMPLES / "quarter-turn.yaml", "--format", "ros2", *args,
                 "-o", out)  # fmt: skip
    assert result.exit_code != 0 and message in result.output, result.output
    assert result.output.strip().count("\n") == 0 or "Usage" in result.output
    assert not out.exists()


def test_a_job_name_that_makes_no_topic_is_refused(tmp_path):
    jobs = tmp_path / "jobs.yaml"
    pose = "{matrix: [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}"
    jobs.write_text(f"- {{name: ok, start: {pose}, end: {pose}}}\n"
                    f"- {{name: 2nd arm, start: {pose}, end: {pose}}}\n")  # fmt: skip
    result = run("batch", jobs, "--format", "ros2", "-o", tmp_path / "j.mcap")
    assert result.exit_code == 1
    assert "job '2nd arm': the topic '/a2b/2nd arm/pose' is not a ROS 2 topic name" in result.output
    assert not (tmp_path / "j.mcap").exists()
    for topic in ("/a2b/pose", "/a/b_2/c", "/x"):
        assert ros2.check_topic(topic) == topic
    for topic in ("a2b/pose", "/a2b//pose", "/a2b/pose/", "/", "/a-b", "/1a", "/a/ b"):
        with pytest.raises(ParameterError, match="is not a ROS 2 topic name"):
            ros2.check_topic(topic)


def test_stamps_split_into_sec_and_nanosec():
    ns = np.array([0, 1, 999_999_999, 10**9, 2**31 * 10**9 - 1])
    sec, nanosec = ros2.split_stamps(ns)
    assert sec.tolist() == [0, 0, 0, 1, 2**31 - 1]
    assert nanosec.tolist() == [0, 1, 999_999_999, 0, 999_999_999]
    words = ros2.stamp_words(ns)
    assert (words & 0xFFFFFFFF).tolist() == sec.tolist() and (
        words >> 32
    ).tolist() == nanosec.tolist()
    with pytest.raises(ParameterError, match="January 2038"):
        ros2.split_stamps(np.array([2**31 * 10**9]))


def test_profile_chooses_the_messages_of_an_mcap_file(tmp_path):
    from mcap.reader import make_reader

    for args, profile in (
        (["--profile", "ros2"], "ros2"),
        ([], ""),
        (["--format", "ros2"], "ros2"),
    ):
        out = tmp_path / "t.mcap"
        result = run("interpolate", SAMPLES / "quarter-turn.yaml", *args, "-o", out)
        assert result.exit_code == 0, result.output
        with open(out, "rb") as f:
            assert make_reader(f).get_header().profile == profile
    result = run("interpolate", SAMPLES / "quarter-turn.yaml", "--profile", "ros2", "--format",
                 "csv")  # fmt: skip
    assert result.exit_code == 2 and "--profile is for MCAP output, not csv" in result.output


def test_ros2_streams_into_a_pipe_and_batches_alike(rng):
    motion = _motion(rng)
    stream = NonSeekableStream()
    a2b.write(motion, stream, "ros2", samples=9)
    tr = read_trajectory(io.BytesIO(bytes(stream.data)))
    assert np.array_equal(tr.quat_wxyz, motion.quat_trans(np.linspace(0, 1, 9))[0])
    batch = NonSeekableStream()
    quat, trans = motion.quat_trans(np.linspace(0, 1, 4))
    chunk = Samples(np.linspace(0, 1, 4), quat_wxyz=quat, trans=trans, job=["a", "a", "b", "b"])
    write_batch_mcap(batch, [chunk], "ros2")
    for job, rows in (("a", slice(0, 2)), ("b", slice(2, 4))):
        tr = read_trajectory(io.BytesIO(bytes(batch.data)), topic=f"/a2b/{job}/pose")
        assert np.array_equal(tr.translations, trans[rows])


def test_a_late_stamp_from_a_times_file_writes_no_byte(tmp_path):
    times = tmp_path / "times.txt"
    times.write_text("1700000000.25\n2147483648\n")
    result = run("resample", SAMPLES / "reference.tum", "--times", times, "--clip",
                 "--format", "ros2", "-o", "-")  # fmt: skip
    assert result.exit_code == 1 and result.stdout_bytes == b""
    assert "ROS 2 stamps hold seconds in an int32" in result.stderr


# -- reading through the indexes ------------------------------------------------------------


def _package_messages(path, topic):
    from mcap.reader import make_reader

    with open(path, "rb") as f:
        return [m.data for _s, _c, m in make_reader(f).iter_messages(topics=[topic])]


def test_the_indexed_reader_gives_what_the_mcap_package_reads(tmp_path, clients, rng):
    """a2b's JSON and ros2 files, and a bag of rosbags' Writer (frame ids of several lengths,
    so that messages differ in length), message by message."""
    from a2b.io.mcapreader import McapFile

    motion = _motion(rng)
    _write(tmp_path / "r.mcap", motion, 5000)
    a2b.write(motion, tmp_path / "j.mcap", "mcap", samples=5000)
    bag = _clients(clients, "write", tmp_path / "bag")["file"]
    for path in (tmp_path / "r.mcap", tmp_path / "j.mcap", bag):
        mcap = McapFile(Path(path).read_bytes(), str(path))
        assert mcap._chunk_indexes and mcap._scanned is None  # through the indexes
        for channel in mcap.channels.values():
            ours = mcap.messages([channel.id])[channel.id]
            assert ours.as_bytes() == _package_messages(path, channel.topic), channel.topic


def _without_indexes(source, target, chunk_size=None):
    """The messages of ``source`` rewritten by the mcap package without any index."""
    from mcap.reader import make_reader
    from mcap.writer import CompressionType, IndexType, Writer

    with open(source, "rb") as f:
        reader = make_reader(f)
        summary = reader.get_summary()
        messages = list(reader.iter_messages())
    options = {"use_chunking": False} if chunk_size is None else {"chunk_size": chunk_size}
    with open(target, "wb") as f:
        writer = Writer(f, index_types=IndexType.NONE, use_statistics=False,
                        compression=CompressionType.LZ4, **options)  # fmt: skip
        writer.start(profile="ros2", library="test")
        ids = {}
        for schema in summary.schemas.values():
            ids[schema.id] = writer.register_schema(schema.name, schema.encoding, schema.data)
        for channel in summary.channels.values():
            writer.register_channel(channel.topic, channel.message_encoding,
                                    ids[channel.schema_id], channel.metadata)  # fmt: skip
        for _schema, channel, message in messages:
            writer.add_message(channel.id, message.log_time, message.data, message.publish_time)
        writer.finish()


@pytest.mark.parametrize("chunk_size", [None, 4096])
def test_a_file_without_indexes_is_read_record_by_record(tmp_path, rng, chunk_size):
    """Messages outside chunks, and in lz4 chunks that no index lists."""
    from a2b.io.mcapreader import McapFile

    motion = _motion(rng)
    _write(tmp_path / "r.mcap", motion, 50)
    _without_indexes(tmp_path / "r.mcap", tmp_path / "plain.mcap", chunk_size)
    mcap = McapFile((tmp_path / "plain.mcap").read_bytes(), "plain.mcap")
    assert len(mcap.messages([1])[1]) == 50
    assert not mcap._chunk_indexes and mcap._scanned is not None  # record by record
    with open(tmp_path / "plain.mcap", "rb") as f:
        tr = read_trajectory(f)
    assert np.array_equal(tr.quat_wxyz, motion.quat_trans(np.linspace(0, 1, 50))[0])


def test_a_damaged_index_is_one_error(tmp_path, rng):
    from mcap.reader import make_reader

    _write(tmp_path / "r.mcap", _motion(rng), 50)
    data = bytearray((tmp_path / "r.mcap").read_bytes())
    summary = make_reader(io.BytesIO(bytes(data))).get_summary()
    index = summary.chunk_indexes[0]
    at = index.message_index_offsets[1] + 15 + 8  # the first message's offset in its chunk
    data[at : at + 8] = (10**6).to_bytes(8, "little")
    with pytest.raises(InputFileError, match=r"r\.mcap: the message index of channel 1 in the "
                       r"chunk at byte \d+ points past the chunk's \d+ bytes"):  # fmt: skip
        read_trajectory(io.BytesIO(bytes(data)), name="r.mcap", fmt="mcap")
