"""The command line as a user meets it, through click's CliRunner.

Every output format is read back with its reader and compared with ``a2b.interpolate`` (or
the motion's own quaternions) bit for bit. Seeded random poses throughout.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

import a2b
from a2b.cli import COMMANDS, cli
from a2b.formats import suffix_names
from a2b.io import csvtable, documents, mcapposes, poseschema, trajectories
from a2b.poses import matrices_from_quat_trans, quat_trans_from_matrices

from .conftest import random_pose

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


@pytest.fixture
def poses(tmp_path, rng):
    start, end = random_pose(rng), random_pose(rng)
    path = tmp_path / "poses.json"
    a, b = write_poses(path, start, end)
    return path, a, b


# -- help, version ---------------------------------------------------------------------------


@pytest.mark.parametrize("name", list(COMMANDS))
def test_every_command_has_h_and_an_example(name):
    result = run(name, "-h")
    assert result.exit_code == 0
    assert result.output.startswith(f"Usage: a2b {name}")
    assert "Example:" in result.output


def test_group_help_lists_every_command_and_completion():
    result = run("-h")
    assert result.exit_code == 0
    for name in COMMANDS:
        assert name in result.output
    assert "_A2B_COMPLETE=bash_source a2b" in result.output


def test_version():
    result = run("--version")
    assert result.exit_code == 0
    assert result.output == f"a2b {a2b.__version__}\n"


def test_unknown_command_and_option_are_usage_errors(poses):
    path, _, _ = poses
    assert run("interpolat").exit_code == 2
    result = run("interpolate", path, "--samplez", "3")
    assert result.exit_code == 2
    assert "--samplez" in result.output and "Usage: a2b interpolate" in result.output
    assert run("interpolate", path, "--m", "1,2,3").exit_code == 2
    assert run("interpolate", path, "--delta", "nan").exit_code == 2
    assert run("interpolate", path, "--samples", "0").exit_code == 2
    assert run("interpolate", path, "--branch", "2").exit_code == 2


def _as_given(a, b, trans=None, mats=None):
    """Samples at t = 0 and t = 1 as written: A and B as given (their translations and, for
    matrices, the whole poses), not as the motion's formula rounds them."""
    a, b = (a2b.poses.pose_matrices(pose) for pose in (a, b))
    if trans is not None:
        trans[[0, -1]] = a[:3, 3], b[:3, 3]
        return trans
    mats = np.array(mats)
    mats[..., [0, -1], :, :] = a, b
    return mats


# -- interpolate: formats read back ----------------------------------------------------------


@pytest.mark.parametrize("mode", ["darboux", "cubic", "screw"])
def test_csv_round_trip(poses, tmp_path, mode):
    path, a, b = poses
    out = tmp_path / "out.csv"
    result = run("interpolate", path, "--mode", mode, "--samples", 33, "-o", out)
    assert result.exit_code == 0, result.output
    with open(out, "rb") as f:
        t, quat, trans = trajectories.read_csv(f)
    ts = np.linspace(0, 1, 33)
    want_quat, want_trans = a2b.motion(a, b, mode).quat_trans(ts)
    assert np.array_equal(t, ts)
    assert np.array_equal(quat, want_quat)
    assert np.array_equal(trans, _as_given(a, b, want_trans))
    assert np.allclose(
        matrices_from_quat_trans(quat, trans), a2b.interpolate(a, b, ts, mode), atol=1e-12
    )


def test_csv_is_the_default_on_stdout(poses):
    path, a, b = poses
    result = run("interpolate", path, "--samples", 3)
    assert result.exit_code == 0
    lines = result.output.splitlines()
    assert lines[0] == "t,tx,ty,tz,qw,qx,qy,qz"
    assert len(lines) == 4
    quat, trans = a2b.motion(a, b).quat_trans([0.0, 0.5, 1.0])
    assert lines[2] == ",".join(repr(float(v)) for v in [0.5, *trans[1], *quat[1]])


def test_matrix_round_trip(poses, tmp_path):
    path, a, b = poses
    out = tmp_path / "out.csv"
    assert run("interpolate", path, "--format", "matrix", "--samples", 17, "-o", out).exit_code == 0
    assert out.read_text().splitlines()[0] == "t,r11,r12,r13,tx,r21,r22,r23,ty,r31,r32,r33,tz"
    with open(out, "rb") as f:
        t, mats = trajectories.read_matrix_csv(f)
    assert np.array_equal(t, np.linspace(0, 1, 17))
    assert np.array_equal(mats, _as_given(a, b, mats=a2b.interpolate(a, b, t)))


def test_study_round_trip(poses, tmp_path):
    path, a, b = poses
    out = tmp_path / "out.csv"
    assert (
        run(
            "interpolate", path, "--format", "study", "--samples", 9, "-o", out, "--delta", 0.3
        ).exit_code
        == 0
    )
    with open(out, "rb") as f:
        t, study = trajectories.read_study_csv(f)
    want = a2b.api.pin_ends(motion := a2b.motion(a, b, delta=0.3), t, {"study": motion.study(t)})
    assert np.array_equal(study, want["study"])


def test_tum_round_trip(poses, tmp_path):
    path, a, b = poses
    out = tmp_path / "out.tum"
    result = run(
        "interpolate", path, "--samples", 11, "-o", out, "--duration", 2.5, "--start-time", 100
    )
    assert result.exit_code == 0
    text = out.read_text().splitlines()
    assert text[0].startswith("#")
    assert len(text[1].split(" ")) == 8
    with open(out, "rb") as f:
        time, quat, trans = trajectories.read_tum(f)
    ts = np.linspace(0, 1, 11)
    want_quat, want_trans = a2b.motion(a, b).quat_trans(ts)
    assert np.array_equal(time, ts * 2.5 + 100)
    assert np.array_equal(quat, want_quat)
    assert np.array_equal(trans, _as_given(a, b, want_trans))


