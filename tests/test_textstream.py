"""A large text trajectory is read a piece at a time as it is parsed (``TextStream``): the same
pieces, poses and errors as the whole text read first."""

from __future__ import annotations

import io

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from a2b.errors import InputFileError
from a2b.io import textrows, trajectories
from a2b.io.textrows import TextStream
from a2b.io.trajectories import opened, trajectory_pieces


def _cut(data: bytes, size: int, first: int) -> list[bytes]:
    """The pieces by their definition: each up to the first line end at or after its size."""
    out, start, step = [], 0, first
    while start < len(data):
        stop = data.find(b"\n", start + step) + 1 if len(data) - start > step else 0
        out.append(data[start : stop or len(data)])
        start, step = stop or len(data), size
    return out


@settings(max_examples=300, deadline=None)
@given(st.lists(st.integers(0, 40), max_size=30), st.integers(1, 50), st.integers(1, 50),
       st.booleans(), st.integers(0, 1))  # fmt: skip
def test_pieces_end_at_the_first_line_end_after_their_size(lines, size, first, end, long):
    data = b"\n".join(b"x" * n for n in lines) + b"\n" * end
    if long:  # lines longer than what is read past a piece's size, one to the end
        data += b"y" * (9 * textrows._AFTER) + b"\nz\n" + b"w" * (3 * textrows._AFTER)
    pieces = list(TextStream(io.BytesIO(data), len(data)).pieces(size, first))
    assert pieces == _cut(data, size, first)


def test_the_pieces_are_read_once_and_a_line_without_end_stops_at_a_nul_byte():
    stream = TextStream(io.BytesIO(b"1\n2\n"), 4)
    assert list(stream.pieces(1, 1)) == [b"1\n", b"2\n"]
    with pytest.raises(ValueError, match="once"):
        list(stream.pieces(1, 1))
    binary = io.BytesIO(b"\0" * (64 << 20))  # no line end: not read to its end
    first = next(TextStream(binary, 64 << 20).pieces(1 << 18, 1 << 18))
    assert b"\0" in first and binary.tell() < 1 << 20


def _tum(count: int, sep: str = " ", header: bytes = b"# time tx ty tz qx qy qz qw\n") -> bytes:
    rng = np.random.default_rng(3)
    quat = rng.normal(size=(count, 4))
    rows = np.column_stack([np.arange(count) * 0.01, rng.normal(size=(count, 3)), quat])
    return header + b"".join(
        (sep.join(repr(float(v)) for v in row) + "\n").encode() for row in rows
    )


def _piece_start(data: bytes, k: int) -> int:
    """Where the ``k``-th piece of ``data`` starts, read in pieces of 2048 bytes (the first
    of 128)."""
    return sum(len(p) for p in _cut(data, 2048, 128)[:k])


def _read(path, size, fmt=None):
    """The poses of a file, or the error's text, and whether it was read as a stream."""
    data = None
    with open(path, "rb") as stream:
        try:
            name, data, fmt = opened(stream, str(path), fmt)
            pieces = list(trajectory_pieces(data, name, fmt, size=size))
        except InputFileError as e:
            return str(e), isinstance(data, TextStream) or data is None
    arrays = [np.concatenate([getattr(p, k) for p in pieces]) for k in ("times", "quat_wxyz")]
    return arrays, isinstance(data, TextStream)


@pytest.mark.parametrize("arrow", [False, True])  # later pieces by numpy, or by pyarrow
@pytest.mark.parametrize(
    "damage",
    [
        None,
        lambda d: textrows.BOM + d,
        lambda d: d[: _piece_start(d, 3)] + textrows.BOM + d[_piece_start(d, 3) :],
        lambda d: d[:50] + b"\0" + d[50:],  # a NUL byte in the first piece
        lambda d: d[:-2000] + b"\0" + d[-2000:],  # a NUL byte in a later piece
        lambda d: d[:-3000] + b"\xff" + d[-3000:],  # no UTF-8
        lambda d: d[:-4000] + b"\r" + d[-4000:],  # a lone carriage return
        lambda d: d[:-5000] + b"nan" + d[-5000:],
        lambda d: d + b"1 2\n",
        lambda d: d.replace(b"\n", b"\r\n"),
        lambda d: d[:-1],  # no line end at the end
        lambda d: b"\n" * 300 + d,  # blank lines over the first pieces
        lambda d: b"\n" * 300 + b"t,tx,ty,tz,qw,qx,qy,qz\n" + d,  # a csv header after them
        lambda d: b"\n" * 300 + b"1 2 3\n" + d,
    ],
)
def test_a_large_file_read_as_it_is_parsed_gives_the_poses_and_errors_of_the_whole(
    tmp_path, monkeypatch, damage, arrow
):
    data = _tum(400)
    if damage is not None:
        data = damage(data)
    fmt = "csv" if b"t,tx" in data else None  # (its header is not on its first line)
    path = tmp_path / "t.tum"
    path.write_bytes(data)
    whole, _ = _read(path, 2048, fmt)
    monkeypatch.setattr(textrows, "STREAM_FROM", 1000)  # "large" from 1000 bytes on
    if arrow:
        monkeypatch.setattr(trajectories, "ARROW_FROM", 1000)
    again, streamed = _read(path, 2048, fmt)
    assert streamed
    if isinstance(whole, str):
        assert again == whole
    else:
        assert all(np.array_equal(a, b) for a, b in zip(whole, again))


def test_a_large_file_is_read_only_as_far_as_it_is_parsed(tmp_path, monkeypatch):
    """The first pose is there after one piece is read: the rest of the file is not."""
    path = tmp_path / "t.tum"
    path.write_bytes(_tum(4000))
    monkeypatch.setattr(textrows, "STREAM_FROM", 1000)
    with open(path, "rb") as stream:
        name, data, fmt = opened(stream, str(path), None)
        first = next(iter(trajectory_pieces(data, name, fmt, size=16384)))
        read = stream.tell()
    assert 0 < len(first) < 100  # a piece of 16384 / 16 bytes first
    assert read <= 1024 + textrows._AFTER + io.DEFAULT_BUFFER_SIZE < path.stat().st_size / 4
