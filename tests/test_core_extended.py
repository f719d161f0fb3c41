"""The extended matrix model: M_m, the kernel bases, μ_m and its fibers (sections 2 and 4)."""

import numpy as np
import pytest

from a2b.errors import ParameterError, PoseError
from a2b.extended import (
    kernel_basis,
    matrices_from_model_points,
    model_points_from_matrices,
    mu,
    mu_fiber_points,
    mu_prime_matrix,
    paper_basis_degenerate,
    paper_kernel_basis,
    rref_kernel_basis,
)
from a2b.poses import quaternions_from_rotations
from a2b.study import kappa

from .conftest import random_pose


def printed_m_matrix(m):
    """The matrix M_m = [M1, M2] exactly as printed in section 4."""
    m0, m1, m2, m3 = m
    m_1 = [
        [m0, m0, -m3, m2, m3],
        [m1, m1, m2, m3, m2],
        [m2, -m2, m1, m0, m1],
        [m3, -m3, -m0, m1, m0],
    ]
    m_2 = [
        [m0, -m1, -m2, m1, m0],
        [-m1, -m0, m3, m0, -m1],
        [m2, m3, -m0, m3, -m2],
        [-m3, m2, m1, m2, m3],
    ]
    return np.hstack([m_1, m_2])


def test_m_matrix_equals_the_printed_one_and_eq_10_11(rng):
    for _ in range(5):
        m = rng.normal(size=4)
        np.testing.assert_allclose(mu_prime_matrix(m), printed_m_matrix(m), atol=0)


def test_ratio_rows_of_eq_9(rng):
    """With x0 = 1, μ'_l(1, R) is proportional to p (each row of eq. 9)."""
    mat = random_pose(rng)
    p = quaternions_from_rotations(mat[:3, :3])
    x = model_points_from_matrices(mat)[:10]
    for k in range(4):
        e = np.zeros(4)
        e[k] = 1
        row = mu_prime_matrix(e) @ x
        np.testing.assert_allclose(row, 4 * p[k] * p, atol=1e-14)


def test_mu_prime_of_a_pose_is_4_m_dot_p_times_p(rng):
    for _ in range(10):
        mat, m = random_pose(rng), rng.normal(size=4)
        p = quaternions_from_rotations(mat[:3, :3])
        x = model_points_from_matrices(mat)[:10]
        np.testing.assert_allclose(mu_prime_matrix(m) @ x, 4 * (m @ p) * p, atol=1e-13)


def test_paper_basis_spans_the_kernel_when_n0_is_not_zero(rng):
    for _ in range(20):
        m = rng.normal(size=4)
        basis = paper_kernel_basis(m)
        assert not paper_basis_degenerate(m)
        assert np.abs(mu_prime_matrix(m) @ basis.T).max() < 1e-12 * np.abs(m).max() ** 5
        assert np.linalg.matrix_rank(basis) == 6
        assert np.linalg.matrix_rank(mu_prime_matrix(m)) == 4


@pytest.mark.parametrize(
    "m", [(1, 0, 0, 0), (1, 0, 0, 0.5), (0, 1, 2, 3), (1, 2, 3, 0), (0.3, 0, 0.7, 0)]
)
def test_paper_basis_degenerates_at_n0_zero_and_rref_works(m):
    """Erratum 5: the basis degenerates when n0 = 4 m0 m1 m2 m3 = 0; RREF still spans the kernel."""
    assert paper_basis_degenerate(m)
    assert np.linalg.matrix_rank(paper_kernel_basis(m)) < 6
    basis = rref_kernel_basis(m)
    assert basis.shape == (6, 10)
    assert np.linalg.matrix_rank(basis) == 6
    assert np.abs(mu_prime_matrix(m) @ basis.T).max() < 1e-13
    auto, name = kernel_basis(m, "auto")
    assert name == "rref"
    with pytest.raises(ParameterError, match="degenerates.*n0 = 4 m0 m1 m2 m3 = 0"):
        kernel_basis(m, "paper")


def test_all_zero_for_identity_m():
    assert not np.any(paper_kernel_basis([1, 0, 0, 0]))


