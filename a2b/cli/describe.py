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
    from rich.console import Console
    from rich.table import Table
    from rich.text import Text

    console = Console()
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


@click.command(context_settings=CONTEXT_SETTINGS)
@click.argument("poses", type=options.INPUT)
@options.motion_options
@options.space_option
@options.json_option
@options.orthonormalize_option
def command(poses, mode, space, as_json, orthonormalize, **parameters):
    """Describe the motion between the two poses in POSES (a file, or - for stdin), or the
    Bézier motion or spline of a `controls:` or `poses:` file (with --space).

    Shows the canonical frame (rotation angle φ, translation d along the screw axis, the
    axis), the motion's essential parameters and its transmission curve (darboux: δ, z0, λ,
    κ and the pitches; cubic: m, m0, m3, a and b), any singular t, and every choice a2b
    made for you (the sign of B's quaternion, the axis of a pure translation, the branch of an
    amplitude, the default m, the mode if the file and the options give none). Pitches are
    translation per radian, dz/dω. --json prints the keys of a2b.describe.

    \b
    Example:
      a2b describe samples/quarter-turn.yaml
      a2b describe samples/canonical.yaml --lam 1.5 --branch -1 --json
      a2b describe samples/spline.yaml --space study
    """
    import json

    import a2b

    from ..io.readers import PoseList, read_motion_file

    defaults: list[str] = []
    with options.repairing(orthonormalize, defaults):
        job = read_motion_file(poses)
        if not isinstance(job, PoseList):
            parameters = options.merge_parameters(job.parameters, parameters, mode)
    if isinstance(job, PoseList):
        options.only_for_two_poses(job, mode=mode, **parameters)
        description = options.curve_motion(job, space, defaults).describe()
    else:
        if space:
            raise click.UsageError(
                "--space is for a list of controls or poses; this is a poses file"
            )
        mode = options.pick("mode", mode, job.mode, "darboux", defaults, "--mode")
        description = a2b.describe(job.start, job.end, mode, **parameters)
    options.check_finite(description, "describe")
    if as_json:
        click.echo(json.dumps(description, indent=2, allow_nan=False))
    else:
        render(description, defaults)
