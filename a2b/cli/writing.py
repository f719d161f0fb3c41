"""The options of the commands that write samples (``interpolate``, ``bezier``, ``spline``,
``batch``, ``resample``): ``-o``, ``--samples``, ``--format`` and ``--profile`` (from the table
of :mod:`a2b.formats`), the times and frames of the formats that hold them, and the last step,
which hands the motion to the library's pipeline (:mod:`a2b.output`).

Only click is imported here, as in :mod:`a2b.cli.options`.
"""

from __future__ import annotations

import click

from .. import formats
from ..formats import FRAME_OPTIONS
from ..names import MAX_SAMPLES, MIN_SAMPLES
from .options import (
    FLOAT,
    TIME_LAW_OPTIONS,
    Count,
    PositiveFloat,
    pick,
    state_choices,
    time_law,
    verbose_option,
)


def output_option(f=None, *, directory: bool = False):
    """``-o/--output``; with ``directory``, also a directory (batch files of one per job).
    ``@output_option`` or ``@output_option(directory=True)``."""
    if f is None:
        return lambda g: output_option(g, directory=directory)
    where = (
        "; a format of a file per job needs a directory, made if missing"
        if directory
        else "; a device or named pipe is written directly"
    )
    return click.option(
        "-o",
        "--output",
        type=click.Path(allow_dash=True, dir_okay=directory),
        default="-",
        show_default=True,
        help="Where to write; '-' is standard output. A file is written to a temporary file and "
        f"renamed into place when complete{where}.",
    )(f)


samples_option = click.option(
    "--samples",
    type=Count(min=MIN_SAMPLES, max=MAX_SAMPLES),
    help="Number of samples, t evenly spaced in [0, 1], written as they are computed "
    "(any number streams in bounded memory)  [default: the file's samples, else 101]",
)


def format_help(batch: bool = False, durations: bool = True) -> str:
    """The help of ``--format``, one entry per format a command writes (:mod:`a2b.formats`):
    its layout; for ``batch``, how a batch lays the jobs out."""
    if not batch:
        entries = [f"{row.name}: {row.described(durations)}" for row in formats.TABLE if row.writer]
        suffixes = ", ".join(formats.suffix_names())
        default = f"[default: from the -o suffix ({suffixes}), else csv]"
        return f"Output format. {'; '.join(entries)}  {default}"
    layouts = {
        "rows": "one file, the job column first (layouts as for a2b interpolate)",
        "files": "a file per job, DIR/NAME.SUFFIX, in the directory -o DIR",
        "topics": "one file, the poses of job NAME on topic /a2b/NAME/pose",
    }
    groups: dict = {}
    for row in formats.TABLE:
        if row.batch_writer:
            groups.setdefault(row.batch, []).append(row.name)
    entries = [f"{', '.join(names)}: {layouts[batch_]}" for batch_, names in groups.items()]
    suffixes = ", ".join(formats.suffix_names(batch=True))
    return f"{'; '.join(entries)}  [default: from the -o suffix {suffixes}, else csv]"


def profile_option(batch: bool = False):
    """``--profile``: the MCAP messages, Foxglove's JSON or ROS 2's CDR."""
    ros2 = (
        "geometry_msgs/PoseStamped per job"
        if batch
        else ("geometry_msgs/PoseStamped, tf2_msgs/TFMessage and nav_msgs/Path")
    )
    return click.option(
        "--profile",
        type=click.Choice(
            [
                row.writer_options["profile"]
                for row in formats.TABLE
                if "profile" in row.writer_options
            ]
        ),
        help="mcap: foxglove (JSON foxglove.PoseInFrame"
        + ("" if batch else " and FrameTransform")
        + ", the default), protobuf (the same in Protobuf; needs a2b-motions[protobuf]) "
        f"or ros2 (CDR {ros2}, as --format ros2).",
    )


def format_option(f=None, *, batch: bool = False, durations: bool = True):
    """``--format`` (the formats of :mod:`a2b.formats` a command writes) and ``--profile``;
    :func:`format_from` resolves the two. ``@format_option`` or ``@format_option(batch=True)``;
    ``durations=False`` for a command whose times are its own (no ``--duration``)."""
    if f is None:
        return lambda g: format_option(g, batch=batch, durations=durations)
    names = [row.name for row in formats.TABLE if (row.batch_writer if batch else row.writer)]
    option = click.option(
        "--format", "fmt", type=click.Choice(names), help=format_help(batch, durations)
    )
    f = option(profile_option(batch)(f))
    return f if batch else storage_option(f)


storage_option = click.option(
    "--storage",
    type=click.Choice(("mcap", "sqlite3")),
    help="ros2: mcap (one MCAP file, the default) or sqlite3 (a rosbag2 bag folder -o FOLDER "
    "with FOLDER_0.db3 and metadata.yaml, as ros2 bag record -s sqlite3 writes it).",
)


#: The formats that write times (``--duration``, ``--start-time``), from the table.
_TIMED = ", ".join(row.name for row in formats.TABLE if row.timed)
#: The formats that name frames (``--frame-id``, ``--child-frame-id``), from the table.
_FRAMED = ", ".join(row.name for row in formats.TABLE if "frame_id" in row.options)

_start_time_option = click.option(
    "--start-time",
    type=FLOAT,
    default=0.0,
    show_default=True,
    help=f"{_TIMED}: the time of t = 0, in seconds (e.g. a Unix time).",
)
_duration_option = click.option(
    "--duration",
    type=PositiveFloat(),
    default=1.0,
    show_default=True,
    help=f"{_TIMED}: seconds from t = 0 to t = 1; time = t · duration + start_time.",
)


