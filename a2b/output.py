"""The writing pipeline: samples of a motion, checked, into a file that appears whole or not at
all.

:func:`write` is the library's way to write what the commands write, with the same checks,
atomicity and streaming: it takes a motion (sampled at evenly spaced t), a timed motion
(sampled at times) or :class:`a2b.samples.Samples`, and a path or a binary stream. The
formats, their writers and their limits come from :mod:`a2b.formats`. Nothing here prints.

>>> import a2b, numpy as np
>>> motion = a2b.motion(np.eye(4), np.eye(4))
>>> a2b.write(motion, "motion.tum", samples=11)  # doctest: +SKIP
"""

from __future__ import annotations

import math
import os
import sys
from collections.abc import Callable, Iterable, Iterator

import numpy as np

from .errors import A2bError, OptionError, ParameterError
from .formats import BY_NAME, FRAME_OPTIONS, OUTPUT_NAMES, Format, from_suffix, resolve
from .samples import Samples, check_finite, poses_of

__all__ = [
    "CHUNK_SAMPLES",
    "check_plan",
    "check_times",
    "format_of",
    "motion_statement",
    "text_ahead",
    "write",
    "write_samples",
]

#: Samples per chunk: about 10 MB of text for ``csv``.
CHUNK_SAMPLES = 65536
#: The storages of a ROS 2 bag (``--storage``) and, for each that is not the format's own
#: (``mcap``: the MCAP file of the ``ros2`` writer), its writers of one motion and of a batch
#: (``sqlite3``: a rosbag2 bag folder).
STORAGES = {
    "mcap": None,
    "sqlite3": ("a2b.io.writers:write_sqlite_bag", "a2b.io.writers:write_batch_sqlite_bag"),
}


def format_of(fmt: str | None, target=None, batch: bool = False) -> tuple[Format, str | None]:
    """The :class:`a2b.formats.Format` of ``fmt``, else the one the suffix of ``target`` names,
    else ``csv``; and the choice made, in words (``None`` if ``fmt`` was given)."""
    if fmt is not None:
        if fmt not in BY_NAME or BY_NAME[fmt].writer is None:
            raise OptionError(f"unknown output format {fmt!r}; expected one of "
                              f"{', '.join(OUTPUT_NAMES)}")  # fmt: skip
        return BY_NAME[fmt], None
    named = from_suffix(target, batch) if isinstance(target, (str, os.PathLike)) else None
    if named is not None:
        return BY_NAME[named[0]], f"format {named[0]}: from the -o suffix {named[1]}"
    return BY_NAME["csv"], "format csv: the default"


def check_times(fmt: Format, first: float, last: float, count: int | None = None) -> None:
    """Refuse times from ``first`` to ``last`` seconds, or ``count`` messages, that ``fmt``
    cannot hold (:class:`a2b.formats.Limits`): the one check of each limit."""
    limits = fmt.limits
    if limits.max_messages is not None and count is not None and count > limits.max_messages:
        raise ParameterError(
            f"MCAP numbers messages with 32-bit sequence numbers: at most 2**32 = "
            f"{limits.max_messages} samples, got {count}"
        )
    if limits.max_nanoseconds is None:
        return
    if not (math.isfinite(first) and math.isfinite(last)) or (limits.non_negative and first < 0):
        what, bad = ("earliest", first) if not first >= 0 else ("latest", last)
        raise ParameterError(
            f"MCAP times must be finite and not negative; the {what} time is {bad:g} s"
        )
    if not last * 1e9 < limits.max_nanoseconds:
        raise ParameterError(
            f"MCAP log times are nanoseconds below 2**63 (the year 2262); the latest time is "
            f"{last:g} s"
        )
    if limits.stamps is not None:
        resolve(limits.stamps)(np.array([round(last * 1e9)], np.int64))


def check_plan(fmt: Format, target, count: int, first: float, span: float) -> None:
    """Refuse, before writing anything, what ``fmt`` cannot hold: ``count`` samples from
    ``first`` to ``first + span`` seconds, or binary output on a terminal."""
    if fmt.binary and _is_stdout(target) and sys.stdout is not None and sys.stdout.isatty():
        raise OptionError(
            f"{fmt.name} is binary: write it with -o FILE or into a pipe, not to a terminal"
        )
    if not fmt.timed:
        return
    last = first + span
    if not math.isfinite(last):
        raise ParameterError(
            f"the time of t = 1, duration + start_time = {span:g} + {first:g}, overflows a double"
        )
    if fmt.limits.distinct_times:
        step = (last - first) / max(count - 1, 1)
        resolution = float(np.spacing(max(abs(first), abs(last))))
        if not step > resolution:
            raise ParameterError(
                f"consecutive {fmt.name} times would differ by {step:.3g} s, which a double near "
                f"{max(abs(first), abs(last)):g} s cannot tell apart (its resolution there is "
                f"{resolution:.3g} s): the time stamps would repeat; give a smaller --start-time "
                "or fewer samples"
            )
    check_times(fmt, first, last, count)


