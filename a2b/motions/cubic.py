"""Cubic circular motions: straight lines in the extended matrix model, mapped by μ_[m] (sections 4,
5).

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

from ..elements import as_numbers, everywhere, refuse, value
from ..errors import ParameterError, SingularMotionError
from ..extended import check_m, paper_basis_degenerate, paper_kernel_basis, refuse_orthogonal
from ..frames import ScrewFrame
from ..names import FRAMES
from ..study import (
    CROSS,
    MATRIX_VECTOR,
    ROTATION,
    bilinear,
    dots,
    rotation_numerators,
    structure_matrix,
)
from ._rational import (
    CHUNK,
    EPS,
    bern_mul,
    bernstein_basis,
    bernstein_derivatives,
    quadratic_rows,
)
from .base import Motion, _vec, broadcast_parameter, linear_root
from .text import number_text

#: Relative sensitivity to rounding of the input above which a canonical cubic motion warns.
SENSITIVITY_WARNING = 1e-9


#: ``(t, r) ↦ B(1, r) t``: eq. 4's symmetric bilinear form of the quaternion 1 and ``r``
#: (:func:`a2b.study.rotation_numerators`), a 3x3 matrix, times the vector ``t``. Of ``tA`` and
#: ``wA wB r``, it is the middle Bernstein coefficient of ``R_D(t) Δ(t) tA``
#: (:func:`_translation_factors`).
_MIDDLE_TURN = structure_matrix(
    lambda t, r: (
        rotation_numerators(np.broadcast_to([1.0, 0.0, 0.0, 0.0], r.shape), r).reshape(-1, 3, 3)
        @ t[..., None]
    )[..., 0],
    3,
    4,
)


def default_m(frame: ScrewFrame, which: str, s=None) -> np.ndarray:
    """``m = pA + pB``: ``(1 + cos(φ/2), 0, 0, sin(φ/2))`` in canonical coordinates
    (``docs/math.md``); ``s`` is ``sin(φ/2) = |r⃗|`` where the caller has it. Shape ``S + (4,)``,
    a view of components ``(4,) + S``."""
    if which == "canonical":
        r = np.asarray(frame.r)
        out = np.zeros((4,) + r.shape[:-1])
        out[0] = 1.0 + r[..., 0]
        out[3] = np.linalg.norm(r[..., 1:], axis=-1) if s is None else s
        return _last(out)
    return np.asarray(frame.p_start) + frame.p_end


def _last(x: np.ndarray) -> np.ndarray:
    """Components first, ``(k,) + S``, as a view ``S + (k,)`` (components last)."""
    return x.reshape(len(x), -1).T.reshape(x.shape[1:] + x.shape[:1])


#: The smallest ratio ``min(|wA|, |wB|) / max(|wA|, |wB|)`` for which :func:`_bounded_away`
#: holds: then ``|p(t)|² / max|p|² ≥ 0.15² / (1 + 0.15²) > 0.022``, more than twice the
#: largest tolerance of the singularity checks (``FRAGILE_TOL = 1e-2``).
WEIGHT_RATIO = 0.15


def _bounded_away(weights: np.ndarray, c) -> bool:
    """Whether every ``p(t) = (1−t) wA pA + t wB pB`` (weights ``(2, J)``, unit ``pA``, ``pB``
    with ``c = pA·pB``, ``(J,)``) keeps ``|p(t)|² / max(wA², wB²) > 2 FRAGILE_TOL`` on [0, 1].

    ``|p(t)|² = (1−t)² wA² + t² wB² + 2t(1−t) wA wB c``: where ``wA wB c ≥ 0`` it is at least
    ``wA² wB² / (wA² + wB²)``, which is ``q² / (1 + q²)`` of ``max(wA², wB²)`` for
    ``q = min(|wA|, |wB|) / max(|wA|, |wB|)`` (``docs/math.md``). The default ``m`` has
    ``wA = wB``: ``|p(t)|² / wA² ≥ ½``, as for a Darboux motion the short way round.
    """
    w_a, w_b = np.abs(weights[0]), np.abs(weights[1])
    same_side = weights[0] * weights[1] * c >= 0.0
    return everywhere(same_side & (np.minimum(w_a, w_b) >= WEIGHT_RATIO * np.maximum(w_a, w_b)))


def _psi(m, coeffs, scalar, name: str, letter: str, shape: tuple) -> np.ndarray:
    """``ψ = 1 + a`` from the scalar, or from fiber coefficients in the paper's basis."""
    if coeffs is not None and scalar is not None:
        raise ParameterError(f"give either {name} or {letter}, not both")
    if scalar is not None:
        return 1.0 + broadcast_parameter(scalar, shape, letter)
    if coeffs is None:
        return np.ones(shape)
    arr = as_numbers(coeffs, name)
    if arr.shape[-1:] != (6,):
        raise ParameterError(
            f"{name} needs 6 numbers (coefficients of f0 … f5), got shape {arr.shape}"
        )
    if not np.all(np.isfinite(arr)):
        raise ParameterError(f"{name} contains NaN or infinity")
    flat_m = np.broadcast_to(m, shape + (4,)).reshape(-1, 4)
    refuse(
        ParameterError,
        paper_basis_degenerate(m),
        lambda i: (
            f"{name} is given in the paper's kernel basis f0 … f5 (eq. 13), which degenerates "
            f"for m = {flat_m[i].tolist()} (n0 = 4 m0 m1 m2 m3 = 0, every f_l[0] = 0); "
            f"choose an m with all four components non-zero, or give {letter} directly"
        ),
        shape,
    )
    coefficients = broadcast_parameter(arr, shape, name, 6)
    return 1.0 + np.sum(coefficients * paper_kernel_basis(m)[..., 0], axis=-1)