def test_kitti_round_trip(poses, tmp_path):
    path, a, b = poses
    out = tmp_path / "out.txt"
    assert run("interpolate", path, "--format", "kitti", "--samples", 12, "-o", out).exit_code == 0
    lines = out.read_text().splitlines()
    assert len(lines) == 12 and all(len(line.split(" ")) == 12 for line in lines)
    with open(out, "rb") as f:
        mats = trajectories.read_kitti(f)
    assert np.array_equal(mats, _as_given(a, b, mats=a2b.interpolate(a, b, np.linspace(0, 1, 12))))


def test_mcap_round_trip(poses, tmp_path):
    path, a, b = poses
    out = tmp_path / "out.mcap"  # the suffix chooses the format
    result = run(
        "interpolate", path, "--samples", 21, "-o", out, "--duration", 3, "--start-time", 5
    )
    assert result.exit_code == 0
    ts = np.linspace(0, 1, 21)
    want_quat, want_trans = a2b.motion(a, b).quat_trans(ts)
    want_trans = _as_given(a, b, want_trans)
    for topic in ("/a2b/pose", "/tf"):
        with open(out, "rb") as f:
            time, quat, trans = mcapposes.read_mcap(f, topic)
        assert np.allclose(time, ts * 3 + 5, atol=1e-9, rtol=0)
        assert np.array_equal(quat, want_quat)
        assert np.array_equal(trans, want_trans)


def test_mcap_frame_ids_and_indexes(poses, tmp_path):
    from mcap.reader import make_reader

    path, _, _ = poses
    out = tmp_path / "out.mcap"
    args = (
        "interpolate",
        path,
        "--samples",
        4,
        "-o",
        out,
        "--frame-id",
        "map",
        "--child-frame-id",
        "tool",
    )
    assert run(*args).exit_code == 0
    with open(out, "rb") as f:
        reader = make_reader(f)
        summary = reader.get_summary()
        messages = [(c.topic, json.loads(m.data)) for _, c, m in reader.iter_messages()]
    assert summary.chunk_indexes and not summary.attachment_indexes and not summary.metadata_indexes
    assert {s.name for s in summary.schemas.values()} == {
        "foxglove.PoseInFrame",
        "foxglove.FrameTransform",
    }
    assert {s.encoding for s in summary.schemas.values()} == {"jsonschema"}
    assert {c.message_encoding for c in summary.channels.values()} == {"json"}
    assert summary.statistics.message_count == 8
    poses_ = [m for topic, m in messages if topic == "/a2b/pose"]
    tfs = [m for topic, m in messages if topic == "/tf"]
    assert len(poses_) == len(tfs) == 4
    assert poses_[0]["frame_id"] == "map"
    assert tfs[0]["parent_frame_id"] == "map" and tfs[0]["child_frame_id"] == "tool"
    assert tfs[-1]["timestamp"] == {"sec": 1, "nsec": 0}


def test_mcap_negative_time_is_an_error(poses, tmp_path):
    path, _, _ = poses
    out = tmp_path / "out.mcap"
    result = run("interpolate", path, "-o", out, "--start-time", -0.5)
    assert result.exit_code == 1
    assert "must be finite and not negative" in result.output
    assert not out.exists()


def test_parameters_from_file_and_command_line(tmp_path, rng):
    a, b = random_pose(rng), random_pose(rng)
    path = tmp_path / "p.json"
    a, b = write_poses(path, a, b, parameters={"delta": 0.4})
    out = tmp_path / "o.csv"
    ts = np.linspace(0, 1, 5)

    def matrices():
        with open(out, "rb") as f:
            _, mats = trajectories.read_matrix_csv(f)
        return mats

    assert run("interpolate", path, "--samples", 5, "--format", "matrix", "-o", out).exit_code == 0
    assert np.array_equal(matrices(), _as_given(a, b, mats=a2b.interpolate(a, b, ts, delta=0.4)))
    # the command line overrides the file, also across parameters that choose the same thing
    assert (
        run(
            "interpolate", path, "--samples", 5, "--format", "matrix", "-o", out, "--delta", -0.2
        ).exit_code
        == 0
    )
    assert np.array_equal(matrices(), _as_given(a, b, mats=a2b.interpolate(a, b, ts, delta=-0.2)))
    assert (
        run(
            "interpolate",
            path,
            "--samples",
            5,
            "--format",
            "matrix",
            "-o",
            out,
            "--pitch-start",
            0.1,
        ).exit_code
        == 0
    )
    assert np.array_equal(
        matrices(), _as_given(a, b, mats=a2b.interpolate(a, b, ts, pitch_start=0.1))
    )
    # --mode drops the file's parameters of other modes
    assert (
        run(
            "interpolate", path, "--samples", 5, "--format", "matrix", "-o", out, "--mode", "screw"
        ).exit_code
        == 0
    )
    assert np.array_equal(matrices(), _as_given(a, b, mats=a2b.interpolate(a, b, ts, "screw")))


