"""ROS 2 bags as input (issue 28): folders with metadata.yaml (SQLite and MCAP storage) and bare
.db3 files written by rosbags' Writer read back bit for bit by ``a2b resample``, each topic by
its own type; every choice stated under -v; options and inputs that do not fit refused."""

from __future__ import annotations

import shutil

import numpy as np
import pytest
from click.testing import CliRunner

from a2b.cli import cli

pytest.importorskip("rosbags")
from .test_rosbag2 import StoragePlugin, _rosbags_bag  # noqa: E402

SAMPLES = __import__("pathlib").Path(__file__).resolve().parent.parent / "samples"


def run(*args):
    return CliRunner().invoke(cli, [str(a) for a in args])


@pytest.fixture(scope="module")
def bags(tmp_path_factory):
    """A SQLite and an MCAP bag folder of rosbags, and what they hold."""
    rng = np.random.default_rng(28)
    root = tmp_path_factory.mktemp("bags")
    return {
        "sqlite3": (root / "sq", _rosbags_bag(root / "sq", rng)),
        "mcap": (root / "mc", _rosbags_bag(root / "mc", rng, StoragePlugin.MCAP)),
    }


def _resampled(tmp_path, source, topic, ns, *extra):
    """``a2b resample SOURCE --topic TOPIC`` at the stamps ``ns``: times and the csv numbers."""
    times = tmp_path / "stamps.txt"
    seconds = (ns // 10**9).astype(float) + (ns % 10**9).astype(float) * 1e-9
    times.write_text("".join(f"{float(t)!r}\n" for t in seconds))
    out = tmp_path / "out.csv"
    result = run("resample", source, "--topic", topic, "--times", times, "-o", out, *extra)
    assert result.exit_code == 0, result.output
    rows = np.array([[float(x) for x in line.split(",")]
                     for line in out.read_text().splitlines()[1:]])  # fmt: skip
    assert np.array_equal(rows[:, 0], seconds)
    return rows


@pytest.mark.parametrize("storage", ["sqlite3", "mcap"])
@pytest.mark.parametrize("form", ["folder", "file"])
@pytest.mark.parametrize("topic", ["/pose", "/odom", "/tf"])
def test_rosbags_bags_read_back_bit_for_bit(tmp_path, bags, storage, form, topic):
    folder, expected = bags[storage]
    suffix = ".db3" if storage == "sqlite3" else ".mcap"
    source = folder if form == "folder" else folder / f"{folder.name}{suffix}"
    ns, poses, _datas = expected[topic]
    child = ["--input-child-frame", "camera"] if topic == "/tf" else []
    rows = _resampled(tmp_path, source, topic, ns, *child)
    want = poses.copy()
    if topic == "/tf":
        want[:, 0] += 1.0  # the camera is 1 m further in x (tests/test_rosbag2.py)
    assert np.array_equal(rows[:, 1:4], want[:, :3])
    assert np.array_equal(rows[:, 4:], want[:, [6, 3, 4, 5]])


def test_a_single_link_tf_needs_no_child_frame(tmp_path):
    """A /tf topic of one child frame is read without --input-child-frame."""
    from rosbags.rosbag2 import Writer

    from .test_rosbag2 import STORE, T, _header

    rng = np.random.default_rng(5)
    ns = 10**9 * np.arange(1, 6)
    poses = rng.normal(size=(5, 7))
    poses[:, 3:] /= np.linalg.norm(poses[:, 3:], axis=1, keepdims=True)
    bag = tmp_path / "tf"
    with Writer(bag, version=8) as writer:
        tf = writer.add_connection("/tf", "tf2_msgs/msg/TFMessage", typestore=STORE)
        for k in range(5):
            x, y, z, qx, qy, qz, qw = poses[k]
            transform = T["geometry_msgs/msg/Transform"](
                translation=T["geometry_msgs/msg/Vector3"](x=x, y=y, z=z),
                rotation=T["geometry_msgs/msg/Quaternion"](x=qx, y=qy, z=qz, w=qw),
            )
            message = T["tf2_msgs/msg/TFMessage"](transforms=[
                T["geometry_msgs/msg/TransformStamped"](
                    header=_header(ns[k], "map"), child_frame_id="base_link", transform=transform
                )
            ])  # fmt: skip
            writer.write(
                tf, int(ns[k]), bytes(STORE.serialize_cdr(message, "tf2_msgs/msg/TFMessage"))
            )
    rows = _resampled(tmp_path, bag, "/tf", ns)
    assert np.array_equal(rows[:, 1:4], poses[:, :3])
    assert np.array_equal(rows[:, 4:], poses[:, [6, 3, 4, 5]])
    result = run("resample", bag, "--rate", 1, "-v", "-o", tmp_path / "x.csv")
    assert "  • topic /tf: the only pose topic (--topic to change)" in result.output


def test_verbose_states_the_storage_and_the_topic(tmp_path, bags):
    folder, _ = bags["sqlite3"]
    result = run(
        "resample", folder, "--topic", "/pose", "--rate", 1, "-v", "-o", tmp_path / "o.csv"
    )
    assert result.exit_code == 0, result.output
    lines = result.output.splitlines()
    assert "  • input format rosbag2: from the file (--input-format to change)" in lines
    assert "  • storage sqlite3: 1 file that metadata.yaml lists" in lines
    assert "  • topic /pose: given with --topic" in lines
    result = run("resample", folder / "sq.db3", "--topic", "/pose", "--rate", 1, "-v",
                 "-o", tmp_path / "o.csv")  # fmt: skip
    assert "  • storage sqlite3: a .db3 alone" in result.output.splitlines()
    folder, _ = bags["mcap"]
    result = run("resample", folder, "--input-child-frame", "camera", "--rate", 1, "-v",
                 "-o", tmp_path / "o.csv")  # fmt: skip
    assert result.exit_code == 0, result.output
    assert "  • storage mcap: 1 file that metadata.yaml lists" in result.output
    assert "  • topic /tf: the only transform topic (--topic to change)" in result.output


def test_several_pose_topics_ask_for_one(bags):
    folder, _ = bags["sqlite3"]
    result = run("resample", folder, "--rate", 1)
    assert result.exit_code == 1
    assert result.output == (
        f"Error: {folder}: several pose topics (/odom, /pose, /tf); choose one with --topic\n"
    )


def test_the_topic_of_a2bs_own_mcap_is_stated(tmp_path):
    """The issue's silent choice: /a2b/pose, /tf and /a2b/path in one file."""
    mcap = tmp_path / "turn.mcap"
    made = run("interpolate", SAMPLES / "quarter-turn.yaml", "--format", "ros2", "-o", mcap)
    assert made.exit_code == 0, made.output
    result = run("resample", mcap, "--rate", 10, "-v", "-o", tmp_path / "o.csv")
    assert result.exit_code == 0, result.output
    assert (
        "  • topic /a2b/pose: a2b's own, of the pose topics /a2b/path, /a2b/pose, /tf "
        "(--topic to change)" in result.output.splitlines()
    )


def test_a_folder_without_metadata_is_a_clear_error(tmp_path):
    (tmp_path / "notabag").mkdir()
    result = run("resample", tmp_path / "notabag", "--rate", 1)
    assert result.exit_code == 1
    assert result.output == (
        f"Error: {tmp_path / 'notabag'}: no metadata.yaml, so not a rosbag2 bag folder "
        "(`ros2 bag reindex` writes one)\n"
    )


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--input-rate", "5"], "--input-rate does not apply to rosbag2 input"),
        (["--input-format", "tum"], "a folder; a2b reads folders as rosbag2 bags, not as tum"),
        (["--topic", "/nope"], "no topic '/nope'; the bag has /odom, /pose, /tf"),
        (["--topic", "/pose", "--input-child-frame", "x"], "--input-child-frame is for"),
    ],
)
def test_what_a_bag_cannot_use_is_refused(bags, args, message):
    folder, _ = bags["sqlite3"]
    result = run("resample", folder, "--rate", 1, *args)
    assert result.exit_code == 1 and message in result.output, result.output
    assert result.output.count("\n") == 1


