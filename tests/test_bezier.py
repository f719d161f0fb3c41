"""Bézier motions and splines (issue 6): a2b.bezier in both spaces."""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

import a2b
from a2b.cli import cli
from a2b.errors import InputFileError, ParameterError, PoseError, SingularMotionError
from a2b.extended import kernel_basis
from a2b.io.poseschema import read_pose_list
from a2b.motions._bernstein import first_small_value
from a2b.motions._rational import bern_mul
from a2b.motions.bezier import (
    SINGULAR_TOL,
    bezier,
    bezier_motion,
    default_m,
    spline,
    spline_motion,
)
from a2b.poses import matrices_from_quat_trans, quat_trans_from_matrices

SPACES = ("matrix", "study")
SAMPLES = Path(__file__).resolve().parents[1] / "samples"
TS = np.linspace(0.0, 1.0, 41)


@pytest.fixture
def rng():
    return np.random.default_rng(20240606)


def random_poses(rng, k, spread=1.0):
    """``k`` random poses; ``spread`` scales the rotation away from the identity."""
    quat = np.array([1.0, 0.0, 0.0, 0.0]) + spread * rng.normal(size=(k, 4))
    return matrices_from_quat_trans(quat, 2.0 * rng.normal(size=(k, 3)))


def about_axis(axis, angle):
    """Unit quaternion of the rotation by ``angle`` about the unit vector ``axis``."""
    return np.concatenate([[np.cos(angle / 2)], np.sin(angle / 2) * np.asarray(axis, float)])


def planar_poses(rng, k, normal, offset):
    """Poses rotating about ``normal`` with origins in the plane ``normal · x = offset``."""
    angles = rng.uniform(-1.5, 1.5, size=k)
    quats = np.stack([about_axis(normal, a) for a in angles])
    helper = np.eye(3)[np.argmin(np.abs(normal))]
    e1 = np.cross(normal, helper)
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(normal, e1)
    xy = rng.normal(size=(k, 2))
    trans = offset * normal + xy[:, :1] * e1 + xy[:, 1:] * e2
    return matrices_from_quat_trans(quats, trans)


def assert_rigid(mats, tol=1e-12):
    rot = mats[..., :3, :3]
    eye = np.broadcast_to(np.eye(3), rot.shape)
    assert np.max(np.abs(rot @ np.swapaxes(rot, -1, -2) - eye)) < tol
    assert np.max(np.abs(np.linalg.det(rot) - 1.0)) < tol
    assert np.all(mats[..., 3, :] == np.array([0.0, 0.0, 0.0, 1.0]))


def unit_normal(rng):
    n = rng.normal(size=3)
    return n / np.linalg.norm(n)


def psi_alphas(m, psis):
    """Fiber coefficients (paper basis) that give control points the x0 values ``psis``."""
    basis, _ = kernel_basis(m, "paper")
    alphas = np.zeros((len(psis), 6))
    alphas[:, 0] = (np.asarray(psis) - 1.0) / basis[0, 0]
    return alphas


# -- endpoints, rigidity, shapes ------------------------------------------------------------------


@pytest.mark.parametrize("space", SPACES)
@pytest.mark.parametrize("k", [2, 3, 4, 6])
def test_bezier_interpolates_first_and_last_control_and_is_rigid(rng, space, k):
    controls = random_poses(rng, k, spread=0.4)
    weights = rng.uniform(0.5, 2.0, size=k)
    extra = {"weights": weights}
    if space == "study":
        extra["offsets"] = rng.normal(size=k)
    else:
        extra["m"] = default_m(quat_trans_from_matrices(controls)[0]) + 0.1 * rng.normal(size=4)
        extra["alphas"] = 0.05 * rng.normal(size=(k, 6))
    poses = bezier(controls, TS, space=space, **extra)
    assert poses.shape == (len(TS), 4, 4)
    np.testing.assert_allclose(poses[0], controls[0], atol=1e-12)
    np.testing.assert_allclose(poses[-1], controls[-1], atol=1e-12)
    assert_rigid(poses)