def test_cubic_vector_options(poses, tmp_path):
    path, a, b = poses
    out = tmp_path / "o.csv"
    m = (1.0, 0.5, -0.25, 0.75)
    args = (
        "--mode",
        "cubic",
        "--m",
        "1,0.5,-0.25,0.75",
        "--a",
        0.1,
        "--b",
        -0.2,
        "--frame",
        "canonical",
    )
    result = run("interpolate", path, "--samples", 7, "--format", "matrix", "-o", out, *args)
    if result.exit_code == 1:  # this m may be orthogonal to a pose in canonical coordinates
        pytest.skip(result.output)
    assert result.exit_code == 0, result.output
    with open(out, "rb") as f:
        t, mats = trajectories.read_matrix_csv(f)
    want = a2b.interpolate(a, b, t, "cubic", m=m, a=0.1, b=-0.2, frame="canonical")
    assert np.array_equal(mats, _as_given(a, b, mats=want))


def test_through_option_reads_a_pose_file(tmp_path):
    half = np.eye(4)
    half[:3, :3] = [[0, -1, 0], [1, 0, 0], [0, 0, 1]]
    half[2, 3] = 1.0
    path = tmp_path / "p.json"
    a, b = write_poses(path, np.eye(4), half)
    third = a2b.interpolate(a, b, [0.3], delta=0.25)[0]
    through = tmp_path / "c.json"
    through.write_text(json.dumps({"matrix": third.tolist()}))
    out = tmp_path / "o.csv"
    assert (
        run(
            "interpolate",
            path,
            "--through",
            through,
            "--format",
            "matrix",
            "--samples",
            5,
            "-o",
            out,
        ).exit_code
        == 0
    )
    with open(out, "rb") as f:
        t, mats = trajectories.read_matrix_csv(f)
    assert np.allclose(mats, a2b.interpolate(a, b, t, delta=0.25), atol=1e-9)


def test_stdin(poses):
    path, _, _ = poses
    result = run("interpolate", "-", "--samples", 2, input=path.read_bytes())
    assert result.exit_code == 0
    assert result.output.splitlines()[2].startswith("1.0,")


def test_a2b_error_is_one_line_exit_1(tmp_path):
    path = tmp_path / "p.yaml"
    path.write_text(
        "start: {quaternion_wxyz: [1, 0, 0, 0]}\nend: "
        "{quaternion_wxyz: [1, 0, 0, 0], translation: [0, 0, "
        "1]}\n"
    )
    out = tmp_path / "o.csv"
    result = CliRunner().invoke(cli, ["interpolate", str(path), "--lam", "0.1", "-o", str(out)])
    assert result.exit_code == 1
    assert result.output.count("\n") == 1 and result.output.startswith("Error: ")
    assert "Traceback" not in result.output
    assert not out.exists()


def test_a_bug_keeps_its_traceback(poses, monkeypatch):
    path, _, _ = poses

    def broken(*args, **kwargs):
        raise RuntimeError("a bug")

    monkeypatch.setattr(a2b, "motion", broken)
    result = CliRunner().invoke(cli, ["interpolate", str(path)])
    assert result.exit_code == 1
    assert isinstance(result.exception, RuntimeError)


def test_failed_run_keeps_the_old_file(poses, tmp_path):
    path, _, _ = poses
    out = tmp_path / "o.csv"
    out.write_text("precious\n")
    result = run("interpolate", path, "-o", out, "--mode", "screw", "--delta", 1)
    assert result.exit_code == 1
    assert out.read_text() == "precious\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["o.csv", "poses.json"]


def test_output_into_missing_directory(poses, tmp_path):
    path, _, _ = poses
    result = run("interpolate", path, "-o", tmp_path / "nowhere" / "o.csv")
    assert result.exit_code == 1
    assert "cannot write" in result.output


# -- describe ---------------------------------------------------------------------------------


def test_describe_json_has_the_keys_of_a2b_describe(poses):
    path, a, b = poses
    for mode in ("darboux", "cubic", "screw"):
        result = run("describe", path, "--mode", mode, "--json")
        assert result.exit_code == 0, result.output
        got = json.loads(result.output)
        want = a2b.describe(a, b, mode)
        assert set(got) == set(want)
        assert got["phi"] == want["phi"] and got["choices"] == want["choices"]


def test_describe_human(tmp_path):
    path = tmp_path / "p.yaml"
    path.write_text(
        "start: {quaternion_wxyz: [1, 0, 0, 0]}\n"
        "end: "
        "{quaternion_wxyz: [0.7071067811865476, 0, 0, 0.7071067811865476], translation: [0, 0, "
        "1]}\n"
    )
    result = run("describe", path, "--lam", 1.5, "--branch", -1)
    assert result.exit_code == 0
    for text in ("φ", "λ, transmission curve amplitude", "1.5", "pitch at the start", "singular t"):
        assert text in result.output


# -- fiber ------------------------------------------------------------------------------------


@pytest.fixture
def pose_file(tmp_path, rng):
    path = tmp_path / "pose.json"
    pose = random_pose(rng)
    path.write_text(json.dumps({"matrix": pose.tolist()}))
    with open(path, "rb") as f:
        return path, poseschema.read_pose(f)


def test_fiber_kappa_json(pose_file):
    path, _ = pose_file
    result = run("fiber", path, "--offsets", "0,0.5,-2", "--json")
    assert result.exit_code == 0
    got = json.loads(result.output)
    assert got["map"] == "kappa"
    assert len(got["points"]) == 3 and all(len(p) == 8 for p in got["points"])
    assert max(got["residuals"]) < 1e-12
    assert got["s"] == [0.0, 0.5, -2.0]


