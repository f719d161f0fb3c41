"""Samples: consecutive poses of motions, on their way to a writer.

:class:`Samples` is the one container between the computing side (:func:`poses_of` of a
motion, :func:`a2b.jobs.sample`, :class:`a2b.resample.Resampler`) and the writers of
:mod:`a2b.io`. :func:`poses_of` is the one switch between the representations a format needs,
and :func:`check_finite` the one check that no sample overflowed.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from itertools import groupby, repeat

import numpy as np

from .errors import A2bError

__all__ = ["FIELDS", "JobRuns", "Samples", "check_finite", "poses_of"]

#: The pose fields of each representation, in the order the motion's method returns them.
FIELDS = {
    "quat_trans": ("quat_wxyz", "trans"),
    "matrices": ("matrices",),
    "study": ("study",),
}


class JobRuns:
    """A ``job`` column in runs: ``names[0]`` for ``counts[0]`` rows, then ``names[1]`` …

    Iterating gives the name of every row, as the list it stands for would.
    """

    __slots__ = ("counts", "names")

    def __init__(self, names: list[str], counts: list[int]):
        if len(names) != len(counts):
            raise ValueError(f"{len(names)} names for {len(counts)} runs")
        self.names = names
        self.counts = counts

    @classmethod
    def of(cls, job: Iterable[str]) -> JobRuns:
        """``job`` as runs (a :class:`JobRuns` is returned as it is)."""
        if isinstance(job, JobRuns):
            return job
        names, counts = [], []
        for name, run in groupby(job):
            names.append(name)
            counts.append(sum(1 for _ in run))
        return cls(names, counts)

    @classmethod
    def join(cls, parts: Iterable[JobRuns]) -> JobRuns:
        """The runs of ``parts`` one after the other."""
        names: list[str] = []
        counts: list[int] = []
        for part in parts:
            names += part.names
            counts += part.counts
        return cls(names, counts)

    def __len__(self) -> int:
        return sum(self.counts)

    def __iter__(self) -> Iterator[str]:
        for name, count in zip(self.names, self.counts):
            yield from repeat(name, count)

    def __repr__(self) -> str:
        return f"JobRuns({self.names!r}, {self.counts!r})"


@dataclass
class Samples:
    """Consecutive samples of one motion or of many (a batch). Only the pose fields of one
    representation are filled.

    ``t (n,)``: the first column of the CSV layouts (the motion's parameter, or a time in
    seconds); ``time (n,)``: seconds after ``origin_ns`` (an integer number of nanoseconds,
    0 by default) for the formats that write times, ``None``: ``t`` is the time. Stamps are
    formed as ``origin_ns + round(time · 1e9)`` (:meth:`nanoseconds`), so that a grid of times
    far from 0 keeps exact steps.
    ``quat_wxyz (n, 4)`` unit, continuous in t, and ``trans (n, 3)``; or ``matrices (n, 4, 4)``
    robotics layout; or ``study (n, 8)``. ``twist (n, 6)``: velocities ``vx vy vz wx wy wz``
    (columns after the pose in the CSV layouts, a ``TwistStamped`` in ros2). ``job`` names
    each row (batch: a list, or :class:`JobRuns`). ``original (n,)``: 1 where the row is a
    pose of a resampled trajectory, 0 where interpolated (a last column ``original``).
    ``stamps_ns (n,)``: the times as exact int64 nanoseconds, where the caller has them (the
    stamps of binary formats then come from here, not from the doubles). ``text``: the lines
    of a text format, ``(format, pieces)``, where the caller made them ahead
    (:func:`a2b.io.writers.chunk_text`) from the finished block; that format's writer writes
    them as they are, so no field may change after them.
    """

    t: np.ndarray
    quat_wxyz: np.ndarray | None = None
    trans: np.ndarray | None = None
    matrices: np.ndarray | None = None
    study: np.ndarray | None = None
    job: list[str] | JobRuns | None = None
    original: np.ndarray | None = None
    twist: np.ndarray | None = None
    time: np.ndarray | None = None
    origin_ns: int = 0
    stamps_ns: np.ndarray | None = None
    text: tuple[str, list] | None = None

    def seconds(self) -> np.ndarray:
        """The times in seconds (``t`` where no ``time`` is given), ``origin_ns`` added."""
        time = self.t if self.time is None else self.time
        return time + self.origin_ns * 1e-9 if self.origin_ns else time

    def nanoseconds(self) -> np.ndarray:
        """The times as integer nanoseconds: ``stamps_ns`` where the caller knows them exactly
        (a time grid, :meth:`a2b.resample.NewTimes.stamps_ns`), else ``origin_ns +
        round(time · 1e9)`` (int64); the limits of the format are checked before
        (:func:`a2b.output.check_times`)."""
        if self.stamps_ns is not None:
            return self.stamps_ns
        time = self.t if self.time is None else self.time
        return np.rint(np.asarray(time, float) * 1e9).astype(np.int64) + self.origin_ns


def poses_of(motion, ts: np.ndarray, representation: str) -> dict:
    """The poses of ``motion`` at ``ts`` in ``representation`` (a key of :data:`FIELDS`), as
    the pose fields of :class:`Samples`. ``motion`` is anything with the methods
    ``quat_trans``, ``matrices`` and ``study`` of ``ts`` (a motion, a segment table). The
    rows at t = 0 and 1 are a motion's end poses as it holds them (:func:`a2b.api.pin_ends`)."""
    if representation not in FIELDS:
        raise ValueError(f"unknown representation {representation!r}")
    from .api import pin_ends

    values = getattr(motion, representation)(ts)
    if not isinstance(values, tuple):
        values = (values,)
    return pin_ends(motion, ts, dict(zip(FIELDS[representation], values)))


def check_finite(samples: Samples, column: str = "t") -> None:
    """Raise :class:`A2bError` if a sample overflowed to NaN or infinity, naming it by its
    ``column`` value (and its job), so that it never reaches the output."""
    n = len(samples.t)
    for name in ("quat_wxyz", "trans", "matrices", "study", "twist"):
        values = getattr(samples, name)
        if values is None or np.isfinite(values).all():
            continue
        row = int(np.argmax(~np.isfinite(values.reshape(n, -1)).all(axis=1)))
        job = ""
        if samples.job is not None:
            job = f"job {list(JobRuns.of(samples.job))[row]}: "
        raise A2bError(
            f"{job}the sample at {column} = {float(samples.t[row]):.17g} is not finite: the "
            "motion overflows double precision; the poses or parameters are too large"
        )
