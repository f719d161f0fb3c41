"""One SQLite file of a rosbag2 bag (``.db3``): its tables read and checked, and written.

The file holds the tables ``topics`` (``id``, ``name``, ``type``, ``serialization_format``,
``offered_qos_profiles``) and ``messages`` (``id``, ``topic_id``, ``timestamp``: the receive
time in integer nanoseconds, ``data``: the serialized message). Schema version 3 (ROS 2
Humble) adds the tables ``schema`` (``schema_version``, ``ros_distro``) and ``metadata``
(``id``, ``metadata_version``, ``metadata``: the bag's metadata as YAML); version 4 (Iron,
Jazzy) the column ``topics.type_description_hash`` and the table ``message_definitions``
(``id``, ``topic_type``, ``encoding``, ``encoded_message_definition``,
``type_description_hash``). Reading needs only the columns of version 1 and reads all four.

Reading opens the file read-only and immutable (``file:…?mode=ro&immutable=1``): it is never
changed and no ``-wal`` or ``-shm`` file is made. One scan of ``messages`` (:func:`survey`)
counts every topic's messages and bytes, without loading any data, before
:func:`fetched` reads them; :func:`check_survey` refuses a topic larger than the caller allows
first. Every :class:`sqlite3.Error` of a damaged file is an :class:`~a2b.errors.InputFileError`
that names the file. The folder around the file is :mod:`a2b.io.rosbag2`'s.
"""

from __future__ import annotations

import operator
import os
import sqlite3
import urllib.parse
from collections.abc import Iterator, Sequence
from contextlib import closing, contextmanager
from itertools import islice
from typing import NamedTuple

import numpy as np

from ..errors import InputFileError, ParameterError, listing, printable

__all__ = [
    "BLOCK",
    "MESSAGE_OVERHEAD",
    "SCHEMA_VERSION",
    "TYPE_HASHES",
    "Survey",
    "check_survey",
    "create",
    "database",
    "fetched",
    "few",
    "shown",
    "insert",
    "survey",
    "topics_table",
]

SQLITE_MAGIC = b"SQLite format 3\x00"
#: The SQLite schema written: Iron's and Jazzy's (``schema``, ``metadata``, ``topics`` with
#: ``type_description_hash``, ``message_definitions``, ``messages``).
SCHEMA_VERSION = 4
#: The bytes each message costs beyond its data (a Python ``bytes``, a list slot, a time),
#: counted against the bound.
MESSAGE_OVERHEAD = 64
#: Messages inserted per ``executemany`` and fetched per page.
BLOCK = 4096
#: RIHS01 type hashes (REP 2011) of the types a2b writes, as rosbag2 records them in
#: ``type_description_hash``. The same in Humble's, Iron's and Jazzy's definitions.
TYPE_HASHES = {
    "geometry_msgs/msg/PoseStamped": (
        "RIHS01_10f3786d7d40fd2b54367835614bff85d4ad3b5dab62bf8bca0cc232d73b4cd8"
    ),
    "tf2_msgs/msg/TFMessage": (
        "RIHS01_e369d0f05a23ae52508854b66f6aa0437f3449d652e8cbf22d5abe85d020f087"
    ),
    "nav_msgs/msg/Path": "RIHS01_1957a5bb3cee5da65c4e52e52b65a93df227efce4c20f8458b36e73066ca334b",
    "geometry_msgs/msg/TwistStamped": (
        "RIHS01_5f0fcd4f81d5d06ad9b4c4c63e3ea51b82d6ae4d0558f1d475229b1121db6f64"
    ),
}


def shown(text, limit: int = 80) -> str:
    """``text`` for a one-line message: escaped (:func:`a2b.errors.printable`) and cut to
    ``limit`` characters, the cut marked with ``…``."""
    text = printable(str(text)[: limit + 1])
    return text if len(text) <= limit else text[:limit] + "…"


def few(items: Sequence, count: int = 4) -> str:
    """``a, b, c, d and 5 more``: a bounded list of user text for a one-line message
    (:func:`a2b.errors.listing`; ``none`` for no items)."""
    return listing(items, count, 81, empty="none")


# -- reading --------------------------------------------------------------------------------


@contextmanager
def database(path: str) -> Iterator[sqlite3.Connection]:
    """``path`` opened read-only and immutable, checked to hold rosbag2's tables; every
    :class:`sqlite3.Error` inside the block becomes an InputFileError naming the file."""
    with open(path, "rb") as f:
        head = f.read(len(SQLITE_MAGIC))
    if head != SQLITE_MAGIC:
        raise InputFileError(f"{path}: not a SQLite file (a rosbag2 .db3 starts 'SQLite format 3')")
    wal = path + "-wal"
    if os.path.exists(wal) and os.path.getsize(wal) > 0:
        raise InputFileError(
            f"{path}: its write-ahead log {os.path.basename(wal)} is not empty: the bag is being "
            "recorded, or its recorder stopped before closing it"
        )
    uri = "file:" + urllib.parse.quote(os.path.abspath(path)) + "?mode=ro&immutable=1"
    try:
        with closing(sqlite3.connect(uri, uri=True)) as connection:
            connection.execute("PRAGMA query_only = 1")
            _check_tables(connection, path)
            yield connection
    except sqlite3.Error as e:
        problem = shown(e, 200)
        raise InputFileError(f"{path}: not a readable rosbag2 SQLite file ({problem})") from None


