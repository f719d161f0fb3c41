"""Sampling motions from precomputed coefficients.

Every motion of a2b is written as ``basis(t) @ table``: a small ``(k, 14)`` coefficient table
times ``k`` basis functions of ``t``. The 14 columns are the twelve numerators of the 3x4 block
``[R | t]`` row by row, the denominator of the rotation entries and the denominator of the
translation entries. Darboux and cubic motions are rational, so the basis is Bernstein's (the
end poses are the first and last coefficients, reproduced to about one ulp); the screw motion
uses ``(1, t, sin tφ, 2 sin²(tφ/2))``.

Sampling divides the basis by the denominators and writes each block of samples with one
single-threaded BLAS product straight into the output: no Python loop per sample, and a loop
over blocks only. The last bits of a sample may depend on how many samples are taken at once
(BLAS rounds a lone row differently from a full block).
"""

from __future__ import annotations

from functools import lru_cache
from math import comb, isfinite, prod

import numpy as np

from ..elements import anywhere, everywhere
from ..study import ROTATION, bilinear

EPS = float(np.finfo(float).eps)
#: ``|p(t)|² / max|p|²`` at or below which a motion is refused as passing through ``p = 0``.
SINGULAR_TOL = 1e-12
#: Below this ratio a motion is sampled, but with an :class:`A2bWarning` about its sensitivity.
SENSITIVE_TOL = 1e-7
#: Below this ratio the rotation is evaluated from the normalised ``p(t)`` (rigid to rounding)
#: instead of the ratio of Bernstein sums, whose rounding grows like ``ε / ratio``.
FRAGILE_TOL = 1e-2

ROT_COLS = (0, 1, 2, 4, 5, 6, 8, 9, 10)
TRANS_COLS = (3, 7, 11)


#: At most this many samples per block in :func:`evaluate_table` and
#: :func:`evaluate_translations`: 8192 rows of 16 doubles are 1 MiB, which stays in L2 cache.
SAMPLE_BLOCK = 8192
#: At most this many multiply-adds per BLAS product: OpenBLAS runs it on one thread (it starts a
#: second one from 2¹⁹), and a second thread stalls whenever the other core is busy.
BLAS_ONE_THREAD = 2**19 - 1


#: Pairs per chunk of a build's work arrays: the outer products of 4,096 pairs (about
#: 1.2 MB) stay in cache, where those of 10⁵ pairs at once (40 MB) ran slower.
CHUNK = 4096


def quadratic_rows(p: np.ndarray) -> np.ndarray:
    """The Bernstein coefficients ``B(pA, pA), B(pA, pB), B(pB, pB)`` of eq. 4's nine rotation
    numerators and of the denominator ``|p(t)|²`` along ``p(t) = (1−t) pA + t pB``: ``(10, 3,
    ...)`` for ends ``(4, 2, ...)``, components first (:func:`a2b.study.bilinear`)."""
    return bilinear(ROTATION, p.take(_FIRST, axis=1), p.take(_SECOND, axis=1))


#: The ends of the three products of :func:`quadratic_rows`: ``(A, A), (A, B), (B, B)``.
_FIRST, _SECOND = np.array([0, 0, 1]), np.array([0, 1, 1])


