"""rosbag2 bags: folders and SQLite files, read as raw messages per topic, and written.

A rosbag2 bag is a folder: ``metadata.yaml`` and the storage files it lists. Its root key
``rosbag2_bagfile_information`` holds ``version`` (1 to 9), ``storage_identifier`` (``sqlite3``
or ``mcap``), ``relative_file_paths`` (the files in order, since version 4 by their names in
the folder; before, prefixed with the folder's name), ``topics_with_message_count`` (each
``topic_metadata`` with ``name``, ``type``, ``serialization_format`` and, from version 4,
``offered_qos_profiles``; from version 7 ``type_description_hash``) and the compression.

The storage files are SQLite (:mod:`a2b.io.sqlitebag`: ``.db3``, the default of ROS 2 Humble
and older) or MCAP (read with a2b's checked reader, :class:`a2b.io.mcapreader.McapFile`). A
``.db3`` alone, without its folder, reads as a bag of one file. Every problem is one
:class:`~a2b.errors.InputFileError` that starts with the name of the file at fault; a topic is
refused, not allocated, when it holds more than the caller allows. :func:`bag_poses` decodes
a topic's poses by its type (:func:`a2b.io.ros2.decode_poses`) for
:func:`a2b.io.trajectories.read_trajectory` (the format ``rosbag2``).

Writing (:func:`write_sqlite_bag`) makes what ``ros2 bag record -s sqlite3`` on Iron makes:
``NAME/NAME_0.db3`` of schema version 4 and ``NAME/metadata.yaml`` of version 8 (the QoS
profiles as YAML text, rmw's enum numbers: :func:`a2b.io.ros2.qos_profiles`). The folder is
built under a temporary name beside the target and renamed into place when complete.
"""

from __future__ import annotations

import os
import re
import shutil
import sqlite3
import stat
import tempfile
from collections.abc import Iterable, Iterator, Sequence
from contextlib import closing, contextmanager
from typing import NamedTuple

import numpy as np

from ..errors import InputFileError, ParameterError
from . import sqlitebag
from .atomic import OutputFileError, _terminate_as_exit
from .sqlitebag import few, shown

__all__ = [
    "MAX_TOPIC_BYTES",
    "BagTopic",
    "bag_files",
    "bag_messages",
    "bag_poses",
    "bag_tf_poses",
    "bag_topics",
    "is_bag",
    "write_sqlite_bag",
]

METADATA = "metadata.yaml"
#: The metadata versions read (rosbag2's history: 9 is Jazzy's), and the one written.
LATEST_VERSION, WRITTEN_VERSION = 9, 8
#: A metadata.yaml larger than this is refused unread (a real one is a few kB per topic).
MAX_METADATA_BYTES = 16 << 20
#: The default bound on the bytes of one topic that :func:`bag_messages` returns.
MAX_TOPIC_BYTES = 1 << 30
#: The message type of ``/tf``: ``--input-child-frame`` picks its transforms.
TF_TYPE = "tf2_msgs/msg/TFMessage"


class BagTopic(NamedTuple):
    """A topic of a bag: its name, message type (``geometry_msgs/msg/PoseStamped``),
    serialization format (``cdr``) and number of messages."""

    name: str
    type_name: str
    serialization_format: str
    count: int


# -- the folder and its metadata.yaml ------------------------------------------------------------


def is_bag(path: str | os.PathLike) -> bool:
    """Whether ``path`` is a rosbag2 bag: a folder holding ``metadata.yaml``, or a file that
    starts as SQLite files do."""
    path = os.fspath(path)
    if os.path.isdir(path):
        return os.path.isfile(os.path.join(path, METADATA))
    try:
        with open(path, "rb") as f:
            return f.read(len(sqlitebag.SQLITE_MAGIC)) == sqlitebag.SQLITE_MAGIC
    except OSError:
        return False


