"""MCAP files read from their bytes: records checked against their ends, CRCs verified, chunks
inflated within a budget, and the messages of a channel cut out with numpy.

https://mcap.dev/spec: a file is the magic ``89 4D 43 41 50 30 0D 0A``, a data section, an
optional summary section, a Footer record and the magic again. A record is an opcode (1 byte),
its length (``uint64``) and its fields; a string or a byte array is a ``uint32`` length and its
bytes, a map a ``uint32`` byte length and its pairs.

=====  ==============  ==========================================================================
op     record          fields read here
=====  ==============  ==========================================================================
0x02   Footer          summary start, summary offset start (``uint64``), summary CRC (``uint32``)
0x03   Schema          id (``uint16``), name, encoding, data
0x04   Channel         id, schema id (``uint16``), topic, message encoding, metadata
0x05   Message         channel id (``uint16``), sequence (``uint32``), log and publish time, data
0x06   Chunk           start and end time, uncompressed size (``uint64``), uncompressed CRC,
                       compression (a string: "", ``zstd`` or ``lz4``), records (``uint64`` length)
0x07   Message Index   channel id, ``(log time, offset)`` pairs (``uint32`` byte length)
0x08   Chunk Index     start and end time, chunk offset and length, message index offsets
                       (``map<uint16, uint64>``), their length, compression, sizes
0x0B   Statistics      counts, times, then messages per channel (``map<uint16, uint64>``)
0x0F   Data End        the CRC of every byte before it (the magic included)
=====  ==============  ==========================================================================

A CRC of 0 means "not computed"; every other one is checked. The ``mcap`` package's reader
makes a Python object of every message (about 7 µs each) and inflates a chunk to whatever size
it declares; here the summary says where each chunk is, each chunk's Message Index where each
message of a channel sits in it, and the messages are cut out as arrays
(:meth:`McapFile.messages`). A file without those indexes is read record by record.
"""

from __future__ import annotations

import struct
import zlib
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputFileError

__all__ = [
    "FREE_INFLATION",
    "INFLATION",
    "MAGIC",
    "MESSAGE_HEAD",
    "Channel",
    "McapFile",
    "Messages",
    "cut",
]

MAGIC = b"\x89MCAP0\r\n"
_FOOTER, _SCHEMA, _CHANNEL, _MESSAGE, _CHUNK = 0x02, 0x03, 0x04, 0x05, 0x06
_MESSAGE_INDEX, _CHUNK_INDEX, _STATISTICS, _DATA_END = 0x07, 0x08, 0x0B, 0x0F
_ENTRY = np.dtype([("log_time", "<u8"), ("offset", "<u8")])
#: A Message record up to its data: opcode, record length, channel id, sequence, log time,
#: publish time (the writers pack their records with it).
MESSAGE_HEAD = np.dtype(
    [
        ("opcode", "u1"),
        ("length", "<u8"),
        ("channel", "<u2"),
        ("sequence", "<u4"),
        ("log_time", "<u8"),
        ("publish_time", "<u8"),
    ]
)
_DATA_AT = MESSAGE_HEAD.itemsize  # a Message record's data: after opcode … publish time
_FOOTER_SIZE = 1 + 8 + 20

#: Chunks inflate to at most this many bytes in all, whatever the size of the file …
FREE_INFLATION = 32 << 20
#: … or to this many times the bytes of the file. Messages with stamps that differ compress
#: 3 to 30 times (a2b's own files 3 to 6 times in all, 31 times in the most for one chunk: a
#: Path of one pose repeated); runs of one byte (a bomb of zeros) compress 30,000 times.
INFLATION = 100


@dataclass
class Channel:
    """A channel and its schema (``schema_name`` and ``schema_encoding`` empty without one)."""

    id: int
    topic: str
    message_encoding: str
    schema_id: int
    schema_name: str = ""
    schema_encoding: str = ""


@dataclass
class _ChunkIndex:
    offset: int
    length: int
    message_index_offsets: dict = field(default_factory=dict)


