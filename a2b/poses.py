"""Poses: 4x4 matrices ⇄ unit quaternion plus translation ⇄ Study parameters.

Array conventions (trailing dimensions, any number of leading ones):

* ``(..., 4, 4)`` homogeneous matrices in the **robotics layout** ``[[R, t], [0, 0, 0, 1]]``.
  The paper writes ``[[1, 0ᵀ], [t, R]]`` (eq. 1); that layout is read or written only when
  asked for with ``layout="paper"``. A rotation about z is valid in both layouts and means a
  different pose in each, so a2b never guesses.
* ``(..., 4)`` quaternions ``quat_wxyz = (w, x, y, z)``, scalar first.
* ``(..., 3)`` translations.
* ``(..., 8)`` Study parameters ``(p0, p1, p2, p3, q0, q1, q2, q3)``.

Validators (``check_*``) raise :class:`a2b.A2bError` with the measured residual and the
tolerance; they never repair their input.
"""

from __future__ import annotations

import math

import numpy as np

from .elements import anywhere, as_numbers, everywhere, unit_scale
from .errors import PoseError
from .study import (
    NARROW_FROM,
    ROTATION,
    STUDY_TOL,
    Structure,
    bilinear,
    check_study,
    dots,
    kappa,
    linear,
    quat_mul,
    sparse_rows,
    structure_matrix,
    study_from_quat_trans,
    vector_form,
)

#: Tolerance of ``max |R Rᵀ − I|`` and ``|det R − 1|`` for rotation blocks of input matrices.
ORTHO_TOL = 1e-9

LAYOUTS = ("robotics", "paper")


def _finite(a: np.ndarray, what: str) -> None:
    if not everywhere(np.isfinite(a)):
        raise PoseError(f"{what} contains NaN or infinity")


def check_rotations(rotations: np.ndarray, *, tol: float = ORTHO_TOL) -> np.ndarray:
    """Validate rotation matrices ``(..., 3, 3)``: finite, orthogonal and ``det R = +1``.

    Raises
    ------
    PoseError
        If ``max |R Rᵀ − I| > tol`` or ``|det R − 1| > tol``, stating the residual.
    """
    r = np.asarray(rotations, dtype=float)
    if r.shape[-2:] != (3, 3):
        raise PoseError(f"a rotation block must be 3x3, got shape {r.shape}")
    _finite(r, "the rotation block")
    _check_rotation_entries(_entries(r), tol)
    return r


def _check_rotation_entries(entries: np.ndarray, tol: float, forms=None) -> None:
    """:func:`check_rotations` of finite rotation blocks, from their :func:`_entries` (and
    the rows of :data:`RIGIDITY` of them, where the caller has them)."""
    orthogonality, det = _rigidity(entries, forms)
    residual = float(np.maximum.reduce(orthogonality, axis=None, initial=0.0))
    if residual > tol:
        raise PoseError(
            f"the rotation block is not orthogonal: max |R Rᵀ − I| = {residual:.3g} "
            f"exceeds tolerance {tol:g}"
            + (
                f"; if it is a rotation rounded to a few digits, --orthonormalize (or "
                f"a2b.poses.orthonormalize) projects it onto the nearest rotation, up to "
                f"{REPAIR_TOL:g}"
                if residual <= REPAIR_TOL
                else ""
            )
        )
    det_residual = float(np.maximum.reduce(np.abs(det - 1.0), axis=None, initial=0.0))
    if not det_residual <= min(tol, 1.0) and anywhere(det < 0):  # |det − 1| > 1 where det < 0
        raise PoseError(
            f"the rotation block has determinant {float(np.min(det)):.6g}: a reflection, not a "
            f"rotation"
        )
    if det_residual > tol:
        raise PoseError(
            f"the rotation block has |det R − 1| = {det_residual:.3g}, exceeding tolerance {tol:g}"
        )


#: How far from orthogonal a rotation block may be for :func:`orthonormalize` to repair it:
#: six significant digits (KITTI's ``%e``) leave about 1e-6.
REPAIR_TOL = 1e-4