def bag_files(path: str | os.PathLike) -> tuple[str, list[str]]:
    """The storage (``sqlite3`` or ``mcap``) and the paths of the storage files of the bag
    ``path`` in the order its metadata lists them; a ``.db3`` file alone is ``("sqlite3",
    [path])``.

    Raises
    ------
    InputFileError
        If ``path`` is no bag, its metadata.yaml cannot be read or lies: a file missing, not a
        regular file, listed twice, or a path that leaves the folder (``..``, an absolute
        path, a symbolic link to elsewhere); a storage other than sqlite3 and mcap; a
        compressed bag.
    """
    return _bag(path)[:2]


def _bag(path) -> tuple[str, list[str], dict | None]:
    """``bag_files`` and the metadata's topics ``{name: (type, format, count)}`` (None for a
    ``.db3`` alone)."""
    path = os.fspath(path)
    if not os.path.isdir(path):
        _regular(path, path)
        return "sqlite3", [path], None
    info = _metadata(path)
    where = os.path.join(path, METADATA)
    storage = info.get("storage_identifier")
    if storage not in ("sqlite3", "mcap"):
        raise InputFileError(
            f"{where}: storage_identifier {shown(repr(storage))}; a2b reads sqlite3 and mcap"
        )
    compression = info.get("compression_mode") or ""
    if str(compression).lower() not in ("", "none"):
        raise InputFileError(
            f"{where}: the bag is compressed (compression_mode {shown(repr(compression))}); "
            "a2b reads uncompressed bags: `ros2 bag convert` writes one"
        )
    files = _files(path, info, where)
    return storage, files, _metadata_topics(info, where)


def _metadata(folder: str) -> dict:
    """The ``rosbag2_bagfile_information`` mapping of the folder's metadata.yaml."""
    import yaml

    where = os.path.join(folder, METADATA)
    if not os.path.isfile(where):
        raise InputFileError(
            f"{folder}: no {METADATA}, so not a rosbag2 bag folder (`ros2 bag reindex` writes one)"
        )
    if os.path.getsize(where) > MAX_METADATA_BYTES:
        raise InputFileError(f"{where}: larger than {MAX_METADATA_BYTES >> 20} MiB")
    try:
        with open(where, "rb") as f:
            document = yaml.load(f.read(MAX_METADATA_BYTES), getattr(yaml, "CSafeLoader", None)
                                 or yaml.SafeLoader)  # fmt: skip
    except (OSError, yaml.YAMLError, UnicodeDecodeError, RecursionError) as e:
        problem = shown(" ".join(str(e).split()), 200)
        raise InputFileError(f"{where}: not readable YAML ({problem})") from None
    info = document.get("rosbag2_bagfile_information") if isinstance(document, dict) else None
    if not isinstance(info, dict):
        raise InputFileError(f"{where}: no mapping rosbag2_bagfile_information")
    version = info.get("version")
    if type(version) is not int or not 1 <= version <= LATEST_VERSION:
        raise InputFileError(
            f"{where}: version {shown(repr(version), 40)}; a2b reads rosbag2 metadata "
            f"versions 1 to {LATEST_VERSION}"
        )
    return info


def _files(folder: str, info: dict, where: str) -> list[str]:
    """The storage files that ``relative_file_paths`` names, checked to be regular files
    inside ``folder``."""
    names = info.get("relative_file_paths")
    if not isinstance(names, list) or not names or not all(isinstance(n, str) for n in names):
        raise InputFileError(f"{where}: relative_file_paths is not a list of file names")
    home = os.path.realpath(folder)
    files, seen, missing = [], set(), []
    for name in names:
        parts = name.replace("\\", "/").split("/")
        if info["version"] < 4 and len(parts) == 2 and parts[0] not in ("", ".", ".."):
            parts = parts[1:]  # before version 4 the paths started with the folder's name
        if (
            os.path.isabs(name)
            or len(parts) != 1
            or parts[0] in ("", ".", "..")
            or not name.isprintable()
        ):
            raise InputFileError(
                f"{where}: the file {shown(repr(name), 200)} is not a name inside the "
                "bag folder; a2b reads only the folder's own files"
            )
        file = os.path.join(folder, parts[0])
        if not os.path.lexists(file):
            missing.append(name)
            continue
        if os.path.dirname(os.path.realpath(file)) != home:
            raise InputFileError(f"{file}: a link to a file outside the bag folder")
        if file in seen:
            raise InputFileError(f"{where}: relative_file_paths lists {shown(name)} twice")
        seen.add(file)
        files.append(file)
    if missing:
        raise InputFileError(
            f"{where}: {len(missing)} of the {len(names)} files it lists are missing: "
            f"{few(missing)}"
        )
    for file in files:
        _regular(file, file)
    return files


