"""Option decorators, parameter types and the sampling-and-writing step shared by the commands.

Only click is imported here: the numeric core, numpy, yaml and rich are imported inside the
functions that need them, so ``a2b --help`` stays fast.
"""

from __future__ import annotations

import contextlib
import math
import os
import re
import sys

import click

from ..errors import printable
from ..names import MAX_SAMPLES, MIN_SAMPLES, MODES
from ..parameters import BY_NAME, EXCLUSIVE, OF_MODE, TABLE

FORMATS = ("csv", "matrix", "study", "tum", "kitti", "mcap", "ros2")
#: The formats that are MCAP files: ``ros2`` is MCAP with the ROS 2 profile.
MCAP_FORMATS = ("mcap", "ros2")
SPACES = ("matrix", "study")
#: ``-o`` suffixes that choose a format when ``--format`` is not given.
FORMAT_SUFFIXES = {".mcap": "mcap", ".tum": "tum", ".kitti": "kitti"}
#: MCAP numbers messages with a uint32 sequence number.
MCAP_MAX_SAMPLES = 2**32
#: MCAP log times are unsigned nanoseconds; a2b's writer forms them as int64.
MCAP_MAX_NANOSECONDS = 2**63 - 1


#: The numbers of the command line, as in the files: ASCII decimal digits with an optional sign,
#: point and exponent (``2``, ``-0.5``, ``.5``, ``1e-3``); no ``inf``, ``nan``, ``1_000``,
#: hexadecimal or other scripts' digits, which Python's ``float`` and ``int`` would take.
DECIMAL = re.compile(r"[-+]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][-+]?[0-9]+)?", re.ASCII)
INTEGER = re.compile(r"[-+]?[0-9]+", re.ASCII)


class FiniteFloat(click.ParamType):
    """A finite decimal number (:data:`DECIMAL`)."""

    name = "NUMBER"

    def convert(self, value, param, ctx):
        if isinstance(value, float):
            return value
        text = str(value).strip()
        if not DECIMAL.fullmatch(text):
            self.fail(f"{value!r} is not a decimal number (such as 2, -0.5 or 1e-3)", param, ctx)
        number = float(text)
        if not math.isfinite(number):
            self.fail(f"{value!r} is not a finite number", param, ctx)
        return number


class Angle(FiniteFloat):
    """An angle: radians (a decimal number), or degrees with a ``deg`` suffix (``45deg``)."""

    name = "ANGLE"

    def convert(self, value, param, ctx):
        if isinstance(value, str):
            from ..parameters import degrees

            radians = degrees(value)
            if radians is not None:
                return radians
        return super().convert(value, param, ctx)


class Count(click.IntRange):
    """A whole number of ASCII digits (:data:`INTEGER`) within a range."""

    def convert(self, value, param, ctx):
        if not isinstance(value, int) and not INTEGER.fullmatch(str(value).strip()):
            self.fail(f"{value!r} is not a whole number of decimal digits", param, ctx)
        return super().convert(value, param, ctx)


class PositiveFloat(FiniteFloat):
    """A finite number greater than zero."""

    name = "NUMBER>0"

    def convert(self, value, param, ctx):
        number = super().convert(value, param, ctx)
        if not number > 0:
            self.fail(f"{value!r} is not greater than 0", param, ctx)
        return number


class Vector(click.ParamType):
    """``n`` comma-separated finite numbers, as in ``--m 1,0,0,0.5``."""

    def __init__(self, n: int, names: str):
        self.n = n
        self.names = names
        self.name = f"{n} NUMBERS"

    def convert(self, value, param, ctx):
        if isinstance(value, tuple):
            return value
        parts = [p.strip() for p in str(value).split(",")]
        if len(parts) != self.n:
            self.fail(
                f"expected {self.n} comma-separated numbers ({self.names}), got {len(parts)}: "
                f"{value!r}",
                param,
                ctx,
            )
        return tuple(FiniteFloat().convert(p, param, ctx) for p in parts)


class NumberList(click.ParamType):
    """Comma-separated finite numbers, any count, as in ``--weights 1,2,2,1``."""

    name = "NUMBERS"

    def convert(self, value, param, ctx):
        if isinstance(value, tuple):
            return value
        return tuple(FLOAT.convert(p.strip(), param, ctx) for p in str(value).split(","))


