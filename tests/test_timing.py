"""Exact derivatives and time laws (a2b.kinematics, a2b.timing), against independent references:
mpmath central differences of the motions' own formulas, Ruckig's time-optimal durations,
closed forms, and high-precision quadrature of the arc length."""

from __future__ import annotations

import mpmath
import numpy as np
import pytest

import a2b
from a2b.errors import ParameterError
from a2b.kinematics import path_rates
from a2b.motions._rational import BLAS_ONE_THREAD
from a2b.motions.bezier import bezier_motion, spline_motion
from a2b.poses import matrices_from_quat_trans
from a2b.timelaw import LIMITS, timing
from a2b.timelaw.profiles import trapezoid

from .conftest import random_pose

MODES = ("darboux", "cubic", "screw")
mpmath.mp.dps = 40


def _motions(rng):
    """One motion of every kind from seeded random poses: the modes, Bézier and splines."""
    a, b = random_pose(rng), random_pose(rng)
    out = {mode: a2b.motion(a, b, mode) for mode in MODES}
    out["darboux-delta"] = a2b.motion(a, b, "darboux", delta=0.3)
    controls = np.stack([random_pose(rng) for _ in range(4)])
    for space in ("matrix", "study"):
        out[f"bezier-{space}"] = bezier_motion(controls, space)
        out[f"spline-{space}"] = spline_motion(controls, space)
    return out


def _mp_pose(motion, t):
    """The pose at ``t`` in mpmath from the motion's own formula: its basis times its
    coefficient table (each numerator over its denominator), at 40 digits."""
    if hasattr(motion, "frame"):  # a two-pose mode
        table = motion.table
        if motion.mode == "screw":
            phi = mpmath.mpf(float(motion.frame.phi))
            basis = [1, t, mpmath.sin(t * phi), 1 - mpmath.cos(t * phi)]
        else:
            n = table.shape[0] - 1
            basis = [mpmath.binomial(n, i) * (1 - t) ** (n - i) * t**i for i in range(n + 1)]
    else:
        segments = motion.controls.shape[0]
        j = min(int(mpmath.floor(t * segments)), segments - 1)
        u = t * segments - j
        table = motion._tables()[j]
        n = table.shape[0] - 1
        basis = [mpmath.binomial(n, i) * (1 - u) ** (n - i) * u**i for i in range(n + 1)]
    values = [
        sum(basis[i] * mpmath.mpf(float(table[i, c])) for i in range(len(basis))) for c in range(14)
    ]
    rows = []
    for r in range(3):
        rows.append(
            [values[4 * r + c] / values[12] for c in range(3)] + [values[4 * r + 3] / values[13]]
        )
    return mpmath.matrix(rows)


def _mp_twist(motion, t, point):
    """World twist (v of the point, ω) by a 40-digit central difference of the poses."""
    h = mpmath.mpf("1e-12")
    t = mpmath.mpf(float(t))
    plus, minus, here = _mp_pose(motion, t + h), _mp_pose(motion, t - h), _mp_pose(motion, t)
    rate = (plus - minus) / (2 * h)
    rot = here[:, :3]
    rot_rate = rate[:, :3]
    w = rot_rate * rot.T
    omega = [(w[2, 1] - w[1, 2]) / 2, (w[0, 2] - w[2, 0]) / 2, (w[1, 0] - w[0, 1]) / 2]
    x = mpmath.matrix([mpmath.mpf(float(v)) for v in point])
    velocity = rot_rate * x + rate[:, 3]
    return np.array([float(v) for v in list(velocity) + omega])


def test_twists_equal_a_high_precision_central_difference(rng):
    point = rng.normal(size=3)
    for name, motion in _motions(rng).items():
        ts = np.sort(rng.uniform(0.02, 0.98, 4))
        got = motion.twists(ts, point=point)
        for t, row in zip(ts, got):
            want = _mp_twist(motion, t, point)
            scale = np.abs(want).max()
            assert np.abs(row - want).max() <= 1e-10 * scale, (name, t, row, want)


def test_accelerations_equal_the_derivative_of_the_twists(rng):
    for name, motion in _motions(rng).items():
        ts = np.sort(rng.uniform(0.05, 0.95, 3))
        acc = motion.accelerations(ts, "world")
        h = 1e-6
        diff = (motion.twists(ts + h) - motion.twists(ts - h)) / (2 * h)
        assert np.allclose(acc, diff, rtol=1e-6, atol=1e-6 * np.abs(acc).max()), name