def _regular(path: str, where: str) -> None:
    try:
        mode = os.stat(path).st_mode
    except OSError as e:
        raise InputFileError(f"{where}: {e.strerror}") from None
    if not stat.S_ISREG(mode):
        raise InputFileError(f"{where}: not a regular file")


def _metadata_topics(info: dict, where: str) -> dict:
    """``{name: (type, serialization format, message count)}`` of ``topics_with_message_count``."""
    entries = info.get("topics_with_message_count") or []
    topics: dict = {}
    for k, entry in enumerate(entries if isinstance(entries, list) else [None]):
        meta = entry.get("topic_metadata") if isinstance(entry, dict) else None
        fields = [meta.get(key) for key in ("name", "type")] if isinstance(meta, dict) else []
        count = entry.get("message_count", 0) if isinstance(entry, dict) else None
        if (
            len(fields) != 2
            or not all(isinstance(f, str) for f in fields)
            or type(count) is not int
        ):
            raise InputFileError(
                f"{where}: topics_with_message_count entry {k + 1} lacks topic_metadata with "
                "a name and a type, or an integer message_count"
            )
        name, type_name = fields
        form = str(meta.get("serialization_format", "cdr"))
        if name in topics and topics[name][0] != type_name:
            raise InputFileError(
                f"{where}: the topic {shown(name)} has two types, "
                f"{shown(topics[name][0])} and {shown(type_name)}"
            )
        before = topics.get(name, (type_name, form, 0))[2]
        topics[name] = (type_name, form, before + count)
    return topics


# -- topics and messages -------------------------------------------------------------------------


def bag_topics(path: str | os.PathLike) -> list[BagTopic]:
    """The topics of the bag ``path`` (a folder or a ``.db3`` file), in the order the bag
    first lists them, with their message counts; a topic recorded with two QoS settings is
    one topic.

    For SQLite storage the counts are those of the files, checked against metadata.yaml; for
    MCAP storage they are metadata.yaml's.

    Raises
    ------
    InputFileError
        As :func:`bag_files`, and if a SQLite file is no rosbag2 file, a message names a topic
        id that its file lacks, a topic has two types, or metadata.yaml's types or counts are
        not the files'.
    """
    storage, files, listed = _bag(path)
    if storage == "mcap":
        return [BagTopic(name, *entry) for name, entry in listed.items()]
    found: dict[str, BagTopic] = {}
    for file in files:
        with sqlitebag.database(file) as connection:
            topics = sqlitebag.topics_table(connection, file)
            found_here = sqlitebag.survey(connection, file, topics)
        for topic_id, (name, type_name, form) in topics.items():
            count = found_here.get(topic_id, sqlitebag.Survey(0, 0, 0, 0)).count
            if name in found:
                _same_type(found[name].type_name, type_name, name, file)
                count += found[name].count
            found[name] = BagTopic(name, type_name, form, count)
    if listed is not None:
        _as_listed(found, listed, os.path.join(os.fspath(path), METADATA))
    return list(found.values())


def _same_type(first: str, second: str, name: str, where: str) -> None:
    if first != second:
        raise InputFileError(
            f"{where}: the topic {shown(name)} has two types, {shown(first)} and {shown(second)}"
        )


def _as_listed(found: dict[str, BagTopic], listed: dict, where: str) -> None:
    """Check that metadata.yaml names the topics of the files with their types and counts."""
    for name, topic in found.items():
        type_name, _form, count = listed.get(name, (topic.type_name, None, topic.count))
        _same_type(type_name, topic.type_name, name, where)
        if count != topic.count:
            raise InputFileError(
                f"{where}: says {shown(name)} has {count} messages, the files hold "
                f"{topic.count} (`ros2 bag reindex` rewrites metadata.yaml from the files)"
            )
    unknown = [name for name in listed if name not in found]
    if unknown:
        raise InputFileError(f"{where}: lists topics the files lack: {few(unknown)}")


