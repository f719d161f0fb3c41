"""Foxglove's messages as Protobuf, through ``protobuf`` and ``foxglove-schemas-protobuf``.

Files from Foxglove's SDK carry ``foxglove.PoseInFrame``, ``PosesInFrame``,
``FrameTransform`` and ``FrameTransforms`` Protobuf-encoded, each Schema a
``google.protobuf.FileDescriptorSet`` (encoding ``protobuf``); rerun imports Foxglove schemas
only in that encoding. Messages are read (:func:`protobuf_entries`) and written
(:class:`ProtobufLayout`, the ``protobuf`` profile of :mod:`a2b.io.mcapwriter`) with the
``protobuf`` library and Foxglove's published classes: the optional extra
``a2b-motions[protobuf]``.
"""

from __future__ import annotations

import importlib

import numpy as np

from ..errors import InputFileError, MissingDependencyError
from .mcapreader import MESSAGE_HEAD

__all__ = ["PROTOBUF_SCHEMAS", "ProtobufLayout", "protobuf_entries"]

#: The Foxglove schemas of Protobuf messages a2b reads poses from.
PROTOBUF_SCHEMAS = (
    "foxglove.PoseInFrame",
    "foxglove.PosesInFrame",
    "foxglove.FrameTransform",
    "foxglove.FrameTransforms",
)
#: Poses per chunk (two messages of about 110 bytes each).
CHUNK_POSES = 4096


def message_class(schema: str):
    """The Protobuf class of the Foxglove ``schema`` (``foxglove.PoseInFrame``)."""
    name = schema.removeprefix("foxglove.")
    try:
        module = importlib.import_module(f"foxglove_schemas_protobuf.{name}_pb2")
    except ImportError:
        raise MissingDependencyError(
            "Foxglove's Protobuf messages need protobuf and foxglove-schemas-protobuf: "
            "pip install 'a2b-motions[protobuf]'"
        ) from None
    return getattr(module, name)


def file_descriptor_set(cls) -> bytes:
    """The ``FileDescriptorSet`` of message class ``cls``: its file and every file it
    imports, each after its imports (an MCAP Schema of encoding ``protobuf``)."""
    from google.protobuf.descriptor_pb2 import FileDescriptorSet

    found, done = FileDescriptorSet(), set()

    def add(file) -> None:
        if file.name in done:
            return
        done.add(file.name)
        for dependency in file.dependencies:
            add(dependency)
        file.CopyToProto(found.file.add())

    add(cls.DESCRIPTOR.file)
    return found.SerializeToString()


def protobuf_entries(datas: list, where: str, schema: str):
    """As :func:`a2b.io.mcapposes.json_entries`, for Protobuf messages of ``schema`` (one of
    :data:`PROTOBUF_SCHEMAS`)."""
    from google.protobuf.message import DecodeError

    cls = message_class(schema)
    rows, parents, children, message = [], [], [], []
    framed = "FrameTransform" in schema
    for i, data in enumerate(datas):
        msg = cls()
        try:
            msg.ParseFromString(data)
            for item in _items(msg, schema):
                rows.append(_row(item, msg))
                parents.append(item.parent_frame_id if framed else None)
                children.append(item.child_frame_id if framed else None)
                message.append(i)
        except (DecodeError, ValueError) as e:
            raise InputFileError(
                f"{where} message {i + 1}: not a {schema.removeprefix('foxglove.')} message "
                f"({type(e).__name__}: {str(e)[:80]})"
            ) from None
    return np.array(rows).reshape(-1, 8), parents, children, np.array(message, np.int64)


def _items(msg, schema: str) -> list:
    """The poses or transforms of one message."""
    if schema == "foxglove.FrameTransforms":
        return list(msg.transforms)
    if schema == "foxglove.PosesInFrame":
        return list(msg.poses)
    return [msg]