def timing_options(f):
    return _duration_option(_start_time_option(f))


def duration_given() -> bool:
    """Whether ``--duration`` was given on the command line (not its default)."""
    from click.core import ParameterSource

    source = click.get_current_context().get_parameter_source("duration")
    return source not in (None, ParameterSource.DEFAULT)


_child_frame_option = click.option(
    "--child-frame-id",
    default="a2b",
    show_default=True,
    help=f"{_FRAMED}: the child frame of the /tf transforms (the moving body).",
)
frame_id_option = click.option(
    "--frame-id",
    default="world",
    show_default=True,
    help=f"{_FRAMED}: the fixed frame of /a2b/pose and the parent frame of /tf.",
)


def frame_options(f):
    return frame_id_option(_child_frame_option(f))


#: The options of :func:`trajectory_options` that :func:`write_motion` takes.
TRAJECTORY_OPTIONS = (
    "fmt",
    "profile",
    "output",
    "duration",
    "start_time",
    "frame_id",
    "child_frame_id",
    "storage",
)


def trajectory_options(f):
    """``--samples``, ``--format``, ``-o``, the tum/mcap timing and frame options, and ``-v``.

    The command receives ``samples`` and ``verbose`` and the keys of :data:`TRAJECTORY_OPTIONS`;
    :func:`pop_trajectory` takes the latter out of its keyword arguments for :func:`write_motion`.
    """
    for option in (verbose_option, frame_options, timing_options, output_option, format_option):
        f = option(f)
    return samples_option(f)


def pop_trajectory(kwargs: dict) -> dict:
    """Remove the keys of :data:`TRAJECTORY_OPTIONS` from ``kwargs`` and return them."""
    return {key: kwargs.pop(key) for key in TRAJECTORY_OPTIONS}


def format_from(
    fmt: str | None,
    output: str,
    choices: list | None = None,
    profile: str | None = None,
    batch: bool = False,
) -> str:
    """``--format`` if given, else the format the ``-o`` suffix names, else ``csv``; then
    ``--profile`` picks the format of that writer with that profile (``mcap`` with
    ``--profile ros2`` is ``ros2``).

    A format a2b picks is stated in ``choices`` when given.
    """
    from ..output import format_of

    row, chosen = format_of(fmt, output, batch)
    if chosen is not None and choices is not None:
        if row.name == "csv" and not formats.from_suffix(str(output), batch):
            suffixes = ", ".join(formats.suffix_names(batch))
            choices.append(f"{chosen} (--format or an -o suffix {suffixes} to change)")
        else:
            choices.append(f"{chosen} (--format to change)")
    if profile is None:
        return row.name
    if "profile" not in row.writer_options:
        raise click.UsageError(f"--profile is for MCAP output, not {row.name}")
    family = [r for r in formats.TABLE if r.writer == row.writer]
    if row.writer_options["profile"] != profile and not row.suffixes:
        raise click.UsageError(
            f"--format {row.name} writes the {row.writer_options['profile']} profile, not {profile}"
        )
    return next(r.name for r in family if r.writer_options["profile"] == profile)


def sample_and_write(motion, samples, from_file, choices: list, verbose: bool, out: dict) -> None:
    """The last steps of interpolate, bezier and spline: pick the sample count (``--samples``,
    else the file's, else 101) and the format, state the choices with ``-v``, then write with
    :mod:`a2b.output` (the options ``out`` of :func:`pop_trajectory`)."""
    from ..formats import BY_NAME
    from ..output import write_motion, write_timed

    out = dict(out)
    law = {key: out.pop(key) for key in TIME_LAW_OPTIONS if key in out} or None
    timed = None
    if law is not None:
        timed = time_law(motion, law, out["duration"] if duration_given() else None, choices)
    if timed is not None and (law["rate"] or law["dt"]):
        if samples is not None:
            raise click.UsageError("give --samples or --rate/--dt, not both")
    else:
        samples = pick("samples", samples, from_file, 101, choices, "--samples")
    fmt = BY_NAME[format_from(out.pop("fmt"), out["output"], choices, out.pop("profile"))]
    state_choices(choices + list(motion.choices), verbose)
    target = out.pop("output")
    storage = out.pop("storage")
    frames = refuse_defaults(fmt, out if timed is None else {k: out[k] for k in FRAME_OPTIONS})
    frames.update({"storage": storage} if storage is not None else {})
    if timed is None:
        write_motion(motion, samples, target, fmt, out["duration"], out["start_time"], **frames)
        return
    by = {"rate": law["rate"], "dt": law["dt"]}
    grid = timed.grid(**by, samples=None if law["rate"] or law["dt"] else samples)
    write_timed(timed, grid, target, fmt, law["velocities"], out["start_time"], **frames)


def refuse_defaults(fmt, out: dict) -> dict:
    """The frame options of ``out`` for a writer of ``fmt``; an option given on the command line
    (not its default) that ``fmt`` does not take is refused (:func:`a2b.output.write`)."""
    from click.core import ParameterSource

    from ..errors import OptionError

    context = click.get_current_context()
    given = [
        key
        for key in ("duration", "start_time", *FRAME_OPTIONS)
        if key in out
        and context.get_parameter_source(key) not in (None, ParameterSource.DEFAULT)
        and key not in fmt.options
    ]
    if given:
        names = ", ".join("--" + key.replace("_", "-") for key in given)
        raise OptionError(f"{names}: not for {fmt.name} output")
    return {k: out[k] for k in FRAME_OPTIONS if k in out and k in fmt.options}