@pytest.mark.parametrize("space", SPACES)
def test_same_answer_for_0_1_and_3_leading_dimensions(rng, space):
    controls = random_poses(rng, 4, spread=0.4)
    ts = rng.uniform(0.0, 1.0, size=(2, 3, 5))
    full = bezier(controls, ts, space=space)
    assert full.shape == (2, 3, 5, 4, 4)
    flat = bezier(controls, ts.ravel(), space=space)
    np.testing.assert_array_equal(full.reshape(-1, 4, 4), flat)
    np.testing.assert_allclose(
        bezier(controls, ts[1, 2, 3], space=space), full[1, 2, 3], atol=1e-15
    )
    spl = spline(controls, ts, space=space)
    assert spl.shape == (2, 3, 5, 4, 4)
    np.testing.assert_allclose(spl[0, 1, 2], spline(controls, ts[0, 1, 2], space=space), atol=1e-15)


@pytest.mark.parametrize("space", SPACES)
def test_quat_trans_and_study_agree_with_matrices_and_are_continuous(rng, space):
    motion = bezier_motion(random_poses(rng, 5, spread=0.5), space)
    quat, trans = motion.quat_trans(TS)
    np.testing.assert_allclose(
        matrices_from_quat_trans(quat, trans), motion.matrices(TS), atol=1e-12
    )
    assert quat[0, 0] >= 0.0
    assert np.min(np.sum(quat[1:] * quat[:-1], axis=-1)) > 0.5  # no sign jumps (−1)
    study = motion.study(TS)
    np.testing.assert_allclose(np.sum(study[:, :4] * study[:, 4:], axis=-1), 0.0, atol=1e-12)


def test_integer_ts_means_equally_spaced_samples(rng):
    controls = random_poses(rng, 3)
    np.testing.assert_array_equal(bezier(controls, 5), bezier(controls, np.linspace(0, 1, 5)))
    np.testing.assert_array_equal(spline(controls, 5), spline(controls, np.linspace(0, 1, 5)))


# -- two controls: the paper's two interpolants ----------------------------------------------------


def test_two_controls_in_matrix_space_are_the_cubic_mode_in_the_given_frame(rng):
    for _ in range(5):
        a, b = random_poses(rng, 2)
        m = rng.normal(size=4)
        alpha, beta = 0.02 * rng.normal(size=(2, 6))
        try:
            expected = a2b.interpolate(
                a, b, TS, mode="cubic", frame="given", m=m, alpha=alpha, beta=beta
            )
        except a2b.A2bError:
            continue  # a random m and fiber that the cubic mode rejects; tested below
        got = bezier([a, b], TS, space="matrix", m=m, alphas=[alpha, beta])
        np.testing.assert_allclose(got, expected, atol=1e-12)
    # the defaults agree too (m = pA + pB, α = β = 0)
    expected = a2b.interpolate(a, b, TS, mode="cubic", frame="given")
    np.testing.assert_allclose(bezier([a, b], TS), expected, atol=1e-12)
    np.testing.assert_allclose(spline([a, b], TS), expected, atol=1e-12)


def test_two_controls_in_study_space_are_the_darboux_mode(rng):
    for _ in range(5):
        a, b = random_poses(rng, 2)
        expected = a2b.interpolate(a, b, TS, mode="darboux", delta=0.0)
        np.testing.assert_allclose(bezier([a, b], TS, space="study"), expected, atol=1e-12)
        np.testing.assert_allclose(spline([a, b], TS, space="study"), expected, atol=1e-12)
        s_a, s_b = rng.normal(size=2)
        expected = a2b.interpolate(a, b, TS, mode="darboux", delta=s_b - s_a)
        got = bezier([a, b], TS, space="study", offsets=[s_a, s_b])
        np.testing.assert_allclose(got, expected, atol=1e-12)


@pytest.mark.parametrize("space", SPACES)
def test_weights_of_two_controls_reparametrise_the_line(rng, space):
    a, b = random_poses(rng, 2)
    w0, w1 = 0.7, 2.5
    reparam = w1 * TS / ((1 - TS) * w0 + TS * w1)
    got = bezier([a, b], TS, space=space, weights=[w0, w1])
    np.testing.assert_allclose(got, bezier([a, b], reparam, space=space), atol=1e-12)
    # a common factor of all weights changes nothing
    controls = random_poses(rng, 4, spread=0.4)
    weights = rng.uniform(0.5, 2.0, size=4)
    np.testing.assert_allclose(
        bezier(controls, TS, space=space, weights=3.0 * weights),
        bezier(controls, TS, space=space, weights=weights),
        atol=1e-12,
    )


# -- planar control poses give planar motions
# -------------------------------------------------------


