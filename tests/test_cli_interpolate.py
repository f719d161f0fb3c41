"""``a2b interpolate``: every output format read back with its reader and compared with
``a2b.interpolate`` bit for bit, parameters, stdin, -v, streaming and what a format cannot hold.

Through click's CliRunner."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import a2b
from a2b.io import mcapposes, trajectories
from a2b.poses import matrices_from_quat_trans

from .clirun import HALF_TURN_TRANSLATION, SAMPLES, SUFFIXES, run, run_split, write_poses
from .conftest import random_pose


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


@pytest.mark.parametrize("sample", ["quarter-turn", "half-turn", "translation", "canonical"])
def test_sample_files_run(sample):
    result = run("interpolate", SAMPLES / f"{sample}.yaml", "--samples", 5)
    assert result.exit_code == 0, result.output
    rows = [list(map(float, line.split(","))) for line in result.output.splitlines()[1:]]
    assert len(rows) == 5 and all(math.isfinite(v) for row in rows for v in row)


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
