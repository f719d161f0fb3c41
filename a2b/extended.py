"""The extended matrix model R^13 and the family of extended kinematic maps μ_[m] (sections 2, 4).

A point of the extended matrix space is ``x = (x0, x1 … x9, x10, x11, x12)``: the homogenising
coordinate ``x0``, the nine entries ``a11, a12, a13, a21, …, a33`` row by row, then the
translation block ``t1, t2, t3``. A pose ``(R, t)`` is the point ``(1, R, t)``. The first ten
coordinates are written ``x'``.

``μ'_m(x') = M_m x'`` (eq. 10, 11) gives the primal part ``p``; μ_m (eq. 12) completes it to
Study parameters with the translation ``x_t / x0`` (``docs/math.md``, "Facts a2b relies on").
"""

from __future__ import annotations

import numpy as np

from .elements import as_numbers, refuse, unit_scale
from .errors import ParameterError, PoseError
from .poses import matrices_from_rot_trans, quaternions_from_rotations
from .study import dots, kappa, study_from_quat_trans

#: Relative size of ``m·p`` below which a pose counts as orthogonal to ``m`` (not in the image).
ORTHOGONAL_TOL = 1e-12
#: ``|n0| / |m|^4`` below which the paper's kernel basis counts as degenerate.
DEGENERATE_TOL = 1e-12

BASES = ("paper", "rref", "auto")

# The four linear maps μ'_0 … μ'_3 of eq. 10 as 4x10 matrices acting on (x0, x1, …, x9).
_MU_PRIME = np.zeros((4, 4, 10))
for _row, _terms in enumerate(
    [
        # μ'_0
        [{0: 1, 1: 1, 5: 1, 9: 1}, {8: 1, 6: -1}, {3: 1, 7: -1}, {4: 1, 2: -1}],
        # μ'_1
        [{8: 1, 6: -1}, {0: 1, 1: 1, 5: -1, 9: -1}, {4: 1, 2: 1}, {7: 1, 3: 1}],
        # μ'_2
        [{3: 1, 7: -1}, {4: 1, 2: 1}, {0: 1, 1: -1, 5: 1, 9: -1}, {8: 1, 6: 1}],
        # μ'_3
        [{4: 1, 2: -1}, {7: 1, 3: 1}, {8: 1, 6: 1}, {0: 1, 1: -1, 5: -1, 9: 1}],
    ]
):
    for _i, _entry in enumerate(_terms):
        for _col, _val in _entry.items():
            _MU_PRIME[_row, _i, _col] = _val


def check_m(m) -> np.ndarray:
    """Validate parameters ``m ∈ R^4 \\ {0}`` of μ_[m], shape ``(..., 4)``, and return them."""
    arr = unit_scale(
        as_numbers(m, "m"), extreme_only=True
    )  # homogeneous: m of 1e-320 or 1e300 works
    if arr.shape[-1:] != (4,):
        raise ParameterError(f"m needs 4 numbers (m0, m1, m2, m3), got shape {arr.shape}")
    shape = arr.shape[:-1]
    refuse(
        ParameterError,
        ~np.isfinite(arr).all(axis=-1),
        lambda i: "m contains NaN or infinity",
        shape,
    )
    refuse(
        ParameterError,
        ~arr.any(axis=-1),
        lambda i: "m = 0: the map μ_[m] is undefined (M_m is the zero matrix)",
        shape,
    )
    return arr


def mu_prime_matrix(m) -> np.ndarray:
    """The 4x10 matrix ``M_m`` of ``μ'_m = Σ m_l μ'_l`` (eq. 10, 11; printed in section 4)."""
    return np.tensordot(check_m(m), _MU_PRIME, axes=1)


def _n_values(m: np.ndarray) -> tuple[np.ndarray, ...]:
    m0, m1, m2, m3 = np.moveaxis(np.asarray(m, dtype=float), -1, 0)
    return (
        4 * m0 * m1 * m2 * m3,
        m0 * m1 - m2 * m3,
        m0 * m2 - m1 * m3,
        m0 * m3 - m1 * m2,
        m0 * m1 + m2 * m3,
        m0 * m2 + m1 * m3,
        m0 * m3 + m1 * m2,
    )