@pytest.mark.parametrize("space", SPACES)
@pytest.mark.parametrize("build", ["bezier", "spline"])
def test_planar_control_poses_give_a_planar_motion(rng, space, build):
    normal, offset = unit_normal(rng), 0.8
    controls = planar_poses(rng, 4, normal, offset)
    params = {}
    if build == "bezier" and space == "matrix":
        params = {"m": rng.normal(size=4), "weights": [1.0, 2.0, 0.5, 1.0]}  # any m, still planar
    elif build == "bezier":  # equal κ-fiber offsets move every h(t) within its own fiber
        params = {"offsets": np.full(4, 0.7), "weights": [1.0, 2.0, 0.5, 1.0]}
    poses = (bezier if build == "bezier" else spline)(controls, TS, space=space, **params)
    assert_rigid(poses)
    # every rotation fixes the normal, every origin stays in the plane
    np.testing.assert_allclose(
        poses[:, :3, :3] @ normal, np.broadcast_to(normal, (len(TS), 3)), atol=1e-12
    )
    np.testing.assert_allclose(poses[:, :3, 3] @ normal, offset, atol=1e-12)
    # so every point of the moving body moves in a plane parallel to it
    point = rng.normal(size=3)
    path = poses[:, :3, :3] @ point + poses[:, :3, 3]
    np.testing.assert_allclose(path @ normal - (path[0] @ normal), 0.0, atol=1e-12)


def test_unequal_fiber_offsets_leave_the_plane(rng):
    """In Study space, offsets s_i act like the Darboux δ: a translation along the normal."""
    normal = unit_normal(rng)
    controls = planar_poses(rng, 3, normal, 0.0)
    poses = bezier(controls, TS, space="study", offsets=[0.0, 0.5, 0.0])
    assert np.max(np.abs(poses[:, :3, 3] @ normal)) > 1e-2
    np.testing.assert_allclose(
        poses[:, :3, :3] @ normal, np.broadcast_to(normal, (len(TS), 3)), atol=1e-12
    )


def test_planar_sample_is_a_planar_cubic_through_its_first_and_last_control():
    with open(SAMPLES / "planar-bezier.yaml", "rb") as fh:
        curve = read_pose_list(fh, "controls")
    assert curve.poses.shape == (4, 4, 4)
    ez = np.array([0.0, 0.0, 1.0])
    for space in SPACES:
        motion = bezier_motion(curve.poses, space)
        assert motion.degree == 3
        poses = motion.matrices(TS)
        assert_rigid(poses)
        np.testing.assert_allclose(poses[[0, -1]], curve.poses[[0, -1]], atol=1e-12)
        np.testing.assert_allclose(
            poses[:, :3, :3] @ ez, np.broadcast_to(ez, (len(TS), 3)), atol=1e-12
        )
        np.testing.assert_allclose(poses[:, 2, 3], 0.0, atol=1e-12)


# -- splines ---------------------------------------------------------------------------------------


@pytest.mark.parametrize("space", SPACES)
def test_spline_passes_through_every_key_pose_and_is_rigid(rng, space):
    keys = random_poses(rng, 6, spread=0.5)
    motion = spline_motion(keys, space)
    np.testing.assert_allclose(motion.matrices(np.linspace(0, 1, 6)), keys, atol=1e-12)
    assert motion.joints() == pytest.approx([0.2, 0.4, 0.6, 0.8])
    assert_rigid(motion.matrices(np.linspace(0, 1, 301)))


def one_sided_derivatives(f, t, h):
    """Second-order one-sided difference quotients of ``f`` at ``t`` from the left and the right."""
    left = (3 * f(t) - 4 * f(t - h) + f(t - 2 * h)) / (2 * h)
    right = (-3 * f(t) + 4 * f(t + h) - f(t + 2 * h)) / (2 * h)
    return left, right


@pytest.mark.parametrize("space", SPACES)
def test_spline_is_c1_at_the_joints(rng, space):
    keys = random_poses(rng, 5, spread=0.5)
    motion = spline_motion(keys, space)
    segments = motion.controls.shape[0]
    # the curve in R^13 (or R^8): derivatives from the Bernstein coefficients of both segments
    ctrl = motion.controls
    ends = 3 * segments * (ctrl[:-1, 3] - ctrl[:-1, 2])
    starts = 3 * segments * (ctrl[1:, 1] - ctrl[1:, 0])
    np.testing.assert_allclose(ends, starts, atol=1e-12)
    np.testing.assert_array_equal(ctrl[:-1, 3], ctrl[1:, 0])
    # ... and numerically, on the curve itself and on the pose curve
    h = 1e-5  # truncation error O(h²) ≈ 1e-10, rounding ≈ 1e-16 / h
    for t in motion.joints():
        left, right = one_sided_derivatives(lambda s: motion.points(np.array([s]))[0], t, h)
        np.testing.assert_allclose(left, right, atol=1e-7)
        left, right = one_sided_derivatives(lambda s: motion.matrices(np.array([s]))[0], t, h)
        assert np.max(np.abs(left - right)) < 1e-7 * max(np.max(np.abs(left)), 1.0)


