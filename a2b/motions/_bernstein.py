"""Polynomials in Bernstein form: where they come close to zero on an interval.

The Bézier motions (:mod:`a2b.motions.bezier`) are singular where ``x0(t)`` or ``|p(t)|²``
vanishes; :func:`first_small_values` finds, for many polynomials at once, the first parameter
where one comes within ``SINGULAR_TOL`` of its largest coefficient.
"""

from __future__ import annotations

import numpy as np

from ._rational import bernstein_basis

#: Relative tolerance of the singularity checks: ``|x0(t)| ≤ SINGULAR_TOL · max |x0 coefficient|``
#: or ``|p(t)|² ≤ SINGULAR_TOL · max |coefficient of |p|²|`` counts as a singular point.
SINGULAR_TOL = 1e-12

_BISECTIONS = 80


def _bern_eval(coeffs: np.ndarray, ts: np.ndarray) -> np.ndarray:
    """Values ``(S, P)`` of ``S`` polynomials (Bernstein coefficients ``(S, n+1)``) at ``ts (S,
    P)``."""
    n = coeffs.shape[-1] - 1
    if n == 0:
        return np.broadcast_to(coeffs[:, :1], ts.shape).copy()
    basis = bernstein_basis(ts.reshape(-1), n).reshape(ts.shape + (n + 1,))
    return np.einsum("spi,si->sp", basis, coeffs)


