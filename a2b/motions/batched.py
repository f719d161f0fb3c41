"""Many motions at once: the coefficient tables of :mod:`a2b.motions` for stacks of poses.

``a2b batch`` samples thousands of small motions. Built one at a time with :func:`a2b.motion`,
each costs a few hundred numpy operations on arrays of 3 or 4 numbers, and sampling 101
points of it costs as many again. Here every step, from :func:`a2b.frames.screw_frame` to the
constructors of :class:`~a2b.motions.darboux.DarbouxMotion`,
:class:`~a2b.motions.cubic.CubicMotion` and :class:`~a2b.motions.screw.ScrewMotion` and their
sampling, is written once for ``J`` jobs, as array operations over the leading axis:

* the screw frame of every pair of poses, with its choices (the short way round, the half-turn
  rule, pure translations and ``B = A``) made by ``np.where``;
* the tables ``(J, k, 14)`` of darboux (``δ`` per job), cubic (``m``, ``a``, ``b`` per job, in
  either frame) and screw motions;
* samples ``(J, S, ...)`` at one ``ts`` for all jobs: quaternions and translations, matrices or
  Study parameters.

The floating-point operations are those of the single-motion code, in the same order:
elementwise where it is elementwise, a sequential sum where it takes a dot product of three or
four numbers, and a batched ``matmul`` (one BLAS product per job, of the same shapes) where it
multiplies matrices. A job's table, choices and samples are therefore those of
``a2b.motion(start, end, mode, **parameters)``, as the tests check.

A job that this path does not decide safely is marked not :attr:`MotionBatch.ok`, and the
caller builds it with :func:`a2b.motion`, which raises, warns or chooses exactly as for a single
motion. That covers invalid poses and parameters, every error and warning of the constructors
(``p(t)`` close to 0, ``x0(t) = 0``, ``m`` orthogonal to a pose, an ill-determined axis,
overflow), and quantities within a factor of two of a threshold where the choice depends on the
last bit (rotations of the size of rounding noise, half-turns with ``d`` ≈ 0).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from types import SimpleNamespace

import numpy as np

from ..api import MODES
from ..extended import ORTHOGONAL_TOL
from ..frames import ROTATION_NOISE
from ..names import FRAMES
from ..poses import (
    ORTHO_TOL,
    canonical_sign,
    quaternions_from_rotations,
    rotations_from_quaternions,
)
from ..study import (
    quat_conj,
    quat_mul,
    rotation_numerators,
    study_from_quat_trans,
    translation_numerators,
)
from ._rational import (
    EPS,
    FRAGILE_TOL,
    ROT_COLS,
    SENSITIVE_TOL,
    TRANS_COLS,
    bern_elevate,
    bern_mul,
    bernstein_basis,
)

__all__ = [
    "FRAMES",
    "MODES",
    "MotionBatch",
    "ScrewFrames",
    "motions",
    "screw_frames",
    "valid_poses",
]

#: A job whose smallest ``|p(t)|² / max|p|²`` on ``[0, 1]`` is below this goes to
#: :func:`a2b.motion`: twice the ratio at which a single motion warns (or refuses).
PATH_RATIO_MIN = 2 * SENSITIVE_TOL

#: A cubic motion in the canonical frame whose axis sensitivity estimate exceeds this goes to
#: :func:`a2b.motion`: half the estimate at which it warns.
AXIS_SENSITIVITY_MAX = 0.5e-9


# -- small exact helpers ----------------------------------------------------------------------


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``Σ a_i b_i`` over the last axis, summed in order: what a dot product of 3 or 4 numbers
    (``a @ b``, ``np.linalg.norm``) computes in the single-motion code."""
    out = a[..., 0] * b[..., 0]
    for i in range(1, a.shape[-1]):
        out = out + a[..., i] * b[..., i]
    return out


def _norm(a: np.ndarray) -> np.ndarray:
    """``np.linalg.norm`` of each vector of the last axis, as for one vector."""
    return np.sqrt(_dot(a, a))


def _matvec(matrices: np.ndarray, vectors: np.ndarray) -> np.ndarray:
    """``M @ v`` for stacks ``(..., n, n)`` and ``(..., n)``, one product per matrix as ``@``."""
    return np.matmul(matrices, vectors[..., None])[..., 0]


def _near(x: np.ndarray, threshold: float) -> np.ndarray:
    """Where ``x`` lies within a factor of two of ``threshold``."""
    return (x > 0.5 * threshold) & (x <= 2.0 * threshold)


