"""Option decorators and parameter types shared by the commands.

Only click is imported here: the numeric core, numpy, yaml and rich are imported inside the
functions that need them, so ``a2b --help`` stays fast.
"""

from __future__ import annotations

import math

import click

MODES = ("darboux", "cubic", "screw")
FORMATS = ("csv", "matrix", "study", "tum", "kitti", "mcap")
#: ``-o`` suffixes that choose a format when ``--format`` is not given.
FORMAT_SUFFIXES = {".mcap": "mcap", ".tum": "tum", ".kitti": "kitti"}


class FiniteFloat(click.ParamType):
    """A finite float (no NaN or infinity)."""

    name = "NUMBER"

    def convert(self, value, param, ctx):
        if isinstance(value, float):
            return value
        try:
            number = float(value)
        except ValueError:
            self.fail(f"{value!r} is not a number", param, ctx)
        if not math.isfinite(number):
            self.fail(f"{value!r} is not a finite number", param, ctx)
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
                f"expected {self.n} comma-separated numbers ({self.names}), got {len(parts)}: {value!r}",
                param,
                ctx,
            )
        return tuple(FiniteFloat().convert(p, param, ctx) for p in parts)


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


FLOAT = FiniteFloat()

#: Motion parameter options, in the order of ``a2b.motion``'s documentation.
_MOTION_OPTIONS = [
    click.option("--delta", type=FLOAT, help="darboux: the fiber offset δ = sB − sA, a length (default 0)."),
    click.option("--kappa", type=FLOAT, help="darboux: the phase κ of the transmission curve z = z0 + λ sin(ω + κ), radians."),
    click.option("--lam", type=FLOAT, help="darboux: the amplitude λ of the transmission curve (two solutions: see --branch)."),
    click.option("--branch", type=Branch(), help="darboux: which of the two solutions for --lam, +1 or -1."),
    click.option("--pitch-start", type=FLOAT, help="darboux: the pitch dz/dω at the start, length per radian."),
    click.option("--pitch-end", type=FLOAT, help="darboux: the pitch dz/dω at the end, length per radian."),
    click.option(
        "--through",
        type=click.File("rb"),
        metavar="POSEFILE",
        help="darboux: a file with a third pose the motion passes through.",
    ),
    click.option(
        "--long-way/--short-way",
        "long_way",
        default=None,
        help="darboux: go the long way round (the other sign of the end pose's Study vector).",
    ),
    click.option("--m", "m", type=Vector(4, "m0, m1, m2, m3"), help="cubic: the vector m of μ_[m], e.g. 1,0,0,0.5."),
    click.option("--alpha", type=Vector(6, "α0 … α5"), help="cubic: fiber coordinates α of the start pose in the kernel basis."),
    click.option("--beta", type=Vector(6, "β0 … β5"), help="cubic: fiber coordinates β of the end pose in the kernel basis."),
    click.option("--a", "a", type=FLOAT, help="cubic: the essential scalar a (instead of --alpha)."),
    click.option("--b", "b", type=FLOAT, help="cubic: the essential scalar b (instead of --beta)."),
    click.option(
        "--frame",
        type=click.Choice(["canonical", "given"]),
        help="cubic: construct in the canonical frame of the two poses (default) or apply μ_[m] in the given coordinates.",
    ),
]

MOTION_PARAMETERS = (
    "delta", "kappa", "lam", "branch", "pitch_start", "pitch_end", "through", "long_way",
    "m", "alpha", "beta", "a", "b", "frame",
)  # fmt: skip


def motion_options(f):
    """``--mode`` and every motion parameter of the core, each defaulting to "not given"."""
    for option in reversed(_MOTION_OPTIONS):
        f = option(f)
    return click.option(
        "--mode",
        type=click.Choice(MODES),
        help="The motion: darboux (vertical Darboux motion, default), cubic (cubic circular) or screw (ScLERP).",
    )(f)


def output_option(f):
    return click.option(
        "-o",
        "--output",
        type=click.Path(allow_dash=True, dir_okay=False),
        default="-",
        show_default=True,
        help="Where to write; '-' is standard output. Written to a temporary file and renamed into place.",
    )(f)


def samples_option(f):
    return click.option(
        "--samples",
        type=click.IntRange(min=1),
        help="Number of samples, t evenly spaced in [0, 1]  [default: the file's samples, else 101]",
    )(f)


def timing_options(f):
    f = click.option(
        "--start-time",
        type=FLOAT,
        default=0.0,
        show_default=True,
        help="tum, mcap: the time of t = 0, in seconds (e.g. a Unix time).",
    )(f)
    return click.option(
        "--duration",
        type=click.FloatRange(min=0.0, min_open=True),
        default=1.0,
        show_default=True,
        help="tum, mcap: seconds from t = 0 to t = 1; time = t · duration + start_time.",
    )(f)


def frame_options(f):
    f = click.option(
        "--child-frame-id",
        default="a2b",
        show_default=True,
        help="mcap: the child frame of the /tf transforms (the moving body).",
    )(f)
    return click.option(
        "--frame-id",
        default="world",
        show_default=True,
        help="mcap: the fixed frame of /a2b/pose and the parent frame of /tf.",
    )(f)


def json_option(f):
    return click.option("--json", "as_json", is_flag=True, help="Machine-readable JSON instead of a table.")(f)


#: Parameters that choose the same thing; giving one on the command line drops the file's others.
EXCLUSIVE = (
    {"delta", "kappa", "lam", "branch", "pitch_start", "pitch_end", "through"},
    {"alpha", "a"},
    {"beta", "b"},
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
        from ..api import PARAMETERS

        merged = {k: v for k, v in merged.items() if k in PARAMETERS[mode]}
    given = {k: v for k, v in from_command_line.items() if v is not None}
    for group in EXCLUSIVE:
        if group & set(given):
            for key in group - set(given):
                if not (key == "branch" and "lam" in given):
                    merged.pop(key, None)
    for key, value in given.items():
        if key == "through":
            from ..io.readers import read_pose

            value = read_pose(value)
        merged[key] = value
    return merged


def format_from(fmt: str | None, output: str) -> str:
    """``--format`` if given, else the format the ``-o`` suffix names, else ``csv``."""
    if fmt:
        return fmt
    for suffix, name in FORMAT_SUFFIXES.items():
        if str(output).lower().endswith(suffix):
            return name
    return "csv"