def orthogonality_residuals(rotations: np.ndarray) -> np.ndarray:
    """``max |R Rᵀ − I|`` of each rotation block ``(..., 3, 3)``: shape ``...``."""
    r = np.asarray(rotations, dtype=float)
    with np.errstate(all="ignore"):
        return _orthogonality(_entries(r))


def orthonormalize(poses, *, tol: float = REPAIR_TOL) -> np.ndarray:
    """Project nearly orthogonal rotation blocks onto the nearest rotations (an explicit repair).

    ``poses`` is rotation blocks ``(..., 3, 3)`` or robotics matrices ``(..., 4, 4)``, whose
    translations are kept. Each block ``R = U Σ Vᵀ`` becomes ``U Vᵀ``, the rotation nearest
    to it in the Frobenius norm: what a matrix typed or stored with a few digits stood for.

    Raises
    ------
    PoseError
        If a block is not finite, is farther than ``tol`` from orthogonal
        (``max |R Rᵀ − I| > tol``: no longer a rounded rotation), or is a reflection.
    """
    m = as_numbers(poses, "a pose matrix", PoseError)
    if m.shape[-2:] not in ((3, 3), (4, 4)):
        raise PoseError(f"expected 3x3 rotation blocks or 4x4 poses, got shape {m.shape}")
    _finite(m, "the pose matrix")
    r = m[..., :3, :3]
    residual = orthogonality_residuals(r)
    if np.any(residual > tol):
        worst = float(residual.max())
        raise PoseError(
            f"the rotation block is too far from orthogonal to repair: max |R Rᵀ − I| = "
            f"{worst:.3g} exceeds the repair tolerance {tol:g}"
        )
    if np.any(determinants(r) < 0):
        raise PoseError("the rotation block is a reflection (det R < 0): no rotation is near it")
    u, _, vt = np.linalg.svd(r)
    out = m.copy()
    out[..., :3, :3] = u @ vt
    return out


def _entries(r: np.ndarray) -> np.ndarray:
    """The entries ``r11, r12, …, r33`` of matrices ``(..., 3, 3)`` as contiguous rows ``(9,
    ...)``: one transposing copy, after which every operation on an entry runs over one
    contiguous array (several times faster than on the strided entries of a stack of 3x3)."""
    flat = np.asarray(r, dtype=float).reshape(np.shape(r)[:-2] + (9,))
    return np.ascontiguousarray(flat.transpose((flat.ndim - 1,) + tuple(range(flat.ndim - 1))))


def _orthogonality(entries: np.ndarray, gram: np.ndarray | None = None) -> np.ndarray:
    """``max |R Rᵀ − I|`` of each matrix, from its :func:`_entries` (and the six entries of
    ``R Rᵀ`` on and above its diagonal, where the caller has them): shape ``...``."""
    if gram is None:
        gram = bilinear(GRAM, entries, entries)
    gram -= _GRAM_IDENTITY.reshape((6,) + (1,) * (gram.ndim - 1))
    return np.maximum.reduce(np.abs(gram, out=gram), axis=0)


def _rigidity(entries: np.ndarray, rows=None) -> tuple[np.ndarray, np.ndarray]:
    """:func:`_orthogonality` and :func:`_determinants` of rotation blocks: for a few, from
    one bilinear form (:data:`RIGIDITY`, or its ``rows`` where the caller has them), for
    many from two (without its padded terms)."""
    if rows is None:
        if entries[0].size > NARROW_FROM:
            return _orthogonality(entries), _determinants(entries)
        rows = bilinear(RIGIDITY, entries, entries)
    return _orthogonality(entries, rows[:6]), _determinants(entries, rows[6:])


def determinants(r: np.ndarray) -> np.ndarray:
    """``det R`` of matrices ``(..., 3, 3)`` by cofactors along the first row."""
    return _determinants(_entries(r))