def valid_poses(matrices: np.ndarray, tol: float = ORTHO_TOL) -> np.ndarray:
    """Which robotics matrices ``(J, 4, 4)`` :func:`a2b.poses.check_matrices` surely accepts.

    True where every entry is finite, the bottom row is exactly ``(0, 0, 0, 1)`` and
    ``max |R Rᵀ − I|`` and ``|det R − 1|`` are at most ``tol / 2`` (so that a last-bit
    difference in the residual cannot change the verdict). False does not mean invalid.
    """
    m = np.asarray(matrices, dtype=float)
    ok = np.isfinite(m).all(axis=(-2, -1)) & (m[..., 3, :] == [0.0, 0.0, 0.0, 1.0]).all(axis=-1)
    rot = np.where(ok[..., None, None], m[..., :3, :3], np.eye(3))
    residual = np.abs(rot @ np.swapaxes(rot, -1, -2) - np.eye(3)).max(axis=(-2, -1))
    det = np.linalg.det(rot) if rot.size else np.ones(rot.shape[:-2])
    return ok & (residual <= 0.5 * tol) & (np.abs(det - 1.0) <= 0.5 * tol)


# -- the screw frames of many pairs of poses --------------------------------------------------

_FLIP = "flipped the sign of B's quaternion so that pA·pB ≥ 0 (the short way round)"
_PURE_TRANSLATION = (
    "pure translation (φ = 0): the axis is the line through A's origin along the translation"
)
_SAME_POSE = "B = A: the axis is chosen parallel to z through A's origin"


@dataclass
class ScrewFrames:
    """The :class:`a2b.frames.ScrewFrame` of ``J`` pairs of poses, one row per job.

    Attributes are those of ``ScrewFrame`` with a leading axis ``J``: ``phi, d (J,)``,
    ``axis_direction, axis_point, t_start, t_end, t_disp (J, 3)``, ``r, p_start, p_end (J, 4)``,
    ``h_start, h_end (J, 8)`` and ``choices``, a list of ``J`` tuples of str. ``ok (J,)`` is
    False for a job whose frame this path does not decide safely (see the module docstring).
    """

    phi: np.ndarray
    d: np.ndarray
    axis_direction: np.ndarray
    axis_point: np.ndarray
    r: np.ndarray
    p_start: np.ndarray
    p_end: np.ndarray
    h_start: np.ndarray
    h_end: np.ndarray
    t_start: np.ndarray
    t_end: np.ndarray
    t_disp: np.ndarray
    choices: list = field(default_factory=list)
    ok: np.ndarray | None = None

    @property
    def t_perp(self) -> np.ndarray:
        """The displacement's translation perpendicular to the axis, ``(J, 3)``."""
        return self.t_disp - self.d[:, None] * self.axis_direction


def screw_frames(start: np.ndarray, end: np.ndarray) -> ScrewFrames:
    """:func:`a2b.frames.screw_frame` of every pair ``start[j]``, ``end[j]``.

    Parameters
    ----------
    start, end : ndarray, shape (J, 4, 4)
        Valid robotics matrices (see :func:`valid_poses`).

    Returns
    -------
    ScrewFrames
        Equal, job by job, to ``screw_frame(start[j], end[j])`` where ``ok[j]``.
    """
    start = np.asarray(start, dtype=float)
    end = np.asarray(end, dtype=float)
    with np.errstate(all="ignore"):
        return _screw_frames(start, end)