def test_the_c1_check_detects_a_kink(rng):
    """Chained two-pose cubic motions are only C⁰; the same check sees the jump."""
    keys = random_poses(rng, 3, spread=0.5)

    def chained(s):
        if s <= 0.5:
            return a2b.interpolate(keys[0], keys[1], [2 * s], mode="cubic", frame="given")[0]
        return a2b.interpolate(keys[1], keys[2], [2 * s - 1], mode="cubic", frame="given")[0]

    left, right = one_sided_derivatives(chained, 0.5, 1e-4)
    assert np.max(np.abs(left - right)) > 1e-2


def test_matrix_spline_controls_have_x0_one_and_catmull_rom_tangents(rng):
    keys = random_poses(rng, 4, spread=0.5)
    motion = spline_motion(keys, "matrix")
    np.testing.assert_array_equal(motion.controls[..., 0], 1.0)
    ctrl = motion.controls
    points = ctrl[:, 0]
    # inner tangent of key 1: (X2 − X0)/2 = 3 · (first inner control − X1) of segment 1
    np.testing.assert_allclose(
        3 * (ctrl[1, 1] - ctrl[1, 0]), 0.5 * (ctrl[2, 0] - points[0]), atol=1e-14
    )
    # translations form the Catmull–Rom spline of the key translations
    trans = motion.matrices(np.array([0.5 / 3]))[0, :3, 3]
    t0, t1, t2 = keys[0, :3, 3], keys[1, :3, 3], keys[2, :3, 3]
    tangent0, tangent1 = t1 - t0, 0.5 * (t2 - t0)
    bez = [t0, t0 + tangent0 / 3, t1 - tangent1 / 3, t1]
    np.testing.assert_allclose(trans, (bez[0] + 3 * bez[1] + 3 * bez[2] + bez[3]) / 8, atol=1e-12)


# -- the root finder -------------------------------------------------------------------------------


def linear(root):
    return np.array([-root, 1.0 - root])


def test_first_small_value_finds_simple_double_and_no_zeros():
    cubic = bern_mul(bern_mul(linear(0.3), linear(0.7)), linear(0.71))
    assert first_small_value(cubic, 0.0, 1.0)[0] == pytest.approx(0.3, abs=1e-15)
    assert first_small_value(-cubic[::-1], 0.0, 1.0)[0] == pytest.approx(0.29, abs=1e-15)
    double = bern_mul(linear(0.55), linear(0.55))  # touches zero, no sign change
    assert first_small_value(double, 0.0, 1.0)[0] == pytest.approx(0.55, abs=1e-12)
    assert first_small_value(double + 1e-3, 0.0, 1.0) is None
    assert first_small_value(double + 0.5 * SINGULAR_TOL * 0.2025, 0.0, 1.0)[0] == pytest.approx(
        0.55
    )
    assert first_small_value(cubic, 0.75, 2.0) is None
    assert first_small_value(cubic, -1.0, 0.1) is None
    assert first_small_value(linear(-0.25), -1.0, 0.0)[0] == pytest.approx(-0.25)


# -- errors ----------------------------------------------------------------------------------------


def test_control_pose_orthogonal_to_m_names_the_control_and_its_t(rng):
    controls = random_poses(rng, 4, spread=0.3)
    quat = quat_trans_from_matrices(controls)[0]

    def orthogonal_to(p):
        v = rng.normal(size=4)
        return v - (v @ p) * p

    m = orthogonal_to(quat[1])
    with pytest.raises(
        ParameterError, match=r"control pose 2 of 4 \(Greville abscissa t = 0\.333333\)"
    ):
        bezier(controls, TS, m=m)
    with pytest.raises(ParameterError, match=r"control pose 1 of 4 \(t = 0\).*m·p = "):
        bezier(controls, TS, m=orthogonal_to(quat[0]))
    with pytest.raises(ParameterError, match=r"control pose 4 of 4 \(t = 1\)"):
        bezier(controls, TS, m=orthogonal_to(quat[3]))
    with pytest.raises(ParameterError, match=r"pose 3 of 4 \(t = 0\.666667\)"):
        spline(controls, TS, m=orthogonal_to(quat[2]))


