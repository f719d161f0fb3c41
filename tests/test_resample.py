"""Trajectories in and ``a2b resample``: readers, the resampling core, the command, and evo.

The screw mode is checked against pytransform3d's ScLERP of each segment, and evo (installed
into a venv of its own, as a user would) associates every pose of an estimate resampled with
``--at`` and reports the error an independent computation gives.
"""

from __future__ import annotations

import io
import os
import subprocess
import warnings
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import a2b
from a2b.cli import cli
from a2b.errors import A2bError, InputFileError, PoseError
from a2b.io import trajectories
from a2b.io.trajectories import read_trajectory
from a2b.poses import matrices_from_quat_trans, orthonormalize, quat_trans_from_matrices
from a2b.resample import Resampler, resample

ROOT = Path(__file__).resolve().parent.parent
SAMPLES = ROOT / "samples"


def random_trajectory(rng, n: int, start: float = 0.0):
    quat = rng.normal(size=(n, 4))
    quat /= np.linalg.norm(quat, axis=1, keepdims=True)
    poses = matrices_from_quat_trans(quat, rng.normal(size=(n, 3)))
    times = start + np.cumsum(rng.uniform(0.05, 1.0, n))
    return times, poses


def run(*args, input=None):
    return CliRunner().invoke(cli, list(map(str, args)), input=input)


# -- readers -----------------------------------------------------------------------------------


@pytest.mark.parametrize("fmt", ["csv", "matrix", "study", "tum", "kitti", "mcap"])
def test_every_output_reads_back_as_a_trajectory_bit_for_bit(tmp_path, fmt):
    out = tmp_path / f"turn.{fmt}"
    timing = ("--duration", 3, "--start-time", 5) if fmt in ("tum", "mcap") else ()
    result = run("interpolate", SAMPLES / "half-turn.yaml", "--format", fmt, "-o", out,
                 "--samples", 37, *timing)  # fmt: skip
    assert result.exit_code == 0, result.output
    motion = a2b.motion(*_poses("half-turn.yaml"))
    ts = np.linspace(0, 1, 37)
    with open(out, "rb") as f:
        path = read_trajectory(f)  # the format from the suffix or the content
    assert path.fmt == fmt
    quat, trans = motion.quat_trans(ts)
    if fmt in ("csv", "tum", "mcap"):
        assert np.array_equal(path.quat_wxyz, quat) and np.array_equal(path.translations, trans)
    elif fmt == "study":
        assert np.array_equal(path.study, motion.study(ts))
    else:
        assert np.array_equal(path.matrices, motion.matrices(ts))
    expected = {"csv": ts, "matrix": ts, "study": ts, "kitti": np.arange(37.0)}
    if fmt in expected:
        assert np.array_equal(path.times, expected[fmt])
    elif fmt == "tum":
        assert np.array_equal(path.times, ts * 3 + 5)
    else:  # MCAP stores integer nanoseconds
        assert np.allclose(path.times, ts * 3 + 5, rtol=0, atol=1e-9)


def _poses(sample: str):
    from a2b.io.poseschema import read_poses

    with open(SAMPLES / sample, "rb") as f:
        job = read_poses(f)
    return job.start, job.end


def test_euroc_stamps_are_whole_nanoseconds_and_qw_comes_first():
    text = (
        "#timestamp [ns],p_RS_R_x [m],p_RS_R_y [m],p_RS_R_z [m],q_RS_w [],q_RS_x [],q_RS_y [],"
        "q_RS_z [],v_RS_R_x [m s^-1]\n"
        "1403636579758555392,4.688,-1.786,0.783,0.534,-0.153,-0.827,-0.082,0.1\n"
        "1403636579763555584,4.688,-1.786,0.787,0.534,-0.153,-0.827,-0.082,0.1\n"
    )
    path = read_trajectory(io.BytesIO(text.encode()), "data.csv")
    assert path.fmt == "euroc"
    assert path.times[0] == 1403636579 + 758555392e-9
    assert path.quat_wxyz[0].tolist() == [0.534, -0.153, -0.827, -0.082]
    assert path.translations[1].tolist() == [4.688, -1.786, 0.787]
    bad = text.replace("1403636579763555584", "1403636579.76")
    with pytest.raises(InputFileError, match=r"^data\.csv:3:1: expected a whole number of nano"):
        read_trajectory(io.BytesIO(bad.encode()), "data.csv")


@pytest.mark.parametrize(
    "name, text, message",
    [
        ("a.tum", "0 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 1\n1 1 0 0 0 0 0 1\n",
         r"^a\.tum:3:1: the time 1\.0 repeats the previous one, 1\.0; times must increase"),
        ("a.tum", "# c\n2 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 1\n",
         r"^a\.tum:3:1: the time 1\.0 goes back from the previous one, 2\.0"),
        ("a.tum", "0 0 0 0 0 0 0 1\n1 0 0 x 0 0 0 1\n",
         r"^a\.tum:2:7: expected a number, got 'x'"),
        ("a.tum", "0 0 0 0 0 0 0 1\n1 0 0 0 0 0 1\n",
         r"^a\.tum:2:1: expected 8 numbers per line \(tum\), got 7"),
        ("a.tum", "0 0 0 0 0 0 0 1\n1 0 0 nan 0 0 0 1\n",
         r"^a\.tum:2:7: expected a finite number, got 'nan'"),
        ("a.tum", "0 0 0 0 0 0 0 0\n", r"^a\.tum:1:1: the quaternion is zero"),
        ("a.kitti", "1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 0 0 1 0 0 0 0 -1 0\n",
         r"^a\.kitti:2:1: the rotation block is a reflection"),
        ("a.kitti", "1 0 0 0 0 1 0 0 0 0 1.0000001 0\n",
         r"^a\.kitti:1:1: the rotation block is not orthogonal: max \|R Rᵀ − I\| = 2e-07 "
         r"exceeds tolerance 1e-09; .*--orthonormalize projects each onto the nearest rotation"),
        ("a.csv", "t,x\n", r"^a\.csv: cannot tell the trajectory format"),
        ("a.csv", "t,tx,ty,tz,qw,qx,qy,qz\n0,0,0,0,1,0,0,0,5\n",
         r"^a\.csv:2:1: expected 8 numbers per line \(csv\), got 9"),
    ],
)  # fmt: skip
def test_trajectory_errors_are_one_line_at_the_line(name, text, message):
    with pytest.raises(InputFileError, match=message) as caught:
        read_trajectory(io.BytesIO(text.encode()), name)
    assert "\n" not in str(caught.value)