def _screw_frames(start, end) -> ScrewFrames:
    p_a = quaternions_from_rotations(start[:, :3, :3])
    p_b = quaternions_from_rotations(end[:, :3, :3])
    t_a = start[:, :3, 3].copy()
    t_b = end[:, :3, 3].copy()
    same = (p_a == p_b).all(axis=-1)
    r = quat_mul(p_b, quat_conj(p_a))
    r[same] = (1.0, 0.0, 0.0, 0.0)
    s = _norm(r[:, 1:])
    rotating = s > ROTATION_NOISE
    half_turn = rotating & (np.abs(r[:, 0]) <= ROTATION_NOISE)
    flip = (r[:, 0] < 0) & ~half_turn
    p_b = np.where(flip[:, None], -p_b, p_b)
    r = np.where(flip[:, None], -r, r)
    t_disp = t_b - _matvec(rotations_from_quaternions(r), t_a)

    # a rotation: the axis of r, and the half-turn rule
    u = r[:, 1:] / np.where(rotating, s, 1.0)[:, None]
    d = _dot(u, t_disp)
    turn = half_turn & ((d < 0) | ((d == 0) & (canonical_sign(u)[:, 0] != u[:, 0])))
    u = np.where(turn[:, None], -u, u)
    d = np.where(turn, -d, d)
    p_b = np.where(turn[:, None], -p_b, p_b)
    r = np.where(turn[:, None], -r, r)
    c = np.abs(r[:, 0])
    phi = 2.0 * np.arctan2(s, c)
    t_perp = t_disp - d[:, None] * u
    axis_point = 0.5 * (t_perp + np.cross(u, t_perp) * (c / np.where(rotating, s, 1.0))[:, None])

    # no rotation: the axis along the translation, or parallel to z for B = A
    norm_t = _norm(t_disp)
    moving = norm_t > 0.0
    u_t = np.where(
        moving[:, None], t_disp / np.where(moving, norm_t, 1.0)[:, None], [0.0, 0.0, 1.0]
    )
    d_t = np.where(moving, norm_t, 0.0)
    axis_point_t = t_a - _dot(u_t, t_a)[:, None] * u_t

    u = np.where(rotating[:, None], u, u_t)
    d = np.where(rotating, d, d_t)
    phi = np.where(rotating, phi, 0.0)
    axis_point = np.where(rotating[:, None], axis_point, axis_point_t)

    ok = (
        ~_near(s, ROTATION_NOISE)
        & ~(rotating & _near(np.abs(r[:, 0]), ROTATION_NOISE))
        & ~(half_turn & (d != 0) & (np.abs(d) <= 1e-12 * norm_t))
        & np.isfinite(d)
        & np.isfinite(t_disp).all(axis=-1)
        & np.isfinite(axis_point).all(axis=-1)
    )
    choices: list = [()] * len(s)
    for j in np.flatnonzero(flip).tolist():
        choices[j] += (_FLIP,)
    for j in np.flatnonzero((s > 0.0) & ~rotating).tolist():
        choices[j] += (
            (
                f"the rotations of A and B differ by |sin(φ/2)| = {float(s[j]):.3g}, within "
                f"rounding ({ROTATION_NOISE:.3g}): treated as a pure translation"
            ),
        )
    for j in np.flatnonzero(half_turn).tolist():
        side = "d > 0" if d[j] > 0 else "d = 0 and the first non-zero axis component positive"
        choices[j] += (
            (
                f"φ = π (|pA·pB| = {float(c[j]):.3g} ≤ {ROTATION_NOISE:.3g}): both axis "
                f"orientations are short; chose the one with {side}"
            ),
        )
    for j in np.flatnonzero(~rotating).tolist():
        choices[j] += (_PURE_TRANSLATION if moving[j] else _SAME_POSE,)
    return ScrewFrames(
        phi=phi,
        d=d,
        axis_direction=u,
        axis_point=axis_point,
        r=r,
        p_start=p_a,
        p_end=p_b,
        h_start=study_from_quat_trans(p_a, t_a),
        h_end=study_from_quat_trans(p_b, t_b),
        t_start=t_a,
        t_end=t_b,
        t_disp=t_disp,
        choices=choices,
        ok=ok,
    )


# -- the motions ------------------------------------------------------------------------------

#: The array attributes of :class:`ScrewFrames`.
_FRAME_ARRAYS = (
    "phi", "d", "axis_direction", "axis_point", "r", "p_start", "p_end",
    "h_start", "h_end", "t_start", "t_end", "t_disp", "ok",
)  # fmt: skip


