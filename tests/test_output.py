"""The writing pipeline of the library (:mod:`a2b.output`): ``a2b.write`` writes what the
commands write, with the same checks, atomicity and streaming."""

from __future__ import annotations

import io

import numpy as np
import pytest
from click.testing import CliRunner

import a2b
from a2b.cli import cli
from a2b.errors import A2bError, OptionError, ParameterError
from a2b.samples import Samples

from .conftest import NonSeekableStream, random_pose

TILTED = """start:
  quaternion_wxyz: [0.9, 0.1, -0.3, 0.2]
  translation: [0.45, -0.7, 0.3]
end:
  quaternion_wxyz: [0.2, 0.5, 0.1, -0.8]
  translation: [0.1, 0.25, 1.3]
"""


def run(*args, input=None):
    return CliRunner().invoke(cli, [str(a) for a in args], input=input, catch_exceptions=False)


@pytest.fixture
def motion(rng):
    return a2b.motion(random_pose(rng), random_pose(rng))


@pytest.mark.parametrize("fmt", ["csv", "matrix", "study", "tum", "kitti", "mcap", "ros2"])
def test_write_writes_the_bytes_of_the_command(tmp_path, fmt):
    path = tmp_path / "poses.yaml"
    path.write_text(TILTED)
    timing = ("--duration", 2, "--start-time", 7) if fmt in ("tum", "mcap", "ros2") else ()
    command = tmp_path / "command.out"
    assert (
        run("interpolate", path, "--samples", 9, "--format", fmt, "-o", command, *timing).exit_code
        == 0
    )
    from a2b.io.poseschema import read_poses

    with open(path, "rb") as f:
        job = read_poses(f)
    library = tmp_path / "library.out"
    times = {"duration": 2.0, "start_time": 7.0} if timing else {}
    a2b.write(a2b.motion(*job.poses()), library, fmt, samples=9, **times)
    assert library.read_bytes() == command.read_bytes()


def test_the_first_and_last_rows_are_the_poses_as_given(tmp_path):
    """Not 0.45000000000000007 for 0.45: t = 0 and t = 1 are A and B (issue 27)."""
    path = tmp_path / "poses.yaml"
    path.write_text(TILTED)
    for mode in ("darboux", "cubic", "screw"):
        rows = run("interpolate", path, "--samples", 5, "--mode", mode).output.splitlines()
        assert rows[1].split(",")[:4] == ["0.0", "0.45", "-0.7", "0.3"]
        assert rows[-1].split(",")[:4] == ["1.0", "0.1", "0.25", "1.3"]
        matrix = run("interpolate", path, "--samples", 3, "--mode", mode, "--format", "matrix")
        last = matrix.output.splitlines()[-1].split(",")
        assert [last[4], last[8], last[12]] == ["0.1", "0.25", "1.3"]


def test_write_into_a_stream_leaves_it_open(motion):
    stream = NonSeekableStream()
    a2b.write(motion, stream, "mcap", samples=5)
    assert not stream.closed and bytes(stream.data).startswith(b"\x89MCAP0\r\n")
    buffer = io.BytesIO()
    a2b.write(motion, buffer, samples=3)  # csv: no suffix to go by
    assert buffer.getvalue().startswith(b"t,tx,ty,tz,qw,qx,qy,qz\n0.0,")


def test_the_suffix_chooses_the_format(tmp_path, motion):
    choices = []
    a2b.write(motion, tmp_path / "m.tum", samples=3, choices=choices)
    assert (tmp_path / "m.tum").read_bytes().startswith(b"# time tx ty tz qx qy qz qw\n")
    assert choices == ["format tum: from the -o suffix .tum"]


@pytest.mark.parametrize(
    "fmt, options, message",
    [
        ("csv", {"frame_id": "map"}, "--frame-id: not for csv output"),
        ("kitti", {"start_time": 3.0}, "--start-time: not for kitti output"),
        ("tum", {"child_frame_id": "tool"}, "--child-frame-id: not for tum output"),
        ("csv", {"rate": 10.0}, "rate, dt and velocities are for a timed motion"),
    ],
)
def test_an_option_that_does_not_apply_is_refused(tmp_path, motion, fmt, options, message):
    target = tmp_path / "out"
    with pytest.raises(OptionError, match=message):
        a2b.write(motion, target, fmt, **options)
    assert not target.exists()


