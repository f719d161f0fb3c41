"""``a2b bezier``: sample the Bézier motion of the control poses of a file."""

from __future__ import annotations

import click

from . import CONTEXT_SETTINGS, options, writing


@click.command(context_settings=CONTEXT_SETTINGS)
@click.argument("poses", type=options.TRAJECTORY)
@options.space_option
@options.m_option(
    "matrix: the vector m of μ_[m], e.g. 1,0,0,0.5  [default: the sum of the control quaternions]"
)
@click.option(
    "--weights",
    type=options.NumberList(),
    help="Positive weights, one per control pose, e.g. 1,2,2,1 (a rational curve).",
)
@options.alphas_option(
    "matrix: fiber coordinates α of a control pose in the kernel basis; repeat once per "
    "control pose, in order."
)
@options.basis_option("matrix: the kernel basis of --alpha", default=None)
@options.offsets_option("study: κ-fiber offsets s, one per control pose (h + s εp).")
@options.trajectory_input_options(rate=False)
@writing.trajectory_options
@options.time_law_options
def command(
    poses,
    space,
    samples,
    verbose,
    input_format,
    topic,
    input_child_frame,
    input_frame,
    orthonormalize,
    **parameters,
):
    """Sample the Bézier motion of the control poses in POSES (a file, or - for stdin).

    POSES is JSON or YAML with a list `controls` of at least two poses, in any pose form of
    `a2b interpolate`, and optionally `space`, `samples` and `parameters` (m, weights, alphas,
    basis, offsets); options given here override the file. POSES may also be a trajectory
    file (as `a2b resample` reads): its poses, in order, are the controls. The curve has
    degree k − 1 for k controls and passes through the first control (t = 0) and the last
    (t = 1).

    \b
    matrix  de Casteljau over the control poses' points (1, R, t) of R^13, mapped by μ_[m]
            in the given frame (the paper's outlook, figure 4); two controls give the cubic
            mode with --frame given
    study   de Casteljau over unit Study vectors with consistent signs, mapped by κ; two
            controls give the darboux mode (δ = s1 − s0)

    Output formats and options as for `a2b interpolate`; -v states every choice a2b makes
    for you (the default m, signs of control quaternions, the kernel basis).

    \b
    Example:
      a2b bezier samples/planar-bezier.yaml --samples 5
      a2b bezier samples/planar-bezier.yaml --space study --format tum -o planar.tum
      a2b bezier samples/planar-bezier.yaml --weights 1,2,2,1 --format mcap -o planar.mcap
      a2b bezier samples/reference.tum --space study --samples 5
    """
    out = writing.pop_trajectory(parameters)
    out.update(options.pop_time_law(parameters))
    choices: list[str] = []
    curve = options.read_pose_list_option(
        poses,
        "controls",
        input_format,
        topic,
        input_child_frame,
        orthonormalize,
        choices,
        input_frame,
    )
    parameters["alphas"] = parameters["alphas"] or None
    motion = options.curve_motion(curve, space, choices, parameters)
    writing.sample_and_write(motion, samples, curve.samples, choices, verbose, out)
