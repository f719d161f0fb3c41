"""``a2b spline``: sample the C¹ spline through the key poses of a file."""

from __future__ import annotations

import click

from . import CONTEXT_SETTINGS, options, writing


@click.command(context_settings=CONTEXT_SETTINGS)
@click.argument("poses", type=options.TRAJECTORY)
@options.space_option
@options.m_option(
    "matrix: the vector m of μ_[m], one for all segments  [default: the sum of the poses' "
    "quaternions]"
)
@options.trajectory_input_options(rate=False)
@writing.trajectory_options
@options.time_law_options
def command(
    poses,
    space,
    m,
    samples,
    verbose,
    input_format,
    topic,
    input_child_frame,
    input_frame,
    orthonormalize,
    **out,
):
    """Sample the C¹ spline through the key poses in POSES (a file, or - for stdin).

    POSES is JSON or YAML with a list `poses` of at least two poses, in any pose form of
    `a2b interpolate`, and optionally `space`, `samples` and `parameters` (m); options given
    here override the file. POSES may also be a trajectory file (as `a2b resample` reads):
    its poses, in order, are the key poses (their times are not used; `a2b resample --mode
    spline` follows the times).

    Consecutive poses are joined by cubic Bézier segments whose inner control points follow
    the uniform Catmull–Rom rule in the chosen space (R^13 for matrix, unit Study vectors for
    study): the tangent at pose j is half the difference of its neighbours, X(j+1) − X(j−1),
    and X1 − X0, XN − X(N−1) at the ends; the segment from pose j to j+1 has the controls
    Xj, Xj + Tj/3, X(j+1) − T(j+1)/3, X(j+1). The motion is C¹ and passes through pose j at
    t = j/N (N + 1 poses), so --samples s·N + 1 hits every pose.

    Output formats and options as for `a2b interpolate`; -v states every choice a2b makes
    for you.

    \b
    Example:
      a2b spline samples/spline.yaml --samples 9
      a2b spline samples/spline.yaml --space study --format tum -o spline.tum
      a2b spline samples/spline.yaml --format mcap -o spline.mcap
      a2b spline samples/walk.kitti --orthonormalize --space study --samples 59
    """
    choices: list[str] = []
    curve = options.read_pose_list_option(
        poses,
        "poses",
        input_format,
        topic,
        input_child_frame,
        orthonormalize,
        choices,
        input_frame,
    )
    motion = options.curve_motion(curve, space, choices, {"m": m})
    writing.sample_and_write(motion, samples, curve.samples, choices, verbose, out)