def _determinants(entries: np.ndarray, cofactors: np.ndarray | None = None) -> np.ndarray:
    """``det R`` from the :func:`_entries` of matrices (and their first row's cofactors,
    where the caller has them)."""
    if cofactors is None:
        cofactors = bilinear(COFACTORS, entries[3:], entries[3:])
    return entries[0] * cofactors[0] - entries[1] * cofactors[1] + entries[2] * cofactors[2]


def _gram(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The entries ``(0,0), (0,1), (0,2), (1,1), (1,2), (2,2)`` of ``A Bᵀ`` for the entries
    ``(..., 9)`` of 3x3 matrices, row by row: with ``B = A``, those of ``A Aᵀ`` that differ."""
    rows_a, rows_b = a.reshape(a.shape[:-1] + (3, 3)), b.reshape(b.shape[:-1] + (3, 3))
    pairs = ((0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))
    return np.stack([dots(rows_a[..., i, :], rows_b[..., j, :]) for i, j in pairs], axis=-1)


def _cofactors(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """The cofactors of the first row of 3x3 matrices, from the entries ``d … i`` ``(..., 6)``
    of their last two rows: ``(e i − f h, d i − f g, d h − e g)``."""
    d, e, f, g, h, i = (x[..., k] for k in range(6))
    d2, e2, f2, g2, h2, i2 = (y[..., k] for k in range(6))
    return np.stack([e * i2 - f * h2, d * i2 - f * g2, d * h2 - e * g2], axis=-1)


#: The structure matrices (:func:`a2b.study.structure_matrix`) of :func:`_gram` and
#: :func:`_cofactors`, so that the checks of many rotations are a few operations over all.
GRAM = structure_matrix(_gram, 9, 9)
COFACTORS = structure_matrix(_cofactors, 6, 6)
#: Both in one form of the nine entries of a matrix with themselves: the six of :data:`GRAM`,
#: then the three cofactors (their terms in the same order; each padded with ``−0.0 r11²``,
#: which changes no sum, signed zeros included).
RIGIDITY = structure_matrix(
    lambda a, b: np.concatenate([_gram(a, b), _cofactors(a[..., 3:], b[..., 3:])], axis=-1),
    9,
    9,
    padding=-0.0,
)
_GRAM_IDENTITY = np.array([1.0, 0.0, 0.0, 1.0, 0.0, 1.0])


def valid_matrices(matrices: np.ndarray, tol: float = ORTHO_TOL) -> np.ndarray:
    """Which robotics matrices ``(..., 4, 4)`` :func:`check_matrices` accepts, as a mask.

    The same tests as :func:`check_matrices`, element by element, for readers that check
    many poses at once and read only the failing ones again, for their message.
    """
    m = np.asarray(matrices, dtype=float)
    with np.errstate(all="ignore"):
        ok = np.isfinite(m).all(axis=(-2, -1)) & (m[..., 3, :] == [0.0, 0.0, 0.0, 1.0]).all(axis=-1)
        entries = _entries(m[..., :3, :3])
        ortho, det = _rigidity(entries)
        return ok & (ortho <= tol) & (det >= 0) & (np.abs(det - 1.0) <= tol)


def pose_matrices(poses):
    """Poses in the forms the API accepts, as robotics matrices ``(..., 4, 4)`` to validate.

    * an array of matrices ``(..., 4, 4)`` (returned as it is);
    * an object with ``as_matrix()``: scipy's ``RigidTransform`` (4x4) or ``Rotation`` (3x3, no
      translation);
    * a tuple ``(quat_wxyz, translation)`` of shapes ``(..., 4)`` and ``(..., 3)``: a2b's
      quaternion order, w first (a scipy quaternion is x, y, z, w: give the ``Rotation``).
    """
    as_matrix = getattr(poses, "as_matrix", None)
    if callable(as_matrix) and not isinstance(poses, np.ndarray):
        m = np.asarray(as_matrix(), dtype=float)
        if m.shape[-2:] == (3, 3):
            return matrices_from_rot_trans(m, np.zeros(m.shape[:-1]))
        return m
    if isinstance(poses, tuple) and len(poses) == 2:
        quat, trans = poses
        if np.shape(quat)[-1:] == (4,) and np.shape(trans)[-1:] == (3,):
            return matrices_from_quat_trans(quat, trans)
    return poses


def check_matrices(
    matrices: np.ndarray, *, layout: str = "robotics", tol: float = ORTHO_TOL
) -> np.ndarray:
    """Validate homogeneous matrices ``(..., 4, 4)`` and return them in the robotics layout.

    Parameters
    ----------
    matrices : array_like, shape (..., 4, 4)
    layout : {"robotics", "paper"}
        ``"robotics"``: ``[[R, t], [0, 0, 0, 1]]``. ``"paper"``: ``[[1, 0ᵀ], [t, R]]`` (eq. 1).
    tol : float
        Tolerance for orthogonality and the determinant of ``R``.

    Returns
    -------
    ndarray, shape (..., 4, 4)
        The same poses, robotics layout.

    Raises
    ------
    PoseError
        For a wrong shape, NaN or infinity, a bad constant row or column, a non-orthogonal
        rotation block or ``det R = −1``.
    """
    return _checked(as_numbers(matrices, "a pose matrix", PoseError), layout, tol)


#: The constant rows of pose matrices in the robotics and the paper's layout.
_BOTTOM_ROW, _TOP_ROW = np.array([0.0, 0.0, 0.0, 1.0]), np.array([1.0, 0.0, 0.0, 0.0])


def _checked(m: np.ndarray, layout: str, tol: float, entries=None) -> np.ndarray:
    """:func:`check_matrices` of a float array; ``entries``, the rotation blocks'
    :func:`_entries` where the caller has them already."""
    m = _checked_rows(m, layout)
    if entries is None:
        entries = _entries(m[..., :3, :3])
    _check_rotation_entries(entries, tol)  # finite already
    return m


def _checked_rows(m: np.ndarray, layout: str) -> np.ndarray:
    """The tests of :func:`check_matrices` before the rotation blocks': the shape, finite
    entries, the constant row; the matrices in the robotics layout."""
    if m.shape[-2:] != (4, 4):
        raise PoseError(f"a pose matrix must be 4x4, got shape {m.shape}")
    _finite(m, "the pose matrix")
    if layout == "robotics":
        fixed, expected, where = m[..., 3, :], _BOTTOM_ROW, "bottom row"
    elif layout == "paper":
        fixed, expected, where = m[..., 0, :], _TOP_ROW, "top row"
    else:
        raise PoseError(f"unknown matrix layout {layout!r}; expected one of {LAYOUTS}")
    if anywhere(fixed != expected):  # exactly; the residual is measured for the message
        residual = float(np.abs(fixed - expected).max())
        raise PoseError(
            f"the {where} of a {layout}-layout pose matrix must be exactly "
            f"{expected.tolist()}; it differs by {residual:.3g}"
            + (
                " (is this the paper's layout? say so with layout: paper)"
                if layout == "robotics"
                else ""
            )
        )
    return robotics_from_paper(m) if layout == "paper" else m


#: Poses that :func:`check_matrices_and_quaternions` takes at a time, so that its work arrays
#: stay in cache: over 2·10⁵ poses at once it took twice as long.
POSE_CHUNK = 8192


def check_matrices_and_quaternions(matrices: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """:func:`check_matrices` (robotics layout) and the :func:`quaternions_from_rotations` of
    the poses, ``(..., 4)``, from one component-major copy of the rotation blocks, in chunks
    of :data:`POSE_CHUNK` poses: what :func:`a2b.motion` needs of its poses.

    An array of floats is used as it is, not copied (:func:`a2b.motion` passes a stack it
    made). Where a chunk fails a check, the poses are checked again as a whole, so that the
    error is the one :func:`check_matrices` gives (its residual the largest of all)."""
    m = np.asarray(matrices)
    if m.dtype != np.float64:
        m = as_numbers(m, "a pose matrix", PoseError)
    if m.shape[-2:] != (4, 4):
        raise PoseError(f"a pose matrix must be 4x4, got shape {m.shape}")
    if m.size <= 16 * POSE_CHUNK:
        return m, _checked_quaternions(m)
    flat = m.reshape(-1, 4, 4)
    quaternions = np.empty((len(flat), 4))
    try:
        for lo in range(0, len(flat), POSE_CHUNK):
            quaternions[lo : lo + POSE_CHUNK] = _checked_quaternions(flat[lo : lo + POSE_CHUNK])
    except PoseError:
        _checked(m, "robotics", ORTHO_TOL)  # the message of the whole
        raise
    return m, quaternions.reshape(m.shape[:-2] + (4,))


def _checked_quaternions(m: np.ndarray) -> np.ndarray:
    """:func:`check_matrices` of robotics matrices ``(..., 4, 4)`` of floats, and their
    quaternions ``(..., 4)``, from one component-major copy of the rotation blocks."""
    x = _shepperd_input(m[..., :3, :3])
    if x.shape[1] > NARROW_FROM:  # many: the checks' forms and Shepperd's map apart
        _checked(m, "robotics", ORTHO_TOL, x[1:])
        return _quaternions(linear(_SHEPPERD, x), m.shape[:-2])
    _checked_rows(m, "robotics")
    forms = bilinear(_POSE_FORMS, x, x)  # RIGIDITY's rows, then Shepperd's terms
    _check_rotation_entries(x[1:], ORTHO_TOL, forms[:9])
    return _quaternions(forms[9:], m.shape[:-2])


def robotics_from_paper(matrices: np.ndarray) -> np.ndarray:
    """Convert ``[[1, 0ᵀ], [t, R]]`` (eq. 1) to ``[[R, t], [0, 0, 0, 1]]``, shape ``(..., 4,
    4)``."""
    m = np.asarray(matrices, dtype=float)
    out = np.zeros_like(m)
    out[..., :3, :3] = m[..., 1:, 1:]
    out[..., :3, 3] = m[..., 1:, 0]
    out[..., 3, 3] = 1.0
    return out


def paper_from_robotics(matrices: np.ndarray) -> np.ndarray:
    """Convert ``[[R, t], [0, 0, 0, 1]]`` to the paper's ``[[1, 0ᵀ], [t, R]]``, ``(..., 4, 4)``."""
    m = np.asarray(matrices, dtype=float)
    out = np.zeros_like(m)
    out[..., 1:, 1:] = m[..., :3, :3]
    out[..., 1:, 0] = m[..., :3, 3]
    out[..., 0, 0] = 1.0
    return out


