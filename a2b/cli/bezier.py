"""``a2b bezier``: sample the Bézier motion of the control poses of a file.

Also the reader of curve files, shared with ``a2b spline`` (:mod:`a2b.cli.spline`): a mapping
with a list of poses under ``controls`` (bezier) or ``poses`` (spline), each in any pose form
of ``a2b interpolate``, and optionally ``space``, ``samples`` and ``parameters``.
"""

from __future__ import annotations

import sys
from dataclasses import dataclass, field
from typing import IO

import click

from . import CONTEXT_SETTINGS, options

SPACES = ("matrix", "study")
BASES = ("paper", "rref", "auto")
#: Parameters a curve file may give, per list key: name -> kind ("m": 4 numbers, "per-control":
#: one number per pose, "per-control-6": 6 numbers per pose, "basis": a kernel basis name).
CURVE_PARAMETERS = {
    "controls": {
        "m": "m",
        "weights": "per-control",
        "alphas": "per-control-6",
        "basis": "basis",
        "offsets": "per-control",
    },
    "poses": {"m": "m"},
}


@dataclass(frozen=True)
class CurveFile:
    """The poses of a curve file (robotics 4x4 matrices, ``(k, 4, 4)``) and what it says.

    ``space`` and ``samples`` are ``None`` where the file does not give them; ``parameters``
    holds only the keys the file gives.
    """

    poses: object
    space: str | None = None
    samples: int | None = None
    parameters: dict = field(default_factory=dict)


def read_curve_file(stream: IO, key: str, name: str | None = None) -> CurveFile:
    """Read a curve file: a list of poses under ``key`` (``controls`` or ``poses``).

    Every pose is read by the pose parser of :mod:`a2b.io.readers`, so every pose form works
    and errors name the file, the line and column and the key, e.g.
    ``curve.yaml:7:5: controls[2].quaternion: expected 4 numbers (w, x, y, z), got 3``.

    Raises
    ------
    InputFileError
    """
    import numpy as np

    from ..io import readers as r

    name = r._stream_name(stream, name)
    doc = r._parse(r._read_text(stream, name), name, r._kind_from_suffix(name))
    top = r._mapping(doc, (), doc.data, f"a mapping with {key}")
    r._check_keys(doc, (), top, (key, "space", "samples", "parameters"), f"a {key} file")
    if key not in top:
        raise doc.error((), f"missing {key!r}: a list of at least two poses")
    items = top[key]
    if not isinstance(items, list) or len(items) < 2:
        got = f"{len(items)}" if isinstance(items, list) else r._describe(items)
        raise doc.error((key,), f"expected a list of at least two poses, got {got}")
    poses = np.stack([r._pose(doc, (key, i), item) for i, item in enumerate(items)])
    k = len(items)
    space = top.get("space")
    if space is not None and space not in SPACES:
        raise doc.error(
            ("space",), f"expected one of {', '.join(SPACES)}, got {r._describe(space)}"
        )
    samples = top.get("samples")
    if samples is not None and (
        not isinstance(samples, int) or isinstance(samples, bool) or samples < 1
    ):
        shown = samples if r._is_number(samples) else r._describe(samples)
        raise doc.error(("samples",), f"expected a positive whole number, got {shown}")
    given = r._mapping(
        doc, ("parameters",), top.get("parameters") or {}, "a mapping of curve parameters"
    )
    kinds = CURVE_PARAMETERS[key]
    r._check_keys(doc, ("parameters",), given, tuple(kinds), "parameters")
    parameters = {}
    for pname, value in given.items():
        here = ("parameters", pname)
        kind = kinds[pname]
        if value is None:
            continue
        if kind == "m":
            parameters[pname] = tuple(r._numbers(doc, here, value, 4, "(m0, m1, m2, m3)"))
        elif kind == "per-control":
            parameters[pname] = tuple(r._numbers(doc, here, value, k, f"(one per pose in {key})"))
        elif kind == "per-control-6":
            if not isinstance(value, list) or len(value) != k:
                got = len(value) if isinstance(value, list) else r._describe(value)
                raise doc.error(
                    here, f"expected {k} lists of 6 numbers (one per pose in {key}), got {got}"
                )
            rows = [
                r._numbers(doc, here + (i,), row, 6, "(α0 … α5)") for i, row in enumerate(value)
            ]
            parameters[pname] = tuple(tuple(row) for row in rows)
        else:
            if value not in BASES:
                raise doc.error(
                    here, f"expected one of {', '.join(BASES)}, got {r._describe(value)}"
                )
            parameters[pname] = value
    return CurveFile(poses, space, samples, parameters)