def test_fiber_mu_json(pose_file):
    path, _ = pose_file
    result = run(
        "fiber",
        path,
        "--map",
        "mu",
        "--m",
        "1,0.3,-0.2,0.5",
        "--alpha",
        "0,0,0,0,0,0",
        "--alpha",
        "1,2,0,0,0,0.5",
        "--json",
    )
    assert result.exit_code == 0, result.output
    got = json.loads(result.output)
    assert got["basis_name"] == "paper" and not got["paper_basis_degenerate"]
    assert len(got["basis"]) == 6 and all(len(f) == 10 for f in got["basis"])
    assert len(got["points"]) == 2 and all(len(p) == 13 for p in got["points"])
    assert max(got["residuals"]) < 1e-9


def test_fiber_mu_says_when_the_paper_basis_degenerates(pose_file):
    path, _ = pose_file
    result = run("fiber", path, "--map", "mu", "--m", "1,0,0,0.5")
    assert result.exit_code == 0
    assert "degenerates" in result.output and "RREF" in result.output
    got = json.loads(run("fiber", path, "--map", "mu", "--m", "1,0,0,0.5", "--json").output)
    assert got["paper_basis_degenerate"] and got["basis_name"] == "rref"
    result = run("fiber", path, "--map", "mu", "--m", "1,0,0,0.5", "--basis", "paper")
    assert result.exit_code == 1 and "degenerates" in result.output


def test_fiber_human_table(pose_file):
    path, _ = pose_file
    result = run("fiber", path)
    assert result.exit_code == 0
    assert "maps back" in result.output and "εp" in result.output


def test_fiber_usage_errors(pose_file):
    path, _ = pose_file
    assert run("fiber", path, "--map", "mu").exit_code == 2
    assert run("fiber", path, "--alpha", "0,0,0,0,0,0").exit_code == 2
    assert run("fiber", path, "--map", "mu", "--m", "1,0,0,0", "--offsets", "1").exit_code == 2


# -- batch ------------------------------------------------------------------------------------


def _jobs(rng, n):
    jobs = []
    for i in range(n):
        a, b = random_pose(rng), random_pose(rng)
        job = {"start": pose_json(a), "end": pose_json(b), "samples": int(rng.integers(2, 6))}
        if i % 3 == 1:
            job["mode"] = "screw"
        if i % 3 == 2:
            job["parameters"] = {"delta": float(rng.normal())}
            job["name"] = f"job {i}, offset"
        jobs.append(job)
    return jobs


def _check_batch(jobs, out):
    with open(out, "rb") as f:
        names, values = csvtable.read_batch_csv(f)
    row = 0
    for i, job in enumerate(jobs):
        doc = documents.Document("x", None, lambda p: None)
        start = poseschema.pose_from_node(doc, (), job["start"])
        end = poseschema.pose_from_node(doc, (), job["end"])
        ts = np.linspace(0, 1, job["samples"])
        quat, trans = a2b.motion(
            start, end, job.get("mode", "darboux"), **job.get("parameters", {})
        ).quat_trans(ts)
        n = len(ts)
        assert names[row : row + n] == [job.get("name", f"job{i}")] * n
        assert np.array_equal(values[row : row + n, 0], ts)
        # batch builds the jobs together through the one core: the same to 1e-15 of their size
        scale = max(1.0, float(np.abs(trans).max()))
        np.testing.assert_allclose(values[row : row + n, 1:4], trans, rtol=0, atol=1e-15 * scale)
        np.testing.assert_allclose(values[row : row + n, 4:8], quat, rtol=0, atol=1e-15)
        row += n
    assert row == len(names)


@pytest.mark.parametrize("suffix", [".yaml", ".json", ".jsonl"])
def test_batch_more_jobs_than_one_chunk(tmp_path, rng, suffix):
    jobs = _jobs(rng, 8)
    path = tmp_path / f"jobs{suffix}"
    if suffix == ".jsonl":
        path.write_text("\n".join(json.dumps(j) for j in jobs) + "\n")
    else:
        path.write_text(json.dumps(jobs))
    out = tmp_path / "out.csv"
    result = run("batch", path, "--chunk-size", 3, "-o", out)
    assert result.exit_code == 0, result.output
    assert result.output == ""  # no progress bar when stderr is not a terminal
    assert out.read_text().splitlines()[0] == "job,t,tx,ty,tz,qw,qx,qy,qz"
    _check_batch(jobs, out)


def test_batch_streams_in_bounded_chunks(rng):
    from a2b.io.jobfiles import JobBlock
    from a2b.io.poseschema import Job
    from a2b.jobs import sample

    consumed = []

    def blocks():
        for i in range(3):
            consumed.append(i)
            jobs = [Job(random_pose(rng), random_pose(rng), samples=3) for _ in range(4)]
            yield JobBlock.from_jobs(jobs)

    pieces = sample(blocks())
    first = next(pieces)
    assert consumed == [0] and len(first.t) == 12
    assert [len(p.t) for p in pieces] == [12, 12]
    assert consumed == [0, 1, 2]


def test_batch_error_names_the_job_and_leaves_no_file(tmp_path, rng):
    jobs = _jobs(rng, 5)
    jobs[3]["parameters"] = {"lam": 1e-6}
    jobs[3]["mode"] = "darboux"
    path = tmp_path / "jobs.json"
    path.write_text(json.dumps(jobs))
    out = tmp_path / "out.csv"
    result = run("batch", path, "--chunk-size", 2, "-o", out)
    assert result.exit_code == 1
    assert "job job3: " in result.output
    assert not out.exists()
    assert [p.name for p in tmp_path.iterdir()] == ["jobs.json"]


