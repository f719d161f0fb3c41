"""Poses, Study parameters, κ and its fibers."""

import numpy as np
import pytest

from a2b import A2bError
from a2b.errors import PoseError
from a2b.poses import (
    canonical_sign,
    check_matrices,
    check_quaternions,
    inverse_matrices,
    matrices_from_quat_trans,
    matrices_from_study,
    paper_from_robotics,
    quat_trans_from_matrices,
    quaternions_from_rotations,
    robotics_from_paper,
    rotations_from_quaternions,
    study_from_matrices,
)
from a2b.study import dq_mul, kappa, kappa_fiber_points, quat_conj, quat_mul

from .conftest import random_pose, rigidity


def same_study(h1, h2, atol=1e-12):
    """Study vectors are equal up to sign (and both unit here)."""
    return min(np.abs(h1 - h2).max(), np.abs(h1 + h2).max()) <= atol


@pytest.mark.parametrize("shape", [(), (5,), (2, 3, 4)])
def test_round_trip_matrix_study_matrix_for_any_leading_shape(rng, shape):
    quat = rng.normal(size=shape + (4,))
    trans = rng.normal(size=shape + (3,)) * 10
    mats = matrices_from_quat_trans(quat, trans)
    assert mats.shape == shape + (4, 4)
    study = study_from_matrices(mats)
    assert study.shape == shape + (8,)
    np.testing.assert_allclose(matrices_from_study(study), mats, atol=1e-13)
    # unit primal part and the Study condition
    np.testing.assert_allclose(np.linalg.norm(study[..., :4], axis=-1), 1.0, atol=1e-15)
    assert np.abs(np.sum(study[..., :4] * study[..., 4:], axis=-1)).max() < 1e-14


def test_leading_dimensions_give_the_same_answer(rng):
    mats = np.stack([random_pose(rng) for _ in range(6)]).reshape(2, 3, 4, 4)
    batched = study_from_matrices(mats)
    for i in range(2):
        for j in range(3):
            np.testing.assert_array_equal(batched[i, j], study_from_matrices(mats[i, j]))


def test_study_matches_dual_quaternion_action(rng):
    """The translation of κ(p + εq) acts as x ↦ p x p̄ + p q̄ − q p̄ (eq. 3)."""
    mats = np.stack([random_pose(rng) for _ in range(4)])
    h = study_from_matrices(mats)
    x = rng.normal(size=3)
    for mat, hh in zip(mats, h):
        p, q = hh[:4], hh[4:]
        xq = np.concatenate([[0.0], x])
        pbar = p * [1, -1, -1, -1]
        qbar = q * [1, -1, -1, -1]
        moved = quat_mul(quat_mul(p, xq), pbar) + quat_mul(p, qbar) - quat_mul(q, pbar)
        np.testing.assert_allclose(moved[1:], mat[:3, :3] @ x + mat[:3, 3], atol=1e-13)
        assert abs(moved[0]) < 1e-13


def test_composition_is_dual_quaternion_product(rng):
    a, b = random_pose(rng), random_pose(rng)
    composed = dq_mul(study_from_matrices(a), study_from_matrices(b))
    np.testing.assert_allclose(matrices_from_study(composed), a @ b, atol=1e-13)


@pytest.mark.parametrize(
    "axis", [(1, 2, 3), (1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 0), (0, -1, 1)]
)
def test_exact_half_turns_round_trip(axis):
    u = np.array(axis, float) / np.linalg.norm(axis)
    rot = 2 * np.outer(u, u) - np.eye(3)
    quat = quaternions_from_rotations(rot)
    assert quat[0] == 0.0
    np.testing.assert_allclose(np.abs(quat[1:]), np.abs(u), atol=1e-16)
    np.testing.assert_allclose(rotations_from_quaternions(quat), rot, atol=1e-15)


def test_half_turn_about_123_is_not_a_wrong_rotation():
    """A known peer returns a wrong rotation here; a2b must give the half-turn back."""
    u = np.array([1.0, 2.0, 3.0]) / np.sqrt(14.0)
    mat = np.eye(4)
    mat[:3, :3] = 2 * np.outer(u, u) - np.eye(3)
    back = matrices_from_study(study_from_matrices(mat))
    np.testing.assert_allclose(back, mat, atol=1e-15)