def test_body_and_spatial_twists_are_the_matrix_forms(rng):
    motion = a2b.motion(random_pose(rng), random_pose(rng), "cubic")
    ts = np.linspace(0.1, 0.9, 5)
    stack = motion.derivatives(ts, 1)
    for k, t in enumerate(ts):
        m, dm = stack[0, k], stack[1, k]
        body = np.linalg.inv(m) @ dm
        spatial = dm @ np.linalg.inv(m)
        for frame, mat in (("body", body), ("spatial", spatial)):
            twist = motion.twists(ts, frame)[k]
            assert np.allclose(twist[:3], mat[:3, 3], atol=1e-12)
            assert np.allclose(twist[3:], [mat[2, 1], mat[0, 2], mat[1, 0]], atol=1e-12)


@pytest.mark.parametrize("samples", [7, 1])
def test_a_batch_element_equals_the_motion_alone(rng, samples):
    """Matrices and body points' paths, with their derivatives: a batch (whose screw motions
    have a basis each) gives every element the bits of the motion alone (one basis), for
    many samples and for one (a product of one column, which BLAS rounds by another kernel)."""
    starts = np.stack([random_pose(rng) for _ in range(3)])
    ends = np.stack([random_pose(rng) for _ in range(3)])
    ts = np.linspace(0, 1, samples) if samples > 1 else np.array([0.3])
    for mode in MODES:
        if mode == "screw" and samples == 1 and int(np.__version__.split(".")[0]) < 2:
            continue  # numpy < 2 multiplies a stack of one-column screw bases with another
            # kernel than one alone (a few ulp apart): checked with numpy 2 only (CI runs both)
        batch = a2b.motion(starts, ends, mode)
        for point in (None, np.zeros(3), rng.normal(size=3)):
            got = batch.derivatives(ts, 3, point=point)
            for i in range(3):
                alone = a2b.motion(starts[i], ends[i], mode).derivatives(ts, 3, point=point)
                assert np.array_equal(got[i], alone), mode


def test_no_batch_size_leaves_a_motion_to_another_blas_kernel(rng):
    """The products of the coefficient tables run in blocks of rows (one BLAS thread each): a
    batch whose rows would leave a block of one row (BLAS's matrix-vector kernel, which rounds
    otherwise) still gives its last motion the bits of the motion alone."""
    ts = np.linspace(0, 1, 26)
    step = BLAS_ONE_THREAD // (3 * len(ts))  # rows a block: 3 Bernstein terms, 26 samples
    count = next(c for c in range(1, 4 * step) if 4 * c % step == 1)  # 4 rows a motion
    starts = matrices_from_quat_trans(rng.normal(size=(count, 4)), rng.normal(size=(count, 3)))
    ends = matrices_from_quat_trans(rng.normal(size=(count, 4)), rng.normal(size=(count, 3)))
    batch = a2b.motion(starts, ends, "darboux")
    got = batch.derivatives(ts, 1, point=np.zeros(3))
    for i in (count - 2, count - 1):
        assert np.array_equal(got[i], batch[i].derivatives(ts, 1, point=np.zeros(3)))


def test_path_rates_do_not_depend_on_the_layout_of_the_stack(rng):
    """``R x``, ``ẋ·ẍ`` and ``ẋ·x⃛`` are summed in one order (:func:`a2b.study.dots`): a stack
    laid out otherwise, as a batch's often is, gives the same bits (``einsum`` and ``@`` did
    not, for a point off the origin)."""
    stack = a2b.motion(random_pose(rng), random_pose(rng), "darboux").derivatives(
        np.linspace(0, 1, 64), 3
    )
    others = (
        np.asfortranarray(stack),
        np.moveaxis(np.moveaxis(stack, -1, 0).copy(), 0, -1),  # component-major
    )
    for point in (None, rng.normal(size=3)):
        want = path_rates(stack, point)
        for other in others:
            got = path_rates(other, point)
            for name in want:
                assert np.array_equal(got[name], want[name]), name


