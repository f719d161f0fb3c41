"""Quaternions, dual quaternions (Study parameters) and the extended kinematic map κ.

Conventions (see ``docs/math.md``):

* a quaternion ``p = p0 + p1 i + p2 j + p3 k`` is stored scalar first, arrays ``(..., 4)``;
* Study parameters ``h = p + ε q`` are stored ``(p0, p1, p2, p3, q0, q1, q2, q3)``,
  arrays ``(..., 8)``;
* the action of ``h`` on a point is ``x ↦ (p x p̄ + p q̄ − q p̄) / (p p̄)`` (eq. 3), so the
  rotation matrix is eq. 4 divided by ``Δ = p p̄`` and the translation is
  ``(p q̄ − q p̄) / Δ``, which is eq. 5 divided by ``Δ``. This is valid for *every* ``h`` with
  ``p ≠ 0``, on the Study quadric or not: it is the extended map κ of section 3.

All functions are vectorised over leading dimensions.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from .elements import unit_scale
from .errors import PoseError

#: Relative tolerance of the Study condition ``p·q = 0`` (see :func:`check_study`).
STUDY_TOL = 1e-9


def _components(a: np.ndarray) -> np.ndarray:
    """The components of vectors ``(..., n)`` as ``n`` contiguous arrays (one copy): arithmetic
    on them reads memory in order, several times faster than on strided views."""
    return np.ascontiguousarray(a.transpose((a.ndim - 1,) + tuple(range(a.ndim - 1))))


def _vectors(*components: np.ndarray) -> np.ndarray:
    """Vectors ``(..., n)``, C-contiguous, from ``n`` component arrays."""
    shape = np.broadcast_shapes(*(c.shape for c in components))
    out = np.empty(shape + (len(components),))
    for k, component in enumerate(components):
        out[..., k] = component
    return out


class Structure(NamedTuple):
    """A bilinear form's structure matrix, and its non-zero entries term by term."""

    #: ``(n_out, n_a n_b)``: column ``i n_b + j`` is ``form(e_i, e_j)``.
    matrix: np.ndarray
    #: ``(m, n_out)``: term ``k`` of each row: the column of its ``k``-th non-zero entry, in
    #: order (padded with 0).
    columns: np.ndarray
    #: ``(m, n_out, 1)``: those entries (padding: see :func:`sparse_rows`).
    weights: np.ndarray
    #: For a bilinear form, ``(m, n_out)`` each: the indices ``i`` and ``j`` of the
    #: components ``a_i b_j`` of each term (``column = i n_b + j``).
    left: np.ndarray | None = None
    right: np.ndarray | None = None
    #: ``left`` and ``right``, each ``(m, 1)`` where a term takes the same component for
    #: every output (:func:`_narrow`).
    narrow: tuple | None = None
    #: Each output row's terms in order, ``(i, j, w)`` for a bilinear form and ``(column, w)``
    #: for a linear map: what :func:`_in_turn` and :func:`_contract_in_turn` run through.
    plan: tuple = ()


def structure_matrix(form, n_a: int, n_b: int, padding: float = 0.0) -> Structure:
    """The structure matrix ``(n_out, n_a n_b)`` of a bilinear ``form(a, b)``: column
    ``i n_b + j`` is ``form(e_i, e_j)`` for the unit vectors ``e_i``, ``e_j``.

    a2b writes each bilinear form once, as a plain function of vectors ``(..., n)``; its
    structure matrix, made by evaluating that function on basis vectors at import, lets
    :func:`bilinear` evaluate it over component-major arrays with a few operations, however
    many terms the formula has. ``padding``: as for :func:`sparse_rows` (``−0.0`` for forms
    whose first components are the constant 1, where a padded term ``−0.0 a_0 b_0`` changes
    no sum).
    """
    a = np.repeat(np.eye(n_a), n_b, axis=0)
    b = np.tile(np.eye(n_b), (n_a, 1))
    rows = sparse_rows(np.asarray(form(a, b), dtype=float).T, padding)
    left, right = rows.columns // n_b, rows.columns % n_b
    plan = tuple(
        tuple(zip(left[:, r].tolist(), right[:, r].tolist(), rows.weights[:, r, 0].tolist()))
        for r in range(left.shape[1])
    )  # the padding terms too: 0 a_0 b_0 is a signed zero, or NaN
    return rows._replace(left=left, right=right, narrow=(_narrow(left), _narrow(right)), plan=plan)