def test_batch_sample_file():
    result = run("batch", SAMPLES / "jobs.yaml", "--format", "study")
    assert result.exit_code == 0
    lines = result.output.splitlines()
    assert lines[0] == "job,t,p0,p1,p2,p3,q0,q1,q2,q3"
    assert {line.split(",")[0] for line in lines[1:]} == {
        "lift",
        "lift_offset",
        "lift_cubic",
        "slide",
    }


@pytest.mark.parametrize("sample", ["quarter-turn", "half-turn", "translation", "canonical"])
def test_sample_files_run(sample):
    result = run("interpolate", SAMPLES / f"{sample}.yaml", "--samples", 5)
    assert result.exit_code == 0, result.output
    rows = [list(map(float, line.split(","))) for line in result.output.splitlines()[1:]]
    assert len(rows) == 5 and all(math.isfinite(v) for row in rows for v in row)


def test_batch_progress_bar_only_on_a_terminal(monkeypatch):
    import sys

    from a2b.cli.batch import _progress

    monkeypatch.setattr(sys.stderr, "isatty", lambda: False, raising=False)
    with _progress(3) as progress:
        assert progress is None
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True, raising=False)
    with _progress(3) as progress:
        assert progress is not None
        task = progress.add_task("jobs", total=3)
        progress.advance(task, 3)


# -- no silent fallbacks: -v and describe state every choice ----------------------------------


def run_split(*args, input=None):
    """Run with stdout and stderr apart (``-v`` writes to stderr)."""
    return CliRunner().invoke(
        cli, [str(a) for a in args], input=input, catch_exceptions=False, prog_name="a2b"
    )


HALF_TURN_TRANSLATION = (
    "start: {quaternion_wxyz: [1, 0, 0, 0]}\nend: "
    "{quaternion_wxyz: [0, 0, 0, 1], translation: [0, 0, 1]}\n"
)


def test_verbose_states_every_choice_on_stderr(tmp_path):
    path = tmp_path / "p.yaml"
    path.write_text(HALF_TURN_TRANSLATION)
    result = run_split("interpolate", path, "--lam", 2, "-v", "--samples", 3)
    assert result.exit_code == 0
    assert result.stdout.splitlines()[0] == "t,tx,ty,tz,qw,qx,qy,qz"
    lines = result.stderr.splitlines()
    assert lines[:3] == [
        "Choices a2b made:",
        "  • mode darboux: the default (--mode or the file to change)",
        f"  • format csv: the default (--format or an -o suffix {SUFFIXES} to change)",
    ]
    # the core's words for the half turn and the amplitude's branch, one line each
    assert len(lines) == 5 and lines[3].startswith("  • φ = π") and "d > 0" in lines[3]
    assert lines[4] == "  • lam has two mirror solutions ±|δ|; used branch +1"
    quiet = run_split("interpolate", path, "--lam", 2, "--samples", 3)
    assert quiet.stderr == "" and quiet.stdout == result.stdout


def test_verbose_names_the_axis_of_a_pure_translation_and_the_default_m(tmp_path):
    path = tmp_path / "p.yaml"
    path.write_text(
        "start: {quaternion_wxyz: [1, 0, 0, 0]}\nend: "
        "{quaternion_wxyz: [1, 0, 0, 0], translation: [1, 2, "
        "3]}\n"
    )
    err = run_split("interpolate", path, "--mode", "cubic", "-o", tmp_path / "o.mcap", "-v").stderr
    assert "  • format mcap: from the -o suffix .mcap (--format to change)" in err
    assert (
        "  • pure translation (φ = 0): the axis is the line through A's origin along the "
        "translation" in err
    )
    assert "  • m defaults to pA + pB in canonical coordinates, so both weights are equal" in err
    assert "mode" not in err  # given on the command line
    c, s = math.cos(math.radians(85)), math.sin(math.radians(85))  # turns of +170° and −170°
    path.write_text(
        f"start: {{quaternion_wxyz: [{c}, 0, 0, {s}]}}\nend: {{quaternion_wxyz: [{c}, 0, 0, "
        f"{-s}]}}\n"
    )
    err = run_split("interpolate", path, "-v", "--samples", 2).stderr
    assert "flipped the sign of B's quaternion so that pA·pB ≥ 0 (the short way round)" in err


@pytest.mark.parametrize(
    "command, sample, expected",
    [
        (
            "bezier",
            "planar-bezier.yaml",
            "m defaults to the sum of the control quaternions with consistent signs",
        ),
        ("spline", "spline.yaml", "inner control points by the uniform Catmull–Rom rule"),
    ],
)
def test_verbose_bezier_and_spline(command, sample, expected):
    result = run_split(command, SAMPLES / sample, "--samples", 3, "-v")
    assert result.exit_code == 0
    assert result.stderr.startswith("Choices a2b made:\n")
    assert expected in result.stderr


def test_verbose_batch_names_the_job_of_each_choice():
    result = run_split("batch", SAMPLES / "jobs.yaml", "-v", "--mode", "darboux", "--samples", 3)
    assert result.exit_code == 0
    assert result.stderr.splitlines() == [
        "Choices a2b made:",
        f"  • format csv: the default (--format or an -o suffix {BATCH_SUFFIXES} to change)",
        "  • job lift_cubic: m defaults to pA + pB in canonical coordinates, so both weights are "
        "equal",
        "  • job slide: pure translation (φ = 0): the axis is the line through A's origin along "
        "the translation",
    ]


