"""The motions against the paper's theorems (Theorems 1 and 2) and docs/math.md's closed forms."""

import math
import warnings

import numpy as np
import pytest

import a2b
from a2b.errors import ParameterError, PoseError, SingularMotionError
from a2b.extended import matrices_from_model_points, mu_fiber_points, paper_kernel_basis
from a2b.frames import screw_frame
from a2b.poses import inverse_matrices, matrices_from_quat_trans, study_from_matrices
from a2b.study import kappa

from .conftest import commutator, pose_about_axis, random_pose, rigidity

TS = np.linspace(0.0, 1.0, 13)

CONFIGS = [
    ("darboux", {}),
    ("darboux", {"delta": 0.8}),
    ("darboux", {"delta": -0.3, "long_way": True}),
    ("cubic", {}),
    ("cubic", {"a": 0.4, "b": -0.3}),
    ("cubic", {"frame": "given"}),
    ("cubic", {"frame": "given", "m": [0.9, 0.2, -0.4, 0.5], "a": 0.2, "b": 0.7}),
    ("screw", {}),
]


def pairs(rng, count=4, scale=2.0):
    return [(random_pose(rng, scale), random_pose(rng, scale)) for _ in range(count)]


def rel_canonical(frame, mats):
    return frame.transmission(mats)


# --------------------------------------------------------------------------------------------
# the canonical frame
# --------------------------------------------------------------------------------------------


def test_screw_frame_reproduces_the_displacement(rng):
    for a, b in pairs(rng, 10):
        f = screw_frame(a, b)
        assert 0.0 <= f.phi <= math.pi
        assert abs(np.linalg.norm(f.axis_direction) - 1) < 1e-15
        assert abs(f.axis_point @ f.axis_direction) < 1e-12 * max(1, np.linalg.norm(f.axis_point))
        disp = pose_about_axis(f.phi, f.axis_direction, f.axis_point, f.d)
        np.testing.assert_allclose(disp @ a, b, atol=1e-12)
        # the canonical transform takes A to I and B to the screw about z
        can = f.to_canonical(np.stack([a, b]), a)
        np.testing.assert_allclose(can[0], np.eye(4), atol=1e-12)
        np.testing.assert_allclose(
            can[1], pose_about_axis(f.phi, [0, 0, 1], [0, 0, 0], f.d), atol=1e-12
        )


def test_frame_of_a_pure_translation_and_of_equal_poses(rng):
    a = random_pose(rng)
    b = a.copy()
    b[:3, 3] += [0, 3, 4]
    f = screw_frame(a, b)
    assert f.phi == 0.0 and f.d == pytest.approx(5.0)
    np.testing.assert_allclose(f.axis_direction, [0, 0.6, 0.8])
    assert any("pure translation" in c for c in f.choices)
    g = screw_frame(a, a)
    assert g.phi == 0.0 and g.d == 0.0
    assert any("B = A" in c for c in g.choices)


@pytest.mark.parametrize("slide", [2.0, -2.0, 0.0])
def test_frame_of_an_exact_half_turn_picks_and_states_an_orientation(slide):
    b = np.eye(4)
    b[:3, :3] = np.diag([1.0, -1.0, -1.0])
    b[0, 3] = slide
    f = screw_frame(np.eye(4), b)
    assert f.phi == pytest.approx(math.pi)
    assert f.d == pytest.approx(abs(slide))
    np.testing.assert_allclose(f.axis_direction, [1, 0, 0] if slide >= 0 else [-1, 0, 0])
    assert any("φ = π" in c for c in f.choices)


# --------------------------------------------------------------------------------------------
# every mode
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize("mode, params", CONFIGS)
def test_end_poses_reproduced_and_every_sample_rigid(rng, mode, params):
    for a, b in pairs(rng):
        mats = a2b.interpolate(a, b, TS, mode, **params)
        assert mats.shape == (len(TS), 4, 4)
        np.testing.assert_allclose(mats[0], a, atol=1e-13)
        np.testing.assert_allclose(mats[-1], b, atol=1e-13)
        assert rigidity(mats) < 1e-13


@pytest.mark.parametrize("mode, params", CONFIGS)
def test_quaternions_and_study_agree_with_matrices_and_are_continuous(rng, mode, params):
    a, b = random_pose(rng), random_pose(rng)
    motion = a2b.motion(a, b, mode, **params)
    ts = np.linspace(0, 1, 200)
    quat, trans = motion.quat_trans(ts)
    np.testing.assert_allclose(
        matrices_from_quat_trans(quat, trans), motion.matrices(ts), atol=1e-13
    )
    np.testing.assert_allclose(np.linalg.norm(quat, axis=1), 1.0, atol=1e-15)
    assert np.all(np.sum(quat[1:] * quat[:-1], axis=1) > 0.9)  # no sign jumps
    study = motion.study(ts)
    np.testing.assert_allclose(
        a2b.poses.matrices_from_study(study), motion.matrices(ts), atol=1e-13
    )