class Messages:
    """The data of a channel's messages in log-time order, side by side: message ``k`` is
    ``buffer[start[k] : start[k] + length[k]]`` (``buffer`` a uint8 array), logged at
    ``log_time[k]`` (``uint64`` nanoseconds)."""

    def __init__(self, buffer: np.ndarray, start, length, log_time=None):
        self.buffer, self.start, self.length = buffer, start, length
        self.log_time = np.zeros(len(start), np.uint64) if log_time is None else log_time

    @classmethod
    def of(cls, datas: list, log_time=None) -> Messages:
        """The messages ``datas`` (bytes each), joined into one buffer."""
        length = np.fromiter(map(len, datas), np.int64, len(datas))
        buffer = np.frombuffer(b"".join(datas), np.uint8)
        return cls(buffer, np.cumsum(length) - length, length, log_time)

    def __len__(self) -> int:
        return len(self.start)

    def as_bytes(self) -> list:
        """One ``bytes`` per message."""
        return [self.buffer[s : s + n].tobytes()
                for s, n in zip(self.start.tolist(), self.length.tolist())]  # fmt: skip

    @classmethod
    def joined(cls, parts: list) -> Messages:
        """The messages of ``parts`` (each a :class:`Messages`) in log-time order, stable: the
        buffers end to end, the messages put in order by their starts alone."""
        parts = [part for part in parts if len(part)] or [cls.of([])]
        shift = np.cumsum([0] + [len(part.buffer) for part in parts[:-1]])
        buffer = parts[0].buffer if len(parts) == 1 else np.concatenate([p.buffer for p in parts])
        start, length, log_time = (
            np.concatenate([getattr(part, key) + (at if key == "start" else 0)
                            for part, at in zip(parts, shift.tolist())])
            for key in ("start", "length", "log_time")
        )  # fmt: skip
        order = np.argsort(log_time, kind="stable")
        if (np.diff(order) != 1).any():
            start, length, log_time = start[order], length[order], log_time[order]
        return cls(buffer, start, length, log_time)


class _Fields:
    """The fields of one record, read in order, each checked against the record's end."""

    def __init__(self, buffer, start: int, end: int, where: str):
        self.buffer, self.at, self.end, self.where = buffer, start, end, where

    def take(self, size: int) -> int:
        at = self.at
        if size > self.end - at:
            raise InputFileError(
                f"{self.where}: a field of {size} bytes runs past its record at byte {at}"
            )
        self.at += size
        return at

    def number(self, fmt: str) -> int:
        at = self.take(struct.calcsize(fmt))
        return struct.unpack_from(fmt, self.buffer, at)[0]

    def raw(self, length_fmt: str = "<I") -> memoryview:
        size = self.number(length_fmt)
        at = self.take(size)
        return memoryview(self.buffer)[at : at + size]

    def string(self) -> str:
        raw = self.raw()
        try:
            return bytes(raw).decode()
        except UnicodeDecodeError:
            raise InputFileError(
                f"{self.where}: a string before byte {self.at} is not UTF-8"
            ) from None

    def offsets(self) -> dict:
        """A ``map<uint16, uint64>``."""
        raw = self.raw()
        if len(raw) % 10:
            raise InputFileError(f"{self.where}: a map before byte {self.at} is cut short")
        pairs = np.frombuffer(raw, np.dtype([("key", "<u2"), ("value", "<u8")]))
        return dict(zip(pairs["key"].tolist(), pairs["value"].tolist()))


def _defined(value):
    """What a Schema or Channel record defines (a channel's schema without its names)."""
    return (
        (value.topic, value.message_encoding, value.schema_id)
        if isinstance(value, Channel)
        else value
    )


def _walk(buffer, start: int, end: int, where: str):
    """``(opcode, body start, body end, record start)`` of each record in ``[start, end)``."""
    at = start
    while at < end:
        if end - at < 9:
            raise InputFileError(f"{where}: a record at byte {at} is cut short")
        opcode, length = struct.unpack_from("<BQ", buffer, at)
        if length > end - at - 9:
            raise InputFileError(
                f"{where}: the record at byte {at} (opcode {opcode:#04x}) declares {length} "
                f"bytes; {end - at - 9} remain"
            )
        yield opcode, at + 9, at + 9 + length, at
        at += 9 + length