def check_quaternions(quat_wxyz: np.ndarray) -> np.ndarray:
    """Validate quaternions ``(..., 4)`` (w, x, y, z) and return them normalised.

    Quaternions are homogeneous, as in the paper: any non-zero multiple of ``p`` is the same
    rotation. So a non-unit quaternion is accepted and divided by its norm; a zero or
    non-finite one is an error.

    Raises
    ------
    PoseError
        For a wrong shape, NaN or infinity, or a zero quaternion.
    """
    q = np.asarray(quat_wxyz, dtype=float)
    if q.shape[-1:] != (4,):
        raise PoseError(f"a quaternion needs 4 numbers (w, x, y, z), got shape {q.shape}")
    _finite(q, "the quaternion")
    q = unit_scale(q)  # homogeneous: [1e-200, 0, 0, 0] is the identity
    norm = np.linalg.norm(q, axis=-1)
    if np.any(norm == 0.0) or np.any(~np.isfinite(norm)):
        raise PoseError(
            f"the quaternion has norm {float(np.min(norm)):.3g}; a rotation needs a non-zero, "
            f"finite quaternion"
        )
    return q / norm[..., None]


def _shepperd_map() -> Structure:
    """The linear map from ``(1, a11, a12, …, a33)`` to the 16 entries of eq. 9's four ratio
    rows (row by row) and the four diagonal terms of eq. 7 that choose among them."""
    one, e = 0, {f"a{i}{j}": 1 + 3 * (i - 1) + (j - 1) for i in (1, 2, 3) for j in (1, 2, 3)}

    def row(*terms):
        out = np.zeros(10)
        for sign, name in terms:
            out[one if name == "1" else e[name]] += sign
        return out

    w_x, w_y, w_z = ((1, "a32"), (-1, "a23")), ((1, "a13"), (-1, "a31")), ((1, "a21"), (-1, "a12"))
    x_y, x_z, y_z = ((1, "a21"), (1, "a12")), ((1, "a31"), (1, "a13")), ((1, "a32"), (1, "a23"))
    signs = ((1, 1, 1), (1, -1, -1), (-1, 1, -1), (-1, -1, 1))
    diagonals = [tuple(zip(sign, ("a11", "a22", "a33"))) for sign in signs]
    # the ratio rows' distinct entries (the 4x4 of eq. 9 is symmetric): see _RATIO_ROWS
    entries = [((1, "1"),) + d for d in diagonals] + [w_x, w_y, w_z, x_y, x_z, y_z]
    rows = [row(*terms) for terms in entries] + [row(*d) for d in diagonals]
    return sparse_rows(np.array(rows), padding=-0.0)