def test_orthonormalize_is_an_explicit_repair_up_to_its_tolerance():
    rng = np.random.default_rng(5)
    _, poses = random_trajectory(rng, 20)
    rounded = np.round(poses, 6)
    with pytest.raises(PoseError, match="--orthonormalize"):
        a2b.motion(rounded[0], rounded[1])
    repaired = orthonormalize(rounded)
    gram = repaired[:, :3, :3] @ np.swapaxes(repaired[:, :3, :3], 1, 2)
    assert np.abs(gram - np.eye(3)).max() < 4e-15
    assert np.abs(repaired - poses).max() < 2e-6  # the rotation the digits stood for
    assert np.array_equal(repaired[:, :3, 3], rounded[:, :3, 3])
    with pytest.raises(PoseError, match="too far from orthogonal to repair: .* 0.0001"):
        orthonormalize(poses * np.array([1, 1, 1.01, 1])[:, None])
    text = "".join(" ".join(f"{v:.6e}" for v in p[:3].ravel()) + "\n" for p in poses)
    with pytest.raises(InputFileError, match="--orthonormalize"):
        read_trajectory(io.BytesIO(text.encode()), "r.kitti")
    path = read_trajectory(io.BytesIO(text.encode()), "r.kitti", orthonormalize=True)
    assert 1e-8 < path.repaired < 1e-5
    assert np.abs(path.matrices - poses).max() < 2e-6


def test_a_bare_quaternion_list_asks_for_its_order():
    result = run("interpolate", "-", input="start: {quaternion: [0, 0, 0, 1]}\nend: {}\n")
    assert result.exit_code == 1
    assert result.output.count("\n") == 1
    assert "start.quaternion: a bare list is ambiguous" in result.output
    assert "quaternion_wxyz" in result.output and "quaternion_xyzw" in result.output


# -- the core ----------------------------------------------------------------------------------


@pytest.mark.parametrize("mode", ["darboux", "cubic", "screw"])
def test_per_motion_parameters_equal_each_motion_alone(mode):
    rng = np.random.default_rng(11)
    _, poses = random_trajectory(rng, 13)
    for shape in [(12,), (3, 4)]:
        starts, ends = poses[:-1].reshape(shape + (4, 4)), poses[1:].reshape(shape + (4, 4))
        motion = a2b.motion(starts, ends, mode)
        ts = rng.uniform(-0.2, 1.2, size=shape + (5,))
        got = motion.matrices(ts)
        quat, _ = motion.quat_trans(ts)
        for index in np.ndindex(shape):
            alone = a2b.motion(starts[index], ends[index], mode)
            # a few ulp of entries up to about 2: with parameters of its own per motion the
            # products of a batch and of one motion may take different BLAS kernels (numpy < 2)
            assert np.allclose(got[index], alone.matrices(ts[index]), rtol=0, atol=2e-15)
            assert np.allclose(quat[index], alone.quat_trans(ts[index])[0], rtol=0, atol=2e-15)
    with pytest.raises(A2bError, match="one row per motion"):
        motion.matrices(np.zeros((4, 3, 2)))


def test_screw_resampling_returns_the_stamps_exactly_and_sclerp_between():
    pt = pytest.importorskip("pytransform3d.transformations")
    rng = np.random.default_rng(3)
    times, poses = random_trajectory(rng, 200)
    kept, own = resample(times, poses, times)
    assert np.array_equal(kept, times) and np.array_equal(own, poses)
    fractions = rng.uniform(0, 1, 199)
    between = times[:-1] + fractions * np.diff(times)
    _, got = resample(times, poses, between)
    u = (between - times[:-1]) / np.diff(times)  # the parameter a2b computes
    for k in range(199):
        expected = pt.transform_from_dual_quaternion(
            pt.dual_quaternion_sclerp(
                pt.dual_quaternion_from_transform(poses[k]),
                pt.dual_quaternion_from_transform(poses[k + 1]),
                u[k],
            )
        )
        assert np.abs(got[k] - expected).max() < 1e-12


@pytest.mark.parametrize("mode", ["darboux", "cubic", "screw"])
def test_each_resampled_segment_is_its_motion_built_alone(mode):
    """Where the segments of a block are close together, a segment's motion is built from
    quaternions found once per pose (for the two segments it ends and starts); where they are
    sparse, from its two matrices: the same samples, bit for bit. Each is the motion of that
    pair built alone (bit for bit but for the cubic, whose batched products may round
    differently: 1e-15)."""
    rng = np.random.default_rng(5)
    times, poses = random_trajectory(rng, 40)
    between = times[:-1] + rng.uniform(0.05, 0.95, 39) * np.diff(times)
    _, in_order = resample(times, poses, between, mode)
    _, sparse = resample(times, poses, between[::3], mode)  # every third segment
    assert np.array_equal(in_order[::3], sparse)
    for k, (row, t) in enumerate(zip(in_order, between)):
        u = (t - times[k]) / (times[k + 1] - times[k])
        alone = a2b.motion(poses[k], poses[k + 1], mode).matrices(np.array([u]))[0]
        if mode == "cubic":
            np.testing.assert_allclose(row, alone, rtol=0, atol=1e-15)
        else:
            assert np.array_equal(row, alone)


def test_a_segments_quaternions_take_one_sign_that_of_its_start():
    """A cubic whose weights differ in sign turns p(t) more than a right angle away from pA:
    its samples keep the sign that makes p(0) the file's quaternion, with no jump inside the
    segment (the stamp at its end is the file's own quaternion, which may be −p(1))."""
    from a2b.poses import quaternions_from_axis_angle
    from a2b.resample import Resampler

    qa, qb = -np.array([1.0, 0.0, 0.0, 0.0]), quaternions_from_axis_angle([0, 0, 1], 2.5)
    resampler = Resampler(np.array([0.0, 1.0]), quat_wxyz=np.stack([qa, qb]),
                          translations=np.zeros((2, 3)), mode="cubic",
                          m=np.array([0.2, 0.0, 0.0, -1.0]))  # fmt: skip
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", a2b.errors.A2bWarning)
        quat, _ = resampler.sample(resampler.locate(np.linspace(0.0, 1.0, 201)), "quat_trans")
    assert np.array_equal(quat[0], qa) and np.array_equal(quat[-1], qb)
    inside = quat[1:-1]
    assert np.dot(inside[0], qa) > 0.99
    assert (np.einsum("ij,ij->i", inside[1:], inside[:-1]) > 0.99).all()


