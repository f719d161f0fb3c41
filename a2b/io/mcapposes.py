"""Poses from MCAP files: the topic chosen, and each channel's messages decoded by its own schema.

========  ==============================================  ==================================
encoding  schemas                                         decoded by
========  ==============================================  ==================================
cdr       ROS 2 ``geometry_msgs/msg/PoseStamped``,        :func:`a2b.io.ros2.decode_poses`
          ``tf2_msgs/msg/TFMessage``,
          ``nav_msgs/msg/Odometry``, ``nav_msgs/msg/Path``
json      ``foxglove.PoseInFrame``, ``PosesInFrame``,     :func:`json_entries`
          ``FrameTransform``, ``FrameTransforms``, or
          none
protobuf  the same four Foxglove schemas                  :func:`a2b.io.protobuf.protobuf_entries`
========  ==============================================  ==================================

``--input-child-frame`` picks the transforms to one frame of a channel of transforms
(:data:`TRANSFORM_SCHEMAS`), which may carry several; with ``--input-frame`` the pose of that
frame is composed through the TF tree (:func:`mcap_tf_poses`).

The table is :data:`DECODERS`: a new message encoding is one row there. A topic may be carried
by several channels, each with its own schema: the poses of each channel are decoded by that
channel's schema and joined in the log-time order of their messages. A file is read by
:class:`a2b.io.mcapreader.McapFile`, which checks its records, its CRCs and its compressed sizes.
"""

from __future__ import annotations

import json
from typing import IO

import numpy as np

from ..errors import InputFileError, listing
from .documents import stream_name
from .mcapreader import McapFile
from .protobuf import PROTOBUF_SCHEMAS
from .ros2 import POSE_TYPES, child_index, decode_poses, decode_transforms
from .tftree import TF_STATIC, compose_topics

__all__ = [
    "DECODERS",
    "JSON_SCHEMAS",
    "TRANSFORM_SCHEMAS",
    "json_entries",
    "mcap_poses",
    "mcap_tf_poses",
    "read_mcap",
]

#: The Foxglove schemas of JSON messages a2b reads poses from.
JSON_SCHEMAS = (
    "foxglove.PoseInFrame",
    "foxglove.PosesInFrame",
    "foxglove.FrameTransform",
    "foxglove.FrameTransforms",
)
_TF = "tf2_msgs/msg/TFMessage"
_PATH = "nav_msgs/msg/Path"
#: The schemas of transforms between named frames: ``--input-child-frame`` picks among them.
TRANSFORM_SCHEMAS = (_TF, "foxglove.FrameTransform", "foxglove.FrameTransforms")


#: JSON messages parsed by one call of ``json.loads`` (as one array): few, so that few of the
#: objects it makes are alive at once (4096 at a time were slower than one by one).
_JSON_BLOCK = 64


def json_entries(datas: list, where: str, schema: str = ""):
    """The poses of JSON Foxglove messages (``datas``, bytes each) of ``schema`` (one of
    :data:`JSON_SCHEMAS`; ``""``: a PoseInFrame or FrameTransform each):
    ``(numbers (N, 8), parents, children, message (N,))``, ``numbers`` the rows
    ``time x y z qw qx qy qz``, ``time = timestamp.sec + timestamp.nsec · 1e-9`` with both
    whole numbers; ``parents`` and ``children`` the frames of each transform (None for a pose);
    ``message`` the index of the message of each.

    A block of messages is parsed as one JSON array, which is the messages only where each
    message is one value: else (or where that fails) message by message, to name the one
    that is not.
    """
    blocks, parents, children, message = [np.empty((0, 8))], [], [], []
    for lo in range(0, len(datas), _JSON_BLOCK):
        block = datas[lo : lo + _JSON_BLOCK]
        try:
            found = json.loads(b"[" + b",".join(block) + b"]")
        except (ValueError, RecursionError):
            found = []
        if len(found) != len(block):
            found = [_json_value(data, where, lo + i, schema) for i, data in enumerate(block)]
        rows = []
        for i, msg in enumerate(found, lo):
            try:
                for item in _json_items(msg, schema):
                    rows.append(_json_pose(item))
                    parents.append(_frame(item, "parent_frame_id", schema))
                    children.append(_frame(item, "child_frame_id", schema))
                    message.append(i)
            except (ValueError, KeyError, TypeError, OverflowError) as e:
                raise InputFileError(_not_a_pose(where, i, e, schema)) from None
        blocks.append(np.array(rows).reshape(-1, 8))
    return np.concatenate(blocks), parents, children, np.array(message, np.int64)