def test_describe_states_the_default_mode_and_the_choices(tmp_path):
    path = tmp_path / "p.yaml"
    path.write_text(HALF_TURN_TRANSLATION)
    out = run("describe", path, "--lam", 2).output
    assert "Choices a2b made:" in out
    assert "mode darboux: the default" in out and "used branch +1" in out
    out = run("describe", path, "--mode", "screw").output
    assert (
        "mode darboux" not in out
        and "both axis orientations are short; chose the one with d > 0" in out
    )


def test_fiber_states_the_kernel_basis_it_chose(pose_file):
    path, _ = pose_file
    out = run("fiber", path, "--map", "mu", "--m", "1,0,0,0.5").output
    assert "Choices a2b made:" in out and "used the RREF basis" in out
    assert "Choices a2b made: none" in run("fiber", path).output


# -- bounded resources and absurd requests -----------------------------------------------------


@pytest.mark.parametrize(
    "n, size",
    [
        (n, size)
        for n in (2, 3, 7, 101, 65537, 200_003)
        for size in (1, 5, 65536)
        if n // size < 50_000
    ],
)
def test_evenly_spaced_chunks_are_linspace_bit_for_bit(n, size):
    from a2b.motions.base import evenly_spaced

    chunks = list(evenly_spaced(n, size))
    assert all(len(c) <= size for c in chunks)
    assert np.array_equal(np.concatenate(chunks), np.linspace(0.0, 1.0, n))


def test_streamed_output_equals_one_block(poses, tmp_path, monkeypatch):
    """Chunks of 7 samples give the same rows as one block, to rounding.

    The times are the same bytes; the entries may differ in the last bits only, because BLAS
    may round a block of 7 rows differently from a block of 50 (see ``a2b.motions._rational``).
    """
    from a2b import output

    path, _, _ = poses
    whole = run("interpolate", path, "--samples", 50, "--format", "matrix").output
    monkeypatch.setattr(output, "CHUNK_SAMPLES", 7)
    chunked = run("interpolate", path, "--samples", 50, "--format", "matrix").output
    a, b = whole.splitlines(), chunked.splitlines()
    assert a[0] == b[0] and len(a) == len(b) == 51
    assert [row.split(",")[0] for row in a] == [row.split(",")[0] for row in b]
    x = np.loadtxt(a[1:], delimiter=",")
    y = np.loadtxt(b[1:], delimiter=",")
    np.testing.assert_allclose(y, x, rtol=0, atol=8 * np.finfo(float).eps)


def test_batch_splits_a_large_job_into_bounded_chunks(rng):
    from a2b.io.jobfiles import JobBlock
    from a2b.io.poseschema import Job
    from a2b.jobs import sample

    jobs = [Job(random_pose(rng), random_pose(rng), samples=n) for n in (3, 25, 4)]
    pieces = list(sample([JobBlock.from_jobs(jobs)], rows=10))
    assert [len(p.t) for p in pieces] == [3, 10, 10, 5, 4]
    names = [name for p in pieces for name in p.job]
    assert names == ["job0"] * 3 + ["job1"] * 25 + ["job2"] * 4
    t = np.concatenate([p.t for p in pieces])
    assert np.array_equal(t[3:28], np.linspace(0, 1, 25))


@pytest.mark.parametrize(
    "args, message",
    [
        (["--samples", 1], "1 is not in the range 2<=x<=9007199254740992"),
        (["--samples", 0], "0 is not in the range"),
        (["--samples", -5], "-5 is not in the range"),
        (["--samples", 2**53 + 1], "is not in the range"),
        (["--duration", "inf"], "'inf' is not a decimal number"),
        (["--duration", "0"], "'0' is not greater than 0"),
        (["--duration", "nan"], "'nan' is not a decimal number"),
    ],
)
def test_absurd_requests_are_usage_errors(poses, args, message):
    path, _, _ = poses
    result = run_split("interpolate", path, *args)
    assert result.exit_code == 2
    assert message in result.stderr


@pytest.mark.parametrize(
    "args, message",
    [
        (["--format", "mcap", "--samples", 2**32 + 1],
         "MCAP numbers messages with 32-bit sequence numbers: at most 2**32 = 4294967296 "
         "samples, got 4294967297"),
        (["--format", "mcap", "--duration", 1e10],
         "MCAP log times are nanoseconds below 2**63 (the year 2262); the latest time is "
         "1e+10 s"),
        (["--format", "mcap", "--start-time", 9.3e9],
         "MCAP log times are nanoseconds below 2**63 (the year 2262); the latest time is "
         "9.3e+09 s"),
        (["--format", "mcap", "--start-time", -0.5],
         "MCAP times must be finite and not negative; the earliest time is -0.5 s"),
        (["--format", "tum", "--start-time", 1e308, "--duration", 1e308],
         "the time of t = 1, duration + start_time = 1e+308 + 1e+308, overflows a double"),
    ],
)  # fmt: skip
def test_what_a_format_cannot_hold_is_an_error_before_writing(poses, tmp_path, args, message):
    path, _, _ = poses
    out = tmp_path / "out.bin"
    result = run_split("interpolate", path, "-o", out, *args)
    assert result.exit_code == 1
    assert result.stderr == f"Error: {message}\n"
    assert not out.exists()


def test_a_pipe_gets_no_mcap_header_for_a_refused_request(poses):
    path, _, _ = poses
    result = run_split("interpolate", path, "--format", "mcap", "--start-time", -1)
    assert result.exit_code == 1 and result.stdout_bytes == b""