def cubic_tables(frame: ScrewFrame, weights, psi, given: bool) -> tuple:
    """``p(t)``'s ends ``S + (2, 4)`` and the Bernstein tables ``S + (4, 14)`` of cubic motions
    with the weights ``wA, wB`` and ``ψA, ψB`` (components first, ``(2, J)`` each): the
    rotation of ``p(t) = (1−t) wA pA + t wB pB`` (degree 2, raised to 3) and the translation of
    eq. 12 over ``Δ · x0`` (canonical frame, ``given`` false) or ``x0`` (given frame).

    Component-major: the numbers of the pairs are read as ``(k, J)`` views of the screw
    frame's arrays, the ends are ``(4, 2, J)`` (returned as a view, as Darboux motions' are),
    and each chunk of :data:`CHUNK` pairs is built in work arrays that every chunk reuses
    (:class:`_Work`) and written into the table by one transposing copy.
    """
    count = weights.shape[1]
    ends = np.empty((4, 2, count))  # p(t)'s: components, A and B, pairs
    np.multiply(_rows(frame.p_start, 4, count), weights[0], out=ends[:, 0])
    np.multiply(_rows(frame.p_end, 4, count), weights[1], out=ends[:, 1])
    inputs = [ends, weights, psi, _rows(frame.t_start, 3, count)]
    if given:
        inputs.append(_rows(frame.t_end, 3, count))
    else:
        d_psi = np.asarray(frame.d).reshape(count) * psi[1]
        slide = d_psi * _rows(frame.axis_direction, 3, count)  # d ψB u
        inputs += [_rows(frame.r, 4, count), _rows(frame.t_perp, 3, count), slide]
    table = np.empty((count, 4, 14))
    work = _Work(min(count, CHUNK), given)
    for lo in range(0, count, CHUNK):
        hi = min(lo + CHUNK, count)
        _cubic_chunk([x[..., lo:hi] for x in inputs], work, table[lo:hi])
    quat_ends = ends.transpose(2, 1, 0).reshape(frame.shape + (2, 4))  # a view, as the table's
    return quat_ends, table.reshape(frame.shape + (4, 14))