def _is_stdout(target) -> bool:
    return target is None or str(target) == "-" or target is getattr(sys.stdout, "buffer", None)


def motion_samples(
    motion, count: int, representation: str, duration: float = 1.0, start_time: float = 0.0
) -> Iterator[Samples]:
    """``motion`` at ``count`` evenly spaced t in [0, 1], a chunk at a time;
    the time of t is ``t · duration + start_time`` seconds, and t = 0, 1 give A and B."""
    from .motions.base import evenly_spaced

    for ts in evenly_spaced(count, CHUNK_SAMPLES):
        samples = Samples(ts, **poses_of(motion, ts, representation))
        yield from stamped([samples], duration, start_time)


def stamped(samples: Iterable[Samples], duration: float, start_time: float) -> Iterator[Samples]:
    """``samples`` of t in [0, 1] with their times: ``t · duration + start_time`` seconds."""
    for block in samples:
        block.time = block.t * duration + start_time
        yield block


def timed_samples(
    timed, times, representation: str, velocities: bool = False, start_time: float = 0.0
) -> Iterator[Samples]:
    """The timed motion ``timed`` at ``times`` (seconds from its start), a chunk at a time:
    ``t`` and the time are ``start_time + time``; with ``velocities`` the twist of the law's
    point; the rows at its start and end are A and B (:func:`a2b.samples.poses_of`).

    ``times`` is an array, or an iterable of arrays (blocks of a time grid, such as
    :meth:`a2b.timelaw.grid.TimeGrid.blocks` gives): they are taken as they come.
    """
    blocks = (
        (times[lo : lo + CHUNK_SAMPLES] for lo in range(0, len(times), CHUNK_SAMPLES))
        if isinstance(times, np.ndarray)
        else times
    )
    for block in blocks:
        ts, twists = timed.sample(block, velocities)
        stamped = block + start_time
        samples = Samples(stamped, twist=twists, **poses_of(timed.motion, ts, representation))
        yield samples


def _options(fmt: Format, options: dict) -> dict:
    """The writer's keyword arguments from ``options``; an option given (not ``None``) that
    ``fmt`` does not take is refused."""
    refused = [k for k, v in options.items() if v is not None and k not in fmt.options]
    if refused:
        names = ", ".join("--" + k.replace("_", "-") for k in refused)
        raise OptionError(f"{names}: not for {fmt.name} output")
    return {k: v for k, v in options.items() if v is not None and k in FRAME_OPTIONS}


def write_samples(
    samples: Iterable[Samples], target, fmt: Format, *, batch: bool = False, **options
) -> None:
    """Write ``samples`` in ``fmt`` to ``target`` (a path, ``-`` or a binary stream) through
    :func:`a2b.io.atomic.atomic_output` (a batch of ``files``: :func:`a2b.io.atomic.
    atomic_directory`): a failure leaves no partial file and an older one as it was. Each
    block's times are checked against the format's limits as it comes.

    ``options``: ``frame_id``, ``child_frame_id`` (refused for formats without frames),
    ``count``, the number of samples if known, ``storage`` (``ros2``: ``mcap``, the
    default, or ``sqlite3``: a rosbag2 bag folder, :data:`STORAGES`), and ``motion``, what to
    state about the motion in the file's metadata (:func:`motion_statement`), given to the
    writers of formats that take it (``motion`` in their options: ``parquet``), else dropped.
    """
    from .io.atomic import atomic_directory, atomic_output

    count = options.pop("count", None)
    motion = options.pop("motion", None)
    storage = options.pop("storage", None)
    keywords = _options(fmt, {**options, "storage": storage})
    if storage is not None and storage not in STORAGES:
        raise OptionError(f"--storage {storage!r:.40}: expected one of {', '.join(STORAGES)}")
    if STORAGES.get(storage) is not None:
        return _write_bag(samples, target, fmt, storage, batch, keywords)
    if batch:
        writer = resolve(fmt.batch_writer)
        keywords = {"fmt": fmt.name, **{k: v for k, v in keywords.items() if k == "frame_id"}}
    else:
        writer = resolve(fmt.writer)
        keywords = {**fmt.writer_options, **keywords}
        if "count" in fmt.writer_options:
            keywords["count"] = count
    if motion is not None and "motion" in fmt.options:
        keywords["motion"] = motion
    stream = _checked(samples, fmt, batch)
    try:
        if hasattr(target, "write"):
            writer(target, stream, **keywords)
            return
        opened = atomic_directory if batch and fmt.batch == "files" else atomic_output
        with opened(target) as out:
            writer(out, stream, **keywords)
    finally:
        stream.close()