NON_FINITE_RESULTS = [
    ("interpolate",
     "end: {quaternion_wxyz: [0, 0, 0, 1], translation: [0, 0, 1]}\nparameters: {lam: 1e200}\n",
     "the motion's coefficients overflow float64"),
    ("describe", "end: {quaternion_wxyz: [1, 0, 0, 0], translation: [1.5e308, 1.5e308, 0]}\n",
     "the displacement from start to end overflows float64 (d = inf)"),
    ("describe",
     "end: {quaternion_wxyz: [0, 0, 0, 1], translation: [0, 0, 1]}\nparameters: {lam: 1e200}\n",
     "the motion's coefficients overflow float64"),
]  # fmt: skip


@pytest.mark.parametrize("command, end, message", NON_FINITE_RESULTS)
def test_results_that_overflow_are_refused(tmp_path, command, end, message):
    path = tmp_path / "p.yaml"
    path.write_text("start: {quaternion_wxyz: [1, 0, 0, 0]}\n" + end)
    args = ["-o", tmp_path / "o.csv"] if command == "interpolate" else ["--json"]
    result = run_split(command, path, *args)
    assert result.exit_code == 1
    assert result.stderr.startswith(f"Error: {message}") and result.stderr.count("\n") == 1
    assert result.stdout == ""
    assert sorted(p.name for p in tmp_path.iterdir()) == ["p.yaml"]


def test_batch_names_the_job_whose_samples_overflow(tmp_path):
    path = tmp_path / "jobs.yaml"
    path.write_text(
        "- {name: fine, start: {quaternion_wxyz: [1, 0, 0, 0]}, "
        "end: {quaternion_wxyz: [1, 0, 0, 0]}, samples: 2}\n"
        "- "
        "{name: huge, start: {quaternion_wxyz: [1, 0, 0, 0]}, end: {quaternion_wxyz: [0, 0, 0, 1], "
        "translation: [0, 0, 1]}, "
        "parameters: {lam: 1e200}}\n"
    )
    result = run_split("batch", path, "-o", tmp_path / "o.csv")
    assert result.exit_code == 1
    assert result.stderr.startswith("Error: job huge: the motion's coefficients overflow float64")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["jobs.yaml"]


# -- output targets that are no regular file -------------------------------------------------


def test_output_into_a_named_pipe_is_written_directly(poses, tmp_path):
    import os
    import threading

    path, _, _ = poses
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    received = []
    reader = threading.Thread(target=lambda: received.append(fifo.read_bytes()))
    reader.start()
    result = run("interpolate", path, "--samples", 3, "-o", fifo)
    reader.join(timeout=30)
    assert result.exit_code == 0
    assert received[0].decode().splitlines()[0] == "t,tx,ty,tz,qw,qx,qy,qz"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["pipe", "poses.json"]


def test_output_through_a_symbolic_link_replaces_the_file_it_points_to(poses, tmp_path):
    path, _, _ = poses
    target = tmp_path / "run-42.csv"
    target.write_text("old\n")
    link = tmp_path / "latest.csv"
    link.symlink_to(target.name)
    assert run("interpolate", path, "--samples", 3, "-o", link).exit_code == 0
    assert link.is_symlink() and target.read_text().startswith("t,tx")


# -- plot: Bézier and spline files ---------------------------------------------------------------


@pytest.mark.parametrize(
    "sample, args, title, marks",
    [
        ("planar-bezier.yaml", [], "Bézier motion of degree 3 (matrix space)", ["C1", "C2"]),
        (
            "planar-bezier.yaml",
            ["--space", "study"],
            "Bézier motion of degree 3 (study space)",
            ["C1", "C2"],
        ),
        ("spline.yaml", [], "C¹ spline of 4 cubic segments (matrix space)", ["P1", "P2", "P3"]),
    ],
)
def test_plot_draws_curve_files(tmp_path, sample, args, title, marks):
    pytest.importorskip("matplotlib")
    out = tmp_path / "curve.svg"
    result = run("plot", SAMPLES / sample, "-o", out, "--samples", 9, *args)
    assert result.exit_code == 0, result.output
    svg = out.read_text()
    assert title.replace("¹", "") in svg.replace("¹", "") or title in svg
    for mark in marks:
        assert f'id="mark:{mark}:x"' in svg
    assert 'id="screw-axis"' not in svg


@pytest.mark.parametrize(
    "args, message",
    [
        (
            ["--mode", "cubic"],
            "--mode is for two poses; this file is a list of controls (a Bézier motion)",
        ),
        (["--delta", "0.1", "--family"], "--family, --delta are for two poses"),
    ],
)
def test_plot_curve_files_refuse_options_for_two_poses(tmp_path, args, message):
    result = run_split("plot", SAMPLES / "planar-bezier.yaml", "-o", tmp_path / "x.png", *args)
    assert result.exit_code == 2
    assert f"Error: {message}" in result.stderr
    result = run_split(
        "plot", SAMPLES / "quarter-turn.yaml", "-o", tmp_path / "x.png", "--space", "study"
    )
    assert result.exit_code == 2 and "--space is for a list of controls or poses" in result.stderr
    assert list(tmp_path.iterdir()) == []


def test_describe_curve_files_states_their_choices():
    result = run_split("describe", SAMPLES / "spline.yaml", "--json")
    assert result.exit_code == 0
    got = json.loads(result.stdout)
    assert got["kind"] == "spline" and got["segments"] == 4 and got["space"] == "matrix"
    assert any("Catmull–Rom" in c for c in got["choices"])
    human = run_split("describe", SAMPLES / "planar-bezier.yaml", "--space", "study").stdout
    assert "a2b describe: Bézier motion" in human and "study" in human
    assert "Choices a2b made: none" in human  # the file says nothing a2b had to choose
    result = run_split("describe", SAMPLES / "spline.yaml", "--mode", "cubic")
    assert (
        result.exit_code == 2
        and "--mode is for two poses; this file is a list of poses (a spline)" in result.stderr
    )


