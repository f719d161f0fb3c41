"""Foxglove's JSON messages as trajectories: FrameTransforms, PosesInFrame, and a
FrameTransform channel of several child frames, in files written by the `mcap` package."""

from __future__ import annotations

import json

import numpy as np
import pytest

from a2b.errors import InputFileError
from a2b.io.trajectories import read_trajectory
from a2b.poses import matrices_from_quat_trans

mcap_writer = pytest.importorskip("mcap.writer")


def _pose(rng):
    q = rng.normal(size=4)
    q /= np.linalg.norm(q)
    return q, rng.normal(size=3)


def _stamp(k):
    return {"sec": k, "nsec": 250_000_000}


def _transform(k, parent, child, quat, trans):
    return {
        "timestamp": _stamp(k),
        "parent_frame_id": parent,
        "child_frame_id": child,
        "translation": dict(zip("xyz", trans.tolist())),
        "rotation": dict(zip("wxyz", quat.tolist())),
    }


def _write(path, schema, topic, messages):
    with open(path, "wb") as f:
        writer = mcap_writer.Writer(f)
        writer.start()
        schema_id = writer.register_schema(schema, "jsonschema", b"{}")
        channel = writer.register_channel(topic, "json", schema_id)
        for k, message in enumerate(messages):
            writer.add_message(channel, k, json.dumps(message).encode(), k)
        writer.finish()
    return path


def _read(path, **options):
    with open(path, "rb") as f:
        return read_trajectory(f, **options)


@pytest.fixture
def two_children(rng):
    """Transforms to base_link and camera in turns, at 0.25, 1.25, … s."""
    return {
        child: [_pose(rng) for _ in range(5)] for child in ("base_link", "camera")
    }  # fmt: skip


def test_frame_transforms_are_read_exactly_by_child_frame(tmp_path, two_children):
    messages = [
        {"transforms": [_transform(k, "odom", child, *poses[k])
                        for child, poses in two_children.items()]}
        for k in range(5)
    ]  # fmt: skip
    path = _write(tmp_path / "t.mcap", "foxglove.FrameTransforms", "/tf", messages)
    for child, poses in two_children.items():
        tr = _read(path, child_frame=child)
        assert tr.times.tolist() == [k + 0.25 for k in range(5)]
        assert tr.quat_wxyz.tolist() == [q.tolist() for q, _ in poses]
        assert tr.trans.tolist() == [p.tolist() for _, p in poses]
    with pytest.raises(InputFileError, match=r"transforms to 2 child frames \(base_link, camera\)"
                                             r"; choose one with --input-child-frame"):  # fmt: skip
        _read(path)
    with pytest.raises(InputFileError, match=r"no transform to the child frame 'lidar'; the "
                                             r"frames are base_link, camera"):  # fmt: skip
        _read(path, child_frame="lidar")


def test_one_frame_transform_channel_of_two_child_frames(tmp_path, two_children):
    """Was: "the time repeats … sort the file"."""
    messages = [
        _transform(k, "odom", child, *poses[k])
        for k in range(5)
        for child, poses in two_children.items()
    ]
    path = _write(tmp_path / "t.mcap", "foxglove.FrameTransform", "/tf", messages)
    tr = _read(path, child_frame="camera")
    assert tr.times.tolist() == [k + 0.25 for k in range(5)]
    assert tr.quat_wxyz.tolist() == [q.tolist() for q, _ in two_children["camera"]]
    assert tr.trans.tolist() == [p.tolist() for _, p in two_children["camera"]]
    with pytest.raises(InputFileError, match=r"transforms to 2 child frames"):
        _read(path)


def test_frame_transforms_compose_through_the_tree(tmp_path, rng):
    """odom→base_link and base_link→camera in one FrameTransform channel, at the same stamps."""
    links = {child: [_pose(rng) for _ in range(3)] for child in ("base_link", "camera")}
    parents = {"base_link": "odom", "camera": "base_link"}
    messages = [
        _transform(k, parents[child], child, *poses[k])
        for k in range(3)
        for child, poses in links.items()
    ]
    path = _write(tmp_path / "t.mcap", "foxglove.FrameTransform", "/tf", messages)
    tr = _read(path, input_frame="odom", child_frame="camera")
    want = [matrices_from_quat_trans(*map(np.array, zip(*poses))) for poses in links.values()]
    np.testing.assert_allclose(tr.matrices, want[0] @ want[1], rtol=0, atol=1e-12)
    assert tr.notes[0].startswith("TF chain odom → base_link → camera")


def test_poses_in_frame_are_the_poses_of_the_last_message(tmp_path, rng):
    poses = [[_pose(rng) for _ in range(n)] for n in (2, 4)]
    messages = [
        {"timestamp": _stamp(k), "frame_id": "map",
         "poses": [{"position": dict(zip("xyz", p.tolist())),
                    "orientation": dict(zip("wxyz", q.tolist()))} for q, p in part]}
        for k, part in enumerate(poses)
    ]  # fmt: skip
    path = _write(tmp_path / "p.mcap", "foxglove.PosesInFrame", "/path", messages)
    tr = _read(path)
    assert tr.times.tolist() == [0.0, 1.0, 2.0, 3.0]
    assert tr.quat_wxyz.tolist() == [q.tolist() for q, _ in poses[1]]
    assert tr.trans.tolist() == [p.tolist() for _, p in poses[1]]


def test_a_poses_in_frame_without_poses_is_one_error(tmp_path):
    message = {"timestamp": _stamp(0), "frame_id": "map", "pose": {}}
    path = _write(tmp_path / "p.mcap", "foxglove.PosesInFrame", "/path", [message])
    with pytest.raises(InputFileError, match=r"/path message 1: not a PosesInFrame message "
                                             r"\(KeyError: 'poses'\)"):  # fmt: skip
        _read(path)