def bag_messages(
    path: str | os.PathLike, topic: str, *, max_bytes: int = MAX_TOPIC_BYTES
) -> tuple[str, np.ndarray, list[bytes]]:
    """``(type_name, log_times_ns, datas)``: the messages of ``topic`` in the bag ``path`` (a
    folder or a ``.db3`` file), file by file in the bag's order and by receive time within a
    file; ``log_times_ns`` are the receive times as ``int64`` nanoseconds, ``datas`` the
    serialized messages (CDR), ready for :func:`a2b.io.ros2.decode_poses`.

    ``max_bytes`` bounds the topic's data plus
    :data:`~a2b.io.sqlitebag.MESSAGE_OVERHEAD` bytes a message; a topic that holds more is
    refused before any of it is read (in an MCAP file: as soon as the bound is passed).

    Raises
    ------
    InputFileError
        As :func:`bag_topics`, and if the bag has no ``topic``, the topic is not serialized
        as CDR, a message's data is not a blob (NULL) or its timestamp no integer, or the
        topic exceeds ``max_bytes``.
    """
    storage, files, listed = _bag(path)
    if storage == "mcap":
        return _mcap_messages(files, topic, listed, max_bytes)
    parts, type_name, budget = [], None, max_bytes
    for file in files:
        with sqlitebag.database(file) as connection:
            topics = sqlitebag.topics_table(connection, file)
            found_here = sqlitebag.survey(connection, file, topics)
            ids = [key for key, entry in topics.items() if entry[0] == topic]
            for key in ids:
                type_name = type_name or topics[key][1]
                _same_type(type_name, topics[key][1], topic, file)
                _check_form(topics[key][2], topic, file)
            mine = [found_here[key] for key in ids if key in found_here]
            count = sum(s.count for s in mine)
            sqlitebag.check_survey(connection, file, topic, ids, mine, budget, max_bytes)
            budget -= sum(s.data_bytes for s in mine) + sqlitebag.MESSAGE_OVERHEAD * count
            if count:
                parts.append(sqlitebag.fetched(connection, ids, count, file))
    if type_name is None:
        everything = [t.name for t in bag_topics(path)]
        raise InputFileError(
            f"{os.fspath(path)}: no topic {shown(topic)}; the bag has {few(everything)}"
        )
    times = np.concatenate([p[0] for p in parts]) if parts else np.empty(0, np.int64)
    if listed is not None and topic in listed:
        mine = BagTopic(topic, type_name, "cdr", len(times))
        _as_listed({topic: mine}, {topic: listed[topic]}, os.path.join(os.fspath(path), METADATA))
    return type_name, times, [data for part in parts for data in part[1]]


def _check_form(form: str, topic: str, where: str) -> None:
    if form != "cdr":
        raise InputFileError(
            f"{where}: the topic {shown(topic)} is serialized as {shown(form)}; a2b reads cdr"
        )