def test_quaternion_sign_convention_is_w_nonnegative(rng):
    quat, _ = quat_trans_from_matrices(np.stack([random_pose(rng) for _ in range(50)]))
    assert np.all(quat[:, 0] >= 0)


def test_paper_layout_round_trip_and_meaning(rng):
    mat = random_pose(rng)
    paper = paper_from_robotics(mat)
    assert paper[0].tolist() == [1.0, 0.0, 0.0, 0.0]
    np.testing.assert_array_equal(paper[1:, 0], mat[:3, 3])
    np.testing.assert_array_equal(robotics_from_paper(paper), mat)
    np.testing.assert_array_equal(check_matrices(paper, layout="paper"), mat)


def test_a_z_rotation_means_different_poses_in_the_two_layouts():
    c, s = np.cos(0.3), np.sin(0.3)
    mat = np.array([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1.0]])
    # valid in both layouts, meaning different poses; a2b takes what it is told
    robotics = check_matrices(mat)
    paper = check_matrices(mat, layout="paper")
    assert not np.allclose(robotics, paper)


@pytest.mark.parametrize(
    "mutate, match",
    [
        (
            lambda m: m.__setitem__((0, 1), m[0, 1] + 1e-3),
            r"not orthogonal: max \|R Rᵀ − I\| = .* exceeds tolerance 1e-09",
        ),
        (lambda m: m.__setitem__((slice(0, 3), 0), -m[:3, 0]), "determinant -1"),
        (
            lambda m: m.__setitem__((3, 0), 0.5),
            r"bottom row .* must be exactly \[0.0, 0.0, 0.0, 1.0\]; it differs by 0.5",
        ),
        (lambda m: m.__setitem__((3, 3), 2.0), "bottom row"),
        (lambda m: m.__setitem__((1, 3), np.nan), "NaN or infinity"),
        (lambda m: m.__setitem__((1, 1), np.inf), "NaN or infinity"),
    ],
)
def test_bad_matrices_are_rejected_with_the_residual(rng, mutate, match):
    mat = random_pose(rng)
    mutate(mat)
    with pytest.raises(PoseError, match=match):
        check_matrices(mat)


def test_sheared_matrix_is_not_silently_orthonormalised():
    mat = np.eye(4)
    mat[0, 1] = 0.1
    with pytest.raises(A2bError, match="not orthogonal"):
        check_matrices(mat)


def test_wrong_shape_is_rejected():
    with pytest.raises(PoseError, match="must be 4x4"):
        check_matrices(np.eye(3))


@pytest.mark.parametrize("quat", [[0, 0, 0, 0], [np.nan, 0, 0, 1], [np.inf, 0, 0, 0]])
def test_zero_or_nonfinite_quaternion_is_rejected(quat):
    with pytest.raises(PoseError):
        check_quaternions(quat)


def test_quaternions_are_homogeneous():
    np.testing.assert_allclose(check_quaternions([2.0, 0, 0, 0]), [1, 0, 0, 0])
    np.testing.assert_allclose(
        matrices_from_quat_trans([3.0, 0, 0, 3.0], [0, 0, 0]),
        matrices_from_quat_trans([1, 0, 0, 1.0], [0, 0, 0]),
    )


def test_study_condition_is_checked_unless_kappa_is_asked_for(rng):
    h = study_from_matrices(random_pose(rng))
    off = h.copy()
    off[4:] += 0.25 * off[:4]  # a point of the κ-fiber, off the Study quadric
    with pytest.raises(PoseError, match=r"Study condition .* residual .* exceeds tolerance 1e-09"):
        matrices_from_study(off)
    np.testing.assert_allclose(
        matrices_from_study(off, through_kappa=True), matrices_from_study(h), atol=1e-14
    )


def test_study_on_exceptional_generator_is_rejected():
    with pytest.raises(PoseError, match="exceptional generator"):
        matrices_from_study([0, 0, 0, 0, 1, 0, 0, 0], through_kappa=True)


def test_study_parameters_are_homogeneous(rng):
    h = study_from_matrices(random_pose(rng))
    np.testing.assert_allclose(matrices_from_study(-3.5 * h), matrices_from_study(h), atol=1e-14)