def _write_bag(samples, target, fmt: Format, storage: str, batch: bool, keywords: dict) -> None:
    """:func:`write_samples` into a bag folder of ``storage`` (:data:`STORAGES`)."""
    if hasattr(target, "write") or _is_stdout(target):
        raise OptionError(f"--storage {storage} writes a bag folder: give its path with -o FOLDER")
    single, many = STORAGES[storage]
    if batch:
        keywords = {k: v for k, v in keywords.items() if k == "frame_id"}
    stream = _checked(samples, fmt, batch)
    try:
        resolve(many if batch else single)(target, stream, **keywords)
    finally:
        stream.close()


def text_ahead(fmt: Format) -> Callable[[Samples], None] | None:
    """For a text table (a format with a ``separator``), what makes a block's lines where its
    samples are made, into :attr:`a2b.samples.Samples.text`: for a producer whose blocks are
    made on the writers' threads (``a2b resample``), so that formatting follows sampling in one
    task (:func:`a2b.io.writers.chunk_text`). Call it on the finished block: nothing may change
    its samples after. ``None`` for the other formats, which the writer formats itself."""
    if fmt.separator is None:
        return None
    from .io.writers import chunk_text

    def make(samples: Samples) -> None:
        samples.text = chunk_text(fmt.name, samples)

    return make


def _checked(samples: Iterable[Samples], fmt: Format, batch: bool) -> Iterator[Samples]:
    """``samples``, each block checked finite (named by ``t``, or by ``time`` where ``t`` is the
    time) and its times and the count so far (of one stream: not a batch, whose jobs are
    counted apart) checked against the limits of ``fmt``."""
    written = 0
    try:
        for block in samples:
            check_finite(block, "t" if block.time is not None else "time")
            written += len(block.t)
            if fmt.limits.max_nanoseconds is not None and len(block.t):
                seconds = block.seconds()
                count = None if batch else written
                check_times(fmt, float(seconds.min()), float(seconds.max()), count)
            yield block
    finally:
        if hasattr(samples, "close"):
            samples.close()


def write(
    source,
    target="-",
    format: str | None = None,
    *,
    samples: int | None = None,
    rate: float | None = None,
    dt: float | None = None,
    velocities: bool = False,
    duration: float | None = None,
    start_time: float | None = None,
    frame_id: str | None = None,
    child_frame_id: str | None = None,
    storage: str | None = None,
    choices: list | None = None,
) -> None:
    """Write a motion, a timed motion or samples to ``target`` in ``format``, checked and whole.

    Parameters
    ----------
    source : Motion, TimedMotion, Samples or iterable of Samples
        A motion (:func:`a2b.motion`, :func:`a2b.bezier`, :func:`a2b.spline`) is sampled at
        ``samples`` evenly spaced t in [0, 1] (default 101); a timed motion
        (:func:`a2b.timing`) at ``samples`` evenly spaced times, or every ``dt`` (``1 /
        rate``) seconds and its end; samples are written as they are.
    target : path, ``"-"`` (standard output) or binary stream
        A path is written to a temporary file renamed into place when complete; a stream is
        written and not closed.
    format : str, optional
        A name of :data:`a2b.formats.OUTPUT_NAMES`; default from the suffix of ``target``
        (``.mcap``, ``.tum``, ``.kitti``), else ``csv``.
    duration, start_time : float, optional
        Formats with times, a motion: the time of t is ``t · duration + start_time`` s
        (defaults 1 and 0); a timed motion: ``start_time`` is the time of its start.
    frame_id, child_frame_id : str, optional
        MCAP formats: the fixed and the moving frame (defaults ``world`` and ``a2b``).
    storage : str, optional
        ``ros2``: ``mcap`` (the default: one MCAP file) or ``sqlite3`` (a rosbag2 bag folder
        with a ``.db3`` and ``metadata.yaml``; ``target`` is the folder).
    velocities : bool
        A timed motion into csv, matrix, study or ros2: the twist of its point, per second.
    choices : list, optional
        The choices made (the format), in words, appended.

    Raises
    ------
    OptionError
        An option that does not apply to the format or the source.
    A2bError
        A sample that is not finite, times or counts the format cannot hold, a target that
        cannot be written. Nothing is left behind.
    """
    fmt, chosen = format_of(format, target)
    if chosen is not None and choices is not None:
        choices.append(chosen)
    frames = {"frame_id": frame_id, "child_frame_id": child_frame_id, "storage": storage}
    _options(fmt, frames)
    start = start_time or 0.0
    if isinstance(source, Samples):
        source = [source]
    if hasattr(source, "profile") and hasattr(source, "sample"):  # a timed motion
        if duration is not None:
            raise OptionError("--duration: a timed motion has its own duration")
        grid = _grid(source, samples, rate, dt)
        return write_timed(source, grid, target, fmt, velocities, start, **frames)
    if rate is not None or dt is not None or velocities:
        raise OptionError("rate, dt and velocities are for a timed motion (a2b.timing)")
    if hasattr(source, "quat_trans"):  # a motion
        _options(fmt, {"duration": duration, "start_time": start_time})
        count = 101 if samples is None else samples
        return write_motion(source, count, target, fmt, duration or 1.0, start, **frames)
    if samples is not None or duration is not None or start_time is not None:
        raise OptionError("samples, duration and start_time are for a motion, not for samples")
    write_samples(iter(source), target, fmt, **frames)


