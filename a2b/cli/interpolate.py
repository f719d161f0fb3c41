"""``a2b interpolate``: sample the motion between the two poses of a file."""

from __future__ import annotations

import sys

import click

from . import CONTEXT_SETTINGS, options


@click.command(context_settings=CONTEXT_SETTINGS)
@click.argument("poses", type=click.File("rb"))
@options.motion_options
@options.samples_option
@click.option(
    "--format",
    "fmt",
    type=click.Choice(options.FORMATS),
    help="Output format  [default: from the -o suffix (.mcap, .tum, .kitti), else csv]",
)
@options.output_option
@options.timing_options
@options.frame_options
def command(poses, mode, samples, fmt, output, duration, start_time, frame_id, child_frame_id, **parameters):
    """Sample the motion from the start to the end pose in POSES (a file, or - for stdin).

    POSES is JSON or YAML with `start` and `end` poses and, optionally, `mode`, `samples` and
    `parameters`; options given here override the file. Every format keeps full precision:
    each number reads back as the same double.

    \b
    Formats:
      csv     t,tx,ty,tz,qw,qx,qy,qz
      matrix  t and the 12 entries of [R | t], row by row
      study   t,p0,p1,p2,p3,q0,q1,q2,q3 (unit Study parameters)
      tum     time tx ty tz qx qy qz qw (time = t · duration + start_time)
      kitti   12 numbers of [R | t] per line
      mcap    foxglove.PoseInFrame on /a2b/pose and foxglove.FrameTransform on /tf

    Pitches are screw-theory pitches: translation per radian, dz/dω.

    \b
    Example:
      a2b interpolate samples/quarter-turn.yaml --samples 5
      a2b interpolate samples/quarter-turn.yaml --delta 0.2 --format tum -o turn.tum
      a2b interpolate samples/half-turn.yaml --mode cubic --m 1,0,0,0.5 -o turn.mcap
      cat samples/quarter-turn.yaml | a2b interpolate - --format mcap | cat > turn.mcap
    """
    import numpy as np

    import a2b

    from ..io.atomic import atomic_output
    from ..io.readers import read_poses
    from ..io.writers import REPRESENTATION, sample_chunks, write_samples

    fmt = options.format_from(fmt, output)
    if fmt == "mcap" and output == "-" and sys.stdout.isatty():
        raise click.UsageError("MCAP is binary: write it with -o FILE or into a pipe, not to a terminal")
    job = read_poses(poses)
    parameters = options.merge_parameters(job.parameters, parameters, mode)
    motion = a2b.motion(job.start, job.end, mode or job.mode or "darboux", **parameters)
    ts = np.linspace(0.0, 1.0, samples or job.samples or 101)
    with atomic_output(output) as stream:
        write_samples(
            stream,
            fmt,
            sample_chunks(motion, ts, REPRESENTATION[fmt]),
            duration=duration,
            start_time=start_time,
            frame_id=frame_id,
            child_frame_id=child_frame_id,
        )