@dataclass
class MotionBatch:
    """``J`` motions of one mode, as coefficient tables, sampled together.

    Attributes
    ----------
    mode : {"darboux", "cubic", "screw"}
    frames : ScrewFrames
    table : ndarray, shape (J, k, 14)
        Job ``j``'s is the ``table`` of ``a2b.motion(start[j], end[j], mode, ...)``.
    ok : ndarray of bool, shape (J,)
        False where :func:`a2b.motion` must build the job instead (it raises, warns, or makes a
        choice that this path does not decide safely). The other attributes of such a job are
        meaningless.
    choices : list of J tuples of str
        What ``a2b.motion(...).choices`` states, job by job.
    quat_ends : ndarray, shape (J, 2, 4)
        Darboux and cubic: the end points of ``p(t) = (1−t) q0 + t q1``. Screw: ``pA`` and
        ``u pA``, so that ``p(t) = cos(tφ/2) pA + sin(tφ/2) u pA``.
    path_ratio : ndarray, shape (J,)
        Darboux and cubic: the smallest ``|p(t)|² / max|p|²`` on ``[0, 1]``; where it is below
        ``FRAGILE_TOL``, :meth:`matrices` takes the rotation from the normalised ``p(t)``, as a
        single motion does. Screw: infinity.
    """

    mode: str
    frames: ScrewFrames
    table: np.ndarray
    ok: np.ndarray
    choices: list
    quat_ends: np.ndarray
    path_ratio: np.ndarray

    def __len__(self) -> int:
        return len(self.ok)

    @property
    def matrices_ok(self) -> np.ndarray:
        """``ok``, less the jobs whose ``path_ratio`` is within a factor of two of
        ``FRAGILE_TOL``, where a single motion's choice of rotation formula for
        :meth:`matrices` depends on the last bit."""
        return self.ok & ~_near(self.path_ratio, FRAGILE_TOL)

    def take(self, index) -> MotionBatch:
        """The motions ``index`` (a slice: views; an index array or a mask) as a new batch."""
        if not isinstance(index, slice):
            index = np.arange(len(self))[index]

        def part(values: list) -> list:
            return values[index] if isinstance(index, slice) else [values[j] for j in index]

        frames = ScrewFrames(
            **{name: getattr(self.frames, name)[index] for name in _FRAME_ARRAYS},
            choices=part(self.frames.choices),
        )
        return MotionBatch(
            self.mode,
            frames,
            self.table[index],
            self.ok[index],
            part(self.choices),
            self.quat_ends[index],
            self.path_ratio[index],
        )

    # -- sampling -------------------------------------------------------------------------
    def _basis(self, ts: np.ndarray) -> np.ndarray:
        """The basis of every job at ``ts``: ``(S, k)`` shared, or ``(J, S, 4)`` for screws."""
        if self.mode == "darboux":
            return bernstein_basis(ts, 2)
        if self.mode == "cubic":
            return bernstein_basis(ts, 3)
        return _screw_basis(self.frames.phi, ts)

    def _quats(self, ts: np.ndarray) -> np.ndarray:
        """``p(t)`` of every job, ``(J, S, 4)``, not normalised.

        Darboux and cubic: ``(1−t) q0 + t q1``, computed component by component (a view of a
        ``(4, J, S)`` array, whose inner loops run over the samples). Screw: one ``(S, 2) @
        (2, 4)`` product per job, as ``ScrewMotion._quats``.
        """
        ends = self.quat_ends
        if self.mode == "screw":
            half = np.empty((2, len(self), len(ts)))
            np.multiply(ts, (0.5 * self.frames.phi)[:, None], out=half[1])
            np.cos(half[1], out=half[0])
            np.sin(half[1], out=half[1])
            return np.matmul(np.moveaxis(half, 0, -1), ends)
        u = 1.0 - ts
        out = np.empty((4, len(self), len(ts)))
        term = np.empty((len(self), len(ts)))
        for c in range(4):  # (J, S) at a time: numpy is slow at broadcasting three axes
            np.multiply.outer(ends[:, 0, c], u, out=out[c])
            np.multiply.outer(ends[:, 1, c], ts, out=term)
            out[c] += term
        return np.moveaxis(out, 0, -1)

    def quat_trans(self, ts) -> tuple[np.ndarray, np.ndarray]:
        """Unit quaternions ``(J, S, 4)`` and translations ``(J, S, 3)`` at ``ts`` ``(S,)``.

        As :meth:`a2b.motions.base.Motion.quat_trans` for each job (``ts`` in ``[0, 1]``).
        The quaternions of darboux and cubic motions are a view of a ``(4, J, S)`` array.
        """
        ts = _check_ts(ts)
        with np.errstate(all="ignore"):
            quat = self._quats(ts)
            _normalise(quat)
            basis = self._basis(ts)
            coefficients = self.table[:, :, TRANS_COLS]
            if self.mode == "screw":
                trans = np.matmul(basis, coefficients)
            else:
                trans = _scaled_products(basis, self.table[:, :, 13:14], coefficients, False)
        return quat, trans

    def matrices(self, ts) -> np.ndarray:
        """Robotics matrices ``(J, S, 4, 4)`` at ``ts`` ``(S,)``, as ``Motion.matrices`` per job."""
        ts = _check_ts(ts)
        out = np.empty((len(self), len(ts), 4, 4))
        with np.errstate(all="ignore"):
            basis = self._basis(ts)
            table = self.table
            k = table.shape[1]
            if self.mode == "screw":
                extended = np.zeros((len(self), k, 16))
                extended[:, :, :12] = table[:, :, :12]
                extended[:, 0, 15] = 1.0
                np.matmul(basis, extended, out=out.reshape(len(self), len(ts), 16))
                return out
            shared = (table[:, :, 12] == table[:, :, 13]).all(axis=1)
            for dens in (1, 2):
                jobs = np.flatnonzero(shared if dens == 1 else ~shared)
                if not len(jobs):
                    continue
                sub = table[jobs]
                extended = np.zeros((len(jobs), dens * k + 1, 16))
                if dens == 1:
                    extended[:, :k, :12] = sub[:, :, :12]
                else:
                    extended[:, :k, ROT_COLS] = sub[:, :, ROT_COLS]
                    extended[:, k : 2 * k, TRANS_COLS] = sub[:, :, TRANS_COLS]
                extended[:, -1, 15] = 1.0
                values = _scaled_products(basis, sub[:, :, 12 : 12 + dens], extended, True)
                bad = ~np.isfinite(values).all(axis=-1)
                values[..., 12:15] = np.where(bad[..., None], 0.0, values[..., 12:15])
                values[..., 15] = np.where(bad, 1.0, values[..., 15])
                out[jobs] = values.reshape(len(jobs), len(ts), 4, 4)
            fragile = np.flatnonzero(self.path_ratio < FRAGILE_TOL)
            if len(fragile):
                quats = self.take(fragile)._quats(ts)
                out[fragile, :, :3, :3] = rotations_from_quaternions(quats)
        return out

    def study(self, ts) -> np.ndarray:
        """Unit Study parameters ``(J, S, 8)`` at ``ts``, as ``Motion.study`` per job."""
        quat, trans = self.quat_trans(ts)
        with np.errstate(all="ignore"):
            return study_from_quat_trans(quat, trans)