def _grid(timed, samples, rate, dt):
    if sum(x is not None for x in (samples, rate, dt)) > 1:
        raise OptionError("give one of samples, rate and dt")
    if rate is None and dt is None:
        return timed.grid(samples=101 if samples is None else samples)
    return timed.grid(rate=rate, dt=dt)


def write_motion(motion, count: int, target, fmt: Format, duration: float = 1.0,
                 start_time: float = 0.0, **frames) -> None:  # fmt: skip
    """``motion`` at ``count`` evenly spaced t in [0, 1], into ``target`` (:func:`write`)."""
    _check_count(count)
    check_plan(fmt, target, count, start_time, duration)
    chunks = motion_samples(motion, count, fmt.representation, duration, start_time)
    statement = motion_statement(fmt, motion, samples=count, duration=duration,
                                 start_time=start_time)  # fmt: skip
    write_samples(chunks, target, fmt, count=count, motion=statement, **frames)


def write_timed(timed, grid, target, fmt: Format, velocities: bool = False,
                start_time: float = 0.0, **frames) -> None:  # fmt: skip
    """The timed motion at the times of ``grid`` (a :class:`a2b.timelaw.TimeGrid` of seconds
    from its start, taken block by block, so any count streams in bounded memory) into
    ``target`` (:func:`write`); the time column and stamps are ``start_time + time``."""
    if velocities and "velocities" not in fmt.holds:
        takes = ", ".join(row.name for row in BY_NAME.values() if "velocities" in row.holds)
        raise OptionError(f"--velocities: {fmt.name} has no velocity field; use {takes}")
    last = float(grid.offsets(grid.count - 1, grid.count)[0])
    check_plan(fmt, target, grid.count, start_time, last or 1.0)
    blocks = (offsets for _, offsets in grid.blocks(CHUNK_SAMPLES))
    chunks = timed_samples(timed, blocks, fmt.representation, velocities, start_time)
    statement = motion_statement(fmt, timed.motion, samples=grid.count, start_time=start_time,
                                 time_law=timed.describe())  # fmt: skip
    write_samples(chunks, target, fmt, count=grid.count, motion=statement, **frames)


def motion_statement(fmt: Format, motion, **more) -> dict | None:
    """What a file of ``fmt`` states about ``motion`` in its metadata (``parquet``:
    ``a2b.motion``): the motion's ``describe()`` (its mode, the parameters given and those
    chosen, the axis …) and ``more`` (samples, duration, …); ``None`` for a format that holds
    no such statement, so that nothing is computed for it."""
    if "motion" not in fmt.options:
        return None
    describe = getattr(motion, "describe", None)
    stated = describe() if describe is not None else {"mode": getattr(motion, "mode", None)}
    return {**stated, **more}


def _check_count(count: int) -> None:
    from .names import MAX_SAMPLES, MIN_SAMPLES

    if not isinstance(count, (int, np.integer)) or not MIN_SAMPLES <= count <= MAX_SAMPLES:
        raise A2bError(f"samples must be a whole number from 2 to 2**53, got {count!r}")
