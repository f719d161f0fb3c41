"""``a2b plot``: the paper's three pictures of a motion between two poses, or of a curve."""

from __future__ import annotations

import click

from ..errors import quoted
from . import CONTEXT_SETTINGS, options

#: More samples than a figure can show are refused rather than held in memory.
PLOT_MAX_SAMPLES = 100_000


class ModeList(click.ParamType):
    """Comma-separated modes, as in ``--compare darboux,cubic,screw``."""

    name = "MODE,MODE,..."

    def convert(self, value, param, ctx):
        if isinstance(value, tuple):
            return value
        modes = tuple(part.strip() for part in str(value).split(",") if part.strip())
        unknown = [mode for mode in modes if mode not in options.MODES]
        if unknown or not modes:
            self.fail(
                f"expected modes from {', '.join(options.MODES)} separated by commas, got "
                f"{quoted(value)}",
                param,
                ctx,
            )
        if len(set(modes)) != len(modes):
            self.fail(f"a mode is repeated in {quoted(value)}", param, ctx)
        return modes


class PointList(click.ParamType):
    """Body points ``x,y,z;x,y,z;...`` in the moving frame's coordinates."""

    name = "X,Y,Z;..."

    def convert(self, value, param, ctx):
        if isinstance(value, tuple):
            return value
        vector = options.Vector(3, "x, y, z")
        points = tuple(
            vector.convert(part, param, ctx) for part in str(value).split(";") if part.strip()
        )
        if not points:
            self.fail("expected at least one point x,y,z", param, ctx)
        return points


points_option = click.option(
    "--points",
    type=PointList(),
    help="Body points whose trajectories are drawn, in the moving frame  [default: the tips of "
    "its unit axes]",
)
_angle_unit_option = click.option(
    "--angle-unit",
    type=click.Choice(["deg", "rad"]),
    default="deg",
    show_default=True,
    help="Unit of the rotation angle ω in the transmission curve and of angles in the title.",
)
_length_unit_option = click.option(
    "--length-unit",
    metavar="NAME",
    help="Name of the poses' length unit for the axis labels, e.g. m.",
)


def units_options(f):
    """``--angle-unit`` and ``--length-unit`` (`a2b plot`, `a2b view`)."""
    return _angle_unit_option(_length_unit_option(f))