@pytest.mark.parametrize("mode", ["darboux", "cubic", "spline"])
def test_every_mode_passes_through_the_stamps_and_is_continuous(mode):
    rng = np.random.default_rng(8)
    times, poses = random_trajectory(rng, 30)
    poses[:, :3, :3] = poses[:1, :3, :3] @ _small_turns(rng, 30)  # neighbours close: smooth
    near = np.concatenate([times[1:-1] - 1e-9, times[1:-1] + 1e-9])
    kept, out = resample(times, poses, np.concatenate([times, near]), mode)
    assert np.array_equal(out[:30], poses)
    around = out[30:].reshape(2, 28, 4, 4)
    assert np.abs(around - poses[1:-1]).max() < 1e-6  # no jump at a stamp


def _small_turns(rng, n):
    angles = np.cumsum(rng.normal(0, 0.2, n))
    c, s = np.cos(angles), np.sin(angles)
    r = np.zeros((n, 3, 3))
    r[:, 0, 0], r[:, 0, 1], r[:, 1, 0], r[:, 1, 1], r[:, 2, 2] = c, -s, s, c, 1
    return r


def test_outside_times_and_gaps():
    times = np.array([0.0, 1.0, 5.0, 6.0])
    poses = np.broadcast_to(np.eye(4), (4, 4, 4)).copy()
    poses[:, 0, 3] = times
    with pytest.raises(A2bError, match=r"the time 6\.5 is outside the trajectory, .*--clip"):
        resample(times, poses, [0.5, 6.5])
    resampler = Resampler(times, poses, max_gap=2.0)
    located = resampler.locate([-1.0, 0.5, 1.0, 3.0, 5.0, 5.5, 7.0], clip=True)
    assert located.outside == 2 and located.gap == 1
    assert located.times.tolist() == [0.5, 1.0, 5.0, 5.5]
    assert located.pose.tolist() == [-1, 1, 2, -1]
    assert resampler.sample(located)[:, 0, 3].tolist() == [0.5, 1.0, 5.0, 5.5]


@pytest.mark.parametrize("representation", ["matrices", "quat_trans", "study"])
def test_times_in_any_order_and_spread_are_sampled_as_each_time_alone(representation):
    """Forty new times in one segment and one in each other (rows of the mean count, a segment
    over several rows, unused places), three on stamps: shuffled, the same samples bit for bit
    in the order given; each the stamp's pose exactly, or the sample that its time alone
    gives (to 1e-15: the core's products round by the number of times in a row)."""
    rng = np.random.default_rng(21)
    times, poses = random_trajectory(rng, 12)
    many = times[3] + np.sort(rng.uniform(0.01, 0.99, 40)) * (times[4] - times[3])
    one = times[:-1] + rng.uniform(0.05, 0.95, 11) * np.diff(times)
    new = np.sort(np.concatenate([many, one, times[[0, 5, 11]]]))
    shuffled = rng.permutation(len(new))
    resampler = Resampler(times, poses, "screw")

    def sampled(at):
        out = resampler.sample(resampler.locate(at), representation)
        return out if isinstance(out, tuple) else (out,)

    in_order, again = sampled(new), sampled(new[shuffled])
    for ours, theirs in zip(again, in_order):
        assert np.array_equal(ours, theirs[shuffled])
    located = resampler.locate(new)
    assert located.pose[-1] == 11 and located.u[-1] == 1.0  # the last stamp ends its segment
    on_stamp = located.pose >= 0
    assert on_stamp.sum() == 3
    for i in range(len(new)):
        for ours, alone in zip(in_order, sampled(new[i : i + 1])):
            if on_stamp[i]:
                assert np.array_equal(ours[i], alone[0])
            else:
                np.testing.assert_allclose(ours[i], alone[0], rtol=0, atol=1e-15)
    if representation == "matrices":
        assert np.array_equal(in_order[0][on_stamp], poses[located.pose[on_stamp]])


@settings(max_examples=200, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(2, 40), st.integers(1, 300))
def test_segments_of_in_order_times_are_searchsorted_s(seed, stamps, count):
    """The stamps found among new times in order (and counted) place each time as a binary
    search of the stamps does: new times on stamps, repeated, between, at both ends."""
    from a2b.resample import _segments_of

    rng = np.random.default_rng(seed)
    t = np.cumsum(rng.choice([0.25, 0.5, 1.0], stamps))
    new = np.concatenate([rng.choice(t, count), rng.uniform(t[0], t[-1], count), t[[0, -1]]])
    for times in (np.sort(new), new):  # in order, and (by binary search) in any order
        expected = np.searchsorted(t, times, side="right") - 1
        assert np.array_equal(_segments_of(t, times), expected)