#: The columns a2b reads from each table of a rosbag2 SQLite file.
_COLUMNS = {
    "topics": ("id", "name", "type", "serialization_format"),
    "messages": ("id", "topic_id", "timestamp", "data"),
}


def _check_tables(connection: sqlite3.Connection, path: str) -> None:
    """Check that ``topics`` and ``messages`` are plain tables with the columns a2b reads. A
    view, a virtual table or a computed column could yield rows without end or blobs that the
    file does not hold."""
    for table, needed in _COLUMNS.items():
        kind = connection.execute(
            "SELECT type, sql FROM sqlite_master WHERE name = ? COLLATE NOCASE", (table,)
        ).fetchone()
        columns = {row[1]: row[6] for row in connection.execute(f"PRAGMA table_xinfo({table})")}
        lacking = [column for column in needed if column not in columns]
        if kind is None or lacking:
            what = f"the table {table} lacks {few(lacking)}" if kind else f"no table {table}"
            raise InputFileError(f"{path}: a SQLite file but not a rosbag2 bag: {what}")
        computed = [name for name, hidden in columns.items() if hidden]
        if kind[0] != "table" or " ".join(str(kind[1]).split()[:2]).upper() != "CREATE TABLE":
            raise InputFileError(f"{path}: {table} is a {kind[0]} of SQL, not a plain table")
        if computed:
            raise InputFileError(f"{path}: {table} has computed columns: {few(computed)}")


def topics_table(connection: sqlite3.Connection, path: str) -> dict[int, tuple[str, str, str]]:
    """``{id: (name, type, serialization format)}`` of the ``topics`` table."""
    topics = {}
    query = "SELECT id, name, type, serialization_format FROM topics ORDER BY id"
    for topic_id, name, type_name, form in connection.execute(query):
        if not all(isinstance(v, str) for v in (name, type_name, form)):
            raise InputFileError(f"{path}: the topic of id {topic_id!r} lacks a name or a type")
        topics[topic_id] = (name, type_name, form)
    return topics


class Survey(NamedTuple):
    """What one scan of the ``messages`` table finds for one topic id."""

    count: int
    data_bytes: int
    not_blob: int
    not_integer: int


def survey(connection: sqlite3.Connection, path: str, topics: dict) -> dict[int, Survey]:
    """Per topic id: its messages, their bytes, and how many have data that is no blob (NULL,
    text) or a timestamp that is no integer. One pass over the table, no data is loaded
    (SQLite's ``length`` of a blob reads only the record's header)."""
    query = (
        "SELECT topic_id, count(*), total(length(data)), sum(typeof(data) != 'blob'), "
        "sum(typeof(timestamp) != 'integer') FROM messages GROUP BY topic_id"
    )
    found = {
        row[0]: Survey(row[1], int(row[2]), row[3], row[4]) for row in connection.execute(query)
    }
    orphans = [topic_id for topic_id in found if topic_id not in topics]
    if orphans:
        count = sum(found[topic_id].count for topic_id in orphans)
        raise InputFileError(
            f"{path}: {count} message{'s' * (count != 1)} name topic ids that the topics table "
            f"lacks: {few(sorted(map(repr, orphans)))}"
        )
    return found


def _rows(connection: sqlite3.Connection, ids: list) -> Iterator[tuple]:
    """``(timestamp, data)`` of the messages of topic ids ``ids`` in the order of their
    timestamps, fetched :data:`BLOCK` at a time."""
    marks = ",".join("?" * len(ids))
    cursor = connection.execute(
        f"SELECT timestamp, data FROM messages WHERE topic_id IN ({marks}) ORDER BY timestamp, id",
        ids,
    )
    while rows := cursor.fetchmany(BLOCK):
        yield from rows


def check_survey(connection, file, topic, ids, mine, budget, max_bytes) -> None:
    """Refuse the messages of ``topic`` (its ids ``ids`` in ``file``, their surveys ``mine``)
    when a data is no blob or a timestamp no integer, or when they need more than the
    ``budget`` bytes left of ``max_bytes``."""
    for column, bad in (("data", "not_blob"), ("timestamp", "not_integer")):
        if any(getattr(s, bad) for s in mine):
            marks = ",".join("?" * len(ids))
            kind = "blob" if column == "data" else "integer"
            row_id, found = connection.execute(
                f"SELECT id, typeof({column}) FROM messages WHERE topic_id IN ({marks}) AND "
                f"typeof({column}) != '{kind}' ORDER BY id LIMIT 1",
                ids,
            ).fetchone()
            raise InputFileError(
                f"{file}: message id {row_id} of {shown(topic)}: its {column} is {found}, "
                f"not {'a blob' if kind == 'blob' else 'an integer'}"
            )
    need = sum(s.data_bytes + MESSAGE_OVERHEAD * s.count for s in mine)
    if need > budget:
        count = sum(s.count for s in mine)
        raise InputFileError(
            f"{file}: the topic {shown(topic)} holds {need / 2**20:.1f} MiB in {count} "
            f"messages here, more than the {max_bytes / 2**20:.1f} MiB allowed (max_bytes)"
        )


