"""``a2b resample``: a whole trajectory at new times, one motion per segment (or a spline)."""

from __future__ import annotations

from collections import Counter
from functools import partial

import click

from . import CONTEXT_SETTINGS, options, writing


@click.command(context_settings=CONTEXT_SETTINGS)
@click.argument("trajectory", type=options.TRAJECTORY)
@options.trajectory_input_options()
@click.option(
    "--rate",
    type=options.PositiveFloat(),
    help="New times every 1/HZ s from the first pose's time.",
    metavar="HZ",
)
@click.option(
    "--at",
    "reference",
    type=options.TRAJECTORY,
    metavar="REFERENCE",
    help="New times: the stamps of another trajectory file (any input format).",
)
@click.option(
    "--times",
    "times_file",
    type=options.INPUT,
    metavar="FILE",
    help="New times: a text file with one time (s) per line; # starts a comment.",
)
@click.option(
    "--mode",
    type=click.Choice(("screw", "darboux", "cubic", "spline")),
    help="screw (ScLERP, default), darboux or cubic per segment (with the motion options "
    "below, the same for every segment), or spline: the C¹ spline through all poses (unit "
    "Study vectors).",
)
@click.option(
    "--clip",
    is_flag=True,
    help="Drop new times outside the trajectory (and count them) instead of failing.",
)
@click.option(
    "--max-gap",
    type=options.PositiveFloat(),
    metavar="S",
    help="Do not bridge segments longer than S seconds: drop the new times inside them (and "
    "count them).",
)
@click.option(
    "--mark",
    is_flag=True,
    help="csv, matrix, study: add a last column 'original', 1 where the row is a pose of "
    "TRAJECTORY, 0 where it is interpolated.",
)
@options.motion_parameter_options
@writing.output_option
@writing.format_option(durations=False)
@writing.frame_options
@options.verbose_option
def command(trajectory, input_format, topic, input_child_frame, input_frame, input_rate,
            orthonormalize, rate, reference, times_file, mode, clip, max_gap, mark, output, fmt,
            profile, storage, frame_id, child_frame_id, verbose, **parameters):  # fmt: skip
    """Sample TRAJECTORY (a file, a ROS 2 bag folder, or - for stdin) at new times.

    TRAJECTORY is TUM, KITTI, EuRoC, a2b's csv, matrix or study output, MCAP with
    foxglove.PoseInFrame or FrameTransform (JSON) or ROS 2 PoseStamped, TFMessage, Odometry
    or Path (CDR), or a ROS 2 bag of those (a folder with metadata.yaml, or a .db3); the
    format comes from --input-format, the suffix or the content. Its times must increase.

    The new times come from exactly one of --rate, --at and --times. A time in the segment
    between two neighbouring poses is the pose of that segment's motion, at the fraction of
    the segment's duration that has passed; a time equal to a stamp gives that pose exactly,
    as the file holds it. Times outside the trajectory are an error (a2b does not
    extrapolate) unless --clip drops them. Output formats as for `a2b interpolate`; the
    `t` column and the TUM and MCAP stamps are the new times in seconds. Everything is
    written as it is computed, in bounded memory.

    \b
    Example:
      a2b resample samples/estimate.tum --at samples/reference.tum --clip -o estimate.tum
      a2b resample samples/walk.kitti --orthonormalize --input-rate 5 --rate 30 --format tum
      a2b resample samples/reference.tum --times samples/stamps.txt --mode spline --mark
      a2b resample samples/reference.tum --rate 100 --max-gap 0.5 -o reference-100hz.mcap
    """
    from ..io.trajectories import opened, trajectory_pieces

    sources = (("--rate", rate), ("--at", reference), ("--times", times_file))
    given = [name for name, value in sources if value is not None]
    if len(given) != 1:
        raise click.UsageError(
            "give the new times with exactly one of --rate, --at and --times"
            + (f" (got {' and '.join(given)})" if given else "")
        )
    choices: list[str] = []
    name, data, in_fmt = opened(trajectory, None, input_format)
    if input_format is None:
        choices.append(f"input format {in_fmt}: from the file (--input-format to change)")
    if in_fmt == "kitti" and input_rate is None:
        choices.append("kitti times: the line indices 0, 1, 2, … (--input-rate to change)")
    if mode is None:
        mode = "screw"
        choices.append("mode screw: the default of resample, ScLERP per segment (--mode to change)")
    given = {key: value for key, value in parameters.items() if value is not None}
    if given and mode == "spline":
        raise click.UsageError(
            "the spline takes no motion parameters; give --mode darboux or cubic"
        )
    options.refuse_foreign_parameters(mode, given)
    parameters = options.merge_parameters({}, given) if given else {}
    from ..formats import BY_NAME
    from ..output import check_plan, text_ahead, write_samples

    fmt = BY_NAME[writing.format_from(fmt, output, choices, profile)]
    if mark and "mark" not in fmt.holds:
        takes = ", ".join(row.name for row in BY_NAME.values() if "mark" in row.holds)
        raise click.UsageError(f"--mark adds a column to {takes}, not to {fmt.name}")
    frames = writing.refuse_defaults(fmt, {"frame_id": frame_id, "child_frame_id": child_frame_id})
    new_times = _new_times(rate, reference, times_file, choices)
    check_plan(fmt, output, 2, 0.0, 1.0)
    if new_times.times is not None and len(new_times.times):
        from ..output import check_times

        # the latest time is known: refused before a byte is written, into a pipe too
        check_times(fmt, 0.0, max(float(new_times.times[-1]), 0.0))
    pieces = trajectory_pieces(data, name, in_fmt, rate=input_rate, topic=topic,
                               child_frame=input_child_frame, input_frame=input_frame, mode=mode,
                               orthonormalize=orthonormalize, choices=choices,
                               **({"size": len(data) + 1} if mode == "spline" else {}))  # fmt: skip
    if input_frame is not None:  # one piece: its TF chain stated with the other choices
        pieces = list(pieces)
        choices.extend(pieces[0].notes)
    run = _Run(name, mode, max_gap, clip, mark, parameters, stamps=fmt.binary, text=text_ahead(fmt))
    options.state_choices(choices, verbose)
    frames.update({"storage": storage} if storage is not None else {})
    stated = {"mode": mode, **parameters}
    write_samples(run.samples(pieces, new_times, fmt.representation), output, fmt,
                  motion=stated, **frames)  # fmt: skip
    _report(run.counts, run.made, run.repaired, new_times.described(), clip, max_gap, verbose)


