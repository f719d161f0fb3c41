"""rosbag2 bags (a2b.io.rosbag2): folders and SQLite files written by rosbags read back bit for
bit, a2b's SQLite bags read by rosbags and evo, hostile bags refused in one line, and memory
bounded by what the caller allows."""

from __future__ import annotations

import os
import shutil
import sqlite3
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import yaml

from a2b.errors import InputFileError, ParameterError
from a2b.io import ros2
from a2b.io.atomic import OutputFileError
from a2b.io.rosbag2 import (
    bag_files,
    bag_messages,
    bag_topics,
    is_bag,
    write_sqlite_bag,
)
from a2b.io.sqlitebag import TYPE_HASHES
from tests.conftest import evo_full_check

rosbags = pytest.importorskip("rosbags")
from rosbags.highlevel import AnyReader  # noqa: E402
from rosbags.rosbag2 import Reader, StoragePlugin, Writer  # noqa: E402
from rosbags.typesys import Stores, get_typestore  # noqa: E402

STORE = get_typestore(Stores.ROS2_HUMBLE)
T = STORE.types
TYPES = {
    "/pose": "geometry_msgs/msg/PoseStamped",
    "/odom": "nav_msgs/msg/Odometry",
    "/tf": "tf2_msgs/msg/TFMessage",
}


def _poses(rng, n):
    """``n`` random poses in ROS order: x y z, then a unit quaternion qx qy qz qw."""
    quat = rng.normal(size=(n, 4))
    quat /= np.linalg.norm(quat, axis=1, keepdims=True)
    return np.column_stack([rng.normal(size=(n, 3)), quat])


def _ros_pose(values):
    return T["geometry_msgs/msg/Pose"](
        position=T["geometry_msgs/msg/Point"](x=values[0], y=values[1], z=values[2]),
        orientation=T["geometry_msgs/msg/Quaternion"](
            x=values[3], y=values[4], z=values[5], w=values[6]
        ),
    )


def _header(ns, frame):
    sec, nanosec = divmod(int(ns), 10**9)
    time = T["builtin_interfaces/msg/Time"](sec=sec, nanosec=nanosec)
    return T["std_msgs/msg/Header"](stamp=time, frame_id=frame)


def _messages(topic, k, ns, values):
    """A message of ``topic`` with the pose ``values`` at ``ns``; frame ids of several lengths,
    so that the padding varies from message to message."""
    frame = "m" * (k % 5 + 1)
    if topic == "/pose":
        return T[TYPES[topic]](header=_header(ns, frame), pose=_ros_pose(values))
    if topic == "/odom":
        vector = T["geometry_msgs/msg/Vector3"]
        twist = T["geometry_msgs/msg/Twist"](linear=vector(x=1.0, y=2.0, z=3.0),
                                             angular=vector(x=4.0, y=5.0, z=6.0))  # fmt: skip
        return T[TYPES[topic]](
            header=_header(ns, frame),
            child_frame_id="b" * (k % 3),
            pose=T["geometry_msgs/msg/PoseWithCovariance"](
                pose=_ros_pose(values), covariance=np.arange(36, dtype=float)
            ),
            twist=T["geometry_msgs/msg/TwistWithCovariance"](twist=twist, covariance=np.zeros(36)),
        )
    transforms = []
    for child, shift in (("base_link", 0.0), ("camera", 1.0)):
        translation = T["geometry_msgs/msg/Vector3"](x=values[0] + shift, y=values[1], z=values[2])
        transform = T["geometry_msgs/msg/Transform"](
            translation=translation, rotation=_ros_pose(values).orientation
        )
        transforms.append(
            T["geometry_msgs/msg/TransformStamped"](
                header=_header(ns, frame), child_frame_id=child, transform=transform
            )
        )
    return T[TYPES[topic]](transforms=transforms)


def _rosbags_bag(path, rng, plugin=StoragePlugin.SQLITE3, n=9):
    """A bag written by rosbags' Writer: /pose, /odom and /tf (children base_link and camera,
    the camera 1 m further in x), the stamps ``ns`` and log times ``ns + 1000``. Returns
    ``{topic: (ns, poses, datas)}``."""
    expected = {}
    ns = 1_700_000_000 * 10**9 + np.cumsum(rng.integers(1, 10**9, size=n))
    with Writer(path, version=8, storage_plugin=plugin) as writer:
        connections = {
            topic: writer.add_connection(topic, name, typestore=STORE)
            for topic, name in TYPES.items()
        }
        for topic in TYPES:
            expected[topic] = (ns, _poses(rng, n), [])
        for k in range(n):
            for topic, (_ns, poses, datas) in expected.items():
                data = bytes(
                    STORE.serialize_cdr(_messages(topic, k, ns[k], poses[k]), TYPES[topic])
                )
                writer.write(connections[topic], int(ns[k]) + 1000, data)
                datas.append(data)
    return expected