def test_a_sensitive_result_is_one_warning_line_and_the_run_goes_on(tmp_path):
    half = 0.5e-4  # a turn of 1e-4 rad, taken the long way round: p(½) nearly vanishes
    path = tmp_path / "p.yaml"
    path.write_text(
        "start: {quaternion_wxyz: [1, 0, 0, 0]}\n"
        f"end: {{quaternion_wxyz: [{math.cos(half)!r}, 0, 0, {math.sin(half)!r}], translation: [1, "
        f"0, "
        f"0]}}\n"
        "parameters: {long_way: true}\n"
    )
    result = run_split("interpolate", path, "--samples", 3, "-o", tmp_path / "o.csv")
    assert result.exit_code == 0
    lines = result.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith(
        "Warning: the Darboux motion passes close to p(t) = 0"
    )
    assert (tmp_path / "o.csv").exists()


def test_batch_warnings_name_their_job(tmp_path):
    half = 0.5e-4
    job = (
        "  start: {quaternion_wxyz: [1, 0, 0, 0]}\n"
        f"  end: {{quaternion_wxyz: [{math.cos(half)!r}, 0, 0, {math.sin(half)!r}], translation: "
        f"[1, "
        f"0, 0]}}\n"
        "  parameters: {long_way: true}\n"
    )
    path = tmp_path / "jobs.yaml"
    path.write_text(f"- name: near\n{job}-\n{job}")
    result = run_split("batch", path, "--samples", 3)
    assert result.exit_code == 0
    lines = result.stderr.splitlines()
    assert len(lines) == 2
    assert lines[0].startswith("Warning: job near: the Darboux motion passes close to p(t) = 0")
    assert lines[1].startswith("Warning: job job1: the Darboux motion passes close to p(t) = 0")


def test_plot_refuses_more_samples_than_a_figure_shows(tmp_path):
    result = run_split(
        "plot", SAMPLES / "quarter-turn.yaml", "-o", tmp_path / "x.png", "--samples", 10**9
    )
    assert result.exit_code == 2 and "1000000000 is not in the range 2<=x<=100000" in result.stderr


def test_output_to_an_empty_name_or_a_read_only_file(poses, tmp_path):
    path, _, _ = poses
    result = run_split("interpolate", path, "-o", "")
    assert result.exit_code == 1 and result.stderr == "Error: cannot write to an empty file name\n"
    locked = tmp_path / "locked.csv"
    locked.write_text("keep\n")
    locked.chmod(0o444)
    result = run_split("interpolate", path, "-o", locked)
    assert result.exit_code == 1
    assert (
        result.stderr
        == f"Error: cannot write {locked}: Permission denied (the file is read-only)\n"
    )
    assert locked.read_text() == "keep\n"


@pytest.mark.parametrize(
    "end, d",
    [
        ("{quaternion_wxyz: [1, 0, 0, 0], translation: [1e308, 1e308, 0]}", 1e308 * 2**0.5),
        ("{quaternion_wxyz: [1, 0, 0, 0], translation: [1e200, 0, 0]}", 1e200),
        ("{quaternion_wxyz: [1, 0, 0, 0], translation: [3e-200, 4e-200, 0]}", 5e-200),
    ],
)
def test_a_length_that_is_a_double_is_no_overflow(tmp_path, end, d):
    """Lengths come from overflow-safe norms: only a length beyond a double is refused."""
    path = tmp_path / "p.yaml"
    path.write_text(f"start: {{quaternion_wxyz: [1, 0, 0, 0]}}\nend: {end}\n")
    result = run_split("describe", path, "--json")
    assert result.exit_code == 0, result.stderr
    assert json.loads(result.stdout)["d"] == pytest.approx(d, rel=1e-15)


EIGHTH_TURN = (
    "start: {quaternion_wxyz: [1, 0, 0, 0]}\n"
    "end: {quaternion_wxyz: [0.9238795325112867, 0, 0, 0.3826834323650898], "
    "translation: [0, 0, 1]}\n"
)
ANGLES = [("45deg", math.pi / 4), ("-90 deg", -math.pi / 2), ("0.5", 0.5)]


@pytest.mark.parametrize("spelling, radians", ANGLES)
def test_an_angle_takes_degrees_with_a_deg_suffix(tmp_path, spelling, radians):
    """--kappa 45deg means π/4; a number alone is radians, as the help says."""
    path = tmp_path / "p.yaml"
    path.write_text(EIGHTH_TURN)
    from_option = run_split("describe", path, "--json", "--kappa", spelling)
    path.write_text(EIGHTH_TURN + f"parameters: {{kappa: {spelling}}}\n")
    from_file = run_split("describe", path, "--json")
    for result in (from_option, from_file):
        if result.exit_code == 0:
            assert json.loads(result.stdout)["kappa"] == pytest.approx(radians, abs=1e-12)
        else:
            assert "κ is in radians; write 45deg for degrees" in result.stderr


def test_an_unreachable_kappa_says_radians():
    result = run_split("describe", SAMPLES / "canonical.yaml", "--kappa", "45")
    assert result.exit_code == 1
    assert "κ is in radians; write 45deg for degrees" in result.stderr