@pytest.mark.parametrize(
    "mode, params",
    [c for c in CONFIGS if not (c[0] == "cubic" and c[1].get("frame") == "given")],
)
def test_motions_do_not_depend_on_the_choice_of_frames(rng, mode, params):
    """κ is equivariant; the canonical cubic frame makes μ_[m] so as well."""
    a, b = random_pose(rng), random_pose(rng)
    g, h = random_pose(rng, 3), random_pose(rng, 3)
    direct = a2b.interpolate(g @ a @ h, g @ b @ h, TS, mode, **params)
    moved = g @ a2b.interpolate(a, b, TS, mode, **params) @ h
    np.testing.assert_allclose(direct, moved, atol=1e-12)


@pytest.mark.parametrize("mode, params", CONFIGS)
def test_extrapolation_outside_0_1_stays_on_the_motion(rng, mode, params):
    a, b = random_pose(rng), random_pose(rng)
    motion = a2b.motion(a, b, mode, **params)
    ts = np.array([-0.5, 0.0, 0.5, 1.0, 1.25])
    mats = motion.matrices(ts)
    assert rigidity(mats) < 1e-12
    np.testing.assert_allclose(mats[1:4], motion.matrices(ts[1:4]), atol=0)


def test_the_three_modes_differ(rng):
    a, b = random_pose(rng), random_pose(rng)
    ts = np.array([0.3])
    d, c, s = (a2b.interpolate(a, b, ts, mode) for mode in ("darboux", "cubic", "screw"))
    assert np.abs(d - c).max() > 1e-3 and np.abs(d - s).max() > 1e-3 and np.abs(c - s).max() > 1e-3


# --------------------------------------------------------------------------------------------
# darboux (Theorem 1)
# --------------------------------------------------------------------------------------------


def kappa_line(h_a, h_b, s_a, s_b, ts):
    """Poses of κ((1−t)(hA + sA εpA) + t(hB + sB εpB)), straight from the definition."""
    line_a = h_a.copy()
    line_a[4:] += s_a * h_a[:4]
    line_b = h_b.copy()
    line_b[4:] += s_b * h_b[:4]
    points = (1 - ts)[:, None] * line_a + ts[:, None] * line_b
    rot, trans = kappa(points)
    out = np.zeros((len(ts), 4, 4))
    out[:, :3, :3], out[:, :3, 3], out[:, 3, 3] = rot, trans, 1
    return out


def test_darboux_is_kappa_of_the_line_and_depends_on_delta_only(rng):
    for a, b in pairs(rng):
        h_a, h_b = study_from_matrices(a), study_from_matrices(b)
        if h_a[:4] @ h_b[:4] < 0:
            h_b = -h_b
        delta = rng.normal()
        expected = a2b.interpolate(a, b, TS, "darboux", delta=delta)
        for shift in rng.normal(size=3) * 5:
            np.testing.assert_allclose(
                kappa_line(h_a, h_b, shift, shift + delta, TS), expected, atol=1e-12
            )


def test_darboux_delta_zero_is_linear_interpolation_of_unit_study_vectors(rng):
    a, b = random_pose(rng), random_pose(rng)
    h_a, h_b = study_from_matrices(a), study_from_matrices(b)
    if h_a[:4] @ h_b[:4] < 0:
        h_b = -h_b
    np.testing.assert_allclose(
        a2b.interpolate(a, b, TS), kappa_line(h_a, h_b, 0, 0, TS), atol=1e-13
    )


@pytest.mark.parametrize("long_way", [False, True])
def test_darboux_is_in_a_cylinder_group_with_a_sine_transmission(rng, long_way):
    for a, b in pairs(rng):
        delta = rng.normal()
        motion = a2b.motion(a, b, "darboux", delta=delta, long_way=long_way)
        ts = np.linspace(0, 1, 25)
        mats = motion.matrices(ts)
        assert commutator(mats) < 1e-12
        omega, z = motion.frame.transmission(mats)
        info = motion.describe()
        np.testing.assert_allclose(omega, motion.omega_of_t(ts), atol=1e-12)
        np.testing.assert_allclose(
            z, info["z0"] + info["lam"] * np.sin(omega + info["kappa"]), atol=1e-12
        )
        np.testing.assert_allclose(z, motion.transmission(omega), atol=1e-12)
        # the closed forms of docs/math.md, by hand
        phi = info["rotation_angle"]
        d = info["d"]
        assert info["z0"] == pytest.approx(d / 2 + delta / math.tan(phi / 2))
        assert info["lam"] == pytest.approx(math.hypot(d / 2, delta) / abs(math.sin(phi / 2)))
        assert omega[-1] == pytest.approx(phi)
        assert abs(phi) <= math.pi if not long_way else abs(phi) >= math.pi