def paper_kernel_basis(m) -> np.ndarray:
    """The paper's kernel basis ``f0 … f5`` of ``M_m`` (eq. 13, 14), shape ``(..., 6, 10)``.

    Entries are quartic in ``m``. The basis degenerates when ``n0 = 4 m0 m1 m2 m3 = 0``
    (``docs/math.md``, correction 5): for ``m = (1, 0, 0, 0)`` every vector is zero although
    the kernel is still six-dimensional. See :func:`paper_basis_degenerate` and
    :func:`kernel_basis`.
    """
    n0, n1, n2, n3, n4, n5, n6 = _n_values(check_m(m))
    z = np.zeros_like(n0)
    rows = [
        [n1 * n2, -n2 * n4, n0, z, z, -n1 * n5, z, z, z, n4 * n5],
        [-n4 * n6, n1 * n6, z, n0, z, -n1 * n3, z, z, z, n3 * n4],
        [-n4 * n5, n1 * n5, z, z, n0, n2 * n4, z, z, z, -n1 * n2],
        [n2 * n3, n5 * n6, z, z, z, -n3 * n5, n0, z, z, -n2 * n6],
        [n1 * n3, -n3 * n4, z, z, z, n4 * n6, z, n0, z, -n1 * n6],
        [-n5 * n6, -n2 * n3, z, z, z, n2 * n6, z, z, n0, n3 * n5],
    ]
    return np.stack([np.stack(row, axis=-1) for row in rows], axis=-2) + 0.0


def paper_basis_degenerate(m):
    """Where the paper's basis (eq. 13) is not a basis: ``|n0| ≤ 1e-12 |m|^4`` (shape ``...``)."""
    arr = check_m(m)
    n0 = _n_values(arr)[0]
    return np.abs(n0) <= DEGENERATE_TOL * np.sum(arr * arr, axis=-1) ** 2


def rref_kernel_basis(m) -> np.ndarray:
    """A kernel basis of ``M_m`` that works for every ``m ≠ 0``, shape ``(6, 10)``.

    The null space from the SVD of ``M_m``, brought to reduced row echelon form, which makes
    the basis unique (it depends on the subspace only, not on the SVD's choices): each vector
    has a 1 in its pivot column and zeros in the other vectors' pivot columns.
    """
    mat = mu_prime_matrix(m)
    _, sing, vt = np.linalg.svd(mat)
    rank = int(np.sum(sing > 1e-12 * sing[0]))
    null = vt[rank:].copy()
    rows, cols = null.shape
    pivot_row = 0
    for col in range(cols):
        if pivot_row == rows:
            break
        best = pivot_row + int(np.argmax(np.abs(null[pivot_row:, col])))
        if abs(null[best, col]) <= 1e-10:
            continue
        null[[pivot_row, best]] = null[[best, pivot_row]]
        null[pivot_row] /= null[pivot_row, col]
        for other in range(rows):
            if other != pivot_row:
                null[other] -= null[other, col] * null[pivot_row]
        null[pivot_row, col] = 1.0
        pivot_row += 1
    null[np.abs(null) < 1e-15] = 0.0
    return null


def kernel_basis(m, basis: str = "auto") -> tuple[np.ndarray, str]:
    """A basis ``(6, 10)`` of the kernel of ``M_m`` and the name of the basis used.

    Parameters
    ----------
    m : array_like, shape (4,)
    basis : {"paper", "rref", "auto"}
        ``"paper"``: eq. 13 (raises if it degenerates); ``"rref"``: :func:`rref_kernel_basis`;
        ``"auto"``: the paper's unless it degenerates, else the RREF basis.

    Raises
    ------
    ParameterError
        ``basis="paper"`` while ``n0 = 0``.
    """
    if basis not in BASES:
        raise ParameterError(f"unknown kernel basis {basis!r}; expected one of {BASES}")
    degenerate = paper_basis_degenerate(m)
    if basis == "paper" and degenerate:
        raise ParameterError(
            f"the paper's kernel basis (eq. 13) degenerates for m = "
            f"{np.asarray(m, float).tolist()}: "
            f"n0 = 4 m0 m1 m2 m3 = {_n_values(check_m(m))[0]:.3g}; use the rref basis, or give a "
            f"and b directly"
        )
    if basis == "rref" or (basis == "auto" and degenerate):
        return rref_kernel_basis(m), "rref"
    return paper_kernel_basis(m), "paper"


def model_points_from_matrices(matrices) -> np.ndarray:
    """The points ``(1, R row by row, t)`` of R^13 of robotics matrices ``(..., 4, 4)`` → ``(...,
    13)``."""
    mat = np.asarray(matrices, dtype=float)
    out = np.empty(mat.shape[:-2] + (13,))
    out[..., 0] = 1.0
    out[..., 1:10] = mat[..., :3, :3].reshape(mat.shape[:-2] + (9,))
    out[..., 10:] = mat[..., :3, 3]
    return out