#: :func:`_shepperd_map` as a :class:`a2b.study.Structure`: one contraction gives every entry
#: of the ratio rows and every diagonal term of all rotations at once, each sum in the order
#: eq. 7 and 9 write it.
_SHEPPERD = _shepperd_map()
#: :data:`RIGIDITY` and :data:`_SHEPPERD` as one bilinear form of ``x = (1, a11, …, a33)``
#: with itself, for a few poses: Shepperd's terms ``w x_i`` as ``w x_i x_0`` (``x_0 = 1``,
#: exactly the same numbers), every row padded with ``−0.0 x_0 x_0``, which changes no sum.
_POSE_FORMS = structure_matrix(
    lambda a, b: np.concatenate(
        [
            _gram(a[..., 1:], b[..., 1:]),
            _cofactors(a[..., 4:], b[..., 4:]),
            (a @ _SHEPPERD.matrix.T) * b[..., :1],
        ],
        axis=-1,
    ),
    10,
    10,
    padding=-0.0,
)
#: Row ``k`` of eq. 9 as rows of :data:`_SHEPPERD`'s output: its diagonal entry ``k``, the
#: off-diagonal ones 4–9 (``wx, wy, wz, xy, xz, yz``) elsewhere.
_RATIO_ROWS = np.array([[0, 4, 5, 6], [4, 1, 7, 8], [5, 7, 2, 9], [6, 8, 9, 3]])