def test_curve_through_infinity_simple_zero(rng):
    controls = random_poses(rng, 3, spread=0.3)
    m = np.array([1.0, 0.3, -0.2, 0.4])
    # x0 = (1−t)² + 2t(1−t) − t² = 1 − 2t², zero at t = 1/√2
    with pytest.raises(
        SingularMotionError, match=r"passes through infinity at t = 0\.707107: x0\(t\) = 0"
    ):
        bezier(controls, TS, m=m, alphas=psi_alphas(m, [1.0, 1.0, -1.0]))


def test_curve_through_infinity_double_zero_without_sign_change(rng):
    controls = random_poses(rng, 3, spread=0.3)
    m = np.array([1.0, 0.3, -0.2, 0.4])
    # x0 = (1−t)² − 2t(1−t) + t² = (1 − 2t)²: touches zero at t = 1/2
    with pytest.raises(
        SingularMotionError, match=r"through infinity at t = 0\.5\b.*tolerance 1e-12"
    ):
        bezier(controls, TS, m=m, alphas=psi_alphas(m, [1.0, -1.0, 1.0]))


def test_two_controls_through_infinity_match_the_cubic_mode(rng):
    a, b = random_poses(rng, 2, spread=0.3)
    m = np.array([1.0, 0.3, -0.2, 0.4])
    alphas = psi_alphas(m, [1.0, -3.0])  # x0 = 1 − 4t, zero at t = 1/4
    with pytest.raises(SingularMotionError, match=r"t = 0\.25\b"):
        bezier([a, b], TS, m=m, alphas=alphas)
    with pytest.raises(SingularMotionError, match=r"t = 0\.25\b"):
        a2b.interpolate(a, b, TS, mode="cubic", frame="given", m=m, alpha=alphas[0], beta=alphas[1])


def test_study_curve_through_p_zero():
    """Rotations about z whose half-angles step by 89°; weights put p(1/2) at the origin."""
    half = np.radians([0.0, 89.0, 178.0, 267.0])
    quats = np.stack([about_axis([0, 0, 1], 2 * h) for h in half])
    controls = matrices_from_quat_trans(quats, np.zeros((4, 3)))
    p = np.stack([np.cos(half), np.sin(half)], axis=1)  # the consistent signs, in the (1, k) plane
    # p0 + 3 w1 p1 + 3 w2 p2 + w3 p3 = 0 with w1 = 1
    w2, w3 = np.linalg.solve(np.stack([3 * p[2], p[3]], axis=1), -p[0] - 3 * p[1])
    assert w2 > 0 and w3 > 0
    with pytest.raises(
        SingularMotionError, match=r"through p\(t\) = 0 \(no rotation defined\) at t = 0\.5\b"
    ):
        bezier(controls, TS, space="study", weights=[1.0, 1.0, w2, w3])


def test_matrix_space_p_never_vanishes_on_the_unit_interval_but_can_beyond(rng):
    """m·p(t) = 4 Σ B_i w_i (m·p_i)² > 0 on [0, 1]; extrapolation is checked as well."""
    quats = np.stack([about_axis([0, 0, 1], a) for a in (0.0, 2.0)])
    controls = matrices_from_quat_trans(quats, rng.normal(size=(2, 3)))
    m = np.array([1.0, 0.0, 0.0, -0.9])  # m·p_1 < 0: the rotation weights have opposite signs
    motion = bezier_motion(controls, "matrix", m=m)
    assert np.prod(motion.describe()["rotation_weights"]) < 0
    assert_rigid(motion.matrices(np.linspace(-3.0, 4.0, 50)))
    # the same rotation twice, weights 1 and 3, ψ = 1 and 1/3: x0 ≡ 1, p(t) = (1 + 2t) 4 (m·p) p
    same = np.stack([controls[0], controls[0]])
    same[1, :3, 3] += 1.0
    m = np.array([1.0, 0.3, -0.2, 0.4])
    motion = bezier_motion(
        same, "matrix", m=m, weights=[1.0, 3.0], alphas=psi_alphas(m, [1.0, 1.0 / 3.0])
    )
    motion.matrices(np.array([-0.2, 1.5]))
    with pytest.raises(SingularMotionError, match=r"p\(t\) = 0 .* at t = -0\.5\b"):
        motion.matrices(np.array([-1.0, 0.5]))