class McapFile:
    """An MCAP file's channels and, through them, its messages.

    Reading checks the magic at both ends, the Footer, the CRCs of the summary and the data
    section, and reads the summary's Schema, Channel, Chunk Index and Statistics records. A
    file without a summary of channels is read record by record at once, for its channels.

    Raises
    ------
    InputFileError
        Whatever does not hold, with the byte where it failed.
    """

    def __init__(self, data: bytes, name: str):
        self.data, self.name = data, name
        self.channels: dict[int, Channel] = {}
        self._schemas: dict[int, tuple[str, str]] = {}
        self._chunk_indexes: list[_ChunkIndex] = []
        self._counts: dict | None = None
        self._scanned: dict | None = None
        self._keep: set = set()
        self._budget = 0
        self.data_end = self._ends()
        if not self.channels:
            self._scan(())

    # -- the ends: magic, footer, summary, data end ------------------------------------------

    def _ends(self) -> int:
        """Check both ends and read the summary; the offset where the data section ends."""
        data, name = self.data, self.name
        if not data.startswith(MAGIC):
            raise InputFileError(f"{name}: not an MCAP file (no MCAP magic at its start)")
        footer = len(data) - len(MAGIC) - _FOOTER_SIZE
        if footer < len(MAGIC) or not data.endswith(MAGIC) or data[footer] != _FOOTER:
            raise InputFileError(
                f"{name}: the file ends without MCAP's Footer and magic (cut short after "
                f"{len(data)} bytes?)"
            )
        fields = _Fields(data, footer + 9, footer + _FOOTER_SIZE, f"{name}: the footer")
        summary_start, _offsets, crc = (fields.number(f) for f in ("<Q", "<Q", "<I"))
        if summary_start and not len(MAGIC) <= summary_start <= footer:
            raise InputFileError(
                f"{name}: the footer puts the summary at byte {summary_start}, outside the "
                f"file's {len(data)} bytes"
            )
        if summary_start:
            self._check_crc(crc, data, summary_start, footer + 9 + 16, "the summary")
            self._summary(summary_start, footer)
        data_end = (summary_start or footer) - 13
        if data_end > len(MAGIC) and struct.unpack_from("<BQ", data, data_end) == (_DATA_END, 4):
            (crc,) = struct.unpack_from("<I", data, data_end + 9)
            self._check_crc(crc, data, 0, data_end, "the data section")
            return data_end
        return summary_start or footer

    def _check_crc(self, crc: int, buffer, start: int, end: int, what: str) -> None:
        if crc and zlib.crc32(memoryview(buffer)[start:end]) != crc:
            raise InputFileError(
                f"{self.name}: the CRC of {what} (bytes {start} to {end}) does not match: "
                f"{zlib.crc32(memoryview(buffer)[start:end]):#010x}, the file says {crc:#010x}"
            )

    def _summary(self, start: int, end: int) -> None:
        where = f"{self.name}: the summary"
        for opcode, body, stop, _at in _walk(self.data, start, end, where):
            fields = _Fields(self.data, body, stop, where)
            if opcode in (_SCHEMA, _CHANNEL):
                self._define(opcode, fields)
            elif opcode == _CHUNK_INDEX:
                fields.take(16)  # message start and end time
                offset, length = fields.number("<Q"), fields.number("<Q")
                self._chunk_indexes.append(_ChunkIndex(offset, length, fields.offsets()))
            elif opcode == _STATISTICS:
                fields.take(8 + 2 + 4 + 4 + 4 + 4 + 8 + 8)
                self._counts = fields.offsets()
        self._name_schemas()

    def _define(self, opcode: int, fields: _Fields) -> None:
        """Read a Schema or a Channel record: a second record of one id must repeat the first."""
        key = fields.number("<H")
        if opcode == _SCHEMA:
            found, known, what = (fields.string(), fields.string()), self._schemas, "schema"
        else:
            schema = fields.number("<H")
            found = Channel(key, fields.string(), fields.string(), schema)
            known, what = self.channels, "channel"
        if key in known and _defined(known[key]) != _defined(found):
            raise InputFileError(
                f"{self.name}: two {what} records of id {key} differ (a file keeps one {what} "
                "per id)"
            )
        known.setdefault(key, found)

    def _name_schemas(self) -> None:
        """Give each channel its schema's name and encoding."""
        for channel in self.channels.values():
            schema = channel.schema_id
            if schema and schema not in self._schemas:
                raise InputFileError(
                    f"{self.name}: channel {channel.id} names schema {schema}, which the file "
                    "does not define"
                )
            channel.schema_name, channel.schema_encoding = self._schemas.get(schema, ("", ""))

    # -- chunks -----------------------------------------------------------------------------

    def _chunk(self, fields: _Fields, at: int) -> np.ndarray:
        """The records of the Chunk whose fields (after the opcode and length) ``fields``
        reads: inflated within the file's budget, their CRC checked, as a uint8 array."""
        fields.take(16)  # message start and end time
        size, crc = fields.number("<Q"), fields.number("<I")
        compression = fields.string()
        raw = fields.raw("<Q")
        where = f"{self.name}: the chunk at byte {at}"
        if compression == "" and len(raw) != size:
            raise InputFileError(f"{where} holds {len(raw)} bytes and declares {size}")
        if compression and size > self._budget:
            raise InputFileError(
                f"{where} declares {size} bytes from {len(raw)} compressed: more than the "
                f"{self._budget} bytes left to inflate for a file of {len(self.data)} bytes (in "
                f"all, the larger of {FREE_INFLATION} and {INFLATION} times its size)"
            )
        records = _inflate(raw, compression, size, where) if compression else raw
        self._budget -= size if compression else 0
        if crc and zlib.crc32(records) != crc:
            raise InputFileError(
                f"{where}: the CRC of its records does not match: {zlib.crc32(records):#010x}, "
                f"the chunk says {crc:#010x}"
            )
        return np.frombuffer(records, np.uint8)

    def _indexed_chunk(self, index: _ChunkIndex) -> np.ndarray:
        at, length = index.offset, index.length
        if not len(MAGIC) <= at or length > self.data_end - at or length < 9:
            raise InputFileError(
                f"{self.name}: a chunk index points at bytes {at} to {at + length}, outside "
                f"the data section (bytes {len(MAGIC)} to {self.data_end})"
            )
        opcode, size = struct.unpack_from("<BQ", self.data, at)
        if opcode != _CHUNK or size != length - 9:
            raise InputFileError(
                f"{self.name}: a chunk index points at byte {at}, where no chunk of "
                f"{length} bytes starts (opcode {opcode:#04x}, {size} + 9 bytes)"
            )
        return self._chunk(_Fields(self.data, at + 9, at + length, self.name), at)

    # -- messages ---------------------------------------------------------------------------

    def messages(self, ids: list) -> dict:
        """``{channel id: Messages}`` of the channels ``ids``, each in log-time order.

        Through the indexes where every chunk has its Message Indexes (each chunk inflated
        once), else from the records as they stand in the file.
        """
        self._budget = max(FREE_INFLATION, INFLATION * len(self.data))  # for each reading
        indexes = self._chunk_indexes
        if indexes and all(index.message_index_offsets for index in indexes):
            return self._through_indexes(ids)
        self._scan(ids)
        return {key: self._scanned.get(key, Messages.of([])) for key in ids}

    def _through_indexes(self, ids: list) -> dict:
        if len({index.offset for index in self._chunk_indexes}) < len(self._chunk_indexes):
            raise InputFileError(f"{self.name}: two chunk indexes point at one chunk")
        parts: dict = {key: [] for key in ids}
        for index in self._chunk_indexes:
            if not any(key in index.message_index_offsets for key in ids):
                continue
            records = self._indexed_chunk(index)
            for key in ids:
                if key in index.message_index_offsets:
                    entries = self._entries(index.message_index_offsets[key], key)
                    parts[key].append(self._cut(records, entries, key, index.offset))
        found = {key: Messages.joined(part) for key, part in parts.items()}
        for key, got in found.items():
            counted = (self._counts or {}).get(key, len(got))
            if counted != len(got):
                raise InputFileError(
                    f"{self.name}: the statistics count {counted} messages on channel {key}, "
                    f"its message indexes {len(got)}"
                )
        return found

    def _entries(self, at: int, key: int) -> np.ndarray:
        """The ``(log_time, offset)`` entries of the Message Index record at ``at``."""
        if not len(MAGIC) <= at <= self.data_end - 15:
            raise InputFileError(f"{self.name}: a message index offset {at} is outside the file")
        opcode, length, channel, size = struct.unpack_from("<BQHI", self.data, at)
        if opcode != _MESSAGE_INDEX or channel != key:
            raise InputFileError(
                f"{self.name}: the message index of channel {key} points at byte {at}, where a "
                f"record of opcode {opcode:#04x} (channel {channel}) starts"
            )
        if size % _ENTRY.itemsize or size > length - 6 or length > self.data_end - at - 9:
            raise InputFileError(
                f"{self.name}: the message index at byte {at} declares {size} bytes of entries "
                f"in a record of {length}"
            )
        return np.frombuffer(self.data, _ENTRY, size // _ENTRY.itemsize, at + 15)

    def _cut(self, records: np.ndarray, entries: np.ndarray, key: int, chunk: int) -> Messages:
        """The messages at ``entries`` of the chunk ``records``, each checked to be a Message
        record of channel ``key`` that fits in the chunk, at the log time of its entry."""
        where = f"{self.name}: the message index of channel {key} in the chunk at byte {chunk}"
        if not len(entries):
            return Messages.of([])
        if int(entries["offset"].max()) > len(records) - _DATA_AT:
            raise InputFileError(f"{where} points past the chunk's {len(records)} bytes")
        offset = entries["offset"].astype(np.int64)
        head = cut(records, offset, _DATA_AT)  # each message's record up to its data
        opcode = head[:, 0]
        channel = head[:, 9:11].copy().view("<u2")[:, 0]
        length = head[:, 1:9].copy().view("<u8")[:, 0]
        log_time = head[:, 15:23].copy().view("<u8")[:, 0]
        if (opcode != _MESSAGE).any() or (channel != key).any():
            raise InputFileError(f"{where} points at a record that is no message of the channel")
        if (length > (len(records) - 9 - offset).astype(np.uint64)).any() or (
            length < _DATA_AT - 9
        ).any():
            raise InputFileError(f"{where}: a message runs past the chunk")
        if (log_time != entries["log_time"]).any():
            raise InputFileError(f"{where} gives a message a log time it does not have")
        size = length.astype(np.int64) - (_DATA_AT - 9)
        start = offset + _DATA_AT
        order = np.argsort(offset, kind="stable")
        if (start[order][:-1] + size[order][:-1] > offset[order][1:]).any():
            raise InputFileError(f"{where} points at messages that overlap")
        if (size == size[0]).all():  # one width: the chunk's messages as one strided view
            rows = cut(records, start, int(size[0]))
            return Messages(rows.reshape(-1), np.arange(len(rows)) * rows.shape[1], size, log_time)
        buffer, packed = _packed(records, start, size)
        return Messages(buffer, packed, size, log_time)

    # -- record by record -------------------------------------------------------------------

    def _scan(self, keep) -> None:
        """Read the data section record by record: the schemas, channels, and the messages of
        the channels ``keep`` as they stand, chunks inflated one at a time (:attr:`_scanned`:
        channel → :class:`Messages`)."""
        self._scanned, self._keep = {}, set(keep)
        self._budget = max(FREE_INFLATION, INFLATION * len(self.data))
        where = f"{self.name}: the data section"
        for opcode, body, end, at in _walk(self.data, len(MAGIC), self.data_end, where):
            if opcode == _CHUNK:
                records = self._chunk(_Fields(self.data, body, end, where), at)
                inner = f"{self.name}: the chunk at byte {at}"
                for op, start, stop, _at in _walk(records, 0, len(records), inner):
                    self._take(records, op, start, stop, inner)
            else:
                self._take(self.data, opcode, body, end, where)
        self._name_schemas()
        for key, found in self._scanned.items():
            log_time = np.array([time for time, _ in found], np.uint64)
            order = np.argsort(log_time, kind="stable").tolist()  # equal times: file order
            self._scanned[key] = Messages.of([found[k][1] for k in order], log_time[order])

    def _take(self, buffer, opcode: int, start: int, end: int, where: str) -> None:
        fields = _Fields(buffer, start, end, where)
        if opcode in (_SCHEMA, _CHANNEL):
            self._define(opcode, fields)
        elif opcode == _MESSAGE:
            key = fields.number("<H")
            fields.take(4)
            log_time = fields.number("<Q")
            fields.take(8)
            if key not in self.channels:
                raise InputFileError(
                    f"{where}: a message at byte {start - 9} is on channel {key}, which no "
                    "Channel record before it defines"
                )
            if key in self._keep:
                message = bytes(buffer[fields.at : end])
                self._scanned.setdefault(key, []).append((log_time, message))


def _inflate(raw: memoryview, compression: str, size: int, where: str) -> memoryview:
    """The ``size`` bytes that ``raw`` inflates to, never more: a chunk that inflates to more
    or fewer bytes than it declares is an error, found without holding more than ``size + 1``."""
    if compression == "zstd":
        import zstandard

        out = np.empty(size + 1, np.uint8)  # not zeroed: every byte kept is written
        try:
            reader = zstandard.ZstdDecompressor().stream_reader(raw, read_across_frames=True)
            got, view = 0, memoryview(out)
            while got <= size:
                n = reader.readinto(view[got:])
                if not n:
                    break
                got += n
        except zstandard.ZstdError as e:
            raise InputFileError(f"{where}: its zstd data is damaged ({e})") from None
    elif compression == "lz4":
        import lz4.frame

        try:
            out = lz4.frame.LZ4FrameDecompressor().decompress(raw, max_length=size + 1)
        except RuntimeError as e:
            raise InputFileError(f"{where}: its lz4 data is damaged ({e})") from None
        got = len(out)
    else:
        raise InputFileError(
            f"{where} is compressed with {compression[:40]!r}; a2b reads zstd, lz4 and none"
        )
    if got != size:
        more = "more" if got > size else f"{got}"
        raise InputFileError(f"{where} declares {size} bytes and inflates to {more}")
    return memoryview(out)[:size]


def _packed(buffer: np.ndarray, start: np.ndarray, size: np.ndarray):
    """The ``size[k]`` bytes of ``buffer`` from each ``start[k]``, end to end, and where each
    starts there; gathered a block of messages at a time (an index of at most about
    :data:`_GATHER` entries)."""
    packed = np.cumsum(size) - size
    out = np.empty(int(size.sum()), np.uint8)
    step = max(1, _GATHER // max(int(size.max()), 1))
    for lo in range(0, len(start), step):
        here = slice(lo, lo + step)
        index = np.repeat(start[here] - packed[here], size[here])
        out_at = slice(int(packed[lo]), int(packed[lo]) + len(index))
        out[out_at] = buffer[index + np.arange(out_at.start, out_at.stop)]
    return out, packed


#: Index entries gathered at a time by :func:`cut` (8 bytes each).
_GATHER = 1 << 20


def cut(buffer: np.ndarray, start: np.ndarray, width: int) -> np.ndarray:
    """``(n, width)`` bytes of ``buffer`` from each of ``start``: one slice for one start, a
    strided view where the starts are evenly spaced (as in a2b's own files), else gathered a
    block of rows at a time (so that the index never outgrows :data:`_GATHER` entries)."""
    if len(start) == 1:
        return buffer[int(start[0]) : int(start[0]) + width][None]
    step = int(start[1] - start[0]) if len(start) > 1 else 0
    if len(start) > 1 and step > 0 and (np.diff(start) == step).all():
        view = np.lib.stride_tricks.as_strided(
            buffer[int(start[0]) :], shape=(len(start), width), strides=(step, 1), writeable=False
        )
        return np.array(view)
    out = np.empty((len(start), width), np.uint8)
    rows = max(1, _GATHER // max(width, 1))
    for lo in range(0, len(start), rows):
        out[lo : lo + rows] = buffer[start[lo : lo + rows, None] + np.arange(width)]
    return out