def _mcap_messages(files: list[str], topic: str, listed: dict, max_bytes: int):
    """:func:`bag_messages` for MCAP storage, file by file through a2b's checked MCAP reader
    (:class:`a2b.io.mcapreader.McapFile`: CRCs, bounded inflation); within a file in the
    log-time order of the messages, the channels of the topic joined."""
    from .mcapreader import McapFile

    type_name, times, datas, budget = None, [], [], max_bytes
    for file in files:
        with open(file, "rb") as f:
            mcap = McapFile(f.read(), file)
        mine = [channel for channel in mcap.channels.values() if channel.topic == topic]
        for channel in mine:
            name = channel.schema_name or listed.get(topic, ("?",))[0]
            type_name = type_name or name
            _same_type(type_name, name, topic, file)
            _check_form(channel.message_encoding, topic, file)
        found = mcap.messages([channel.id for channel in mine])
        parts = [found[channel.id] for channel in mine]
        budget -= sum(int(p.length.sum()) + sqlitebag.MESSAGE_OVERHEAD * len(p) for p in parts)
        if budget < 0:
            raise InputFileError(
                f"{file}: the topic {shown(topic)} holds more than the "
                f"{max_bytes / 2**20:.1f} MiB allowed (max_bytes)"
            )
        logged = np.concatenate([np.asarray(p.log_time, np.int64) for p in parts]
                                + [np.empty(0, np.int64)])  # fmt: skip
        here = [data for p in parts for data in p.as_bytes()]
        order = np.argsort(logged, kind="stable")
        times.append(logged[order].astype(np.int64))
        datas.extend(here[k] for k in order.tolist())
    if type_name is None:
        if topic not in listed:
            raise InputFileError(
                f"{os.path.dirname(files[0])}: no topic {shown(topic)}; the bag has "
                f"{few(list(listed))}"
            )
        type_name = listed[topic][0]
    return type_name, np.concatenate(times + [np.empty(0, np.int64)]), datas


def bag_poses(path: str | os.PathLike, name: str, topic: str, child_frame: str | None = None):
    """Times (s), quaternions ``(N, 4)`` wxyz and translations ``(N, 3)`` of the poses of
    ``topic`` in the bag ``path`` (a folder or a ``.db3``), decoded by the topic's own type
    (:func:`a2b.io.ros2.decode_poses`: ``PoseStamped``, ``Odometry``, ``TFMessage``, ``Path``);
    ``name`` starts the messages.

    Raises
    ------
    InputFileError
        As :func:`bag_messages`; if the topic's type carries no poses, ``child_frame`` is given
        for a topic that is no ``TFMessage``, or a pose is not finite.
    """
    from .ros2 import decode_poses

    type_name, _log_times, datas = bag_messages(path, topic)
    where = f"{name}: {shown(topic)}"
    if child_frame is not None and type_name != TF_TYPE:
        raise InputFileError(
            f"{where} carries {shown(type_name)}: --input-child-frame is for {TF_TYPE} topics"
        )
    times, quat, trans, _message = decode_poses(type_name, datas, where, child_frame)
    if not (np.isfinite(quat).all() and np.isfinite(trans).all()):
        raise InputFileError(f"{where}: a pose is not finite")
    return times, quat, trans


def bag_tf_poses(
    path: str | os.PathLike,
    name: str,
    topic: str | None,
    parent: str,
    child: str,
    mode: str = "screw",
    **parameters,
):
    """``(times, quat_wxyz, translations, statement)``: the poses of the frame ``child`` in
    ``parent``, composed through the TF tree of the bag ``path`` as
    :func:`a2b.io.mcapposes.mcap_tf_poses` composes an MCAP file's
    (:func:`a2b.io.tftree.compose_topics`): the transforms of every ``TFMessage`` topic
    (``topic``: that one) and of :data:`~a2b.io.tftree.TF_STATIC`, which are static.

    Raises
    ------
    InputFileError
        As :func:`bag_messages` and :func:`a2b.io.tftree.compose_topics`; if ``topic`` is not
        in the bag, or a topic read is no ``TFMessage`` topic or none is.
    """
    from .ros2 import decode_transforms
    from .tftree import TF_STATIC, compose_topics

    topics = bag_topics(path)
    if topic is not None and topic not in {t.name for t in topics}:
        raise InputFileError(
            f"{name}: no topic {shown(topic)}; the bag has {few([t.name for t in topics])}"
        )
    mine = [
        t for t in topics
        if t.name in (topic, TF_STATIC) or (topic is None and t.type_name == TF_TYPE)
    ]  # fmt: skip
    where = f"{name}: {few(sorted(t.name for t in mine))}" if mine else name
    wrong = sorted({t.type_name for t in mine} - {TF_TYPE})
    if wrong or not mine:
        raise InputFileError(
            f"{where}: --input-frame composes the transforms of {TF_TYPE}, "
            + (f"not {', '.join(map(shown, wrong))}" if wrong else "and the bag has none")
        )
    decoded = []
    for t in mine:
        _type_name, _log_times, datas = bag_messages(path, t.name)
        *frames, times, quat, trans, _ = decode_transforms(datas, f"{name}: {shown(t.name)}")
        decoded.append((t.name, *frames, times, quat, trans))
    return compose_topics(decoded, where, parent, child, mode, **parameters)