class Branch(click.ParamType):
    """+1 or -1."""

    name = "+1|-1"

    def convert(self, value, param, ctx):
        if value in (1, -1):
            return value
        text = str(value).strip()
        if text in ("1", "+1"):
            return 1
        if text == "-1":
            return -1
        self.fail(f"expected +1 or -1, got {value!r}", param, ctx)


class InputFile(click.File):
    """A file to read in binary, or ``-`` for standard input, which must be open."""

    def __init__(self):
        super().__init__("rb")

    def convert(self, value, param, ctx):
        if value == "-" and (sys.stdin is None or _closed(0)):
            self.fail("standard input is closed (give a file, or - with input)", param, ctx)
        return super().convert(value, param, ctx)


def _closed(fd: int) -> bool:
    try:
        os.fstat(fd)
    except OSError:
        return True
    return False


INPUT = InputFile()
FLOAT = FiniteFloat()
M_VECTOR = Vector(4, "m0, m1, m2, m3")
ALPHA_VECTOR = Vector(6, "α0 … α5")


def m_option(help_: str):
    """``--m``, the vector m of μ_[m]; ``help_`` says what it does for the command."""
    return click.option("--m", "m", type=M_VECTOR, help=help_)


#: The kernel bases of M_m (:func:`a2b.extended.kernel_basis`).
BASES = ("auto", "paper", "rref")


def basis_option(help_: str, default: str | None = "auto"):
    """``--basis``: the kernel basis of M_m, ``auto`` (the paper's unless it degenerates)."""
    return click.option(
        "--basis",
        type=click.Choice(BASES),
        default=default,
        help=f"{help_}; auto is the paper's (eq. 13) unless it degenerates for m  [default: auto]",
    )


def offsets_option(help_: str):
    """``--offsets``: κ-fiber offsets s (points h + s εp), comma-separated."""
    return click.option("--offsets", type=NumberList(), help=help_)


def alphas_option(help_: str):
    """``--alpha`` given once per point (collected as ``alphas``): fiber coordinates α."""
    return click.option("--alpha", "alphas", type=ALPHA_VECTOR, multiple=True, help=help_)


def _motion_option(parameter):
    """The click option of a motion parameter of :mod:`a2b.parameters`."""
    from ..names import FRAMES

    flag = "--" + parameter.name.replace("_", "-")
    help_ = f"{parameter.mode}: {parameter.help}"
    if parameter.kind == "bool":
        off = "--" + parameter.off.replace("_", "-")
        return click.option(f"{flag}/{off}", parameter.name, default=None, help=help_)
    kinds = {
        "number": FLOAT,
        "branch": Branch(),
        "pose": INPUT,
        "frame": click.Choice(FRAMES),
    }
    if parameter.unit == "radian":
        kinds["number"] = Angle()
        help_ += " Degrees with a deg suffix: 45deg."
    kind = kinds.get(parameter.kind) or Vector(parameter.size, parameter.components)
    metavar = "POSEFILE" if parameter.kind == "pose" else None
    return click.option(flag, parameter.name, type=kind, metavar=metavar, help=help_)


#: Motion parameter options, in the order of the table of :mod:`a2b.parameters`.
_MOTION_OPTIONS = [_motion_option(parameter) for parameter in TABLE]
MOTION_PARAMETERS = tuple(BY_NAME)


def motion_parameter_options(f):
    """Every motion parameter of the core (not ``--mode``), each defaulting to "not given"."""
    for option in reversed(_MOTION_OPTIONS):
        f = option(f)
    return f


def motion_options(f):
    """``--mode`` and every motion parameter of the core, each defaulting to "not given"."""
    f = motion_parameter_options(f)
    return click.option(
        "--mode",
        type=click.Choice(MODES),
        help="The motion: darboux (vertical Darboux motion, default), cubic (cubic circular) or "
        "screw (ScLERP).",
    )(f)