@pytest.mark.parametrize("mode", MODES)
def test_a_timed_batch_element_is_the_element_timed_alone(rng, mode):
    """Constant speed (arc lengths, their inversion, the progress's derivatives) and a point
    off the origin: every sampled value of a batch element is bit for bit the one alone."""
    starts = np.stack([random_pose(rng) for _ in range(4)])
    ends = np.stack([random_pose(rng) for _ in range(4)])
    point = rng.normal(size=3)
    limits = {"max_speed": 1.0, "max_accel": 2.0, "max_jerk": 5.0}
    motion = a2b.motion(starts, ends, mode)
    batch = timing(motion, "jerk-limited", point=point, constant_speed=True, **limits)
    times = batch.profile.duration[:, None] * np.linspace(0, 1, 11)
    got = (batch.parameters(times), batch.twists(times), batch.accelerations(times))
    rates = batch.rates(times)
    for i in range(4):
        alone = timing(motion[i], "jerk-limited", point=point, constant_speed=True, **limits)
        assert np.array_equal(batch.profile.coefficients[i], alone.profile.coefficients)
        assert np.array_equal(batch.path_length[i], alone.path_length)
        want = (alone.parameters(times[i]), alone.twists(times[i]))
        want += (alone.accelerations(times[i]),)
        for g, w in zip(got, want):
            assert np.array_equal(g[i], w)
        for name, value in alone.rates(times[i]).items():
            assert np.array_equal(rates[name][i], value), name


def _rng_limits(rng, names):
    return {f"max_{n}": float(np.exp(rng.uniform(-1.5, 1.5))) for n in names}


def test_jerk_limited_profile_has_ruckigs_time_optimal_duration():
    ruckig = pytest.importorskip("ruckig", reason="ruckig is a test dependency")
    rng = np.random.default_rng(7)
    count = 1000
    starts = np.stack([random_pose(rng) for _ in range(count)])
    ends = np.stack([random_pose(rng) for _ in range(count)])
    motion = a2b.motion(starts, ends, "darboux")
    v = np.exp(rng.uniform(-2, 2, count))
    a = np.exp(rng.uniform(-2, 2, count))
    j = np.exp(rng.uniform(-2, 2, count))
    timed = timing(
        motion, "jerk-limited", max_speed=v, max_accel=a, max_jerk=j, constant_speed=True
    )
    lengths = timed.path_length
    otg = ruckig.Ruckig(1)
    inp, out = ruckig.InputParameter(1), ruckig.Trajectory(1)
    worst = 0.0
    for i in range(count):
        inp.current_position, inp.target_position = [0.0], [float(lengths[i])]
        inp.max_velocity, inp.max_acceleration, inp.max_jerk = [v[i]], [a[i]], [j[i]]
        otg.calculate(inp, out)
        worst = max(worst, abs(timed.duration[i] / out.duration - 1))
    assert worst <= 1e-9, worst


def test_trapezoid_equals_its_closed_form():
    rng = np.random.default_rng(3)
    v, a = np.exp(rng.uniform(-2, 2, (2, 500)))
    got = trapezoid(v, a).duration
    want = np.where(v * v <= a, v / a + 1 / v, 2 * np.sqrt(1 / a))
    assert np.allclose(got, want, rtol=1e-13, atol=0)


@pytest.mark.slow  # a sweep of random limit sets: 10 s or more a profile
@pytest.mark.parametrize("profile", ["trapezoid", "jerk-limited", "quintic"])
def test_every_limit_holds_and_one_is_reached(profile):
    rng = np.random.default_rng(11)
    names = ["speed", "accel", "angular_speed", "angular_accel"]
    if profile != "trapezoid":
        names.append("jerk")
    for trial in range(4):
        for name, motion in _motions(rng).items():
            point = rng.normal(size=3) * 0.3 if trial % 2 else None
            limits = _rng_limits(rng, rng.choice(names, size=rng.integers(1, 4), replace=False))
            if profile == "jerk-limited" and "max_jerk" not in limits:
                limits["max_jerk"] = 5.0
            if profile == "trapezoid" and not {"max_accel", "max_angular_accel"} & set(limits):
                limits["max_accel"] = 2.0
            constant = bool(trial >= 2)
            timed = timing(motion, profile, point=point, constant_speed=constant, **limits)
            rates = timed.rates(timed.times(samples=2001))
            reached = []
            for key, limit in limits.items():
                peak = np.abs(rates[key[4:]]).max()
                assert peak <= limit * (1 + 1e-9), (name, key, peak, limit)
                reached.append(peak / limit)
            assert max(reached) >= 0.9, (name, limits, reached)  # a spline jumps at joints
            found = timed.peaks([k[4:] for k in limits])
            assert max(found[k[4:]] / lim for k, lim in limits.items()) == pytest.approx(1, 1e-9)