@click.command(context_settings=CONTEXT_SETTINGS)
@click.argument("poses", type=options.INPUT)
@click.option(
    "-o",
    "--output",
    type=click.Path(allow_dash=True, dir_okay=False),
    default="-",
    show_default=True,
    help="The image to write: .png, .svg or .pdf, written to a temporary file and renamed into "
    "place; '-' writes PNG (or --image-format) to standard output, which must not be a terminal.",
)
@click.option(
    "--image-format",
    type=click.Choice(["png", "svg", "pdf"]),
    help="The image format  [default: from the -o suffix, else png]",
)
@options.motion_options
@options.space_option
@click.option(
    "--compare",
    type=ModeList(),
    help="Overlay several modes, one colour each, e.g. darboux,cubic,screw (instead of --mode).",
)
@click.option(
    "--family",
    is_flag=True,
    help="Also draw the family of transmission curves through A and B: darboux varies δ, cubic "
    "(1+b)/(1+a).",
)
@click.option(
    "--family-of",
    type=click.Choice(["ab", "m"]),
    help="cubic: vary a and b (ab, the default) or m3:m0 (m) in the family; implies --family.",
)
@points_option
@units_options
@click.option(
    "--samples",
    type=options.Count(min=2, max=PLOT_MAX_SAMPLES),
    help="Samples per motion, t evenly spaced in [0, 1] (a figure shows no more than "
    f"{PLOT_MAX_SAMPLES})  [default: the file's samples, else 101]",
)
@click.option(
    "--speeds",
    is_flag=True,
    help="Instead, draw the speed of the point, its acceleration along the path and the "
    "angular speed over time, under the time law of --duration and the time-law options.",
)
@click.option(
    "--duration", type=options.PositiveFloat(), help="--speeds: the time law's duration (s)."
)
@options.time_law_options(sampling=False)
@options.verbose_option
@options.orthonormalize_option
def command(
    poses,
    output,
    image_format,
    mode,
    space,
    compare,
    family,
    family_of,
    points,
    angle_unit,
    length_unit,
    samples,
    speeds,
    duration,
    verbose,
    orthonormalize,
    **parameters,
):
    """Draw the motion between the start and end pose in POSES (a file, or - for stdin),
    or the Bézier motion or spline of a `controls:` or `poses:` file (as for a2b bezier and
    a2b spline, with --space).

    Three panels, as in the paper's figures: the moving frame at 8 instants (axes x, y, z in
    red, green, blue), the trajectories of body points, and the transmission curve: the
    rotation ω about and the translation z along the screw axis, relative to A, with the
    closed form (darboux a sine, cubic a tangent, screw a line) drawn through the samples.
    Motions that are not in the cylinder group of A and B (cubic with --frame given) have no
    transmission curve. The suffix of -o chooses PNG, SVG or PDF. Needs matplotlib:
    pip install 'a2b-motions[plot]'.

    With --compare, each motion parameter applies to the modes that take it. A curve is
    drawn with its control poses (C1, C2, …) or key poses (P1, P2, …) marked; the motion
    options, --compare and --family are for two poses only.

    With --speeds the figure shows instead, over time, the speed of the time law's point
    (--point, the origin by default), its acceleration along the path and the angular speed,
    with the limits dashed, under the law of --duration and the time-law options of `a2b
    interpolate` (--time-law, --max-*, --point, --constant-speed); --samples counts samples
    evenly spaced in time (801 by default).

    \b
    Example:
      a2b plot samples/quarter-turn.yaml -o turn.png
      a2b plot samples/quarter-turn.yaml --compare darboux,cubic,screw -o compare.svg
      a2b plot samples/half-turn.yaml --mode cubic --family --angle-unit rad -o family.pdf
      a2b plot samples/planar-bezier.yaml --space study -o planar.svg
      a2b plot samples/quarter-turn.yaml --speeds --max-speed 1 --max-accel 2 -o speeds.png
    """
    import sys

    from ..io.atomic import atomic_output
    from ..io.poseschema import read_motion_file
    from ..plot import figure_format, plot_motions, write_figure

    choices: list[str] = []
    if image_format:
        fmt = image_format
    elif output == "-":
        fmt = "png"
        choices.append("image format png: the default for standard output (--image-format)")
    else:
        fmt = figure_format(output)
    if output == "-" and sys.stdout.isatty():
        raise click.UsageError(
            "an image is binary: write it with -o FILE or into a pipe, not to a terminal"
        )
    if compare and mode:
        raise click.UsageError("give --mode or --compare, not both")
    law = options.figure_law(parameters)
    if not speeds:
        given = [name for name, v in (("duration", duration),) + tuple(law.items()) if v]
        if given:
            raise click.UsageError(f"--{given[0].replace('_', '-')} is for --speeds")
    elif family or family_of or points:
        raise click.UsageError("--family, --family-of and --points are not for --speeds")
    with options.repairing(orthonormalize, choices):
        job = read_motion_file(*options.read_pose_file(poses))
    if speeds:
        figure = _speeds_figure(
            job, mode, compare, space, parameters, law, duration, samples, length_unit, choices
        )
        options.state_choices(choices, verbose)
        with atomic_output(output) as stream:
            write_figure(figure, stream, fmt)
        return
    samples = options.pick("samples", samples, job.samples, 101, choices, "--samples")
    style = {
        "points": points,
        "angle_unit": angle_unit,
        "length_unit": length_unit,
        "samples": samples,
    }
    start, end, motions, marks = options.figure_motions(
        job, mode, compare, space, parameters, choices, family=family, family_of=family_of
    )
    options.state_choices(choices, verbose)
    figure = plot_motions(start, end, motions, family=family_of or family, marks=marks, **style)
    with atomic_output(output) as stream:
        write_figure(figure, stream, fmt)


def _speeds_figure(job, mode, compare, space, parameters, law, duration, samples, unit, choices):
    """The figure of ``a2b plot --speeds``: each drawn motion timed by the law of the options."""
    import a2b

    from ..plot import plot_speeds

    _, _, motions, _ = options.figure_motions(job, mode, compare, space, parameters, choices)
    if not isinstance(motions, list):  # a Bézier motion or spline
        motions = {motions.kind: motions}
    else:
        motions = {m: a2b.motion(job.start, job.end, m, **given) for m, given in motions}
    timed = {}
    for label, motion in motions.items():
        own: list[str] = []
        timed[label] = options.time_law(motion, law, duration, own, always=True)
        choices += [f"{label}: {c}" if len(motions) > 1 else c for c in own]
    if samples is None:
        samples = 801
        choices.append("801 samples evenly spaced in time (--samples)")
    limits = {k[4:]: v for k, v in law.items() if k.startswith("max_") and v is not None}
    return plot_speeds(timed, limits=limits, length_unit=unit, samples=samples)