def _normalise(quat: np.ndarray) -> None:
    """Divide quaternions ``(J, S, 4)`` by their norms in place, as ``Motion.quat_trans`` does
    with ``np.einsum("ij,ij->i", q, q)``.

    On a ``(4, J, S)`` view the squared norm is summed component by component in the order
    that einsum sums each row's four squares (checked once, see :func:`_einsum_order`); if
    einsum's order is another, the rows are copied and summed by einsum itself.
    """
    columns = np.moveaxis(quat, -1, 0)
    if quat.flags.c_contiguous or not _einsum_order():
        flat = quat.reshape(-1, 4)
        norm = np.sqrt(np.einsum("ij,ij->i", flat, flat)).reshape(quat.shape[:-1])
    else:  # (q0² + q2²) + (q1² + q3²), two axes at a time
        c0, c1, c2, c3 = columns
        norm = np.multiply(c0, c0)
        term = np.multiply(c2, c2)
        norm += term
        other = np.multiply(c1, c1)
        np.multiply(c3, c3, out=term)
        other += term
        norm += other
        np.sqrt(norm, out=norm)
    for column in columns:
        column /= norm


_EINSUM_ORDER: list = []


def _einsum_order() -> bool:
    """Whether ``np.einsum("ij,ij->i", q, q)`` sums ``(q0² + q2²) + (q1² + q3²)`` here."""
    if not _EINSUM_ORDER:
        # values of wide-ranging size, on which the orders of summation disagree; made
        # without numpy.random, whose import would add to every start-up
        k = np.arange(2048.0)
        q = (np.sin(1.7 * k) * np.exp(4.0 * np.cos(0.37 * k))).reshape(512, 4)
        square = q * q
        pairs = (square[:, 0] + square[:, 2]) + (square[:, 1] + square[:, 3])
        _EINSUM_ORDER.append(
            all(
                np.array_equal(np.einsum("ij,ij->i", q[:n], q[:n]), pairs[:n])
                for n in (1, 101, 512)
            )
        )
    return _EINSUM_ORDER[0]


def _check_ts(ts) -> np.ndarray:
    arr = np.asarray(ts, dtype=float)
    if arr.ndim != 1 or not np.all((arr >= 0.0) & (arr <= 1.0)):
        raise ValueError("a MotionBatch is sampled at a 1-D ts in [0, 1]")
    return arr


def _scaled_products(basis, denominators, coefficients, constant):
    """``[b / d_1, …, b / d_m, (1)] @ coefficients`` for every job, as ``_rational`` does for one.

    ``basis (S, k)``, ``denominators (J, k, m)``, ``coefficients (J, m k (+ 1), w)``; returns
    ``(J, S, w)``. The denominators are one ``(m, k) @ (k, S)`` product per job, and the
    scaled basis is laid out ``(m k (+ 1), S)`` and transposed, as in the single-motion code.
    """
    jobs, k, m = denominators.shape
    n = basis.shape[0]
    columns = basis.T
    inverse = np.matmul(np.swapaxes(denominators, 1, 2), columns)  # (J, m, S)
    np.divide(1.0, inverse, out=inverse)
    scaled = np.empty((jobs, m * k + constant, n))
    if constant:
        scaled[:, -1] = 1.0
    for j in range(m):
        for i in range(k):  # (J, S) at a time: numpy is slow at broadcasting three axes
            np.multiply(inverse[:, j], columns[i], out=scaled[:, j * k + i])
    return np.matmul(np.swapaxes(scaled, 1, 2), coefficients)