@settings(max_examples=200, deadline=None)
@given(st.integers(0, 2**32 - 1), st.integers(1, 12), st.integers(1, 30), st.booleans())
def test_rows_of_a_block_hold_each_parameter_once_in_its_segments_row(seed, each, count, cut):
    """The parameters of a block as rows of one segment each: ``ts.ravel()[places]`` are the
    parameters, in a row of their segment, and every other place is ½; a block of a regular
    rate (every segment but the first and last with the same count) needs no index (a slice)."""
    from a2b.resample import _rows

    rng = np.random.default_rng(seed)
    counts = np.full(count, each)
    if cut:  # the first and last segments cut by the block's ends
        counts[[0, -1]] = rng.integers(1, each + 1, 2)
    else:
        counts = rng.integers(1, 2 * each + 1, count)
    k = np.repeat(np.sort(rng.choice(10 * count, count, replace=False)), counts)
    u = rng.uniform(0.01, 0.99, len(k))
    for order in (np.arange(len(k)), rng.permutation(len(k))):
        rows, ts, places = _rows(k[order], u[order])
        flat = np.arange(ts.size)[slice(None) if places is None else places]
        assert np.array_equal(ts.ravel()[flat], u[order])
        assert np.array_equal(np.repeat(rows, ts.shape[1])[flat], k[order])
        unused = np.ones(ts.size, dtype=bool)
        unused[flat] = False
        assert (ts.ravel()[unused] == 0.5).all()
        width = -(-len(k) // count)  # the mean count
        regular = (counts[1:-1] == width).all() and counts.max() <= width
        if order[0] == 0 and (np.diff(order) == 1).all() and regular:
            assert places is None or isinstance(places, slice), counts


@pytest.mark.parametrize("between", [40, 4])  # few on stamps, and many (> 1/8)
def test_times_on_stamps_build_no_segment_of_their_own(between):
    """A time on a stamp is the stamp's pose as given, whether the few on stamps are sampled
    with the rest and set, or taken apart: no segment is built for it (one that failed to
    build would be an error where no time falls)."""
    rng = np.random.default_rng(5)
    times, poses = random_trajectory(rng, 8)
    inside = times[1] + np.sort(rng.uniform(0.01, 0.99, between)) * (times[2] - times[1])
    new = np.concatenate([times[[0]], inside, times[[4, 6]]])
    for order in (slice(None), slice(None, None, -1)):
        resampler = Resampler(times, poses, "screw")
        quat, trans = resampler.sample(resampler.locate(new[order]), "quat_trans")
        assert resampler.segments_built == 1
        own = quat_trans_from_matrices(poses[[0, 4, 6]])
        stamps = np.isin(new[order], times)
        assert np.array_equal(quat[stamps], own[0][:: 1 if order.step is None else -1])
        assert np.array_equal(trans[stamps], own[1][:: 1 if order.step is None else -1])
        alone = Resampler(times, poses, "screw")
        for i in np.flatnonzero(~stamps)[:3]:
            one = alone.sample(alone.locate(new[order][i : i + 1]), "quat_trans")
            np.testing.assert_allclose(quat[i], one[0][0], rtol=0, atol=1e-15)


def test_a_failing_segment_is_named_by_its_poses_and_times():
    times = np.array([0.0, 1.0, 2.0])
    poses = np.broadcast_to(np.eye(4), (3, 4, 4)).copy()
    poses[1:, :3, :3] = [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]]  # a screw, then
    poses[1:, :3, 3] = [[0.0, 0.0, 1.0], [0.0, 0.0, 2.0]]  # a translation: κ needs a turn
    resample(times, poses, [0.5], "darboux", kappa=0.5)
    with pytest.raises(A2bError, match=r"^the segment from pose 1 \(time 1\.0\) to pose 2 "):
        resample(times, poses, [0.5, 1.5], "darboux", kappa=0.5)


# -- the command -------------------------------------------------------------------------------


def test_resample_at_its_own_stamps_is_the_file(tmp_path):
    out = tmp_path / "same.tum"
    result = run("resample", SAMPLES / "reference.tum", "--at", SAMPLES / "reference.tum",
                 "-o", out)  # fmt: skip
    assert result.exit_code == 0, result.output
    with open(SAMPLES / "reference.tum", "rb") as f:
        original = read_trajectory(f)
    with open(out, "rb") as f:
        again = read_trajectory(f)
    assert np.array_equal(again.times, original.times)
    assert np.array_equal(again.quat_wxyz, original.quat_wxyz)
    assert np.array_equal(again.translations, original.translations)


def test_resample_streams_every_format_and_marks_the_originals(tmp_path):
    for fmt in ("csv", "matrix", "study", "tum", "kitti", "mcap"):
        out = tmp_path / f"r.{fmt}"
        result = run("resample", SAMPLES / "reference.tum", "--rate", 33, "--format", fmt,
                     "-o", out)  # fmt: skip
        assert result.exit_code == 0, result.output
        with open(out, "rb") as f:
            path = read_trajectory(f, fmt=fmt)
        assert len(path) == 195  # 5.9 s at 33 Hz from the first stamp
    result = run("resample", SAMPLES / "reference.tum", "--times", SAMPLES / "stamps.txt",
                 "--mark", "--mode", "spline")  # fmt: skip
    assert result.exit_code == 0, result.output
    rows = result.output.splitlines()
    assert rows[0] == "t,tx,ty,tz,qw,qx,qy,qz,original"
    marks = [row.rsplit(",", 1)[1] for row in rows[1:]]
    assert marks == ["0", "1", "0", "1"]  # 1 or 0, as README says


def test_resample_refusals_are_one_line_with_the_fix(tmp_path):
    stamps = tmp_path / "stamps.txt"
    stamps.write_text("1700000001.0\n1700000001.0\n")
    cases = [
        (["--rate", "10", "--at", SAMPLES / "reference.tum"], "exactly one of --rate"),
        (["--times", stamps], "stamps.txt:2:1: the time 1700000001.0 repeats the previous one"),
        (["--at", SAMPLES / "walk.kitti"], "KITTI files have none"),
        (["--rate", "10", "--mark", "--format", "tum"], "--mark adds a column to csv"),
    ]
    for args, message in cases:
        result = run("resample", SAMPLES / "reference.tum", *args)
        assert result.exit_code != 0 and message in result.output, (args, result.output)
        assert result.output.strip().count("\n") == 0 or "Usage" in result.output
    result = run("resample", SAMPLES / "estimate.tum", "--at", SAMPLES / "reference.tum", "--clip",
                 "--max-gap", 0.12, "-o", tmp_path / "e.tum")  # fmt: skip
    assert result.exit_code == 0
    assert "Dropped 1 time outside the trajectory (--clip)." in result.output
    assert "inside segments longer than --max-gap 0.12 s." in result.output


def test_a_repair_is_stated_under_v():
    result = run("resample", SAMPLES / "walk.kitti", "--orthonormalize", "--rate", "2", "-v",
                 "--mode", "spline", "--format", "kitti")  # fmt: skip
    assert result.exit_code == 0, result.output
    assert "orthonormalized 30 rotation blocks: largest max |R Rᵀ − I| was" in result.output