def test_kappa_fiber_points_map_back(rng):
    """Erratum 1: the fiber is {h + s εp}, and every point maps back to the pose."""
    mat = random_pose(rng, scale=5)
    h = study_from_matrices(mat)
    points = kappa_fiber_points(h, rng.normal(size=7) * 10)
    rot, trans = kappa(points)
    np.testing.assert_allclose(rot, np.broadcast_to(mat[:3, :3], rot.shape), atol=1e-13)
    np.testing.assert_allclose(trans, np.broadcast_to(mat[:3, 3], trans.shape), atol=1e-12)


def test_the_papers_printed_fiber_direction_eps_q_is_wrong(rng):
    """The paper says the fiber is spanned by h and εq; that changes the pose (erratum 1)."""
    mat = random_pose(rng, scale=5)
    h = study_from_matrices(mat)
    wrong = h.copy()
    wrong[4:] *= 1.5  # h + 0.5 εq
    _, trans = kappa(wrong)
    assert np.abs(trans - mat[:3, 3]).max() > 1e-3


def test_kappa_of_any_point_is_rigid(rng):
    h = rng.normal(size=(100, 8))
    rot, trans = kappa(h)
    mats = np.zeros((100, 4, 4))
    mats[:, :3, :3], mats[:, :3, 3], mats[:, 3, 3] = rot, trans, 1
    assert rigidity(mats) < 1e-14


def test_inverse(rng):
    mat = random_pose(rng, 3)
    np.testing.assert_allclose(inverse_matrices(mat) @ mat, np.eye(4), atol=1e-14)


@pytest.mark.parametrize("scale", [1e-9, 1.0, 1e9])
def test_huge_and_tiny_translations_round_trip(rng, scale):
    mat = random_pose(rng, scale)
    back = matrices_from_study(study_from_matrices(mat))
    np.testing.assert_allclose(back[:3, :3], mat[:3, :3], atol=1e-15)
    np.testing.assert_allclose(back[:3, 3], mat[:3, 3], rtol=1e-14, atol=1e-15 * scale)


def test_the_entry_a32_is_2_p0p1_plus_p2p3(rng):
    """docs/math.md, correction 2: the paper prints 2(p0 p1 + p2 p3) as a23; it is a32."""
    from a2b.poses import rotations_from_quaternions

    for _ in range(10):
        p = rng.normal(size=4)
        p /= np.linalg.norm(p)
        r = rotations_from_quaternions(p)
        p0, p1, p2, p3 = p
        assert r[2, 1] == pytest.approx(2 * (p0 * p1 + p2 * p3), abs=1e-15)
        assert r[1, 2] == pytest.approx(2 * (p2 * p3 - p0 * p1), abs=1e-15)
        # and it is the rotation p x p̄ of a pure quaternion x
        x = rng.normal(size=3)
        rotated = quat_mul(quat_mul(p, np.concatenate([[0.0], x])), quat_conj(p))[1:]
        np.testing.assert_allclose(r @ x, rotated, atol=1e-14)


def _shepperd_one(r: np.ndarray) -> np.ndarray:
    """One rotation's quaternion by eq. 7–9 the plain way: the first row whose diagonal term
    is largest, normalised, the first non-zero component made positive."""
    (a11, a12, a13), (a21, a22, a23), (a31, a32, a33) = r.tolist()
    diagonal = [a11 + a22 + a33, a11 - a22 - a33, -a11 + a22 - a33, -a11 - a22 + a33]
    rows = [
        [1 + a11 + a22 + a33, a32 - a23, a13 - a31, a21 - a12],
        [a32 - a23, 1 + a11 - a22 - a33, a21 + a12, a31 + a13],
        [a13 - a31, a21 + a12, 1 - a11 + a22 - a33, a32 + a23],
        [a21 - a12, a31 + a13, a32 + a23, 1 - a11 - a22 + a33],
    ]
    p = np.array(rows[diagonal.index(max(diagonal))])
    p = p / np.sqrt(((p[0] * p[0] + p[1] * p[1]) + p[2] * p[2]) + p[3] * p[3])
    lead = p[np.flatnonzero(p)[0]]
    return -p if lead < 0 else p


