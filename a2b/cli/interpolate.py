"""``a2b interpolate``: sample the motion between the two poses of a file."""

from __future__ import annotations

import click

from . import CONTEXT_SETTINGS, options


@click.command(context_settings=CONTEXT_SETTINGS)
@click.argument("poses", type=options.INPUT)
@options.motion_options
@options.orthonormalize_option
@options.trajectory_options
@options.time_law_options
def command(poses, mode, samples, verbose, orthonormalize, **parameters):
    """Sample the motion from the start to the end pose in POSES (a file, or - for stdin).

    POSES is JSON or YAML with `start` and `end` poses and, optionally, `mode`, `samples` and
    `parameters`; options given here override the file. Every format keeps full precision:
    each number reads back as the same double. Samples are computed and written in chunks,
    so any count runs in bounded memory (`--samples 1000000000 | head` starts at once).

    \b
    Formats:
      csv     t,tx,ty,tz,qw,qx,qy,qz
      matrix  t and the 12 entries of [R | t], row by row
      study   t,p0,p1,p2,p3,q0,q1,q2,q3 (unit Study parameters)
      tum     time tx ty tz qx qy qz qw (time = t · duration + start_time)
      kitti   12 numbers of [R | t] per line
      mcap    foxglove.PoseInFrame on /a2b/pose and foxglove.FrameTransform on /tf
      ros2    MCAP for ROS 2: PoseStamped on /a2b/pose, TFMessage on /tf, a Path at the end

    Pitches are screw-theory pitches: translation per radian, dz/dω. -v states on stderr
    every choice a2b makes for you: defaults, the sign of a quaternion, the screw axis of a
    pure translation, the branch of an amplitude.

    \b
    Example:
      a2b interpolate samples/quarter-turn.yaml --samples 5
      a2b interpolate samples/quarter-turn.yaml --delta 0.2 --format tum -o turn.tum
      a2b interpolate samples/half-turn.yaml --mode cubic --m 1,0,0,0.5 -o turn.mcap -v
      cat samples/quarter-turn.yaml | a2b interpolate - --format mcap | cat > turn.mcap
      a2b interpolate samples/quarter-turn.yaml --format ros2 -o turn.mcap
    """
    import a2b

    from ..io.poseschema import read_poses

    out = options.pop_trajectory(parameters)
    out.update(options.pop_time_law(parameters))
    choices: list[str] = []
    with options.repairing(orthonormalize, choices):
        job = read_poses(poses)
        parameters = options.merge_parameters(job.parameters, parameters, mode)
    mode = options.pick("mode", mode, job.mode, "darboux", choices, "--mode")
    motion = a2b.motion(job.start, job.end, mode, **parameters)
    options.sample_and_write(motion, samples, job.samples, choices, verbose, out)