# -- evo, a real client ------------------------------------------------------------------------


@pytest.fixture(scope="session")
def evo_ape(clients):
    """evo's ``evo_ape``, from the venv of the real clients (conftest.py)."""
    return clients / "evo_ape"


def test_evo_associates_every_pose_resampled_with_at(tmp_path, evo_ape):
    estimate = tmp_path / "estimate.tum"
    result = run("resample", SAMPLES / "estimate.tum", "--at", SAMPLES / "reference.tum",
                 "--clip", "-o", estimate)  # fmt: skip
    assert result.exit_code == 0, result.output
    results = tmp_path / "ape.zip"
    env = dict(os.environ, MPLBACKEND="Agg", HOME=str(tmp_path))
    done = subprocess.run(
        [str(evo_ape), "tum", str(SAMPLES / "reference.tum"), str(estimate),
         "--save_results", str(results), "--no_warnings"],
        capture_output=True, text=True, env=env, timeout=300,
    )  # fmt: skip
    assert done.returncode == 0, done.stdout + done.stderr
    import json
    import zipfile

    with zipfile.ZipFile(results) as z:
        stats = json.loads(z.read("stats.json"))
        name = next(n for n in z.namelist() if n.startswith("error_array"))
        errors = np.load(io.BytesIO(z.read(name)))
    with open(SAMPLES / "reference.tum", "rb") as f:
        reference = read_trajectory(f)
    with open(estimate, "rb") as f:
        ours = read_trajectory(f)
    assert len(errors) == len(ours) == len(reference) - 1  # every pose associated
    # evo's APE (translation part, no alignment): the distance of the positions at each stamp
    same = np.isin(reference.times, ours.times)
    independent = np.linalg.norm(reference.translations[same] - ours.translations, axis=1)
    assert np.allclose(np.sort(errors), np.sort(independent), rtol=1e-9, atol=1e-12)
    assert stats["rmse"] == pytest.approx(np.sqrt(np.mean(independent**2)), rel=1e-9)


# -- poses the way users write them ------------------------------------------------------------


def test_rpy_and_axis_angle_poses_match_scipy():
    rotation = pytest.importorskip("scipy.spatial.transform").Rotation
    from a2b.io.poseschema import read_pose

    rng = np.random.default_rng(21)
    for rpy in rng.uniform(-3, 3, size=(5, 3)):
        text = f"rpy_xyz: {rpy.tolist()}\ntranslation: [1, 2, 3]\n"
        pose = read_pose(io.BytesIO(text.encode()), "p.yaml")
        assert np.abs(pose[:3, :3] - rotation.from_euler("xyz", rpy).as_matrix()).max() < 1e-15
        assert pose[:3, 3].tolist() == [1.0, 2.0, 3.0]
        axis, angle = rng.normal(size=3), float(rng.uniform(-3, 3))
        text = f"axis_angle: {{axis: {axis.tolist()}, angle: {angle!r}}}\n"
        pose = read_pose(io.BytesIO(text.encode()), "p.yaml")
        expected = rotation.from_rotvec(axis / np.linalg.norm(axis) * angle).as_matrix()
        assert np.abs(pose[:3, :3] - expected).max() < 1e-15
    degrees = read_pose(io.BytesIO(b"rpy_xyz: [0, 0, 90deg]\n"), "p.yaml")
    assert np.allclose(degrees[:3, :3], [[0, -1, 0], [1, 0, 0], [0, 0, 1]], rtol=0, atol=3e-16)
    with pytest.raises(
        InputFileError, match=r"p\.yaml:1:1: axis_angle: the axis_angle lacks angle"
    ):
        read_pose(io.BytesIO(b"axis_angle: {axis: [0, 0, 1]}\n"), "p.yaml")
    with pytest.raises(InputFileError, match=r"p\.yaml:1:1: axis_angle: a rotation axis needs"):
        read_pose(io.BytesIO(b"axis_angle: {axis: [0, 0, 0], angle: 1}\n"), "p.yaml")


def test_the_api_takes_scipy_transforms_and_quaternion_translation_tuples():
    transform = pytest.importorskip("scipy.spatial.transform")
    turn = transform.Rotation.from_euler("z", 90, degrees=True)
    matrix = np.eye(4)
    matrix[:3, :3] = turn.as_matrix()
    expected = a2b.interpolate(np.eye(4), matrix, 5, "screw")
    assert np.array_equal(a2b.interpolate(np.eye(4), turn, 5, "screw"), expected)
    as_tuple = ([1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 0.0])
    quat = [np.cos(np.pi / 4), 0.0, 0.0, np.sin(np.pi / 4)]
    assert np.allclose(a2b.interpolate(as_tuple, (quat, [0, 0, 0]), 5, "screw"), expected)
    if hasattr(transform, "RigidTransform"):
        rigid = transform.RigidTransform.from_components([1.0, 2.0, 3.0], turn)
        expected = a2b.interpolate(np.eye(4), rigid.as_matrix(), 5)
        assert np.array_equal(a2b.interpolate(np.eye(4), rigid, 5), expected)


def test_a_far_excursion_is_warned_with_its_ratio():
    start, end = _poses("quarter-turn.yaml")
    with pytest.warns(a2b.errors.A2bWarning, match=r"up to 260 away .* 173 times their distance"):
        motion = a2b.motion(start, end, "darboux", lam=888.0)
    assert motion.warnings and "173 times" in motion.warnings[0]
    with warnings.catch_warnings():
        warnings.simplefilter("error", a2b.errors.A2bWarning)
        for mode in ("darboux", "cubic", "screw"):  # the defaults stay close
            a2b.motion(start, end, mode)
    result = run("interpolate", SAMPLES / "quarter-turn.yaml", "--lam", 888, "--samples", 2)
    assert result.exit_code == 0 and "Warning: the Darboux motion takes the origin" in result.output