def _json_items(msg, schema: str) -> list:
    """The messages of one pose each that ``msg`` holds: a FrameTransforms' transforms, a
    PosesInFrame's poses (each with its stamp), else ``msg``."""
    if schema == "foxglove.FrameTransforms":
        items = msg["transforms"]
    elif schema == "foxglove.PosesInFrame":
        items = [{"timestamp": msg["timestamp"], "pose": pose} for pose in msg["poses"]]
    else:
        return [msg]
    if not isinstance(items, list):
        raise TypeError(f"its {'transforms' if 'Frame' in schema else 'poses'} are not a list")
    return items


def _frame(item: dict, key: str, schema: str):
    """The frame ``key`` of a FrameTransform, checked to be text; None for other schemas."""
    if "FrameTransform" not in schema:
        return None
    frame = item[key]
    if not isinstance(frame, str):
        raise TypeError(f"{key} is not a string")
    return frame


def _json_value(data: bytes, where: str, i: int, schema: str):
    try:
        return json.loads(data)
    except (ValueError, RecursionError) as e:
        raise InputFileError(_not_a_pose(where, i, e, schema)) from None


def _not_a_pose(where: str, i: int, e: Exception, schema: str) -> str:
    what = schema.removeprefix("foxglove.") or "PoseInFrame or FrameTransform"
    return f"{where} message {i + 1}: not a {what} message ({type(e).__name__}: {str(e)[:80]})"


def _json_pose(msg: dict) -> tuple:
    """The time and the numbers ``x y z qw qx qy qz`` of one PoseInFrame or FrameTransform."""
    stamp = msg["timestamp"]
    sec, nsec = stamp["sec"], stamp["nsec"]
    whole = type(sec) is int and type(nsec) is int
    if not (whole and 0 <= sec < 2**63 and 0 <= nsec < 2**63):
        raise ValueError(f"the stamp {sec!r:.40}, {nsec!r:.40} is not two whole numbers ≥ 0")
    if "pose" in msg:
        position, orientation = msg["pose"]["position"], msg["pose"]["orientation"]
    else:
        position, orientation = msg["translation"], msg["rotation"]
    p, q = position, orientation
    return (
        sec + nsec * 1e-9,
        *(float(p["x"]), float(p["y"]), float(p["z"])),
        *(float(q["w"]), float(q["x"]), float(q["y"]), float(q["z"])),
    )


def _foxglove_entries(channel, messages, where: str):
    """:func:`json_entries` of a JSON channel's messages, or their Protobuf equivalent."""
    if channel.message_encoding == "protobuf":
        from .protobuf import protobuf_entries

        return protobuf_entries(messages.as_bytes(), where, channel.schema_name)
    return json_entries(messages.as_bytes(), where, channel.schema_name)


def _foxglove_channel(channel, messages, where: str, child_frame):
    """The poses of Foxglove messages (JSON or Protobuf): one per message; a FrameTransform(s)
    channel's transforms to ``child_frame`` (which may be left out when there is one child
    frame); a PosesInFrame channel's poses of its last message, at the times 0, 1, 2, … (they
    share one stamp)."""
    schema = channel.schema_name
    numbers, _parents, children, message = _foxglove_entries(channel, messages, where)
    if schema == "foxglove.PosesInFrame":
        last = message == message[-1] if len(message) else message == 0
        numbers, message = numbers[last], message[last]
        numbers[:, 0] = np.arange(len(numbers))
    elif "FrameTransform" in schema:
        names = sorted(set(children))
        mine = np.array(children, object) == names[child_index(names, child_frame, where)]
        numbers, message = numbers[mine], message[mine]
    return numbers[:, 0], numbers[:, 4:], numbers[:, 1:4], message