class _Run:
    """The samples of a resampling, as the trajectory is parsed, and what was counted;
    ``stamps``: with their exact integer nanoseconds (for binary formats; text formats write
    the times); ``text``: what makes the lines of a text output with each block's samples, in
    the same task (:func:`a2b.output.text_ahead`), or ``None``."""

    def __init__(self, name, mode, max_gap, clip, mark, parameters, stamps=True, text=None):
        self.name, self.mode, self.max_gap, self.clip, self.mark = name, mode, max_gap, clip, mark
        self.parameters, self.stamps, self.text = parameters, stamps, text
        self.counts = {"outside": 0, "gap": 0, "written": 0, "poses": 0, "built": 0, "warned": 0}
        self.made, self.repaired = Counter(), []

    def samples(self, pieces, new_times, representation):
        """The samples at the new times, block by block, in order: each made on the writers'
        threads (:func:`a2b.io.parallel.in_order`) and counted here."""
        from ..io.parallel import in_order

        counts, last = self.counts, None
        sample = partial(self._sampled, representation, new_times)
        blocks = self._blocks(pieces, new_times)
        for samples, located, built, resampler in in_order(sample, blocks, eager=True):
            if resampler is not last:  # the first block of a window
                self._ended(last)
                resampler.warned, last = counts["warned"], resampler  # ten shown in the run
            resampler.account(built)
            counts["outside"] += located.outside
            counts["gap"] += located.gap
            counts["written"] += len(located.times)
            yield samples
        self._ended(last)

    def _blocks(self, pieces, new_times):
        """Each piece of the trajectory, with the last pose of the piece before, is a window
        of segments, and the new times up to its end go through its resampler: ``(resampler,
        block)``, parsed here while the blocks before are sampled (a spline needs every pose
        first: one window)."""
        from ..errors import InputFileError
        from ..resample import Resampler, windows

        resampler = None
        for window in windows(pieces, self.repaired):
            self.counts["poses"] = window["last"]
            if window["last"] < 2:
                continue  # a first piece of one pose: it is the start of the next window
            first = window.pop("last") - len(window["times"])  # the number of its first pose
            resampler = Resampler(mode=self.mode, max_gap=self.max_gap, checked=True, **window,
                                  first=first, **self.parameters)  # fmt: skip
            for block in new_times.upto(float(window["times"][-1]), float(window["times"][0])):
                yield resampler, block
        if resampler is None:
            raise InputFileError(f"{self.name}: expected at least 2 poses, got "
                                 f"{self.counts['poses']}")  # fmt: skip
        for block in new_times.upto(None, None):  # after the end: outside the trajectory
            yield resampler, block

    def _ended(self, resampler) -> None:
        """Count what ``resampler``, done with its window, built and chose."""
        if resampler is not None:
            self.counts["built"] += resampler.segments_built
            self.counts["warned"] = resampler.warned
            self.made.update(resampler.choices)

    def _sampled(self, representation, new_times, item):
        """The samples at the new times of ``item`` (``(resampler, block)``), with their exact
        nanosecond stamps if asked; where they are, what
        :meth:`a2b.resample.Resampler.account` takes, and the resampler (on any thread)."""
        from ..samples import FIELDS, Samples

        resampler, block = item

        located = resampler.locate(block, self.clip)
        values, built = resampler.sample_apart(located, representation)
        stamps = new_times.stamps_ns(located.times) if self.stamps else None
        samples = Samples(located.times, stamps_ns=stamps)
        for key, value in zip(FIELDS[representation], values if isinstance(values, tuple)
                              else (values,)):  # fmt: skip
            setattr(samples, key, value)
        if self.mark:
            samples.original = (located.pose >= 0).astype(float)
        if self.text is not None:
            self.text(samples)
        return samples, located, built, resampler


