"""What the tests of the command line share: running ``a2b`` through click's CliRunner, and
pose files with repr-exact numbers."""

from __future__ import annotations

import json
from pathlib import Path

from click.testing import CliRunner

from a2b.cli import cli
from a2b.formats import suffix_names
from a2b.io import poseschema
from a2b.poses import quat_trans_from_matrices

SAMPLES = Path(__file__).resolve().parent.parent / "samples"

#: The suffixes that choose a format, as -v names them (from the table of formats).
SUFFIXES = ", ".join(suffix_names())
BATCH_SUFFIXES = ", ".join(suffix_names(batch=True))


def run(*args, input=None):
    return CliRunner().invoke(
        cli, [str(a) for a in args], input=input, catch_exceptions=False, prog_name="a2b"
    )


def pose_json(matrix):
    """A pose mapping in quaternion form, with repr-exact numbers."""
    quat, trans = quat_trans_from_matrices(matrix)
    return {"quaternion_wxyz": quat.tolist(), "translation": trans.tolist()}


def write_poses(path, start, end, **extra):
    """A poses file with repr-exact numbers; returns its poses as a2b reads them, for
    :func:`a2b.motion` (``(quat_wxyz, translation)`` where the file gives a quaternion)."""
    data = {"start": pose_json(start), "end": pose_json(end), **extra}
    path.write_text(json.dumps(data))
    with open(path, "rb") as f:
        job = poseschema.read_poses(f)
    return job.poses()


def run_split(*args, input=None):
    """Run with stdout and stderr apart (``-v`` writes to stderr)."""
    return CliRunner().invoke(
        cli, [str(a) for a in args], input=input, catch_exceptions=False, prog_name="a2b"
    )


HALF_TURN_TRANSLATION = (
    "start: {quaternion_wxyz: [1, 0, 0, 0]}\nend: "
    "{quaternion_wxyz: [0, 0, 0, 1], translation: [0, 0, 1]}\n"
)
