"""Cubic circular motions: straight lines in the extended matrix model, mapped by μ_[m] (sections 4, 5).

The fiber points ``A = ((1, RA) + Σ α_l f_l, ψA tA)`` and ``B = ((1, RB) + Σ β_l f_l, ψB tB)``
with ``ψA = 1 + a``, ``ψB = 1 + b`` span the line ``x(t) = (1−t) A + t B``; the pose at ``t`` is
``μ_m(x(t))``. Because ``M_m f_l = 0`` and ``M_m (1, R) = 4 (m·p) p`` (``docs/math.md``), the
rotation is that of ``p(t) = (1−t) wA pA + t wB pB`` with ``w = 4 m·p``, and α, β enter only
through ``a`` and ``b``.

Two frames:

* ``canonical`` (default): the construction in canonical coordinates (A = I, B a screw about z),
  moved back. The motion lies in the cylinder group of A and B (Theorem 2), eq. 17 and 18 hold,
  and only ``m0``, ``m3`` (of ``m`` in canonical coordinates), ``a`` and ``b`` matter.
* ``given``: eq. 12 applied literally in the user's coordinates (the outlook's construction).
  The translation is then the weighted linear interpolation
  ``((1−t) ψA tA + t ψB tB) / ((1−t) ψA + t ψB)`` and the motion is in general **not** in a
  cylinder group (erratum 3).

The canonical translation is evaluated without ever forming the change of frame, as

``t(t) = R_D(t) tA + [t wB ((1−t) wA c + t wB) t⊥ − t(1−t) wA wB (r⃗ × t⊥)] / Δ(t) + z(t) u``

with ``r = pB p̄A = (c, r⃗)``, ``Δ = |p(t)|²`` and ``z = t d ψB / ((1−t) ψA + t ψB)`` (eq. 18);
no term divides by ``sin(φ/2)``, so tiny rotation angles lose no accuracy.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import ParameterError, SingularMotionError
from ..extended import check_m, check_not_orthogonal, kernel_basis, paper_basis_degenerate
from ..frames import ScrewFrame
from ..names import FRAMES
from ..study import rotation_numerators
from ._rational import (
    EPS,
    FRAGILE_TOL,
    bern_elevate,
    bern_mul,
    bernstein_basis,
    check_quaternion_path,
    linear_root,
    make_table,
    quaternion_path_minimum,
)

#: Relative sensitivity to rounding of the input above which a canonical cubic motion warns.
SENSITIVITY_WARNING = 1e-9
from .base import Motion, _vec, linear_path


def default_m(frame: ScrewFrame, which: str) -> np.ndarray:
    """``m = pA + pB``: ``(1 + cos(φ/2), 0, 0, sin(φ/2))`` in canonical coordinates (``docs/math.md``)."""
    if which == "canonical":
        return np.array([1.0 + frame.r[0], 0.0, 0.0, float(np.linalg.norm(frame.r[1:]))])
    return frame.p_start + frame.p_end


def _psi(m, coeffs, scalar, name: str, letter: str) -> float:
    if coeffs is not None and scalar is not None:
        raise ParameterError(f"give either {name} or {letter}, not both")
    if scalar is not None:
        value = float(scalar)
        if not math.isfinite(value):
            raise ParameterError(f"{letter} must be finite, got {value}")
        return 1.0 + value
    if coeffs is None:
        return 1.0
    arr = np.asarray(coeffs, dtype=float)
    if arr.shape != (6,):
        raise ParameterError(
            f"{name} needs 6 numbers (coefficients of f0 … f5), got shape {arr.shape}"
        )
    if not np.all(np.isfinite(arr)):
        raise ParameterError(f"{name} contains NaN or infinity")
    if paper_basis_degenerate(m):
        raise ParameterError(
            f"{name} is given in the paper's kernel basis f0 … f5 (eq. 13), which degenerates for "
            f"m = {np.asarray(m).tolist()} (n0 = 4 m0 m1 m2 m3 = 0, every f_l[0] = 0); "
            f"choose an m with all four components non-zero, or give {letter} directly"
        )
    basis, _ = kernel_basis(m, "paper")
    return 1.0 + float(arr @ basis[:, 0])


class CubicMotion(Motion):
    """A cubic circular motion between two poses (Theorem 2).

    Parameters
    ----------
    start, end : ndarray (4, 4)
    frame : ScrewFrame
    m : array_like (4,), optional
        The parameter of μ_[m], in canonical coordinates for ``frame="canonical"``, in the
        given coordinates for ``frame="given"``. Default ``pA + pB``.
    alpha, beta : array_like (6,), optional
        Fiber coefficients in the paper's basis f0 … f5 for m (eq. 13); they matter only
        through ``a = Σ α_l f_l[0]`` and ``b = Σ β_l f_l[0]``. Note that the ``f_l`` are quartic
        in ``m``, so the effect of α depends on the scale of m.
    a, b : float, optional
        The essential scalars directly (instead of alpha, beta). Default 0.
    frame_name : {"canonical", "given"}
    """

    mode = "cubic"

    def __init__(
        self,
        start,
        end,
        frame: ScrewFrame,
        *,
        m=None,
        alpha=None,
        beta=None,
        a=None,
        b=None,
        frame_name: str = "canonical",
    ):
        super().__init__(start, end, frame)
        if frame_name not in FRAMES:
            raise ParameterError(f"unknown frame {frame_name!r}; expected one of {FRAMES}")
        self.frame_name = frame_name
        if m is None:
            m_arr = default_m(frame, frame_name)
            self.choices.append(
                f"m defaults to pA + pB in {frame_name} coordinates, so both weights are equal"
            )
        else:
            m_arr = check_m(m)
        self.m = m_arr
        self.psi_a = _psi(m_arr, alpha, a, "alpha", "a")
        self.psi_b = _psi(m_arr, beta, b, "beta", "b")
        r, p_a, p_b = frame.r, frame.p_start, frame.p_end
        c = float(r[0])
        s = float(np.linalg.norm(r[1:]))
        if frame_name == "canonical":
            p_a_can = np.array([1.0, 0.0, 0.0, 0.0])
            p_b_can = np.array([c, 0.0, 0.0, s])
            w_a = 4.0 * check_not_orthogonal(m_arr, p_a_can, "start pose (canonical coordinates)")
            w_b = 4.0 * check_not_orthogonal(m_arr, p_b_can, "end pose (canonical coordinates)")
        else:
            w_a = 4.0 * check_not_orthogonal(m_arr, p_a, "start pose")
            w_b = 4.0 * check_not_orthogonal(m_arr, p_b, "end pose")
        self.weights = (w_a, w_b)
        self._check_psi()
        pa_w, pb_w = w_a * p_a, w_b * p_b
        self._p = np.stack([pa_w, pb_w])
        rot = np.stack(
            [rotation_numerators(pa_w), rotation_numerators(pa_w, pb_w), rotation_numerators(pb_w)]
        )
        delta = np.array([pa_w @ pa_w, pa_w @ pb_w, pb_w @ pb_w])
        x0 = np.array([self.psi_a, self.psi_b])
        t_a = frame.t_start
        if frame_name == "given":
            t_b = frame.t_end
            trans_num = np.stack([self.psi_a * t_a, self.psi_b * t_b])
            trans = bern_elevate(trans_num, 3)
            trans_den = bern_elevate(x0, 3)
        else:
            rho_a = np.array([w_a, 0.0, 0.0, 0.0])
            rho_b = w_b * r
            n_rho = np.stack(
                [
                    rotation_numerators(rho_a),
                    rotation_numerators(rho_a, rho_b),
                    rotation_numerators(rho_b),
                ]
            )
            rotated_start = n_rho.reshape(3, 3, 3) @ t_a
            t_perp = frame.t_perp
            cross = np.cross(r[1:], t_perp)
            n_disp = np.stack(
                [np.zeros(3), 0.5 * w_a * w_b * (c * t_perp - cross), w_b * w_b * t_perp]
            )
            first = bern_mul(rotated_start + n_disp, x0)  # over Δ · x0
            z_num = np.stack([np.zeros(3), frame.d * self.psi_b * frame.axis_direction])  # t d ψB u
            second = bern_mul(z_num, delta)
            trans = first + second
            trans_den = bern_mul(delta, x0)
        self.table = make_table(bern_elevate(rot, 3), bern_elevate(delta, 3), trans, trans_den)
        self._check_interval(0.0, 1.0)
        if frame_name == "canonical":
            self._check_axis_sensitivity(s)

    def _check_axis_sensitivity(self, s: float) -> None:
        """Warn when a nearly pure translation makes the canonical motion depend on rounding.

        For small φ the canonical cubic moves the part ``t⊥`` of the displacement across the
        screw axis with the rotation's profile ``f(t) = t wB / ((1−t) wA + t wB)`` and the slide
        ``d u`` with eq. 18's ``g(t) = t ψB / ((1−t) ψA + t ψB)``. The axis of float64 input is
        known to about ``ε / sin(φ/2)``, so the poses move by about
        ``ε / sin(φ/2) · max |f − g|`` of the motion's size. (With the defaults f = g.)
        """
        if s == 0.0:
            return
        w_a, w_b = self.weights
        ts = np.linspace(0.0, 1.0, 101)
        with np.errstate(divide="ignore", invalid="ignore"):
            f = ts * w_b / ((1 - ts) * w_a + ts * w_b)
            g = ts * self.psi_b / ((1 - ts) * self.psi_a + ts * self.psi_b)
        diff = np.abs(f - g)
        spread = float(np.max(diff[np.isfinite(diff)], initial=0.0))
        estimate = EPS / s * spread
        if estimate > SENSITIVITY_WARNING:
            self._warn(
                f"the rotation angle φ = {self.frame.phi:.3g} is so small that the screw axis is "
                f"ill-determined, and with wB/wA ≠ ψB/ψA the canonical cubic motion depends on it: "
                f"its poses change by about {estimate:.1g} of the motion's size under rounding of "
                "the input (the defaults m = pA + pB, a = b = 0, or frame given, avoid this)"
            )

    def _check_psi(self):
        root = linear_root(self.psi_a, self.psi_b)
        if self.psi_a * self.psi_b <= 0.0:
            where = "every t" if (self.psi_a == 0.0 and self.psi_b == 0.0) else f"t = {root:.6g}"
            raise SingularMotionError(
                f"the cubic motion passes through infinity at {where}: ψA = 1 + a = {self.psi_a:.6g} and "
                f"ψB = 1 + b = {self.psi_b:.6g} need the same sign (x0(t) = (1−t) ψA + t ψB vanishes)"
            )

    def _basis(self, ts):
        return bernstein_basis(ts, 3)

    def _quats(self, ts):
        return linear_path(ts, self._p)

    def _rotation_is_fragile(self, lo, hi):
        return quaternion_path_minimum(self._p[0], self._p[1], lo, hi)[1] < FRAGILE_TOL

    def _check_interval(self, lo, hi):
        root = linear_root(self.psi_a, self.psi_b)
        if root is not None and lo <= root <= hi:
            raise SingularMotionError(
                f"the cubic motion passes through infinity at t = {root:.6g} (x0(t) = 0), inside the "
                f"sampled range [{lo:.6g}, {hi:.6g}]"
            )
        check_quaternion_path(self._p[0], self._p[1], lo, hi, "cubic motion", warn=self._warn)

    def singular_t(self):
        root = linear_root(self.psi_a, self.psi_b)
        return [] if root is None else [root]

    def canonical_m(self) -> tuple[float, float]:
        """``(m0, m3)`` in canonical coordinates that give this motion's rotation (eq. 17).

        For ``frame="canonical"`` these are the user's; for ``"given"`` they are the canonical
        parameters with the same weights ``wA, wB`` (the rotation is the same; the translation
        is not).
        """
        if self.frame_name == "canonical":
            return float(self.m[0]), float(self.m[3])
        w_a, w_b = self.weights
        c = float(self.frame.r[0])
        s = float(np.linalg.norm(self.frame.r[1:]))
        m0 = w_a / 4
        m3 = (w_b / 4 - m0 * c) / s if s > 0 else 0.0
        return m0, m3

    def tan_half_omega(self, ts: np.ndarray) -> np.ndarray:
        """Eq. 17 with the canonical ``m0, m3``."""
        m0, m3 = self.canonical_m()
        phi = self.frame.phi
        t = np.asarray(ts, dtype=float)
        return -((m3 * (math.cos(phi) - 1) - m0 * math.sin(phi)) * t) / (
            (m0 * (math.cos(phi) - 1) + m3 * math.sin(phi)) * t + 2 * m0
        )

    def z_of_t(self, ts: np.ndarray) -> np.ndarray:
        """Eq. 18: ``z = t d (1 + b) / ((1−t)(1 + a) + t(1 + b))``."""
        t = np.asarray(ts, dtype=float)
        return t * self.frame.d * self.psi_b / ((1 - t) * self.psi_a + t * self.psi_b)

    def _describe(self):
        m0, m3 = self.canonical_m()
        basis_name = "paper" if not paper_basis_degenerate(self.m) else "paper (degenerate: n0 = 0)"
        return {
            "frame": self.frame_name,
            "m": _vec(self.m),
            "m0": m0,
            "m3": m3,
            "a": self.psi_a - 1.0,
            "b": self.psi_b - 1.0,
            "psi_start": self.psi_a,
            "psi_end": self.psi_b,
            "weights": [float(w) for w in self.weights],
            "kernel_basis": basis_name,
            "in_cylinder_group": self.frame_name == "canonical" or self.frame.phi == 0.0,
            "transmission_curve": "tan(omega/2) by eq. 17, z = t d (1+b) / ((1-t)(1+a) + t(1+b)) (eq. 18)",
        }