def test_darboux_trajectories_are_planar_conics(rng):
    a, b = random_pose(rng), random_pose(rng)
    mats = a2b.interpolate(a, b, np.linspace(-0.5, 1.5, 15), "darboux", delta=0.6)
    for point in rng.normal(size=(4, 3)):
        traj = mats[:, :3, :3] @ point + mats[:, :3, 3]
        centred = traj - traj.mean(axis=0)
        _, sing, vt = np.linalg.svd(centred)
        assert sing[2] < 1e-12 * sing[0]  # planar
        xy = centred @ vt[:2].T
        design = np.column_stack(
            [xy[:, 0] ** 2, xy[:, 0] * xy[:, 1], xy[:, 1] ** 2, xy[:, 0], xy[:, 1], np.ones(15)]
        )
        conic_sing = np.linalg.svd(design / np.abs(design).max(axis=0), compute_uv=False)
        assert conic_sing[-1] < 1e-10 * conic_sing[0]  # a conic


def sampled_pitch(motion, at):
    h = 1e-6
    ts = np.array([0.0, h]) if at == "start" else np.array([1.0 - h, 1.0])
    omega, z = motion.frame.transmission(motion.matrices(ts))
    return (z[1] - z[0]) / (omega[1] - omega[0])


def test_darboux_pitch_solvers_hit_the_pitch(rng):
    for a, b in pairs(rng):
        for at in ("start", "end"):
            target = rng.normal()
            motion = a2b.motion(a, b, "darboux", **{f"pitch_{at}": target})
            assert motion.describe()[f"pitch_{at}"] == pytest.approx(target, abs=1e-12)
            assert sampled_pitch(motion, at) == pytest.approx(target, rel=1e-4, abs=1e-5)


def test_darboux_phase_solver_hits_kappa(rng):
    for a, b in pairs(rng):
        reference = a2b.motion(a, b, "darboux", delta=rng.normal())
        kappa_target = reference.describe()["kappa"]
        motion = a2b.motion(a, b, "darboux", kappa=kappa_target)
        assert motion.delta == pytest.approx(reference.delta, abs=1e-10)
        assert motion.describe()["kappa"] == pytest.approx(kappa_target, abs=1e-12)


def test_darboux_phase_on_the_wrong_half_is_a_clear_error(rng):
    a, b = random_pose(rng), random_pose(rng)
    kappa_target = a2b.describe(a, b, "darboux", delta=0.2)["kappa"]
    with pytest.raises(ParameterError, match="κ \\+ π"):
        a2b.motion(a, b, "darboux", kappa=kappa_target + math.pi)


@pytest.mark.parametrize("branch", [1, -1])
def test_darboux_amplitude_solver_and_its_two_mirror_solutions(rng, branch):
    a, b = random_pose(rng), random_pose(rng)
    info = a2b.describe(a, b, "darboux")
    lam = info["lam"] * 1.7
    motion = a2b.motion(a, b, "darboux", lam=lam, branch=branch)
    assert motion.describe()["lam"] == pytest.approx(lam, rel=1e-12)
    assert np.sign(motion.delta) == branch
    assert any("branch" in c for c in motion.describe()["choices"])


def test_darboux_amplitude_below_the_minimum_is_an_error_stating_it(rng):
    a, b = random_pose(rng), random_pose(rng)
    minimum = a2b.describe(a, b, "darboux")["lam"]  # δ = 0 has the smallest amplitude
    with pytest.raises(ParameterError, match=f"below the minimum .* = {minimum:.6g}"):
        a2b.motion(a, b, "darboux", lam=0.9 * minimum)


def test_darboux_through_a_third_pose(rng):
    for a, b in pairs(rng):
        delta = rng.normal()
        t_c = rng.uniform(-0.3, 1.3)
        third = a2b.interpolate(a, b, [t_c], "darboux", delta=delta)[0]
        motion = a2b.motion(a, b, "darboux", through=third)
        assert motion.delta == pytest.approx(delta, abs=1e-9)
        assert np.abs(motion.matrices([t_c])[0] - third).max() < 1e-9