# -- writing -------------------------------------------------------------------------------------

_TYPE_NAME = re.compile(r"[A-Za-z][A-Za-z0-9_]*/msg/[A-Za-z][A-Za-z0-9_]*", re.ASCII)


def write_sqlite_bag(
    folder: str | os.PathLike,
    topics: Sequence[tuple[str, str, str]],
    messages: Iterable[tuple[int, int, bytes]],
) -> int:
    """Write the SQLite bag ``folder``: ``NAME/NAME_0.db3`` and ``NAME/metadata.yaml``.

    Parameters
    ----------
    folder : str or path
        The bag to write. It appears only when complete. An existing folder is replaced when
        it is empty or a rosbag2 bag (only ``metadata.yaml`` and ``.db3``/``.mcap`` files);
        anything else there is refused.
    topics : sequence of (name, type_name, qos_text)
        Each topic's name (``/a2b/pose``), message type (``geometry_msgs/msg/PoseStamped``)
        and offered QoS profiles as rosbag2 stores them (:func:`a2b.io.ros2.qos_profiles`).
    messages : iterable of (topic_index, timestamp_ns, data)
        The messages in the order to store them: the index of the topic in ``topics``, the
        receive time in integer nanoseconds, the CDR bytes. Read in blocks.

    Returns
    -------
    int
        The number of messages written.

    Raises
    ------
    ParameterError
        If a topic name is not a ROS 2 name, a type name is not ``package/msg/Name``, a topic
        is given twice, or a message names no topic or has a time outside ``[0, 2**63)``.
    OutputFileError
        If the folder cannot be written, or exists and is no bag.
    """
    from .ros2 import check_topic

    for name, type_name, qos in topics:
        check_topic(name)
        if not _TYPE_NAME.fullmatch(type_name) or not isinstance(qos, str):
            raise ParameterError(
                f"topic {shown(name)}: the type {shown(repr(type_name))} is not "
                "package/msg/Name, or its QoS profiles are not text"
            )
    names = [topic[0] for topic in topics]
    if len(set(names)) != len(names):
        twice = sorted({name for name in names if names.count(name) > 1})
        raise ParameterError(f"a bag holds each topic once; given twice: {few(twice)}")
    with _bag_folder(folder) as (tmp, name):
        with closing(sqlite3.connect(os.path.join(tmp, f"{name}_0.db3"))) as connection:
            sqlitebag.create(connection, topics)
            counts, first, last = sqlitebag.insert(connection, len(topics), messages)
            info = _information(f"{name}_0.db3", topics, counts, first, last)
            connection.execute(
                "INSERT INTO metadata(metadata_version, metadata) VALUES(?, ?)",
                (WRITTEN_VERSION, _yaml(info)),
            )
            connection.execute("CREATE INDEX timestamp_idx ON messages (timestamp ASC)")
            connection.commit()
        with open(os.path.join(tmp, METADATA), "w", encoding="utf-8") as f:
            f.write(_yaml({"rosbag2_bagfile_information": info}))
    return sum(counts)


def _information(file: str, topics, counts, first, last) -> dict:
    """The ``rosbag2_bagfile_information`` of version :data:`WRITTEN_VERSION`."""
    start, duration = (0, 0) if first is None else (first, last - first)
    span = {
        "starting_time": {"nanoseconds_since_epoch": start},
        "duration": {"nanoseconds": duration},
        "message_count": sum(counts),
    }
    return {
        "version": WRITTEN_VERSION,
        "storage_identifier": "sqlite3",
        "duration": span["duration"],
        "starting_time": span["starting_time"],
        "message_count": sum(counts),
        "topics_with_message_count": [
            {
                "topic_metadata": {
                    "name": name,
                    "type": kind,
                    "serialization_format": "cdr",
                    "offered_qos_profiles": qos,
                    "type_description_hash": sqlitebag.TYPE_HASHES.get(kind, ""),
                },
                "message_count": count,
            }
            for (name, kind, qos), count in zip(topics, counts)
        ],
        "compression_format": "",
        "compression_mode": "",
        "relative_file_paths": [file],
        "files": [{"path": file, **span}],
        "custom_data": {},
        "ros_distro": sqlitebag.DISTRO,
    }


