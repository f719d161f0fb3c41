"""``a2b describe``: the canonical frame and the essential parameters of a motion."""

from __future__ import annotations

import click

from . import CONTEXT_SETTINGS, options

#: How ``a2b describe`` labels the keys of :func:`a2b.describe` in its table.
LABELS = {
    "mode": "mode",
    "phi": "φ, rotation angle of B A⁻¹ (rad)",
    "phi_degrees": "φ (degrees)",
    "d": "d, translation along the screw axis",
    "axis_point": "screw axis: point",
    "axis_direction": "screw axis: direction",
    "delta": "δ = sB − sA, fiber offset",
    "z0": "z0, transmission curve offset",
    "lam": "λ, transmission curve amplitude",
    "kappa": "κ, transmission curve phase (rad)",
    "pitch_start": "pitch at the start, dz/dω",
    "pitch_end": "pitch at the end, dz/dω",
    "m": "m of μ_[m]",
    "a": "a (essential scalar of the start)",
    "b": "b (essential scalar of the end)",
    "transmission_curve": "transmission curve",
    "singular_t": "singular t",
    "kind": "kind",
    "space": "space",
    "degree": "degree of each segment",
    "segments": "segments",
    "joints": "t where segments meet",
    "weights": "weights of the controls",
    "offsets": "κ-fiber offsets of the controls",
    "x0": "x0 of the controls",
    "rotation_weights": "rotation weights 4 m·p of the controls",
    "poses": "key poses",
}


def _number(value) -> str:
    if isinstance(value, bool) or value is None:
        return str(value).lower() if value is not None else "—"
    if isinstance(value, float):
        return f"{value:.10g}"
    if isinstance(value, (list, tuple)):
        return "(" + ", ".join(_number(v) for v in value) + ")" if value else "none"
    return str(value)


def render(description: dict, defaults: list | None = None) -> None:
    """Print ``description`` as a rich table, then the choices a2b made (``defaults`` first)."""
    from rich.table import Table
    from rich.text import Text

    console = options.console()
    what = f"{description['mode']} motion" if "mode" in description else description.get("kind", "")
    table = Table(title=Text(f"a2b describe: {what}"), show_header=True)
    table.add_column("quantity")
    table.add_column("value", overflow="fold")
    for key, value in description.items():
        if key == "choices":
            continue
        table.add_row(Text(LABELS.get(key, key.replace("_", " "))), Text(_number(value)))
    console.print(table)
    choices = list(defaults or []) + list(description.get("choices") or [])
    console.print("Choices a2b made:" if choices else "Choices a2b made: none")
    for choice in choices:
        console.print(f"  • {choice}", highlight=False, markup=False, soft_wrap=True)


#: Rows of the time-law table: key of :meth:`a2b.timelaw.TimedMotion.describe` and label.
LAW_ROWS = {
    "profile": "time law",
    "duration": "duration (s)",
    "path_length": "path length of the point",
    "speed": "peak speed of the point (/s)",
    "accel": "peak acceleration along the path (/s²)",
    "jerk": "peak jerk along the path (/s³)",
    "total_accel": "peak total acceleration, centripetal included (/s²)",
    "angular_speed": "peak angular speed (rad/s)",
    "angular_accel": "peak angular acceleration (rad/s²)",
    "degree": "degree of the pose entries in t",
    "binding": "binding limit",
}


def law_figures(motion, law: dict, duration) -> dict:
    """The time-law figures of ``motion``: :meth:`TimedMotion.describe`, flattened, and the
    degree of its pose entries (the table's basis; the screw motion is not rational)."""
    timed = options.time_law(motion, law, duration, [], always=True)
    out = timed.describe()
    peaks = out.pop("peaks")
    out.update(peaks)
    degree = getattr(motion, "pose_degree", None)  # a mode's; else a Bézier motion's tables
    out["degree"] = degree() if degree else int(motion._tables().shape[-2] - 1)
    out["binding"] = out["binding"] or "duration"
    if out["profile"] in ("linear", "trapezoid"):  # steps in σ̈ (trapezoid) or σ̇ (linear)
        out["jerk"] = "unbounded (the acceleration steps)"
        if out["profile"] == "linear":
            out["accel"] = "unbounded (starts and stops at once)"
    return out