def test_darboux_third_pose_outside_the_cylinder_group_is_an_error(rng):
    a, b = random_pose(rng), random_pose(rng)
    with pytest.raises(ParameterError, match="not in the cylinder group.*tolerance"):
        a2b.motion(a, b, "darboux", through=random_pose(rng))


def test_darboux_parameters_are_exclusive_and_branch_needs_lam(rng):
    a, b = random_pose(rng), random_pose(rng)
    with pytest.raises(ParameterError, match="at most one"):
        a2b.motion(a, b, "darboux", delta=1, kappa=0.2)
    with pytest.raises(ParameterError, match="branch"):
        a2b.motion(a, b, "darboux", branch=-1)


def test_darboux_pure_translation_is_straight_and_its_long_way_is_singular(rng):
    a = random_pose(rng)
    b = a.copy()
    b[:3, 3] += [1, -2, 0.5]
    mats = a2b.interpolate(a, b, TS, "darboux", delta=3.0)
    np.testing.assert_allclose(
        mats[:, :3, :3], np.broadcast_to(a[:3, :3], (len(TS), 3, 3)), atol=1e-15
    )
    np.testing.assert_allclose(
        mats[:, :3, 3], (1 - TS)[:, None] * a[:3, 3] + TS[:, None] * b[:3, 3], atol=1e-14
    )
    with pytest.raises(SingularMotionError, match="p\\(t\\) = 0.*t = 0.5"):
        a2b.motion(a, b, "darboux", long_way=True)
    with pytest.raises(ParameterError, match="pure translation"):
        a2b.motion(a, b, "darboux", lam=2.0)


def test_darboux_phase_with_d_zero_is_an_error(rng):
    b = pose_about_axis(1.0, [0, 0, 1], [1, 2, 0], 0.0)
    with pytest.raises(ParameterError, match="d = 0"):
        a2b.motion(np.eye(4), b, "darboux", kappa=0.3)


# --------------------------------------------------------------------------------------------
# cubic (Theorem 2)
# --------------------------------------------------------------------------------------------


def literal_cubic(a, b, m, alpha, beta, ts):
    """μ_m of the line between fiber points in R^13, straight from eq. 12 and 15."""
    x_a = mu_fiber_points(a, m, [alpha])[0]
    x_b = mu_fiber_points(b, m, [beta])[0]
    line = (1 - ts)[:, None] * x_a + ts[:, None] * x_b
    return matrices_from_model_points(line, m)


def test_cubic_given_frame_is_literally_mu_of_the_line(rng):
    for a, b in pairs(rng):
        m = rng.normal(size=4)
        alpha, beta = rng.normal(size=6) * 0.05, rng.normal(size=6) * 0.05
        motion = a2b.motion(a, b, "cubic", frame="given", m=m, alpha=alpha, beta=beta)
        if motion.psi_a * motion.psi_b <= 0:
            continue
        np.testing.assert_allclose(
            motion.matrices(TS), literal_cubic(a, b, m, alpha, beta, TS), atol=1e-11
        )


def test_cubic_canonical_frame_is_the_construction_in_canonical_coordinates(rng):
    for a, b in pairs(rng):
        m = rng.normal(size=4)
        alpha, beta = rng.normal(size=6) * 0.05, rng.normal(size=6) * 0.05
        motion = a2b.motion(a, b, "cubic", m=m, alpha=alpha, beta=beta)
        f = motion.frame
        big_f = f.canonical_transform()
        b_can = big_f @ b @ inverse_matrices(a) @ inverse_matrices(big_f)
        c_can = literal_cubic(np.eye(4), b_can, m, alpha, beta, TS)
        expected = inverse_matrices(big_f) @ c_can @ big_f @ a
        np.testing.assert_allclose(motion.matrices(TS), expected, atol=1e-11)