def _yaml(document: dict) -> str:
    """``document`` as YAML, each repeated value written out again (no ``&id001`` anchors,
    which ``ros2 bag`` does not write)."""
    import yaml

    class Dumper(yaml.SafeDumper):
        def ignore_aliases(self, data):
            return True

    return yaml.dump(document, Dumper=Dumper, sort_keys=False, default_flow_style=False,
                     width=1 << 16)  # fmt: skip


#: The files of a bag folder that writing a bag over it may remove.
_BAG_FILE = re.compile(r".*\.(db3|mcap)|" + re.escape(METADATA))


@contextmanager
def _bag_folder(folder) -> Iterator[tuple[str, str]]:
    """A temporary folder beside ``folder`` and the bag's name; renamed to ``folder`` when
    the block ends normally (an existing bag is moved aside first, then removed), removed if
    it raises (including ``KeyboardInterrupt`` and SIGTERM)."""
    if not os.fspath(folder) or os.fspath(folder) == "-":
        raise OutputFileError("a rosbag2 bag is a folder: give its path with -o FOLDER")
    target = os.path.realpath(os.fspath(folder))
    name, parent = os.path.basename(target), os.path.dirname(target)
    if os.path.lexists(target):
        _replaceable(target, os.fspath(folder))
    with _terminate_as_exit():
        try:
            tmp = tempfile.mkdtemp(prefix=f".{name}.", suffix=".tmp", dir=parent)
        except OSError as e:
            raise OutputFileError(f"cannot write {folder}: {e.strerror or e}") from e
        try:
            try:
                yield tmp, name
                _publish(tmp, target)
            except OSError as e:
                raise OutputFileError(f"cannot write {folder}: {e.strerror or e}") from e
            except sqlite3.Error as e:  # a full disk, a message over SQLite's 1 GB limit
                raise OutputFileError(f"cannot write {folder}: {shown(e, 200)}") from e
        finally:
            shutil.rmtree(tmp, ignore_errors=True)


def _replaceable(target: str, shown) -> None:
    if not os.path.isdir(target):
        raise OutputFileError(f"cannot write the bag {shown}: it is a file, not a folder")
    entries = sorted(os.listdir(target))
    foreign = [e for e in entries if not _BAG_FILE.fullmatch(e)
               or not os.path.isfile(os.path.join(target, e))]  # fmt: skip
    if foreign or (entries and METADATA not in entries):
        raise OutputFileError(
            f"cannot write the bag {shown}: the folder exists and is no rosbag2 bag (it holds "
            f"{few(foreign or entries)}); give a new folder"
        )


def _publish(tmp: str, target: str) -> None:
    """Rename the finished folder ``tmp`` to ``target``, replacing an existing bag there."""
    umask = os.umask(0)
    os.umask(umask)
    for entry in os.listdir(tmp):
        os.chmod(os.path.join(tmp, entry), 0o666 & ~umask)
    os.chmod(tmp, 0o777 & ~umask)
    if not os.path.lexists(target):
        os.rename(tmp, target)
        return
    old = tempfile.mkdtemp(prefix=f".{os.path.basename(target)}.", suffix=".old",
                           dir=os.path.dirname(target))  # fmt: skip
    os.rename(target, os.path.join(old, "bag"))
    try:
        os.rename(tmp, target)
    except OSError:
        os.rename(os.path.join(old, "bag"), target)  # put the old bag back
        os.rmdir(old)
        raise
    shutil.rmtree(old, ignore_errors=True)