def test_constant_speed_covers_equal_lengths_in_equal_times(rng):
    for name, motion in _motions(rng).items():
        point = rng.normal(size=3)
        timed = timing(motion, "linear", duration=2.0, point=point, constant_speed=True)
        ts = timed.parameters(np.linspace(0, 2.0, 9))

        def speed(t, motion=motion, point=point):
            return float(motion.point_speeds(np.array([t]), point)[0])

        from scipy.integrate import quad  # scipy comes with pytransform3d, a test dependency

        pieces = [
            quad(speed, lo, hi, epsabs=0, epsrel=1e-13, limit=200)[0]
            for lo, hi in zip(ts[:-1], ts[1:])
        ]
        pieces = np.array(pieces)
        assert np.ptp(pieces) <= 1e-9 * pieces.mean(), (name, pieces)
        speeds = np.linalg.norm(timed.twists(np.linspace(0, 2, 50))[:, :3], axis=-1)
        assert np.ptp(speeds) <= 1e-9 * speeds.mean(), name


def test_arc_lengths_match_high_precision_quadrature(rng):
    """Each motion of a batch refines its own panels: the totals and the cumulative lengths at
    every panel edge agree with scipy's adaptive quadrature to 1e-11, the panel counts differ
    between motions (the padding is +inf), and an element equals its motion alone."""
    from scipy.integrate import quad

    from a2b.timelaw import arc_lengths

    starts = np.stack([random_pose(rng) for _ in range(24)])
    ends = np.stack([random_pose(rng) for _ in range(24)])
    point = rng.normal(size=3)
    for mode in MODES:
        motion = a2b.motion(starts, ends, mode)
        total, cumulative = arc_lengths(motion, point)
        panels = np.isfinite(cumulative).sum(axis=-1) - 1
        for i in range(24):
            edges = np.linspace(0.0, 1.0, panels[i] + 1)

            def speed(t, i=i):
                return float(motion[i].point_speeds(np.array([t]), point)[0])

            parts = [quad(speed, lo, hi, epsabs=0, epsrel=1e-13, limit=200)[0]
                     for lo, hi in zip(edges[:-1], edges[1:])]  # fmt: skip
            reference = np.concatenate([[0.0], np.cumsum(parts)])
            np.testing.assert_allclose(cumulative[i, : panels[i] + 1], reference, rtol=1e-11)
            assert np.all(cumulative[i, panels[i] + 1 :] == np.inf)
            assert total[i] == pytest.approx(reference[-1], rel=1e-11)
            alone = arc_lengths(motion[i], point)
            assert alone[0] == pytest.approx(total[i], rel=1e-14)
            np.testing.assert_allclose(alone[1], cumulative[i, : panels[i] + 1], rtol=1e-14)
        if mode == "darboux":
            assert len(set(panels.tolist())) > 1, panels  # some need more panels than others
    for name, curve in _motions(rng).items():  # curves: a panel never straddles a joint
        if not name.startswith(("bezier", "spline")):
            continue
        total, cumulative = arc_lengths(curve, point)
        edges = np.linspace(0.0, 1.0, cumulative.shape[-1])
        assert set(np.round(curve.joints(), 12)) <= set(np.round(edges, 12))

        def speed(t, curve=curve):
            return float(curve.point_speeds(np.array([t]), point)[0])

        parts = [quad(speed, lo, hi, epsabs=0, epsrel=1e-13, limit=200)[0]
                 for lo, hi in zip(edges[:-1], edges[1:])]  # fmt: skip
        np.testing.assert_allclose(cumulative[1:], np.cumsum(parts), rtol=1e-11, err_msg=name)
    grid = a2b.motion(starts.reshape(2, 3, 4, 4, 4), ends.reshape(2, 3, 4, 4, 4), "cubic")
    flat = arc_lengths(a2b.motion(starts, ends, "cubic"), point)[0]
    np.testing.assert_allclose(arc_lengths(grid, point)[0], flat.reshape(2, 3, 4), rtol=1e-14)