def test_a_db3_on_standard_input_is_refused(bags):
    folder, _ = bags["sqlite3"]
    data = (folder / "sq.db3").read_bytes()
    result = CliRunner().invoke(cli, ["resample", "-", "--rate", "1"], input=data)
    assert result.exit_code == 1
    assert "a rosbag2 bag is read by its path (a folder or a .db3 file), not from a stream" in (
        result.output
    )


def test_spline_and_bezier_take_a_bag(tmp_path, bags):
    folder, _ = bags["mcap"]
    for command in ("spline", "bezier"):
        result = run(command, folder, "--topic", "/pose", "-v", "-o", tmp_path / "o.csv")
        assert result.exit_code == 0, result.output
        assert "  • topic /pose: given with --topic" in result.output


def test_a_bag_folder_moved_reads_the_same(tmp_path, bags):
    """metadata.yaml names the files in the folder, not the folder: a copy reads the same."""
    folder, expected = bags["sqlite3"]
    copy = tmp_path / "copy"
    shutil.copytree(folder, copy)
    ns, poses, _ = expected["/pose"]
    rows = _resampled(tmp_path, copy, "/pose", ns)
    assert np.array_equal(rows[:, 1:4], poses[:, :3])


def _tf_bag(path, rng, plugin):
    """A bag of rosbags' Writer: /tf with map→odom (a screw about z at 1, 2, 3, 4 s) and
    odom→base_link (random, every 0.5 s), /tf_static with base_link→camera. Returns the
    transforms (quat_wxyz, translations) of each and the stamps of base_link."""
    from rosbags.rosbag2 import Writer

    from .test_rosbag2 import STORE, T, _header
    from .test_tftree import _about_z, _unit

    base_times = 1.0 + np.arange(7) * 0.5
    odom = _about_z(rng.uniform(-1, 1, 4), rng.uniform(-1, 1, 4))
    base = _unit(rng, 7), rng.normal(size=(7, 3))
    camera = _unit(rng, 1), rng.normal(size=(1, 3))

    def stamped(t, parent, child, q, p):
        return T["geometry_msgs/msg/TransformStamped"](
            header=_header(round(t * 1e9), parent), child_frame_id=child,
            transform=T["geometry_msgs/msg/Transform"](
                translation=T["geometry_msgs/msg/Vector3"](x=p[0], y=p[1], z=p[2]),
                rotation=T["geometry_msgs/msg/Quaternion"](x=q[1], y=q[2], z=q[3], w=q[0]),
            ),
        )  # fmt: skip

    def cdr(transforms):
        message = T["tf2_msgs/msg/TFMessage"](transforms=transforms)
        return bytes(STORE.serialize_cdr(message, "tf2_msgs/msg/TFMessage"))

    with Writer(path, version=8, storage_plugin=plugin) as writer:
        tf, static = (writer.add_connection(topic, "tf2_msgs/msg/TFMessage", typestore=STORE)
                      for topic in ("/tf", "/tf_static"))  # fmt: skip
        writer.write(static, 10**9, cdr([stamped(1.0, "base_link", "camera",
                                                 camera[0][0], camera[1][0])]))  # fmt: skip
        for k, t in enumerate(base_times):
            transforms = [stamped(t, "odom", "base_link", base[0][k], base[1][k])]
            if t == int(t):
                i = int(t) - 1
                transforms.insert(0, stamped(t, "map", "odom", odom[0][i], odom[1][i]))
            writer.write(tf, round(t * 1e9) + 1000, cdr(transforms))
    return odom, base, camera, base_times