@pytest.mark.parametrize("shape", [(), (7,), (2, 3, 4)])
def test_quaternions_from_rotations_are_the_plain_method_bit_for_bit(rng, shape):
    """The vectorised row choice and sign (component by component) are the scalar method's,
    for random rotations and for the ties and half-turns where the choice matters."""
    special = [np.eye(3), np.diag([1.0, -1.0, -1.0]), np.diag([-1.0, 1.0, -1.0]),
               np.diag([-1.0, -1.0, 1.0]), [[0, 1, 0], [1, 0, 0], [0, 0, -1]],
               [[0, -1, 0], [-1, 0, 0], [0, 0, -1]], [[0, -1, 0], [1, 0, 0], [0, 0, 1]],
               [[1, 0, 0], [0, 0, -1], [0, 1, 0]]]  # fmt: skip
    count = int(np.prod(shape, dtype=int))
    rot = matrices_from_quat_trans(rng.normal(size=(count, 4)), np.zeros((count, 3)))[:, :3, :3]
    rot[: min(count, len(special))] = np.array(special[:count], dtype=float)
    rot = rot.reshape(shape + (3, 3))
    quat = quaternions_from_rotations(rot)
    assert quat.shape == shape + (4,)
    expected = np.array([_shepperd_one(r) for r in rot.reshape(-1, 3, 3)]).reshape(quat.shape)
    assert np.array_equal(quat, expected)


def test_orthogonality_and_determinant_checks_name_the_worst_residual(rng):
    mats = np.stack([random_pose(rng) for _ in range(6)])
    mats[4, 1, 2] += 3e-7  # the worst of the batch
    mats[2, 0, 0] += 2e-9
    from a2b.poses import determinants, orthogonality_residuals

    residuals = orthogonality_residuals(mats[:, :3, :3])
    direct = np.abs(mats[:, :3, :3] @ np.swapaxes(mats[:, :3, :3], 1, 2) - np.eye(3)).max((1, 2))
    np.testing.assert_allclose(residuals, direct, rtol=1e-9, atol=1e-15)
    assert np.argmax(residuals) == 4 and residuals[2] > 1e-9
    worst = f"{residuals.max():.3g}"
    with pytest.raises(PoseError, match=rf"max \|R Rᵀ − I\| = {worst} exceeds tolerance 1e-09"):
        check_matrices(mats)
    np.testing.assert_allclose(determinants(mats[:, :3, :3]), np.linalg.det(mats[:, :3, :3]))


@pytest.mark.parametrize("n", [3, 4])
def test_canonical_sign_makes_the_first_nonzero_component_positive(rng, n):
    v = rng.normal(size=(500, n))
    v[rng.random(v.shape) < 0.4] = 0.0  # leading zeros of every length, and zero vectors
    out = canonical_sign(v)
    for before, after in zip(v, out):
        nonzero = np.flatnonzero(before)
        sign = -1.0 if len(nonzero) and before[nonzero[0]] < 0 else 1.0
        assert np.array_equal(after, sign * before)
        assert not len(nonzero) or after[nonzero[0]] > 0
    assert canonical_sign(np.array([0.0, -2.0, 1.0])).tolist() == [-0.0, 2.0, -1.0]


