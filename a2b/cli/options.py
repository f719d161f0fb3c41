"""Option decorators, parameter types and the sampling-and-writing step shared by the commands.

Only click is imported here: the numeric core, numpy, yaml and rich are imported inside the
functions that need them, so ``a2b --help`` stays fast.
"""

from __future__ import annotations

import contextlib
import io
import math
import os
import re
import sys

import click

from .. import formats
from ..errors import printable
from ..names import BASES, MODES, SPACES
from ..parameters import BY_NAME, EXCLUSIVE, OF_MODE, TABLE

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


class TrajectoryInput(InputFile):
    """As :class:`InputFile`, and a folder: a ROS 2 bag, given to the readers as an empty
    stream named by the folder's path (:func:`a2b.io.trajectories.opened` reads the bag by
    that name)."""

    def convert(self, value, param, ctx):
        if isinstance(value, (str, os.PathLike)) and os.path.isdir(value):
            import io

            folder = io.BytesIO()
            folder.name = os.fspath(value)
            return folder
        return super().convert(value, param, ctx)


def _closed(fd: int) -> bool:
    try:
        os.fstat(fd)
    except OSError:
        return True
    return False


INPUT = InputFile()
TRAJECTORY = TrajectoryInput()
FLOAT = FiniteFloat()
M_VECTOR = Vector(4, "m0, m1, m2, m3")
ALPHA_VECTOR = Vector(6, "α0 … α5")