def test_a_failure_half_way_leaves_the_old_file(tmp_path, motion):
    target = tmp_path / "out.csv"
    target.write_bytes(b"precious\n")
    quat, trans = motion.quat_trans(np.linspace(0, 1, 4))
    good = Samples(np.linspace(0, 0.5, 4), quat_wxyz=quat, trans=trans)
    bad = Samples(np.linspace(0.6, 1, 4), quat_wxyz=quat.copy(), trans=trans.copy())
    bad.trans[2, 1] = np.inf

    def samples():
        yield good
        yield bad

    with pytest.raises(A2bError, match=r"^the sample at time = 0\.8666666666666667 is not finite"):
        a2b.write(samples(), target)
    assert target.read_bytes() == b"precious\n"
    assert [p.name for p in tmp_path.iterdir()] == ["out.csv"]


def test_a_timed_motion_streams_at_its_rate(tmp_path, motion):
    timed = a2b.timing(motion, "quintic", duration=2.0)
    target = tmp_path / "timed.csv"
    a2b.write(timed, target, rate=10, velocities=True, start_time=5.0)
    lines = target.read_text().splitlines()
    assert lines[0] == "t,tx,ty,tz,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz"
    assert len(lines) == 22 and lines[1].startswith("5.0,") and lines[-1].startswith("7.0,")
    with pytest.raises(OptionError, match="--velocities: tum has no velocity field"):
        a2b.write(timed, tmp_path / "t.tum", rate=10, velocities=True)


def test_stamps_are_exact_nanoseconds_after_an_integer_origin(motion):
    """The seam for time grids far from 0: ``origin_ns + round(time · 1e9)``."""
    from mcap.reader import make_reader

    origin = 1_700_000_000_123_456_789
    quat, trans = motion.quat_trans(np.linspace(0, 1, 200))
    time = np.arange(200) / 200.0  # every 5 ms
    samples = Samples(time, quat_wxyz=quat, trans=trans, origin_ns=origin)
    stream = io.BytesIO()
    a2b.write(samples, stream, "ros2")
    stream.seek(0)
    times = [m.log_time for _, c, m in make_reader(stream).iter_messages() if c.topic == "/tf"]
    assert times == [origin + 5_000_000 * k for k in range(200)]


def test_mcap_limits_are_checked_as_the_samples_come(motion):
    quat, trans = motion.quat_trans(np.linspace(0, 1, 3))
    late = Samples(np.array([0.0, 1.0, 2.2e9]), quat_wxyz=quat, trans=trans)
    with pytest.raises(ParameterError, match="ROS 2 stamps hold seconds in an int32"):
        a2b.write(late, io.BytesIO(), "ros2")
    early = Samples(np.array([-1.0, 0.0, 1.0]), quat_wxyz=quat, trans=trans)
    with pytest.raises(ParameterError, match="the earliest time is -1 s"):
        a2b.write(early, io.BytesIO(), "mcap")


def test_mark_is_one_or_zero():
    from pathlib import Path

    reference = Path(__file__).resolve().parent.parent / "samples" / "reference.tum"
    rows = run("resample", reference, "--rate", 20, "--mark").output.splitlines()
    assert rows[0].endswith(",original")
    assert {row.rsplit(",", 1)[1] for row in rows[1:]} == {"0", "1"}


def test_a_timed_motion_starts_and_ends_at_the_poses_as_given(tmp_path):
    path = tmp_path / "poses.yaml"
    path.write_text(TILTED)
    rows = run("interpolate", path, "--max-speed", 0.5, "--rate", 2).output.splitlines()
    assert rows[1].split(",")[:4] == ["0.0", "0.45", "-0.7", "0.3"]
    assert rows[-1].split(",")[1:4] == ["0.1", "0.25", "1.3"]