def test_spline_and_bezier_take_their_poses_from_trajectory_files(tmp_path):
    with open(SAMPLES / "walk.kitti", "rb") as f:
        walk = read_trajectory(f, orthonormalize=True)
    result = run("spline", SAMPLES / "walk.kitti", "--orthonormalize", "--space", "study",
                 "--samples", 59, "--format", "matrix")  # fmt: skip
    assert result.exit_code == 0, result.output
    _, matrices = trajectories.read_matrix_csv(io.BytesIO(result.output.encode()))
    assert np.abs(matrices[::2] - walk.matrices).max() < 1e-12  # key pose j at t = j / 29
    with open(SAMPLES / "reference.tum", "rb") as f:
        reference = read_trajectory(f)
    result = run("bezier", SAMPLES / "reference.tum", "--space", "study", "--samples", 2)
    assert result.exit_code == 0, result.output
    _, quat, trans = trajectories.read_csv(io.BytesIO(result.output.encode()))
    assert np.allclose(trans, reference.translations[[0, -1]], rtol=0, atol=1e-12)
    data = (SAMPLES / "reference.tum").read_bytes()
    piped = run("spline", "-", "--input-format", "tum", "--samples", 3, input=data)
    assert piped.exit_code == 0, piped.output
    refused = run("spline", SAMPLES / "spline.yaml", "--topic", "/tf")
    assert refused.exit_code == 2 and "--topic is for trajectory files" in refused.output


def test_segment_warnings_name_the_segment_and_stop_at_ten():
    from a2b.resample import WARNINGS_SHOWN

    times = np.arange(30.0)
    angles = 0.3 * times
    quat = np.stack([np.cos(angles / 2), 0 * angles, 0 * angles, np.sin(angles / 2)], axis=1)
    poses = matrices_from_quat_trans(quat, np.stack([0.1 * times, 0 * times, 0 * times], 1))
    resampler = Resampler(times, poses, "darboux", lam=888.0)
    with pytest.warns(a2b.errors.A2bWarning) as caught:
        resampler.sample(resampler.locate(times[:-1] + 0.5))
    shown = [str(w.message) for w in caught if issubclass(w.category, a2b.errors.A2bWarning)]
    assert len(shown) == WARNINGS_SHOWN and resampler.warned == 29
    assert shown[0].startswith("the segment from pose 0 (time 0.0) to pose 1 (time 1.0): the ")
    assert {w.filename for w in caught} == {__file__}  # the caller's line, not a2b's
    with pytest.warns(a2b.errors.A2bWarning) as caught:  # the function: ten, then the count
        resample(times, poses, times[:-1] + 0.5, "darboux", lam=888.0)
    shown = [str(w.message) for w in caught]
    assert len(shown) == WARNINGS_SHOWN + 1 and {w.filename for w in caught} == {__file__}
    assert shown[-1] == "19 more segments were warned about (the first 10 are shown above)"


def test_blocks_made_on_the_pool_give_what_one_thread_gives(tmp_path, monkeypatch):
    """Blocks of new times sampled on two threads, windows of a few poses: the same text, the
    same warnings (the first ten of the run, in order, naming their segments) and the same
    counts as everything in one thread."""
    from a2b import resample as resample_module
    from a2b.io import parallel, trajectories

    times = np.arange(60.0)
    angles = 0.3 * times
    quat = np.stack([np.cos(angles / 2), 0 * angles, 0 * angles, np.sin(angles / 2)], axis=1)
    rows = np.column_stack([times, 0.1 * times, 0 * times, 0 * times, quat[:, 1:], quat[:, :1]])
    path = tmp_path / "turn.tum"
    path.write_text("".join(" ".join(repr(float(v)) for v in row) + "\n" for row in rows))
    monkeypatch.setattr(resample_module, "BLOCK", 16)
    monkeypatch.setitem(trajectories.trajectory_pieces.__kwdefaults__, "size", 300)  # windows
    got = []
    for workers in (1, 2):
        monkeypatch.setattr(parallel, "WORKERS", workers)
        out = tmp_path / f"out{workers}.csv"
        result = run("resample", path, "--rate", 7, "--mode", "darboux", "--lam", 888, "-v",
                     "-o", out)  # fmt: skip
        assert result.exit_code == 0, result.output
        got.append((out.read_bytes(), result.output))
    assert got[0] == got[1]
    warned = [line for line in got[0][1].splitlines() if line.startswith("Warning: the seg")]
    assert [line.split(":")[1] for line in warned] == [
        f" the segment from pose {k} (time {k:.1f}) to pose {k + 1} (time {k + 1:.1f})"
        for k in range(10)
    ]
    assert "49 more segments were warned about" in got[0][1]
    assert "built 59 segment motions" in got[0][1]


