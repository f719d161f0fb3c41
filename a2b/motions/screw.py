"""The screw motion (ScLERP), ``C(t) = exp(t log(B A⁻¹)) A``: the classical baseline.

About the axis ``(u, c)`` of ``D = B A⁻¹`` the motion rotates by ``ω = tφ`` and slides by
``t d``. With ``K`` the cross-product matrix of ``u``,

* ``R(t) = (I + sin(tφ) K + vers(tφ) K²) RA`` where ``vers x = 2 sin²(x/2)`` (no cancellation
  for small angles), and
* ``t(t) = R_D(t) tA + t⊥ (vers/2 + cot(φ/2) sin/2) + (u × t⊥)(cot(φ/2) vers/2 − sin/2) + t d u``,

which is linear in the basis ``(1, t, sin tφ, vers tφ)`` and never forms the far-away axis
point of a nearly pure translation.
"""

from __future__ import annotations

import numpy as np

from ..frames import ScrewFrame
from ..poses import rotations_from_quaternions
from ..study import cross, quat_mul
from .base import Motion

#: Largest |tφ/2| for which the screw basis is computed from tan(tφ/2) (see ``_basis``); numpy's
#: vectorised tan reduces larger arguments less accurately, and there np.sin is used.
HALF_ANGLE_TAN = 1.6


class ScrewMotion(Motion):
    """The helical interpolants of pairs of poses (ScLERP)."""

    mode = "screw"
    what = "screw motion"

    def __init__(self, start, end, frame: ScrewFrame):
        super().__init__(start, end, frame)
        phi, d = np.asarray(frame.phi), np.asarray(frame.d)
        u = np.asarray(frame.axis_direction)
        k = np.zeros(u.shape + (3,))
        k[..., 0, 1], k[..., 0, 2], k[..., 1, 2] = -u[..., 2], u[..., 1], -u[..., 0]
        k[..., 1, 0], k[..., 2, 0], k[..., 2, 1] = u[..., 2], -u[..., 1], u[..., 0]
        k2 = k @ k
        rot_a = rotations_from_quaternions(frame.p_start)
        t_a = np.asarray(frame.t_start)
        t_perp = frame.t_perp
        u_cross_t = cross(u, t_perp)
        # the table written in place: rows (1, t, sin, vers) of [R | t] and the denominators 1
        self.table = np.empty(u.shape[:-1] + (4, 14))
        blocks = self.table[..., :12].reshape(u.shape[:-1] + (4, 3, 4))
        blocks[..., 0, :, :3] = rot_a
        blocks[..., 1, :, :3] = 0.0
        np.matmul(k, rot_a, out=blocks[..., 2, :, :3])
        np.matmul(k2, rot_a, out=blocks[..., 3, :, :3])
        self.table[..., 12:] = np.array([1.0, 0.0, 0.0, 0.0])[:, None]
        trans = np.stack(
            [t_a, d[..., None] * u, (k @ t_a[..., None])[..., 0], (k2 @ t_a[..., None])[..., 0]],
            axis=-2,
        )
        turning = (phi > 0.0)[..., None]
        with np.errstate(divide="ignore", invalid="ignore"):
            half_cot = np.where(
                turning, 0.5 * np.cos(phi / 2)[..., None] / np.sin(phi / 2)[..., None], 0.0
            )
        trans[..., 2, :] += np.where(turning, half_cot * t_perp - 0.5 * u_cross_t, 0.0)
        trans[..., 3, :] += np.where(turning, 0.5 * t_perp + half_cot * u_cross_t, 0.0)
        trans[..., 1, :] += np.where(turning, 0.0, t_perp)
        blocks[..., 3] = trans
        # p(t) = cos(tφ/2) pA + sin(tφ/2) u pA: the "ends" of this path are pA and u pA
        u_quat = np.concatenate([np.zeros(u.shape[:-1] + (1,)), u], axis=-1)
        self.quat_ends = np.stack([frame.p_start, quat_mul(u_quat, frame.p_start)], axis=-2)

    def _basis(self, ts):
        """Rows ``(1, t, sin tφ, vers tφ)``: ``(N, 4)`` for one motion, ``S + (N, 4)`` else."""
        phi = np.asarray(self.frame.phi)
        t = np.asarray(ts, dtype=float)
        if phi.ndim:
            t = np.broadcast_to(t, phi.shape + t.shape[-1:])
            phi = phi[..., None]
        out = np.empty((4,) + t.shape)
        out[0] = 1.0
        out[1] = t
        half = np.multiply(t, 0.5 * phi, out=out[3])
        if t.size and max(-float(half.min()), float(half.max())) <= HALF_ANGLE_TAN:
            # τ = tan(tφ/2): sin = 2τ / (1 + τ²) and vers = 2 sin²(tφ/2) = τ sin. numpy
            # vectorises tan but not sin: one tan takes a fifth of the time of two sines,
            # and on |tφ/2| ≤ 1.6 (t ∈ [0, 1] and a little beyond) sin and vers stay within
            # 4e-16 and 5e-16 relative, without cancellation, also at the pole tφ → π.
            tau = np.tan(half, out=half)
            sin = np.multiply(tau, tau, out=out[2])
            sin += 1.0
            np.divide(tau, sin, out=sin)
            sin *= 2.0
            np.multiply(tau, sin, out=tau)
        else:
            angle = np.multiply(t, phi, out=out[2])
            np.sin(half, out=half)
            np.multiply(half, half, out=half)
            half *= 2.0
            np.sin(angle, out=angle)
        return np.moveaxis(out, 0, -1)

    def _basis_derivatives(self, ts, order):
        """``(1, t, sin tφ, vers tφ)`` and its derivatives ``(0, 1, φ cos, φ sin)``, … in t."""
        phi = np.asarray(self.frame.phi)
        t = np.asarray(ts, dtype=float)
        if phi.ndim:
            t = np.broadcast_to(t, phi.shape + t.shape[-1:])
            phi = phi[..., None]
        angle = t * phi
        sin, cos = np.sin(angle), np.cos(angle)
        rows = [np.moveaxis(self._basis(ts), -1, 0)]
        waves = [(phi * cos, phi * sin), (-(phi**2) * sin, phi**2 * cos)]
        waves.append((-(phi**3) * cos, -(phi**3) * sin))
        zero = np.zeros(t.shape)
        for r in range(1, order + 1):
            one = np.ones(t.shape) if r == 1 else zero
            rows.append(np.stack([zero, one, *waves[r - 1]]))
        return np.moveaxis(np.moveaxis(np.stack(rows), 1, -1), 0, -3)

    def _quats(self, ts):
        # exp(tφ/2 u) pA = cos(tφ/2) pA + sin(tφ/2) (u pA): (N, 2) @ (2, 4) per motion
        phi = np.asarray(self.frame.phi)
        t = np.asarray(ts, dtype=float)
        angle = (0.5 * phi)[..., None] * t
        half = np.stack([np.cos(angle), np.sin(angle)], axis=-1)
        return half @ self.quat_ends

    def _check_interval(self, lo, hi):
        """A screw motion is defined for every t."""

    def _rotation_is_fragile(self, lo, hi):
        return np.zeros(self.shape, dtype=bool)

    def _describe(self):
        phi, d = float(self.frame.phi), float(self.frame.d)
        return {
            "pitch": d / phi if phi > 0 else None,
            "transmission_curve": "z = d * omega / phi (a straight line)",
        }
