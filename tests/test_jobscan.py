"""Scanning JSON Lines jobs in a helper process (``a2b.io.jobscan.scan_ahead``).

The jobs and errors are those of reading in this process (see also ``compare_readers`` in
tests/test_batched.py, which runs every fuzzed jobs file both ways); here: the handing over
through shared memory and the pipe, and the helper's life.
"""

from __future__ import annotations

import io
import os
import threading
import time

import numpy as np
import pytest

from a2b.errors import InputFileError
from a2b.io import jobscan, parallel, readers

from .test_batched import assert_same_jobs


def _jobs_text(n: int, bad_at: int | None = None) -> bytes:
    lines = []
    for i in range(n):
        w = 1.0 + i / 7
        end = '{"quaternion": [1, 0, 0, 0]}' if i != bad_at else '{"quaternion": [1, 0, 0]}'
        lines.append(
            f'{{"name": "j{i}", "start": {{"quaternion": [{w!r}, 0.5, 0, 0], '
            f'"translation": [{i}, 2.5, -1]}}, "end": {end}}}'
        )
    return ("\n".join(lines) + "\n").encode()


def _read(data: bytes, name: str, ahead: bool, size: int = 4, scan: int = 3):
    """The jobs read in blocks of ``size``, and the error's message (or None)."""
    stream = io.BytesIO(data)
    sniffed = jobscan.sniff(stream, name)
    scanned = jobscan.scan_ahead(stream, sniffed, scan) if ahead else None
    jobs, error = [], None
    try:
        for block in readers.read_jobs(stream, name, sniffed=sniffed, scanned=scanned).blocks(size):
            assert 0 < len(block) <= size
            jobs.extend(block.jobs())
    except InputFileError as e:
        error = str(e)
    return jobs, error


def _no_children_left():
    with pytest.raises(ChildProcessError):
        os.waitpid(-1, os.WNOHANG)


@pytest.mark.parametrize("slots, slot_bytes", [(64, 1 << 18), (2, 1 << 18), (1, 700), (2, 10)])
@pytest.mark.parametrize("bad_at", [None, 0, 17, 49])
def test_scanned_ahead_is_read_here(monkeypatch, slots, slot_bytes, bad_at):
    """Through many slots or one, in slots or (too large for one) through the pipe, with an
    error anywhere: the same jobs, the same error after them, and the helper reaped."""
    monkeypatch.setattr(jobscan, "SLOTS", slots)
    monkeypatch.setattr(jobscan, "SLOT_BYTES", slot_bytes)
    data = _jobs_text(50, bad_at)
    expected = _read(data, "jobs.jsonl", ahead=False)
    got = _read(data, "jobs.jsonl", ahead=True)
    assert got[1] == expected[1]
    assert (got[1] is None) == (bad_at is None)
    assert_same_jobs(got[0], expected[0])
    assert len(got[0]) == (50 if bad_at is None else bad_at)
    _no_children_left()


def test_json_lines_told_by_their_first_line_are_scanned_ahead():
    data = _jobs_text(9)
    sniffed = jobscan.sniff(io.BytesIO(data), "<stdin>")
    assert sniffed.json_lines and sniffed.kind is None and sniffed.first.startswith('{"name"')
    assert_same_jobs(_read(data, "<stdin>", ahead=True)[0], _read(data, "<stdin>", False)[0])
    assert not jobscan.sniff(io.BytesIO(b"- {start: 1}\n"), "<stdin>").json_lines
    _no_children_left()


def test_errors_of_scanning_arrive_after_the_jobs_before_them():
    """A line that is no UTF-8, an empty file, a stream that fails: as read here."""
    bad_bytes = _jobs_text(5) + b"\xff\n" + _jobs_text(2)
    for data, name in [(bad_bytes, "j.jsonl"), (b"\n \n", "j.jsonl")]:
        expected = _read(data, name, ahead=False)
        got = _read(data, name, ahead=True)
        assert got[1] == expected[1] is not None
        assert_same_jobs(got[0], expected[0])

    class Failing(io.BytesIO):
        def __iter__(self):
            yield from _jobs_text(4).splitlines(keepends=True)
            raise OSError("the disk went away")

    def sizes(ahead):
        stream = Failing()
        sniffed = jobscan.Sniffed("j.jsonl", "jsonl", True, None)
        scanned = jobscan.scan_ahead(stream, sniffed, 3) if ahead else None
        got = []
        with pytest.raises(OSError, match="the disk went away"):  # the same error, pickled
            for block in readers.read_jobs(stream, sniffed=sniffed, scanned=scanned).blocks(3):
                got.append(len(block))
        return got

    one_by_one = []
    stream = Failing()
    with pytest.raises(OSError, match="the disk went away"):
        for job in readers.read_jobs(stream, "j.jsonl"):
            one_by_one.append(job)
    assert sizes(True) == sizes(False) == [3, 1] and len(one_by_one) == 4
    _no_children_left()