def _screw_basis(phi: np.ndarray, ts: np.ndarray) -> np.ndarray:
    """``ScrewMotion._basis`` of every job, ``(J, S, 4)``: the same function, on a ``(J, S)`` t."""
    from .screw import ScrewMotion

    t = np.broadcast_to(ts, (len(phi), len(ts))).copy()
    holder = SimpleNamespace(frame=SimpleNamespace(phi=phi[:, None]))
    return ScrewMotion._basis(holder, t)


def _path_ratio(p_a: np.ndarray, p_b: np.ndarray) -> np.ndarray:
    """``quaternion_path_minimum(p_a, p_b, 0, 1)[1]`` for every row of ``(J, 4)`` arrays."""
    diff = p_b - p_a
    dd = _dot(diff, diff)
    t_min = np.where(
        dd == 0.0, 0.0, np.clip(-_dot(p_a, diff) / np.where(dd == 0.0, 1.0, dd), 0.0, 1.0)
    )
    p_min = p_a + t_min[:, None] * diff
    scale = np.maximum(_dot(p_a, p_a), _dot(p_b, p_b))
    return _dot(p_min, p_min) / scale


def _tables(rot, rot_den, trans, trans_den) -> np.ndarray:
    """``make_table`` for every job: coefficient-first ``(k, J, 9)``, ``(k, J)``, ``(k, J, 3)``,
    ``(k, J)`` to tables ``(J, k, 14)``."""
    k, jobs = rot_den.shape
    table = np.zeros((jobs, k, 14))
    table[:, :, ROT_COLS] = np.swapaxes(rot, 0, 1)
    table[:, :, TRANS_COLS] = np.swapaxes(trans, 0, 1)
    table[:, :, 12] = rot_den.T
    table[:, :, 13] = trans_den.T
    return table


def _column(values, jobs: int, default: float) -> tuple[np.ndarray, np.ndarray]:
    """A per-job float parameter ``(J,)`` (None: ``default``) and where it is finite."""
    if values is None:
        return np.full(jobs, default), np.ones(jobs, dtype=bool)
    arr = np.asarray(values, dtype=float).reshape(jobs)
    finite = np.isfinite(arr)
    return np.where(finite, arr, default), finite


def motions(
    start,
    end,
    mode: str = "darboux",
    *,
    delta=None,
    m=None,
    a=None,
    b=None,
    frame: str = "canonical",
    checked: bool = False,
) -> MotionBatch:
    """The motions of one mode between ``start[j]`` and ``end[j]``, for every ``j`` at once.

    Parameters
    ----------
    start, end : array_like, shape (J, 4, 4)
        Robotics-layout poses. Rows that :func:`valid_poses` does not surely accept are not ok.
    mode : {"darboux", "cubic", "screw"}
    delta : array_like, shape (J,), optional
        darboux: the fiber offset δ of each job (default 0).
    m : array_like, shape (J, 4), optional
        cubic: the parameter of μ_[m] of each job, in the coordinates of ``frame``
        (default ``pA + pB`` there).
    a, b : array_like, shape (J,), optional
        cubic: the essential scalars of each job (default 0).
    frame : {"canonical", "given"}
        cubic: the frame of every job.
    checked : bool
        The poses are known to pass :func:`a2b.poses.check_matrices` (as a jobs file's do),
        so :func:`valid_poses` is not asked again.

    Returns
    -------
    MotionBatch
        Where ``ok[j]``, job ``j`` has the table, the choices and the samples of
        ``a2b.motion(start[j], end[j], mode, delta=delta[j])`` (darboux),
        ``a2b.motion(start[j], end[j], "cubic", m=m[j], a=a[j], b=b[j], frame=frame)``
        or ``a2b.motion(start[j], end[j], "screw")``.
    """
    if mode not in MODES:
        raise ValueError(f"unknown mode {mode!r}; expected one of {', '.join(MODES)}")
    if frame not in FRAMES:
        raise ValueError(f"unknown frame {frame!r}; expected one of {', '.join(FRAMES)}")
    start = np.asarray(start, dtype=float)
    end = np.asarray(end, dtype=float)
    if start.ndim != 3 or start.shape[1:] != (4, 4) or end.shape != start.shape:
        raise ValueError(
            f"start and end must be (J, 4, 4) arrays, got {start.shape} and {end.shape}"
        )
    if checked:
        ok = np.ones(len(start), dtype=bool)
    else:
        ok = valid_poses(start) & valid_poses(end)
        eye = np.eye(4)
        start = np.where(ok[:, None, None], start, eye)
        end = np.where(ok[:, None, None], end, eye)
    with np.errstate(all="ignore"):
        frames = _screw_frames(start, end)
        ok &= frames.ok
        if mode == "darboux":
            batch = _darboux(frames, delta, ok)
        elif mode == "cubic":
            batch = _cubic(frames, m, a, b, frame, ok)
        else:
            batch = _screw(frames, ok)
        batch.ok &= np.isfinite(batch.table).all(axis=(1, 2))
    return batch