def quaternions_from_rotations(rotations: np.ndarray) -> np.ndarray:
    """Unit quaternions ``(..., 4)`` (w, x, y, z) of rotation matrices ``(..., 3, 3)``.

    Uses the ratio row of eq. 9 whose diagonal term (eq. 7) is largest, as in Shepperd's
    method, so it never divides by a small number and is exact for half-turns. The sign is
    fixed so that ``w > 0``, or for a half-turn (``w = 0``) so that the first non-zero
    component is positive.

    References
    ----------
    Schröcker, *From A to B*, eq. 7–9.
    """
    r = np.asarray(rotations, dtype=float)
    return _quaternions(linear(_SHEPPERD, _shepperd_input(r)), r.shape[:-2])


def _shepperd_input(r: np.ndarray) -> np.ndarray:
    """``(1, a11, a12, …, a33)`` of rotation blocks ``(..., 3, 3)`` as contiguous rows
    ``(10, N)``: Shepperd's map's input, and below its first row the blocks' entries."""
    count = math.prod(r.shape[:-2])
    x = np.empty((10, count))
    x[0] = 1.0
    x[1:].reshape(3, 3, count)[...] = r.reshape(count, 3, 3).transpose(1, 2, 0)
    return x


def _quaternions(terms: np.ndarray, shape: tuple) -> np.ndarray:
    """:func:`quaternions_from_rotations` from :data:`_SHEPPERD`'s terms ``(14, count)`` of
    the :func:`_shepperd_input`."""
    count = terms.shape[1]
    best = terms[10:].argmax(axis=0)  # the first largest, as a strict > from the first row
    if count <= 64:  # a few rotations: one index, the fewest numpy calls
        p = terms[_RATIO_ROWS[best], np.arange(count)[:, None]]  # (count, 4)
    else:  # many: contiguous passes, component-major
        chosen = _RATIO_ROWS.T[:, best]  # (4, count): the row of terms of each component
        chosen *= count
        chosen += np.arange(count)
        p = terms.reshape(-1).take(chosen).T  # (count, 4), component-major in memory
    p /= np.sqrt(dots(p, p))[:, None]
    return canonical_sign(p.reshape(shape + (4,)))