def bernstein_basis(ts: np.ndarray, degree: int) -> np.ndarray:
    """Bernstein polynomials ``C(n, i) (1−t)^(n−i) t^i``, shape ``(len(ts), degree + 1)``.

    The result is a transposed view of one ``(degree + 1, len(ts))`` array, so that each basis
    function is contiguous in memory: the layout :func:`evaluate_table` reads fastest. Every
    value is computed with the same operations, in the same order, as the textbook products
    ``u·u``, ``2u·t``, ``t·t`` (degree 2) and ``u²·u``, ``3u²·t``, ``3u·t²``, ``t²·t``
    (degree 3), ``u = 1 − t``.
    """
    t = np.asarray(ts, dtype=float)
    shape = t.shape
    if not shape:
        t = t.reshape(1)
    out = np.empty((degree + 1,) + t.shape)
    if degree == 1:
        np.subtract(1.0, t, out=out[0])
        out[1] = t
    elif degree == 2:
        u = np.subtract(1.0, t, out=out[0])
        np.multiply(u, 2.0, out=out[1])
        out[1] *= t
        np.multiply(u, u, out=out[0])
        np.multiply(t, t, out=out[2])
    elif degree == 3:
        u = np.subtract(1.0, t, out=out[0])
        tt = np.multiply(t, t, out=out[3])
        np.multiply(u, 3.0, out=out[2])
        out[2] *= tt
        uu = np.multiply(u, u, out=out[1])
        np.multiply(uu, u, out=out[0])
        uu *= 3.0
        uu *= t
        tt *= t
    elif degree <= 1000:  # C(1000, 500) ≈ 2.7e299 is still a double
        u = 1.0 - t
        for i in range(degree + 1):
            out[i] = float(comb(degree, i)) * u ** (degree - i) * t**i
    else:  # logarithms of binomials, which overflow a double beyond C(1029, 514)
        from math import lgamma

        log_binomials = [
            lgamma(degree + 1) - lgamma(i + 1) - lgamma(degree - i + 1) for i in range(degree + 1)
        ]
        u = 1.0 - t
        sign_u, sign_t = np.where(u < 0, -1.0, 1.0), np.where(t < 0, -1.0, 1.0)  # extrapolation
        with np.errstate(divide="ignore", over="ignore"):
            log_u, log_t = np.log(np.abs(u)), np.log(np.abs(t))
            for i in range(degree + 1):
                power_u = 0.0 if i == degree else (degree - i) * log_u
                power_t = 0.0 if i == 0 else i * log_t
                out[i] = np.exp(log_binomials[i] + power_u + power_t)
                out[i] *= sign_u ** (degree - i) * sign_t**i
    return out.T if len(shape) == 1 else np.moveaxis(out, 0, -1).reshape(shape + (degree + 1,))


def bern_mul(a: np.ndarray, b: np.ndarray, form=np.multiply) -> np.ndarray:
    """Product of Bernstein-form polynomials; coefficients on axis 0, broadcasting the rest.

    ``form`` is the product: elementwise by default, or any bilinear map of the trailing axes
    (``form(a_i, b)`` for one coefficient ``a_i`` and all of ``b``), for example
    :func:`a2b.study.rotation_numerators`, whose value on ``p(t), p(t)`` is then a polynomial of
    degree ``m + n`` in Bernstein form.
    """
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    m, n = a.shape[0] - 1, b.shape[0] - 1
    out = None
    weights = _product_weights(m, n)
    for i in range(m + 1):  # one array operation per coefficient of a: O(m n) numbers in all
        term = form(a[i], b)
        term = term * weights[i].reshape((n + 1,) + (1,) * (term.ndim - 1))
        if out is None:
            out = np.zeros((m + n + 1,) + term.shape[1:])
        out[i : i + n + 1] += term
    return out


@lru_cache(maxsize=256)
def _product_weights(m: int, n: int) -> np.ndarray:
    """``C(m, i) C(n, j) / C(m + n, i + j)``, shape ``(m + 1, n + 1)``, in (0, 1].

    Correctly rounded from exact integers up to ``m + n = 60``; from binomials rounded to
    doubles up to ``m + n = 1000`` (a few ulp; ``C(1000, 500) ≈ 2.7e299``); beyond, from their
    logarithms (about 1e-13 relative), so that nothing overflows for any degree.
    """
    i, j = np.arange(m + 1)[:, None], np.arange(n + 1)[None, :]
    if m + n <= 60:
        return _frozen(
            np.array(
                [[comb(m, a) * comb(n, b) / comb(m + n, a + b) for b in j[0]] for a in i[:, 0]]
            )
        )
    if m + n <= 1000:

        def binomials(k: int) -> np.ndarray:
            return np.array([float(comb(k, r)) for r in range(k + 1)])

        return _frozen(binomials(m)[i] * binomials(n)[j] / binomials(m + n)[i + j])
    from math import lgamma

    def log_binomials(k: int) -> np.ndarray:
        return np.array([lgamma(k + 1) - lgamma(r + 1) - lgamma(k - r + 1) for r in range(k + 1)])

    return _frozen(np.exp(log_binomials(m)[i] + log_binomials(n)[j] - log_binomials(m + n)[i + j]))