def _cdr_channel(channel, messages, where: str, child_frame):
    return decode_poses(channel.schema_name, messages, where, child_frame)


#: For each message encoding: the schemas a2b reads poses from (``""``: none), and the decoder
#: of their messages, ``(Channel, Messages, where, child frame)`` → ``(times, quat_wxyz,
#: translations, the message of each pose)``.
DECODERS = {
    "cdr": (POSE_TYPES, _cdr_channel),
    "json": (JSON_SCHEMAS + ("",), _foxglove_channel),
    "protobuf": (PROTOBUF_SCHEMAS, _foxglove_channel),
}


def _decoder(channel):
    """The decoder of ``channel``'s messages, or None when a2b reads no poses from them."""
    schemas, decoder = DECODERS.get(channel.message_encoding, ((), None))
    return decoder if channel.schema_name in schemas else None


def _kind(channel) -> str:
    """What ``channel`` carries, for messages: its schema's name, else its encoding."""
    return channel.schema_name or f"schemaless {channel.message_encoding}"


def mcap_poses(data: bytes, name: str, topic: str | None, child_frame: str | None = None):
    """Times (s), quaternions ``(N, 4)`` wxyz and translations ``(N, 3)`` of the poses of one
    topic of the MCAP file ``data`` (see the module's table).

    ``topic`` None picks the one topic with poses (``/a2b/pose`` among several; with
    ``child_frame``, the one topic of transforms); ``child_frame`` picks the transforms to that
    frame on a topic of :data:`TRANSFORM_SCHEMAS` and is refused on any other.

    Raises
    ------
    InputFileError
        If the file is damaged, the topic has no poses or is not one, or a pose is not finite.
    """
    mcap = McapFile(data, name)
    channels = list(mcap.channels.values())
    topic = pick_topic(channel_topics(channels), name, topic, child_frame)[0]
    mine = [channel for channel in channels if channel.topic == topic]
    where = f"{name}: {listing([topic], width=80)}"
    kinds = sorted({_kind(channel) for channel in mine})
    if any(_decoder(channel) is None for channel in mine):
        readable = "; ".join(
            f"{encoding.upper()} {', '.join(name for name in names if name)}"
            for encoding, (names, _) in DECODERS.items()
        )
        raise InputFileError(f"{where} carries {listing(kinds)}; a2b reads poses from {readable}")
    if child_frame is not None and not set(kinds) <= set(TRANSFORM_SCHEMAS):
        raise InputFileError(
            f"{where} carries {listing(kinds)}: --input-child-frame is for topics of "
            f"{listing(TRANSFORM_SCHEMAS)}"
        )
    if len(mine) > 1 and {_PATH, "foxglove.PosesInFrame"} & set(kinds):
        raise InputFileError(
            f"{where}: a Path or PosesInFrame topic is read from one channel, not {len(mine)}"
        )
    found = mcap.messages([channel.id for channel in mine])
    parts = []
    for channel in mine:
        here = where if len(mine) == 1 else f"{where} (channel {channel.id})"
        messages = found[channel.id]
        decode = _decoder(channel)
        times, quat, trans, message = decode(channel, messages, here, child_frame)
        parts.append((times, quat, trans, messages.log_time[message]))
    if len(parts) == 1:
        times, quat, trans, _ = parts[0]
    else:
        order = np.argsort(np.concatenate([part[3] for part in parts]), kind="stable")
        times, quat, trans = (np.concatenate([part[i] for part in parts])[order] for i in range(3))
    if not (np.isfinite(quat).all() and np.isfinite(trans).all()):
        raise InputFileError(f"{where}: a pose is not finite")
    return times, quat, trans


