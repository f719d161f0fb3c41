"""ROS 2 messages for MCAP: their definitions, CDR built and read with numpy, and ROS 2 names.

A ROS 2 MCAP file (profile ``ros2``) carries each message type as a Schema of encoding
``ros2msg`` whose data is the type's full definition, its dependencies appended after lines of
80 ``=`` (:func:`schema_text`), and each message as CDR, little endian: a 4-byte encapsulation
header ``00 01 00 00``, then the fields in order, each aligned to its own size counted from the
end of that header (the DDS XCDR1 rules ROS 2 uses). A string is a ``uint32`` length that counts
a final NUL, its bytes and the NUL.

The messages a2b writes have no field of varying length once the frame ids are fixed, so every
message of a topic has one layout (:class:`Cdr`): the byte offset of each number and a template
with the constant bytes. A chunk of messages is then a numpy structured array filled column by
column, and reading is the same offsets gathered for all messages at once
(:func:`decode_poses`).

Stamps are ``builtin_interfaces/Time``: ``int32 sec`` and ``uint32 nanosec`` in
``[0, 10**9)`` (:func:`split_stamps`).
"""

from __future__ import annotations

import re
import struct

import numpy as np

from ..errors import InputFileError, ParameterError, listing, printable, quoted
from .mcapreader import Messages, cut

__all__ = [
    "MAX_TOPIC_LENGTH",
    "POSE_TYPES",
    "Cdr",
    "check_frame_id",
    "check_topic",
    "child_index",
    "decode_poses",
    "decode_transforms",
    "qos_profiles",
    "schema_name",
    "schema_text",
    "split_stamps",
]

#: The fields of each message type, as in its ``.msg`` file (comments and defaults left out).
DEFINITIONS = {
    "builtin_interfaces/Time": "int32 sec\nuint32 nanosec\n",
    "std_msgs/Header": "builtin_interfaces/Time stamp\nstring frame_id\n",
    "geometry_msgs/Point": "float64 x\nfloat64 y\nfloat64 z\n",
    "geometry_msgs/Vector3": "float64 x\nfloat64 y\nfloat64 z\n",
    "geometry_msgs/Quaternion": "float64 x\nfloat64 y\nfloat64 z\nfloat64 w\n",
    "geometry_msgs/Pose": "geometry_msgs/Point position\ngeometry_msgs/Quaternion orientation\n",
    "geometry_msgs/PoseStamped": "std_msgs/Header header\ngeometry_msgs/Pose pose\n",
    "geometry_msgs/Transform": (
        "geometry_msgs/Vector3 translation\ngeometry_msgs/Quaternion rotation\n"
    ),
    "geometry_msgs/TransformStamped": (
        "std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/Transform transform\n"
    ),
    "tf2_msgs/TFMessage": "geometry_msgs/TransformStamped[] transforms\n",
    "nav_msgs/Path": "std_msgs/Header header\ngeometry_msgs/PoseStamped[] poses\n",
    "geometry_msgs/Twist": "geometry_msgs/Vector3 linear\ngeometry_msgs/Vector3 angular\n",
    "geometry_msgs/TwistStamped": "std_msgs/Header header\ngeometry_msgs/Twist twist\n",
}


def schema_name(type_name: str) -> str:
    """``geometry_msgs/PoseStamped`` → ``geometry_msgs/msg/PoseStamped``, the schema name."""
    package, name = type_name.split("/")
    return f"{package}/msg/{name}"


def schema_text(type_name: str) -> bytes:
    """The full definition of ``type_name`` (``package/Name``): its fields, then each type it
    uses, depth first in order of first use, as ``MSG: package/Name`` after 80 ``=``."""
    used: list[str] = []

    def visit(name: str) -> None:
        for line in DEFINITIONS[name].splitlines():
            field_type = line.split()[0].removesuffix("[]")
            if "/" in field_type and field_type not in used:
                used.append(field_type)
                visit(field_type)

    visit(type_name)
    parts = [DEFINITIONS[type_name]]
    parts += [f"{'=' * 80}\nMSG: {name}\n{DEFINITIONS[name]}" for name in used]
    return "".join(parts).encode()