def test_an_arc_length_that_does_not_converge_names_its_motion(rng, monkeypatch):
    import a2b.timelaw.arclength

    starts = np.stack([random_pose(rng) for _ in range(4)])
    ends = starts.copy()
    ends[2] = random_pose(rng)  # the others stand still: their lengths are 0 at once
    monkeypatch.setattr(a2b.timelaw.arclength, "MOST_PANELS", 1)
    message = (
        r"motion 2: the path length of the point did not converge: two quadratures differ by "
        r".* relative, tolerance 1e-09"
    )
    with pytest.raises(a2b.A2bError, match=message):
        a2b.timelaw.arc_lengths(a2b.motion(starts, ends, "darboux"))


def test_a_point_that_stands_still_has_no_length_and_a_speed_limit_binds_nothing():
    """A rotation about a body point: its speeds are of rounding size, which no relative
    tolerance can refine (the arc length stops at a floor of 1e-12 of its distance)."""
    from a2b.poses import matrices_from_quat_trans
    from a2b.timelaw import arc_lengths

    point = np.array([1.0, 2.0, 3.0])
    axis = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8])
    turn = matrices_from_quat_trans(np.r_[np.cos(0.7), np.sin(0.7) * axis], np.zeros(3))
    shift = np.eye(4)
    shift[:3, 3] = point
    end = shift @ turn @ np.linalg.inv(shift)
    for mode in MODES:
        motion = a2b.motion(np.eye(4), end, mode)
        total, cumulative = arc_lengths(motion, point)
        assert total < 1e-13 and cumulative.shape == (2,)
        timed = timing(motion, max_speed=1.0, max_angular_speed=1.0, point=point)
        assert timed.binding == "angular_speed"


def test_limits_hold_where_a_long_cruise_crosses_a_narrow_turn():
    """A spline whose point nearly stops in t while it turns: at constant speed its angular
    acceleration peaks for 0.07 s of a 49 s law, between the time grid's points; the times at
    which the law passes evenly spaced t find it (this law exceeded the limit by 20 %)."""
    rng = np.random.default_rng(9)
    controls = np.stack([random_pose(rng) for _ in range(4)])
    limits = {"speed": 1.0, "accel": 2.0, "jerk": 5.0, "angular_speed": 1.5, "angular_accel": 3.0}
    timed = timing(
        spline_motion(controls, "study"),
        constant_speed=True,
        **{f"max_{k}": v for k, v in limits.items()},
    )
    rates = timed.rates(np.linspace(0.0, float(timed.duration), 20001))
    for name, limit in limits.items():
        assert np.max(np.abs(rates[name])) <= limit * (1 + 1e-9), name
    assert timed.binding == "angular_accel"
    assert np.max(rates["angular_accel"]) >= 3.0 * (1 - 1e-3)  # reached (between samples)


def test_duration_slows_the_law_down_and_a_short_one_is_refused(rng):
    motion = a2b.motion(random_pose(rng), random_pose(rng), "screw")
    fastest = timing(motion, max_speed=1.0, max_accel=1.0)
    slower = timing(motion, max_speed=1.0, max_accel=1.0, duration=fastest.duration * 2)
    assert slower.duration == pytest.approx(fastest.duration * 2, rel=1e-15)
    assert slower.binding == "duration"
    with pytest.raises(ParameterError, match=r"limit \(max_.*\) needs at least .* s; the duration"):
        timing(motion, max_speed=1.0, max_accel=1.0, duration=fastest.duration / 2)


def test_bad_requests_are_clear_errors(rng):
    motion = a2b.motion(random_pose(rng), random_pose(rng), "darboux")
    with pytest.raises(ParameterError, match="needs a duration or at least one limit"):
        timing(motion)
    with pytest.raises(ParameterError, match="unbounded jerk"):
        timing(motion, "trapezoid", max_accel=1, max_jerk=1)
    with pytest.raises(ParameterError, match="unbounded acceleration"):
        timing(motion, "linear", max_accel=1)
    with pytest.raises(ParameterError, match="is -1 length/s; usable values run from 1e-30"):
        timing(motion, max_speed=-1)
    with pytest.raises(ParameterError, match="profile must be one of"):
        timing(motion, "cubic", duration=1)
    timed = timing(motion, duration=1.0)
    with pytest.raises(ParameterError, match=r"times must lie in \[0, duration\]"):
        timed.matrices([0.5, 1.5])
    assert set(LIMITS) == {"speed", "accel", "jerk", "angular_speed", "angular_accel"}


