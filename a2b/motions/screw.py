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
from ._rational import make_table
from .base import Motion


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
        angle = ts * self.frame.phi
        half = np.sin(0.5 * angle)
        return np.stack([np.ones_like(ts), ts, np.sin(angle), 2.0 * half * half], axis=-1)

    def _quats(self, ts):
        half = 0.5 * ts * self.frame.phi
        rel = np.empty(ts.shape + (4,))
        rel[..., 0] = np.cos(half)
        rel[..., 1:] = np.sin(half)[..., None] * self.frame.axis_direction
        return quat_mul(rel, self.frame.p_start)

    def _describe(self):
        phi, d = self.frame.phi, self.frame.d
        return {
            "pitch": d / phi if phi > 0 else None,
            "transmission_curve": "z = d * omega / phi (a straight line)",
        }