def canonical_sign(p: np.ndarray) -> np.ndarray:
    """Flip vectors ``(..., n)`` (quaternions, axis directions) so that the first non-zero
    component is positive; zero vectors stay as they are."""
    p = np.asarray(p, dtype=float)
    first = p[..., 0]
    if everywhere(first > 0.0):  # the common case: nothing to flip
        return p
    if everywhere(first != 0.0):  # the first component decides everywhere
        flip = first < 0.0
    else:
        flip = p[..., -1] < 0.0  # the last component's sign, unless an earlier one is non-zero
        for i in range(p.shape[-1] - 2, -1, -1):
            flip = np.where(p[..., i] == 0.0, flip, p[..., i] < 0.0)
    return p * np.where(flip, -1.0, 1.0)[..., None]  # × −1 is negation, bit for bit


def rotations_from_quaternions(quat_wxyz: np.ndarray) -> np.ndarray:
    """Rotation matrices ``(..., 3, 3)`` of quaternions ``(..., 4)`` (eq. 4 divided by ``Δ``)."""
    p = np.asarray(quat_wxyz, dtype=float)
    numerators = vector_form(ROTATION, p, p)  # eq. 4's nine, and Δ = p·p
    numerators = numerators[..., :9] / numerators[..., 9:]
    return numerators.reshape(p.shape[:-1] + (3, 3))


def quaternions_from_axis_angle(axes, angles) -> np.ndarray:
    """Unit quaternions ``(..., 4)`` of turns by ``angles`` (radians, ``...``) about ``axes``
    ``(..., 3)`` (any non-zero length): ``(cos(θ/2), sin(θ/2) u)``.

    Raises
    ------
    PoseError
        For a zero or non-finite axis or angle.
    """
    axis = as_numbers(axes, "an axis", PoseError)
    angle = as_numbers(angles, "an angle", PoseError)
    _finite(axis, "the axis")
    _finite(angle, "the angle")
    norm = np.linalg.norm(unit_scale(axis), axis=-1)
    if axis.shape[-1:] != (3,) or np.any(norm == 0.0):
        raise PoseError(f"a rotation axis needs 3 numbers, not all zero, got {axis.tolist()}")
    unit = unit_scale(axis) / norm[..., None]
    half = 0.5 * angle[..., None]
    return np.concatenate([np.cos(half), np.sin(half) * unit], axis=-1)


def quaternions_from_rpy_xyz(rpy) -> np.ndarray:
    """Unit quaternions ``(..., 4)`` of roll, pitch, yaw ``(..., 3)`` (radians) about the fixed
    axes x, then y, then z: ``R = Rz(yaw) Ry(pitch) Rx(roll)``, the convention of ROS's
    ``setRPY`` and of URDF."""
    angles = as_numbers(rpy, "roll, pitch, yaw", PoseError)
    if angles.shape[-1:] != (3,):
        raise PoseError(f"roll, pitch, yaw are 3 numbers, got shape {angles.shape}")
    eye = np.eye(3)
    turns = [quaternions_from_axis_angle(eye[i], angles[..., i]) for i in range(3)]
    return quat_mul(turns[2], quat_mul(turns[1], turns[0]))