class NumberList(click.ParamType):
    """Comma-separated finite numbers, any count, as in ``--weights 1,2,2,1``."""

    name = "NUMBERS"

    def convert(self, value, param, ctx):
        if isinstance(value, tuple):
            return value
        return tuple(options.FLOAT.convert(p.strip(), param, ctx) for p in str(value).split(","))


def space_option(f):
    return click.option(
        "--space",
        type=click.Choice(SPACES),
        help="Build the curve in R^13 and map it by μ_[m] (matrix, default), or over unit Study "
        "vectors and map it by κ (study).",
    )(f)


def format_option(f):
    return click.option(
        "--format",
        "fmt",
        type=click.Choice(options.FORMATS),
        help="Output format  [default: from the -o suffix (.mcap, .tum, .kitti), else csv]",
    )(f)


def write_motion(
    motion, samples, fmt, output, duration, start_time, frame_id, child_frame_id
) -> None:
    """Sample ``motion`` at ``samples`` equally spaced t in [0, 1] and write it like ``interpolate``."""
    import numpy as np

    from ..io.atomic import atomic_output
    from ..io.writers import REPRESENTATION, sample_chunks, write_samples

    fmt = options.format_from(fmt, output)
    if fmt == "mcap" and output == "-" and sys.stdout.isatty():
        raise click.UsageError(
            "MCAP is binary: write it with -o FILE or into a pipe, not to a terminal"
        )
    ts = np.linspace(0.0, 1.0, samples)
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


@click.command(context_settings=CONTEXT_SETTINGS)
@click.argument("poses", type=click.File("rb"))
@space_option
@click.option(
    "--m",
    "m",
    type=options.Vector(4, "m0, m1, m2, m3"),
    help="matrix: the vector m of μ_[m], e.g. 1,0,0,0.5  [default: the sum of the control quaternions]",
)
@click.option(
    "--weights",
    type=NumberList(),
    help="Positive weights, one per control pose, e.g. 1,2,2,1 (a rational curve).",
)
@click.option(
    "--alpha",
    "alphas",
    type=options.Vector(6, "α0 … α5"),
    multiple=True,
    help="matrix: fiber coordinates α of a control pose in the kernel basis; repeat once per control pose, in order.",
)
@click.option(
    "--basis",
    type=click.Choice(BASES),
    help="matrix: the kernel basis of --alpha (default paper, eq. 13).",
)
@click.option(
    "--offsets",
    type=NumberList(),
    help="study: κ-fiber offsets s, one per control pose (h + s ε p).",
)
@options.samples_option
@format_option
@options.output_option
@options.timing_options
@options.frame_options
def command(
    poses, space, samples, fmt, output, duration, start_time, frame_id, child_frame_id, **parameters
):
    """Sample the Bézier motion of the control poses in POSES (a file, or - for stdin).

    POSES is JSON or YAML with a list `controls` of at least two poses, in any pose form of
    `a2b interpolate`, and optionally `space`, `samples` and `parameters` (m, weights, alphas,
    basis, offsets); options given here override the file. The curve has degree k − 1 for k
    controls and passes through the first control (t = 0) and the last (t = 1).

    \b
    matrix  de Casteljau over the control poses' points (1, R, t) of R^13, mapped by μ_[m]
            in the given frame (the paper's outlook, figure 4); two controls give the cubic
            mode with --frame given
    study   de Casteljau over unit Study vectors with consistent signs, mapped by κ; two
            controls give the darboux mode (δ = s1 − s0)

    Output formats and options as for `a2b interpolate`.

    \b
    Example:
      a2b bezier samples/planar-bezier.yaml --samples 5
      a2b bezier samples/planar-bezier.yaml --space study --format tum -o planar.tum
      a2b bezier samples/planar-bezier.yaml --weights 1,2,2,1 --format mcap -o planar.mcap
    """
    from ..motions.bezier import bezier_motion

    curve = read_curve_file(poses, "controls")
    given = dict(parameters)
    given["alphas"] = given["alphas"] or None
    merged = options.merge_parameters(curve.parameters, given)
    motion = bezier_motion(curve.poses, space or curve.space or "matrix", **merged)
    write_motion(
        motion,
        samples or curve.samples or 101,
        fmt,
        output,
        duration,
        start_time,
        frame_id,
        child_frame_id,
    )