def test_extrapolation_through_infinity_is_reported(rng):
    controls = random_poses(rng, 2, spread=0.3)
    m = np.array([1.0, 0.3, -0.2, 0.4])
    motion = bezier_motion(controls, "matrix", m=m, alphas=psi_alphas(m, [1.0, 3.0]))  # x0 = 1 + 2t
    motion.matrices(TS)
    with pytest.raises(SingularMotionError, match=r"through infinity at t = -0\.5\b"):
        motion.matrices(np.array([-0.75, 0.0]))


def test_parameter_errors(rng):
    controls = random_poses(rng, 3)
    with pytest.raises(ParameterError, match="unknown space 'dual'"):
        bezier(controls, TS, space="dual")
    with pytest.raises(
        ParameterError, match=r"weights must be positive; control pose 2 of 3 has weight -1"
    ):
        bezier(controls, TS, weights=[1.0, -1.0, 1.0])
    with pytest.raises(
        ParameterError, match=r"weights needs one number per control pose, shape \(3,\)"
    ):
        bezier(controls, TS, weights=[1.0, 1.0])
    with pytest.raises(
        ParameterError, match=r"alphas needs 6 numbers per control pose, shape \(3, 6\)"
    ):
        bezier(controls, TS, alphas=np.zeros((2, 6)))
    with pytest.raises(ParameterError, match="space study does not take m, alphas"):
        bezier(controls, TS, space="study", m=[1, 0, 0, 0], alphas=np.zeros((3, 6)))
    with pytest.raises(ParameterError, match="space matrix does not take offsets"):
        bezier(controls, TS, offsets=[0, 0, 0])
    with pytest.raises(ParameterError, match="space study does not take m"):
        spline(controls, TS, space="study", m=[1, 0, 0, 0])
    with pytest.raises(ParameterError, match="at least 2 control poses, got 1"):
        bezier(controls[:1], TS)
    with pytest.raises(PoseError, match="not orthogonal"):
        bezier(controls * np.array([1.1, 1, 1, 1])[:, None], TS)
    with pytest.raises(ParameterError, match="ts contains NaN"):
        bezier(controls, [0.0, np.nan])
    # m = (1, 0, 0, 0) degenerates the paper's basis (docs/math.md, correction 5): fiber
    # coefficients need rref, which the default basis, auto, takes
    with pytest.raises(ParameterError, match="degenerates"):
        bezier(controls, TS, m=[1.0, 0.0, 0.0, 0.0], alphas=np.zeros((3, 6)), basis="paper")
    np.testing.assert_array_equal(
        bezier(controls, TS, m=[1.0, 0.0, 0.0, 0.0], alphas=np.zeros((3, 6))),
        bezier(controls, TS, m=[1.0, 0.0, 0.0, 0.0], alphas=np.zeros((3, 6)), basis="rref"),
    )


def test_default_m_of_cancelling_rotations_is_an_error():
    quats = np.stack([about_axis([0, 0, 1], a) for a in (0.0, np.pi, 2 * np.pi - 1e-3)])
    # consistent signs: 1, k, then ≈ −1 (a full turn, nearly): the sum is ≈ k, fine
    assert np.linalg.norm(default_m(quats)) > 0.5
    with pytest.raises(ParameterError, match="no default m: .* not lie in one open half-space"):
        default_m(np.array([[1.0, 0, 0, 0], [0, 0, 0, 1.0], [-1.0, 0, 0, 0], [0, 0, 0, -1.0]]))


# -- the command line ------------------------------------------------------------------------------


def run(*args, input=None):
    return CliRunner().invoke(cli, list(args), input=input, catch_exceptions=False)


PLANAR_CSV = """t,tx,ty,tz,qw,qx,qy,qz
0.0,0.0,0.0,0.0,1.0,0.0,0.0,0.0
0.25,0.90625,1.125,0.0,0.9298351215248353,0.0,0.0,0.36797642149857207
0.5,2.0,1.5,0.0,0.7071067811865476,0.0,0.0,0.7071067811865476
0.75,3.09375,1.125,0.0,0.36797642149857207,0.0,0.0,0.9298351215248353
1.0,4.0,0.0,0.0,0.0,0.0,0.0,1.0
"""