def test_a_caller_that_stops_early_ends_the_helper(monkeypatch):
    """Stopping after one block, while the helper waits for a free slot or for more input,
    kills and reaps it at once."""
    monkeypatch.setattr(jobscan, "SLOTS", 1)
    data = _jobs_text(200)
    stream = io.BytesIO(data)
    scanned = jobscan.scan_ahead(stream, jobscan.sniff(stream, "j.jsonl"), 2)
    assert len(next(scanned)) == 2
    time.sleep(0.05)  # the helper fills the one slot and waits
    begin = time.monotonic()
    scanned.close()
    assert time.monotonic() - begin < 1.0
    _no_children_left()

    read_end, write_end = os.pipe()  # input that never ends
    with os.fdopen(read_end, "rb") as endless:
        endless_jobs = jobscan.scan_ahead(
            endless, jobscan.Sniffed("j.jsonl", "jsonl", True, None), 2
        )
        os.write(write_end, _jobs_text(3))
        assert len(next(endless_jobs)) == 2
        endless_jobs.close()
    os.close(write_end)
    _no_children_left()


def test_no_helper_while_threads_run():
    stop = threading.Event()
    other = threading.Thread(target=stop.wait)
    other.start()
    try:
        stream = io.BytesIO(_jobs_text(3))
        assert jobscan.scan_ahead(stream, jobscan.sniff(stream, "j.jsonl"), 2) is None
    finally:
        stop.set()
        other.join()


def test_a_busy_child_is_counted_as_our_own():
    """The scanning helper, still busy when the writers start, leaves its processor to
    them: it is this process's own runnable task, not another program's."""
    pid = os.fork()
    if pid == 0:  # pragma: no cover - spins, then leaves
        end = time.monotonic() + 0.5
        while time.monotonic() < end:
            pass
        os._exit(0)
    try:
        time.sleep(0.05)
        counts = [parallel._runnable_own_tasks() for _ in range(20)]
    finally:
        os.waitpid(pid, 0)
    assert max(counts) >= 2  # this process and its spinning child
    assert np.median(counts) >= 1


def test_closing_before_the_first_block_ends_the_helper():
    """A caller that fails between starting the helper and taking a block (an output file that
    cannot be created) closes it, or drops it: either way the helper is ended and reaped."""
    for drop in (False, True):
        stream = io.BytesIO(_jobs_text(5000))
        scanning = jobscan.scan_ahead(stream, jobscan.sniff(stream, "j.jsonl"), 2)
        pid = scanning._pid
        if drop:
            del scanning
        else:
            scanning.close()
            scanning.close()  # twice is harmless
            assert list(scanning) == []
        with pytest.raises(ChildProcessError):
            os.waitpid(pid, os.WNOHANG)
    _no_children_left()


def test_no_helper_without_a_process_to_be_had(monkeypatch):
    """Where no process can be forked (a limit on processes), the jobs are scanned here."""

    def no_fork():
        raise BlockingIOError(11, "Resource temporarily unavailable")

    monkeypatch.setattr(os, "fork", no_fork)
    stream = io.BytesIO(_jobs_text(3))
    sniffed = jobscan.sniff(stream, "j.jsonl")
    assert jobscan.scan_ahead(stream, sniffed, 2) is None
    jobs = readers.read_jobs(stream, sniffed=sniffed, scanned=None)
    assert sum(len(b) for b in jobs.blocks(2)) == 3


def test_names_beyond_ascii_stay_on_the_fast_path(monkeypatch):
    """Only a name UTF-8 cannot write is read the exact way; others, of any script, are not."""
    calls = []
    exact = jobscan._exact_job
    monkeypatch.setattr(jobscan, "_exact_job", lambda *a: calls.append(a) or exact(*a))
    lines = [
        '{"name": "%s", "start": {"quaternion": [1, 0, 0, 0]}, "end": {"quaternion": [0, 1, 0, 0]}}'
        % name
        for name in ("Gelenk-ä", "関節", "ok", "\\udcff")
    ]
    stream = io.BytesIO(("\n".join(lines) + "\n").encode())
    sniffed = jobscan.sniff(stream, "j.jsonl")
    with pytest.raises(InputFileError, match="lone surrogate"):
        list(jobscan.scan_blocks(jobscan.lines(stream, sniffed.name, sniffed.first), "j.jsonl", 8))
    assert [number for _, _, number, _ in calls] == [4]


def test_a_batch_that_cannot_write_leaves_no_helper(tmp_path):
    from click.testing import CliRunner

    from a2b.cli import cli

    jobs = tmp_path / "jobs.jsonl"
    jobs.write_bytes(_jobs_text(3000))
    result = CliRunner().invoke(cli, ["batch", str(jobs), "-o", str(tmp_path / "no" / "x.csv")])
    assert result.exit_code == 1 and "cannot write" in result.output
    _no_children_left()