def _darboux(frames: ScrewFrames, delta, ok) -> MotionBatch:
    jobs = len(ok)
    delta, finite = _column(delta, jobs, 0.0)
    ok = ok & finite
    s_a, s_b = 0.0 - delta / 2, delta / 2
    h_a, h_b = frames.h_start, frames.h_end
    p_a, q_a = h_a[:, :4], h_a[:, 4:] + s_a[:, None] * h_a[:, :4]
    p_b, q_b = h_b[:, :4], h_b[:, 4:] + s_b[:, None] * h_b[:, :4]
    rot = np.stack(
        [rotation_numerators(p_a), rotation_numerators(p_a, p_b), rotation_numerators(p_b)]
    )
    den = np.stack([_dot(p_a, p_a), _dot(p_a, p_b), _dot(p_b, p_b)])
    trans = np.stack(
        [
            translation_numerators(p_a, q_a),
            0.5 * (translation_numerators(p_a, q_b) + translation_numerators(p_b, q_a)),
            translation_numerators(p_b, q_b),
        ]
    )
    ratio = _path_ratio(p_a, p_b)
    ok &= ratio >= PATH_RATIO_MIN
    choices = list(frames.choices)
    for j in np.flatnonzero((frames.phi == 0.0) & (delta != 0.0)).tolist():
        choices[j] += ("δ has no effect on a pure translation",)
    table = _tables(rot, den, trans, den)
    return MotionBatch("darboux", frames, table, ok, choices, np.stack([p_a, p_b], axis=1), ratio)


def _cubic(frames: ScrewFrames, m, a, b, frame_name: str, ok) -> MotionBatch:
    jobs = len(ok)
    r, p_a, p_b = frames.r, frames.p_start, frames.p_end
    c = r[:, 0]
    s = _norm(r[:, 1:])
    if m is None:
        if frame_name == "canonical":
            m_arr = np.zeros((jobs, 4))
            m_arr[:, 0] = 1.0 + c
            m_arr[:, 3] = s
        else:
            m_arr = p_a + p_b
    else:
        m_arr = np.asarray(m, dtype=float).reshape(jobs, 4)
        given = np.isfinite(m_arr).all(axis=1) & m_arr.any(axis=1)
        ok = ok & given
        m_arr = np.where(given[:, None], m_arr, 1.0)
    a_val, a_ok = _column(a, jobs, 0.0)
    b_val, b_ok = _column(b, jobs, 0.0)
    ok = ok & a_ok & b_ok
    psi_a, psi_b = 1.0 + a_val, 1.0 + b_val
    if frame_name == "canonical":
        p_a_can = np.zeros((jobs, 4))
        p_a_can[:, 0] = 1.0
        p_b_can = np.zeros((jobs, 4))
        p_b_can[:, 0] = c
        p_b_can[:, 3] = s
        dot_a, dot_b = _dot(m_arr, p_a_can), _dot(m_arr, p_b_can)
    else:
        dot_a, dot_b = _dot(m_arr, p_a), _dot(m_arr, p_b)
    m_norm = _norm(m_arr)
    ok &= (np.abs(dot_a) > 2 * ORTHOGONAL_TOL * m_norm) & (
        np.abs(dot_b) > 2 * ORTHOGONAL_TOL * m_norm
    )
    ok &= psi_a * psi_b > 0.0
    w_a, w_b = 4.0 * dot_a, 4.0 * dot_b
    pa_w, pb_w = w_a[:, None] * p_a, w_b[:, None] * p_b
    rot = np.stack(
        [rotation_numerators(pa_w), rotation_numerators(pa_w, pb_w), rotation_numerators(pb_w)]
    )
    delta = np.stack([_dot(pa_w, pa_w), _dot(pa_w, pb_w), _dot(pb_w, pb_w)])  # (3, J)
    x0 = np.stack([psi_a, psi_b])  # (2, J)
    t_a = frames.t_start
    if frame_name == "given":
        trans = bern_elevate(np.stack([psi_a[:, None] * t_a, psi_b[:, None] * frames.t_end]), 3)
        trans_den = bern_elevate(x0, 3)
    else:
        rho_a = np.zeros((jobs, 4))
        rho_a[:, 0] = w_a
        rho_b = w_b[:, None] * r
        n_rho = np.stack(
            [
                rotation_numerators(rho_a),
                rotation_numerators(rho_a, rho_b),
                rotation_numerators(rho_b),
            ],
            axis=1,
        )  # (J, 3, 9)
        rotated_start = np.moveaxis(_matvec(n_rho.reshape(jobs, 3, 3, 3), t_a[:, None, :]), 1, 0)
        t_perp = frames.t_perp
        cross = np.cross(r[:, 1:], t_perp)
        n_disp = np.stack(
            [
                np.zeros((jobs, 3)),
                (0.5 * w_a * w_b)[:, None] * (c[:, None] * t_perp - cross),
                (w_b * w_b)[:, None] * t_perp,
            ]
        )
        first = bern_mul(rotated_start + n_disp, x0[:, :, None])
        z_num = np.stack([np.zeros((jobs, 3)), (frames.d * psi_b)[:, None] * frames.axis_direction])
        second = bern_mul(z_num, delta[:, :, None])
        trans = first + second
        trans_den = bern_mul(delta, x0)
        ok &= _axis_sensitivity(s, w_a, w_b, psi_a, psi_b) <= AXIS_SENSITIVITY_MAX
    ratio = _path_ratio(pa_w, pb_w)
    ok &= ratio >= PATH_RATIO_MIN
    table = _tables(bern_elevate(rot, 3), bern_elevate(delta, 3), trans, trans_den)
    choices = list(frames.choices)
    if m is None:
        made = (f"m defaults to pA + pB in {frame_name} coordinates, so both weights are equal",)
        choices = [ch + made for ch in choices]
    quat_ends = np.stack([pa_w, pb_w], axis=1)
    return MotionBatch("cubic", frames, table, ok, choices, quat_ends, ratio)