output_option = click.option(
    "-o",
    "--output",
    type=click.Path(allow_dash=True, dir_okay=False),
    default="-",
    show_default=True,
    help="Where to write; '-' is standard output. A file is written to a temporary file and "
    "renamed into place when complete; a device or named pipe is written directly.",
)
samples_option = click.option(
    "--samples",
    type=Count(min=MIN_SAMPLES, max=MAX_SAMPLES),
    help="Number of samples, t evenly spaced in [0, 1], written as they are computed "
    "(any number streams in bounded memory)  [default: the file's samples, else 101]",
)
_format_option = click.option(
    "--format",
    "fmt",
    type=click.Choice(FORMATS),
    help="Output format; ros2 is MCAP that ros2 bag, rosbags and evo read  [default: from the "
    "-o suffix (.mcap, .tum, .kitti), else csv]",
)
profile_option = click.option(
    "--profile",
    type=click.Choice(("foxglove", "ros2")),
    help="mcap: foxglove (JSON foxglove.PoseInFrame and FrameTransform, the default) or ros2 "
    "(CDR geometry_msgs/PoseStamped, tf2_msgs/TFMessage and nav_msgs/Path, as --format ros2).",
)


def format_option(f):
    """``--format`` and ``--profile``; :func:`format_from` resolves the two."""
    return _format_option(profile_option(f))


_start_time_option = click.option(
    "--start-time",
    type=FLOAT,
    default=0.0,
    show_default=True,
    help="tum, mcap, ros2: the time of t = 0, in seconds (e.g. a Unix time).",
)
_duration_option = click.option(
    "--duration",
    type=PositiveFloat(),
    default=1.0,
    show_default=True,
    help="tum, mcap, ros2: seconds from t = 0 to t = 1; time = t · duration + start_time.",
)


def timing_options(f):
    return _duration_option(_start_time_option(f))


POINT_VECTOR = Vector(3, "x, y, z")

#: The options of :func:`time_law_options`, as the keyword arguments of :func:`a2b.timing`.
TIME_LAW_OPTIONS = (
    "time_law",
    "max_speed",
    "max_accel",
    "max_jerk",
    "max_angular_speed",
    "max_angular_accel",
    "point",
    "constant_speed",
    "rate",
    "dt",
    "velocities",
)


def time_law_options(f=None, *, sampling: bool = True):
    """A time law (:mod:`a2b.timelaw`): profile, limits, point, constant speed and, with
    ``sampling`` (commands that write samples), the sampling in time and velocity output. Any
    of them times the samples; :func:`pop_time_law` takes them. ``@time_law_options`` or
    ``@time_law_options(sampling=False)``."""
    if f is None:
        return lambda g: time_law_options(g, sampling=sampling)
    limit = {
        "speed": "speed of the point (length/s)",
        "accel": "acceleration of the point along its path (length/s²)",
        "jerk": "jerk of the point along its path (length/s³); implies jerk-limited",
        "angular-speed": "angular speed (rad/s)",
        "angular-accel": "angular acceleration (rad/s²)",
    }
    opts = [
        click.option(
            "--time-law",
            type=click.Choice(("linear", "trapezoid", "jerk-limited", "quintic")),
            help="Time the samples by this profile, at rest at both ends except linear  "
            "[default with limits: jerk-limited with --max-jerk, trapezoid with an acceleration "
            "limit, else linear]",
        )
    ]
    for name, words in limit.items():
        opts.append(click.option(f"--max-{name}", type=PositiveFloat(), help=f"Limit the {words}."))
    opts += [
        click.option(
            "--point",
            type=POINT_VECTOR,
            help="The body point x,y,z (moving frame) whose speed is limited and written "
            "[default: 0,0,0, the origin]",
        ),
        click.option(
            "--constant-speed",
            is_flag=True,
            help="Move the point at constant speed along its path (arc length to 1e-12).",
        ),
        click.option(
            "--rate", type=PositiveFloat(), help="Sample every 1/HZ seconds (and the end)."
        ),
        click.option("--dt", type=PositiveFloat(), help="Sample every DT seconds (and the end)."),
        click.option(
            "--velocities",
            is_flag=True,
            help="csv, matrix, study: add vx,vy,vz,wx,wy,wz (velocity of the point and "
            "angular velocity, fixed frame, per second); ros2: TwistStamped on "
            "/a2b/twist.",
        ),
    ]
    for option in reversed(opts if sampling else opts[:-3]):
        f = option(f)
    return f