def _narrow(indices: np.ndarray) -> np.ndarray:
    """Term indices ``(m, n_out)`` as ``(m, 1)`` where each term takes the same component for
    every output row (as the left factor of a quaternion product does): :func:`_terms` then
    gathers ``m`` rows, not ``m n_out``, and broadcasts them (for many columns; on a few, the
    broadcasting costs more than the gather saves)."""
    return indices[:, :1] if (indices == indices[:, :1]).all() else indices


def sparse_rows(matrix: np.ndarray, padding: float = 0.0) -> Structure:
    """The :class:`Structure` of a matrix ``(n_out, n_in)``: its rows' non-zero entries.

    Rows with fewer terms than the longest are padded with column 0 and weight ``padding``.
    A linear map whose input row 0 is the constant 1 pads with ``-0.0``, the one term that
    leaves every sum as it is, signed zeros included.
    """
    matrix = np.ascontiguousarray(matrix, dtype=float)
    width = max(1, int((matrix != 0).sum(axis=1).max()))
    columns = np.zeros((width, len(matrix)), dtype=np.intp)
    weights = np.full((width, len(matrix), 1), padding)
    plan = []
    identity = padding == 0.0 and math.copysign(1.0, padding) < 0  # -0.0: terms to leave out
    for row, entries in enumerate(matrix):
        (found,) = np.nonzero(entries)
        columns[: len(found), row] = found
        weights[: len(found), row, 0] = entries[found]
        used = len(found) if identity else width
        plan.append(tuple(zip(columns[:used, row].tolist(), weights[:used, row, 0].tolist())))
    return Structure(matrix, columns, weights, plan=tuple(plan))