def _axis_sensitivity(s, w_a, w_b, psi_a, psi_b) -> np.ndarray:
    """The estimate of ``CubicMotion._check_axis_sensitivity`` for every job (0 for ``s = 0``)."""
    ts = np.linspace(0.0, 1.0, 101)
    f = ts * w_b[:, None] / ((1 - ts) * w_a[:, None] + ts * w_b[:, None])
    g = ts * psi_b[:, None] / ((1 - ts) * psi_a[:, None] + ts * psi_b[:, None])
    diff = np.abs(f - g)
    spread = np.max(np.where(np.isfinite(diff), diff, 0.0), axis=1, initial=0.0)
    return np.where(s == 0.0, 0.0, EPS / np.where(s == 0.0, 1.0, s) * spread)


def _screw(frames: ScrewFrames, ok) -> MotionBatch:
    jobs = len(ok)
    phi, d = frames.phi, frames.d
    u = frames.axis_direction
    k = np.zeros((jobs, 3, 3))
    k[:, 0, 1], k[:, 0, 2] = -u[:, 2], u[:, 1]
    k[:, 1, 0], k[:, 1, 2] = u[:, 2], -u[:, 0]
    k[:, 2, 0], k[:, 2, 1] = -u[:, 1], u[:, 0]
    k2 = np.matmul(k, k)
    rot_a = rotations_from_quaternions(frames.p_start)
    t_a = frames.t_start
    t_perp = frames.t_perp
    cross = np.cross(u, t_perp)
    rot = np.stack(
        [rot_a, np.zeros((jobs, 3, 3)), np.matmul(k, rot_a), np.matmul(k2, rot_a)]
    ).reshape(4, jobs, 9)
    trans = np.stack([t_a, d[:, None] * u, _matvec(k, t_a), _matvec(k2, t_a)])  # (4, J, 3)
    turning = phi > 0.0
    cot = np.array([math.cos(x / 2) / math.sin(x / 2) if x > 0.0 else 0.0 for x in phi.tolist()])
    half_cot = (0.5 * cot)[:, None]
    trans[2] = np.where(turning[:, None], trans[2] + (half_cot * t_perp - 0.5 * cross), trans[2])
    trans[3] = np.where(turning[:, None], trans[3] + (0.5 * t_perp + half_cot * cross), trans[3])
    trans[1] = np.where(turning[:, None], trans[1], trans[1] + t_perp)
    unit = np.zeros((4, jobs))
    unit[0] = 1.0
    u_p_a = quat_mul(np.concatenate([np.zeros((jobs, 1)), u], axis=1), frames.p_start)
    return MotionBatch(
        "screw",
        frames,
        _tables(rot, unit, trans, unit),
        ok,
        list(frames.choices),
        np.stack([frames.p_start, u_p_a], axis=1),
        np.full(jobs, np.inf),
    )