def _row(item, msg) -> tuple:
    """``time x y z qw qx qy qz`` of a PoseInFrame, FrameTransform or a Pose of ``msg``."""
    stamp = (item if item.DESCRIPTOR.name != "Pose" else msg).timestamp
    if stamp.seconds < 0 or not 0 <= stamp.nanos < 10**9:
        raise ValueError(f"the stamp {stamp.seconds}, {stamp.nanos} is not a time ≥ 0")
    if item.DESCRIPTOR.name == "FrameTransform":
        p, q = item.translation, item.rotation
    else:
        pose = item if item.DESCRIPTOR.name == "Pose" else item.pose
        p, q = pose.position, pose.orientation
    return (stamp.seconds + stamp.nanos * 1e-9, p.x, p.y, p.z, q.w, q.x, q.y, q.z)


class ProtobufLayout:
    """The messages of a pose as Protobuf: ``foxglove.PoseInFrame`` and, when there is a
    child frame, ``foxglove.FrameTransform`` from ``frame_id`` to it; made by the
    ``protobuf`` library, one message at a time (the interface of
    :class:`a2b.io.mcapwriter.JsonLayout`)."""

    profile = ""
    encoding = "protobuf"
    zstd_level = 1
    chunk_poses = CHUNK_POSES

    def __init__(self, frame_id: str, child_frame_id: str | None):
        self.frame_id, self.child_frame_id = frame_id, child_frame_id
        names = ["foxglove.PoseInFrame"] + ["foxglove.FrameTransform"] * (
            child_frame_id is not None
        )
        self.classes = [message_class(name) for name in names]
        self.schemas = [
            (name, "protobuf", file_descriptor_set(cls)) for name, cls in zip(names, self.classes)
        ]

    def _messages(self, ns: np.ndarray, numbers: np.ndarray) -> list:
        """The data of each message, pose by pose: PoseInFrame, FrameTransform, …"""
        pose_class = self.classes[0]
        tf_class = self.classes[1] if len(self.classes) > 1 else None
        sec, nsec = np.divmod(ns, 1_000_000_000)
        out = []
        for s, n, (x, y, z, qx, qy, qz, qw) in zip(sec.tolist(), nsec.tolist(), numbers.tolist()):
            pose = pose_class(frame_id=self.frame_id)
            pose.timestamp.seconds, pose.timestamp.nanos = s, n
            position, orientation = pose.pose.position, pose.pose.orientation
            position.x, position.y, position.z = x, y, z
            orientation.x, orientation.y, orientation.z, orientation.w = qx, qy, qz, qw
            out.append(pose.SerializeToString())
            if tf_class is not None:
                tf = tf_class(parent_frame_id=self.frame_id, child_frame_id=self.child_frame_id)
                tf.timestamp.CopyFrom(pose.timestamp)
                tf.translation.CopyFrom(position)
                tf.rotation.CopyFrom(orientation)
                out.append(tf.SerializeToString())
        return out

    def records(self, sequence, ns, numbers, channels):
        """The Message records of a chunk: their bytes, and per message its offset in them
        and its log time."""
        datas = self._messages(ns, numbers)
        per = len(self.classes)
        head = np.zeros(len(datas), MESSAGE_HEAD)
        length = np.array([len(data) for data in datas], np.int64)
        head["opcode"] = 0x05  # an MCAP Message record
        head["length"] = length + (MESSAGE_HEAD.itemsize - 9)
        head["channel"] = np.asarray(channels).reshape(-1)
        head["sequence"] = np.repeat(sequence, per)
        head["log_time"] = head["publish_time"] = np.repeat(ns, per)
        heads = head.tobytes()
        size = MESSAGE_HEAD.itemsize
        records = b"".join(heads[k * size : (k + 1) * size] + data for k, data in enumerate(datas))
        record_length = length + size
        offset = np.cumsum(record_length) - record_length
        return np.frombuffer(records, np.uint8), offset, head["log_time"]