def mcap_tf_poses(
    data: bytes,
    name: str,
    topic: str | None,
    parent: str,
    child: str,
    mode: str = "screw",
    **parameters,
):
    """``(times, quat_wxyz, translations, statement)``: the poses of the frame ``child`` in
    ``parent``, composed through the TF tree of the MCAP file ``data``
    (:func:`a2b.io.tftree.compose_topics`, which says the chain in ``statement``).

    The transforms are those of every topic of :data:`TRANSFORM_SCHEMAS` (``topic``: that one and
    :data:`TF_STATIC`); the ones on :data:`TF_STATIC` are static. ``mode`` and ``parameters``
    interpolate each dynamic link between its stamps.
    """
    mcap = McapFile(data, name)
    channels = [
        channel for channel in mcap.channels.values()
        if channel.topic in (topic, TF_STATIC)
        or (topic is None and channel.schema_name in TRANSFORM_SCHEMAS)
    ]  # fmt: skip
    if topic is not None:
        pick_topic(channel_topics(mcap.channels.values()), name, topic, child)
    where = f"{name}: {listing(sorted({channel.topic for channel in channels}), width=80)}"
    wrong = sorted({_kind(channel) for channel in channels} - set(TRANSFORM_SCHEMAS))
    if wrong or not channels:
        raise InputFileError(
            f"{where}: --input-frame composes the transforms of {listing(TRANSFORM_SCHEMAS)}, "
            + (f"not {listing(wrong)}" if wrong else "and the file has none")
        )
    found = mcap.messages([channel.id for channel in channels])
    decoded = []
    for channel in channels:
        here = f"{name}: {listing([channel.topic], width=80)}"
        if channel.schema_name == _TF:
            *frames, times, quat, trans, _ = decode_transforms(found[channel.id], here)
        else:
            numbers, *frames, _ = _foxglove_entries(channel, found[channel.id], here)
            frames = [np.array(names, object) for names in frames]
            times, quat, trans = numbers[:, 0], numbers[:, 4:], numbers[:, 1:4]
        decoded.append((channel.topic, *frames, times, quat, trans))
    return compose_topics(decoded, where, parent, child, mode, **parameters)


def channel_topics(channels) -> list[tuple[str, str, bool]]:
    """``(topic, what it carries, whether a2b reads poses from it)`` of each channel."""
    return [(channel.topic, _kind(channel), _decoder(channel) is not None) for channel in channels]


def pick_topic(
    found: list, name: str, topic: str | None, child_frame: str | None, holder: str = "file"
) -> tuple[str, str]:
    """``(topic, why)``: the topic to read of ``found`` (``(topic, kind, poses)`` of each
    channel of an MCAP file or topic of a bag, the ``holder``): ``topic`` if it is there, else
    the one topic a2b reads poses from (``/a2b/pose`` among several; with ``child_frame``,
    the one topic of transforms). The one rule, for the library and the commands
    (:func:`a2b.io.trajectories.chosen_topic` states ``why`` under ``-v``).

    Raises
    ------
    InputFileError
        If the topic given is not there, or no topic or several qualify.
    """
    topics = sorted({topic for topic, _kind, _poses in found})
    if topic is not None:
        if topic not in topics:
            raise InputFileError(
                f"{name}: no topic {listing([repr(topic)])}; the {holder} has "
                f"{listing(topics) or 'none'}"
            )
        return topic, "given with --topic"
    candidates = sorted({
        topic for topic, kind, poses in found
        if poses and (child_frame is None or kind in TRANSFORM_SCHEMAS)
    })  # fmt: skip
    what = "transform topic" if child_frame is not None else "pose topic"
    if "/a2b/pose" in candidates and child_frame is None and len(candidates) > 1:
        return "/a2b/pose", f"a2b's own, of the {what}s {listing(candidates)}"
    if len(candidates) != 1:
        raise InputFileError(
            f"{name}: {'several' if candidates else 'no'} {what}s "
            f"({listing(candidates or topics) or 'none'}); choose one with --topic"
        )
    return candidates[0], f"the only {what}"


def read_mcap(stream: IO, topic: str = "/a2b/pose") -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Read the poses of an MCAP topic from a binary ``stream``: ``time`` (s), ``quat_wxyz``,
    ``translations`` as the messages hold them (:func:`mcap_poses`)."""
    return mcap_poses(stream.read(), stream_name(stream, None), topic)
