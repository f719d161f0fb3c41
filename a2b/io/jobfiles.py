"""Jobs files: many motions in one file, read in validated blocks (``a2b batch``).

A jobs file is a YAML or JSON list of job mappings (:data:`a2b.io.poseschema.JOB_KEYS`), or
JSON Lines with one per line. :func:`read_jobs` reads either; :meth:`Jobs.blocks` hands them
out as :class:`JobBlock` s whose poses are stacked and checked in bulk (:func:`finish_block`).
The common forms of a job take the fast path of :mod:`a2b.io.jobscan`; any other is read the
exact way of :mod:`a2b.io.poseschema`, which words the error. Both read the one schema.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass
from typing import IO

import numpy as np

from ..errors import A2bError, InputFileError
from .documents import Document, decode, gc_paused, parse, parse_json
from .jobscan import NUMBER_TYPES, Scanned, lines, scan_blocks, sniff
from .poseschema import JOB_KEYS, Job, describe, job_from_node

__all__ = ["JobBlock", "Jobs", "finish_block", "job_blocks", "json_line_job", "read_jobs"]


@dataclass
class JobBlock:
    """Consecutive jobs of a jobs file, validated, with their poses stacked.

    ``start`` and ``end`` are robotics matrices ``(n, 4, 4)``; ``modes``, ``samples``,
    ``parameters`` and ``names`` are lists of ``n`` entries, as the fields of :class:`Job`
    (``None`` where the file does not give one). ``checked``: every pose passed
    :func:`a2b.poses.check_matrices` (true for the blocks of a jobs file).
    """

    start: np.ndarray
    end: np.ndarray
    modes: list
    samples: list
    parameters: list
    names: list
    _jobs: list | None = None
    checked: bool = False

    def __len__(self) -> int:
        return len(self.modes)

    def job(self, i: int) -> Job:
        """Job ``i`` of the block (the object given to :meth:`from_jobs`, if any)."""
        if self._jobs is not None:
            return self._jobs[i]
        return Job(
            self.start[i],
            self.end[i],
            self.modes[i],
            self.samples[i],
            self.parameters[i],
            self.names[i],
        )

    def jobs(self) -> list[Job]:
        """The jobs one by one."""
        return [self.job(i) for i in range(len(self))]

    def split(self, n: int) -> tuple[JobBlock, JobBlock]:
        """The first ``n`` jobs and the rest."""

        def part(sl):
            return JobBlock(
                self.start[sl], self.end[sl], self.modes[sl], self.samples[sl],
                self.parameters[sl], self.names[sl], None if self._jobs is None else self._jobs[sl],
                self.checked,
            )  # fmt: skip

        return part(slice(None, n)), part(slice(n, None))

    @classmethod
    def concatenate(cls, blocks: list[JobBlock]) -> JobBlock:
        """One block of the jobs of ``blocks``, in order."""
        if len(blocks) == 1:
            return blocks[0]
        jobs = None
        if all(b._jobs is not None for b in blocks):
            jobs = [job for b in blocks for job in b._jobs]
        elif any(b._jobs is not None for b in blocks):
            jobs = [job for b in blocks for job in b.jobs()]
        return cls(
            np.concatenate([b.start for b in blocks]),
            np.concatenate([b.end for b in blocks]),
            [m for b in blocks for m in b.modes],
            [s for b in blocks for s in b.samples],
            [p for b in blocks for p in b.parameters],
            [n for b in blocks for n in b.names],
            jobs,
            all(b.checked for b in blocks),
        )

    @classmethod
    def from_jobs(cls, jobs: list[Job]) -> JobBlock:
        """A block of the given jobs. Poses that are no 4x4 arrays of numbers are stacked as
        NaN; :meth:`job` still returns them as given."""

        def stack(poses):
            out = np.full((len(poses), 4, 4), np.nan)
            for i, pose in enumerate(poses):
                try:
                    value = np.asarray(pose, dtype=float)
                except (ValueError, TypeError):
                    continue
                if value.shape == (4, 4):
                    out[i] = value
            return out

        return cls(
            stack([j.start for j in jobs]),
            stack([j.end for j in jobs]),
            [j.mode for j in jobs],
            [j.samples for j in jobs],
            [j.parameters for j in jobs],
            [j.name for j in jobs],
            list(jobs),
        )


@dataclass
class Jobs:
    """The jobs of a jobs file: iterate to validate and get them one by one, or take them in
    blocks (:meth:`blocks`); use one or the other.

    ``count`` is the number of jobs, or ``None`` for JSON Lines, which are read lazily.
    """

    count: int | None
    _iter: Iterator[Job]
    _blocks: Callable[[int], Iterator[JobBlock]] | None = None

    def __iter__(self) -> Iterator[Job]:
        return self._iter

    def blocks(self, size: int = 256) -> Iterator[JobBlock]:
        """The jobs in :class:`JobBlock` s of ``size`` (the last may be shorter).

        The same jobs and the same errors, raised at the same job, as iterating: a block holds
        the jobs before an invalid one, and the error comes when the next block is asked for.
        Blocks are read a block ahead at most, and validated in bulk: the poses of the
        common forms (quaternion and translation, robotics matrix) with array operations,
        anything else job by job.
        """
        if size < 1:
            raise ValueError(f"a block holds at least one job, got size {size}")
        if self._blocks is None:
            return job_blocks(self._iter, size)
        return self._blocks(size)


def job_blocks(jobs: Iterable[Job], size: int) -> Iterator[JobBlock]:
    """Any jobs in :class:`JobBlock` s of ``size``, taken from ``jobs`` a block at a time.

    An :class:`A2bError` while taking them (a lazily validated file) comes after a block of
    the jobs before it, as with :meth:`Jobs.blocks`.
    """
    block: list[Job] = []
    try:
        for job in jobs:
            block.append(job)
            if len(block) == size:
                yield JobBlock.from_jobs(block)
                block = []
    except A2bError:
        if block:
            yield JobBlock.from_jobs(block)
        raise
    if block:
        yield JobBlock.from_jobs(block)


def read_jobs(stream: IO, name: str | None = None) -> Jobs:
    """Read a jobs file: a YAML or JSON list of job mappings, or JSON Lines (one per line).

    A job has ``start``, ``end`` and optionally ``name``, ``mode``, ``samples`` and
    ``parameters``. JSON Lines are read line by line as the jobs are consumed, so a large file
    never sits in memory, and the error of a line comes as soon as the line arrives, after
    the jobs before it. A list is parsed and validated at once (the parsed tree is then
    dropped, before Python's cyclic collector would walk it); the error of an invalid job is
    raised when the jobs before it have been taken.
    """
    sniffed = sniff(stream, name)
    name, kind = sniffed.name, sniffed.kind
    if sniffed.json_lines:
        return _json_lines_jobs(lines(stream, name, sniffed.first), name)
    raw_start = sniffed.first
    with gc_paused():
        doc = parse(decode(raw_start + stream.read(), name), name, kind)
        if not isinstance(doc.data, list):
            hint = " (one motion: a2b interpolate)" if isinstance(doc.data, dict) else ""
            raise doc.error((), f"expected a list of jobs, got {describe(doc.data)}{hint}")
        if not doc.data:
            raise doc.error((), "expected a list of jobs, got an empty list")
        count = len(doc.data)
        block, error = _list_jobs(doc)
        del doc

    def jobs() -> Iterator[Job]:
        for i in range(len(block)):
            yield block.job(i)
        if error is not None:
            raise error

    def blocks(size: int) -> Iterator[JobBlock]:
        rest = block
        while len(rest):
            piece, rest = rest.split(size)
            yield piece
        if error is not None:
            raise error

    return Jobs(count, jobs(), blocks)


def _list_jobs(doc: Document) -> tuple[JobBlock, InputFileError | None]:
    """The jobs of a parsed list before the first invalid one, and that one's error."""
    builder = Scanned()
    for i, item in enumerate(doc.data):
        if not builder.add_fast(item, None, (doc, i, item)):
            try:
                job = job_from_node(doc, (i,), item, JOB_KEYS)
            except InputFileError as e:
                return _finished(builder, e)
            builder.add_job(job, (doc, i, item))
    return _finished(builder, None)


def _finished(builder: Scanned, error):
    """:func:`finish_block` as one block and the error that comes first."""
    blocks = []
    try:
        blocks.extend(finish_block(builder))
    except InputFileError as e:
        error = e
    if not blocks:
        empty = np.empty((0, 4, 4))
        return JobBlock(empty, empty, [], [], [], [], checked=True), error
    return blocks[0], error


def _json_lines_jobs(lines: Iterator[str], name: str) -> Jobs:
    def blocks(size: int) -> Iterator[JobBlock]:
        for scanned in scan_blocks(lines, name, size, json_line_job):
            yield from finish_block(scanned)

    return Jobs(None, _json_lines(lines, name), blocks)


def _json_lines(lines: Iterator[str], name: str) -> Iterator[Job]:
    index = 0
    for number, line in enumerate(lines, start=1):
        if not line.strip():
            continue
        yield json_line_job(line, name, number, index)
        index += 1
    if index == 0:
        raise InputFileError(f"{name}: no jobs: the file has no lines with a job")


def json_line_job(line: str, name: str, number: int, index: int) -> Job:
    """The job on line ``number`` of a JSON Lines file, the ``index``-th job, fully checked."""
    doc = parse_json(line.rstrip("\r\n"), name, first_line=number)  # an error at its end: here
    inner = doc.locate
    doc.locate = lambda path, _inner=inner: _inner(path[1:])  # the job index is the line
    return job_from_node(doc, (index,), doc.data, JOB_KEYS)


def _exact_job(where: tuple) -> Job:
    """The exact reading of a job that the bulk check did not accept: it raises the error."""
    if isinstance(where[0], str):
        return json_line_job(*where)
    doc, i, item = where
    return job_from_node(doc, (i,), item, JOB_KEYS)


def _poses(scanned: Scanned) -> tuple[np.ndarray, np.ndarray]:
    """The matrices of every slot, quaternion slots first, and which of them are valid."""
    from ..elements import unit_scale
    from ..poses import rotations_from_quaternions, valid_matrices

    q, m = _numbers_of(scanned.q, 7), _numbers_of(scanned.m, 16)
    q_ok, m_ok = q[1], m[1]
    q, m = q[0].reshape(-1, 7), m[0].reshape(-1, 4, 4)
    with np.errstate(all="ignore"):
        quat = unit_scale(q[:, :4])
        norm = np.linalg.norm(quat, axis=-1)
        q_ok &= np.isfinite(q).all(axis=1) & (norm != 0.0) & np.isfinite(norm)
        mats = np.zeros((len(q) + len(m), 4, 4))
        mats[: len(q), :3, :3] = rotations_from_quaternions(quat / norm[:, None])
        mats[: len(q), :3, 3] = q[:, 4:]
        mats[: len(q), 3, 3] = 1.0
        mats[len(q) :] = m
        m_ok &= valid_matrices(m)
    return mats, np.concatenate([q_ok, m_ok])


def finish_block(scanned: Scanned) -> Iterator[JobBlock]:
    """The :class:`JobBlock` of scanned jobs (none if there are none): their numbers checked
    in bulk; at a job they fail, read it the exact way, which raises its error after the block
    of the jobs before it."""
    n = len(scanned)
    if not n:
        return
    mats, ok = _poses(scanned)
    quaternions = len(scanned.q) // 7
    ok = np.append(ok, False)  # where the jobs read the exact way point
    starts, ends, modes, samples, parameters, names, where = map(list, zip(*scanned.records))

    def index(slots):
        arr = np.array([len(mats) if s is None else s for s in slots], dtype=np.intp)
        return np.where(arr >= 0, arr, quaternions + ~arr)

    start_at, end_at = index(starts), index(ends)
    mats = np.concatenate([mats, np.zeros((1, 4, 4))])
    start, end = mats[start_at], mats[end_at]

    def block(k: int) -> JobBlock:
        return JobBlock(
            start[:k], end[:k], modes[:k], samples[:k], parameters[:k], names[:k], checked=True
        )

    for i in np.flatnonzero(~(ok[start_at] & ok[end_at])).tolist():
        job = scanned.exact.get(i)
        if job is None:
            try:
                job = _exact_job(where[i])
            except InputFileError:
                if i:
                    yield block(i)
                raise
        start[i], end[i] = job.start, job.end
    yield block(n)


def _numbers_of(values: list, width: int) -> tuple[np.ndarray, np.ndarray]:
    """``values`` as a float array, and which groups of ``width`` are all ints and floats.

    A group with anything else (a bool, a string, ``None``, a YAML number that is no finite
    double) is zeroed and marked, as are all groups if an integer is beyond the doubles.
    """
    groups = len(values) // width
    ok = np.ones(groups, dtype=bool)
    if not NUMBER_TYPES.issuperset(map(type, values)):
        values = list(values)
        for g in range(groups):
            if not NUMBER_TYPES.issuperset(map(type, values[g * width : (g + 1) * width])):
                ok[g] = False
                values[g * width : (g + 1) * width] = [0.0] * width
    try:
        return np.array(values, dtype=float), ok
    except OverflowError:  # an integer beyond the doubles
        return np.zeros(len(values)), np.zeros(groups, dtype=bool)