def pop_time_law(kwargs: dict) -> dict:
    """Remove the keys of :data:`TIME_LAW_OPTIONS` from ``kwargs`` and return them (``None``
    for the sampling options of a command without them)."""
    return {key: kwargs.pop(key, None) for key in TIME_LAW_OPTIONS}


def duration_given() -> bool:
    """Whether ``--duration`` was given on the command line (not its default)."""
    from click.core import ParameterSource

    source = click.get_current_context().get_parameter_source("duration")
    return source not in (None, ParameterSource.DEFAULT)


def figure_law(parameters: dict) -> dict:
    """The time-law options of a command that writes no samples (``describe``, ``plot
    --speeds``: :func:`time_law_options` without sampling), taken from ``parameters``."""
    law = pop_time_law(parameters)
    for name in ("rate", "dt", "velocities"):
        law.pop(name)
    return law


def law_given(law: dict) -> bool:
    """Whether any time-law option of ``law`` (:func:`pop_time_law`) was given."""
    return any(v not in (None, False) for v in law.values())


def time_law(motion, law: dict, duration: float | None, choices: list, always: bool = False):
    """The :class:`a2b.timelaw.TimedMotion` the options ``law`` ask for, or ``None`` (samples
    even in t, as before); with ``always`` a law even when no time-law option is given (over
    ``--duration``, else 1 s). ``duration``: ``--duration`` if given."""
    from ..timelaw import timing

    limits = {
        k: law[k]
        for k in ("max_speed", "max_accel", "max_jerk", "max_angular_speed", "max_angular_accel")
    }
    if not always and not law_given({k: v for k, v in law.items() if k != "point"}):
        if law["point"] is not None:
            raise click.UsageError("--point is for a time law or --velocities")
        return None
    if law.get("rate") is not None and law.get("dt") is not None:
        raise click.UsageError("give --rate or --dt, not both")
    given = {k: v for k, v in limits.items() if v is not None}
    timed = timing(
        motion,
        law["time_law"],
        duration=duration if given or duration else 1.0,
        point=law["point"],
        constant_speed=law["constant_speed"],
        **given,
    )
    if law["time_law"] is None:
        choices.append(f"time law {timed.profile.kind} (--time-law to change)")
    binding = timed.binding or "duration"
    choices.append(f"the time law takes {timed.duration:.9g} s; binding: {binding}")
    return timed


verbose_option = click.option(
    "-v",
    "--verbose",
    is_flag=True,
    help="State on stderr every choice a2b makes for you (defaults, signs, bases, branches, axes).",
)
space_option = click.option(
    "--space",
    type=click.Choice(SPACES),
    help="Build the curve in R^13 and map it by μ_[m] (matrix, default), or over unit Study "
    "vectors and map it by κ (study).",
)


_child_frame_option = click.option(
    "--child-frame-id",
    default="a2b",
    show_default=True,
    help="mcap, ros2: the child frame of the /tf transforms (the moving body).",
)
_frame_option = click.option(
    "--frame-id",
    default="world",
    show_default=True,
    help="mcap, ros2: the fixed frame of /a2b/pose and the parent frame of /tf.",
)


def frame_options(f):
    return _frame_option(_child_frame_option(f))