def test_rref_basis_is_unique_for_the_subspace(rng):
    m = rng.normal(size=4)
    np.testing.assert_allclose(rref_kernel_basis(m), rref_kernel_basis(3.0 * m), atol=1e-12)
    # and it spans the same space as the paper's
    paper = paper_kernel_basis(m)
    both = np.vstack([paper / np.abs(paper).max(), rref_kernel_basis(m)])
    assert np.linalg.matrix_rank(both, tol=1e-9) == 6


@pytest.mark.parametrize("basis", ["paper", "rref"])
def test_mu_fiber_points_map_back_to_the_pose(rng, basis):
    """Eq. 15: x' = (1, R) + Σ α f, x_t = ψ t; μ_m maps each point back, though it is not rigid."""
    mat = random_pose(rng, 4)
    m = rng.normal(size=4)
    points = mu_fiber_points(mat, m, rng.normal(size=(5, 6)), basis=basis)
    assert points.shape == (5, 13)
    np.testing.assert_allclose(points[:, 10:], points[:, :1] * mat[:3, 3])
    affine = points[:, 1:10].reshape(5, 3, 3) / points[:, :1, None]
    assert np.abs(affine @ affine.transpose(0, 2, 1) - np.eye(3)).max() > 1e-3  # not rigid
    back = matrices_from_model_points(points, m)
    np.testing.assert_allclose(back, np.broadcast_to(mat, back.shape), atol=1e-12)


def test_mu_returns_the_translation_x_t_over_x0(rng):
    x = rng.normal(size=13)
    m = rng.normal(size=4)
    rot, trans = kappa(mu(x, m))
    np.testing.assert_allclose(trans, x[10:] / x[0], atol=1e-13)
    # the paper's c = x0 μ_m(x) gives the same pose
    rot2, trans2 = kappa(x[0] * mu(x, m))
    np.testing.assert_allclose(trans2, trans, atol=1e-13)


def test_m_orthogonal_to_the_pose_is_an_error(rng):
    mat = random_pose(rng)
    p = quaternions_from_rotations(mat[:3, :3])
    m = np.array([-p[1], p[0], -p[3], p[2]])  # orthogonal to p
    with pytest.raises(
        ParameterError, match=r"orthogonal to the quaternion of the pose \(m·p = .*tolerance 1e-12"
    ):
        mu_fiber_points(mat, m, np.zeros((1, 6)))


def test_m_zero_is_an_error():
    with pytest.raises(ParameterError, match="m = 0"):
        mu_prime_matrix([0, 0, 0, 0])


def test_points_at_infinity_and_in_the_base_locus_are_errors(rng):
    m = rng.normal(size=4)
    x = rng.normal(size=13)
    x[0] = 0
    with pytest.raises(PoseError, match="infinity"):
        matrices_from_model_points(x, m)
    kernel_point = np.concatenate([paper_kernel_basis(m)[0], [1, 2, 3]])
    with pytest.raises(PoseError, match="base locus"):
        matrices_from_model_points(kernel_point, m)


def test_fiber_api_for_both_maps_and_the_degenerate_basis(rng):
    import a2b

    pose = random_pose(rng, 3)
    kappa_fiber = a2b.fiber(pose, "kappa", s=[-2.0, 0.0, 5.0])
    assert len(kappa_fiber["points"]) == 3 and all(len(p) == 8 for p in kappa_fiber["points"])
    assert max(kappa_fiber["residuals"]) < 1e-12
    mu_fiber = a2b.fiber(pose, "mu", m=[1, 0, 0, 0.5], alphas=rng.normal(size=(4, 6)))
    assert all(len(p) == 13 for p in mu_fiber["points"])
    assert max(mu_fiber["residuals"]) < 1e-12
    assert mu_fiber["paper_basis_degenerate"] and mu_fiber["basis_name"] == "rref"
    assert any("degenerates" in c for c in mu_fiber["choices"])
    with pytest.raises(ParameterError, match="degenerates"):
        a2b.fiber(pose, "mu", m=[1, 0, 0, 0.5], basis="paper")
    with pytest.raises(ParameterError, match="needs m"):
        a2b.fiber(pose, "mu")
