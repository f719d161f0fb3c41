"""TF as a tree: a frame's pose composed through /tf and /tf_static (a2b.io.tftree).

The files are written by the `mcap` package, with TFMessages in CDR made here by struct; the
expected poses are products of the transforms written, and the interpolated ones a screw about
z, whose ScLERP is linear in angle and height.
"""

from __future__ import annotations

import struct

import numpy as np
import pytest
from click.testing import CliRunner

from a2b.cli import cli
from a2b.errors import InputFileError
from a2b.io import ros2
from a2b.io.tftree import TransformRecords, compose
from a2b.io.trajectories import read_trajectory
from a2b.poses import matrices_from_quat_trans

mcap_writer = pytest.importorskip("mcap.writer")

TF = "tf2_msgs/msg/TFMessage"


def _unit(rng, n):
    q = rng.normal(size=(n, 4))
    return q / np.linalg.norm(q, axis=1, keepdims=True)


def _about_z(angle, height):
    """quat_wxyz and translation of a turn by ``angle`` about z and a lift by ``height``."""
    quat = np.stack([np.cos(angle / 2), 0 * angle, 0 * angle, np.sin(angle / 2)], axis=-1)
    trans = np.stack([0 * angle, 0 * angle, height], axis=-1)
    return quat, trans


def _transform(t, parent, child, quat, trans):
    """A TransformStamped: ``(sec, nanosec, parent, child, x y z qx qy qz qw)``."""
    sec, nanosec = divmod(round(t * 1e9), 10**9)
    return sec, nanosec, parent, child, [*map(float, trans), *map(float, quat[1:]), float(quat[0])]


def _tf_message(transforms) -> bytes:
    """CDR of a ``tf2_msgs/msg/TFMessage`` (little endian), each field aligned to its size
    from the end of the 4-byte encapsulation header."""
    body = bytearray(struct.pack("<I", len(transforms)))

    def align(size):
        body.extend(b"\0" * (-len(body) % size))

    for sec, nanosec, parent, child, numbers in transforms:
        align(4)
        body += struct.pack("<iI", sec, nanosec)
        for name in (parent, child):
            align(4)
            body += struct.pack("<I", len(name) + 1) + name.encode() + b"\0"
        align(8)
        body += struct.pack("<7d", *numbers)
    return b"\0\x01\0\0" + bytes(body)


def _write(path, messages):
    """``messages``: (topic, [transform, …]) in log order, written by the `mcap` package."""
    with open(path, "wb") as f:
        writer = mcap_writer.Writer(f)
        writer.start(profile="ros2")
        schema = writer.register_schema(TF, "ros2msg", ros2.schema_text("tf2_msgs/TFMessage"))
        channels = {}
        for i, (topic, transforms) in enumerate(messages):
            if topic not in channels:
                channels[topic] = writer.register_channel(topic, "cdr", schema)
            writer.add_message(channels[topic], i, _tf_message(transforms), i)
        writer.finish()


@pytest.fixture
def chain_file(tmp_path, rng):
    """map→odom (a screw about z at 0, 1, 2, 3 s), odom→base_link (random, every 0.5 s),
    base_link→camera on /tf_static, and base_link→lidar, which is not on the way."""
    odom_times = np.arange(4.0)
    base_times = np.arange(7) * 0.5
    odom = _about_z(rng.uniform(-1, 1, 4), rng.uniform(-1, 1, 4))
    base = _unit(rng, 7), rng.normal(size=(7, 3))
    camera = _unit(rng, 1)[0], rng.normal(size=3)
    lidar = _unit(rng, 1)[0], rng.normal(size=3)
    messages = [("/tf_static", [_transform(0.0, "base_link", "camera", *camera),
                                _transform(0.0, "base_link", "lidar", *lidar)])]  # fmt: skip
    for t, q, p in zip(base_times, *base):
        transforms = [_transform(t, "odom", "base_link", q, p)]
        if t in odom_times:
            k = int(t)
            transforms.insert(0, _transform(t, "map", "odom", odom[0][k], odom[1][k]))
        messages.append(("/tf", transforms))
    path = tmp_path / "tf.mcap"
    _write(path, messages)
    return path, odom, base, camera, base_times


def _read(path, **options):
    with open(path, "rb") as f:
        return read_trajectory(f, **options)


