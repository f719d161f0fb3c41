"""``a2b view``: an interactive 3D page of a motion, a curve or a trajectory."""

from __future__ import annotations

import click

from . import CONTEXT_SETTINGS, options
from .plot import ModeList, points_option, units_options


@click.command(context_settings=CONTEXT_SETTINGS)
@click.argument("poses", type=options.TRAJECTORY)
@click.option(
    "-o",
    "--output",
    type=click.Path(allow_dash=True, dir_okay=False),
    help="The page to write (HTML), to a temporary file renamed into place; '-' writes it to "
    "standard output, which must not be a terminal  [default with --open: a new file in the "
    "temporary directory]",
)
@click.option("--open", "open_", is_flag=True, help="Open the page in the default browser.")
@options.motion_options
@options.space_option
@click.option(
    "--compare",
    type=ModeList(),
    help="One body per mode, each with its own colour and legend entry, e.g. "
    "darboux,cubic,screw (instead of --mode).",
)
@points_option
@units_options
@click.option(
    "--samples",
    type=options.Count(min=2, max=100_000),
    help="Samples per motion (at most 201 are animation frames)  [default: the file's "
    "samples, else 101]",
)
@options.trajectory_input_options(rate=True)
@options.verbose_option
def command(poses, output, open_, mode, space, compare, points, angle_unit, length_unit,
            samples, input_format, topic, input_child_frame, input_frame, input_rate,
            orthonormalize,
            verbose, **parameters):  # fmt: skip
    """Write one self-contained HTML page that shows the motion between the poses in POSES
    (a file, or - for stdin) in 3D: the moving frame animated along t (play, pause, a
    slider), the trajectories of its axis tips, the screw axis, A and B, the transmission
    curve with a marker that follows t, and the parameters of each motion in a side panel.

    POSES is a poses file, a `controls:` or `poses:` list (a Bézier motion or spline, as for
    a2b bezier and a2b spline, with --space), or a trajectory file (as a2b resample reads:
    its poses are shown in order, t running over them). The page inlines plotly.js and
    loads nothing from the network, so it works offline and can be mailed. Needs plotly:
    pip install 'a2b-motions[view]'.

    \b
    Example:
      a2b view samples/quarter-turn.yaml -o turn.html
      a2b view samples/quarter-turn.yaml --compare darboux,cubic,screw -o compare.html
      a2b view samples/spline.yaml --space study -o spline.html
      a2b view samples/reference.tum -o reference.html
    """
    import os
    import sys
    import tempfile

    from ..io.atomic import atomic_output
    from ..io.poseschema import read_motion_file
    from ..io.trajectories import read_trajectory
    from ..view import MAX_FRAMES, MAX_LINE_POINTS, animation_steps, require_plotly, view_page

    require_plotly()
    if output is None and not open_:
        raise click.UsageError("give -o FILE.html (or - for standard output), or --open")
    if output == "-" and sys.stdout.isatty():
        raise click.UsageError("the page is 5 MB of HTML: write it with -o FILE, or use --open")
    if output == "-" and open_:
        raise click.UsageError("--open opens a file: give -o FILE.html, or leave -o out")
    if compare and mode:
        raise click.UsageError("give --mode or --compare, not both")
    choices: list[str] = []
    name, data, fmt = options.read_input(poses, input_format, choices)
    style = {"points": points, "angle_unit": angle_unit, "length_unit": length_unit}
    if fmt is not None:  # a trajectory: its poses in order
        given = {"--mode": mode, "--compare": compare, "--space": space, "--samples": samples,
                 **{"--" + k.replace("_", "-"): v for k, v in parameters.items()}}  # fmt: skip
        named = [k for k, v in given.items() if v not in (None, False, ())]
        if named:
            raise click.UsageError(
                f"{named[0]} is for poses files; this is a trajectory, whose poses are drawn"
            )
        path = read_trajectory(data, name, fmt, rate=input_rate, topic=topic,
                               child_frame=input_child_frame, input_frame=input_frame,
                               orthonormalize=orthonormalize, minimum=2,
                               choices=choices)  # fmt: skip
        choices.extend(path.notes)
        mats = path.matrices
        samples = len(mats)
        times = None if fmt == "kitti" and input_rate is None else path.times  # else indices
        page = view_page(mats[0], mats[-1], [("trajectory", mats)], samples=samples,
                         times=times, title=f"{name}: {samples} poses", **style)  # fmt: skip
    else:
        if topic or input_child_frame or input_frame or input_rate:
            raise click.UsageError("--topic, --input-child-frame, --input-frame and --input-rate "
                                   "are for trajectory files")  # fmt: skip
        with options.repairing(orthonormalize, choices):
            job = read_motion_file(data, name)
        samples = options.pick("samples", samples, job.samples, 101, choices, "--samples")
        start, end, motions, marks = options.figure_motions(
            job, mode, compare, space, parameters, choices
        )
        page = view_page(start, end, motions, samples=samples, marks=marks, **style)
    steps = animation_steps(samples)
    if steps < samples:
        lines = "all of them" if samples <= MAX_LINE_POINTS else f"{MAX_LINE_POINTS} of them"
        choices.append(f"animation: {steps} of the {samples} samples as frames (at most "
                       f"{MAX_FRAMES}); the lines drawn through {lines}")  # fmt: skip
    if output is None:
        handle, output = tempfile.mkstemp(prefix="a2b-view-", suffix=".html")
        os.close(handle)
        choices.append(f"output {output}: a new file, as -o was not given")
    options.state_choices(choices, verbose)
    with atomic_output(output) as stream:
        stream.write(page.encode())
    if open_:
        import pathlib
        import webbrowser

        if not webbrowser.open(pathlib.Path(output).resolve().as_uri()):
            raise click.ClickException(f"no browser could be opened; the page is {output}")