def _new_times(rate, reference, times_file, choices):
    """The new times (:class:`a2b.resample.NewTimes`): every 1/rate s, or a file's."""
    from ..errors import InputFileError
    from ..resample import NewTimes

    if rate is not None:
        return NewTimes(rate=rate)
    if reference is not None:
        from ..io.trajectories import read_trajectory

        path = read_trajectory(reference, orthonormalize=True, choices=choices)  # its stamps
        if path.fmt == "kitti":
            raise click.UsageError(
                "--at needs a reference with time stamps; KITTI files have none (use --rate)"
            )
        times = path.times
        if not len(times):
            raise InputFileError(f"{path.name}: the reference has no poses")
    else:
        from ..io.textrows import read_times

        times = read_times(times_file)
    from ..io.documents import stream_name

    return NewTimes(times=times, source=stream_name(reference or times_file, None))


def _report(counts, made, repaired, times, clip, max_gap, verbose) -> None:
    """Say what was dropped (always: data was left out) and, with -v, what was built."""
    from ..resample import WARNINGS_SHOWN, unshown

    warned, built = counts["warned"], counts["built"]

    if counts["outside"]:
        click.echo(
            f"Dropped {_times(counts['outside'])} outside the trajectory (--clip).", err=True
        )
    if counts["gap"]:
        click.echo(
            f"Dropped {_times(counts['gap'])} inside segments longer than --max-gap {max_gap:g} s.",
            err=True,
        )
    if warned > WARNINGS_SHOWN:
        click.echo(f"Warning: {unshown(warned)}.", err=True)
    if verbose:
        click.echo(
            f"Wrote {counts['written']} poses ({times}); built {built} segment motions.",
            err=True,
        )
        if repaired:
            message = options.repaired(counts["poses"], max(repaired), "rotation block")
            click.echo(f"  • {message}", err=True)
        for choice, count in made.most_common(20):
            click.echo(f"  • {count} segment(s): {choice}", err=True)


def _times(count: int) -> str:
    return f"{count} time{'s' * (count != 1)}"