def render_law(columns: dict) -> None:
    """One table of the time-law figures, a column per motion."""
    from rich.table import Table
    from rich.text import Text

    table = Table(title=Text("a2b describe: time law"), show_header=True)
    table.add_column("quantity")
    for name in columns:
        table.add_column(name, overflow="fold")
    for key, label in LAW_ROWS.items():
        table.add_row(Text(label), *(Text(_number(c[key])) for c in columns.values()))
    options.console().print(table)


@click.command(context_settings=CONTEXT_SETTINGS)
@click.argument("poses", type=options.INPUT)
@options.motion_options
@options.space_option
@options.json_option
@options.orthonormalize_option
@click.option("--duration", type=options.PositiveFloat(), help="The time law's duration (s).")
@options.time_law_options(sampling=False)
@click.option(
    "--compare",
    is_flag=True,
    help="The time-law figures of darboux, cubic and screw side by side (defaults of each).",
)
def command(poses, mode, space, as_json, orthonormalize, duration, compare, **parameters):
    """Describe the motion between the two poses in POSES (a file, or - for stdin), or the
    Bézier motion or spline of a `controls:` or `poses:` file (with --space).

    Shows the canonical frame (rotation angle φ, translation d along the screw axis, the
    axis), the motion's essential parameters and its transmission curve (darboux: δ, z0, λ,
    κ and the pitches; cubic: m, m0, m3, a and b), any singular t, and every choice a2b
    made for you (the sign of B's quaternion, the axis of a pure translation, the branch of an
    amplitude, the default m, the mode if the file and the options give none). Pitches are
    translation per radian, dz/dω. --json prints the keys of a2b.describe.

    With a time law (--duration, a limit, --time-law or --constant-speed; see `a2b
    interpolate`) it also reports the duration, the path length of the point, the peaks of
    its speed, of its acceleration and jerk along the path and of its total acceleration, the
    peak angular speed and acceleration, the degree of the motion and the binding limit.
    --compare puts these figures side by side for darboux, cubic and screw.

    \b
    Example:
      a2b describe samples/quarter-turn.yaml
      a2b describe samples/canonical.yaml --lam 1.5 --branch -1 --json
      a2b describe samples/spline.yaml --space study
      a2b describe samples/quarter-turn.yaml --max-speed 1 --max-accel 2 --compare
    """
    import json

    import a2b

    from ..io.poseschema import PoseList, read_motion_file

    law = options.figure_law(parameters)
    timed = compare or duration is not None or options.law_given(law)

    defaults: list[str] = []
    with options.repairing(orthonormalize, defaults):
        job = read_motion_file(*options.read_pose_file(poses))
        if not isinstance(job, PoseList):
            parameters = options.merge_parameters(job.parameters, parameters, mode)
    if isinstance(job, PoseList):
        if compare:
            raise click.UsageError("--compare is for the two-pose modes; this is a pose list")
        options.only_for_two_poses(job, mode=mode, **parameters)
        motion = options.curve_motion(job, space, defaults)
        description = motion.describe()
        motions = {motion.kind: motion}
    else:
        if space:
            raise click.UsageError(
                "--space is for a list of controls or poses; this is a poses file"
            )
        if compare and (mode or parameters_given(parameters)):
            raise click.UsageError(
                "--compare shows each mode with its defaults: give no --mode or motion parameter"
            )
        modes = options.MODES if compare else None
        if not compare:
            mode = options.pick("mode", mode, job.mode, "darboux", defaults, "--mode")
            modes = (mode,)
        motions = {
            m: a2b.motion(job.start, job.end, m, **({} if compare else parameters)) for m in modes
        }
        description = None if compare else motions[mode].describe()
    out = {}
    if description is not None:
        out = dict(description)
    if timed:
        figures = {name: law_figures(m, law, duration) for name, m in motions.items()}
        if compare:
            out = {"compare": figures}
        else:
            out["time_law"] = next(iter(figures.values()))
    options.check_finite(out, "describe")
    from ..io.atomic import writing_stdout

    with writing_stdout():
        if as_json:
            click.echo(json.dumps(out, indent=2, allow_nan=False))
            return
        if description is not None:
            out.pop("time_law", None)
            render(out, defaults)
        if timed:
            render_law(figures)


def parameters_given(parameters: dict) -> bool:
    return any(v not in (None, False, ()) for v in parameters.values())