def _check_read(path, expected):
    assert {t.name: (t.type_name, t.count) for t in bag_topics(path)} == {
        topic: (TYPES[topic], len(ns)) for topic, (ns, _p, _d) in expected.items()
    }
    for topic, (ns, poses, datas) in expected.items():
        type_name, log_times, got = bag_messages(path, topic)
        assert type_name == TYPES[topic] and got == datas
        assert log_times.dtype == np.int64 and (log_times == ns + 1000).all()
        child = "camera" if topic == "/tf" else None
        times, quat_wxyz, trans, _ = ros2.decode_poses(type_name, got, topic, child)
        assert times.tolist() == [int(t // 10**9) + (t % 10**9) * 1e-9 for t in ns.tolist()]
        want_trans = poses[:, :3] + ([1.0, 0, 0] if child else 0)
        assert (trans == want_trans).all() and (quat_wxyz == poses[:, [6, 3, 4, 5]]).all()


# -- bags that rosbags writes, read bit for bit ------------------------------------------------


def test_reads_a_sqlite_folder_of_rosbags(tmp_path, rng):
    bag = tmp_path / "recording"
    expected = _rosbags_bag(bag, rng)
    assert is_bag(bag) and bag_files(bag) == ("sqlite3", [str(bag / "recording.db3")])
    _check_read(bag, expected)


def test_reads_a_bare_db3_of_rosbags(tmp_path, rng):
    expected = _rosbags_bag(tmp_path / "recording", rng)
    bare = tmp_path / "alone.db3"
    shutil.copy(tmp_path / "recording" / "recording.db3", bare)
    assert is_bag(bare) and bag_files(bare) == ("sqlite3", [str(bare)])
    _check_read(bare, expected)


def test_reads_an_mcap_folder_of_rosbags(tmp_path, rng):
    bag = tmp_path / "recording"
    expected = _rosbags_bag(bag, rng, StoragePlugin.MCAP)
    assert bag_files(bag) == ("mcap", [str(bag / "recording.mcap")])
    _check_read(bag, expected)


def test_reads_the_files_of_a_split_bag_in_the_order_of_metadata(tmp_path, rng):
    """Two SQLite files, listed by metadata.yaml second-first: read in that order."""
    first, second = tmp_path / "a", tmp_path / "b"
    one, two = _rosbags_bag(first, rng, n=4), _rosbags_bag(second, rng, n=3)
    bag = tmp_path / "split"
    bag.mkdir()
    shutil.copy(second / "b.db3", bag / "split_0.db3")
    shutil.copy(first / "a.db3", bag / "split_1.db3")
    info = yaml.safe_load((first / "metadata.yaml").read_text())
    info["rosbag2_bagfile_information"]["relative_file_paths"] = ["split_0.db3", "split_1.db3"]
    for entry in info["rosbag2_bagfile_information"]["topics_with_message_count"]:
        entry["message_count"] = 7
    (bag / "metadata.yaml").write_text(yaml.safe_dump(info))
    type_name, log_times, datas = bag_messages(bag, "/pose")
    assert datas == two["/pose"][2] + one["/pose"][2]
    assert log_times.tolist() == [t + 1000 for t in [*two["/pose"][0], *one["/pose"][0]]]
    assert [t.count for t in bag_topics(bag)] == [7, 7, 7]


def test_reading_leaves_the_file_as_it_was_and_makes_no_side_file(tmp_path, rng):
    bag = tmp_path / "recording"
    _rosbags_bag(bag, rng)
    before = {p.name: (p.read_bytes(), p.stat().st_mtime_ns) for p in bag.iterdir()}
    bag_messages(bag, "/pose")
    bag_topics(bag / "recording.db3")
    assert {p.name: (p.read_bytes(), p.stat().st_mtime_ns) for p in bag.iterdir()} == before


# -- bags that a2b writes, read by rosbags ------------------------------------------------------


def _pose_datas(frame, ns, poses):
    """The CDR of PoseStamped messages, built with a2b's own layout (a2b.io.ros2.pose_stamped)."""
    cdr = ros2.pose_stamped(frame)
    rows = np.frombuffer(cdr.template * len(ns), np.uint8).reshape(len(ns), -1).copy()
    at = cdr.columns["stamp"][0]
    rows[:, at : at + 8] = ros2.stamp_words(ns).astype("<u8").view(np.uint8).reshape(-1, 8)
    at = cdr.columns["pose"][0]
    rows[:, at : at + 56] = poses.astype("<f8").view(np.uint8).reshape(-1, 56)
    return [row.tobytes() for row in rows]


def _tf_datas(ns, poses):
    cdr = ros2.tf_message("map", "tool")
    rows = np.frombuffer(cdr.template * len(ns), np.uint8).reshape(len(ns), -1).copy()
    at = cdr.columns["stamp"][0]
    rows[:, at : at + 8] = ros2.stamp_words(ns).astype("<u8").view(np.uint8).reshape(-1, 8)
    at = cdr.columns["pose"][0]
    rows[:, at : at + 56] = poses.astype("<f8").view(np.uint8).reshape(-1, 56)
    return [row.tobytes() for row in rows]


def _a2b_bag(folder, rng, n=50):
    ns = 1_000_000_000 + np.arange(n, dtype=np.int64) * 5_000_000
    poses = _poses(rng, n)
    topics = [
        ("/a2b/pose", "geometry_msgs/msg/PoseStamped", ros2.qos_profiles(10)),
        ("/tf", "tf2_msgs/msg/TFMessage", ros2.qos_profiles(100)),
    ]
    pose_datas, tf_datas = _pose_datas("map", ns, poses), _tf_datas(ns, poses)
    messages = [(0, int(t), d) for t, d in zip(ns, pose_datas)]
    messages += [(1, int(t), d) for t, d in zip(ns, tf_datas)]
    messages.sort(key=lambda m: (m[1], m[0]))
    assert write_sqlite_bag(folder, topics, iter(messages)) == 2 * n
    return ns, poses, {"/a2b/pose": pose_datas, "/tf": tf_datas}


def test_rosbags_reads_every_message_of_a2b_bag(tmp_path, rng):
    bag = tmp_path / "out"
    ns, poses, datas = _a2b_bag(bag, rng)
    assert sorted(os.listdir(bag)) == ["metadata.yaml", "out_0.db3"]
    with Reader(bag) as reader:
        assert reader.message_count == 2 * len(ns)
        assert reader.start_time == ns[0] and reader.end_time == ns[-1] + 1
        assert {c.topic: (c.msgtype, c.msgcount) for c in reader.connections} == {
            "/a2b/pose": ("geometry_msgs/msg/PoseStamped", len(ns)),
            "/tf": ("tf2_msgs/msg/TFMessage", len(ns)),
        }
        qos = {
            c.topic: [(q.history.value, q.depth, q.reliability.value, q.durability.value)
                      for q in c.ext.offered_qos_profiles]
            for c in reader.connections
        }  # fmt: skip
        assert qos == {"/a2b/pose": [(1, 10, 1, 2)], "/tf": [(1, 100, 1, 2)]}
    with AnyReader([bag]) as reader:  # its types from the bag's message_definitions
        got = {"/a2b/pose": [], "/tf": []}
        for connection, log_time, raw in reader.messages():
            msg = reader.deserialize(raw, connection.msgtype)
            pose = msg.pose if connection.topic == "/a2b/pose" else msg.transforms[0].transform
            stamp = (
                msg.header if connection.topic == "/a2b/pose" else msg.transforms[0].header
            ).stamp
            position = getattr(pose, "position", None) or pose.translation
            orientation = getattr(pose, "orientation", None) or pose.rotation
            numbers = [position.x, position.y, position.z, orientation.x, orientation.y,
                       orientation.z, orientation.w]  # fmt: skip
            got[connection.topic].append((log_time, stamp.sec * 10**9 + stamp.nanosec, numbers))
            assert bytes(raw) == datas[connection.topic][len(got[connection.topic]) - 1]
    for topic in got:
        assert [g[0] for g in got[topic]] == ns.tolist() == [g[1] for g in got[topic]]
        assert np.array([g[2] for g in got[topic]]).tobytes() == poses.tobytes()


def test_a2b_bag_is_what_rosbags_writes(tmp_path, rng):
    """The tables and columns of rosbags' SQLite bag (schema 4), and the type hashes and
    definitions rosbags computes."""
    _a2b_bag(tmp_path / "ours", rng, n=2)
    _rosbags_bag(tmp_path / "theirs", rng, n=2)

    def tables(path):
        with sqlite3.connect(path) as db:
            names = [r[0] for r in db.execute("SELECT name FROM sqlite_master ORDER BY name")]
            layout = {n: [r[1:3] for r in db.execute(f"PRAGMA table_info({n})")] for n in names
                      if not n.endswith("_idx")}  # fmt: skip
            return names, layout, db.execute("SELECT schema_version FROM schema").fetchall()

    assert tables(tmp_path / "ours" / "ours_0.db3") == tables(tmp_path / "theirs" / "theirs.db3")
    for name, digest in TYPE_HASHES.items():
        assert STORE.hash_rihs01(name) == digest
    with sqlite3.connect(tmp_path / "ours" / "ours_0.db3") as db:
        rows = db.execute("SELECT topic_type, encoding, encoded_message_definition, "
                          "type_description_hash FROM message_definitions").fetchall()  # fmt: skip
    names = ("geometry_msgs/msg/PoseStamped", "tf2_msgs/msg/TFMessage")
    definitions = [STORE.generate_msgdef(n, ros_version=2)[0] for n in names]
    assert rows == [(n, "ros2msg", d, TYPE_HASHES[n]) for n, d in zip(names, definitions)]
    info = yaml.safe_load((tmp_path / "ours" / "metadata.yaml").read_text())
    theirs = yaml.safe_load((tmp_path / "theirs" / "metadata.yaml").read_text())
    assert info.keys() == theirs.keys()
    assert (
        info["rosbag2_bagfile_information"].keys() == theirs["rosbag2_bagfile_information"].keys()
    )


def test_a2b_reads_its_own_bag_back(tmp_path, rng):
    bag = tmp_path / "out"
    ns, poses, datas = _a2b_bag(bag, rng)
    for topic in datas:
        type_name, log_times, got = bag_messages(bag, topic)
        assert got == datas[topic] and (log_times == ns).all()
        times, quat, trans, _ = ros2.decode_poses(type_name, got, topic)
        assert (trans == poses[:, :3]).all() and (quat == poses[:, [6, 3, 4, 5]]).all()


def test_evo_reads_a2b_bag_with_a_full_check(tmp_path, clients, rng):
    bag = tmp_path / "turn"
    _a2b_bag(bag, rng, n=200)
    out = evo_full_check(clients, str(bag), tmp_path)
    assert "nr. of poses\t200" in out and "duration (s)\t0.995" in out


# -- writing: whole or not at all ---------------------------------------------------------------


def _topics():
    return [("/a2b/pose", "geometry_msgs/msg/PoseStamped", ros2.qos_profiles(10))]


def test_a_failure_while_writing_leaves_nothing(tmp_path):
    def messages():
        yield 0, 1, b"\x00\x01\x00\x00"
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        write_sqlite_bag(tmp_path / "bag", _topics(), messages())
    assert os.listdir(tmp_path) == []


def test_an_existing_bag_is_replaced_and_other_folders_are_refused(tmp_path, rng):
    bag = tmp_path / "out"
    _a2b_bag(bag, rng, n=3)
    (bag / "out_1.db3").write_bytes(b"an older split file")
    ns, _poses_, datas = _a2b_bag(bag, rng, n=5)
    assert sorted(os.listdir(bag)) == ["metadata.yaml", "out_0.db3"]
    assert bag_messages(bag, "/tf")[2] == datas["/tf"]
    assert sorted(os.listdir(tmp_path)) == ["out"]
    notes = tmp_path / "notes"
    notes.mkdir()
    (notes / "todo.txt").write_text("keep me")
    with pytest.raises(OutputFileError, match=r"notes: the folder exists and is no rosbag2 bag "
                       r"\(it holds todo.txt\)"):  # fmt: skip
        write_sqlite_bag(notes, _topics(), [])
    (tmp_path / "file").write_text("keep me")
    with pytest.raises(OutputFileError, match="it is a file, not a folder"):
        write_sqlite_bag(tmp_path / "file", _topics(), [])
    assert (notes / "todo.txt").read_text() == (tmp_path / "file").read_text() == "keep me"


def test_an_empty_bag_reads_back_empty(tmp_path):
    assert write_sqlite_bag(tmp_path / "empty", _topics(), []) == 0
    type_name, times, datas = bag_messages(tmp_path / "empty", "/a2b/pose")
    assert type_name == "geometry_msgs/msg/PoseStamped" and len(times) == 0 and datas == []
    with Reader(tmp_path / "empty") as reader:
        assert [c.msgcount for c in reader.connections] == [0]


@pytest.mark.parametrize(
    "topics, messages, match",
    [
        ([("a2b/pose", "geometry_msgs/msg/PoseStamped", "")], [], "not a ROS 2 topic name"),
        ([("/a", "geometry_msgs/PoseStamped", "")], [], "is not package/msg/Name"),
        (_topics() * 2, [], "given twice: /a2b/pose"),
        (_topics(), [(1, 0, b"")], "a message names topic 1; there are 1"),
        (_topics(), [(0, -1, b"")], r"time -1 ns is outside \[0, 2\*\*63\)"),
    ],
)
def test_wrong_topics_and_messages_are_refused(tmp_path, topics, messages, match):
    with pytest.raises(ParameterError, match=match):
        write_sqlite_bag(tmp_path / "bag", topics, messages)
    assert os.listdir(tmp_path) == []


# -- hostile bags -------------------------------------------------------------------------------


@pytest.fixture
def bag(tmp_path, rng):
    """A small a2b bag to damage."""
    _a2b_bag(tmp_path / "bag", rng, n=4)
    return tmp_path / "bag"


def _edit_metadata(bag, **changes):
    info = yaml.safe_load((bag / "metadata.yaml").read_text())
    info["rosbag2_bagfile_information"].update(changes)
    (bag / "metadata.yaml").write_text(yaml.safe_dump(info))


def _one_line(excinfo):
    text = str(excinfo.value)
    assert "\n" not in text and len(text) < 400, text
    return text


@pytest.mark.parametrize(
    "changes, match",
    [
        ({"relative_file_paths": ["bag_0.db3", "bag_1.db3"]},
         "1 of the 2 files it lists are missing: bag_1.db3"),
        ({"relative_file_paths": ["../bag_0.db3"]}, "'../bag_0.db3' is not a name inside"),
        ({"relative_file_paths": ["/etc/passwd"]}, "'/etc/passwd' is not a name inside"),
        ({"relative_file_paths": ["bag_0.db3", "bag_0.db3"]}, "lists bag_0.db3 twice"),
        ({"relative_file_paths": "bag_0.db3"}, "relative_file_paths is not a list"),
        ({"relative_file_paths": ["bag_0.db3\x1b[2J"]}, r"'bag_0.db3\\x1b\[2J' is not a name"),
        ({"relative_file_paths": ["."]}, "'.' is not a name inside"),
        ({"storage_identifier": "x" * 10**4}, "storage_identifier 'x{79}…; a2b reads sqlite3"),
        ({"version": 10}, "version 10; a2b reads rosbag2 metadata versions 1 to 9"),
        ({"storage_identifier": "rosbag_v2"}, "storage_identifier 'rosbag_v2'"),
        ({"compression_mode": "FILE"}, "the bag is compressed"),
        ({"topics_with_message_count": [{"message_count": 4}]}, "entry 1 lacks topic_metadata"),
    ],
)  # fmt: skip
def test_metadata_that_lies_is_refused(bag, changes, match):
    _edit_metadata(bag, **changes)
    with pytest.raises(InputFileError, match=match) as excinfo:
        bag_messages(bag, "/tf")
    assert _one_line(excinfo).startswith(str(bag))


def test_metadata_counts_and_types_are_checked_against_the_files(bag):
    info = yaml.safe_load((bag / "metadata.yaml").read_text())
    entries = info["rosbag2_bagfile_information"]["topics_with_message_count"]
    entries[1]["message_count"] = 5
    _edit_metadata(bag, topics_with_message_count=entries)
    with pytest.raises(InputFileError, match="says /tf has 5 messages, the files hold 4"):
        bag_topics(bag)
    with pytest.raises(InputFileError, match="says /tf has 5 messages, the files hold 4"):
        bag_messages(bag, "/tf")
    entries[1]["message_count"] = 4
    entries[1]["topic_metadata"]["type"] = "geometry_msgs/msg/PoseStamped"
    _edit_metadata(bag, topics_with_message_count=entries)
    with pytest.raises(InputFileError, match="/tf has two types, geometry_msgs/msg/PoseStamped "
                       "and tf2_msgs/msg/TFMessage"):  # fmt: skip
        bag_messages(bag, "/tf")


def test_a_link_out_of_the_folder_and_a_folder_without_metadata_are_refused(bag, tmp_path):
    outside = tmp_path / "elsewhere.db3"
    shutil.move(bag / "bag_0.db3", outside)
    os.symlink(outside, bag / "bag_0.db3")
    with pytest.raises(InputFileError, match="a link to a file outside the bag folder"):
        bag_files(bag)
    os.unlink(bag / "metadata.yaml")
    with pytest.raises(InputFileError, match=r"bag: no metadata.yaml, so not a rosbag2 bag"):
        bag_topics(bag)
    assert not is_bag(bag)


def test_a_fifo_is_not_opened(bag):
    os.unlink(bag / "bag_0.db3")
    os.mkfifo(bag / "bag_0.db3")
    with pytest.raises(InputFileError, match="bag_0.db3: not a regular file"):
        bag_messages(bag, "/tf")


def _damage(bag, *statements):
    with sqlite3.connect(bag / "bag_0.db3") as db:
        for statement in statements:
            db.execute(statement)
    db.close()


@pytest.mark.parametrize(
    "statements, match",
    [
        (["DROP TABLE messages"], "a SQLite file but not a rosbag2 bag: no table messages"),
        (["ALTER TABLE topics DROP COLUMN serialization_format"],
         "the table topics lacks serialization_format"),
        (["UPDATE messages SET topic_id = 7 WHERE id < 3"],
         "2 messages name topic ids that the topics table lacks: 7"),
        (["UPDATE topics SET type = 'nav_msgs/msg/Odometry', name = '/tf' WHERE id = 1"],
         "the topic /tf has two types, nav_msgs/msg/Odometry and tf2_msgs/msg/TFMessage"),
        (["UPDATE topics SET serialization_format = 'json' WHERE id = 2"],
         "the topic /tf is serialized as json; a2b reads cdr"),
        (["PRAGMA writable_schema = 1",
          "UPDATE sqlite_master SET sql = replace(sql, 'data BLOB NOT NULL', 'data BLOB') "
          "WHERE name = 'messages'"], None),
    ],
)  # fmt: skip
def test_sqlite_files_that_are_no_rosbag2_bag_are_refused(bag, statements, match):
    _damage(bag, *statements)
    if match is None:  # NOT NULL dropped: now a NULL data can be stored
        _damage(bag, "UPDATE messages SET data = NULL WHERE id = 4")
        match = r"bag_0.db3: message id 4 of /tf: its data is null, not a blob"
    with pytest.raises(InputFileError, match=match) as excinfo:
        bag_messages(bag, "/tf")
    assert str(bag / "bag_0.db3") in _one_line(excinfo)


def test_text_instead_of_a_blob_and_a_text_timestamp_are_refused(bag):
    _damage(bag, "UPDATE messages SET data = 'text' WHERE id = 2")
    with pytest.raises(InputFileError, match="message id 2 of /tf: its data is text, not a blob"):
        bag_messages(bag, "/tf")
    _damage(bag, "UPDATE messages SET data = x'00', timestamp = 'noon' WHERE id = 2")
    with pytest.raises(InputFileError, match="its timestamp is text, not an integer"):
        bag_messages(bag, "/tf")


def test_files_that_are_no_sqlite_are_refused(tmp_path, bag):
    (tmp_path / "notes.db3").write_text("SQLite? no.")
    with pytest.raises(InputFileError, match=r"notes.db3: not a SQLite file"):
        bag_topics(tmp_path / "notes.db3")
    assert not is_bag(tmp_path / "notes.db3")
    data = bytearray((bag / "bag_0.db3").read_bytes())
    data[100:4096] = b"\xff" * 3996  # the first page's b-tree, past the header
    (tmp_path / "broken.db3").write_bytes(data)
    with pytest.raises(InputFileError, match=r"broken.db3: not a readable rosbag2 SQLite file"):
        bag_topics(tmp_path / "broken.db3")
    (bag / "bag_0.db3-wal").write_bytes(b"\0" * 32)
    with pytest.raises(InputFileError, match="its write-ahead log bag_0.db3-wal is not empty"):
        bag_topics(bag)


def test_an_unknown_topic_names_the_ones_there_are(bag):
    with pytest.raises(InputFileError, match=r"bag: no topic /odom; the bag has /a2b/pose, /tf$"):
        bag_messages(bag, "/odom")


def test_a_topic_larger_than_allowed_is_refused_before_it_is_read(bag):
    size = sum(map(len, bag_messages(bag, "/tf")[2])) + 4 * 64
    assert len(bag_messages(bag, "/tf", max_bytes=size)[2]) == 4
    with pytest.raises(InputFileError, match=r"the topic /tf holds 0.0 MiB in 4 messages here, "
                       r"more than the 0.0 MiB allowed \(max_bytes\)"):  # fmt: skip
        bag_messages(bag, "/tf", max_bytes=size - 1)


def test_a_name_with_control_characters_is_escaped(bag):
    _damage(bag, "UPDATE topics SET name = '/tf' || char(27) || '[2J' || char(10) WHERE id = 2")
    with pytest.raises(InputFileError) as excinfo:
        bag_messages(bag / "bag_0.db3", "/nothing")
    assert _one_line(excinfo).endswith(r"the bag has /a2b/pose, /tf\x1b[2J\n")
    with pytest.raises(InputFileError, match="metadata.yaml: lists topics the files lack: /tf$"):
        bag_topics(bag)


# -- memory ---------------------------------------------------------------------------------------

_MEMORY = """
import resource, sys
import numpy as np
from a2b.io import ros2
from a2b.io.rosbag2 import bag_messages, write_sqlite_bag
from a2b.errors import InputFileError

def peak():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024  # MiB

folder, n = sys.argv[1], int(sys.argv[2])
data = bytes(ros2.pose_stamped("map").template) + bytes(600)
topics = [("/a2b/pose", "geometry_msgs/msg/PoseStamped", ros2.qos_profiles(10))]
write_sqlite_bag(folder + "/warm", topics, ((0, k, data) for k in range(10)))
bag_messages(folder + "/warm", "/a2b/pose")
before = peak()
write_sqlite_bag(folder + "/big", topics, ((0, k, data) for k in range(n)))
written = peak()
try:
    bag_messages(folder + "/big", "/a2b/pose", max_bytes=1 << 20)
except InputFileError as e:
    refused = str(e).replace(" ", "_")
refused_peak = peak()
_type, times, datas = bag_messages(folder + "/big", "/a2b/pose")
assert len(datas) == n and datas[-1] == data and times[-1] == n - 1
print(before, written, refused_peak, peak(), refused)
"""


def test_a_big_bag_is_written_and_refused_in_bounded_memory(tmp_path):
    n = 100_000  # 68 MB of messages, 676 bytes each
    done = subprocess.run(
        [sys.executable, "-c", _MEMORY, str(tmp_path), str(n)],
        capture_output=True, text=True, timeout=300,
        env=dict(os.environ, PYTHONPATH=str(Path(__file__).parent.parent)),
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    *peaks, message = done.stdout.split()
    before, written, refused_peak, read_peak = map(float, peaks)
    assert os.path.getsize(tmp_path / "big" / "big_0.db3") > 60e6
    assert written - before < 25, done.stdout  # MiB, for 68 MB written
    assert refused_peak - before < 25, done.stdout
    data_mib = n * 676 / 2**20  # what the topic holds; read, it costs the data and a little
    assert read_peak - before < 1.3 * data_mib + 25, done.stdout
    assert "more_than_the_1.0_MiB_allowed" in message


# -- older bags, other damage -------------------------------------------------------------------


@pytest.mark.parametrize(
    "statements",
    [
        [  # schema 3, ROS 2 Humble: no type hashes, no message definitions
            "ALTER TABLE topics DROP COLUMN type_description_hash",
            "DROP TABLE message_definitions",
            "UPDATE schema SET schema_version = 3",
        ],
        [  # schema 1, before QoS profiles and the schema table
            "ALTER TABLE topics DROP COLUMN type_description_hash",
            "ALTER TABLE topics DROP COLUMN offered_qos_profiles",
            "DROP TABLE message_definitions",
            "DROP TABLE schema",
            "DROP TABLE metadata",
        ],
    ],
)
def test_older_sqlite_schemas_read(tmp_path, rng, statements):
    ns, poses, datas = _a2b_bag(tmp_path / "bag", rng, n=6)
    _damage(tmp_path / "bag", *statements)
    type_name, log_times, got = bag_messages(tmp_path / "bag", "/tf")
    assert type_name == "tf2_msgs/msg/TFMessage" and got == datas["/tf"]
    assert (log_times == ns).all()


def test_metadata_before_version_4_names_files_with_the_folder(bag):
    _edit_metadata(bag, version=3, relative_file_paths=["bag/bag_0.db3"])
    assert bag_files(bag) == ("sqlite3", [str(bag / "bag_0.db3")])
    _edit_metadata(bag, version=3, relative_file_paths=["renamed/bag_0.db3"])
    assert bag_files(bag) == ("sqlite3", [str(bag / "bag_0.db3")])
    for version, name in ((3, "a/b/bag_0.db3"), (3, "../bag_0.db3"), (4, "bag/bag_0.db3")):
        _edit_metadata(bag, version=version, relative_file_paths=[name])
        with pytest.raises(InputFileError, match=f"'{name}' is not a name inside"):
            bag_files(bag)


@pytest.mark.parametrize(
    "text, match",
    [
        ("rosbag2_bagfile_information: [1, 2", "not readable YAML"),
        ("- a list", "no mapping rosbag2_bagfile_information"),
        ("rosbag2_bagfile_information: {version: '8'}", "version '8'; a2b reads rosbag2"),
        ("\ufeff\x00", "not readable YAML"),
    ],
)
def test_metadata_that_is_no_bag_metadata_is_refused(bag, text, match):
    (bag / "metadata.yaml").write_text(text)
    with pytest.raises(InputFileError, match=match) as excinfo:
        bag_topics(bag)
    assert _one_line(excinfo).startswith(str(bag / "metadata.yaml"))


def test_a_huge_metadata_file_is_refused_unread(bag):
    with open(bag / "metadata.yaml", "ab") as f:
        f.truncate(17 << 20)
    with pytest.raises(InputFileError, match="metadata.yaml: larger than 16 MiB"):
        bag_topics(bag)


def test_a_damaged_mcap_file_in_a_folder_is_one_error(tmp_path, rng):
    bag = tmp_path / "recording"
    _rosbags_bag(bag, rng, StoragePlugin.MCAP, n=3)
    data = (bag / "recording.mcap").read_bytes()
    (bag / "recording.mcap").write_bytes(data[: len(data) // 2] + b"\xff" * 64)
    with pytest.raises(InputFileError, match=r"recording.mcap: the file ends without") as e:
        bag_messages(bag, "/pose")
    _one_line(e)
    _rosbags_bag(tmp_path / "again", rng, StoragePlugin.MCAP, n=3)
    with pytest.raises(InputFileError, match=r"again: no topic /nothing; the bag has /pose, /odom"):
        bag_messages(tmp_path / "again", "/nothing")


def test_a_message_that_is_no_bytes_is_refused(tmp_path):
    with pytest.raises(ParameterError, match="a message's data is str, not bytes"):
        write_sqlite_bag(tmp_path / "bag", _topics(), [(0, 5, "text")])
    with pytest.raises(ParameterError, match=r"a message is \(0, 1.5, b''\), not \(topic index"):
        write_sqlite_bag(tmp_path / "bag", _topics(), [(0, 1.5, b"")])
    with pytest.raises(OutputFileError, match="cannot write .*: No such file or directory"):
        write_sqlite_bag(tmp_path / "missing" / "bag", _topics(), [])
    assert os.listdir(tmp_path) == []


def test_a_topic_recorded_with_two_qos_settings_is_one_topic(tmp_path, rng):
    ns, _poses_, datas = _a2b_bag(tmp_path / "bag", rng, n=6)
    _damage(
        tmp_path / "bag",
        "INSERT INTO topics VALUES(3, '/tf', 'tf2_msgs/msg/TFMessage', 'cdr', '', '')",
        "UPDATE messages SET topic_id = 3 WHERE topic_id = 2 AND id % 4 = 0",
    )
    type_name, log_times, got = bag_messages(tmp_path / "bag" / "bag_0.db3", "/tf")
    assert got == datas["/tf"] and (log_times == ns).all()
    assert [(t.name, t.count) for t in bag_topics(tmp_path / "bag")] == [("/a2b/pose", 6),
                                                                         ("/tf", 6)]  # fmt: skip


def test_names_with_uri_characters_are_read_and_written(tmp_path, rng):
    folder = tmp_path / "a?b#c%20d e"
    ns, _poses_, datas = _a2b_bag(folder, rng, n=3)
    assert sorted(os.listdir(folder)) == ["a?b#c%20d e_0.db3", "metadata.yaml"]
    assert bag_messages(folder, "/a2b/pose")[2] == datas["/a2b/pose"]


@pytest.mark.parametrize(
    "statements, match",
    [
        (["ALTER TABLE messages RENAME TO stored",
          "CREATE VIEW messages AS WITH RECURSIVE c(x) AS (SELECT 1 UNION ALL SELECT x + 1 "
          "FROM c) SELECT x AS id, 2 AS topic_id, x AS timestamp, zeroblob(1000000) AS data "
          "FROM c"], "messages is a view of SQL, not a plain table"),
        (["ALTER TABLE messages ADD COLUMN more BLOB GENERATED ALWAYS AS (zeroblob(1000000))"],
         "messages has computed columns: more"),
    ],
)  # fmt: skip
def test_views_and_computed_columns_are_refused_unread(bag, statements, match):
    """An endless view or a computed blob would hang or allocate without bytes in the file."""
    _damage(bag, *statements)
    with pytest.raises(InputFileError, match=match):
        bag_messages(bag / "bag_0.db3", "/tf")