def mu(x, m) -> np.ndarray:
    """The extended kinematic map μ_m: R^13 → Study parameters (eq. 12), ``(..., 13) → (..., 8)``.

    ``p = M_m x'`` and ``q = −½ (x_t / x0) p``, so that ``κ(μ_m(x))`` has the rotation of ``p``
    and the translation ``x_t / x0`` (``docs/math.md``). The paper's ``c`` of eq. 16 is
    ``x0 · μ_m(x)``.
    """
    x = np.asarray(x, dtype=float)
    if x.shape[-1:] != (13,):
        raise ParameterError(
            f"a point of the extended matrix model needs 13 numbers, got shape {x.shape}"
        )
    p = x[..., :10] @ mu_prime_matrix(m).T
    return study_from_quat_trans(p, x[..., 10:] / x[..., :1])


def matrices_from_model_points(x, m) -> np.ndarray:
    """Robotics matrices ``(..., 4, 4)`` of points ``(..., 13)`` under μ_m.

    Raises
    ------
    PoseError
        Where ``x0 = 0`` (a point at infinity) or ``M_m x' = 0`` (in the base locus).
    """
    x = np.asarray(x, dtype=float)
    if np.any(x[..., 0] == 0.0):
        raise PoseError("a point with x0 = 0 lies at infinity and maps to no pose")
    h = mu(x, m)
    norm_p = np.linalg.norm(h[..., :4], axis=-1)
    scale = np.linalg.norm(mu_prime_matrix(m)) * np.linalg.norm(x[..., :10], axis=-1)
    relative = norm_p / scale
    if np.any(relative <= 1e-12):
        raise PoseError(
            f"M_m x' = 0: the point lies in the base locus of μ_[m] and maps to no pose "
            f"(|M_m x'| / (|M_m| |x'|) = {float(np.min(relative)):.3g}, tolerance 1e-12)"
        )
    return matrices_from_rot_trans(*kappa(h))


def check_not_orthogonal(m, quat_wxyz, what: str):
    """``m·p`` for unit quaternions ``p`` (``(..., 4)``); raise where ``μ_[m]`` is undefined."""
    arr = check_m(m)
    dot = dots(arr, np.asarray(quat_wxyz, dtype=float))
    refuse_orthogonal(arr, dot[..., None], (what,))
    return dot[()] if not dot.shape else dot


def refuse_orthogonal(m: np.ndarray, dot: np.ndarray, what: tuple) -> None:
    """Refuse where ``μ_[m]`` is undefined at a pose: ``|m·p| ≤ ORTHOGONAL_TOL |m|``.

    ``m`` is checked (:func:`check_m`), ``(..., 4)``; ``dot`` holds its dot products ``m·p``
    with ``k`` poses' unit quaternions, ``S + (k,)``, which ``what`` names (``k`` names, checked
    in that order).
    """
    shape = dot.shape[:-1]
    norm = np.sqrt(dots(m, m))  # numpy.linalg.norm's sum, in its order
    bad = np.abs(dot) <= ORTHOGONAL_TOL * norm[..., None]
    if not bad.any():
        return
    flat_m = np.broadcast_to(m, shape + (4,)).reshape(-1, 4)
    flat_dot = dot.reshape(-1, len(what))
    for k, name in enumerate(what):
        refuse(
            ParameterError,
            bad[..., k],
            lambda i: (
                f"m = {flat_m[i].tolist()} is orthogonal to the quaternion of the {name} "
                f"(m·p = {float(flat_dot[i, k]):.3g}, tolerance "
                f"{ORTHOGONAL_TOL:g}·|m|): μ_[m] is undefined at that pose"
            ),
            shape,
        )


def mu_fiber_points(matrix, m, alphas, basis: str = "paper") -> np.ndarray:
    """Points of the μ_[m]-fiber of a pose (eq. 15), shape ``(k, 13)``.

    ``x' = (1, R) + Σ α_l f_l``, ``ψ = x'[0]`` and ``x_t = ψ t``. These are affine 3x4
    matrices that are not rigid; μ_m maps every one of them back to the pose.

    Parameters
    ----------
    matrix : array_like, shape (4, 4)
        The pose, robotics layout.
    m : array_like, shape (4,)
    alphas : array_like, shape (k, 6)
        Coefficients in the chosen kernel basis.
    basis : {"paper", "rref", "auto"}
    """
    mat = np.asarray(matrix, dtype=float)
    check_not_orthogonal(m, quaternions_from_rotations(mat[:3, :3]), "pose")
    alphas = np.atleast_2d(np.asarray(alphas, dtype=float))
    if alphas.shape[-1] != 6:
        raise ParameterError(f"each alpha needs 6 numbers, got shape {alphas.shape}")
    if not np.all(np.isfinite(alphas)):
        raise ParameterError("alpha contains NaN or infinity")
    base, _ = kernel_basis(m, basis)
    point = model_points_from_matrices(mat)
    out = np.broadcast_to(point, alphas.shape[:-1] + (13,)).copy()
    out[..., :10] += alphas @ base
    out[..., 10:] = out[..., :1] * mat[:3, 3]
    return out
