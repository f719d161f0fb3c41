"""``a2b interpolate``: sample the motion between the two poses of a file."""

from __future__ import annotations

import click

from . import CONTEXT_SETTINGS, options, writing


@click.command(context_settings=CONTEXT_SETTINGS)
@click.argument("poses", type=options.INPUT)
@options.motion_options
@options.orthonormalize_option
@writing.trajectory_options
@options.time_law_options
def command(poses, mode, samples, verbose, orthonormalize, **parameters):
    """Sample the motion from the start to the end pose in POSES (a file, or - for stdin).

    POSES is JSON or YAML with `start` and `end` poses and, optionally, `mode`, `samples` and
    `parameters`; options given here override the file. Every format keeps full precision:
    each number reads back as the same double. Samples are computed and written in chunks,
    so any count runs in bounded memory (`--samples 1000000000 | head` starts at once).

    --format lists the formats and what a line or message of each holds.

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

    out = writing.pop_trajectory(parameters)
    out.update(options.pop_time_law(parameters))
    choices: list[str] = []
    with options.repairing(orthonormalize, choices):
        job = read_poses(*options.read_pose_file(poses))
        parameters = options.merge_parameters(job.parameters, parameters, mode)
    mode = options.pick("mode", mode, job.mode, "darboux", choices, "--mode")
    motion = a2b.motion(*job.poses(), mode, **parameters)
    writing.sample_and_write(motion, samples, job.samples, choices, verbose, out)