@pytest.mark.parametrize("storage", ["sqlite3", "mcap"])
def test_a_tf_chain_in_a_bag_is_the_product_of_the_transforms(tmp_path, rng, storage):
    from rosbags.rosbag2 import StoragePlugin as Plugin

    from a2b.poses import matrices_from_quat_trans

    from .test_tftree import _about_z

    plugin = Plugin.SQLITE3 if storage == "sqlite3" else Plugin.MCAP
    (odom_q, odom_p), base, camera, base_times = _tf_bag(tmp_path / "tf", rng, plugin)
    stamps, out = tmp_path / "stamps.txt", tmp_path / "out.csv"
    stamps.write_text("".join(f"{float(t)!r}\n" for t in base_times))
    result = run("resample", tmp_path / "tf", "--input-frame", "map", "--input-child-frame",
                 "camera", "--times", stamps, "-v", "-o", out)  # fmt: skip
    assert result.exit_code == 0, result.output
    assert "TF chain map → odom → base_link → camera" in result.output
    assert "base_link→camera static" in result.output
    assert f"  • storage {storage}: 1 file that metadata.yaml lists" in result.output
    rows = np.array([[float(x) for x in line.split(",")]
                     for line in out.read_text().splitlines()[1:]])  # fmt: skip
    assert rows[:, 0].tolist() == base_times.tolist()
    angle = np.interp(base_times, 1 + np.arange(4.0),
                      np.unwrap(2 * np.arctan2(odom_q[:, 3], odom_q[:, 0])))  # fmt: skip
    height = np.interp(base_times, 1 + np.arange(4.0), odom_p[:, 2])
    want = (
        matrices_from_quat_trans(*_about_z(angle, height))
        @ matrices_from_quat_trans(*base)
        @ matrices_from_quat_trans(*camera)
    )
    got = matrices_from_quat_trans(rows[:, 4:], rows[:, 1:4])
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-12)


def test_a_broken_chain_in_a_bag_names_the_frames(tmp_path, rng):
    from rosbags.rosbag2 import StoragePlugin as Plugin

    _tf_bag(tmp_path / "tf", rng, Plugin.SQLITE3)
    result = run("resample", tmp_path / "tf", "--input-frame", "world", "--input-child-frame",
                 "camera", "--rate", 1, "-o", tmp_path / "o.csv")  # fmt: skip
    assert result.exit_code == 1
    assert result.output.count("\n") == 1
    assert "no transform to the frame 'map', so no chain from 'world' to 'camera'" in (
        result.output
    )