# -- names ROS 2 accepts --------------------------------------------------------------------------

_TOKEN = re.compile(r"[A-Za-z_][A-Za-z0-9_]*", re.ASCII)
_TOPIC_CHARACTERS = re.compile(r"[A-Za-z0-9_/]*", re.ASCII)
#: The longest fully qualified topic name ROS 2 accepts: rmw's ``RMW_TOPIC_MAX_NAME_LENGTH``,
#: 255 (the DDS implementations' limit) less 8 characters kept for prefixes such as ``rt/``.
MAX_TOPIC_LENGTH = 255 - 8


def check_topic(topic: str, what: str = "topic") -> str:
    """``topic`` if ROS 2 accepts it as a fully qualified topic name, else a ParameterError.

    The rules of ``rmw_validate_full_topic_name`` (design.ros2.org, "Topic and Service name
    mapping to DDS"), checked in its order: not empty; starts with ``/``; does not end with
    ``/`` (``/`` alone is no topic either); only ASCII letters, digits, ``_`` and ``/``; no
    ``//``; no ``/``-separated token starts with a digit; at most :data:`MAX_TOPIC_LENGTH`
    characters. The message names the first rule broken.
    """
    tokens = topic.split("/")[1:]
    if not topic:
        problem = "it is empty"
    elif not topic.startswith("/"):
        problem = "it must start with /"
    elif topic.endswith("/"):
        problem = "it must not end with /"
    elif not _TOPIC_CHARACTERS.fullmatch(topic):
        bad = next(ch for ch in topic if not _TOPIC_CHARACTERS.fullmatch(ch))
        problem = f"it holds {quoted(bad)}; only ASCII letters, digits, _ and / are allowed"
    elif "//" in topic:
        problem = "it must not hold //"
    elif not all(map(_TOKEN.fullmatch, tokens)):
        problem = "a part between slashes starts with a digit"
    elif len(topic) > MAX_TOPIC_LENGTH:
        problem = f"it has {len(topic)} characters; ROS 2 allows at most {MAX_TOPIC_LENGTH}"
    else:
        return topic
    raise ParameterError(f"{what} {quoted(topic)} is not a ROS 2 topic name: {problem}")


def check_frame_id(frame_id: str, option: str = "--frame-id") -> str:
    """``frame_id`` if tf2 accepts it, else a ParameterError: not empty, no leading ``/`` (tf2
    drops it with a warning), no whitespace, control or other unprintable characters (a NUL
    would end the CDR string early)."""
    if not frame_id:
        problem = "it is empty"
    elif frame_id.startswith("/"):
        problem = "it must not start with / (tf2 drops it)"
    elif not frame_id.isprintable() or any(ch.isspace() for ch in frame_id):
        problem = "it must not hold whitespace or unprintable characters"
    else:
        return frame_id
    raise ParameterError(f"{option} {quoted(frame_id)} is not a ROS 2 frame id: {problem}")


def qos_profiles(depth: int, durability: int = 2) -> str:
    """The ``offered_qos_profiles`` of a channel, as rosbag2 stores them (YAML, the numbers of
    rmw's enums): keep last ``depth``, reliable, ``durability`` 2 volatile or 1 transient local,
    automatic liveliness, no deadline, lifespan or lease (rmw's infinite duration)."""
    infinite = "\n    sec: 9223372036\n    nsec: 854775807"
    return (
        f"- history: 1\n  depth: {depth}\n  reliability: 1\n  durability: {durability}\n"
        f"  deadline:{infinite}\n  lifespan:{infinite}\n  liveliness: 1\n"
        f"  liveliness_lease_duration:{infinite}\n  avoid_ros_namespace_conventions: false"
    )


#: The latest time a ``builtin_interfaces/Time`` holds: its ``sec`` is an int32.
MAX_SECONDS = 2**31 - 1