def test_a_batch_is_timed_in_one_call_as_each_alone(rng):
    starts = np.stack([random_pose(rng) for _ in range(5)])
    ends = np.stack([random_pose(rng) for _ in range(5)])
    batch = timing(
        a2b.motion(starts, ends, "cubic"), max_speed=1.0, max_accel=2.0, max_angular_speed=1.5
    )
    for i in range(5):
        alone = timing(
            a2b.motion(starts[i], ends[i], "cubic"),
            max_speed=1.0,
            max_accel=2.0,
            max_angular_speed=1.5,
        )
        assert batch.duration[i] == pytest.approx(alone.duration, rel=1e-12)
        assert batch.binding[i] == alone.binding


def _cli(*args):
    from click.testing import CliRunner

    from a2b.cli import cli

    result = CliRunner().invoke(cli, list(args), catch_exceptions=False)
    return result


def test_written_samples_keep_the_limits_by_finite_differences(tmp_path):
    out = tmp_path / "timed.csv"
    result = _cli(
        "interpolate",
        "samples/quarter-turn.yaml",
        "--max-speed",
        "1",
        "--max-accel",
        "2",
        "--max-jerk",
        "4",
        "--point",
        "0.1,0.2,0",
        "--rate",
        "1000",
        "--velocities",
        "-o",
        str(out),
    )
    assert result.exit_code == 0, result.output
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    times, trans, quat = data[:, 0], data[:, 1:4], data[:, 4:8]
    from a2b.poses import matrices_from_quat_trans

    mats = matrices_from_quat_trans(quat, trans)
    point = mats[:, :3, :3] @ np.array([0.1, 0.2, 0.0]) + mats[:, :3, 3]
    steps = np.diff(times)
    speed = np.linalg.norm(np.diff(point, axis=0), axis=1) / steps
    assert speed.max() <= 1 + 1e-5
    # the written velocities are the point's: they agree with the differences
    mid = (data[1:, 8:11] + data[:-1, 8:11]) / 2
    assert np.allclose(mid, np.diff(point, axis=0) / steps[:, None], atol=2e-6)
    accel = np.abs(np.diff(speed) / steps[1:])
    assert accel.max() <= 2 * (1 + 1e-3)


def test_describe_compare_and_the_errors_of_the_command_line():
    result = _cli(
        "describe",
        "samples/quarter-turn.yaml",
        "--max-speed",
        "1",
        "--max-accel",
        "2",
        "--compare",
        "--json",
    )
    assert result.exit_code == 0, result.output
    import json

    figures = json.loads(result.output)["compare"]
    assert set(figures) == {"darboux", "cubic", "screw"}
    for column in figures.values():
        assert column["speed"] <= 1 + 1e-9 and column["accel"] <= 2 + 1e-9
        assert column["binding"] in ("speed", "accel")
    assert figures["screw"]["degree"].startswith("not rational")
    bad = _cli(
        "interpolate",
        "samples/quarter-turn.yaml",
        "--max-speed",
        "1",
        "--velocities",
        "--format",
        "tum",
    )
    assert bad.exit_code == 2 and "tum has no velocity field" in bad.output
    bad = _cli(
        "interpolate", "samples/quarter-turn.yaml", "--max-accel", "1", "--time-law", "linear"
    )
    assert bad.exit_code != 0 and "unbounded acceleration" in bad.output
    bad = _cli("interpolate", "samples/quarter-turn.yaml", "--rate", "10", "--dt", "0.1")
    assert bad.exit_code == 2 and "not both" in bad.output


def test_evo_reads_a_timed_tum_file(tmp_path, clients):
    import subprocess

    out = tmp_path / "timed.tum"
    result = _cli(
        "interpolate",
        "samples/quarter-turn.yaml",
        "--max-speed",
        "0.5",
        "--max-accel",
        "1",
        "--constant-speed",
        "--rate",
        "50",
        "-o",
        str(out),
    )
    assert result.exit_code == 0, result.output
    info = subprocess.run(
        [str(clients / "evo_traj"), "tum", str(out), "--full_check"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert info.returncode == 0, info.stderr
    assert "infos" in info.stdout and "path length" in info.stdout