@pytest.mark.parametrize("fmt", ["csv", "matrix", "study", "tum", "kitti"])
def test_the_lines_made_with_the_samples_are_the_writers(tmp_path, monkeypatch, fmt):
    """A text table's lines, made on the sampling threads with each block's samples, marks
    included, are the bytes the writer makes of the samples itself, over many blocks."""
    from a2b import resample as resample_module
    from a2b.cli import resample as command
    from a2b.io import writers

    monkeypatch.setattr(resample_module, "BLOCK", 16)
    made = []
    chunk_text = writers.chunk_text
    monkeypatch.setattr(writers, "chunk_text", lambda f, c: made.append(f) or chunk_text(f, c))
    mark = ("--mark",) if fmt in ("csv", "matrix", "study") else ()
    args = (SAMPLES / "reference.tum", "--rate", 33, "--format", fmt, *mark)
    ahead = run("resample", *args, "-o", tmp_path / "ahead")
    assert ahead.exit_code == 0, ahead.output
    assert made == [fmt] * -(-195 // 16)  # every block, on the sampling threads

    class Plain(command._Run):
        def __init__(self, *arguments, **keywords):
            super().__init__(*arguments, **{**keywords, "text": None})

    monkeypatch.setattr(command, "_Run", Plain)
    made.clear()
    plain = run("resample", *args, "-o", tmp_path / "plain")
    assert plain.exit_code == 0, plain.output
    assert made == []
    assert (tmp_path / "ahead").read_bytes() == (tmp_path / "plain").read_bytes()


@pytest.mark.parametrize("workers", [1, 2])
def test_a_sample_that_overflows_after_lines_made_ahead_leaves_the_old_output(
    tmp_path, monkeypatch, workers
):
    """A block that is not finite after many whose lines were made with their samples: the
    finite check's one message, naming the block's first time, and the older file untouched,
    as with the lines made by the writer; on standard output whole lines before it."""
    from a2b import resample as resample_module
    from a2b.cli import resample as command
    from a2b.io import parallel

    monkeypatch.setattr(resample_module, "BLOCK", 16)
    monkeypatch.setattr(parallel, "WORKERS", workers)
    args = ("resample", SAMPLES / "reference.tum", "--rate", 33, "--format", "tum")
    whole = run(*args, "-o", "-")
    assert whole.exit_code == 0, whole.output
    starts = [line.split()[0] for line in whole.stdout.splitlines()[1::16]]  # the blocks' first
    assert len(starts) == 13
    sample_apart = resample_module.Resampler.sample_apart

    def overflowing(self, located, representation):
        values, built = sample_apart(self, located, representation)
        if len(located.times) and located.times[0] >= float(starts[9]):  # the tenth block on
            (values[0] if isinstance(values, tuple) else values)[0] = np.nan
        return values, built

    monkeypatch.setattr(resample_module.Resampler, "sample_apart", overflowing)
    message = f"Error: the sample at time = {float(starts[9]):.17g} is not finite: the motion"
    failed = {}
    for fmt in ("csv", "matrix", "study", "tum", "kitti"):
        out = tmp_path / f"out.{fmt}"
        out.write_bytes(b"precious\n")
        failed[fmt] = run(*args[:-1], fmt, "-o", out)
        assert failed[fmt].exit_code == 1, failed[fmt].output
        assert failed[fmt].output.startswith(message), failed[fmt].output
        assert out.read_bytes() == b"precious\n"
    assert len(list(tmp_path.iterdir())) == 5  # no temporary file left
    piped = run(*args, "-o", "-")
    assert piped.exit_code == 1 and piped.stderr == failed["tum"].output
    assert whole.stdout.startswith(piped.stdout) and piped.stdout.endswith("\n")

    class Plain(command._Run):
        def __init__(self, *arguments, **keywords):
            super().__init__(*arguments, **{**keywords, "text": None})

    monkeypatch.setattr(command, "_Run", Plain)
    plain = run(*args, "-o", tmp_path / "out.tum")
    assert plain.exit_code == 1 and plain.output == failed["tum"].output


SIX_DIGITS = (
    "start: {matrix: [[1, 0, 0, 0], [0, 0.707107, -0.707107, 0], [0, 0.707107, 0.707107, 0], "
    "[0, 0, 0, 1]]}\nend: {quaternion_wxyz: [1, 0, 0, 0], translation: [1, 0, 0]}\n"
)


def test_orthonormalize_repairs_matrix_poses_in_every_command(tmp_path):
    poses = tmp_path / "six.yaml"
    poses.write_text(SIX_DIGITS)
    jobs = tmp_path / "jobs.yaml"
    jobs.write_text("- " + SIX_DIGITS.replace("\nend", "\n  end"))
    for command, path, verbose in [
        ("interpolate", poses, ["-v"]),
        ("describe", poses, []),  # describe states its choices always
        ("batch", jobs, ["-v"]),
    ]:
        refused = run(command, path)
        assert refused.exit_code == 1
        assert "6.19e-07 exceeds tolerance 1e-09; if it is a rotation rounded" in refused.output
        assert "--orthonormalize" in refused.output
        repaired = run(command, path, "--orthonormalize", *verbose)
        assert repaired.exit_code == 0, repaired.output
        assert "orthonormalized 1 matrix pose: largest max |R Rᵀ − I| was 6.19e-07" in (
            repaired.output
        )
    result = run("interpolate", poses, "--orthonormalize", "--samples", 2, "--format", "matrix")
    _, matrices = trajectories.read_matrix_csv(io.BytesIO(result.output.encode()))
    turn = np.array([[1, 0, 0], [0, np.sqrt(0.5), -np.sqrt(0.5)], [0, np.sqrt(0.5), np.sqrt(0.5)]])
    assert np.abs(matrices[0, :3, :3] - turn).max() < 1e-15  # the rotation 6 digits stood for
    too_far = SIX_DIGITS.replace("0.707107, 0.707107", "0.7, 0.7")
    poses.write_text(too_far)
    result = run("interpolate", poses, "--orthonormalize")
    assert result.exit_code == 1 and "exceeds tolerance 0.0001" in result.output


def test_a_trajectory_given_as_a_pose_file_points_to_resample():
    result = run("interpolate", SAMPLES / "reference.tum")
    assert result.exit_code == 1 and result.output.count("\n") == 1
    assert "… (4886 characters) (a trajectory file? a2b resample reads TUM" in result.output


@pytest.mark.parametrize("mode", ["darboux", "cubic", "screw"])
def test_default_motions_stay_within_half_their_distance(monkeypatch, mode):
    """Why only motions with a parameter are checked for excursions: the defaults never are."""
    from a2b.motions import base

    rng = np.random.default_rng(99)
    n = 3000
    starts = matrices_from_quat_trans(rng.normal(size=(n, 4)), rng.normal(size=(n, 3)))
    ends = matrices_from_quat_trans(rng.normal(size=(n, 4)), rng.normal(size=(n, 3)))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", a2b.errors.A2bWarning)  # a few near p(t) = 0
        motion = a2b.motion(starts, ends, mode)
    sensitive = motion.warning_notes.mask()
    monkeypatch.setattr(base, "EXCURSION_RATIO", 0.5)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", a2b.errors.A2bWarning)
        base.check_excursion(motion)
    assert not caught, str(caught[0].message)
    assert sensitive.sum() < n // 100


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_a_damaged_trajectory_is_one_clear_error(data):
    """Cut, replace or insert bytes anywhere in a TUM, KITTI or CSV file: it reads, or it is
    one InputFileError that names the file (never another exception)."""
    name = data.draw(st.sampled_from(["reference.tum", "walk.kitti", "stamps.csv"]))
    if name == "stamps.csv":
        original = b"t,tx,ty,tz,qw,qx,qy,qz\n0.0,0,0,0,1,0,0,0\n0.5,1,2,3,0,1,0,0\n"
    else:
        original = (SAMPLES / name).read_bytes()
    text = bytearray(original)
    for _ in range(data.draw(st.integers(1, 4))):
        at = data.draw(st.integers(0, len(text)))
        junk = data.draw(
            st.binary(max_size=6)
            | st.sampled_from([b"nan", b"1e999", b",", b"\n", b" ", b"#", b"-", b"\xff"])
        )
        cut = data.draw(st.integers(0, 8))
        text[at : at + cut] = junk  # fmt: skip
    try:
        read_trajectory(io.BytesIO(bytes(text)), name, orthonormalize=name == "walk.kitti")
    except InputFileError as e:
        assert str(e).startswith(name) and "\n" not in str(e), str(e)


@settings(max_examples=300, deadline=None)
@given(cuts=st.lists(st.tuples(st.integers(0, 10**6), st.integers(0, 8), st.binary(max_size=4)),
                     min_size=1, max_size=3))  # fmt: skip
def test_a_damaged_mcap_file_is_one_clear_error(cuts, tmp_path_factory):
    path = tmp_path_factory.getbasetemp() / "small.mcap"
    if not path.exists():
        assert run("interpolate", SAMPLES / "quarter-turn.yaml", "--samples", 20, "-o",
                   path).exit_code == 0  # fmt: skip
    text = bytearray(path.read_bytes())
    for at, cut, junk in cuts:
        at %= len(text)
        text[at : at + cut] = junk
    try:
        read_trajectory(io.BytesIO(bytes(text)), "x.mcap")
    except InputFileError as e:
        assert str(e).startswith("x.mcap")


def test_resample_takes_the_motion_options_of_its_mode():
    result = run("resample", SAMPLES / "reference.tum", "--rate", 3, "--mode", "darboux",
                 "--delta", 10000, "-o", "/dev/null")  # fmt: skip
    assert result.exit_code == 0, result.output
    warned = [line for line in result.output.splitlines() if line.startswith("Warning: ")]
    assert len(warned) == 11  # ten segments named, then the count of the rest
    assert warned[0].startswith("Warning: the segment from pose 3 (time 1700000000.3) to pose 4")
    assert (
        warned[-1] == "Warning: 2 more segments were warned about (the first 10 are shown above)."
    )
    refused = run("resample", SAMPLES / "reference.tum", "--rate", 3, "--delta", 1)
    assert refused.exit_code == 2  # a usage error, naming the options
    assert "--mode screw does not take --delta; give --mode darboux" in refused.output
    refused = run("resample", SAMPLES / "reference.tum", "--rate", 3, "--mode", "darboux",
                  "--m", "1,0,0,0.5", "--pitch-start", 1)  # fmt: skip
    assert refused.exit_code == 2 and "does not take --m; give --mode cubic" in refused.output
    refused = run("resample", SAMPLES / "reference.tum", "--rate", 3, "--mode", "spline", "--a", 1)
    assert refused.exit_code == 2 and "the spline takes no motion parameters" in refused.output


@pytest.mark.parametrize("name", ["reference.tum", "walk.kitti"])
def test_a_trajectory_read_in_small_pieces_is_the_same(name):
    from a2b.io.trajectories import trajectory_pieces

    data = (SAMPLES / name).read_bytes()
    whole = read_trajectory(io.BytesIO(data), name, orthonormalize=True)
    pieces = list(trajectory_pieces(data, name, whole.fmt, size=200, orthonormalize=True))
    assert len(pieces) > 5
    assert np.array_equal(np.concatenate([p.times for p in pieces]), whole.times)
    assert np.array_equal(np.concatenate([p.matrices for p in pieces]), whole.matrices)
    lines = data.splitlines(keepends=True)
    if name.endswith(".tum"):  # KITTI has no times to repeat
        repeated = b"".join(lines[:20] + [lines[19]] + lines[20:])  # line 21 repeats line 20
        with pytest.raises(InputFileError, match=rf"^{name}:21:1: the time .* repeats"):
            list(trajectory_pieces(repeated, name, whole.fmt, size=200))
    damaged = b"".join(lines[:25] + [lines[25].replace(b"0", b"x", 1)] + lines[26:])
    with pytest.raises(InputFileError, match=rf"^{name}:26:\d+: expected a number, got '"):
        list(trajectory_pieces(damaged, name, whole.fmt, size=200, orthonormalize=True))


def test_a_bad_line_after_many_poses_leaves_the_old_output(tmp_path):
    """The trajectory is parsed in pieces as it is sampled: a bad line near the end comes after
    rows were written, and the output is still all or nothing."""
    rng = np.random.default_rng(4)
    times, poses = random_trajectory(rng, 60000)
    quat, trans = quat_trans_from_matrices(poses)
    from a2b.io.floatrepr import format_rows

    rows = np.column_stack([times, trans, quat[:, [1, 2, 3, 0]]])
    path = tmp_path / "long.tum"
    path.write_bytes(format_rows(rows, sep=" ") + b"1 2 3\n")
    out = tmp_path / "out.csv"
    out.write_bytes(b"precious\n")
    result = run("resample", path, "--rate", 10, "-o", out)
    assert result.exit_code == 1
    assert result.output == f"Error: {path}:60001:1: expected 8 numbers per line (tum), got 3\n"
    assert out.read_bytes() == b"precious\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["long.tum", "out.csv"]


def test_the_command_line_knows_every_trajectory_format():
    from a2b.formats import INPUT_NAMES

    assert set(INPUT_NAMES) == set(trajectories.TRAJECTORY_FORMATS)


def test_a_segment_whose_times_fall_in_two_blocks_is_counted_once(rng):
    """Blocks of BLOCK new times build their segments together; a segment split between two
    blocks is built in both but counted once (``-v``: built N − 1 segment motions)."""
    from a2b.resample import BLOCK, Resampler

    from .conftest import random_pose

    n = BLOCK // 5  # ten new times a segment: about two blocks
    times = np.arange(n) * 0.01
    poses = np.stack([random_pose(rng) for _ in range(n)])
    resampler = Resampler(times, poses, "screw")
    new_times = np.linspace(0.0, times[-1], 10 * n)[1:-1] + 1e-7  # none on a stamp
    new_times = new_times[new_times < times[-1]]
    resampler.sample(resampler.locate(new_times))
    assert len(new_times) > BLOCK
    assert resampler.segments_built == n - 1
