"""Many motions described as jobs, built block by block through the one motion core.

A job is a pair of poses with, optionally, a name, a mode, a sample count and parameters (see
``a2b batch --help``). :func:`sample` builds each block of jobs as a few batched motions, one
per kind of job (mode and the names of its parameters), with :func:`a2b.motion`, and samples
consecutive jobs of one kind and one sample count together. What a job gets (its samples, its
choices, its warnings, its error) is what the same motion gets built alone; errors and
warnings name the job (``job NAME: ...``), and the samples of every job before a failing one
are yielded before its error is raised.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable, Iterable, Iterator

import numpy as np

from .api import motion as build_motion
from .errors import A2bError, A2bWarning
from .motions.base import Motion, evenly_spaced
from .samples import JobRuns, Samples, check_finite, poses_of

#: Rows in one piece of samples: about 10 MB of CSV text.
PIECE_ROWS = 65536


def sample(
    blocks: Iterable,
    *,
    mode: str = "darboux",
    samples: int = 101,
    representation: str = "quat_trans",
    rows: int = PIECE_ROWS,
    report: Callable[[str, list], None] | None = None,
    advance: Callable[[int], None] | None = None,
    unique_names: bool = False,
) -> Iterator[Samples]:
    """Sample every job of ``blocks`` at evenly spaced t in [0, 1], in order.

    Parameters
    ----------
    blocks : iterable of job blocks
        Each with ``start``, ``end`` (stacked robotics matrices ``(J, 4, 4)``, valid) and the
        lists ``names``, ``modes``, ``samples``, ``parameters`` (``None`` where a job does not
        give one), as :class:`a2b.io.jobfiles.JobBlock`.
    mode, samples :
        For jobs that give none.
    representation : {"quat_trans", "matrices", "study"}
    rows : int
        The most rows of one :class:`a2b.samples.Samples`; memory is bounded by it and the
        block size.
    report : callable, optional
        ``report(name, choices)`` for every job, before its samples.
    advance : callable, optional
        ``advance(n)`` after the ``n`` jobs of each block.
    unique_names : bool
        Refuse a job whose name (given, or its index) an earlier job has, before the samples
        of its block: for outputs that keep each job under its name.

    Yields
    ------
    Samples
        ``t`` and the pose fields of ``representation``, ``job`` as :class:`JobRuns`; checked
        finite.
    """
    first = 0
    seen: set = set()
    for block in blocks:
        if unique_names:
            for i, name in enumerate(job_names(block.names, first)):
                if name in seen:
                    raise A2bError(
                        f"job {name!r} (job {first + i}): an earlier job has this name; "
                        "each job is written under its name, so names must differ"
                    )
                seen.add(name)
        yield from _block(block, first, mode, samples, representation, rows, report)
        first += len(block.names)
        if advance is not None:
            advance(len(block.names))


def _kind(mode: str, parameters: dict) -> tuple:
    """Jobs of one kind are built together: one mode, the same parameters given, one frame."""
    return (mode, tuple(sorted(parameters)), parameters.get("frame"))


#: The name of a job that has none: ``job`` and its index in the file (``job0``, ``job1``, …),
#: text that pandas' and polars' ``read_csv`` keep as text beside named jobs.
DEFAULT_NAME = "job{index}"


def job_names(names: list, first: int) -> list[str]:
    """The names of the jobs ``names`` (``None`` where a job has none) whose first is job
    ``first`` of the file: given, or :data:`DEFAULT_NAME`."""
    return [DEFAULT_NAME.format(index=first + i) if name is None else name
            for i, name in enumerate(names)]  # fmt: skip


def _block(block, first, mode, samples, representation, rows, report) -> Iterator[Samples]:
    count = len(block.names)
    names = job_names(block.names, first)
    modes = [m or mode for m in block.modes]
    counts = [s or samples for s in block.samples]
    kinds: dict = {}
    for i in range(count):
        kinds.setdefault(_kind(modes[i], block.parameters[i]), []).append(i)
    # Build every kind; where a job cannot be built, build again without it and the jobs after
    # it, so that the jobs before it are sampled before its error is raised.
    stop, failure = count, None
    while True:
        kinds = {k: [i for i in members if i < stop] for k, members in kinds.items()}
        kinds = {k: members for k, members in kinds.items() if members}
        built: dict = {}  # kind -> (motion, warnings by member)
        first_failure = None
        for kind, members in kinds.items():
            try:
                built[kind] = _build(block, kind, members)
            except A2bError as e:
                position = members[getattr(e, "index", 0)]
                if first_failure is None or position < first_failure[0]:
                    first_failure = (position, e)
        if first_failure is None:
            break
        failure = first_failure
        stop = failure[0]
    place = {}  # position -> (kind, index in its motion)
    for kind, members in kinds.items():
        for j, i in enumerate(members):
            if i < stop:
                place[i] = (kind, j)
    i = 0
    while i < stop:
        kind, j = place[i]
        motion, caught = built[kind]
        for message in caught.get(j, ()):
            warnings.warn(A2bWarning(f"job {names[i]}: {message}"), stacklevel=2)
        if report is not None:
            report(names[i], motion.notes.of(j))
        # consecutive jobs of this kind and sample count are sampled together
        last = i + 1
        while (
            last < stop
            and place[last][0] == kind
            and place[last][1] == j + (last - i)
            and counts[last] == counts[i]
            and not built[kind][1].get(place[last][1])
        ):
            if report is not None:
                report(names[last], motion.notes.of(place[last][1]))
            last += 1
        yield from _pieces(motion, j, j + last - i, names[i:last], counts[i], representation, rows)
        i = last
    if failure is not None:
        position, e = failure
        reason = getattr(e, "reason", str(e))
        raise type(e)(f"job {names[position]}: {reason}") from e


def _build(block, kind, members: list) -> tuple[Motion, dict]:
    """The motion of shape ``(len(members),)`` of jobs of one kind, and their warnings."""
    mode, keys, frame = kind
    index = np.asarray(members)
    parameters = {}
    for key in keys:
        values = [block.parameters[i][key] for i in members]
        if key == "frame":
            parameters[key] = frame
        elif key == "long_way":
            parameters[key] = np.array(values, dtype=bool)
        else:
            parameters[key] = np.array(values, dtype=float)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", A2bWarning)
        motion = build_motion(block.start[index], block.end[index], mode, **parameters)
    by_member: dict = {}
    for warning in caught:
        message = warning.message
        if isinstance(message, A2bWarning) and hasattr(message, "index"):
            by_member.setdefault(message.index, []).append(message.reason)
        else:
            warnings.warn_explicit(message, warning.category, warning.filename, warning.lineno)
    return motion, by_member


def _pieces(motion: Motion, lo: int, hi: int, names, count, representation, rows):
    """Samples of jobs ``lo:hi`` of ``motion``, each at ``count`` samples, checked finite."""
    if count > rows:  # one long job streams in pieces
        for j, name in zip(range(lo, hi), names):
            single = motion[j]
            for ts in evenly_spaced(count, rows):
                yield _checked(single, ts, ts, representation, [name], [len(ts)])
        return
    ts = next(evenly_spaced(count, count))
    per_piece = max(1, rows // count)
    for start in range(lo, hi, per_piece):
        stop = min(start + per_piece, hi)
        part = names[start - lo : stop - lo]
        tiled = np.tile(ts, stop - start)
        yield _checked(motion[start:stop], ts, tiled, representation, part, [count] * len(part))


def _checked(motion: Motion, ts, tiled, representation: str, names, counts) -> Samples:
    """The samples of ``motion`` (shape ``()`` or ``(J,)``) at ``ts`` as rows, checked finite."""
    poses = poses_of(motion, ts, representation)
    lead = len(motion.shape) + 1
    rows = {key: array.reshape((-1,) + array.shape[lead:]) for key, array in poses.items()}
    samples = Samples(tiled, job=JobRuns(list(names), list(counts)), **rows)
    check_finite(samples)
    return samples