def fetched(connection, ids: list, count: int, where: str) -> tuple[np.ndarray, list[bytes]]:
    """The ``count`` receive times and data of the messages of topic ids ``ids``."""
    times = np.empty(count, np.int64)
    datas: list[bytes] = []
    for k, (stamp, data) in enumerate(_rows(connection, ids)):
        if k == count:  # an immutable file answers the same twice; this one did not
            break
        times[k] = stamp
        datas.append(data)
    if len(datas) != count:
        raise InputFileError(f"{where}: the messages changed while they were read")
    return times, datas


# -- writing ---------------------------------------------------------------------------------------

_SCHEMA = """
CREATE TABLE schema(schema_version INTEGER PRIMARY KEY, ros_distro TEXT NOT NULL);
CREATE TABLE metadata(id INTEGER PRIMARY KEY, metadata_version INTEGER NOT NULL,
                      metadata TEXT NOT NULL);
CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL,
                    serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL,
                    type_description_hash TEXT NOT NULL);
CREATE TABLE message_definitions(id INTEGER PRIMARY KEY, topic_type TEXT NOT NULL,
                                 encoding TEXT NOT NULL, encoded_message_definition TEXT NOT NULL,
                                 type_description_hash TEXT NOT NULL);
CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL,
                      timestamp INTEGER NOT NULL, data BLOB NOT NULL);
"""
#: The ``ros_distro`` written into the schema table and metadata.yaml.
DISTRO = "a2b"


def create(connection: sqlite3.Connection, topics) -> None:
    """The tables, the schema row, the topics and the definitions of their types."""
    from .ros2 import DEFINITIONS, schema_text

    connection.execute("PRAGMA journal_mode = OFF")  # a failure discards the whole folder
    connection.execute("PRAGMA synchronous = OFF")
    connection.executescript(_SCHEMA)
    connection.execute("INSERT INTO schema VALUES(?, ?)", (SCHEMA_VERSION, DISTRO))
    connection.executemany(
        "INSERT INTO topics VALUES(?, ?, ?, 'cdr', ?, ?)",
        [(k + 1, name, kind, qos, TYPE_HASHES.get(kind, "")) for k, (name, kind, qos) in
         enumerate(topics)],
    )  # fmt: skip
    for kind in dict.fromkeys(kind for _name, kind, _qos in topics):
        short = kind.replace("/msg/", "/")
        if short in DEFINITIONS:  # rosbag2 leaves out the definitions it cannot find
            connection.execute(
                "INSERT INTO message_definitions(topic_type, encoding, "
                "encoded_message_definition, type_description_hash) VALUES(?, 'ros2msg', ?, ?)",
                (kind, schema_text(short).decode(), TYPE_HASHES.get(kind, "")),
            )


def _checked(item, topic_count: int) -> tuple[int, int, bytes]:
    """``(topic index, timestamp, data)`` of one message, checked."""
    try:
        index, stamp, data = item
        index, stamp = operator.index(index), operator.index(stamp)
    except (TypeError, ValueError):
        raise ParameterError(
            f"a message is {shown(repr(item))}, not (topic index, time in ns, bytes)"
        ) from None
    if not 0 <= index < topic_count:
        raise ParameterError(f"a message names topic {index}; there are {topic_count}")
    if not 0 <= stamp < 2**63:
        raise ParameterError(f"a message's time {stamp} ns is outside [0, 2**63)")
    if not isinstance(data, (bytes, bytearray, memoryview)):
        raise ParameterError(f"a message's data is {type(data).__name__}, not bytes")
    return index, stamp, data


def insert(connection: sqlite3.Connection, topic_count: int, messages) -> tuple:
    """Insert ``messages`` :data:`BLOCK` at a time; their counts per topic, first and last
    time."""
    counts, first, last = [0] * topic_count, None, None
    items = iter(messages)
    while block := list(islice(items, BLOCK)):
        rows = []
        for item in block:
            index, stamp, data = _checked(item, topic_count)
            counts[index] += 1
            rows.append((index + 1, stamp, data))
        stamps = [row[1] for row in rows]
        first = min(stamps) if first is None else min(first, *stamps)
        last = max(stamps) if last is None else max(last, *stamps)
        connection.executemany(
            "INSERT INTO messages(topic_id, timestamp, data) VALUES(?, ?, ?)", rows
        )
    return counts, first, last