def test_cubic_alpha_enters_only_through_the_papers_a(rng):
    m = rng.normal(size=4)
    alpha = rng.normal(size=6)
    n0 = 4 * m[0] * m[1] * m[2] * m[3]
    n1, n2, n3 = m[0] * m[1] - m[2] * m[3], m[0] * m[2] - m[1] * m[3], m[0] * m[3] - m[1] * m[2]
    n4, n5, n6 = m[0] * m[1] + m[2] * m[3], m[0] * m[2] + m[1] * m[3], m[0] * m[3] + m[1] * m[2]
    assert n0 != 0
    a_paper = (
        n1 * n2 * alpha[0]
        - n4 * n6 * alpha[1]
        - n4 * n5 * alpha[2]
        + n2 * n3 * alpha[3]
        + n1 * n3 * alpha[4]
        - n5 * n6 * alpha[5]
    )
    assert float(alpha @ paper_kernel_basis(m)[:, 0]) == pytest.approx(a_paper)
    a_pose, b_pose = random_pose(rng), random_pose(rng)
    scale = 0.2 / max(abs(a_paper), 1e-9)
    via_alpha = a2b.motion(a_pose, b_pose, "cubic", m=m, alpha=alpha * scale)
    via_a = a2b.motion(a_pose, b_pose, "cubic", m=m, a=a_paper * scale)
    np.testing.assert_allclose(via_alpha.matrices(TS), via_a.matrices(TS), atol=1e-13)
    assert via_alpha.describe()["a"] == pytest.approx(a_paper * scale)


@pytest.mark.parametrize("frame", ["canonical", "given"])
def test_cubic_eq_17_and_18(rng, frame):
    for a, b in pairs(rng):
        m = rng.normal(size=4)
        m[0] = abs(m[0]) + 0.5
        params = dict(m=m, a=rng.uniform(-0.5, 0.5), b=rng.uniform(-0.5, 0.5), frame=frame)
        try:
            motion = a2b.motion(a, b, "cubic", **params)
        except SingularMotionError:
            continue
        omega, z = motion.frame.transmission(motion.matrices(TS))
        # eq. 17 compared as an angle (tan has poles)
        expected = 2 * np.arctan(motion.tan_half_omega(TS))
        diff = np.angle(np.exp(1j * (omega - expected) / 2))
        assert np.abs(np.sin(diff)).max() < 1e-11
        if frame == "canonical":
            np.testing.assert_allclose(z, motion.z_of_t(TS), atol=1e-12)


def test_cubic_canonical_is_in_a_cylinder_group_and_given_is_not(rng):
    """Erratum 3: μ_[m] does not commute with a change of frame. Nobody should 'fix' this."""
    largest_given = 0.0
    for a, b in pairs(rng, 6):
        canonical = a2b.interpolate(a, b, TS, "cubic")
        assert commutator(canonical) < 1e-12
        given = a2b.interpolate(a, b, TS, "cubic", frame="given")
        largest_given = max(largest_given, commutator(given))
    assert largest_given > 1e-2
    info = a2b.describe(a, b, "cubic", frame="given")
    assert info["in_cylinder_group"] is False


def test_cubic_transmission_is_a_shifted_scaled_tangent(rng):
    """(p t + q) tan(ω/2) = (r t + s) z with constants from eq. 17 and 18."""
    a, b = random_pose(rng), random_pose(rng)
    m = np.array([1.0, 0.3, -0.2, 0.4])
    motion = a2b.motion(a, b, "cubic", m=m, a=0.3, b=-0.2)
    omega, z = motion.frame.transmission(motion.matrices(TS))
    m0, m3 = m[0], m[3]
    phi, d = motion.frame.phi, motion.frame.d
    num = -(m3 * (math.cos(phi) - 1) - m0 * math.sin(phi))
    den = m0 * (math.cos(phi) - 1) + m3 * math.sin(phi)
    psi_a, psi_b = 1.3, 0.8
    lhs = (den * TS + 2 * m0) * d * psi_b * np.tan(omega / 2)
    rhs = num * (psi_a + TS * (psi_b - psi_a)) * z
    np.testing.assert_allclose(lhs, rhs, atol=1e-11)


