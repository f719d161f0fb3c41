"""Samples at t = 0 and t = 1 are A and B exactly as given (issue 27): the translations, and
the quaternions bit for bit where the file gives quaternions, in every output and every
path that samples (interpolate, a time law, batch, the library)."""

from __future__ import annotations

import numpy as np
import pytest
from click.testing import CliRunner

import a2b
from a2b.cli import cli

ISSUE = """start:
  quaternion_xyzw: [0, 0, 0, 1]
  translation: [0.45, 0.1, 0.3]
end:
  quaternion_xyzw: [1, 0, 0, 0]
  translation: [0.45, 0.7, 0.3]
"""
#: Unit quaternions that a matrix does not give back bit for bit.
ODD = """start:
  quaternion_wxyz: [0.2, 0.3, 0.5, 0.7874007874011811]
  translation: [0.45, 0.1, 0.3]
end:
  quaternion_xyzw: [0.1, 0.7, 0.1, 0.7]
  translation: [0.3, 0.7, 0.1]
"""
ROWS = {
    ISSUE: ("0.45,0.1,0.3,1.0,0.0,0.0,0.0", "0.45,0.7,0.3,0.0,1.0,0.0,0.0"),
    ODD: ("0.45,0.1,0.3,0.2,0.3,0.5,0.7874007874011811", "0.3,0.7,0.1,0.7,0.1,0.7,0.1"),
}


def run(*args) -> list[str]:
    result = CliRunner().invoke(cli, [str(a) for a in args])
    assert result.exit_code == 0, result.output
    return result.output.splitlines()


@pytest.mark.parametrize("text", [ISSUE, ODD], ids=["issue", "odd"])
@pytest.mark.parametrize("mode", ["darboux", "screw", "cubic"])
def test_the_first_and_last_rows_are_the_poses_as_written(tmp_path, text, mode):
    path = tmp_path / "poses.yaml"
    path.write_text(text)
    rows = run("interpolate", path, "--samples", 5, "--mode", mode)
    first, last = ROWS[text]
    assert rows[1] == "0.0," + first and rows[-1] == "1.0," + last


def test_the_quarter_turn_sample_ends_as_written():
    rows = run("interpolate", "samples/quarter-turn.yaml", "--samples", 7, "--mode", "screw")
    assert rows[1] == "0.0,0.0,0.0,0.0,1.0,0.0,0.0,0.0"
    assert rows[-1] == "1.0,1.0,1.0,0.5,0.7071067811865476,0.0,0.0,0.7071067811865476"


@pytest.mark.parametrize("text", [ISSUE, ODD], ids=["issue", "odd"])
def test_study_rows_at_the_ends_are_those_of_the_given_poses(tmp_path, text):
    path = tmp_path / "poses.yaml"
    path.write_text(text)
    with open(path, "rb") as f:
        job = a2b.io.poseschema.read_poses(f)
    want = a2b.poses.study_from_quat_trans(
        np.array([q for q, _ in job.poses()]), np.array([t for _, t in job.poses()])
    )
    for mode in ("darboux", "screw", "cubic"):
        rows = run("interpolate", path, "--samples", 4, "--mode", mode, "--format", "study")
        got = np.array([[float(x) for x in rows[i].split(",")[1:]] for i in (1, -1)])
        assert np.array_equal(got, want), mode


def test_a_time_law_starts_and_ends_at_the_poses_as_written(tmp_path):
    path = tmp_path / "poses.yaml"
    path.write_text(ODD)
    rows = run("interpolate", path, "--duration", 2, "--rate", 10, "--time-law", "quintic")
    first, last = ROWS[ODD]
    assert rows[1] == "0.0," + first and rows[-1] == "2.0," + last


def test_batch_rows_at_the_ends_agree_with_interpolate(tmp_path):
    jobs = tmp_path / "jobs.yaml"
    jobs.write_text("- name: j\n" + "".join("  " + line + "\n" for line in ISSUE.splitlines()))
    rows = run("batch", jobs, "--samples", 5, "-o", "-")
    first, last = ROWS[ISSUE]
    assert rows[1] == "j,0.0," + first and rows[-1] == "j,1.0," + last


def test_the_library_keeps_the_quaternions_it_was_given():
    qa = np.array([0.2, 0.3, 0.5, 0.7874007874011811])
    qb = -np.array([0.7, 0.1, 0.7, 0.1])  # the other sign: the same rotation
    for mode in ("darboux", "screw", "cubic"):
        motion = a2b.motion((qa, [0.45, 0.1, 0.3]), (qb, [0.3, 0.7, 0.1]), mode)
        quat, trans = motion.quat_trans([0.0, 0.5, 1.0])
        assert np.array_equal(quat[0], qa)
        assert np.array_equal(np.abs(quat[-1]), -qb), mode  # at the sign the motion uses
        mats = a2b.interpolate((qa, [0.45, 0.1, 0.3]), (qb, [0.3, 0.7, 0.1]), [0, 1], mode)
        assert np.array_equal(mats[0][:3, 3], [0.45, 0.1, 0.3])
        assert np.array_equal(mats[1][:3, 3], [0.3, 0.7, 0.1])


def test_a_batch_of_motions_keeps_its_end_quaternions():
    rng = np.random.default_rng(7)
    q = rng.normal(size=(2, 5, 4))
    q /= np.linalg.norm(q, axis=-1, keepdims=True)
    t = rng.normal(size=(2, 5, 3))
    motion = a2b.motion((q[0], t[0]), (q[1], t[1]), "screw")
    quat, _ = motion.quat_trans([0.0, 1.0])
    assert np.array_equal(np.abs(quat[:, 0]), np.abs(q[0]))
    assert np.array_equal(np.abs(quat[:, 1]), np.abs(q[1]))


def test_batch_translations_at_the_ends_are_as_written(tmp_path):
    """(A jobs file's quaternions reach the motion through the matrices: the translations are
    as written, the quaternions to the last bit or two.)"""
    jobs = tmp_path / "jobs.yaml"
    jobs.write_text("- name: j\n" + "".join("  " + line + "\n" for line in ODD.splitlines()))
    rows = run("batch", jobs, "--samples", 5, "-o", "-")
    assert rows[1].split(",")[2:5] == ["0.45", "0.1", "0.3"]
    assert rows[-1].split(",")[2:5] == ["0.3", "0.7", "0.1"]