def _bisect(coeffs: np.ndarray, rows: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """Zeros of polynomial ``coeffs[rows]`` in brackets ``[lo, hi]`` with a sign change."""
    c = coeffs[rows]
    f_lo = np.sign(_bern_eval(c, lo[:, None]))[:, 0]
    for _ in range(_BISECTIONS):
        mid = 0.5 * (lo + hi)
        f_mid = np.sign(_bern_eval(c, mid[:, None]))[:, 0]
        right = f_mid == f_lo  # the zero lies in [mid, hi]
        lo = np.where(right, mid, lo)
        hi = np.where(right, hi, mid)
        if np.all(hi - lo <= 2.0 * np.spacing(np.maximum(np.abs(lo), np.abs(hi)))):
            break
    return 0.5 * (lo + hi)


def _zeros_and_extrema(coeffs: np.ndarray, lo: float, hi: float) -> tuple[np.ndarray, np.ndarray]:
    """Real zeros and critical points in ``[lo, hi]`` of polynomials in Bernstein form.

    ``coeffs`` has shape ``(S, n+1)``; both results have shape ``(S, w)`` with ``w ≤ n + 1``,
    padded with NaN.

    The critical points are the zeros of the derivative (Bernstein coefficients proportional to
    ``c_{i+1} − c_i``; the constant factor ``n`` is left out, as it moves no zero and would
    overflow over many derivatives). Between two consecutive ones, and the ends of the interval,
    a polynomial is monotone, so a sign change there brackets exactly one zero, which bisection
    finds to machine precision. The derivatives are taken down to degree 1 and their zeros
    found from there upwards, in a loop: work and memory are polynomial in ``n``. Zeros of even
    multiplicity are critical points; callers compare the values there with a tolerance.
    """
    rows, n = coeffs.shape[0], coeffs.shape[1] - 1
    empty = np.full((rows, 0), np.nan)
    if n <= 0:
        return empty, empty
    chain = [coeffs]
    while chain[-1].shape[1] > 2:  # down to degree 1, whose derivative has no zero
        chain.append(np.diff(chain[-1], axis=-1))
    crit, zeros = empty, empty
    for c in reversed(chain):
        crit, zeros = zeros, _zeros_between(c, zeros, lo, hi)
    return zeros, crit


def _zeros_between(coeffs: np.ndarray, crit: np.ndarray, lo: float, hi: float) -> np.ndarray:
    """The zeros in ``[lo, hi]`` of polynomials whose critical points there are ``crit``."""
    rows = coeffs.shape[0]
    pts = np.concatenate([np.full((rows, 1), lo), crit, np.full((rows, 1), hi)], axis=1)
    pts = np.sort(pts, axis=1)  # NaN last
    pts = np.where(np.isnan(pts), hi, pts)
    vals = _bern_eval(coeffs, pts)
    exact = np.where(vals == 0.0, pts, np.nan)
    change = vals[:, :-1] * vals[:, 1:] < 0.0
    bracketed = np.full(change.shape, np.nan)
    if np.any(change):
        r, i = np.nonzero(change)
        bracketed[r, i] = _bisect(coeffs, r, pts[r, i], pts[r, i + 1])
    zeros = np.sort(np.concatenate([exact, bracketed], axis=1), axis=1)  # NaN last
    width = int(np.max(np.sum(~np.isnan(zeros), axis=1), initial=0))
    return zeros[:, :width]


#: Halvings of [0, 1] that :func:`_away_from_zero` tries before it gives up.
_HALVINGS = 6


def _away_from_zero(c: np.ndarray, tol: float) -> np.ndarray:
    """Which polynomials (Bernstein coefficients ``(S, n+1)`` on [0, 1]) provably stay above
    ``tol · max |c|`` in absolute value on [0, 1].

    A polynomial lies in the convex hull of its Bernstein coefficients, so coefficients all
    above ``tol · max |c|`` (or all below its negative) prove it; where they do not, the
    interval is halved by de Casteljau's algorithm, up to :data:`_HALVINGS` times, and each half
    is tested alike. False means "not proved": the exact search decides. This is ``O(n²)`` per
    piece, against the exact search's many evaluations of high-degree polynomials.
    """
    bound = tol * np.max(np.abs(c), axis=1, keepdims=True)
    pieces = c[:, None, :]  # (S, pieces, n + 1)
    proved = np.zeros(c.shape[0], dtype=bool)
    for _ in range(_HALVINGS + 1):
        positive = (pieces > bound[:, :, None]).all(axis=2)
        negative = (pieces < -bound[:, :, None]).all(axis=2)
        ok = positive | negative
        if ok.all(axis=1).all():
            return np.ones(c.shape[0], dtype=bool)
        proved = ok.all(axis=1)
        if pieces.shape[1] >= 2**_HALVINGS or (~ok).sum() * c.shape[1] ** 2 > 1 << 24:
            break
        pieces = np.concatenate(_halves(pieces), axis=1)
    return proved


def _halves(pieces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The Bernstein coefficients of the left and right halves (de Casteljau at t = ½)."""
    n = pieces.shape[-1] - 1
    left = np.empty_like(pieces)
    right = np.empty_like(pieces)
    row = pieces.copy()
    for k in range(n + 1):
        left[..., k] = row[..., 0]
        right[..., n - k] = row[..., -1]
        row = 0.5 * (row[..., :-1] + row[..., 1:])
    return left, right


def first_small_values(coeffs, lo: float, hi: float, tol: float = SINGULAR_TOL):
    """For each polynomial, the smallest ``t ∈ [lo, hi]`` where it vanishes or nearly does.

    Parameters
    ----------
    coeffs : array_like, shape (S, n+1)
        Bernstein coefficients on ``[0, 1]`` of ``S`` polynomials (``[lo, hi]`` may extend
        beyond ``[0, 1]``).
    lo, hi : float
    tol : float
        Relative tolerance: ``|f(t)| ≤ tol · max |coeffs|`` counts as zero.

    Returns
    -------
    ts, ratios : ndarray, shape (S,)
        The first such ``t`` (NaN if there is none) and ``|f(t)| / max |coeffs|`` there.
    """
    c = np.asarray(coeffs, dtype=float)
    rows = c.shape[0]
    if 0.0 <= lo and hi <= 1.0:
        away = _away_from_zero(c, tol)
        if away.all():
            return np.full(rows, np.nan), np.full(rows, np.nan)
        if away.any():
            ts, ratios = np.full(rows, np.nan), np.full(rows, np.nan)
            ts[~away], ratios[~away] = first_small_values(c[~away], lo, hi, tol)
            return ts, ratios
    scale = np.max(np.abs(c), axis=1)
    safe = np.where(scale == 0.0, 1.0, scale)
    zeros, crit = _zeros_and_extrema(c / safe[:, None], lo, hi)
    pts = np.concatenate([np.full((rows, 1), lo), crit, np.full((rows, 1), hi)], axis=1)
    pts = np.where(np.isnan(pts), hi, pts)
    small = np.where(np.abs(_bern_eval(c, pts)) <= tol * scale[:, None], pts, np.nan)
    found = np.concatenate([zeros, small], axis=1)
    has = ~np.all(np.isnan(found), axis=1)
    ts = np.full(rows, np.nan)
    ts[has] = np.nanmin(found[has], axis=1)
    ratios = np.full(rows, np.nan)
    if np.any(has):
        ratios[has] = np.abs(_bern_eval(c[has], ts[has][:, None])[:, 0]) / safe[has]
    return ts, ratios


def first_small_value(coeffs, lo: float, hi: float, tol: float = SINGULAR_TOL):
    """The smallest ``t ∈ [lo, hi]`` where one polynomial (Bernstein coefficients ``(n+1,)``)
    vanishes or has ``|f(t)| ≤ tol · max |coeffs|``, with that ratio; or None.

    See :func:`first_small_values`.
    """
    ts, ratios = first_small_values(np.asarray(coeffs, dtype=float)[None], lo, hi, tol)
    return None if np.isnan(ts[0]) else (float(ts[0]), float(ratios[0]))


# -- validation ---------------------------------------------------------------------------------
