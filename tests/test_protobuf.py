"""Foxglove's messages as Protobuf (`--profile protobuf`): a2b's output read by the `mcap`
package's Protobuf decoding, imported by rerun as transforms (read back from its .rrd), and
files written by foxglove-sdk read back exactly. Needs the extra a2b-motions[protobuf]."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from a2b.cli import cli
from a2b.io.trajectories import read_trajectory
from tests.conftest import tool_venv

pytest.importorskip("foxglove_schemas_protobuf")


def _read(path, **options):
    with open(path, "rb") as f:
        return read_trajectory(f, **options)


def _poses(rng, n):
    q = rng.normal(size=(n, 4))
    return q / np.linalg.norm(q, axis=1, keepdims=True), rng.normal(size=(n, 3))


def _tum(path, times, quat, trans):
    rows = [f"{t!r} {' '.join(map(repr, [*p, *q[1:], q[0]]))}" for t, q, p in
            zip(times.tolist(), quat.tolist(), trans.tolist())]  # fmt: skip
    path.write_text("\n".join(rows) + "\n")
    return path


def _schema_decoders():
    """Decoders of Protobuf messages by their Schema records: mcap-protobuf-support's (it
    needs mcap ≥ 1.6), else classes built here from the Schema's own FileDescriptorSet, with
    the ``protobuf`` library alone (in a pool of their own: nothing of Foxglove's classes)."""
    try:
        from mcap_protobuf.decoder import DecoderFactory
    except ImportError:
        pass
    else:
        return [DecoderFactory()]
    from google.protobuf import descriptor_pool, message_factory
    from google.protobuf.descriptor_pb2 import FileDescriptorSet
    from mcap.decoder import DecoderFactory as Base

    class FromSchema(Base):
        def decoder_for(self, message_encoding, schema):
            pool = descriptor_pool.DescriptorPool()
            for file in FileDescriptorSet.FromString(schema.data).file:
                pool.Add(file)
            cls = message_factory.GetMessageClass(pool.FindMessageTypeByName(schema.name))
            return cls.FromString

    return [FromSchema()]


def test_protobuf_output_is_read_by_the_mcap_package_and_back_by_a2b(tmp_path, rng):
    from mcap.reader import make_reader

    quat, trans = _poses(rng, 5)
    times = np.arange(5) * 0.25 + 1.0
    tum = _tum(tmp_path / "in.tum", times, quat, trans)
    out = tmp_path / "out.mcap"
    result = CliRunner().invoke(cli, ["resample", str(tum), "--rate", "4", "-o", str(out),
                                      "--profile", "protobuf", "--frame-id", "map",
                                      "--child-frame-id", "robot"])  # fmt: skip
    assert result.exit_code == 0, result.output
    with open(out, "rb") as f:
        reader = make_reader(f, decoder_factories=_schema_decoders())
        seen = {"/a2b/pose": [], "/tf": []}
        for schema, channel, message, proto in reader.iter_decoded_messages():
            assert channel.message_encoding == "protobuf" and schema.encoding == "protobuf"
            seen[channel.topic].append((schema.name, message.log_time, proto))
    poses, tfs = seen["/a2b/pose"], seen["/tf"]
    assert [name for name, _, _ in poses] == ["foxglove.PoseInFrame"] * 5
    assert [name for name, _, _ in tfs] == ["foxglove.FrameTransform"] * 5
    for k, ((_, log_time, pose), (_, _, tf)) in enumerate(zip(poses, tfs)):
        assert log_time == 1_000_000_000 + k * 250_000_000
        assert (pose.timestamp.seconds, pose.timestamp.nanos) == divmod(log_time, 10**9)
        assert pose.frame_id == tf.parent_frame_id == "map" and tf.child_frame_id == "robot"
        o, p = pose.pose.orientation, pose.pose.position
        assert [o.w, o.x, o.y, o.z] == quat[k].tolist() and [p.x, p.y, p.z] == trans[k].tolist()
        assert [tf.rotation.w, tf.translation.z] == [o.w, p.z]
    back = _read(out)
    assert back.times.tolist() == times.tolist()
    assert back.quat_wxyz.tolist() == quat.tolist() and back.trans.tolist() == trans.tolist()
    assert _read(out, child_frame="robot").trans.tolist() == trans.tolist()


def test_files_of_foxglove_sdk_are_read_exactly(tmp_path, rng):
    foxglove = pytest.importorskip("foxglove")
    from foxglove.messages import (
        FrameTransform,
        FrameTransforms,
        Pose,
        PoseInFrame,
        Quaternion,
        Timestamp,
        Vector3,
    )

    quat, trans = _poses(rng, 4)
    path = tmp_path / "sdk.mcap"

    def pose(k):
        p, q = trans[k].tolist(), quat[k].tolist()
        return Vector3(x=p[0], y=p[1], z=p[2]), Quaternion(w=q[0], x=q[1], y=q[2], z=q[3])

    with foxglove.open_mcap(path):
        for k in range(4):
            stamp, (p, q) = Timestamp(sec=k, nsec=5), pose(k)
            foxglove.log("/pose", PoseInFrame(timestamp=stamp, frame_id="map",
                                              pose=Pose(position=p, orientation=q)),
                         log_time=k)  # fmt: skip
            transforms = [
                FrameTransform(timestamp=stamp, parent_frame_id="map", child_frame_id=child,
                               translation=p, rotation=q)
                for child in ("base", "camera")
            ]  # fmt: skip
            foxglove.log("/tfs", FrameTransforms(transforms=transforms), log_time=k)
            foxglove.log("/tf", transforms[1], log_time=k)
    for topic, options in (("/pose", {}), ("/tfs", {"child_frame": "base"}),
                           ("/tf", {"child_frame": "camera"}), ("/tf", {})):  # fmt: skip
        tr = _read(path, topic=topic, **options)
        assert tr.times.tolist() == [k + 5e-9 for k in range(4)], topic
        assert tr.quat_wxyz.tolist() == quat.tolist(), topic
        assert tr.trans.tolist() == trans.tolist(), topic


def test_without_the_extra_protobuf_is_one_line_that_names_it(tmp_path, rng, monkeypatch):
    quat, trans = _poses(rng, 2)
    tum = _tum(tmp_path / "in.tum", np.arange(2.0), quat, trans)
    out = tmp_path / "out.mcap"
    args = ["resample", str(tum), "--rate", "1", "-o", str(out), "--profile", "protobuf"]
    assert CliRunner().invoke(cli, args).exit_code == 0
    monkeypatch.setitem(sys.modules, "foxglove_schemas_protobuf.PoseInFrame_pb2", None)
    for args in (args, ["resample", str(out), "--rate", "1"]):
        result = CliRunner().invoke(cli, args)
        assert result.exit_code == 1
        assert result.output == (
            "Error: Foxglove's Protobuf messages need protobuf and foxglove-schemas-protobuf: "
            "pip install 'a2b-motions[protobuf]'\n"
        )


#: rerun-sdk, in a venv of its own (its pyarrow and numpy pins are its own).
RERUN = "rerun-sdk==0.41.0"
_TRANSFORMS = """
import json, sys
from rerun.chunk import RrdReader
found = {}
for chunk in RrdReader(sys.argv[1]).stream():
    batch = chunk.to_record_batch()
    for name in batch.schema.names:
        if name.startswith("Transform3D:"):
            found.setdefault(chunk.entity_path, {})[name] = batch.column(name).to_pylist()
print(json.dumps(found))
"""


@pytest.fixture(scope="session")
def rerun_bin() -> Path:
    """The ``bin`` directory of a venv with :data:`RERUN` (:func:`conftest.tool_venv`)."""
    return tool_venv("rerun", (RERUN,), "import rerun.chunk")


@pytest.mark.clients
def test_rerun_imports_protobuf_output_as_transforms(tmp_path, rng, rerun_bin):
    """rerun decodes Foxglove's schemas only when Protobuf-encoded: the .rrd it converts holds
    Transform3D rows (float32) of a2b's transforms."""
    quat, trans = _poses(rng, 3)
    tum = _tum(tmp_path / "in.tum", np.arange(3.0), quat, trans)
    out, rrd = tmp_path / "out.mcap", tmp_path / "out.rrd"
    args = ["resample", str(tum), "--rate", "1", "-o", str(out), "--profile", "protobuf",
            "--frame-id", "map", "--child-frame-id", "robot"]  # fmt: skip
    assert CliRunner().invoke(cli, args).exit_code == 0
    subprocess.run([str(rerun_bin / "rerun"), "mcap", "convert", str(out), "-o", str(rrd)],
                   check=True, capture_output=True, timeout=300)  # fmt: skip
    found = subprocess.run([str(rerun_bin / "python"), "-c", _TRANSFORMS, str(rrd)], check=True,
                           capture_output=True, text=True, timeout=300).stdout  # fmt: skip
    tf = json.loads(found)["/tf"]
    assert tf["Transform3D:parent_frame"] == [["map"]] * 3
    assert tf["Transform3D:child_frame"] == [["robot"]] * 3
    xyzw = quat[:, [1, 2, 3, 0]].astype(np.float32)
    assert tf["Transform3D:quaternion"] == [[q] for q in xyzw.tolist()]
    assert tf["Transform3D:translation"] == [[p] for p in trans.astype(np.float32).tolist()]