def m_option(help_: str):
    """``--m``, the vector m of μ_[m]; ``help_`` says what it does for the command."""
    return click.option("--m", "m", type=M_VECTOR, help=help_)


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
    """A time law (:mod:`a2b.timing`): profile, limits, point, constant speed and, with
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
            "limit, else quintic; linear with --duration alone]",
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
    from ..timelaw import timing

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


json_option = click.option(
    "--json", "as_json", is_flag=True, help="Machine-readable JSON instead of a table."
)


def refuse_foreign_parameters(mode: str, given: dict) -> None:
    """A usage error for the motion options ``given`` that ``mode`` does not take, naming them
    as options and the modes that take them all (the library's error names its parameters)."""
    foreign = [key for key in given if key not in OF_MODE[mode]]
    if foreign:
        takers = [other for other in OF_MODE if all(key in OF_MODE[other] for key in foreign)]
        raise click.UsageError(
            f"--mode {mode} does not take {', '.join('--' + k.replace('_', '-') for k in foreign)}"
            + (f"; give --mode {' or '.join(takers)}" if takers else "")
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

            value = read_pose(*read_pose_file(value))
        merged[key] = value
    return merged


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


def trajectory_input_options(rate: bool = True):
    """``--input-format``, ``--topic``, ``--input-child-frame``, ``--input-frame``,
    ``--orthonormalize`` and (with ``rate``) ``--input-rate`` for a trajectory file
    (:func:`a2b.io.trajectories.read_trajectory`)."""
    options = [
        click.option(
            "--input-format",
            type=click.Choice(formats.INPUT_NAMES),
            help="A trajectory's format  [default: from the suffix (.tum, .kitti, .mcap, "
            ".db3), else from the content; a folder is a rosbag2 bag]",
        ),
        click.option(
            "--topic",
            help="mcap and rosbag2 input: the topic of the poses  [default: the only pose "
            "topic, or /a2b/pose; -v says which]",
        ),
        click.option(
            "--input-child-frame",
            metavar="FRAME",
            help="mcap and rosbag2 input, a topic of transforms (ROS 2 TFMessage, Foxglove "
            "FrameTransform or FrameTransforms): the poses are its transforms to FRAME  [default: "
            "its only child frame]",
        ),
        click.option(
            "--input-frame",
            metavar="FRAME",
            help="mcap input: the poses of --input-child-frame in FRAME, composed through "
            "/tf and /tf_static; -v states the chain.",
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
    "(max |R Rᵀ − I| ≤ 1e-4) onto the nearest rotations, stating the largest residual among "
    "the choices a2b made (-v, or the table of describe and fiber).",
)


def console():
    """A rich console on standard output whose closed pipe raises :class:`BrokenPipeError`, so
    that the command ends quietly with status 0 as every command does (rich's own way exits
    with status 1)."""
    from rich.console import Console

    class _Console(Console):
        def on_broken_pipe(self) -> None:
            raise BrokenPipeError

    return _Console()


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


#: The largest pose file (a pose, a poses file, a pose list) read: a larger one is refused
#: before it is read whole. (Trajectories have no such bound: their memory is that of the poses.)
POSE_FILE_BYTES = 64 << 20


def read_pose_file(stream) -> tuple[io.BytesIO, str]:
    """``(content, name)`` of a pose file, the arguments of a pose-file reader, read in bounded
    memory: a NUL byte (``/dev/zero``) and more than :data:`POSE_FILE_BYTES` are errors as soon
    as they arrive (:func:`a2b.io.textrows.read_text_bytes`)."""
    from ..io.documents import stream_name
    from ..io.textrows import read_text_bytes

    name = stream_name(stream, None)
    return io.BytesIO(read_text_bytes(stream, name, limit=POSE_FILE_BYTES)), name


def read_text_input(stream) -> tuple:
    """``(stream, name)`` of a text file read as it is consumed, a NUL byte (``/dev/zero``)
    an error as soon as it arrives (:func:`a2b.io.textrows.replayed`): a jobs file."""
    from ..io.documents import stream_name
    from ..io.textrows import replayed

    name = stream_name(stream, None)
    return replayed(stream, name), name


def read_input(stream, fmt: str | None, choices: list) -> tuple:
    """``(name, stream, format)`` of a file that is a trajectory (``format`` given, or told by
    the suffix or the first bytes: :func:`a2b.io.trajectories.sniff_format`) or else a pose
    file (``format`` ``None``, its content read as by :func:`read_pose_file`). A trajectory's
    ``stream`` gives its bytes from the start, for :func:`a2b.io.trajectories.read_trajectory`,
    which reads them in bounded memory."""
    from ..errors import InputFileError
    from ..io.documents import stream_name
    from ..io.textrows import read_text_bytes, replayed
    from ..io.trajectories import _head, sniff_format

    name = stream_name(stream, None)
    head = _head(stream)
    if fmt is None:
        try:
            fmt = sniff_format(head, name)
        except InputFileError:
            data = read_text_bytes(stream, name, head, limit=POSE_FILE_BYTES)
            return name, io.BytesIO(data), None  # not a trajectory: a pose file
        choices.append(f"input format {fmt}: a trajectory file (--input-format to change)")
    return name, replayed(stream, name, head, text=False), fmt


def read_pose_list_option(
    stream,
    key: str,
    fmt,
    topic,
    child_frame,
    orthonormalize: bool,
    choices: list,
    input_frame: str | None = None,
):
    """The poses of a pose-list file (``controls`` or ``poses``), or of a trajectory file: one
    given ``--input-format``, with a trajectory suffix, or whose content is a trajectory's
    (:func:`read_input`)."""
    from ..io.poseschema import PoseList, read_pose_list
    from ..io.trajectories import read_trajectory

    name, data, fmt = read_input(stream, fmt, choices)
    if fmt is None:
        if topic or child_frame or input_frame:
            given = (
                "--topic" if topic else "--input-frame" if input_frame else "--input-child-frame"
            )
            raise click.UsageError(f"{given} is for trajectory files")
        with repairing(orthonormalize, choices):
            return read_pose_list(data, key, name)
    path = read_trajectory(
        data,
        name,
        fmt,
        topic=topic,
        child_frame=child_frame,
        input_frame=input_frame,
        orthonormalize=orthonormalize,
        minimum=2,
        choices=choices,
    )
    choices.extend(path.notes)
    if path.repaired is not None:
        choices.append(repaired(len(path), path.repaired, "rotation block"))
    return PoseList(key, path.matrices)