def _rows(field, width: int, count: int) -> np.ndarray:
    """A frame's field ``S + (width,)`` as components ``(width, J)``: for a batch, a view of
    the component-major array that :func:`a2b.frames.screw_frame` made."""
    return np.asarray(field).reshape(count, width).T


class _Work:
    """The work arrays of :func:`_cubic_chunk` for chunks of up to ``n`` pairs, made once per
    build with their constant entries: the two factors of the table's Bernstein product,
    ``(3, width, n)`` and ``(2, width, n)``.

    Their rows are ``n + 8`` doubles long: rows exactly 4,096 doubles (32 KiB) apart fall into
    the same cache sets, and the transposing copy into the table ran four times slower.
    """

    def __init__(self, n: int, given: bool):
        row = n + 8
        width = 14 if given else 17  # the table's columns (and the canonical slide's three)
        self.first = np.zeros((3, width, row))
        self.second = np.zeros((2, width, row))
        #: eq. 4's rows in the table's columns, (coefficient, row, column, pairs)
        self.rotation = self.first[:, :12].reshape(3, 3, 4, row)[:, :, :3]
        self.second[:, :12].reshape(2, 3, 4, row)[:, :, :3] = 1.0  # rotation and Δ by 1
        self.second[:, 12] = 1.0
        if given:
            self.first[:, 3:14:4] = 1.0  # 1 · (ψ t) over 1 · x0
            self.first[:, 13] = 1.0


def _cubic_chunk(inputs: list, work: _Work, table: np.ndarray):
    """:func:`cubic_tables` of one chunk of ``n`` pairs: ``inputs`` ``(..., n)`` as gathered
    there, written into its ``table`` ``(n, 4, 14)``.

    The whole table is one Bernstein product of degree 2 by 1 (:func:`bern_mul`), column by
    column in the table's order: the rotation rows of ``p(t)`` and Δ by the constant 1 (which
    raises them to degree 3), and the translation's numerators by their second factor
    (:func:`_translation_factors`). Where ``x0`` is constant 1 (``a = b = 0``), the canonical
    translation's denominator ``Δ · x0`` is then the rotation's to the bit, and sampling
    divides by one denominator instead of two.
    """
    n = table.shape[0]
    rows = quadratic_rows(inputs[0])  # (10, 3, n)
    work.rotation[..., :n] = rows[:9].reshape(3, 3, 3, n).transpose(2, 0, 1, 3)
    first, second = work.first[..., :n], work.second[..., :n]
    first[:, 12] = rows[9]  # Δ
    _translation_factors(inputs, rows, first, second)
    # over the whole rows (the tail holds finite numbers of an earlier chunk, or zeros), so
    # that the product's rows are as far apart as the work arrays'
    out = bern_mul(work.first, work.second)[..., :n]  # (4, width, n)
    if out.shape[1] > 14:  # the canonical slide
        out[:, 3:12:4] += out[:, 14:]
    table[...] = out[:, :14].transpose(2, 0, 1)


