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

import math

import numpy as np

from ..frames import ScrewFrame
from ..poses import rotations_from_quaternions
from ..study import quat_mul
from ._rational import blocked_product, make_table
from .base import Motion

#: Largest |tφ/2| for which the screw basis is computed from tan(tφ/2) (see ``_basis``); numpy's
#: vectorised tan reduces larger arguments less accurately, and there np.sin is used.
HALF_ANGLE_TAN = 1.6


class ScrewMotion(Motion):
    """The helical interpolant of two poses (ScLERP)."""

    mode = "screw"

    def __init__(self, start, end, frame: ScrewFrame):
        super().__init__(start, end, frame)
        phi, d = frame.phi, frame.d
        u = frame.axis_direction
        k = np.array([[0.0, -u[2], u[1]], [u[2], 0.0, -u[0]], [-u[1], u[0], 0.0]])
        k2 = k @ k
        rot_a = rotations_from_quaternions(frame.p_start)
        t_a = frame.t_start
        t_perp = frame.t_perp
        cross = np.cross(u, t_perp)
        rot = np.stack([rot_a, np.zeros((3, 3)), k @ rot_a, k2 @ rot_a]).reshape(4, 9)
        trans = np.stack([t_a, d * u, k @ t_a, k2 @ t_a])
        if phi > 0.0:
            cot = math.cos(phi / 2) / math.sin(phi / 2)
            trans[2] += 0.5 * cot * t_perp - 0.5 * cross
            trans[3] += 0.5 * t_perp + 0.5 * cot * cross
        else:
            trans[1] += t_perp
        self.table = make_table(rot, [1.0, 0.0, 0.0, 0.0], trans, [1.0, 0.0, 0.0, 0.0])

    def _basis(self, ts):
        # Rows (1, t, sin tφ, vers tφ) of one array, returned transposed, as bernstein_basis.
        t = np.asarray(ts, dtype=float)
        out = np.empty((4,) + t.shape)
        out[0] = 1.0
        out[1] = t
        half = np.multiply(t, 0.5 * self.frame.phi, out=out[3])
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
            angle = np.multiply(t, self.frame.phi, out=out[2])
            np.sin(half, out=half)
            np.multiply(half, half, out=half)
            half *= 2.0
            np.sin(angle, out=angle)
        return out.T if t.ndim == 1 else np.moveaxis(out, 0, -1)

    def _quats(self, ts):
        # exp(tφ/2 u) pA = cos(tφ/2) pA + sin(tφ/2) (u pA): one (N, 2) @ (2, 4) product
        t = np.asarray(ts, dtype=float)
        half = np.empty((2,) + t.shape)
        np.multiply(t, 0.5 * self.frame.phi, out=half[1])
        np.cos(half[1], out=half[0])
        np.sin(half[1], out=half[1])
        p_a = self.frame.p_start
        u_p_a = quat_mul(np.concatenate([[0.0], self.frame.axis_direction]), p_a)
        half = half.T if t.ndim == 1 else np.moveaxis(half, 0, -1)
        if half.ndim != 2:
            return half @ np.stack([p_a, u_p_a])
        return blocked_product(half, np.stack([p_a, u_p_a]))

    def _describe(self):
        phi, d = self.frame.phi, self.frame.d
        return {
            "pitch": d / phi if phi > 0 else None,
            "transmission_curve": "z = d * omega / phi (a straight line)",
        }
