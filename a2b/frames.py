"""The screw axis of a displacement and the canonical frame of two poses.

For poses ``A`` and ``B`` (robotics matrices) the displacement ``D = B A⁻¹`` (so ``B = D A``)
is a screw: a rotation by ``φ ∈ [0, π]`` about an axis with unit direction ``u`` through the
point ``c``, and a translation ``d`` along it. In **canonical coordinates** (``docs/math.md``) the
axis is the z-axis, ``A = I`` and ``B`` is the rotation by ``φ`` about z with the translation
``d`` along z. a2b never needs the change of frame ``F`` to sample a motion (the formulas in
:mod:`a2b.motions` are written in the given coordinates and stay well conditioned for tiny
``φ``), but :meth:`ScrewFrame.to_canonical` provides it for analysis and tests.

Choices a2b makes, recorded in :attr:`ScrewFrame.choices`:

* the sign of B's quaternion, so that ``pA·pB ≥ 0`` (the short way round);
* for ``φ = π`` (both signs are short), the axis orientation with ``d > 0`` or, for ``d = 0``,
  with the first non-zero component of ``u`` positive;
* for a pure translation (``φ = 0``), the axis along the translation through A's origin;
  for ``B = A``, the axis parallel to z through A's origin.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .poses import canonical_sign, quat_trans_from_matrices, study_from_quat_trans
from .study import quat_conj, quat_mul

#: ``|sin(φ/2)|`` at or below which the relative rotation of two poses is rounding noise.
ROTATION_NOISE = 4 * np.finfo(float).eps


@dataclass(frozen=True)
class ScrewFrame:
    """The screw ``D = B A⁻¹`` of two poses, with consistent unit Study vectors.

    Attributes
    ----------
    phi : float
        Rotation angle in ``[0, π]``.
    d : float
        Translation along the axis (signed, in the poses' length unit).
    axis_direction : ndarray (3,)
        Unit vector ``u``.
    axis_point : ndarray (3,)
        The point of the axis closest to the origin of the fixed frame.
    r : ndarray (4,)
        Unit quaternion ``pB p̄A = (cos φ/2, sin φ/2 u)`` of ``D``'s rotation.
    p_start, p_end : ndarray (4,)
        Unit quaternions of A and B, with ``p_end p̄_start = r``.
    h_start, h_end : ndarray (8,)
        Unit Study vectors of A and B with these primal parts.
    t_start, t_end : ndarray (3,)
        Translations of A and B.
    t_disp : ndarray (3,)
        Translation of ``D``; ``t_perp = t_disp − d u``.
    choices : list of str
        Every choice made for the user, in words.
    """

    phi: float
    d: float
    axis_direction: np.ndarray
    axis_point: np.ndarray
    r: np.ndarray
    p_start: np.ndarray
    p_end: np.ndarray
    h_start: np.ndarray
    h_end: np.ndarray
    t_start: np.ndarray
    t_end: np.ndarray
    t_disp: np.ndarray
    choices: list = field(default_factory=list)

    @property
    def t_perp(self) -> np.ndarray:
        """Component of the displacement's translation perpendicular to the axis, ``(3,)``."""
        return self.t_disp - self.d * self.axis_direction

    def canonical_transform(self) -> np.ndarray:
        """A rigid ``F`` (4x4) taking the axis to the z-axis, the axis point to the origin."""
        u = self.axis_direction
        ez = np.array([0.0, 0.0, 1.0])
        v = np.cross(u, ez)
        sin_a = np.linalg.norm(v)
        cos_a = float(np.dot(u, ez))
        if sin_a < 1e-15:
            rot = np.eye(3) if cos_a > 0 else np.diag([1.0, -1.0, -1.0])
        else:
            k = v / sin_a
            kx = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
            rot = np.eye(3) + sin_a * kx + (1 - cos_a) * kx @ kx
        out = np.eye(4)
        out[:3, :3] = rot
        out[:3, 3] = -rot @ self.axis_point
        return out

    def to_canonical(self, matrices: np.ndarray, start: np.ndarray) -> np.ndarray:
        """Poses ``(..., 4, 4)`` in canonical coordinates: ``X ↦ F X A⁻¹ F⁻¹``."""
        from .poses import inverse_matrices

        f = self.canonical_transform()
        return f @ np.asarray(matrices, dtype=float) @ inverse_matrices(start) @ inverse_matrices(f)

    def transmission(self, matrices: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Rotation angle ω and translation z of poses ``(N, 4, 4)`` relative to A about the axis.

        ``ω`` is measured about ``u`` (unwrapped, starting from the branch nearest 0) and
        ``z = u · t_D`` where ``D = X A⁻¹``. Meaningful for motions in this cylinder group.
        """
        quat, trans = quat_trans_from_matrices(matrices)
        rel = quat_mul(quat, quat_conj(self.p_start))
        omega = 2.0 * np.arctan2(rel[..., 1:] @ self.axis_direction, rel[..., 0])
        omega = np.where(omega > np.pi, omega - 2 * np.pi, omega)
        omega = np.where(omega <= -np.pi, omega + 2 * np.pi, omega)
        omega = np.unwrap(omega)
        mats = np.asarray(matrices, dtype=float)
        t_disp = trans - np.einsum("...ij,j->...i", mats[..., :3, :3], _rot_t(self))
        return omega, t_disp @ self.axis_direction


def _rot_t(frame: ScrewFrame) -> np.ndarray:
    # Rᵀ_A t_A: with X = D A, t_X = R_D t_A + t_D and R_D = R_X R_Aᵀ.
    from .poses import rotations_from_quaternions

    return rotations_from_quaternions(frame.p_start).T @ frame.t_start


def screw_frame(start: np.ndarray, end: np.ndarray) -> ScrewFrame:
    """The screw axis of ``D = B A⁻¹`` for robotics matrices ``start = A`` and ``end = B``.

    Parameters
    ----------
    start, end : ndarray, shape (4, 4)
        Valid poses (see :func:`a2b.poses.check_matrices`).

    Returns
    -------
    ScrewFrame
    """
    p_a, t_a = quat_trans_from_matrices(start)
    p_b, t_b = quat_trans_from_matrices(end)
    choices = []
    if np.array_equal(p_a, p_b):  # identical rotations: no rounding residue from p p̄
        r = np.array([1.0, 0.0, 0.0, 0.0])
    else:
        r = quat_mul(p_b, quat_conj(p_a))
    s = float(np.linalg.norm(r[1:]))
    half_turn = s > ROTATION_NOISE and abs(r[0]) <= ROTATION_NOISE
    if r[0] < 0 and not half_turn:
        p_b, r = -p_b, -r
        choices.append("flipped the sign of B's quaternion so that pA·pB ≥ 0 (the short way round)")
    from .poses import rotations_from_quaternions

    rot_d = rotations_from_quaternions(r)
    t_disp = t_b - rot_d @ t_a
    if 0.0 < s <= ROTATION_NOISE:
        choices.append(
            f"the rotations of A and B differ by |sin(φ/2)| = {s:.3g}, within rounding "
            f"({ROTATION_NOISE:.3g}): treated as a pure translation"
        )
    if s > ROTATION_NOISE:
        u = r[1:] / s
        d = float(u @ t_disp)
        if half_turn:
            # A half-turn (pA·pB = 0 within rounding): u and −u are equally short; pick one and
            # say so, rather than let the sign of rounding noise decide.
            flip = d < 0 or (d == 0 and canonical_sign(u)[0] != u[0])
            if flip:
                u, d, p_b, r = -u, -d, -p_b, -r
            choices.append(
                f"φ = π (|pA·pB| = {abs(r[0]):.3g} ≤ {ROTATION_NOISE:.3g}): both axis orientations are "
                "short; chose the one with "
                + ("d > 0" if d > 0 else "d = 0 and the first non-zero axis component positive")
            )
        phi = 2.0 * float(np.arctan2(s, abs(r[0])))
        t_perp = t_disp - d * u
        axis_point = 0.5 * (t_perp + np.cross(u, t_perp) * (abs(r[0]) / s))
    else:
        phi = 0.0
        norm_t = float(np.linalg.norm(t_disp))
        if norm_t > 0.0:
            u = t_disp / norm_t
            d = norm_t
            choices.append(
                "pure translation (φ = 0): the axis is the line through A's origin along the translation"
            )
        else:
            u = np.array([0.0, 0.0, 1.0])
            d = 0.0
            choices.append("B = A: the axis is chosen parallel to z through A's origin")
        axis_point = t_a - (u @ t_a) * u
    h_a = study_from_quat_trans(p_a, t_a)
    h_b = study_from_quat_trans(p_b, t_b)
    return ScrewFrame(
        phi=phi,
        d=d,
        axis_direction=u,
        axis_point=axis_point,
        r=r,
        p_start=p_a,
        p_end=p_b,
        h_start=h_a,
        h_end=h_b,
        t_start=t_a,
        t_end=t_b,
        t_disp=t_disp,
        choices=choices,
    )