def test_cli_bezier_planar_sample_exact_output():
    result = run("bezier", str(SAMPLES / "planar-bezier.yaml"), "--samples", "5")
    assert result.exit_code == 0, result.output
    assert result.output == PLANAR_CSV


@pytest.mark.parametrize("command", ["bezier", "spline"])
def test_cli_help_has_an_example(command):
    for flag in ("-h", "--help"):
        result = run(command, flag)
        assert result.exit_code == 0
        assert "Example:" in result.output
        assert f"a2b {command} samples/" in result.output


def read_matrix_output(text):
    from a2b.io.trajectories import read_matrix_csv

    return read_matrix_csv(io.StringIO(text))


@pytest.mark.parametrize("space", SPACES)
def test_cli_bezier_matches_the_library_with_options_overriding_the_file(space):
    with open(SAMPLES / "planar-bezier.yaml", "rb") as fh:
        controls = read_pose_list(fh, "controls").poses
    extra = ["--weights", "1,2,2,1"]
    params = {"weights": [1.0, 2.0, 2.0, 1.0]}
    if space == "matrix":
        extra += ["--m", "1,0,0,0.5", "--basis", "rref"] + ["--alpha", "0.1,0,0,0,0,0"] * 4
        params.update(
            m=[1.0, 0.0, 0.0, 0.5], basis="rref", alphas=np.tile([0.1, 0, 0, 0, 0, 0], (4, 1))
        )
    else:
        extra += ["--offsets", "0,0.1,0.2,0"]
        params["offsets"] = [0.0, 0.1, 0.2, 0.0]
    result = run(
        "bezier",
        str(SAMPLES / "planar-bezier.yaml"),
        "--space",
        space,
        "--samples",
        "7",
        "--format",
        "matrix",
        *extra,
    )
    assert result.exit_code == 0, result.output
    ts, mats = read_matrix_output(result.output)
    np.testing.assert_array_equal(ts, np.linspace(0, 1, 7))
    np.testing.assert_array_equal(mats, bezier(controls, ts, space=space, **params))


@pytest.mark.parametrize("space", SPACES)
def test_cli_spline_hits_every_key_pose(space, tmp_path):
    with open(SAMPLES / "spline.yaml", "rb") as fh:
        keys = read_pose_list(fh, "poses").poses
    out = tmp_path / "spline.csv"
    result = run(
        "spline",
        str(SAMPLES / "spline.yaml"),
        "--space",
        space,
        "--samples",
        "9",
        "--format",
        "matrix",
        "-o",
        str(out),
    )
    assert result.exit_code == 0 and result.output == ""
    ts, mats = read_matrix_output(out.read_text())
    np.testing.assert_allclose(mats[::2], keys, atol=1e-12)
    np.testing.assert_array_equal(mats, spline(keys, ts, space=space))


def test_cli_reads_stdin_and_file_parameters():
    text = """{"controls": [{"quaternion_wxyz": [1, 0, 0, 0]},
                            {"quaternion_wxyz": [0, 0, 0, 1], "translation": [1, 0, 0]}],
               "space": "study", "samples": 3, "parameters": {"offsets": [0, 0.5]}}"""
    result = run("bezier", "-", "--format", "matrix", input=text)
    assert result.exit_code == 0, result.output
    ts, mats = read_matrix_output(result.output)
    b = np.eye(4)
    b[:3, :3] = [[-1, 0, 0], [0, -1, 0], [0, 0, 1]]
    b[0, 3] = 1.0
    np.testing.assert_allclose(
        mats, a2b.interpolate(np.eye(4), b, ts, mode="darboux", delta=0.5), atol=1e-15
    )


