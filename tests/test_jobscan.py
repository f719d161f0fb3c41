"""Scanning JSON Lines jobs (``a2b.io.jobscan``): the fast path gives the exact reader's jobs.

Every line is either checked fast or read the exact way; the jobs, their errors and the order
of the two are those of reading line by line with the exact reader.
"""

from __future__ import annotations

import io

import numpy as np
import pytest

from a2b.errors import InputFileError
from a2b.io import jobfiles, jobscan, poseschema


def _jobs_text(n: int, bad_at: int | None = None) -> bytes:
    lines = []
    for i in range(n):
        w = 1.0 + i / 7
        end = (
            '{"quaternion_wxyz": [1, 0, 0, 0]}' if i != bad_at else '{"quaternion_wxyz": [1, 0, 0]}'
        )
        lines.append(
            f'{{"name": "j{i}", "start": {{"quaternion_wxyz": [{w!r}, 0.5, 0, 0], '
            f'"translation": [{i}, 2.5, -1]}}, "end": {end}}}'
        )
    return ("\n".join(lines) + "\n").encode()


def _read_blocks(data: bytes, name: str, size: int = 4):
    """The jobs read in blocks of ``size``, and the error's message (or None)."""
    jobs, error = [], None
    try:
        for block in jobfiles.read_jobs(io.BytesIO(data), name).blocks(size):
            assert 0 < len(block) <= size
            jobs.extend(block.jobs())
    except InputFileError as e:
        error = str(e)
    return jobs, error


def _read_one_by_one(data: bytes, name: str):
    jobs, error = [], None
    try:
        for job in jobfiles.read_jobs(io.BytesIO(data), name):
            jobs.append(job)
    except InputFileError as e:
        error = str(e)
    return jobs, error


def _same(a, b):
    assert len(a) == len(b)
    for x, y in zip(a, b):
        assert x.name == y.name and x.mode == y.mode and x.samples == y.samples
        assert x.parameters == y.parameters
        np.testing.assert_array_equal(x.start, y.start)
        np.testing.assert_array_equal(x.end, y.end)


@pytest.mark.parametrize("bad_at", [None, 0, 17, 49])
def test_blocks_give_the_jobs_and_errors_of_reading_one_by_one(bad_at):
    data = _jobs_text(50, bad_at)
    in_blocks = _read_blocks(data, "j.jsonl")
    one_by_one = _read_one_by_one(data, "j.jsonl")
    assert in_blocks[1] == one_by_one[1]
    assert (in_blocks[1] is None) == (bad_at is None)
    _same(in_blocks[0], one_by_one[0])
    assert len(in_blocks[0]) == (50 if bad_at is None else bad_at)


def test_errors_of_scanning_arrive_after_the_jobs_before_them():
    """A line that is no UTF-8, an empty file, a stream that fails."""
    bad_bytes = _jobs_text(5) + b"\xff\n" + _jobs_text(2)
    for data in (bad_bytes, b"\n \n"):
        got = _read_blocks(data, "j.jsonl")
        expected = _read_one_by_one(data, "j.jsonl")
        assert got[1] == expected[1] is not None
        _same(got[0], expected[0])

    class Failing(io.BytesIO):
        def __iter__(self):
            yield from _jobs_text(4).splitlines(keepends=True)
            raise OSError("the disk went away")

    sizes = []
    with pytest.raises(OSError, match="the disk went away"):
        for block in jobfiles.read_jobs(Failing(), "j.jsonl").blocks(3):
            sizes.append(len(block))
    assert sizes == [3, 1]


def test_names_beyond_ascii_stay_on_the_fast_path():
    """Only a name UTF-8 cannot write is read the exact way; others, of any script, are not."""
    calls = []

    def exact(*args):
        calls.append(args)
        return jobfiles.json_line_job(*args)

    lines = [
        f'{{"name": "{name}", "start": {{"quaternion_wxyz": [1, 0, 0, 0]}}, '
        '"end": {"quaternion_wxyz": [0, 1, 0, 0]}}'
        for name in ("Gelenk-ä", "関節", "ok", "\\udcff")
    ]
    stream = io.BytesIO(("\n".join(lines) + "\n").encode())
    sniffed = jobscan.sniff(stream, "j.jsonl")
    with pytest.raises(InputFileError, match="lone surrogate"):
        list(
            jobscan.scan_blocks(
                jobscan.lines(stream, sniffed.name, sniffed.first), "j.jsonl", 8, exact
            )
        )
    assert [number for _, _, number, _ in calls] == [4]


def test_parameter_kinds_come_from_the_table():
    from a2b.parameters import TABLE

    assert set(poseschema.PARAMETER_KINDS) == {p.name for p in TABLE}
    assert poseschema.PARAMETER_KINDS["m"] == 4 and poseschema.PARAMETER_KINDS["delta"] == "number"
