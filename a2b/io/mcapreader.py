"""The messages of one channel of an indexed MCAP file, with array operations.

The ``mcap`` package's reader makes a Python object of every record, about 7 µs a message
(13.8 s for the 10^6 messages of one topic of a 2·10^6-message file). The summary of an
indexed file already says where each chunk is, and each chunk's Message Index records where
each message of a channel sits in it. So: each chunk of the channel is decompressed once, the
offsets of its messages are read as one array, and the messages are cut out with numpy. The
``mcap`` package still reads the summary; a file without chunk or message indexes, or with a
compression other than zstd or none, is for the package's reader (:func:`channel_messages`
returns None).

https://mcap.dev/spec: a Chunk record is opcode 0x06, its length, then message start and end
time, uncompressed size, uncompressed CRC, compression (a string) and the records (a byte
array); a Message Index record is opcode 0x07, its length, channel id, and ``(log time,
offset)`` pairs; a Message record is opcode 0x05, its length, channel id, sequence, log time,
publish time, and the data (31 bytes before it).
"""

from __future__ import annotations

import struct

import numpy as np

__all__ = ["Messages", "channel_messages", "cut"]

_MESSAGE, _CHUNK, _MESSAGE_INDEX = 0x05, 0x06, 0x07
_ENTRY = np.dtype([("log_time", "<u8"), ("offset", "<u8")])
_DATA_AT = 1 + 8 + 2 + 4 + 8 + 8  # a Message record's data: after opcode … publish time


class Messages:
    """The data of messages, in log-time order: ``rows`` (an ``(n, width)`` uint8 array) when
    they are all ``width`` bytes long, else ``datas`` (a list of bytes)."""

    def __init__(self, rows: np.ndarray | None = None, datas: list | None = None):
        self.rows, self.datas = rows, datas

    def __len__(self) -> int:
        return len(self.rows) if self.rows is not None else len(self.datas)

    def as_bytes(self) -> list:
        """One ``bytes`` per message."""
        return [row.tobytes() for row in self.rows] if self.rows is not None else self.datas


def channel_messages(data: bytes, summary, channel_id: int) -> Messages | None:
    """The messages of ``channel_id`` in ``data`` through its indexes, or None when the file
    lacks them (or compresses a chunk other than with zstd): then read it record by record.

    Raises
    ------
    ValueError
        If an index points at something that is not a message of the channel.
    """
    if summary is None or not summary.chunk_indexes:
        return None
    counts = (summary.statistics.channel_message_counts or {}) if summary.statistics else {}
    pieces, times = [], []
    for index in summary.chunk_indexes:
        if channel_id not in index.message_index_offsets:
            continue
        if index.compression not in ("", "zstd"):
            return None
        records = _records(data, index)
        entries = _entries(data, index.message_index_offsets[channel_id])
        offset = entries["offset"].astype(np.int64)
        if offset.size and offset.max() + _DATA_AT > len(records):
            raise ValueError(f"a message index points past its chunk at {index.chunk_start_offset}")
        head = np.frombuffer(records, np.uint8)
        opcode = head[offset]
        length = _u64(head, offset + 1)
        channel = head[offset + 9].astype(np.uint16) | (head[offset + 10].astype(np.uint16) << 8)
        if (opcode != _MESSAGE).any() or (channel != channel_id).any():
            raise ValueError(f"a message index of channel {channel_id} points at another record")
        size = length - (_DATA_AT - 9)
        if (offset + 9 + length > len(records)).any() or (size < 0).any():
            raise ValueError("a message runs past its chunk")
        pieces.append((head, offset + _DATA_AT, size))
        times.append(entries["log_time"])
    if not pieces:
        return Messages(datas=[]) if counts.get(channel_id, 0) == 0 else None
    order = np.argsort(np.concatenate(times), kind="stable")
    sizes = np.concatenate([size for _, _, size in pieces])
    if (sizes == sizes[0]).all():  # one width: cut each chunk's messages as one strided view
        rows = np.concatenate([cut(head, start, int(sizes[0])) for head, start, _ in pieces])
        return Messages(rows=rows[order] if (np.diff(order) != 1).any() else rows)
    datas = [head[s : s + n].tobytes() for head, starts, ns in pieces
             for s, n in zip(starts.tolist(), ns.tolist())]  # fmt: skip
    return Messages(datas=[datas[k] for k in order.tolist()])


def _u64(buffer: np.ndarray, at: np.ndarray) -> np.ndarray:
    return buffer[at[:, None] + np.arange(8)].copy().view("<u8")[:, 0].astype(np.int64)


def cut(buffer: np.ndarray, start: np.ndarray, width: int) -> np.ndarray:
    """``(n, width)`` bytes of ``buffer`` from each of ``start``: one slice for one start, a
    strided view where the starts are evenly spaced (as in a2b's own files), else gathered
    (which costs an index of 8 bytes per byte)."""
    if len(start) == 1:
        return buffer[int(start[0]) : int(start[0]) + width][None]
    step = int(start[1] - start[0]) if len(start) > 1 else 0
    if len(start) > 1 and step > 0 and (np.diff(start) == step).all():
        view = np.lib.stride_tricks.as_strided(
            buffer[int(start[0]) :], shape=(len(start), width), strides=(step, 1), writeable=False
        )
        return np.array(view)
    return buffer[start[:, None] + np.arange(width)]


def _records(data: bytes, index) -> bytes:
    """The uncompressed records of the chunk that ``index`` (a Chunk Index) points at."""
    at = index.chunk_start_offset
    opcode, _length = struct.unpack_from("<BQ", data, at)
    if opcode != _CHUNK:
        raise ValueError(f"the chunk index points at a record of opcode {opcode:#x}, not a chunk")
    at += 9 + 8 + 8
    size, _crc, name_length = struct.unpack_from("<QII", data, at)
    at += 16
    compression = data[at : at + name_length].decode()
    at += name_length
    (records_length,) = struct.unpack_from("<Q", data, at)
    at += 8
    raw = data[at : at + records_length]
    if compression == "":
        return raw
    import zstandard

    return zstandard.ZstdDecompressor().decompress(raw, max_output_size=size)


def _entries(data: bytes, at: int) -> np.ndarray:
    """The ``(log_time, offset)`` entries of the Message Index record at ``at``."""
    opcode, _length, _channel, size = struct.unpack_from("<BQHI", data, at)
    if opcode != _MESSAGE_INDEX:
        raise ValueError(f"a message index offset points at a record of opcode {opcode:#x}")
    return np.frombuffer(data, _ENTRY, size // _ENTRY.itemsize, at + 15)