#: The options of :func:`trajectory_options` that :func:`write_motion` takes.
TRAJECTORY_OPTIONS = (
    "fmt",
    "profile",
    "output",
    "duration",
    "start_time",
    "frame_id",
    "child_frame_id",
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


json_option = click.option(
    "--json", "as_json", is_flag=True, help="Machine-readable JSON instead of a table."
)


def merge_parameters(from_file: dict, from_command_line: dict, mode: str | None = None) -> dict:
    """The file's motion parameters, overridden by those given on the command line.

    An option overrides the file's value of the same name and of the parameters that choose
    the same thing (``--lam`` replaces a ``delta`` from the file; ``--a`` replaces ``alpha``).
    With ``mode`` (a ``--mode`` given on the command line), the file's parameters that this
    mode does not take are dropped. ``--through`` arrives as an open file and is read here.
    """
    merged = dict(from_file)
    if mode is not None:
        merged = {k: v for k, v in merged.items() if k in OF_MODE[mode]}
    given = {k: v for k, v in from_command_line.items() if v is not None}
    for group in EXCLUSIVE:
        if group & set(given):
            for key in group - set(given):
                if not (key == "branch" and "lam" in given):
                    merged.pop(key, None)
    for key, value in given.items():
        if key == "through":
            from ..io.poseschema import read_pose

            value = read_pose(value)
        merged[key] = value
    return merged


def format_from(
    fmt: str | None, output: str, choices: list | None = None, profile: str | None = None
) -> str:
    """``--format`` if given, else the format the ``-o`` suffix names, else ``csv``; then
    ``--profile ros2`` makes ``mcap`` into ``ros2``.

    A format a2b picks is stated in ``choices`` when given.
    """
    fmt = fmt or _format_from_suffix(output, choices)
    if profile is None:
        return fmt
    if fmt not in MCAP_FORMATS:
        raise click.UsageError(f"--profile is for MCAP output, not {fmt}")
    if fmt == "ros2" and profile == "foxglove":
        raise click.UsageError("--format ros2 writes the ros2 profile, not foxglove")
    return "ros2" if profile == "ros2" else "mcap"


def _format_from_suffix(output: str, choices: list | None) -> str:
    for suffix, name in FORMAT_SUFFIXES.items():
        if str(output).lower().endswith(suffix):
            if choices is not None:
                choices.append(f"format {name}: from the -o suffix {suffix} (--format to change)")
            return name
    if choices is not None:
        choices.append(
            "format csv: the default (--format or an -o suffix .mcap, .tum, .kitti to change)"
        )
    return "csv"


def pick(what: str, given, from_file, default, choices: list, option: str):
    """``given`` (the command line), else ``from_file``, else ``default``, stated in ``choices``."""
    if given is not None:
        return given
    if from_file is not None:
        return from_file
    choices.append(f"{what} {default}: the default ({option} or the file to change)")
    return default


def only_for_two_poses(curve, **given) -> None:
    """Refuse the options ``given`` (by name) that belong to two poses, for a pose list."""
    names = [name for name, value in given.items() if value not in (None, False, ())]
    if names:
        what = "a Bézier motion" if curve.key == "controls" else "a spline"
        raise click.UsageError(
            f"{', '.join('--' + n.replace('_', '-') for n in names)} "
            f"{'is' if len(names) == 1 else 'are'} for two poses; this file is a list of "
            f"{curve.key} ({what})"
        )


def figure_motions(job, mode, compare, space, parameters: dict, choices: list, **two_poses):
    """What `a2b plot` and `a2b view` draw: ``(start, end, motions, marks)``.

    A pose list (``controls`` or ``poses``) gives its Bézier motion or spline and its inner
    poses as marks (C1, C2, … or P1, P2, …); the options of ``two_poses`` and the motion
    options are refused for it. A poses file gives its mode (``--mode``, the file's, else
    darboux) or the ``--compare`` modes, each with the parameters meant for it.
    """
    from ..api import PARAMETERS
    from ..errors import ParameterError
    from ..io.poseschema import PoseList

    if isinstance(job, PoseList):
        only_for_two_poses(job, mode=mode, compare=compare, **two_poses, **parameters)
        motion = curve_motion(job, space, choices)
        choices += list(motion.choices)
        prefix = "C" if job.key == "controls" else "P"
        marks = [(f"{prefix}{i}", pose) for i, pose in enumerate(job.poses)][1:-1]
        return job.poses[0], job.poses[-1], motion, marks
    if space:
        raise click.UsageError("--space is for a list of controls or poses; this is a poses file")
    if compare:
        given = [k for k, v in parameters.items() if v is not None]
        unused = sorted(k for k in given if not any(k in PARAMETERS[m] for m in compare))
        if unused:
            raise ParameterError(
                f"{', '.join('--' + k.replace('_', '-') for k in unused)} applies to none of the "
                f"compared modes {', '.join(compare)}"
            )
    parameters = merge_parameters(job.parameters, parameters, mode)
    if compare:  # each mode takes the parameters meant for it (from the file or the options)
        motions = [
            (m, {k: v for k, v in parameters.items() if k in PARAMETERS[m]}) for m in compare
        ]
    else:
        picked = pick("mode", mode, job.mode, "darboux", choices, "--mode")
        motions = [(picked, parameters)]
    return job.start, job.end, motions, None


def curve_motion(curve, space: str | None, choices: list, given: dict | None = None):
    """The Bézier motion (``controls``) or spline (``poses``) of a pose list.

    Its parameters are the file's, overridden by ``given`` (from the command line); the space
    is ``space``, else the file's, else matrix, stated in ``choices``.
    """
    from ..motions.bezier import bezier_motion, spline_motion

    parameters = merge_parameters(curve.parameters, given or {})
    space = pick("space", space, curve.space, "matrix", choices, "--space")
    build = bezier_motion if curve.key == "controls" else spline_motion
    return build(curve.poses, space, **parameters)


def sample_and_write(motion, samples, from_file, choices: list, verbose: bool, out: dict) -> None:
    """The last steps of interpolate, bezier and spline: pick the sample count (``--samples``,
    else the file's, else 101) and the format, state the choices with ``-v``, then
    :func:`write_motion` with the options ``out`` of :func:`pop_trajectory`."""
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
    out["fmt"] = format_from(out["fmt"], out["output"], choices, out.pop("profile"))
    state_choices(choices + list(motion.choices), verbose)
    if timed is None:
        write_motion(motion, samples, **out)
        return
    times = timed.times(
        rate=law["rate"], dt=law["dt"], samples=None if law["rate"] or law["dt"] else samples
    )
    write_timed(timed, times, law["velocities"], **out)


def write_timed(
    timed,
    times,
    velocities: bool,
    *,
    fmt: str,
    output: str,
    duration: float,
    start_time: float,
    frame_id: str,
    child_frame_id: str,
) -> None:
    """Write a timed motion at ``times`` (seconds from its start): the first column (or the
    stamp) is ``start_time + time``; with ``velocities`` the twist of the law's point."""
    from ..io.writers import CHUNK_SAMPLES, REPRESENTATION, sample_chunks

    if velocities and fmt not in ("csv", "matrix", "study", "ros2"):
        raise click.UsageError(
            f"--velocities: {fmt} has no velocity field; use csv, matrix, study or ros2"
        )
    check_output(fmt, output, len(times), float(times[-1] - times[0]) or 1.0, start_time)
    representation = REPRESENTATION[fmt]

    def chunks():
        for lo in range(0, len(times), CHUNK_SAMPLES):
            block = times[lo : lo + CHUNK_SAMPLES]
            ts, twists = timed.sample(block, velocities)
            for chunk in sample_chunks(timed.motion, ts, representation, size=len(ts)):
                chunk.t, chunk.twist = block + start_time, twists
                check_chunk(chunk, "time")
                yield chunk

    write_chunks(
        chunks(), fmt, output, frame_id=frame_id, child_frame_id=child_frame_id, count=len(times)
    )


def state_choices(choices: list, verbose: bool) -> None:
    """With ``-v``, write every choice a2b made for the user to stderr, one per line."""
    if not verbose:
        return
    click.echo("Choices a2b made:" if choices else "Choices a2b made: none", err=True)
    for choice in choices:
        click.echo(f"  • {printable(choice)}", err=True)


def check_finite(data, what: str) -> None:
    """Raise if a number in ``data`` (nested dicts and lists) is NaN or infinite.

    The core computes in doubles; input near their limits (a translation of 1e300, an
    amplitude of 1e200) can overflow on the way. Such a result is refused, not printed.
    """
    import math

    from ..errors import A2bError

    def walk(value, key):
        if isinstance(value, float) and not math.isfinite(value):
            raise A2bError(
                f"{what}: {key} = {value} overflows double precision; the poses or "
                "parameters are too large"
            )
        if isinstance(value, dict):
            for k, v in value.items():
                walk(v, k)
        elif isinstance(value, (list, tuple)):
            for v in value:
                walk(v, key)

    walk(data, "a value")


def motion_chunks(motion, samples: int, representation: str):
    """Sample ``motion`` at ``samples`` evenly spaced t in [0, 1], one writer chunk at a time.

    Every chunk is checked: a sample that overflowed to NaN or infinity stops the run with an
    :class:`A2bError` instead of reaching the output.
    """
    from ..io.writers import CHUNK_SAMPLES, sample_chunks
    from ..motions.base import evenly_spaced

    for ts in evenly_spaced(samples, CHUNK_SAMPLES):
        for chunk in sample_chunks(motion, ts, representation, size=len(ts)):
            check_chunk(chunk)
            yield chunk


def check_chunk(chunk, column: str = "t") -> None:
    """Raise :class:`A2bError` if a sample of ``chunk`` overflowed to NaN or infinity, naming
    it by its ``column`` value, so that it never reaches the output."""
    import numpy as np

    from ..errors import A2bError

    for name in ("quat_wxyz", "trans", "matrices", "study", "twist"):
        values = getattr(chunk, name)
        if values is not None and not np.isfinite(values).all():
            bad = ~np.isfinite(values.reshape(len(chunk.t), -1)).all(axis=1)
            where = float(chunk.t[np.argmax(bad)])
            raise A2bError(
                f"the sample at {column} = {where:.17g} is not finite: the motion overflows "
                "double precision; the poses or parameters are too large"
            )


def check_output(fmt: str, output: str, samples: int, duration: float, start_time: float) -> None:
    """Refuse, before writing anything, what the format cannot hold.

    MCAP: binary, so not to a terminal; at most 2**32 messages per topic (uint32 sequence
    numbers); log times ``t · duration + start_time`` from 0 to 2**63 − 1 nanoseconds (the
    year 2262); ros2 stamps up to 2**31 − 1 s (2038). tum and MCAP: times that overflow a
    double.
    """
    import math
    import sys

    import numpy as np

    from ..errors import ParameterError

    if fmt in MCAP_FORMATS and str(output) == "-" and sys.stdout.isatty():
        raise click.UsageError(
            "MCAP is binary: write it with -o FILE or into a pipe, not to a terminal"
        )
    if fmt not in ("tum", *MCAP_FORMATS):
        return
    last = duration + start_time  # the time of t = 1, the latest (duration > 0)
    if not math.isfinite(last):
        raise ParameterError(
            f"the time of t = 1, duration + start_time = {duration:g} + {start_time:g}, "
            "overflows a double"
        )
    step = duration / max(samples - 1, 1)
    resolution = float(np.spacing(max(abs(start_time), abs(last))))
    if fmt == "tum" and not step > resolution:
        raise ParameterError(
            f"consecutive TUM times would differ by {step:.3g} s, which a double near "
            f"{max(abs(start_time), abs(last)):g} s cannot tell apart (its resolution there is "
            f"{resolution:.3g} s): the time stamps would repeat; give a smaller --start-time or "
            "fewer samples"
        )
    if fmt not in MCAP_FORMATS:
        return
    if samples > MCAP_MAX_SAMPLES:
        raise ParameterError(
            f"MCAP numbers messages with 32-bit sequence numbers: at most 2**32 = "
            f"{MCAP_MAX_SAMPLES} samples, got {samples}"
        )
    if start_time < 0:
        raise ParameterError(f"MCAP times must not be negative; --start-time is {start_time:g} s")
    if not last * 1e9 < MCAP_MAX_NANOSECONDS:
        raise ParameterError(
            f"MCAP log times are nanoseconds below 2**63 (the year 2262); the time of t = 1, "
            f"duration + start_time, is {last:g} s"
        )
    if fmt == "ros2":
        from ..io.ros2 import split_stamps

        split_stamps(np.array([round(last * 1e9)]))


#: The formats of trajectory files (:mod:`a2b.io.trajectories`), without importing it (a test
#: checks that the two agree).
TRAJECTORY_FORMATS = ("tum", "kitti", "euroc", "csv", "matrix", "study", "mcap")


def trajectory_input_options(rate: bool = True):
    """``--input-format``, ``--topic``, ``--input-child-frame``, ``--orthonormalize`` and (with
    ``rate``) ``--input-rate`` for a trajectory file
    (:func:`a2b.io.trajectories.read_trajectory`)."""
    options = [
        click.option(
            "--input-format",
            type=click.Choice(TRAJECTORY_FORMATS),
            help="A trajectory's format  [default: from the suffix (.tum, .kitti, .mcap), else "
            "from the content]",
        ),
        click.option("--topic", help="mcap input: the topic of the poses, if several."),
        click.option(
            "--input-child-frame",
            metavar="FRAME",
            help="mcap input, a ROS 2 tf2_msgs/TFMessage topic: the poses are its transforms "
            "to FRAME  [default: its only child frame]",
        ),
        orthonormalize_option,
    ]
    if rate:
        options.insert(
            3,
            click.option(
                "--input-rate",
                type=PositiveFloat(),
                metavar="HZ",
                help="kitti input: the poses are 1/HZ s apart  [default: times are the line "
                "indices 0, 1, 2, …]",
            ),
        )

    def decorate(f):
        for option in reversed(options):
            f = option(f)
        return f

    return decorate


orthonormalize_option = click.option(
    "--orthonormalize",
    is_flag=True,
    help="Project rotation blocks that are orthogonal only to a few digits "
    "(max |R Rᵀ − I| ≤ 1e-4) onto the nearest rotations; -v states the residual.",
)


@contextlib.contextmanager
def repairing(orthonormalize: bool, choices: list):
    """Read pose files within: with ``orthonormalize``, matrix poses are repaired
    (:func:`a2b.io.poseschema.orthonormalizing`) and the repairs stated in ``choices``."""
    if not orthonormalize:
        yield
        return
    from ..io.poseschema import orthonormalizing

    with orthonormalizing() as repairs:
        yield
    if repairs:
        choices.append(repaired(len(repairs), max(repairs), "matrix pose"))


def repaired(count: int, residual: float, what: str) -> str:
    """What ``--orthonormalize`` did, for ``-v``."""
    return (
        f"orthonormalized {count} {what}{'s' * (count != 1)}: largest max |R Rᵀ − I| was "
        f"{residual:.3g}"
    )


def read_pose_list_option(
    stream, key: str, fmt, topic, child_frame, orthonormalize: bool, choices: list
):
    """The poses of a pose-list file (``controls`` or ``poses``), or of a trajectory file: one
    given ``--input-format``, with a trajectory suffix, or whose content is a trajectory's."""
    import io

    from ..errors import InputFileError
    from ..io.documents import stream_name
    from ..io.poseschema import PoseList, read_pose_list
    from ..io.trajectories import read_trajectory, sniff_format

    name = stream_name(stream, None)
    data = stream.read()
    if fmt is None:
        try:
            fmt = sniff_format(data, name)
        except InputFileError:
            fmt = None  # not a trajectory: a pose list
        else:
            choices.append(f"input format {fmt}: a trajectory file (--input-format to change)")
    if fmt is None:
        if topic or child_frame:
            given = "--topic" if topic else "--input-child-frame"
            raise click.UsageError(f"{given} is for trajectory files")
        with repairing(orthonormalize, choices):
            return read_pose_list(io.BytesIO(data), key, name)
    path = read_trajectory(
        io.BytesIO(data),
        name,
        fmt,
        topic=topic,
        child_frame=child_frame,
        orthonormalize=orthonormalize,
        minimum=2,
    )
    if path.repaired is not None:
        choices.append(repaired(len(path), path.repaired, "rotation block"))
    return PoseList(key, path.matrices)


def write_chunks(chunks, fmt: str, output: str, **options) -> None:
    """Write sample chunks in format ``fmt`` to ``output`` through
    :func:`a2b.io.atomic.atomic_output`: a failure leaves no partial file."""
    from ..io.atomic import atomic_output
    from ..io.writers import write_samples

    try:
        with atomic_output(output) as stream:
            write_samples(stream, fmt, chunks, **options)
    finally:  # a generator that computes in a process of its own stops it now
        if hasattr(chunks, "close"):
            chunks.close()


def write_motion(
    motion,
    samples: int,
    *,
    fmt: str,
    output: str,
    duration: float,
    start_time: float,
    frame_id: str,
    child_frame_id: str,
) -> None:
    """Sample ``motion`` at ``samples`` evenly spaced t in [0, 1] and write them to ``output``.

    ``fmt`` is already resolved (:func:`format_from`). The samples stream chunk by chunk
    into :func:`a2b.io.atomic.atomic_output`, so memory stays bounded for any count and a
    failure leaves no partial file. Used by ``interpolate``, ``bezier`` and ``spline``.
    """
    from ..io.writers import REPRESENTATION

    check_output(fmt, output, samples, duration, start_time)
    write_chunks(
        motion_chunks(motion, samples, REPRESENTATION[fmt]),
        fmt,
        output,
        duration=duration,
        start_time=start_time,
        frame_id=frame_id,
        child_frame_id=child_frame_id,
        count=samples,
    )