def test_a_large_batch_is_checked_in_chunks_with_the_message_of_the_whole(rng):
    """a2b.motion checks 2·10⁴ poses in chunks (poses.POSE_CHUNK): the quaternions are those of
    one pass bit for bit, and an error names the worst residual of all the chunks, or the
    first check that fails over the whole batch, as check_matrices does."""
    from a2b.poses import POSE_CHUNK, check_matrices_and_quaternions

    count = 2 * POSE_CHUNK + 6
    mats = matrices_from_quat_trans(rng.normal(size=(count, 4)), rng.normal(size=(count, 3)))
    checked, quat = check_matrices_and_quaternions(mats.reshape(2, -1, 4, 4))
    assert quat.shape == (2, count // 2, 4) and checked.shape == (2, count // 2, 4, 4)
    assert np.array_equal(quat.reshape(-1, 4), quaternions_from_rotations(mats[:, :3, :3]))
    bad = mats.copy()
    bad[3, 1, 2] += 2e-8  # first chunk
    bad[2 * POSE_CHUNK + 1, 0, 1] += 5e-6  # last chunk: the worst
    with pytest.raises(PoseError) as whole:
        check_matrices(bad)
    assert "max |R Rᵀ − I| = " in str(whole.value)
    assert float(str(whole.value).split(" = ")[1].split()[0]) > 1e-6  # the last chunk's
    with pytest.raises(PoseError) as chunked:
        check_matrices_and_quaternions(bad)
    assert str(chunked.value) == str(whole.value)
    bad[POSE_CHUNK + 3, 3, 0] = 1e-3  # middle chunk: the bottom row fails before any rotation
    with pytest.raises(PoseError, match=r"bottom row .* differs by 0.001"):
        check_matrices_and_quaternions(bad)
    with pytest.raises(PoseError, match=r"bottom row .* differs by 0.001"):
        check_matrices(bad)


def test_the_pose_forms_of_a_few_poses_are_the_separate_forms_bit_for_bit(rng):
    from a2b.poses import (
        _POSE_FORMS,
        _SHEPPERD,
        COFACTORS,
        GRAM,
        RIGIDITY,
        _shepperd_input,
        check_matrices_and_quaternions,
        quaternions_from_rotations,
    )
    from a2b.study import bilinear, linear

    poses = [random_pose(rng) for _ in range(40)]
    for turn in ([0, 1, 0, 0], [0, 0, 1, 0], [0, 1, 1, 0], [1, 0, 0, 0]):  # half-turns, I
        poses.append(matrices_from_quat_trans(np.array(turn, float), [0.0, 0.0, 0.0]))
    signed = np.diag([1.0, -1.0, -1.0, 1.0])
    signed[1, 2] = signed[0, 1] = -0.0  # zeros whose signs the sums keep
    poses.append(signed)
    for chosen in ([p] for p in poses):
        m = np.array(chosen)
        x = _shepperd_input(m[..., :3, :3])
        forms = bilinear(_POSE_FORMS, x, x)
        entries = x[1:]
        separate = np.concatenate(
            [bilinear(GRAM, entries, entries), bilinear(COFACTORS, entries[3:], entries[3:])]
        )
        assert forms[:9].tobytes() == separate.tobytes()
        assert bilinear(RIGIDITY, entries, entries).tobytes() == separate.tobytes()
        assert forms[9:].tobytes() == linear(_SHEPPERD, x).tobytes()
    m = np.array(poses)  # few poses (one form) and many (the forms apart) alike
    _, few = check_matrices_and_quaternions(m[:3])
    _, many = check_matrices_and_quaternions(np.concatenate([m] * 3))
    assert few.tobytes() == many[:3].tobytes()
    assert (
        many.tobytes() == quaternions_from_rotations(np.concatenate([m] * 3)[:, :3, :3]).tobytes()
    )


@pytest.mark.parametrize("shape", [(50, 4), (3, 7, 8), (9, 1), (4,), (2, 0), (3, 20)])
def test_largest_magnitudes_are_numpys_maximum_of_the_magnitudes(rng, shape):
    """The largest magnitude along the last axis, taken component by component (the short
    axes of quaternions and Study vectors), is numpy's reduction: NaN, infinity, zeros and
    every scale included."""
    from a2b.elements import largest_magnitudes, unit_scale

    a = rng.normal(size=shape) * 10.0 ** rng.integers(-320, 300, shape)
    if a.size > 4:
        a.flat[[0, 3]] = np.nan, -np.inf
        a.flat[-1] = 0.0
    with np.errstate(invalid="ignore"):
        try:
            expected = np.max(np.abs(a), axis=-1, keepdims=True)
        except ValueError:  # no maximum of nothing
            with pytest.raises(ValueError):
                largest_magnitudes(a)
            return
    assert np.array_equal(largest_magnitudes(a), expected, equal_nan=True)
    for axis in range(-a.ndim, a.ndim):  # any other axis: numpy's
        with np.errstate(invalid="ignore"):
            reference = np.max(np.abs(a), axis=axis, keepdims=True) if a.size else None
        if reference is not None:
            assert np.array_equal(largest_magnitudes(a, axis), reference, equal_nan=True)
    scaled = unit_scale(a)
    finite = np.isfinite(expected[..., 0]) & (expected[..., 0] > 0)
    assert (np.abs(scaled[finite]).max(axis=-1, initial=0.5) < 1.0).all()
