"""Vertical Darboux motions: straight lines in the extended dual-quaternion model (section 3).

Take the unit Study vectors ``hA``, ``hB`` (with ``pA·pB ≥ 0``; the long way flips ``hB``),
the fiber points ``hA + sA ε pA`` and ``hB + sB ε pB`` and the line
``h(t) = (1−t)(hA + sA ε pA) + t(hB + sB ε pB)``. The pose at ``t`` is ``κ(h(t))``, with no
normalisation or projection onto the Study quadric. The motion depends on ``δ = sB − sA``
only; a2b uses ``sA = −δ/2``, ``sB = δ/2``.

In canonical coordinates (``docs/math.md``, Theorem 1) the transmission curve is
``z = z0 + λ sin(ω + κ)`` with ``z0 = d/2 + δ cot(φ/2)``, ``λ = √(d²/4 + δ²) / |sin(φ/2)|``,
and the pitch ``dz/dω`` is ``(d/2) cot(φ/2) ∓ δ`` at the start and the end. For the long way
round the same formulas hold with ``φ`` replaced by ``φ − 2π``.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import ParameterError
from ..frames import ScrewFrame
from ..study import rotation_numerators, translation_numerators
from ._rational import (
    FRAGILE_TOL,
    bernstein_basis,
    check_quaternion_path,
    make_table,
    quaternion_path_minimum,
)
from .base import Motion, linear_path

#: Relative tolerance for a third pose to count as a member of the cylinder group of A and B.
CYLINDER_TOL = 1e-9

SOLVERS = ("delta", "kappa", "lam", "pitch_start", "pitch_end", "through")


def _wrap(angle: float) -> float:
    """Wrap an angle to ``(−π, π]``."""
    wrapped = math.remainder(angle, 2 * math.pi)
    return math.pi if wrapped == -math.pi else wrapped


def _require_rotation(phi_eff: float, what: str) -> None:
    if phi_eff == 0.0:
        raise ParameterError(
            f"{what} is undefined for a pure translation (φ = 0): every Darboux interpolant is "
            "the straight translation"
        )


def delta_from_kappa(kappa: float, phi: float, d: float) -> float:
    """δ for a prescribed phase κ of ``z = z0 + λ sin(ω + κ)`` (``docs/math.md``)."""
    _require_rotation(phi, "the phase κ")
    half = math.sin(phi / 2)
    theta = kappa + phi / 2 - (math.pi if half < 0 else 0.0)
    if d == 0.0:
        raise ParameterError(
            "the phase κ does not determine δ when d = 0 (the transmission curve is "
            "z0 + λ sin(ω + κ) with κ = −φ/2 ± π/2 for every δ); give delta or lam instead"
        )
    cos_t = math.cos(theta)
    if abs(cos_t) < 1e-12:
        raise ParameterError(
            f"κ = {kappa:.6g} ≡ −φ/2 ± π/2 requires d = 0 (here d = {d:.6g}); no Darboux interpolant has it"
        )
    if cos_t * d < 0:
        raise ParameterError(
            f"no Darboux interpolant of these poses has phase κ = {kappa:.6g} with λ ≥ 0; "
            f"κ + π = {_wrap(kappa + math.pi):.6g} describes the mirrored sine and is reachable"
        )
    return -(d / 2) * math.tan(theta)


def delta_from_lam(lam: float, phi: float, d: float, branch: int = 1) -> float:
    """δ for a prescribed amplitude λ: ``|δ| = √(λ² sin²(φ/2) − d²/4)``, sign from ``branch``."""
    _require_rotation(phi, "the amplitude λ")
    if branch not in (1, -1):
        raise ParameterError(f"branch must be +1 or -1, got {branch!r}")
    half = abs(math.sin(phi / 2))
    minimum = abs(d) / (2 * half)
    if not lam >= minimum * (1 - 1e-12):
        raise ParameterError(
            f"amplitude λ = {lam:.6g} is below the minimum |d| / (2 sin(φ/2)) = {minimum:.6g} "
            "of the Darboux interpolants of these poses"
        )
    return branch * math.sqrt(max(lam * lam * half * half - d * d / 4, 0.0))


def delta_from_pitch(pitch: float, phi: float, d: float, at: str) -> float:
    """δ for a prescribed pitch ``dz/dω`` (translation per radian) at the start or the end."""
    _require_rotation(phi, f"the pitch at the {at}")
    cot = math.cos(phi / 2) / math.sin(phi / 2)
    base = (d / 2) * cot
    return base - pitch if at == "start" else pitch - base


def delta_from_third_pose(omega_c: float, z_c: float, phi: float, d: float) -> float:
    """δ of the one Darboux interpolant through the cylinder-group pose ``(ωC, zC)``."""
    _require_rotation(phi, "a third pose")
    denom = math.cos(omega_c - phi / 2) - math.cos(phi / 2)
    if abs(denom) < 1e-12:
        raise ParameterError(
            f"the third pose has the rotation angle of A or B (ωC = {omega_c:.6g}); "
            "no Darboux interpolant is singled out by it"
        )
    return ((d / 2) * math.sin(omega_c - phi / 2) - (z_c - d / 2) * math.sin(phi / 2)) / denom


def third_pose_coordinates(frame: ScrewFrame, pose: np.ndarray) -> tuple[float, float]:
    """``(ωC, zC)`` of a pose in the cylinder group of A and B, or a clear error."""
    from ..poses import quat_trans_from_matrices, rotations_from_quaternions
    from ..study import quat_conj, quat_mul

    p_c, t_c = quat_trans_from_matrices(pose)
    rel = quat_mul(p_c, quat_conj(frame.p_start))
    u = frame.axis_direction
    off_axis = rel[1:] - (rel[1:] @ u) * u
    rot_residual = float(np.linalg.norm(off_axis))
    rot_e = rotations_from_quaternions(rel)
    t_e = t_c - rot_e @ frame.t_start
    c = frame.axis_point
    expected = (np.eye(3) - rot_e) @ c + (u @ t_e) * u
    scale = max(1.0, float(np.linalg.norm(t_e)), float(np.linalg.norm(c)), abs(frame.d))
    trans_residual = float(np.linalg.norm(t_e - expected)) / scale
    if rot_residual > CYLINDER_TOL or trans_residual > CYLINDER_TOL:
        raise ParameterError(
            "the third pose is not in the cylinder group of A and B (a rotation about and a "
            f"translation along their screw axis): rotation residual {rot_residual:.3g}, "
            f"relative translation residual {trans_residual:.3g}, tolerance {CYLINDER_TOL:g}"
        )
    omega = 2.0 * math.atan2(float(rel[1:] @ u), float(rel[0]))
    return omega, float(u @ t_e)


class DarbouxMotion(Motion):
    """A vertical Darboux motion between two poses (Theorem 1).

    Parameters
    ----------
    start, end : ndarray (4, 4)
        Robotics matrices A and B.
    frame : ScrewFrame
        ``a2b.frames.screw_frame(start, end)``.
    delta, kappa, lam, pitch_start, pitch_end, through :
        At most one of them fixes the essential parameter δ (default ``delta = 0``).
        ``kappa`` is the phase in radians, ``lam`` the amplitude (with ``branch`` ±1 choosing
        the sign of δ), the pitches are translations per radian, ``through`` a 4x4 pose in the
        cylinder group of A and B.
    long_way : bool
        Rotate by ``2π − φ`` instead of ``φ`` (flip the sign of ``hB``).
    """

    mode = "darboux"

    def __init__(
        self,
        start,
        end,
        frame: ScrewFrame,
        *,
        delta=None,
        kappa=None,
        lam=None,
        branch=None,
        pitch_start=None,
        pitch_end=None,
        through=None,
        long_way: bool = False,
    ):
        super().__init__(start, end, frame)
        given = {
            name: value
            for name, value in dict(
                delta=delta,
                kappa=kappa,
                lam=lam,
                pitch_start=pitch_start,
                pitch_end=pitch_end,
                through=through,
            ).items()
            if value is not None
        }
        if len(given) > 1:
            raise ParameterError(
                "darboux has one essential parameter; give at most one of "
                f"{', '.join(SOLVERS)} (got {', '.join(given)})"
            )
        if branch is not None and lam is None:
            raise ParameterError("branch chooses between the two solutions for lam; give lam too")
        self.long_way = bool(long_way)
        phi, d = frame.phi, frame.d
        self.phi_eff = phi - 2 * math.pi if (self.long_way and phi > 0) else phi
        if self.long_way and phi == 0.0:
            self.phi_eff = -2 * math.pi
        phi_e = self.phi_eff if phi > 0 else 0.0
        for name in given:
            if not isinstance(given[name], np.ndarray) and name != "through":
                value = float(given[name])
                if not math.isfinite(value):
                    raise ParameterError(f"{name} must be finite, got {value}")
                given[name] = value
        if "kappa" in given:
            delta_v = delta_from_kappa(given["kappa"], phi_e, d)
        elif "lam" in given:
            delta_v = delta_from_lam(given["lam"], phi_e, d, 1 if branch is None else int(branch))
        elif "pitch_start" in given:
            delta_v = delta_from_pitch(given["pitch_start"], phi_e, d, "start")
        elif "pitch_end" in given:
            delta_v = delta_from_pitch(given["pitch_end"], phi_e, d, "end")
        elif "through" in given:
            _require_rotation(phi_e, "a third pose")
            from ..poses import check_matrices

            omega_c, z_c = third_pose_coordinates(frame, check_matrices(given["through"]))
            delta_v = delta_from_third_pose(omega_c, z_c, phi_e, d)
        else:
            delta_v = given.get("delta", 0.0)
        self.delta = float(delta_v)
        self.solved_from = next(iter(given), "delta")
        if lam is not None:
            self.choices.append(
                f"lam has two mirror solutions ±|δ|; used branch {1 if branch is None else int(branch):+d}"
            )
        if phi == 0.0 and self.delta != 0.0:
            self.choices.append("δ has no effect on a pure translation")

        h_a = frame.h_start
        h_b = -frame.h_end if self.long_way else frame.h_end
        if self.long_way:
            self.choices.append("long way round: flipped the sign of hB")
        s_a, s_b = 0.0 - self.delta / 2, self.delta / 2  # 0.0 − x avoids printing −0
        p_a, q_a = h_a[:4], h_a[4:] + s_a * h_a[:4]
        p_b, q_b = h_b[:4], h_b[4:] + s_b * h_b[:4]
        self.fiber_offsets = (s_a, s_b)
        self._p = np.stack([p_a, p_b])
        rot = np.stack(
            [rotation_numerators(p_a), rotation_numerators(p_a, p_b), rotation_numerators(p_b)]
        )
        den = np.array([p_a @ p_a, p_a @ p_b, p_b @ p_b])
        trans = np.stack(
            [
                translation_numerators(p_a, q_a),
                0.5 * (translation_numerators(p_a, q_b) + translation_numerators(p_b, q_a)),
                translation_numerators(p_b, q_b),
            ]
        )
        self.table = make_table(rot, den, trans, den)
        self._check_interval(0.0, 1.0)

    def _basis(self, ts):
        return bernstein_basis(ts, 2)

    def _quats(self, ts):
        return linear_path(ts, self._p)

    def _rotation_is_fragile(self, lo, hi):
        return quaternion_path_minimum(self._p[0], self._p[1], lo, hi)[1] < FRAGILE_TOL

    def _check_interval(self, lo, hi):
        check_quaternion_path(self._p[0], self._p[1], lo, hi, "Darboux motion", warn=self._warn)

    def singular_t(self):
        p_a, p_b = self._p
        if np.allclose(p_a, -p_b, rtol=0, atol=1e-12):
            return [0.5]
        return []

    def closed_form(self) -> dict:
        """The transmission curve's parameters in canonical coordinates (``docs/math.md``)."""
        phi, d, delta = self.phi_eff, self.frame.d, self.delta
        if phi == 0.0:
            return dict(z0=None, lam=None, kappa=None, pitch_start=None, pitch_end=None)
        half_sin = math.sin(phi / 2)
        cot = math.cos(phi / 2) / half_sin
        amplitude = math.hypot(d / 2, delta)
        theta = math.atan2(-delta, d / 2)
        kappa = -phi / 2 + theta + (math.pi if half_sin < 0 else 0.0)
        return dict(
            z0=d / 2 + delta * cot,
            lam=amplitude / abs(half_sin),
            kappa=_wrap(kappa) if amplitude > 0 else None,
            pitch_start=(d / 2) * cot - delta,
            pitch_end=(d / 2) * cot + delta,
        )

    def transmission(self, omega: np.ndarray) -> np.ndarray:
        """The closed-form ``z(ω)`` in canonical coordinates (``docs/math.md``).

        Raises
        ------
        ParameterError
            For a pure translation (φ = 0), where z is no function of ω.
        """
        phi, d, delta = self.phi_eff, self.frame.d, self.delta
        _require_rotation(phi if self.frame.phi > 0 else 0.0, "the transmission curve z(ω)")
        half = math.sin(phi / 2)
        return (
            d / 2
            + (
                (d / 2) * np.sin(omega - phi / 2)
                - delta * (np.cos(omega - phi / 2) - math.cos(phi / 2))
            )
            / half
        )

    def omega_of_t(self, ts: np.ndarray) -> np.ndarray:
        """The closed-form ``ω(t)``: ``tan(ω/2) = t sin(φ/2) / (1 − t + t cos(φ/2))``."""
        phi = self.phi_eff
        t = np.asarray(ts, dtype=float)
        return 2.0 * np.arctan2(t * math.sin(phi / 2), 1 - t + t * math.cos(phi / 2))

    def _describe(self):
        out = {"delta": self.delta, "solved_from": self.solved_from, "long_way": self.long_way}
        out["rotation_angle"] = self.phi_eff
        out.update(self.closed_form())
        out["fiber_offsets"] = list(self.fiber_offsets)
        out["transmission_curve"] = "z = z0 + lam * sin(omega + kappa)"
        return out
