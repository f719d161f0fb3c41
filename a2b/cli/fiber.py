"""``a2b fiber``: points of the fiber of one pose under κ or μ_[m], and the check that they map
back."""

from __future__ import annotations

import click

from . import CONTEXT_SETTINGS, options


def _fmt(values) -> str:
    return ", ".join(f"{v:.6g}" for v in values)


def render(result: dict) -> None:
    """Print the basis, the points and their residuals as rich tables."""
    from rich.table import Table
    from rich.text import Text

    console = options.console()
    if result["map"] == "kappa":
        console.print(Text(f"κ-fiber: points h + s εp; basis {result['basis_name']}"))
        console.print(Text(f"  h  = ({_fmt(result['basis'][0])})"))
        console.print(Text(f"  εp = ({_fmt(result['basis'][1])})"))
        table = Table(title=Text("fiber points (p0 … p3, q0 … q3)"))
        table.add_column("s", justify="right")
        labels = result["s"]
    else:
        if result["paper_basis_degenerate"] and result["basis_name"] != "rref":
            console.print(
                Text("Note: the paper's kernel basis (eq. 13) degenerates for this m (n0 = 0)."),
                style="yellow",
            )
        console.print(
            Text(
                f"μ_[m]-fiber, m = ({_fmt(result['m'])}), {result['basis_name']} basis f0 … f5 "
                f"(x0, a11 … a33):"
            )
        )
        basis = Table(show_header=False)
        for i, f in enumerate(result["basis"]):
            basis.add_row(Text(f"f{i}"), Text(_fmt(f)))
        console.print(basis)
        table = Table(title=Text("fiber points (x0, a11 … a33, t1 … t3)"))
        table.add_column("α", justify="right")
        labels = [_fmt(a) for a in result["alphas"]]
    table.add_column("point", overflow="fold")
    table.add_column("maps back to the pose: max |error|", justify="right")
    for label, point, residual in zip(labels, result["points"], result["residuals"]):
        table.add_row(Text(str(label)), Text(_fmt(point)), Text(f"{residual:.3g}"))
    console.print(table)
    choices = result.get("choices") or []
    console.print("Choices a2b made:" if choices else "Choices a2b made: none")
    for choice in choices:
        console.print(f"  • {choice}", highlight=False, markup=False, soft_wrap=True)


@click.command(context_settings=CONTEXT_SETTINGS)
@click.argument("pose", type=options.INPUT)
@click.option(
    "--map",
    "kind",
    type=click.Choice(["kappa", "mu"]),
    default="kappa",
    show_default=True,
    help="κ (extended dual-quaternion model, points of P^7) or μ_[m] (extended matrix model, "
    "points of R^13).",
)
@options.offsets_option("kappa: one fiber point h + s εp per offset s  [default: -1,0,1]")
@options.m_option("mu: the vector m of μ_[m] (required).")
@options.alphas_option(
    "mu: one fiber point (1, R) + Σ α_l f_l per --alpha  [default: 0 and each unit vector]"
)
@options.basis_option("mu: the kernel basis of M_m")
@options.json_option
@options.orthonormalize_option
def command(pose, kind, offsets, m, alphas, basis, as_json, orthonormalize):
    """Points of the fiber of the pose in POSE (a file with one pose, or - for stdin).

    A fiber is every point of the extended model that maps to the same pose. Under κ it is
    the line h + s εp (a2b uses the corrected form: docs/math.md, correction 1); under
    μ_[m] it is the 6-dimensional family (1, R) + Σ α_l f_l of affine matrices (eq. 15). Each point
    is mapped
    back, and the largest deviation from the pose is shown.

    \b
    Example:
      a2b fiber samples/pose.yaml --offsets 0,0.5
      a2b fiber samples/pose.yaml --map mu --m 1,0,0,0.5 --alpha 0,0,0,0,0,1 --json
    """
    import json

    from ..io.poseschema import read_pose

    if kind == "mu" and m is None:
        raise click.UsageError("--map mu needs --m, e.g. --m 1,0,0,0.5")
    if kind == "kappa" and (m is not None or alphas):
        raise click.UsageError("--m and --alpha belong to --map mu")
    if kind == "mu" and offsets:
        raise click.UsageError("--offsets belongs to --map kappa")
    if not offsets:
        offsets = (-1.0, 0.0, 1.0)
    if not alphas:
        alphas = [tuple(0.0 for _ in range(6))] + [
            tuple(float(i == j) for i in range(6)) for j in range(6)
        ]
    from ..fibers import fiber

    repairs: list[str] = []
    with options.repairing(orthonormalize, repairs):
        pose = read_pose(*options.read_pose_file(pose))
    result = fiber(pose, kind, s=offsets, m=m, alphas=alphas, basis=basis)
    result["choices"] = repairs + result["choices"]  # the repair is a choice the user sees
    options.check_finite(result, "fiber")
    from ..io.atomic import writing_stdout

    with writing_stdout():
        if as_json:
            click.echo(json.dumps(result, indent=2, allow_nan=False))
        else:
            render(result)