def _frozen(array: np.ndarray) -> np.ndarray:
    """``array`` made read-only: a cached value that callers share."""
    array.setflags(write=False)
    return array


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


def bernstein_derivatives(ts: np.ndarray, degree: int, order: int) -> np.ndarray:
    """The basis of :func:`bernstein_basis` and its derivatives in ``t`` up to ``order``:
    shape ``(order + 1, N, degree + 1)`` for ``ts (N,)``, ``S + (order + 1, N, degree + 1)``
    for ``ts S + (N,)``.

    ``d^r/dt^r B_i^n = n!/(n−r)! Σ_j (−1)^(r−j) C(r, j) B_(i−j)^(n−r)`` (zero for ``r > n``).
    """
    t = np.asarray(ts, dtype=float)
    out = np.zeros((order + 1,) + t.shape + (degree + 1,))
    out[0] = bernstein_basis(t, degree)
    for r in range(1, min(order, degree) + 1):
        lower = bernstein_basis(t, degree - r)
        scale = float(np.prod(np.arange(degree - r + 1, degree + 1)))
        for j in range(r + 1):
            out[r, ..., j : j + degree - r + 1] += ((-1) ** (r - j) * comb(r, j) * scale) * lower
    return np.moveaxis(out, 0, -3)


def table_derivatives(bases: np.ndarray, table: np.ndarray, point=None) -> np.ndarray:
    """Robotics matrices and their derivatives ``S + (r + 1, N, 4, 4)`` from the derivatives of
    a basis, ``(r + 1, N, k)`` or ``S + (r + 1, N, k)``, and tables ``S + (k, 14)``.

    Each entry is ``F = n / d``, a numerator over its denominator, both ``basis @ table``; its
    derivatives follow from ``n^(r) = Σ_j C(r, j) F^(j) d^(r−j)`` solved for ``F^(r)`` (Leibniz's
    rule), so they are exact up to rounding. The bottom row is ``(0, 0, 0, 1)`` in the matrices
    and 0 in every derivative.

    With ``point`` (``(3,)``, in the moving frame), only the path ``x = R point + t`` of that
    body point and its derivatives, ``S + (r + 1, N, 3)``: the table is first reduced to the six
    numerators of ``R point`` and ``t`` (over their two denominators), so each sample costs a
    fraction of a matrix.
    """
    table = np.asarray(table, dtype=float)
    shape, k = table.shape[:-2], table.shape[-2]
    order = bases.shape[-3] - 1
    if point is None:  # 12 numerators over (rotation, rotation, rotation, translation)
        columns, split, dens_of = table, (3, 4), [12, 12, 12, 13]
    elif not np.any(point):  # the origin's path is the translation: 3 numerators over 1
        columns, split, dens_of = table[..., [3, 7, 11, 13]], (3, 1), slice(3, 4)
    else:  # R point and t: 6 numerators over (rotation, translation)
        blocks = table[..., :12].reshape(table.shape[:-1] + (3, 4))
        reduced = np.stack([blocks[..., :3] @ point, blocks[..., 3]], axis=-1)
        columns = np.concatenate([reduced.reshape(shape + (k, 6)), table[..., 12:]], axis=-1)
        split, dens_of = (3, 2), slice(6, 8)
    # component-major work arrays (r + 1, columns, motions, N): each derivative of each column
    # is one contiguous plane, so every step below runs on long rows. A product per plane, but
    # a single sample's derivatives in one product, and no product of a single row: BLAS rounds
    # a product of one column or one row by another kernel, and a motion must take the same
    # alone (one basis for all) as in any batch (the screw's: a basis per motion)
    flat = np.ascontiguousarray(np.moveaxis(columns.reshape((-1, k, columns.shape[-1])), -1, 0))
    width, count, n = flat.shape[0], flat.shape[1], bases.shape[-2]
    values = np.empty((order + 1, width, count, n))
    if bases.ndim > 3:  # one basis per motion: a product per motion, as for one motion alone
        per_motion = np.moveaxis(bases.reshape((count,) + bases.shape[-3:]), -1, -3)
        coefficients = np.moveaxis(flat, 0, 1)
        if n == 1:
            products = coefficients @ per_motion.reshape(count, k, -1)
            values[..., 0] = products.transpose(2, 1, 0)
        else:
            for r in range(order + 1):
                values[r] = np.swapaxes(coefficients @ per_motion[:, :, r], 0, 1)
    else:  # one basis for all: products small enough for one BLAS thread each (a second
        # thread stalls whenever another process keeps the other core busy)
        rows = flat.reshape(-1, k)
        if n > 1:
            stacked = np.ascontiguousarray(np.swapaxes(bases, -1, -2))  # (r + 1, k, N)
            planes = values.reshape(order + 1, -1, n)
        else:
            stacked = np.moveaxis(bases, -1, 0).reshape(1, k, order + 1)
            planes = np.empty((1, len(rows), order + 1))
        step = max(3, BLAS_ONE_THREAD // (k * stacked.shape[-1]))
        edges = [*range(0, len(rows), step), len(rows)]
        if edges[-1] - edges[-2] == 1 and len(edges) > 2:  # no product of one row either
            edges[-2] -= 1
        for plane, basis in zip(planes, stacked):
            for lo, hi in zip(edges, edges[1:]):
                np.matmul(rows[lo:hi], basis, out=plane[lo:hi])
        if n == 1:
            values[..., 0] = planes[0].T.reshape(values.shape[:-1])
    numerators = values[:, : split[0] * split[1]].reshape((order + 1,) + split + (count, n))
    dens = values[:, dens_of]
    scale = 1.0 / dens[0]
    quotients = np.empty(numerators.shape)
    np.multiply(numerators[0], scale, out=quotients[0])
    for r in range(1, order + 1):  # n_r − Σ_j C(r, j) F_j d_(r−j), over d_0
        top = np.multiply(quotients[0], dens[r], out=quotients[r])
        np.subtract(numerators[r], top, out=top)
        for j in range(1, r):
            part = quotients[j] * dens[r - j]
            top -= comb(r, j) * part
        top *= scale
    if point is not None:  # (r + 1, 3, motions, N) -> S + (r + 1, N, 3), a view
        path = quotients.sum(axis=2) if split[1] > 1 else quotients[:, :, 0]
        return path.transpose(2, 0, 3, 1).reshape(shape + (order + 1, n, 3))
    out = np.zeros((count, order + 1, n, 4, 4))
    out[..., :3, :] = quotients.transpose(3, 0, 4, 1, 2)
    out[:, 0, :, 3, 3] = 1.0
    return out.reshape(shape + out.shape[1:])


def make_table(rot, rot_den, trans, trans_den) -> np.ndarray:
    """Tables ``(..., k, 14)`` from coefficients ``(..., k, 9)``, ``(..., k)``, ``(..., k, 3)``,
    ``(..., k)``."""
    rot = np.asarray(rot, dtype=float)
    trans = np.asarray(trans, dtype=float)
    rot_den = np.asarray(rot_den, dtype=float)
    trans_den = np.asarray(trans_den, dtype=float)
    shape = np.broadcast_shapes(rot.shape[:-1], trans.shape[:-1], rot_den.shape, trans_den.shape)
    table = np.empty(shape + (14,))
    for row in range(3):  # columns of row r of [R | t]: 4r … 4r + 2, then 4r + 3 (slices: fast)
        table[..., 4 * row : 4 * row + 3] = rot[..., 3 * row : 3 * row + 3]
        table[..., 4 * row + 3] = trans[..., row]
    table[..., 12] = rot_den
    table[..., 13] = trans_den
    return table


def evaluate_table(basis: np.ndarray, table: np.ndarray) -> np.ndarray:
    """Robotics matrices ``S + (N, 4, 4)`` from a basis and tables ``S + (k, 14)``.

    ``basis`` is ``(N, k)``, shared by every table, or ``S + (N, k)``, one per table (the
    screw motion's depends on φ). Entry ``j`` of a sample is ``Σ_i (b_i / d) c_ij``, with
    ``d`` the denominator of that entry: the basis is divided by the denominator first, so
    that one product ``[b / d_rot, b / d_trans, 1] @ E`` with an extended ``(2k + 1, 16)``
    table per block of samples writes finished rows of 16 straight into the output, the
    bottom row ``(0, 0, 0, 1)`` included (the constant basis function 1 times the coefficient
    1). Tables that share one denominator need only ``(k + 1, 16)``, and where every
    denominator is 1 (the screw motion) nothing is divided.

    Each entry ``x_j`` is within about ``k + 2`` units in the last place of the exact value of
    the table, relative to the size ``(Σ_i |b_i c_ij| + |x_j| Σ_i |b_i d_i|) / |d|`` of its
    terms (``Σ_i |b_i c_ij| / |d| + |x_j|`` for ``t ∈ [0, 1]``, where no terms of ``d`` cancel).

    Each job takes the path that its own denominators call for (:func:`_kinds`), so that an
    element of a batch is bit for bit the element alone: a product over more rows of the
    extended table rounds differently, even where the extra rows are zeros.
    """
    columns, tables, shape = _flatten(basis, table)
    out = np.empty((len(tables), columns.shape[-1], 4, 4))
    kinds = _kinds(columns, tables[:, :, 12], tables[:, :, 13])
    _by_kind(kinds, columns, tables, out, _table_rows)
    return out.reshape(shape + out.shape[1:])


def _table_rows(kind: int, columns: np.ndarray, tables: np.ndarray, out: np.ndarray) -> None:
    """:func:`evaluate_table` of jobs of one kind: ``kind`` denominators (0, 1 or 2)."""
    jobs, k, _ = tables.shape
    rows = out.reshape(jobs, out.shape[1], 16)
    if kind == 0:
        extended = _Extended(tables, k, [(slice(0, k), slice(0, 12))], (0, 15))
        _rows(columns, None, extended, rows, False)
        return
    if kind == 1:
        blocks = [(slice(0, k), slice(0, 12))]
    else:
        blocks = [(slice(0, k), list(ROT_COLS)), (slice(k, 2 * k), list(TRANS_COLS))]
    extended = _Extended(tables, kind * k + 1, blocks, (-1, 15))
    if not _rows(columns, tables[:, :, 12 : 12 + kind], extended, rows, True):
        # 0 · ∞ spread NaN into the bottom row of samples with a vanishing denominator
        out[:, :, 3, :3] = 0.0
        out[:, :, 3, 3] = 1.0


class _Extended:
    """The extended tables ``(jobs, rows, 16)`` of :func:`evaluate_table`, made block by block
    as :func:`_rows` asks for them (``extended(first, last)``), in one reused buffer: for
    10⁵ motions of one sample each, the whole extended table would be 50 MB to write and
    read once.

    ``blocks`` are ``(rows, columns)`` that take the table's columns of the same index
    (rows ``0 … k − 1`` of the table, shifted to the given rows); ``one`` is the entry that
    is 1 (the bottom-right corner, from a constant basis function).
    """

    def __init__(self, tables: np.ndarray, rows: int, blocks: list, one: tuple):
        self.tables, self.rows, self.blocks, self.one = tables, rows, blocks, one
        self.shape = (len(tables), rows, 16)
        self.buffer = None

    def __call__(self, first: int, last: int) -> np.ndarray:
        size = last - first
        if self.buffer is None or len(self.buffer) < size:
            self.buffer = np.zeros((size, self.rows, 16))
            self.buffer[:, self.one[0], self.one[1]] = 1.0
        part = self.buffer[:size]
        for rows, cols in self.blocks:
            part[:, rows, cols] = self.tables[first:last, :, cols]
        return part


def evaluate_translations(basis: np.ndarray, table: np.ndarray) -> np.ndarray:
    """Translations ``S + (N, 3)`` from a basis and tables ``S + (k, 14)``.

    As in :func:`evaluate_table`: ``Σ_i (b_i / d) c_ij`` per block of samples, written straight
    into the output.
    """
    columns, tables, shape = _flatten(basis, table)
    out = np.empty((len(tables), columns.shape[-1], 3))
    kinds = _kinds(columns, tables[:, :, 13])
    _by_kind(kinds, columns, tables, out, _translation_rows)
    return out.reshape(shape + out.shape[1:])


def _translation_rows(kind: int, columns: np.ndarray, tables: np.ndarray, out: np.ndarray):
    """:func:`evaluate_translations` of jobs of one kind: ``kind`` denominators (0 or 1)."""
    coefficients = np.ascontiguousarray(tables[:, :, TRANS_COLS])
    _rows(columns, tables[:, :, 13:14] if kind else None, coefficients, out, False)


def _flatten(basis, table) -> tuple[np.ndarray, np.ndarray, tuple]:
    """The basis as columns ``(1 or J, k, N)``, the tables as ``(J, k, 14)``, and ``S``."""
    table = np.asarray(table, dtype=float)
    basis = np.asarray(basis, dtype=float)
    shape = table.shape[:-2]
    jobs = prod(shape)
    k = table.shape[-2]
    columns = basis.swapaxes(-1, -2)  # a view: (k, N) contiguous for bernstein_basis
    columns = columns.reshape((1 if basis.ndim == 2 else jobs, k, basis.shape[-2]))
    return columns, table.reshape(jobs, k, 14), shape


def _kinds(columns: np.ndarray, rot_den: np.ndarray, trans_den=None) -> np.ndarray:
    """How many denominators each job's samples divide by, ``(J,)``: 0 where ``basis @
    denominator`` is exactly 1 (``(1, 0, …, 0)`` on a first basis row of 1s, as for the screw
    motion), 1 where the rotation and the translation share one (or only ``rot_den`` is
    given), 2 else. ``columns`` is the basis ``(1 or J, k, N)``, the denominators ``(J, k)``."""
    jobs, k = rot_den.shape
    if jobs == 1 and len(columns) == 1:  # one motion: the same tests on Python floats
        rot = rot_den[0].tolist()
        same = trans_den is None or rot == trans_den[0].tolist()  # NaN ≠ NaN, as below
        unit = same and rot[0] == 1.0 and not any(rot[1:]) and everywhere(columns[0, 0] == 1.0)
        return np.array([0 if unit else 1 if same else 2])
    same = np.ones(jobs, dtype=bool)
    if trans_den is not None and not everywhere(rot_den == trans_den):
        for i in range(k):  # column by column: 3x faster than all()
            same &= rot_den[:, i] == trans_den[:, i]
    kinds = np.where(same, 1, 2)
    first = columns[:, 0]  # False below for a Bernstein basis beyond t = 0
    ones = first == 1.0
    if len(first) == 1 or everywhere(ones):  # one basis for every job, or 1s everywhere
        unit = np.full(jobs, everywhere(ones))
    else:  # (a reduction of the short axis of each job's samples costs 7x as much)
        unit = ones.all(axis=-1)
    if anywhere(unit):
        unit = unit & same & (rot_den[:, 0] == 1.0)
        for i in range(1, k):
            unit &= rot_den[:, i] == 0.0
        kinds[unit] = 0
    return kinds


def _by_kind(kinds: np.ndarray, columns, tables: np.ndarray, out: np.ndarray, evaluate) -> None:
    """``evaluate(kind, columns, tables, out)`` with each job's own kind (:func:`_kinds`): the
    most common kind on every job in place, then the jobs of each other kind gathered, again,
    and put in their place (a mixed batch costs the few others twice, not a copy of all)."""
    first = int(kinds[0]) if len(kinds) else 0
    if len(kinds) < 2 or everywhere(kinds == first):  # one kind (and always for one motion)
        evaluate(first, columns, tables, out)
        return
    counts = np.bincount(kinds, minlength=3)
    main = int(counts.argmax())
    evaluate(main, columns, tables, out)
    for kind in np.flatnonzero(counts):
        if kind == main:
            continue
        mine = np.flatnonzero(kinds == kind)
        part = np.empty((len(mine),) + out.shape[1:])
        evaluate(int(kind), columns if len(columns) == 1 else columns[mine], tables[mine], part)
        out[mine] = part


def blocked_product(basis: np.ndarray, coefficients: np.ndarray) -> np.ndarray:
    """``basis @ coefficients`` for a basis ``(N, k)`` and coefficients ``(k, w)``, block by block.

    The same product as ``@``, in blocks small enough for one BLAS thread each (see
    :data:`BLAS_ONE_THREAD`): a single large product with a second thread can take a hundred
    times longer while another process keeps the second core busy, as in a shell pipeline.
    """
    basis = np.asarray(basis, dtype=float)
    coefficients = np.asarray(coefficients, dtype=float)
    out = np.empty((basis.shape[0], coefficients.shape[1]))
    _rows(basis.T[None], None, coefficients[None], out[None], False)
    return out


def _rows(columns, denominators, coefficients, out, constant) -> bool:
    """``out = [b / d_1, …, b / d_m, (1)] @ coefficients`` for every job, block by block.

    ``columns`` is the basis ``(1 or J, k, N)`` (one row per basis function), ``denominators``
    ``(J, k, m)`` or ``None`` (every denominator 1: the basis itself), ``coefficients``
    ``(J, m k (+ 1), w)`` (or a function ``(first, last)`` that gives those of jobs ``first``
    to ``last − 1``, with their ``shape``), with ``constant`` a last basis function 1, and
    ``out`` ``(J, N, w)``.
    A block holds the samples of one job or, for short motions, of several, at most
    :data:`SAMPLE_BLOCK` rows: it is divided and multiplied while it is in cache, and each
    BLAS product is small enough to run on one thread. Returns whether every ``1 / d`` was
    finite.
    """
    jobs, n, _ = out.shape
    if not (jobs and n):
        return True
    k = columns.shape[1]
    m = 0 if denominators is None else denominators.shape[2]
    width = coefficients.shape[1] * coefficients.shape[2]
    rows = min(SAMPLE_BLOCK, max(256, BLAS_ONE_THREAD // max(width, 1)))
    samples = min(n, rows)
    group = min(jobs, max(1, rows // max(n, 1)))  # jobs per block
    den_rows = None if denominators is None else np.ascontiguousarray(denominators.swapaxes(1, 2))
    inverse = np.empty((group, m, samples))
    scaled = np.empty((group, m * k + constant, samples))
    if constant:
        scaled[:, -1] = 1.0
    total = 0.0
    for first in range(0, jobs, group):
        last = min(first + group, jobs)
        size = last - first
        block_columns = columns if columns.shape[0] == 1 else columns[first:last]
        if callable(coefficients):
            block_coefficients = coefficients(first, last)
        else:
            block_coefficients = coefficients[first:last]
        for start in range(0, n, samples):
            stop = min(start + samples, n)
            block = block_columns[:, :, start:stop]
            if den_rows is None and not constant:
                if len(block) != size:  # one basis for every job
                    block = np.broadcast_to(block, (size,) + block.shape[1:])
                np.matmul(block.swapaxes(1, 2), block_coefficients, out=out[first:last, start:stop])
                continue
            part = scaled[:size, :, : stop - start]
            if den_rows is None:
                part[:, :k] = block
            else:
                inv = inverse[:size, :, : stop - start]
                np.matmul(den_rows[first:last], block, out=inv)
                np.divide(1.0, inv, out=inv)
                total += float(np.add.reduce(inv, axis=None))
                for j in range(m):
                    np.multiply(block, inv[:, j : j + 1], out=part[:, j * k : (j + 1) * k])
            np.matmul(part.swapaxes(1, 2), block_coefficients, out=out[first:last, start:stop])
    return isfinite(total)