def _translation_factors(inputs: list, rows, first, second) -> None:
    """The factors of the translation's columns (3, 7, 11: numerators, 13: denominator) in
    ``first`` (degree 2) and ``second`` (degree 1), and those of the canonical slide (14 to
    16).

    Given frame: ``1 · (ψ t)`` over ``1 · x0``, the rational linear interpolation
    ``((1−t) ψA tA + t ψB tB) / ((1−t) ψA + t ψB)``. Canonical frame: the numerators over
    Δ, ``R_D(t) Δ(t) tA`` and the part across the axis, times ``x0``, plus Δ times the slide
    ``t d ψB u`` (module docstring), over ``Δ · x0``. ``R_D(t) Δ(t)`` are the rows of
    ``ρ(t) = p(t) p̄A = (1−t) wA + t wB r``, whose Bernstein coefficients are ``wA² I``,
    ``B(wA, wB r)`` and ``B(wB r, wB r)`` (eq. 4): the first two act on ``tA`` as a scaling
    and as :data:`_MIDDLE_TURN`.
    """
    weights, psi, t_a = inputs[1:4]
    if len(inputs) == 5:  # the given frame
        np.multiply(t_a, psi[0], out=second[0, 3:12:4])
        np.multiply(inputs[4], psi[1], out=second[1, 3:12:4])
        second[:, 13] = psi
        return
    r, t_perp, slide = inputs[4:]
    turned = first[:, 3:12:4]  # R_D(t) Δ(t) tA, then the part across the axis
    rho_b = r * weights[1]
    np.multiply(weights[0] * weights[0], t_a, out=turned[0])
    turned[1] = bilinear(_MIDDLE_TURN, t_a, weights[0] * rho_b)
    turned[2] = bilinear(MATRIX_VECTOR, bilinear(ROTATION, rho_b, rho_b)[:9], t_a)
    r_cross_t = bilinear(CROSS, r[1:], t_perp)
    turned[1] += 0.5 * weights[0] * weights[1] * (r[0] * t_perp - r_cross_t)
    turned[2] += weights[1] * weights[1] * t_perp
    first[:, 13:] = rows[9, :, None]  # Δ
    second[:, 3:14:4] = psi[:, None]  # x0
    second[:, 13] = psi
    second[1, 14:] = slide  # t d ψB u


