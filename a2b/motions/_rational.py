"""Sampling motions from precomputed coefficients.

Every motion of a2b is written as ``basis(t) @ table``: a small ``(k, 14)`` coefficient table
times ``k`` basis functions of ``t``. The 14 columns are the twelve numerators of the 3x4 block
``[R | t]`` row by row, the denominator of the rotation entries and the denominator of the
translation entries. Darboux and cubic motions are rational, so the basis is Bernstein's (the
end poses are then the first and last coefficients, reproduced exactly); the screw motion uses
``(1, t, sin tφ, 2 sin²(tφ/2))``.

Sampling is one matrix product and two divisions per sample, with no Python loop.
"""

from __future__ import annotations

from math import comb

import numpy as np

from ..errors import SingularMotionError

ROT_COLS = (0, 1, 2, 4, 5, 6, 8, 9, 10)
TRANS_COLS = (3, 7, 11)


def bernstein_basis(ts: np.ndarray, degree: int) -> np.ndarray:
    """Bernstein polynomials ``C(n, i) (1−t)^(n−i) t^i``, shape ``(len(ts), degree + 1)``."""
    t = np.asarray(ts, dtype=float)
    u = 1.0 - t
    if degree == 1:
        return np.stack([u, t], axis=-1)
    if degree == 2:
        return np.stack([u * u, 2.0 * u * t, t * t], axis=-1)
    if degree == 3:
        uu, tt = u * u, t * t
        return np.stack([uu * u, 3.0 * uu * t, 3.0 * u * tt, tt * t], axis=-1)
    return np.stack([comb(degree, i) * u ** (degree - i) * t**i for i in range(degree + 1)], axis=-1)


def bern_mul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Product of Bernstein-form polynomials; coefficients on axis 0, broadcasting the rest."""
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    m, n = a.shape[0] - 1, b.shape[0] - 1
    shape = np.broadcast_shapes(a.shape[1:], b.shape[1:])
    out = np.zeros((m + n + 1,) + shape)
    for i in range(m + 1):
        for j in range(n + 1):
            out[i + j] += comb(m, i) * comb(n, j) / comb(m + n, i + j) * a[i] * b[j]
    return out


def bern_elevate(a: np.ndarray, degree: int) -> np.ndarray:
    """Raise a Bernstein-form polynomial (coefficients on axis 0) to ``degree``."""
    a = np.asarray(a, dtype=float)
    while a.shape[0] - 1 < degree:
        n = a.shape[0] - 1
        k = np.arange(n + 2).reshape((-1,) + (1,) * (a.ndim - 1)) / (n + 1)
        padded_lo = np.concatenate([np.zeros_like(a[:1]), a])
        padded_hi = np.concatenate([a, np.zeros_like(a[:1])])
        a = k * padded_lo + (1 - k) * padded_hi
    return a


def bern_to_monomial(a: np.ndarray) -> np.ndarray:
    """Monomial coefficients (lowest first) of a scalar Bernstein-form polynomial ``(n+1,)``."""
    a = np.asarray(a, dtype=float)
    n = a.shape[0] - 1
    out = np.zeros(n + 1)
    for i in range(n + 1):
        # C(n,i) t^i (1-t)^(n-i) = C(n,i) Σ_j C(n-i, j) (-1)^j t^(i+j)
        for j in range(n - i + 1):
            out[i + j] += a[i] * comb(n, i) * comb(n - i, j) * (-1) ** j
    return out


def make_table(rot, rot_den, trans, trans_den) -> np.ndarray:
    """Assemble a ``(k, 14)`` table from coefficient arrays ``(k, 9)``, ``(k,)``, ``(k, 3)``, ``(k,)``."""
    rot = np.asarray(rot, dtype=float)
    table = np.zeros((rot.shape[0], 14))
    table[:, ROT_COLS] = rot
    table[:, TRANS_COLS] = trans
    table[:, 12] = rot_den
    table[:, 13] = trans_den
    return table


def evaluate_table(basis: np.ndarray, table: np.ndarray) -> np.ndarray:
    """Robotics matrices ``(N, 4, 4)`` from a basis ``(N, k)`` and a table ``(k, 14)``."""
    values = basis @ table
    n = values.shape[0]
    out = np.empty((n, 4, 4))
    scale = np.empty((n, 12))
    inv_rot = 1.0 / values[:, 12]
    inv_trans = 1.0 / values[:, 13]
    scale[:, ROT_COLS] = inv_rot[:, None]
    scale[:, TRANS_COLS] = inv_trans[:, None]
    out[:, :3, :] = (values[:, :12] * scale).reshape(n, 3, 4)
    out[:, 3, :3] = 0.0
    out[:, 3, 3] = 1.0
    return out


def evaluate_translations(basis: np.ndarray, table: np.ndarray) -> np.ndarray:
    """Translations ``(N, 3)`` from a basis ``(N, k)`` and a table ``(k, 14)``."""
    values = basis @ table[:, list(TRANS_COLS) + [13]]
    return values[:, :3] / values[:, 3:]


def linear_root(v0: float, v1: float) -> float | None:
    """The root of ``(1−t) v0 + t v1`` or None if it is constant non-zero."""
    if v0 == v1:
        return None if v0 != 0.0 else 0.0
    return v0 / (v0 - v1) + 0.0  # + 0.0 turns −0 into 0


def check_quaternion_path(pa: np.ndarray, pb: np.ndarray, lo: float, hi: float, what: str) -> None:
    """Raise if ``p(t) = (1−t) pa + t pb`` (nearly) vanishes for some ``t ∈ [lo, hi]``.

    ``|p(t)|²`` is a quadratic in t; its minimum on the interval is compared with
    ``1e-12 · max(|pa|², |pb|²)``.
    """
    diff = pb - pa
    dd = float(diff @ diff)
    t_min = 0.0 if dd == 0.0 else float(np.clip(-(pa @ diff) / dd, lo, hi))
    p_min = pa + t_min * diff
    scale = max(float(pa @ pa), float(pb @ pb))
    value = float(p_min @ p_min)
    if value <= 1e-12 * scale:
        raise SingularMotionError(
            f"the {what} passes through p(t) = 0 (no rotation defined) at t = {t_min:.6g}: "
            f"|p(t)|² / |p|²_max = {value / scale:.3g}, tolerance 1e-12"
        )