def bilinear(form: Structure, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """A bilinear form given by its :func:`structure_matrix`, on component-major arrays.

    ``a`` is ``(n_a, ...)`` and ``b`` is ``(n_b, ...)``, components first; their trailing
    shapes broadcast. Returns ``(n_out, ...)``: the outer product of ``a`` and ``b``, of
    which each output row sums its few non-zero terms, in the order of the columns. Every
    step is elementwise, the terms added one after another, so that an element of a batch is
    bit for bit the element computed alone (a BLAS or ``einsum`` product sums in an order
    that depends on an element's place in the array).
    """
    shape = a.shape[1:]
    if b.shape[1:] != shape:
        shape = _broadcast(shape, b.shape[1:])
    size = math.prod(shape)
    trailing = len(shape)
    if a.ndim <= trailing:  # fewer dimensions (one quaternion against many): as numpy aligns them
        a = _aligned(a, trailing)
    if b.ndim <= trailing:
        b = _aligned(b, trailing)
    if size < IN_TURN_FROM:
        if size <= NARROW_FROM:
            return _terms(form, a, b, trailing, form.left, form.right)
        return _terms(form, a, b, trailing, *form.narrow)
    if a.shape[1:] != shape:  # (numpy's broadcast_to costs 16 µs, a tenth of a call here)
        a = np.broadcast_to(a, a.shape[:1] + shape)
    if b.shape[1:] != shape:
        b = np.broadcast_to(b, b.shape[:1] + shape)
    a, b = a.reshape(len(a), size), b.reshape(len(b), size)
    out = np.empty((len(form.matrix), size))
    scratch = np.empty(min(size, IN_TURN_CHUNK))
    for lo in range(0, size, IN_TURN_CHUNK):  # work arrays that stay in cache
        hi = min(lo + IN_TURN_CHUNK, size)
        _in_turn(form.plan, a[:, lo:hi], b[:, lo:hi], out[:, lo:hi], scratch[: hi - lo])
    return out.reshape(out.shape[:1] + shape)


def _broadcast(one: tuple, other: tuple) -> tuple:
    """:func:`numpy.broadcast_shapes` of two shapes, for the common case of shapes of one
    length in a few operations (``numpy.broadcast_shapes`` costs microseconds)."""
    if len(one) == len(other) and all(x == y or x == 1 or y == 1 for x, y in zip(one, other)):
        return tuple(y if x == 1 else x for x, y in zip(one, other))
    return np.broadcast_shapes(one, other)


def _aligned(x: np.ndarray, trailing: int) -> np.ndarray:
    """``x`` ``(n, ...)`` with ``trailing`` dimensions after the components (new ones of 1
    first), so that gathered terms broadcast as the arrays do."""
    missing = trailing - (x.ndim - 1)
    return x.reshape(x.shape[:1] + (1,) * missing + x.shape[1:]) if missing else x


def _terms(form: Structure, a, b, trailing: int, left, right) -> np.ndarray:
    """:func:`bilinear` of arrays with ``trailing`` dimensions after the components: each term
    ``w a_i b_j`` of each output row gathered (by ``left`` and ``right``, those of ``form`` or
    its :attr:`Structure.narrow`), multiplied, and added in order."""
    terms = a.take(left, axis=0) * b.take(right, axis=0)  # (m, n_out, ...)
    terms *= (
        form.weights
        if trailing == 1
        else form.weights.reshape(form.columns.shape + (1,) * trailing)
    )
    return sum_terms(terms)


#: Up to this many numbers, :func:`sum_terms` adds with one ``numpy.add.accumulate``, which
#: costs less than a call per term there and several times more on larger arrays (its inner
#: loop runs along the terms).
ACCUMULATE_UP_TO = 128


def sum_terms(terms: np.ndarray) -> np.ndarray:
    """``terms`` ``(m, ...)`` summed over the first axis in order, ``((t0 + t1) + t2) + …``
    (overwriting them): the same additions whether one ``numpy.add.accumulate`` does them or
    a call per term, as contiguous elementwise additions (never a pairwise reduction, whose
    order depends on the layout)."""
    if terms.size <= ACCUMULATE_UP_TO:
        return np.add.accumulate(terms, axis=0, out=terms)[-1]
    out = terms[0]
    for term in terms[1:]:
        out += term
    return out


def _in_turn(plan: tuple, a, b, out: np.ndarray, scratch: np.ndarray) -> None:
    """:func:`_terms` row by row and term by term into ``out`` ``(n_out, N)``, for many
    columns: the same products, weights and additions in the same order (``x − y`` is
    ``x + (−1) y`` exactly), two passes a term where gathering takes five."""
    for row, terms in zip(out, plan):
        (i, j, w), rest = terms[0], terms[1:]
        np.multiply(a[i], b[j], out=row)
        if w != 1.0:
            row *= w
        for i, j, w in rest:
            np.multiply(a[i], b[j], out=scratch)
            if w == -1.0:
                row -= scratch
            else:
                if w != 1.0:
                    scratch *= w
                row += scratch


def linear(form: Structure, x: np.ndarray) -> np.ndarray:
    """A linear map given by its :func:`sparse_rows` on a component-major array ``(n_in, N)``:
    ``(n_out, N)``, each row's terms summed in the order of the columns, in chunks that stay
    in cache (as :func:`bilinear`)."""
    size = x.shape[1]
    if size < IN_TURN_FROM:
        return contract(form, x)
    out = np.empty((len(form.matrix), size))
    for lo in range(0, size, IN_TURN_CHUNK):
        hi = min(lo + IN_TURN_CHUNK, size)
        _contract_in_turn(form.plan, x[:, lo:hi], out[:, lo:hi])
    return out


def _contract_in_turn(plan: tuple, x: np.ndarray, out: np.ndarray) -> None:
    """:func:`contract` of a linear map row by row and term by term into ``out``: the same
    weighted terms added in the same order (the ``−0.0`` padding, which changes no sum, left
    out)."""
    for row, terms in zip(out, plan):
        (c, w), rest = terms[0], terms[1:]
        np.multiply(x[c], w, out=row)
        for c, w in rest:
            if w == 1.0:
                row += x[c]
            elif w == -1.0:
                row -= x[c]
            else:
                row += x[c] * w


#: Columns from which :func:`bilinear` broadcasts the terms' constant factors.
NARROW_FROM = 64
#: Columns from which :func:`bilinear` and :func:`linear` compute row by row and term by term
#: (:func:`_in_turn`), rather than gathering every term at once: 1.2–2× faster on thousands
#: of columns, and a hundred numpy calls, too many for one motion.
IN_TURN_FROM = 2048
#: Columns at a time in :func:`_in_turn`, so that the rows stay in cache.
IN_TURN_CHUNK = 4096


def contract(form: Structure, outer: np.ndarray) -> np.ndarray:
    """Each output row's non-zero terms of an outer product ``(n_a, n_b, ...)`` (or, for a
    linear map, of its input ``(n_in, ...)``), summed in the order of the columns:
    ``(n_out, N)``."""
    terms = outer.reshape(form.matrix.shape[1], -1).take(form.columns, axis=0)  # (m, n_out, N)
    terms *= form.weights
    return sum_terms(terms)  # then term by term: contiguous additions


#: Up to this many products, :func:`dots` adds them with one ``numpy.add.accumulate``.
DOTS_ACCUMULATE_UP_TO = 64


def dots(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Dot products ``a·b`` of vectors ``(..., n)`` (broadcast), summed term by term in order:
    ``((a0 b0 + a1 b1) + a2 b2) + …``.

    The order does not depend on the arrays' shapes or memory layouts, so an element of a
    batch is bit for bit the element computed alone. ``numpy.sum(a * b, axis=-1)`` and
    ``einsum`` are not: they sum a contiguous last axis in another order (pairwise, or in
    vector registers) than a strided one, and a batch's arrays are often laid out otherwise
    than one element's.
    """
    if not isinstance(a, np.ndarray) or a.dtype != float:
        a = np.asarray(a, dtype=float)
    if not isinstance(b, np.ndarray) or b.dtype != float:
        b = np.asarray(b, dtype=float)
    products = a * b
    if products.shape[-1] == 1:
        return products[..., 0]
    if products.size <= DOTS_ACCUMULATE_UP_TO:  # one call: as sum_terms
        sums = np.add.accumulate(products, axis=-1, out=products)
        return sums[..., -1] if sums.ndim > 1 else sums[-1]
    out = products[..., 0] + products[..., 1]
    for k in range(2, products.shape[-1]):
        out += products[..., k]
    return out


def quat_mul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Hamilton product ``a b`` of quaternions ``(..., 4)``, scalar first (by its structure
    matrix :data:`HAMILTON`, made from :func:`_hamilton`)."""
    return vector_form(HAMILTON, a, b)


def vector_form(form: Structure, a, b) -> np.ndarray:
    """:func:`bilinear` of vectors ``(..., n)``, components last: moved first and back, as
    views."""
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    out = bilinear(form, a.transpose(_last_first(a.ndim)), b.transpose(_last_first(b.ndim)))
    return out.transpose(tuple(range(1, out.ndim)) + (0,))


def _last_first(ndim: int) -> tuple:
    return (ndim - 1,) + tuple(range(ndim - 1))


def _hamilton(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The Hamilton product's formula, for :data:`HAMILTON`."""
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    a0, a1, a2, a3 = _components(a)
    b0, b1, b2, b3 = _components(b)
    return _vectors(
        a0 * b0 - a1 * b1 - a2 * b2 - a3 * b3,
        a0 * b1 + a1 * b0 + a2 * b3 - a3 * b2,
        a0 * b2 - a1 * b3 + a2 * b0 + a3 * b1,
        a0 * b3 + a1 * b2 - a2 * b1 + a3 * b0,
    )


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The vector product ``a × b`` of vectors ``(..., 3)`` (:func:`numpy.cross` in fewer
    operations)."""
    a1, a2, a3 = _components(np.asarray(a, dtype=float))
    b1, b2, b3 = _components(np.asarray(b, dtype=float))
    return _vectors(a2 * b3 - a3 * b2, a3 * b1 - a1 * b3, a1 * b2 - a2 * b1)


def quat_conj(p: np.ndarray) -> np.ndarray:
    """Conjugate ``p̄ = p0 − p1 i − p2 j − p3 k`` of quaternions ``(..., 4)``."""
    p = np.asarray(p, dtype=float)
    return p * np.array([1.0, -1.0, -1.0, -1.0])


def dq_mul(g: np.ndarray, h: np.ndarray) -> np.ndarray:
    """Dual-quaternion product ``g h`` of Study vectors ``(..., 8)``.

    ``(p + ε q)(r + ε s) = p r + ε (p s + q r)``. Composition of displacements: the pose
    ``κ(g h)`` is ``κ(g) ∘ κ(h)``.
    """
    g = np.asarray(g, dtype=float)
    h = np.asarray(h, dtype=float)
    p, q = g[..., :4], g[..., 4:]
    r, s = h[..., :4], h[..., 4:]
    return np.concatenate([quat_mul(p, r), quat_mul(p, s) + quat_mul(q, r)], axis=-1)


def rotation_numerators(p: np.ndarray, r: np.ndarray | None = None) -> np.ndarray:
    """The nine entries ``a11 … a33`` of eq. 4 (not divided by ``Δ``), row by row.

    With one argument this is the quadratic form of eq. 4 (with ``docs/math.md``, correction 2:
    ``a32 = 2(p0 p1 + p2 p3)``). With two arguments it is the symmetric bilinear form whose
    diagonal is eq. 4, so that for ``p(t) = (1−t) p + t r`` the Bernstein coefficients of the
    numerators are ``B(p, p), B(p, r), B(r, r)``.

    Parameters
    ----------
    p, r : array_like, shape (..., 4)

    Returns
    -------
    ndarray, shape (..., 9)
    """
    p = np.asarray(p, dtype=float)
    r = p if r is None else np.asarray(r, dtype=float)
    p0, p1, p2, p3 = _components(p)
    r0, r1, r2, r3 = (p0, p1, p2, p3) if r is p else _components(r)
    return _vectors(
        p0 * r0 + p1 * r1 - p2 * r2 - p3 * r3,
        p1 * r2 + p2 * r1 - p0 * r3 - p3 * r0,
        p0 * r2 + p2 * r0 + p1 * r3 + p3 * r1,
        p0 * r3 + p3 * r0 + p1 * r2 + p2 * r1,
        p0 * r0 - p1 * r1 + p2 * r2 - p3 * r3,
        p2 * r3 + p3 * r2 - p0 * r1 - p1 * r0,
        p1 * r3 + p3 * r1 - p0 * r2 - p2 * r0,
        p0 * r1 + p1 * r0 + p2 * r3 + p3 * r2,
        p0 * r0 - p1 * r1 - p2 * r2 + p3 * r3,
    )


def translation_numerators(p: np.ndarray, q: np.ndarray) -> np.ndarray:
    """``p q̄ − q p̄ = 2 vec(p q̄)``, the translation of κ(p + εq) times ``Δ``.

    Bilinear in ``(p, q)``; these are the ``a_1, a_2, a_3`` of eq. 5. The translation of
    ``κ(p + εq)`` is this divided by ``Δ = p p̄``.

    Parameters
    ----------
    p, q : array_like, shape (..., 4)

    Returns
    -------
    ndarray, shape (..., 3)
    """
    p = np.asarray(p, dtype=float)
    q = np.asarray(q, dtype=float)
    p0, p1, p2, p3 = _components(p)
    q0, q1, q2, q3 = _components(q)
    # vec(p q̄) with q̄ = (q0, -q1, -q2, -q3)
    return 2.0 * _vectors(
        -p0 * q1 + p1 * q0 - p2 * q3 + p3 * q2,
        -p0 * q2 + p1 * q3 + p2 * q0 - p3 * q1,
        -p0 * q3 - p1 * q2 + p2 * q1 + p3 * q0,
    )


def check_study(h: np.ndarray, *, tol: float = STUDY_TOL, on_quadric: bool = True) -> np.ndarray:
    """Validate Study parameters ``(..., 8)`` and return them as a float array.

    Checks that every entry is finite, that the primal part ``p`` is not zero (``h`` is not on
    the exceptional generator E) and, when ``on_quadric`` is true, the Study condition
    ``p q̄ + q p̄ = 2 p·q = 0`` (eq. 2) with the residual ``|p·q| / (|p| (|p| + |q|))``.

    Raises
    ------
    PoseError
        With the measured residual and the tolerance.
    """
    h = np.asarray(h, dtype=float)
    if h.shape[-1:] != (8,):
        raise PoseError(f"Study parameters need 8 numbers, got shape {h.shape}")
    if not np.all(np.isfinite(h)):
        raise PoseError("Study parameters contain NaN or infinity")
    h = unit_scale(
        h, extreme_only=True
    )  # homogeneous: Study parameters of 1e300 or 1e-300 are poses too
    p, q = h[..., :4], h[..., 4:]
    norm_p = np.linalg.norm(p, axis=-1)
    norm_q = np.linalg.norm(q, axis=-1)
    scale = np.maximum(norm_p, norm_q)
    if np.any(norm_p <= 1e-300) or np.any(norm_p <= 1e-14 * scale):
        raise PoseError(
            "Study parameters with primal part p = 0 lie on the exceptional generator E "
            f"and are no pose (|p| = {np.min(norm_p):.3g})"
        )
    if on_quadric:
        residual = np.abs(np.sum(p * q, axis=-1)) / (norm_p * (norm_p + norm_q))
        worst = float(np.max(residual))
        if worst > tol:
            raise PoseError(
                f"Study parameters violate the Study condition p·q = 0: residual {worst:.3g} "
                f"exceeds tolerance {tol:g}"
            )
    return h


def study_from_quat_trans(quat_wxyz: np.ndarray, translations: np.ndarray) -> np.ndarray:
    """Study parameters ``(..., 8)`` from quaternions ``p`` and translations ``t``: ``q = −½ t p``
    (eq. 6).

    For a unit ``p`` this is eq. 6; for any ``p ≠ 0`` it gives the point of the Study quadric with
    primal part ``p`` whose κ-image has the translation ``t``.
    """
    p = np.asarray(quat_wxyz, dtype=float)
    t = np.asarray(translations, dtype=float)
    t1, t2, t3 = _components(t)
    p0, p1, p2, p3 = _components(p)
    # q = -1/2 (0, t) p
    q = -0.5 * np.stack(
        [
            -t1 * p1 - t2 * p2 - t3 * p3,
            t1 * p0 + t2 * p3 - t3 * p2,
            -t1 * p3 + t2 * p0 + t3 * p1,
            t1 * p2 - t2 * p1 + t3 * p0,
        ],
        axis=-1,
    )
    return np.concatenate([np.broadcast_to(p, q.shape), q], axis=-1)


def kappa(h: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The extended kinematic map κ: P^7 minus E → SE(3) (section 3, eq. 3–5).

    Parameters
    ----------
    h : array_like, shape (..., 8)
        Study parameters ``(p0, p1, p2, p3, q0, q1, q2, q3)`` with ``p ≠ 0``. They need not
        satisfy the Study condition.

    Returns
    -------
    rotations : ndarray, shape (..., 3, 3)
    translations : ndarray, shape (..., 3)
    """
    h = np.asarray(h, dtype=float)
    p, q = h[..., :4], h[..., 4:]
    delta = dots(p, p)
    rot = rotation_numerators(p) / delta[..., None]
    trans = translation_numerators(p, q) / delta[..., None]
    return rot.reshape(h.shape[:-1] + (3, 3)), trans


def kappa_fiber_points(h: np.ndarray, s: np.ndarray) -> np.ndarray:
    """Points ``h + s ε p`` of the κ-fiber of ``h`` (``docs/math.md``, correction 1).

    Projectively, the fiber is the line ``h ∨ εp`` without the point ``εp`` on E. Every point
    maps back to ``κ(h)`` because ``p q̄ − q p̄`` does not change under ``q → q + s p``.

    Parameters
    ----------
    h : array_like, shape (8,)
    s : array_like, shape (k,)

    Returns
    -------
    ndarray, shape (k, 8)
    """
    h = np.asarray(h, dtype=float)
    s = np.atleast_1d(np.asarray(s, dtype=float))
    out = np.broadcast_to(h, s.shape + (8,)).copy()
    out[..., 4:] += s[..., None] * h[..., :4]
    return out


def kappa_fiber_direction(h: np.ndarray) -> np.ndarray:
    """The direction ``εp = (0, 0, 0, 0, p0, p1, p2, p3)`` of the κ-fiber of ``h``."""
    h = np.asarray(h, dtype=float)
    return np.concatenate([np.zeros_like(h[..., :4]), h[..., :4]], axis=-1)


# The structure matrices of a2b's bilinear forms, each made from its formula above.

#: ``(a, b) ↦ a b``: the Hamilton product of quaternions ``(4, ...)``.
HAMILTON = structure_matrix(_hamilton, 4, 4)
#: ``(u, p) ↦ (0, u) p``: a pure quaternion of the vector ``u`` times ``p`` (the screw's
#: second end ``u pA``).
AXIS_TIMES = structure_matrix(
    lambda u, p: _hamilton(np.concatenate([np.zeros(u.shape[:-1] + (1,)), u], axis=-1), p), 3, 4
)
#: ``(b, a) ↦ b ā``: the rotation ``pB p̄A`` from A's to B's, of quaternions ``(4, ...)``.
TURN = structure_matrix(lambda b, a: _hamilton(b, quat_conj(a)), 4, 4)
#: ``(a, b) ↦ a × b`` of vectors ``(3, ...)``.
CROSS = structure_matrix(cross, 3, 3)


#: Eq. 4's nine rotation numerators as the symmetric bilinear form ``B(p, r)``, with the
#: denominator ``p·r`` as a tenth row: ``B(p, p) / (p·p)`` is the rotation of ``p``.
def rotation_rows(p: np.ndarray, r: np.ndarray) -> np.ndarray:
    """:func:`rotation_numerators` of ``p, r`` ``(..., 4)`` with the denominator ``p·r`` as a
    tenth entry: ``(..., 10)``, the formula of :data:`ROTATION`."""
    return np.concatenate([rotation_numerators(p, r), dots(p, r)[..., None]], axis=-1)


ROTATION = structure_matrix(rotation_rows, 4, 4)
#: ``(m, v) ↦ m v`` for the nine entries of 3x3 matrices ``m`` (row by row) and vectors ``v``.
MATRIX_VECTOR = structure_matrix(lambda m, v: (m.reshape(-1, 3, 3) @ v[..., None])[..., 0], 9, 3)