def test_a_camera_composed_through_the_chain_is_the_product_of_the_transforms(chain_file):
    path, (odom_q, odom_p), base, camera, base_times = chain_file
    got = _read(path, input_frame="map", child_frame="camera")
    assert got.times.tolist() == base_times.tolist()
    # map→odom at the half seconds: the screw about z, halfway in angle and height
    angle = 2 * np.arctan2(odom_q[:, 3], odom_q[:, 0])
    angle = np.interp(base_times, np.arange(4.0), np.unwrap(angle))
    height = np.interp(base_times, np.arange(4.0), odom_p[:, 2])
    want = (
        matrices_from_quat_trans(*_about_z(angle, height))
        @ matrices_from_quat_trans(*base)
        @ matrices_from_quat_trans(camera[0][None], camera[1][None])
    )
    np.testing.assert_allclose(got.matrices, want, rtol=0, atol=1e-12)
    assert "TF chain map → odom → base_link → camera" in got.notes[0]
    assert "base_link→camera static" in got.notes[0]


def test_one_dynamic_link_reads_as_the_file_holds_it(chain_file):
    path, _, (quat, trans), _, base_times = chain_file
    got = _read(path, input_frame="odom", child_frame="base_link")
    assert got.times.tolist() == base_times.tolist()
    assert got.quat_wxyz.tolist() == quat.tolist() and got.trans.tolist() == trans.tolist()


def test_the_cli_states_the_chain(chain_file, tmp_path):
    path = chain_file[0]
    out = tmp_path / "camera.csv"
    result = CliRunner().invoke(cli, ["resample", str(path), "--input-frame", "map",
                                      "--input-child-frame", "camera", "--rate", "4", "-o",
                                      str(out), "-v"])  # fmt: skip
    assert result.exit_code == 0, result.output
    assert "TF chain map → odom → base_link → camera" in result.output
    assert len(out.read_text().splitlines()) == 1 + 13  # 0 to 3 s at 4 Hz


@pytest.mark.parametrize(
    ("parent", "child", "message"),
    [
        ("world", "camera", r"no transform to the frame 'map', so no chain from 'world' to "
                            r"'camera' \(found up to 'map' → 'odom' → 'base_link' → 'camera'"),
        ("map", "gripper", r"no transform to the frame 'gripper'"),
        ("map", "map", r"one frame"),
    ],
)  # fmt: skip
def test_a_broken_chain_names_the_frames(chain_file, parent, child, message):
    with pytest.raises(InputFileError, match=message):
        _read(chain_file[0], input_frame=parent, child_frame=child)


def test_a_frame_with_two_parents_is_refused(tmp_path):
    q, p = np.array([1.0, 0, 0, 0]), np.zeros(3)
    path = tmp_path / "two.mcap"
    _write(path, [("/tf", [_transform(0.0, "map", "base", q, p)]),
                  ("/tf", [_transform(1.0, "odom", "base", q, p)])])  # fmt: skip
    with pytest.raises(InputFileError, match=r"the frame 'base' has two parents, map, odom; "):
        _read(path, input_frame="map", child_frame="base")


def test_no_transform_before_the_first_stamp_names_the_link(tmp_path):
    q, p = np.array([1.0, 0, 0, 0]), np.zeros(3)
    path = tmp_path / "late.mcap"
    _write(path, [("/tf", [_transform(0.0, "odom", "base", q, p)]),
                  ("/tf", [_transform(0.5, "map", "odom", q, p)]),
                  ("/tf", [_transform(1.0, "odom", "base", q, p)]),
                  ("/tf", [_transform(1.0, "map", "odom", q, p)])])  # fmt: skip
    with pytest.raises(InputFileError, match=r"no transform 'map'→'odom' at or before 0\.0 s, "
                                             r"the first stamp of 'odom'→'base'"):  # fmt: skip
        _read(path, input_frame="map", child_frame="base")


def test_input_frame_needs_a_child_frame_and_mcap(chain_file, tmp_path):
    with pytest.raises(InputFileError, match="--input-frame needs --input-child-frame"):
        _read(chain_file[0], input_frame="map")
    tum = tmp_path / "a.tum"
    tum.write_text("0 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 1\n")
    with pytest.raises(InputFileError, match="--input-frame does not apply to tum input"):
        _read(tum, input_frame="map")


def test_the_tree_composes_records_of_any_container(rng):
    """The records alone, as a rosbag2 reader decodes them: a static link latched at its last
    transform, a dynamic one sampled by the mode chosen."""
    quat, trans = _unit(rng, 3), rng.normal(size=(3, 3))
    records = TransformRecords(
        np.array(["a", "a", "b"], object), np.array(["b", "b", "c"], object),
        np.array([0.0, 2.0, 5.0]), quat, trans, np.array([False, False, True]),
    )  # fmt: skip
    times, q, p, statement = compose(records, "a", "c", "records", mode="screw")
    assert times.tolist() == [0.0, 2.0]
    want = matrices_from_quat_trans(quat[:2], trans[:2]) @ matrices_from_quat_trans(
        quat[2:], trans[2:]
    )
    np.testing.assert_allclose(matrices_from_quat_trans(q, p), want, rtol=0, atol=1e-12)
    assert statement.startswith("TF chain a → b → c (a→b dynamic, b→c static)")
