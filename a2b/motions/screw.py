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

from functools import cached_property

import numpy as np

from ..elements import everywhere
from ..frames import ScrewFrame
from ..study import AXIS_TIMES, CROSS, bilinear, sum_terms, vector_form
from ._rational import CHUNK
from .base import Motion
from .text import number_text

#: Largest |tφ/2| for which the screw basis is computed from tan(tφ/2) (see ``_basis``); numpy's
#: vectorised tan reduces larger arguments less accurately, and there np.sin is used.
HALF_ANGLE_TAN = 1.6
#: Largest |tφ/2| for which the quaternions are computed from tan(tφ/2) (see ``_quats``): the
#: double below π/2, where cos(tφ/2) ≥ 0 and tan is positive (1.6e16).
HALF_TURN = np.pi / 2


def screw_tables(frame: ScrewFrame, start: np.ndarray) -> np.ndarray:
    """The tables ``S + (4, 14)``: rows ``(1, t, sin tφ, vers tφ)`` of ``[R | t]`` and the
    denominators 1 (see the module's docstring).

    Component-major, in chunks of :data:`CHUNK` pairs: the four columns of ``[RA | tA]`` as
    ``(3, 4, J)``, so that ``K X = u × X`` is one :func:`a2b.study.bilinear` and
    ``K² X = u (u·X) − X`` three elementwise steps over all of them (``|u| = 1``), not 3x3
    products per pair.
    """
    rot = start.reshape(-1, 4, 4)[:, :3, :3]  # A's rotation block, as given
    given = (
        rot,
        frame.t_start.reshape((-1, 3)),
        frame.axis_direction.reshape((-1, 3)),
        frame.t_perp.reshape((-1, 3)),
        frame.phi.reshape(-1),
        frame.d.reshape(-1),
    )
    table = np.zeros((len(rot), 4, 14))
    table[:, 0, 12:] = 1.0
    if len(rot) <= CHUNK:
        _screw_chunk(*given, table)
    else:
        for lo in range(0, len(rot), CHUNK):
            _screw_chunk(*(item[lo : lo + CHUNK] for item in given), table[lo : lo + CHUNK])
    return table.reshape(frame.shape + (4, 14))


def _screw_chunk(rot, t_a, u, t_perp, phi, d, table) -> None:
    """:func:`screw_tables` for one chunk of pairs, written into its ``table`` ``(J, 4, 14)``."""
    count = len(rot)
    u, t_perp = u.T, t_perp.T  # (3, J)
    vectors = np.empty((3, 5, count))  # the columns of [RA | tA], and t⊥ for u × t⊥
    vectors[:, :3] = rot.transpose(1, 2, 0)
    vectors[:, 3] = t_a.T
    vectors[:, 4] = t_perp
    columns = vectors[:, :4]
    crossed = bilinear(CROSS, u[:, None], vectors)  # (3, 5, J)
    k_cols, u_cross_t = crossed[:, :4], crossed[:, 4]
    k2_cols = u[:, None] * sum_terms(u[:, None] * columns)  # u (u·X), its terms added in order
    k2_cols -= columns
    turning = phi > 0.0
    every = everywhere(turning)
    half = phi / 2
    if every:  # ½ cot(φ/2)
        half_cot = 0.5 * np.cos(half) / np.sin(half)
    else:  # where φ > 0, else 0 (not divided)
        half_cot = np.divide(
            0.5 * np.cos(half), np.sin(half), out=np.zeros(phi.shape), where=turning
        )
    k_turn = half_cot * t_perp - 0.5 * u_cross_t
    k2_turn = 0.5 * t_perp + half_cot * u_cross_t
    if not every:  # no such terms without a rotation
        k_turn, k2_turn = np.where(turning, k_turn, 0.0), np.where(turning, k2_turn, 0.0)
    k_cols[:, 3] += k_turn
    k2_cols[:, 3] += k2_turn
    # rows 0, 2, 3 of the tables, each one 2-d transposing copy (twice as fast as a 3-d one)
    table[:, 0, :12] = columns.reshape(12, count).T
    table[:, 1, 3:12:4] = (d * u + (0.0 if every else np.where(turning, 0.0, t_perp))).T
    table[:, 2, :12] = k_cols.reshape(12, count).T
    table[:, 3, :12] = k2_cols.reshape(12, count).T


class ScrewMotion(Motion):
    """The helical interpolants of pairs of poses (ScLERP)."""

    mode = "screw"
    what = "screw motion"

    def __init__(self, start, end, frame: ScrewFrame):
        super().__init__(start, end, frame)
        self.table = screw_tables(frame, start)

    @cached_property
    def quat_ends(self) -> np.ndarray:
        """``S + (2, 4)``: ``p(t) = cos(tφ/2) pA + sin(tφ/2) u pA``, so the "ends" of this path
        are pA and u pA (made when asked for: sampling matrices does not need them)."""
        frame = self.frame
        ends = np.empty(self.shape + (2, 4))
        ends[..., 0, :] = frame.p_start
        ends[..., 1, :] = vector_form(AXIS_TIMES, frame.axis_direction, frame.p_start)
        return ends

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
        if t.size and float(np.maximum.reduce(np.abs(half), axis=None)) <= HALF_ANGLE_TAN:
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
        return out.transpose(tuple(range(1, out.ndim)) + (0,))

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
        if angle.size and float(np.maximum.reduce(np.abs(angle), axis=None)) <= HALF_TURN:
            # τ = tan(tφ/2): cos = 1 / √(1 + τ²) and sin = τ cos, where cos ≥ 0 (t ∈ [0, 1]
            # and φ ≤ π). One vectorised tan and four cheap passes take a quarter of the time
            # of cos and sin; both stay within 2.4e-16 of the exact values (5.6e-17 with cos
            # and sin), and the quaternion is normalised after.
            tau = np.tan(angle)
            cos = np.multiply(tau, tau)
            cos += 1.0
            np.sqrt(cos, out=cos)
            np.divide(1.0, cos, out=cos)
            half = np.stack([cos, np.multiply(tau, cos, out=tau)], axis=-1)
        else:
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

    description = "the screw motion (ScLERP), the baseline"
    transmission_form = "line"

    def transmission(self, omega: np.ndarray) -> np.ndarray | None:
        """The straight line ``z = d ω / φ``; None for a pure translation (φ = 0)."""
        phi, d = np.asarray(self.frame.phi), np.asarray(self.frame.d)
        if np.any(phi == 0.0):
            return None
        if self.shape:
            phi, d = phi[..., None], d[..., None]
        return d * np.asarray(omega, dtype=float) / phi

    def summary(self, angle_unit: str = "deg") -> str:
        pitch = self.describe()["pitch"]
        return "pure translation" if pitch is None else f"pitch = {number_text(pitch)} per rad"

    def pose_degree(self) -> str:
        return "not rational (trigonometric)"