class CubicMotion(Motion):
    """Cubic circular motions between pairs of poses (Theorem 2).

    Parameters
    ----------
    start, end : ndarray, shape S + (4, 4)
    frame : ScrewFrame
    m : array_like, shape (..., 4), optional
        The parameter of μ_[m], in canonical coordinates for ``frame="canonical"``, in the
        given coordinates for ``frame="given"``. Default ``pA + pB``.
    alpha, beta : array_like, shape (..., 6), optional
        Fiber coefficients in the paper's basis f0 … f5 for m (eq. 13); they matter only
        through ``a = Σ α_l f_l[0]`` and ``b = Σ β_l f_l[0]``. Note that the ``f_l`` are quartic
        in ``m``, so the effect of α depends on the scale of m.
    a, b : float or array_like, optional
        The essential scalars directly (instead of alpha, beta). Default 0.
    frame_name : {"canonical", "given"}
    """

    mode = "cubic"
    what = "cubic motion"

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
        shape = self.shape
        self.frame_name = frame_name
        r = np.asarray(frame.r)
        s = np.sqrt(dots(r[..., 1:], r[..., 1:]))  # |r⃗| = sin(φ/2), as numpy.linalg.norm sums
        if m is None:
            m_arr = self.m = default_m(frame, frame_name, s)
            self.notes.add(
                f"m defaults to pA + pB in {frame_name} coordinates, so both weights are equal"
            )
        else:
            m_arr = check_m(m)
            try:
                m_arr = np.broadcast_to(m_arr, shape + (4,))
            except ValueError:
                raise ParameterError(
                    f"m of shape {m_arr.shape} does not broadcast against the poses' shape {shape}"
                ) from None
            self.m = np.array(m_arr, dtype=float)
        psi = np.empty((2,) + shape)  # ψA, ψB: components first, as the weights
        psi[0] = _psi(m_arr, alpha, a, "alpha", "a", shape)
        psi[1] = _psi(m_arr, beta, b, "beta", "b", shape)
        self.psi_a, self.psi_b = psi
        weights = self._weights(m_arr, r[..., 0], s)  # (2, J)
        self.weights = weights.T.reshape(shape + (2,))
        root = linear_root(self.psi_a, self.psi_b)
        self._check_psi(root)
        self.quat_ends, self.table = cubic_tables(
            frame, weights, psi.reshape(2, -1), frame_name == "given"
        )
        self._bounded = _bounded_away(weights, r[..., 0].reshape(-1))
        self._check_interval(0.0, 1.0, root)
        if frame_name == "canonical":
            self._check_axis_sensitivity(s)
        if not shape:
            self.psi_a, self.psi_b = self.psi_a[()], self.psi_b[()]

    def _weights(self, m_arr, c, s) -> np.ndarray:
        """``4 (m·pA)`` and ``4 (m·pB)``, components first ``(2, J)``, in the motion's frame
        (refused where 0)."""
        shape = self.shape
        count = math.prod(shape)
        quats = np.zeros((2, 4) + shape)  # A and B, components
        if self.frame_name == "canonical":  # pA = 1 and pB = (c, 0, 0, s)
            quats[0, 0] = 1.0
            quats[1, 0] = c
            quats[1, 3] = s
            where = " (canonical coordinates)"
        else:
            quats[0] = _rows(self.frame.p_start, 4, count).reshape((4,) + shape)
            quats[1] = _rows(self.frame.p_end, 4, count).reshape((4,) + shape)
            where = ""
        dot = dots(m_arr[..., None, :], quats.reshape(8, count).T.reshape(shape + (2, 4)))
        refuse_orthogonal(m_arr, dot, ("start pose" + where, "end pose" + where))
        weights = np.empty((2, count))
        np.multiply(dot.reshape(count, 2).T, 4.0, out=weights)
        return weights

    def _check_axis_sensitivity(self, s) -> None:
        """Warn when a nearly pure translation makes the canonical motion depend on rounding.

        For small φ the canonical cubic moves the part ``t⊥`` of the displacement across the
        screw axis with the rotation's profile ``f(t) = t wB / ((1−t) wA + t wB)`` and the slide
        ``d u`` with eq. 18's ``g(t) = t ψB / ((1−t) ψA + t ψB)``. The axis of float64 input is
        known to about ``ε / sin(φ/2)``, so the poses move by about
        ``ε / sin(φ/2) · max |f − g|`` of the motion's size. (With the defaults f = g.)
        """
        # Only where ε / sin(φ/2) is large, or where a weight changes sign (f unbounded), can
        # the estimate pass the threshold: the spread of two maps of [0, 1] onto [0, 1] is ≤ 1.
        w_a, w_b = self.weights[..., 0], self.weights[..., 1]
        with np.errstate(divide="ignore"):
            candidates = (EPS / s > SENSITIVITY_WARNING) | (w_a * w_b <= 0)
        if not candidates.any():
            return
        estimate = np.zeros(self.shape)
        pick = (lambda x: x) if not self.shape else (lambda x: np.asarray(x)[candidates])
        w_a, w_b, s_c = pick(w_a)[..., None], pick(w_b)[..., None], pick(s)
        psi_a = pick(self.psi_a)[..., None]
        psi_b = pick(self.psi_b)[..., None]
        ts = np.linspace(0.0, 1.0, 101)
        with np.errstate(divide="ignore", invalid="ignore"):
            f = ts * w_b / ((1 - ts) * w_a + ts * w_b)
            g = ts * psi_b / ((1 - ts) * psi_a + ts * psi_b)
            diff = np.abs(f - g)
            spread = np.max(np.where(np.isfinite(diff), diff, 0.0), axis=-1, initial=0.0)
            found = np.where(s_c == 0.0, 0.0, EPS / np.where(s_c == 0.0, 1.0, s_c) * spread)
        if self.shape:
            estimate[candidates] = found
        else:
            estimate = found
        self._warn(
            estimate > SENSITIVITY_WARNING,
            lambda i: (
                f"the rotation angle φ = {value(self.frame.phi, i):.3g} is so small that the "
                "screw axis is ill-determined, and with wB/wA ≠ ψB/ψA the canonical cubic motion "
                f"depends on it: its poses change by about {value(estimate, i):.1g} of the "
                "motion's size under rounding of the input (the defaults m = pA + pB, a = b = 0, "
                "or frame given, avoid this)"
            ),
        )

    def _check_psi(self, root):
        self._refuse(
            SingularMotionError,
            self.psi_a * self.psi_b <= 0.0,
            lambda i: (
                "the cubic motion passes through infinity at "
                + (
                    "every t"
                    if value(self.psi_a, i) == 0.0 and value(self.psi_b, i) == 0.0
                    else f"t = {value(root, i):.6g}"
                )
                + f": ψA = 1 + a = {value(self.psi_a, i):.6g} and ψB = 1 + b = "
                f"{value(self.psi_b, i):.6g} need the same sign (x0(t) = (1−t) ψA + t ψB vanishes)"
            ),
        )

    def _basis(self, ts):
        return bernstein_basis(ts, 3)

    def _basis_derivatives(self, ts, order):
        return bernstein_derivatives(ts, 3, order)

    def _check_interval(self, lo, hi, root=None):
        if root is None:
            root = linear_root(self.psi_a, self.psi_b)
        self._refuse(
            SingularMotionError,
            (lo <= root) & (root <= hi),
            lambda i: (
                f"the cubic motion passes through infinity at t = {value(root, i):.6g} "
                f"(x0(t) = 0), inside the sampled range [{lo:.6g}, {hi:.6g}]"
            ),
        )
        if not self._bounded_on(lo, hi):
            self._check_path(lo, hi)

    def _bounded_on(self, lo: float, hi: float) -> bool:
        """Whether ``[lo, hi]`` is ``[0, 1]`` and :func:`_bounded_away` holds for every motion:
        then ``|p(t)|²`` stays above every tolerance of the singularity checks, which have
        nothing to find."""
        return lo == 0.0 and hi == 1.0 and self._bounded

    def _rotation_is_fragile(self, lo, hi):
        if self._bounded_on(lo, hi):
            return np.zeros(self.shape, dtype=bool)
        return super()._rotation_is_fragile(lo, hi)

    def singular_t(self):
        root = float(linear_root(self.psi_a, self.psi_b))
        return [] if np.isnan(root) else [root]

    def canonical_m(self) -> tuple:
        """``(m0, m3)`` in canonical coordinates that give this motion's rotation (eq. 17).

        For ``frame="canonical"`` these are the user's; for ``"given"`` they are the canonical
        parameters with the same weights ``wA, wB`` (the rotation is the same; the translation
        is not).
        """
        if self.frame_name == "canonical":
            return self.m[..., 0][()], self.m[..., 3][()]
        w_a, w_b = self.weights[..., 0], self.weights[..., 1]
        c = np.asarray(self.frame.r)[..., 0]
        s = np.linalg.norm(np.asarray(self.frame.r)[..., 1:], axis=-1)
        m0 = w_a / 4
        m3 = np.where(s > 0, (w_b / 4 - m0 * c) / np.where(s > 0, s, 1.0), 0.0)
        return m0[()], m3[()]

    def tan_half_omega(self, ts: np.ndarray) -> np.ndarray:
        """Eq. 17 with the canonical ``m0, m3``."""
        m0, m3 = (np.asarray(x)[..., None] if self.shape else x for x in self.canonical_m())
        phi = np.asarray(self.frame.phi)
        phi = phi[..., None] if self.shape else phi
        t = np.asarray(ts, dtype=float)
        return -((m3 * (np.cos(phi) - 1) - m0 * np.sin(phi)) * t) / (
            (m0 * (np.cos(phi) - 1) + m3 * np.sin(phi)) * t + 2 * m0
        )

    def z_of_t(self, ts: np.ndarray) -> np.ndarray:
        """Eq. 18: ``z = t d (1 + b) / ((1−t)(1 + a) + t(1 + b))``."""
        d, psi_a, psi_b = (np.asarray(x) for x in (self.frame.d, self.psi_a, self.psi_b))
        if self.shape:
            d, psi_a, psi_b = d[..., None], psi_a[..., None], psi_b[..., None]
        t = np.asarray(ts, dtype=float)
        return t * d * psi_b / ((1 - t) * psi_a + t * psi_b)

    def _describe(self):
        m0, m3 = self.canonical_m()
        degenerate = paper_basis_degenerate(self.m)
        return {
            "frame": self.frame_name,
            "m": _vec(self.m),
            "m0": float(m0),
            "m3": float(m3),
            "a": float(self.psi_a - 1.0),
            "b": float(self.psi_b - 1.0),
            "psi_start": float(self.psi_a),
            "psi_end": float(self.psi_b),
            "weights": [float(w) for w in self.weights],
            "kernel_basis": "paper (degenerate: n0 = 0)" if degenerate else "paper",
            "in_cylinder_group": bool(self.frame_name == "canonical" or self.frame.phi == 0.0),
            "transmission_curve": (
                "tan(omega/2) by eq. 17, z = t d (1+b) / ((1-t)(1+a) + t(1+b)) (eq. 18)"
            ),
        }

    description = "the cubic circular motion (a line in the extended matrix model, by μ_[m])"
    transmission_form = "tangent"
    family_kinds = ("ab", "m")

    @classmethod
    def from_parameters(cls, start, end, frame: ScrewFrame, params: dict) -> CubicMotion:
        frame_name = params.pop("frame", "canonical")
        return cls(start, end, frame, frame_name=frame_name, **params)

    def transmission(self, omega: np.ndarray) -> np.ndarray | None:
        """Eq. 17 solved for t and put into eq. 18, a scaled and shifted tangent:

        .. math:: t = \\frac{−2 m_0 \\sin\\frac ω2}{Q \\sin\\frac ω2 + P \\cos\\frac ω2},\\quad
                  z = \\frac{t d (1 + b)}{(1 − t)(1 + a) + t (1 + b)}

        where ``P = m3 (cos φ − 1) − m0 sin φ`` and ``Q = m0 (cos φ − 1) + m3 sin φ``; NaN where
        the tangent has its pole. None in the given frame (not in a cylinder group). One motion.
        """
        if self.frame_name != "canonical":
            return None
        m0, m3 = self.canonical_m()
        phi = float(self.frame.phi)
        p = m3 * (math.cos(phi) - 1) - m0 * math.sin(phi)
        q = m0 * (math.cos(phi) - 1) + m3 * math.sin(phi)
        omega = np.asarray(omega, dtype=float)
        sin_h, cos_h = np.sin(omega / 2), np.cos(omega / 2)
        with np.errstate(divide="ignore", invalid="ignore"):
            t = -2 * m0 * sin_h / (q * sin_h + p * cos_h)
            z = self.z_of_t(t)
        return np.where(np.isfinite(z), z, np.nan)

    def family(self, kind: str, side: int) -> tuple[str, list, float]:
        """``"ab"``: the ratio ``(1 + b) / (1 + a)`` with a fixed, which alone decides z(t)
        (eq. 18); ``"m"``: the ratio ``m3 : m0`` through ``wB / wA``, which decides ω(t)
        (eq. 17). Both step by factors of 2."""
        if self.frame_name != "canonical":
            raise ParameterError(
                "a cubic motion in the given frame is not in a cylinder group and has no "
                "transmission curve"
            )
        a, steps = self.psi_a - 1.0, [2.0**k for k in range(-side, side + 1)]
        if kind == "ab":
            chosen = self.psi_b / self.psi_a
            members = [(chosen * f, {"m": self.m, "a": a, "b": self.psi_a * chosen * f - 1.0})
                       for f in steps]  # fmt: skip
            return "(1+b)/(1+a)", members, chosen
        m0, m3 = self.canonical_m()
        c = float(self.frame.r[0])
        s = float(np.linalg.norm(self.frame.r[1:]))
        ratio = (m0 * c + m3 * s) / m0  # wB / wA
        members = []
        for f in steps:
            m = np.array(self.m, dtype=float)
            m[3] = m0 * (ratio * f - c) / s
            members.append((m[3] / m0, {"m": m, "a": a, "b": self.psi_b - 1.0}))
        return "m3/m0", members, m3 / m0

    def summary(self, angle_unit: str = "deg") -> str:
        info = self.describe()
        text = (
            f"m0:m3 = {number_text(info['m0'])}:{number_text(info['m3'])}, "
            f"a = {number_text(info['a'])}, b = {number_text(info['b'])}"
        )
        return text + (", given frame" if info["frame"] == "given" else "")