def test_cubic_trajectories_are_cubics_whose_axial_projection_is_a_circle(rng):
    a, b = random_pose(rng), random_pose(rng)
    motion = a2b.motion(a, b, "cubic", m=[1.0, 0.2, 0.1, 0.3], a=0.3, b=-0.1)
    ts = np.linspace(-0.5, 1.5, 21)
    mats = motion.matrices(ts)
    u, c = motion.frame.axis_direction, motion.frame.axis_point
    e1 = np.cross(u, [1.0, 0, 0] if abs(u[0]) < 0.9 else [0, 1.0, 0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(u, e1)
    values = motion._basis(ts) @ motion.table
    common = values[:, 13]  # Δ(t) x0(t), a cubic
    for point in rng.normal(size=(3, 3)):
        traj = mats[:, :3, :3] @ point + mats[:, :3, 3]
        xy = np.column_stack([(traj - c) @ e1, (traj - c) @ e2])
        radius = np.linalg.norm(xy, axis=1)
        np.testing.assert_allclose(radius, radius[0], rtol=1e-12)  # a circle about the axis
        # numerator of the trajectory is a polynomial of degree three in t
        numer = traj * common[:, None]
        vander = np.vander(ts, 4)
        coeffs, *_ = np.linalg.lstsq(vander, numer, rcond=None)
        assert np.abs(vander @ coeffs - numer).max() < 1e-10 * np.abs(numer).max()


def test_cubic_slopes_at_start_and_end_have_the_same_sign(rng):
    for _ in range(20):
        a, b = random_pose(rng), random_pose(rng)
        m = rng.normal(size=4)
        params = dict(m=m, a=rng.uniform(-0.9, 2), b=rng.uniform(-0.9, 2))
        try:
            motion = a2b.motion(a, b, "cubic", **params)
        except a2b.A2bError:
            continue
        h = 1e-6
        omega, z = motion.frame.transmission(motion.matrices(np.array([0, h, 1 - h, 1])))
        start = (z[1] - z[0]) / (omega[1] - omega[0])
        end = (z[3] - z[2]) / (omega[3] - omega[2])
        assert np.sign(start) == np.sign(end)


def test_cubic_default_m_is_symmetric(rng):
    a, b = random_pose(rng), random_pose(rng)
    motion = a2b.motion(a, b, "cubic")
    w_a, w_b = motion.weights
    assert w_a == pytest.approx(w_b)
    info = motion.describe()
    phi = info["phi"]
    assert info["m0"] == pytest.approx(1 + math.cos(phi / 2)) and info["m3"] == pytest.approx(
        math.sin(phi / 2)
    )
    # symmetric about the midpoint: reversing A and B reverses the motion
    forward = a2b.interpolate(a, b, TS, "cubic")
    backward = a2b.interpolate(b, a, 1 - TS, "cubic")
    np.testing.assert_allclose(forward, backward, atol=1e-12)


def test_cubic_errors(rng):
    a, b = random_pose(rng), random_pose(rng)
    with pytest.raises(ParameterError, match="orthogonal to the quaternion of the start pose"):
        a2b.motion(a, b, "cubic", m=[0, 1, 2, 0])  # canonical pA = 1
    with pytest.raises(SingularMotionError, match=r"passes through infinity at t = 0.5"):
        a2b.motion(a, b, "cubic", a=-2.0, b=0.0)
    with pytest.raises(SingularMotionError, match=r"passes through infinity at t = 0\b"):
        a2b.motion(a, b, "cubic", a=-1.0)
    with pytest.raises(ParameterError, match="degenerates"):
        a2b.motion(a, b, "cubic", alpha=[1, 0, 0, 0, 0, 0])  # default m has m1 = m2 = 0
    with pytest.raises(ParameterError, match="either alpha or a"):
        a2b.motion(a, b, "cubic", m=[1, 2, 3, 4], alpha=[0] * 6, a=0.1)
    with pytest.raises(ParameterError, match="6 numbers"):
        a2b.motion(a, b, "cubic", m=[1, 2, 3, 4], alpha=[0] * 5)
    with pytest.raises(ParameterError, match="unknown frame"):
        a2b.motion(a, b, "cubic", frame="world")
    motion = a2b.motion(a, b, "cubic", b=-0.6)  # x0 vanishes at t = 1 / 0.6
    with pytest.raises(SingularMotionError, match="t = 1.66667"):
        motion.matrices([0.0, 2.0])
    assert motion.describe()["singular_t"] == [pytest.approx(1 / 0.6)]


def test_cubic_given_m_orthogonal_to_end_pose(rng):
    a, b = random_pose(rng), random_pose(rng)
    p = a2b.poses.quaternions_from_rotations(b[:3, :3])
    m = np.array([-p[1], p[0], -p[3], p[2]])
    with pytest.raises(ParameterError, match="end pose"):
        a2b.motion(a, b, "cubic", frame="given", m=m)


# --------------------------------------------------------------------------------------------
# screw
# --------------------------------------------------------------------------------------------


def test_screw_is_the_helical_motion(rng):
    for a, b in pairs(rng):
        f = screw_frame(a, b)
        expected = np.stack(
            [pose_about_axis(t * f.phi, f.axis_direction, f.axis_point, t * f.d) @ a for t in TS]
        )
        np.testing.assert_allclose(a2b.interpolate(a, b, TS, "screw"), expected, atol=1e-12)


def test_screw_halves_compose_to_the_whole(rng):
    a, b = random_pose(rng), random_pose(rng)
    half = a2b.interpolate(a, b, [0.5], "screw")[0]
    rel = half @ inverse_matrices(a)
    np.testing.assert_allclose(rel @ rel @ a, b, atol=1e-12)


# --------------------------------------------------------------------------------------------
# edge cases
# --------------------------------------------------------------------------------------------

EDGE_PHIS = [0.0, 1e-12, 1e-6, 1e-3, 1.0, math.pi - 1e-9, math.pi]


@pytest.mark.parametrize("phi", EDGE_PHIS)
@pytest.mark.parametrize("scale", [1e-9, 1.0, 1e9])
@pytest.mark.parametrize(
    "mode, params", [("darboux", {}), ("cubic", {}), ("cubic", {"frame": "given"}), ("screw", {})]
)
def test_edge_angles_and_scales(rng, phi, scale, mode, params):
    a = random_pose(rng, scale)
    axis = rng.normal(size=3)
    disp = pose_about_axis(phi, axis, rng.normal(size=3) * scale, rng.normal() * scale)
    b = disp @ a
    b[:3, :3] = a2b.poses.rotations_from_quaternions(
        a2b.poses.quaternions_from_rotations(b[:3, :3])
    )
    mats = a2b.interpolate(a, b, TS, mode, **params)
    motion_scale = max(np.abs(a[:3, 3]).max(), np.abs(b[:3, 3]).max())
    np.testing.assert_allclose(mats[0], a, atol=1e-12 * motion_scale + 1e-15)
    np.testing.assert_allclose(mats[-1], b, atol=1e-12 * motion_scale + 1e-15)
    assert rigidity(mats) < 1e-13
    if mode != "cubic" or params.get("frame") != "given":
        scaled = mats.copy()
        scaled[:, :3, 3] /= motion_scale  # a similarity: commuting stays commuting
        assert commutator(scaled) < 1e-9


@pytest.mark.parametrize("mode", ["darboux", "cubic", "screw"])
def test_equal_poses_give_the_constant_motion(rng, mode):
    a = random_pose(rng)
    mats = a2b.interpolate(a, a, TS, mode)
    np.testing.assert_allclose(mats, np.broadcast_to(a, mats.shape), atol=1e-14)


@pytest.mark.parametrize("mode", ["darboux", "cubic", "screw"])
def test_pure_rotation_d_zero(rng, mode):
    b = pose_about_axis(2.0, rng.normal(size=3), rng.normal(size=3), 0.0)
    mats = a2b.interpolate(np.eye(4), b, TS, mode)
    omega, z = screw_frame(np.eye(4), b).transmission(mats)
    np.testing.assert_allclose(z, 0.0, atol=1e-13)
    assert np.all(np.diff(omega) > 0)


# --------------------------------------------------------------------------------------------
# the API
# --------------------------------------------------------------------------------------------


def test_api_rejects_unknown_parameters_and_modes(rng):
    a, b = random_pose(rng), random_pose(rng)
    with pytest.raises(ParameterError, match="mode screw does not take delta"):
        a2b.interpolate(a, b, TS, "screw", delta=1)
    with pytest.raises(ParameterError, match="unknown mode"):
        a2b.interpolate(a, b, TS, "linear")
    with pytest.raises(ParameterError, match="1-D"):
        a2b.interpolate(a, b, [[0, 1]])
    with pytest.raises(ParameterError, match="NaN"):
        a2b.interpolate(a, b, [0, np.nan])
    stretched = a.copy()
    stretched[:3, :3] *= 1.01
    with pytest.raises(PoseError, match="not orthogonal"):
        a2b.interpolate(stretched, b, TS)


def test_describe_has_the_documented_keys(rng):
    a, b = random_pose(rng), random_pose(rng)
    common = {"phi", "d", "axis_point", "axis_direction", "choices", "singular_t"}
    darboux = a2b.describe(a, b, "darboux")
    assert common | {"delta", "z0", "lam", "kappa", "pitch_start", "pitch_end"} <= set(darboux)
    cubic = a2b.describe(a, b, "cubic")
    assert common | {"m0", "m3", "a", "b"} <= set(cubic)
    import json

    json.dumps(darboux), json.dumps(cubic), json.dumps(a2b.describe(a, b, "screw"))


# --------------------------------------------------------------------------------------------
# near the singularities: rigid, warned or refused, never garbage
# --------------------------------------------------------------------------------------------


def small_rotation_pair(rng, phi):
    a = random_pose(rng)
    disp = pose_about_axis(phi, rng.normal(size=3), rng.normal(size=3), rng.normal())
    return a, disp @ a


@pytest.mark.parametrize("phi", [1e-1, 1e-2, 1e-3])
def test_long_way_near_a_translation_stays_rigid(rng, phi):
    a, b = small_rotation_pair(rng, phi)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", a2b.errors.A2bWarning)
        darboux = a2b.interpolate(a, b, np.linspace(-0.2, 1.2, 57), "darboux", long_way=True)
        pa, pb = (a2b.poses.quaternions_from_rotations(x[:3, :3]) for x in (a, b))
        m = pa - pb if pa @ pb > 0 else pa + pb  # weights of opposite sign
        cubic = a2b.interpolate(a, b, np.linspace(0, 1, 57), "cubic", frame="given", m=m)
    assert rigidity(darboux) < 1e-13
    assert rigidity(cubic) < 1e-13


def test_long_way_close_to_a_translation_warns_then_refuses(rng):
    a, b = small_rotation_pair(rng, 1e-4)
    with pytest.warns(a2b.errors.A2bWarning, match=r"close to p\(t\) = 0 at t = 0.5"):
        motion = a2b.motion(a, b, "darboux", long_way=True)
    assert motion.describe()["warnings"]
    a, b = small_rotation_pair(rng, 1e-7)
    with pytest.raises(SingularMotionError, match="tolerance 1e-12"):
        a2b.motion(a, b, "darboux", long_way=True)


def test_ill_conditioned_canonical_cubic_warns_and_the_defaults_do_not(rng):
    a, b = small_rotation_pair(rng, 1e-12)
    with pytest.warns(a2b.errors.A2bWarning, match="screw axis is ill-determined"):
        a2b.motion(a, b, "cubic", m=[0.9, 0.2, -0.4, 0.5], a=0.4, b=-0.3)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        motion = a2b.motion(a, b, "cubic")
        a2b.motion(a, b, "cubic", frame="given", m=[0.9, 0.2, -0.4, 0.5], a=0.4, b=-0.3)
    assert motion.describe()["warnings"] == []


def test_half_turn_within_rounding_follows_the_half_turn_rule(rng):
    """pA·pB at rounding level must not decide the orientation; the stated rule does."""
    for _ in range(20):
        a = random_pose(rng)
        b = pose_about_axis(math.pi, rng.normal(size=3), rng.normal(size=3), rng.normal()) @ a
        frame = screw_frame(a, b)
        assert frame.d >= 0
        assert frame.phi == pytest.approx(math.pi)
        assert any("φ = π" in choice for choice in frame.choices)
        np.testing.assert_allclose(a2b.interpolate(a, b, [1.0], "screw")[0], b, atol=1e-12)


def test_overflow_is_an_error_not_nan(rng):
    a, b = random_pose(rng), random_pose(rng)
    with pytest.raises(a2b.A2bError, match="overflow"):
        a2b.motion(a, b, "darboux", lam=1e200).matrices(TS)
    far = b.copy()
    far[:3, 3] = [1.5e308, -1.5e308, 1.5e308]  # 1e300 still works; this overflows
    with pytest.raises(a2b.A2bError, match="overflow"):
        a2b.interpolate(a, far, TS)
    with pytest.raises(a2b.A2bError, match="overflows float64 at t = 1e\\+200"):
        a2b.interpolate(a, b, [0.0, 1e200], "cubic")


def test_darboux_short_way_stays_half_away_from_the_origin(rng):
    """The short way round skips the singularity check on [0, 1] (docs/math.md): |p(t)|² ≥ ½
    there for every pair, half-turns and equal rotations included; the long way is checked."""
    from a2b.motions.base import path_minimum

    starts = matrices_from_quat_trans(rng.normal(size=(2000, 4)), rng.normal(size=(2000, 3)))
    ends = matrices_from_quat_trans(rng.normal(size=(2000, 4)), rng.normal(size=(2000, 3)))
    ends[:50, :3, :3] = starts[:50, :3, :3]  # equal rotations
    half = np.diag([1.0, -1.0, -1.0])  # half-turns about x
    ends[50:100, :3, :3] = starts[50:100, :3, :3] @ half
    motion = a2b.motion(starts, ends, "darboux")
    _, ratio = path_minimum(motion.quat_ends, 0.0, 1.0)
    assert ratio.min() >= 0.5 - 1e-15
    assert not motion._rotation_is_fragile(0.0, 1.0).any()
    shifted = np.eye(4)
    shifted[0, 3] = 1.0
    with pytest.raises(SingularMotionError):  # the long way round is still checked
        a2b.motion(np.eye(4), shifted, "darboux", long_way=True)