def split_stamps(ns: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(sec, nanosec)`` of times in integer nanoseconds, ``0 <= nanosec < 10**9``.

    Raises
    ------
    ParameterError
        If a time is later than ``2**31 − 1`` s (January 2038), which ``int32 sec`` cannot hold.
    """
    sec, nanosec = np.divmod(np.asarray(ns, np.int64), 1_000_000_000)
    if sec.size and sec.max() > MAX_SECONDS:
        raise ParameterError(
            f"ROS 2 stamps hold seconds in an int32: at most 2**31 − 1 = {MAX_SECONDS} s "
            f"(January 2038); a time is {int(sec.max())} s"
        )
    return sec, nanosec


# -- CDR with a fixed layout ----------------------------------------------------------------------


class Cdr:
    """The fixed layout of CDR messages whose strings are known in advance.

    Parts are added in field order: :meth:`number` (a column, filled per message),
    :meth:`uint32` and :meth:`string` (constants). :attr:`template` holds the constant bytes
    and zeros for the columns; :attr:`columns` maps each column's name to its byte offset and
    numpy type. ``lead`` bytes come before the encapsulation header (room for an MCAP record
    head); ``phase`` is the CDR offset of the first part, for a struct inside a message.
    """

    ENCAPSULATION = b"\x00\x01\x00\x00"  # CDR, little endian

    def __init__(self, lead: int = 0, *, phase: int | None = None):
        self.data = bytearray(lead)
        if phase is None:
            self.data += self.ENCAPSULATION
            self.origin, self.phase = len(self.data), 0
        else:
            self.origin, self.phase = lead, phase
        self.columns: dict[str, tuple[int, str]] = {}

    def _align(self, size: int) -> None:
        self.data += bytes(-(self.phase + len(self.data) - self.origin) % size)

    def number(self, name: str, dtype, align: int | None = None) -> Cdr:
        """A column of ``dtype`` (a numpy type, possibly with a shape), aligned to ``align``
        bytes (default: its item's size)."""
        dtype = np.dtype(dtype)
        self._align(align or dtype.base.itemsize)
        self.columns[name] = (len(self.data), dtype)
        self.data += bytes(dtype.itemsize)
        return self

    def uint32(self, value: int) -> Cdr:
        self._align(4)
        self.data += struct.pack("<I", value)
        return self

    def string(self, text: str) -> Cdr:
        raw = text.encode()
        self.uint32(len(raw) + 1)
        self.data += raw + b"\0"
        return self

    def header(self, frame_id: str) -> Cdr:
        """A ``std_msgs/Header``: the column ``stamp`` (``int32 sec`` and ``uint32 nanosec``,
        as one little-endian ``uint64``: :func:`stamp_words`), a constant frame id."""
        return self.number("stamp", "<u8", align=4).string(frame_id)

    @property
    def template(self) -> bytes:
        return bytes(self.data)

    @property
    def end_phase(self) -> int:
        """The CDR offset after the last part: the phase of what follows."""
        return self.phase + len(self.data) - self.origin

    def fields(self, shift: int = 0, prefix: str = "") -> dict:
        """The columns as ``{prefix + name: (dtype, offset + shift)}``, the fields of a numpy
        structured dtype."""
        return {
            prefix + name: (np.dtype(dtype), offset + shift)
            for name, (offset, dtype) in self.columns.items()
        }


#: A pose in ROS messages: 7 doubles, the position (or translation) x y z, then the quaternion
#: x y z w (a ``Pose`` and a ``Transform`` alike).
POSE = ("<f8", (7,))


def stamp_words(ns: np.ndarray) -> np.ndarray:
    """The ``builtin_interfaces/Time`` of times in nanoseconds as little-endian ``uint64``
    words: ``sec`` in the low half, ``nanosec`` in the high (:func:`split_stamps`)."""
    sec, nanosec = split_stamps(ns)
    return sec.astype(np.uint64) | (nanosec.astype(np.uint64) << np.uint64(32))


def pose_stamped(frame_id: str, lead: int = 0, phase: int | None = None) -> Cdr:
    """``geometry_msgs/PoseStamped``: columns ``stamp`` and ``pose`` (:data:`POSE`)."""
    return Cdr(lead, phase=phase).header(frame_id).number("pose", POSE)


TWIST = ("<f8", (6,))


def twist_stamped(frame_id: str, lead: int = 0) -> Cdr:
    """``geometry_msgs/TwistStamped``: columns ``stamp`` and ``twist`` (:data:`TWIST`)."""
    return Cdr(lead).header(frame_id).number("twist", TWIST)


def tf_message(frame_id: str, child_frame_id: str, lead: int = 0) -> Cdr:
    """``tf2_msgs/TFMessage`` with one transform ``frame_id`` → ``child_frame_id``."""
    cdr = Cdr(lead).uint32(1).header(frame_id).string(child_frame_id)
    return cdr.number("pose", POSE)


def path_message(frame_id: str, lead: int, count: int) -> tuple[Cdr, Cdr]:
    """``nav_msgs/Path`` of ``count`` poses: the layouts of its header (through the sequence
    length) and of its first PoseStamped. Every later one starts 8-aligned (after doubles):
    ``pose_stamped(frame_id, phase=0)``."""
    head = Cdr(lead).header(frame_id).uint32(count)
    return head, pose_stamped(frame_id, phase=head.end_phase)


# -- reading CDR ----------------------------------------------------------------------------------

#: The fewest bytes of a ``PoseStamped`` in a Path (stamp, a frame id of 1 byte and its NUL, the
#: pose) and of a ``TransformStamped`` (the same and a child frame id): a count of entries that
#: the bytes left cannot hold is refused before anything is allocated for it.
_POSE_STAMPED_BYTES = 4 + 4 + 4 + 1 + 56
_TRANSFORM_BYTES = _POSE_STAMPED_BYTES + 4 + 1


class _Messages:
    """The CDR messages of one topic, side by side in one buffer, read at arrays of offsets."""

    def __init__(self, datas, where: str):
        if not isinstance(datas, Messages):
            datas = Messages.of(datas)
        self.buffer, self.start = datas.buffer, datas.start
        lengths = datas.length
        self.end = self.start + lengths
        self.origin = self.start + 4
        self.where = where
        short = lengths < 4
        bad = short.copy()
        if not short.all():
            rows = np.flatnonzero(~short)
            head = self._bytes(rows, np.full(len(rows), -4), 2)  # before the CDR origin
            bad[rows] = (head[:, 0] != 0) | (head[:, 1] != 1)
        if bad.any():
            k = int(np.argmax(bad))
            first = self.buffer[self.start[k] : min(self.start[k] + 4, self.end[k])]
            raise InputFileError(
                f"{where} message {k + 1}: not little-endian plain CDR (encapsulation "
                f"{first.tobytes().hex(' ') or 'missing'}; a2b reads 00 01)"
            )

    def read(self, rows: np.ndarray, at: np.ndarray, dtype: str, count: int = 1) -> np.ndarray:
        """``count`` values of ``dtype`` at CDR offset ``at`` (aligned here) of messages ``rows``;
        returns the values and the offset after them."""
        size = np.dtype(dtype).itemsize
        at = at + (-at % size)
        stop = self.origin[rows] + at + size * count
        if (stop > self.end[rows]).any():
            k = int(rows[np.argmax(stop > self.end[rows])])
            raise InputFileError(f"{self.where} message {k + 1}: the message ends too soon")
        values = self._bytes(rows, at, size * count).view(dtype).reshape(len(rows), count)
        return (values[:, 0] if count == 1 else values), at + size * count

    def _bytes(self, rows: np.ndarray, at: np.ndarray, size: int) -> np.ndarray:
        """``size`` bytes at CDR offset ``at`` of messages ``rows``, one row each
        (:func:`a2b.io.mcapreader.cut`: one strided view where they are evenly spaced)."""
        return cut(self.buffer, self.origin[rows] + at, size)

    def room(self, rows: np.ndarray, at: np.ndarray) -> np.ndarray:
        """The bytes of messages ``rows`` after CDR offset ``at``."""
        return self.end[rows] - self.origin[rows] - at

    def string(self, rows: np.ndarray, at: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The lengths (with the NUL) of the strings at ``at``, each checked to lie within its
        message, and the offset after them; the text is not copied (:meth:`names`)."""
        length, at = self.read(rows, at, "<u4")
        length = length.astype(np.int64)
        bad = (length < 1) | (length > self.room(rows, at))
        if bad.any():
            k = int(rows[np.argmax(bad)])
            raise InputFileError(f"{self.where} message {k + 1}: a string overruns the message")
        return length, at + length

    def names(self, rows: np.ndarray, at: np.ndarray, length: np.ndarray):
        """``(codes, names)``: the strings of ``length`` bytes (with the NUL) at ``at`` as one
        integer each, the index of its text in ``names`` (bytes, in order of the texts). Strings
        of one length are compared as fixed-width rows, one length at a time: never more bytes
        than the strings hold."""
        codes, names = np.empty(len(rows), np.int64), []
        for size in np.unique(length).tolist():
            mine = np.flatnonzero(length == size)
            if size == 1:
                codes[mine], names = len(names), names + [b""]
                continue
            chars = self._bytes(rows[mine], at[mine], size - 1)
            if (chars == chars[0]).all():  # the usual case: one frame
                codes[mine], names = len(names), names + [chars[0].tobytes()]
                continue
            texts = chars.view(f"S{size - 1}")[:, 0]
            _, first, inverse = np.unique(texts, return_index=True, return_inverse=True)
            codes[mine] = len(names) + inverse.reshape(-1)
            names += [chars[i].tobytes() for i in first.tolist()]
        return codes, names

    def header(self, rows: np.ndarray, at: np.ndarray):
        """``(sec, nanosec, offset after)`` of a ``std_msgs/Header`` at ``at``."""
        sec, at = self.read(rows, at, "<i4")
        nanosec, at = self.read(rows, at, "<u4")
        _frame, at = self.string(rows, at)
        return sec, nanosec, at

    def count(self, rows: np.ndarray, at: np.ndarray, least: int, what: str):
        """A sequence's length at ``at``, refused where the bytes left cannot hold that many
        elements of at least ``least`` bytes; and the offset after it."""
        count, at = self.read(rows, at, "<u4")
        room = self.room(rows, at)
        over = count.astype(np.int64) * least > room
        if over.any():
            k = int(np.argmax(over))
            raise InputFileError(
                f"{self.where} message {int(rows[k]) + 1}: {int(count[k])} {what} declared in "
                f"the {int(room[k])} bytes left (each takes at least {least})"
            )
        return count.astype(np.int64), at


def _pose_stamped(messages: _Messages, rows, where, child_frame):
    sec, nanosec, at = messages.header(rows, np.zeros(len(rows), np.int64))
    numbers, _ = messages.read(rows, at, "<f8", 7)
    return sec, nanosec, numbers, rows


def _odometry(messages: _Messages, rows, where, child_frame):
    """The header, ``child_frame_id``, then the pose (its covariance and the twist follow)."""
    sec, nanosec, at = messages.header(rows, np.zeros(len(rows), np.int64))
    _child, at = messages.string(rows, at)
    numbers, _ = messages.read(rows, at, "<f8", 7)
    return sec, nanosec, numbers, rows


#: A TFMessage of more transforms than this has them placed one message at a time
#: (:func:`_entry_starts`); fewer are read transform by transform across all messages.
_FEW_TRANSFORMS = 8


def _transforms(messages: _Messages, rows, where: str, child_frame: str | None):
    """The stamps and numbers of the transforms to ``child_frame`` in TFMessages, in order."""
    sec, nanosec, numbers, message, _parents, (codes, names) = _tf_entries(messages, rows, where)
    mine = codes == child_index([name.decode(errors="replace") for name in names], child_frame,
                                where)  # fmt: skip
    if not mine.all():
        sec, nanosec, numbers, message = (a[mine] for a in (sec, nanosec, numbers, message))
    return sec, nanosec, numbers, message


def _tf_entries(messages: _Messages, rows, where: str):
    """Every transform of the TFMessages ``rows``, message by message and in order within:
    ``(sec, nanosec, numbers (N, 7), message, (parent codes, names), (child codes, names))``,
    the frame names as in :meth:`_Messages.names`."""
    count, at = messages.count(rows, np.zeros(len(rows), np.int64), _TRANSFORM_BYTES,
                               "transforms")  # fmt: skip
    found = []  # per transform: (message, place in it, its CDR offset)
    few = count <= _FEW_TRANSFORMS
    for k in range(int(count[few].max(initial=0))):  # the k-th transform of each message
        here = few & (count > k)
        found.append((rows[here], np.full(int(here.sum()), k), at[here]))
        at[here] = _entry_ends(messages, rows[here], at[here], 2)
    for row in rows[~few].tolist():
        starts = _entry_starts(messages, row, int(at[row]), int(count[row]), 2, where)
        found.append((np.full(len(starts), row), np.arange(len(starts)), starts))
    if not found:
        none = (np.empty(0, np.int64), [])
        return np.empty(0, np.int32), np.empty(0, np.uint32), np.empty((0, 7)), rows[:0], none, none
    message, place, start = (np.concatenate([part[i] for part in found]) for i in range(3))
    order = np.lexsort((place, message))  # message by message, in order within
    if (np.diff(order) != 1).any():
        message, start = message[order], start[order]
    sec, at = messages.read(message, start, "<i4")
    nanosec, at = messages.read(message, at, "<u4")
    parent_length, after = messages.string(message, at)
    child_length, child_end = messages.string(message, after)
    numbers, _ = messages.read(message, child_end, "<f8", 7)
    parents = messages.names(message, at + 4, parent_length)
    children = messages.names(message, after + 4 + (-after % 4), child_length)
    return sec, nanosec, numbers, message, parents, children


def decode_transforms(datas, where: str):
    """Every transform of the CDR ``tf2_msgs/msg/TFMessage`` messages ``datas`` (a list of
    bytes, or :class:`a2b.io.mcapreader.Messages`), in order: ``(parents, children, times in
    s, quat_wxyz (N, 4), translations (N, 3), message (N,))``; ``parents`` and ``children``
    are arrays of the frame names (str), ``message`` the index of the message of each.
    Checked as :func:`decode_poses` checks."""
    messages = _Messages(datas, where)
    sec, nanosec, numbers, message, parents, children = _tf_entries(
        messages, np.arange(len(datas)), where
    )
    frames = [
        np.array([name.decode(errors="replace") for name in names] + [""], object)[codes]
        for codes, names in (parents, children)
    ]
    numbers = numbers.reshape(-1, 7)
    times = sec.astype(float) + nanosec.astype(float) * 1e-9
    return (*frames, times, numbers[:, [6, 3, 4, 5]], numbers[:, :3].copy(), message)


def child_index(names: list, child_frame: str | None, where: str) -> int:
    """The index in ``names`` (the child frames, str) of ``child_frame``, or of the one child
    frame there is; else a one-line error that lists them."""
    children = sorted(names)
    if child_frame is None:
        if len(children) != 1:
            raise InputFileError(
                f"{where}: transforms to {len(children)} child frames "
                f"({listing(map(printable, children))}); choose one with --input-child-frame"
            )
        child_frame = children[0]
    if child_frame not in names:
        raise InputFileError(
            f"{where}: no transform to the child frame {quoted(child_frame)}; the frames "
            f"are {listing(map(printable, children)) or 'none'}"
        )
    return names.index(child_frame)


def _entry_ends(messages: _Messages, rows, at, strings: int):
    """The CDR offsets after the stamped entries at ``at`` of messages ``rows``: a Time,
    ``strings`` strings (a frame id; a TransformStamped's child frame id too), 7 doubles."""
    _stamp, at = messages.read(rows, at, "<u4", 2)
    for _ in range(strings):
        _length, at = messages.string(rows, at)
    _numbers, at = messages.read(rows, at, "<f8", 7)
    return at


def _entry_starts(messages: _Messages, row: int, offset: int, count: int, strings: int, where):
    """The CDR offsets of ``count`` stamped entries of message ``row`` from ``offset`` on (the
    PoseStamped of a Path: ``strings`` 1; the TransformStamped of a TFMessage: 2).

    Every entry after the first starts 8-aligned (after doubles), so where each has strings
    as long as the second's, they are evenly spaced: found at once and checked; else one by
    one (each entry's place depends on the lengths before it).
    """
    origin, end = int(messages.origin[row]), int(messages.end[row])
    view = memoryview(messages.buffer)

    def after(at: int) -> tuple[int, list, list]:  # the end, places and bytes of the lengths
        at += -at % 4 + 8
        places, lengths = [], []
        for _ in range(strings):
            at += -at % 4
            if origin + at + 4 > end:
                raise InputFileError(f"{where} message {row + 1}: the message ends too soon")
            places.append(at)
            lengths.append(messages.buffer[origin + at : origin + at + 4])
            at += 4 + struct.unpack_from("<I", view, origin + at)[0]
        return at + (-at % 8) + 56, places, lengths

    if count > 2:
        second, _, _ = after(offset)
        third, places, lengths = after(second)
        starts = np.concatenate([[offset], second + (third - second) * np.arange(count - 1)])
        last = origin + int(starts[-1]) + max(places) - second + 4
        if last <= end and all(
            (cut(messages.buffer, origin + starts[1:] + (place - second), 4) == length).all()
            for place, length in zip(places, lengths)
        ):
            return starts
    starts = np.empty(count, np.int64)
    for i in range(count):
        starts[i], offset = offset, after(offset)[0]
    return starts


def _path(messages: _Messages, rows, where: str, child_frame):
    """The stamps and numbers of the poses of the last ``nav_msgs/Path`` message."""
    if not len(rows):
        return np.empty(0, np.int32), np.empty(0, np.uint32), np.empty((0, 7)), rows
    last = rows[-1:]
    _sec, _nanosec, at = messages.header(last, np.zeros(1, np.int64))
    count, at = messages.count(last, at, _POSE_STAMPED_BYTES, "poses")
    starts = _entry_starts(messages, int(last[0]), int(at[0]), int(count[0]), 1, where)
    here = np.full(len(starts), last[0])
    sec, nanosec, at = messages.header(here, starts)
    numbers, _ = messages.read(here, at, "<f8", 7)
    return sec, nanosec, numbers, here


#: The readers of each message type a2b reads poses from, by schema name: each returns
#: ``(sec, nanosec, numbers (N, 7), the message of each pose)``.
_DECODERS = {
    "geometry_msgs/msg/PoseStamped": _pose_stamped,
    "tf2_msgs/msg/TFMessage": _transforms,
    "nav_msgs/msg/Odometry": _odometry,
    "nav_msgs/msg/Path": _path,
}

#: The message types a2b reads poses from, by their schema names.
POSE_TYPES = tuple(_DECODERS)


def decode_poses(type_name: str, datas, where: str, child_frame: str | None = None):
    """``(times in s, quat_wxyz (N, 4), translations (N, 3), message (N,))`` of the CDR
    messages ``datas`` (a list of bytes, or :class:`a2b.io.mcapreader.Messages`); ``message``
    is the index of the message that holds each pose.

    ``type_name`` is one of :data:`POSE_TYPES`; the time of a pose is its header's stamp,
    ``sec + nanosec · 1e-9``. ``geometry_msgs/PoseStamped`` and ``nav_msgs/Odometry`` give one
    pose per message; ``nav_msgs/Path`` the poses of its last message (the latest plan);
    ``tf2_msgs/TFMessage`` every transform to ``child_frame``, which may be left out when there
    is one child frame (and is used by no other type). ``where`` starts every error message.
    Every count and length in a message is checked against the bytes it has before anything
    is allocated for it.
    """
    decoder = _DECODERS.get(type_name)
    if decoder is None:
        raise InputFileError(
            f"{where}: a2b reads {', '.join(POSE_TYPES)}, not {listing([type_name])}"
        )
    messages = _Messages(datas, where)
    sec, nanosec, numbers, message = decoder(messages, np.arange(len(datas)), where, child_frame)
    numbers = numbers.reshape(-1, 7)
    times = sec.astype(float) + nanosec.astype(float) * 1e-9
    return times, numbers[:, [6, 3, 4, 5]], numbers[:, :3].copy(), message