def matrices_from_quat_trans(quat_wxyz: np.ndarray, translations: np.ndarray) -> np.ndarray:
    """Robotics-layout matrices ``(..., 4, 4)`` from quaternions ``(..., 4)`` and translations
    ``(..., 3)``.

    The quaternion is validated by :func:`check_quaternions` (non-zero, finite; any scale).
    """
    q = check_quaternions(quat_wxyz)
    t = np.asarray(translations, dtype=float)
    if t.shape[-1:] != (3,):
        raise PoseError(f"a translation needs 3 numbers, got shape {t.shape}")
    _finite(t, "the translation")
    shape = np.broadcast_shapes(q.shape[:-1], t.shape[:-1])
    out = np.zeros(shape + (4, 4))
    out[..., :3, :3] = rotations_from_quaternions(q)
    out[..., :3, 3] = t
    out[..., 3, 3] = 1.0
    return out


def quat_trans_from_matrices(matrices: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit quaternions ``(..., 4)`` (w, x, y, z) and translations ``(..., 3)`` of robotics
    matrices.

    The quaternion sign follows :func:`quaternions_from_rotations` (``w ≥ 0``).
    """
    m = np.asarray(matrices, dtype=float)
    return quaternions_from_rotations(m[..., :3, :3]), m[..., :3, 3].copy()


def study_from_matrices(matrices: np.ndarray) -> np.ndarray:
    """Study parameters ``(..., 8)`` of robotics-layout matrices ``(..., 4, 4)``.

    ``p`` is the unit quaternion of :func:`quaternions_from_rotations` (eq. 7–9), ``q`` follows
    from eq. 6 as ``q = −½ t p``; the result satisfies the Study condition and ``|p| = 1``.
    The input is assumed valid (see :func:`check_matrices`).
    """
    p, t = quat_trans_from_matrices(matrices)
    return study_from_quat_trans(p, t)


def matrices_from_study(
    study: np.ndarray, *, through_kappa: bool = False, tol: float = STUDY_TOL
) -> np.ndarray:
    """Robotics-layout matrices ``(..., 4, 4)`` of Study parameters ``(..., 8)``.

    Parameters
    ----------
    study : array_like, shape (..., 8)
        ``(p0, p1, p2, p3, q0, q1, q2, q3)``, homogeneous (any non-zero scale).
    through_kappa : bool
        If false (default), the Study condition must hold within ``tol``. If true, any ``h``
        with ``p ≠ 0`` is accepted and read through the extended map κ (section 3).

    Raises
    ------
    PoseError
        For ``p = 0``, non-finite entries, or (unless ``through_kappa``) a violated Study
        condition, stating the residual and the tolerance.
    """
    h = check_study(study, tol=tol, on_quadric=not through_kappa)
    return matrices_from_rot_trans(*kappa(h))


def matrices_from_rot_trans(rotations: np.ndarray, translations: np.ndarray) -> np.ndarray:
    """Robotics matrices ``(..., 4, 4)`` from rotations ``(..., 3, 3)`` and translations ``(...,
    3)``."""
    rot = np.asarray(rotations, dtype=float)
    out = np.zeros(rot.shape[:-2] + (4, 4))
    out[..., :3, :3] = rot
    out[..., :3, 3] = translations
    out[..., 3, 3] = 1.0
    return out


def inverse_matrices(matrices: np.ndarray) -> np.ndarray:
    """Inverse of rigid robotics-layout matrices ``(..., 4, 4)``: ``[[Rᵀ, −Rᵀ t], [0, 1]]``."""
    m = np.asarray(matrices, dtype=float)
    out = np.zeros_like(m)
    rt = np.swapaxes(m[..., :3, :3], -1, -2)
    out[..., :3, :3] = rt
    out[..., :3, 3] = -np.einsum("...ij,...j->...i", rt, m[..., :3, 3])
    out[..., 3, 3] = 1.0
    return out