def test_cli_errors_are_one_line_with_file_position_or_t():
    planar = str(SAMPLES / "planar-bezier.yaml")
    result = run("bezier", planar, "--m", "0,1,0,0")
    assert result.exit_code == 1
    assert "orthogonal to the quaternion of the control pose 1 of 4 (t = 0)" in result.output
    assert "Traceback" not in result.output
    result = run(
        "bezier",
        planar,
        "--m",
        "1,0,0,1",
        "--basis",
        "rref",
        "--alpha",
        "0,0,0,0,0,0",
        "--alpha",
        "0,0,0,0,0,0",
        "--alpha",
        "0,0,0,0,0,0",
        "--alpha",
        "-2,0,0,0,0,0",
    )
    assert result.exit_code == 1
    assert "passes through infinity at t = " in result.output
    result = run("bezier", planar, "--weights", "1,2")
    assert result.exit_code == 1
    assert "weights needs one number per control pose, shape (4,)" in result.output
    result = run(
        "bezier",
        "-",
        input="controls:\n  - quaternion_wxyz: [1, 0, 0, 0]\n  - quaternion_wxyz: [1, 0, 0]\n",
    )
    assert result.exit_code == 1
    assert (
        "<stdin>:3:5: controls[1].quaternion_wxyz: expected 4 numbers (w, x, y, z), got 3"
        in result.output
    )
    result = run("spline", "-", input="poses:\n  - quaternion_wxyz: [1, 0, 0, 0]\n")
    assert result.exit_code == 1
    assert "<stdin>:1:1: poses: expected a list of at least two poses, got 1" in result.output
    result = run("spline", "-", input="controls: []\n")
    assert result.exit_code == 1
    assert "unknown key 'controls' in a poses file" in result.output
    result = run(
        "spline", planar.replace("planar-bezier", "spline"), "--space", "study", "--m", "1,0,0,0"
    )
    assert result.exit_code == 1
    assert "space study does not take m" in result.output


def test_read_pose_list_checks_per_control_parameters():
    text = b"""controls:
  - quaternion_wxyz: [1, 0, 0, 0]
  - quaternion_wxyz: [1, 0, 0, 0]
parameters:
  alphas: [[0, 0, 0, 0, 0, 0]]
"""
    with pytest.raises(
        InputFileError, match=r"curve.yaml:5:3: parameters.alphas: expected 2 lists of 6 numbers"
    ):
        read_pose_list(io.BytesIO(text), "controls", name="curve.yaml")


def test_default_m_takes_every_pose_the_short_way_or_says_it_cannot():
    half = np.radians([0.0] * 10 + [50.0, 100.0])
    quats = np.stack([np.cos(half), 0 * half, 0 * half, np.sin(half)], axis=1)
    keys = matrices_from_quat_trans(quats, np.arange(36.0).reshape(12, 3))
    # the sum points 9.5° from the identity, 90.5° from the last pose: m·p < 0 there
    assert quats[-1] @ quats.sum(axis=0) < 0
    motion = spline_motion(keys, "matrix", m=quats.sum(axis=0))
    assert "opposite sign for pose(s) 12" in motion.choices[-1]
    m = default_m(quats)
    assert np.linalg.norm(m) == pytest.approx(1.0)
    assert np.min(quats @ m) > 0.99 * np.cos(np.radians(50.0))  # the best margin is cos 50°
    motion = spline_motion(keys, "matrix")
    assert "maximising min m·p_i" in motion.choices[-1]
    assert motion.describe()["poses"] == 12
    # 19 steps of 30° about z: 570°, no half-space holds the quaternions
    angles = np.radians(30.0) * np.arange(20)
    turning = matrices_from_quat_trans(
        np.stack([np.cos(angles / 2), 0 * angles, 0 * angles, np.sin(angles / 2)], axis=1),
        np.zeros((20, 3)),
    )
    with pytest.raises(ParameterError, match=r"no default m: .* use space study"):
        spline(turning, TS)
    spline(turning, TS, space="study")


def test_a_long_spline_lists_ten_flipped_poses_and_counts_the_rest():
    """A trajectory's spline may flip the signs of many poses: the choice lists the first ten
    (numbered from 1) and how many more, not every one (a resampled trajectory has 10^6)."""
    from a2b.motions.bezier import spline_motion
    from a2b.poses import matrices_from_quat_trans

    angles = 1.0 * np.arange(80)  # about z, past π again and again: w ≥ 0 flips the sign
    quat = np.stack([np.cos(angles / 2), 0 * angles, 0 * angles, np.sin(angles / 2)], axis=1)
    poses = matrices_from_quat_trans(quat, np.zeros((80, 3)))
    (text,) = [c for c in spline_motion(poses, "study").choices if "flipped" in c]
    listed = text.split("pose(s) ")[1].split(" and ")[0].split(", ")
    more = int(text.split(" and ")[1].split(" more")[0])
    assert listed == ["5", "6", "7", "8", "9", "10", "17", "18", "19", "20"]  # 4 rad is past π
    assert more == 29 and text.endswith("so that consecutive quaternions have p_i·p_{i+1} ≥ 0")
