"""Bézier motions through control poses, and C¹ splines through key poses (section 6, figure 4).

The paper's outlook: the extended matrix model is an affine space, so the affine constructions
of CAD apply to motions directly. Map the control poses to points of the extended space, build
the curve there, and map every point of it to a pose.

``space="matrix"``
    A control pose ``(R_i, t_i)`` becomes the point ``X_i = (x'_i, ψ_i t_i) ∈ R^13`` with
    ``x'_i = (1, R_i) + Σ_l α_il f_l`` (a point of its μ_[m]-fiber, eq. 15; ``α_i = 0`` gives
    the pose itself) and ``ψ_i = x'_i[0]``. With weights ``w_i`` the curve is

    .. math:: x(t) = \\sum_i B_i^n(t)\\, w_i X_i,

    de Casteljau's curve of the points ``w_i X_i``, and the pose at ``t`` is
    ``κ(μ_m(x(t)))`` in the given coordinates (eq. 12): the rotation of ``p(t) = M_m x'(t)``
    and the translation ``x_t(t) / x0(t)``. Because ``M_m f_l = 0`` and
    ``M_m (1, R) = 4 (m·p) p`` (``docs/math.md``), the rotation and the translation decouple:

    .. math::

        p(t) = \\sum_i B_i^n(t)\\, 4 w_i (m·p_i)\\, p_i, \\qquad
        t(t) = \\frac{\\sum_i B_i^n(t)\\, w_i ψ_i\\, t_i}{\\sum_i B_i^n(t)\\, w_i ψ_i}.

    The rotation is a polynomial Bézier curve of quaternions whose control quaternions are
    taken in the half-space ``m·p > 0`` (so the sign of a control's quaternion never matters;
    ``m`` decides which way round), and the translation is a rational Bézier curve of the
    translations with weights ``w_i ψ_i``. The fiber coefficients ``α_i`` act only through
    ``ψ_i``. With two controls this is the cubic mode with ``frame="given"``. Since
    ``m·p(t) = 4 Σ_i B_i^n(t) w_i (m·p_i)² > 0`` on ``[0, 1]``, a Bézier curve in matrix space
    never passes through ``p = 0`` there; only ``x0 = 0`` can break it. The default ``m`` is
    :func:`default_m`.

``space="study"``
    A control pose becomes its unit Study vector ``h_i`` (``|p_i| = 1``), with signs made
    consistent from one control to the next (``p_i·p_{i+1} ≥ 0``), moved within its κ-fiber to
    ``h_i + s_i ε p_i`` (``docs/math.md``, correction 1), and weighted:
    ``h(t) = Σ_i B_i^n(t) w_i (h_i + s_i ε p_i)``. The pose at ``t`` is ``κ(h(t))``, without
    normalising ``h(t)`` or projecting it onto the Study quadric (section 3). With two controls
    and ``s = (−δ/2, δ/2)`` this is the Darboux mode with parameter ``δ``.

Both curves pass through the first and the last control pose (``t = 0`` and ``t = 1``).

Splines join key poses ``P_0 … P_N`` with cubic Bézier segments in either space. The inner
control points follow the uniform Catmull–Rom rule in the chosen space: with the points
``X_j`` of the poses (rigid points ``(1, R_j, t_j)`` of R^13, or consistent unit Study vectors)
and the tangents ``T_j = (X_{j+1} − X_{j−1}) / 2`` (at the ends ``T_0 = X_1 − X_0`` and
``T_N = X_N − X_{N−1}``), segment ``j`` has the controls
``X_j, X_j + T_j / 3, X_{j+1} − T_{j+1} / 3, X_{j+1}``. The segments meet with equal first
derivatives in R^13 (or R^8), and one map (μ_m with one ``m``, or κ) turns that into a C¹ motion.
The inner control points need not be rigid; μ_m and κ map them all the same. Segment ``j``
covers ``t ∈ [j/N, (j+1)/N]``, so ``t = j/N`` is the key pose ``P_j``. For two poses the spline
is the straight line: the cubic mode (``frame="given"``) or the Darboux mode with ``δ = 0``.

Singularities. A curve breaks where ``x0(t) = 0`` (it passes through infinity) or where
``p(t) = 0`` (no rotation). Both ``x0(t)`` and ``|p(t)|²`` are polynomials in ``t`` (Bernstein
form, degree ``n`` and ``2n``). a2b finds their real zeros and minima on the sampled range
exactly: the critical points come from the derivative, recursively, and between two
consecutive critical points a polynomial is monotone, so bisection to machine precision finds
its one zero there. A curve also counts as broken where ``|x0(t)|`` falls to
``SINGULAR_TOL = 1e-12`` times the largest Bernstein coefficient of ``x0``, or ``|p(t)|²`` to
``1e-12`` times the largest coefficient of ``|p|²`` (on ``[0, 1]`` these coefficients bound the
polynomial): closer than that, the pose is not computed reliably.

References
----------
H.-P. Schröcker, *From A to B: New Methods to Interpolate Two Poses*, eq. 12, 15, section 3
and section 6 (figure 4).
"""

from __future__ import annotations

import numpy as np

from ..elements import as_numbers, unit_scale
from ..errors import ParameterError, PoseError, SingularMotionError
from ..extended import (
    BASES,
    check_m,
    check_not_orthogonal,
    model_points_from_matrices,
    mu_fiber_points,
    mu_prime_matrix,
)
from ..kinematics import Kinematic, check_point
from ..poses import check_matrices, quat_trans_from_matrices, study_from_matrices
from ..study import kappa_fiber_points, rotation_numerators, translation_numerators
from ._bernstein import SINGULAR_TOL, first_small_values
from ._rational import (
    bern_elevate,
    bern_mul,
    bernstein_basis,
    bernstein_derivatives,
    make_table,
    table_derivatives,
)
from .base import check_ts

__all__ = [
    "SINGULAR_TOL",
    "SPACES",
    "BezierMotion",
    "bezier",
    "bezier_motion",
    "default_m",
    "spline",
    "spline_motion",
]

SPACES = ("matrix", "study")

#: The most entries of a Bernstein basis evaluated at once (8 MB).
BASIS_NUMBERS = 1 << 20


def _check_poses(poses, what: str, minimum: int = 2) -> np.ndarray:
    arr = check_matrices(poses)
    if arr.ndim != 3:
        raise PoseError(
            f"the {what} must be a list of 4x4 matrices, shape (k, 4, 4); got shape {arr.shape}"
        )
    if arr.shape[0] < minimum:
        raise ParameterError(f"a curve needs at least {minimum} {what}, got {arr.shape[0]}")
    return arr


def _per_control(values, k: int, name: str, width: int | None = None) -> np.ndarray:
    arr = as_numbers(values, name)
    shape = (k,) if width is None else (k, width)
    if arr.shape != shape:
        each = "one number" if width is None else f"{width} numbers"
        raise ParameterError(
            f"{name} needs {each} per control pose, shape {shape}; got shape {arr.shape}"
        )
    if not np.all(np.isfinite(arr)):
        raise ParameterError(f"{name} contains NaN or infinity")
    return arr


def _check_weights(weights, k: int) -> np.ndarray:
    if weights is None:
        return np.ones(k)
    w = unit_scale(
        _per_control(weights, k, "weights"), extreme_only=True
    )  # homogeneous: 1e200 each works
    if np.any(w <= 0.0):
        i = int(np.argmax(w <= 0.0))
        raise ParameterError(
            f"weights must be positive; control pose {i + 1} of {k} has weight {w[i]:.6g}"
        )
    return w


def _greville(i: int, k: int) -> str:
    return (
        f"control pose {i + 1} of {k} (t = {i / (k - 1):.6g})"
        if i in (0, k - 1)
        else (f"control pose {i + 1} of {k} (Greville abscissa t = {i / (k - 1):.6g})")
    )


def consistent_signs(vectors: np.ndarray) -> tuple[np.ndarray, list[int]]:
    """Flip quaternions or Study vectors ``(k, 4|8)`` so that ``p_i·p_{i+1} ≥ 0``, in order.

    Returns the flipped copy and the indices (0-based) that were flipped.
    """
    out = np.array(vectors, dtype=float)
    flipped = []
    for i in range(1, out.shape[0]):
        if out[i - 1, :4] @ out[i, :4] < 0.0:
            out[i] = -out[i]
            flipped.append(i)
    return out, flipped


def _nearest_hull_point(points: np.ndarray, iterations: int = 2000) -> np.ndarray:
    """The point of the convex hull of ``points (k, d)`` nearest to the origin (approximately).

    Its direction ``u`` maximises ``min_i u·points_i`` over unit vectors (when that is
    positive). Frank–Wolfe with exact line search (Gilbert's algorithm), stopped when the
    duality gap ``|x|² − min_i x·points_i`` is below ``1e-3 |x|²``.
    """
    x = points.mean(axis=0)
    for _ in range(iterations):
        dots = points @ x
        j = int(np.argmin(dots))
        xx = float(x @ x)
        if xx == 0.0 or xx - dots[j] <= 1e-3 * xx:
            break
        step = points[j] - x
        x = x + min(1.0, (xx - dots[j]) / float(step @ step)) * step
    return x


def default_m(quat_wxyz) -> np.ndarray:
    """The default ``m``: the sum of the poses' unit quaternions, with consistent signs.

    ``m = Σ_i p_i`` where ``p_0`` has ``w ≥ 0`` and each ``p_{i+1}`` takes the sign with
    ``p_i·p_{i+1} ≥ 0``. For two poses this is ``pA + pB``, the default of the cubic mode with
    ``frame="given"``, so both controls get the same rotation weight ``4 m·p``. It is not
    normalised, for the same reason: the paper's kernel basis (eq. 13) is quartic in ``m``, so
    fiber coefficients mean the same as in the cubic mode only for the same ``m``.

    μ_m takes every quaternion in the half-space ``m·p > 0``, so a pose with ``m·p_i ≤ 0``
    would be approached the long way round. If the sum leaves such a pose (three or more
    poses spread unevenly), the default is instead the unit vector that maximises
    ``min_i m·p_i``: the direction of the point of the quaternions' convex hull nearest to
    the origin.

    Raises
    ------
    ParameterError
        If no ``m`` has ``m·p_i > 0`` for every pose: the quaternions, with consistent signs,
        do not lie in one open half-space (the rotations add up to about a full turn or
        more). Then give ``m``, or build the curve in Study space.
    """
    quats, _ = consistent_signs(np.asarray(quat_wxyz, dtype=float))
    m = quats.sum(axis=0)
    if np.all(quats @ m > 1e-9 * float(np.linalg.norm(m))):
        return m
    nearest = _nearest_hull_point(quats)
    norm = float(np.linalg.norm(nearest))
    margin = float(np.min(quats @ nearest)) / norm if norm > 0 else 0.0
    if margin <= 1e-6:
        raise ParameterError(
            "no default m: the poses' quaternions, with consistent signs, do not lie in one "
            f"open half-space (best min m·p_i = {margin:.3g} for |m| = 1), so μ_[m] would take "
            "some of them the long way round; give m, or use space study"
        )
    return nearest / norm


def _default_m_choice(m: np.ndarray, quats: np.ndarray, what: str) -> str:
    if abs(float(np.linalg.norm(m)) - 1.0) < 1e-12 and not np.allclose(
        m, consistent_signs(quats)[0].sum(0)
    ):
        return (
            f"m defaults to the unit vector maximising min m·p_i over the {what}, because their "
            "sum (with consistent signs) left a pose with m·p_i ≤ 0"
        )
    return f"m defaults to the sum of the {what} with consistent signs"


# -- the motion ---------------------------------------------------------------------------------


class BezierMotion(Kinematic):
    """A motion made of rational Bézier segments in R^13 (mapped by μ_m) or R^8 (mapped by κ).

    Build it with :func:`bezier_motion` or :func:`spline_motion`. ``t ∈ [0, 1]`` runs over all
    segments; segment ``j`` of ``S`` covers ``[j/S, (j+1)/S]``. Values of ``t`` outside
    ``[0, 1]`` extrapolate the first or the last segment (and are checked for singularities).

    Attributes
    ----------
    space : {"matrix", "study"}
    controls : ndarray, shape (S, n+1, 13) or (S, n+1, 8)
        The weighted control points of each segment: homogeneous points of R^13
        ``(x0, x1 … x9, x10, x11, x12)``, or Study vectors ``(p0 … p3, q0 … q3)``.
    m : ndarray (4,) or None
        The parameter of μ_[m] (matrix space).
    choices : list of str
        Every choice made for the user, in words.
    """

    def __init__(self, space: str, controls: np.ndarray, m, kind: str, info: dict, choices: list):
        self.space = space
        self.controls = controls
        self.m = m
        self.kind = kind
        self.info = info
        self.choices = choices
        self.degree = controls.shape[1] - 1
        self._mu_t = None if m is None else mu_prime_matrix(m).T
        quats = self._quaternion_controls()
        self._quat_sign = 1.0 if quats[0, 0] @ self.info["first_quaternion"] >= 0 else -1.0
        self._check_segments(0.0, 1.0)

    # -- polynomial pieces ----------------------------------------------------------------------
    def _quaternion_controls(self) -> np.ndarray:
        """Bernstein coefficients ``(S, n+1, 4)`` of the (unnormalised) quaternion ``p(t)``."""
        if self.space == "matrix":
            return self.controls[..., :10] @ self._mu_t
        return self.controls[..., :4]

    def _name(self) -> str:
        return f"{self.kind} ({self.space} space)"

    def _check(self, first: int, last: int, lo: float, hi: float) -> None:
        """Raise if segments ``first … last`` (local parameter in ``[lo, hi]``) are singular."""
        segments = self.controls.shape[0]
        picked = self.controls[first : last + 1]
        if self.space == "matrix":
            ts, ratios = first_small_values(picked[..., 0], lo, hi)
            if np.any(~np.isnan(ts)):
                j = int(np.argmax(~np.isnan(ts)))
                x0 = picked[j, :, 0]
                raise SingularMotionError(
                    f"the {self._name()} passes through infinity at "
                    f"t = {(first + j + ts[j]) / segments:.6g}: x0(t) = 0 (|x0(t)| / max|x0_i| = "
                    f"{ratios[j]:.3g}, tolerance {SINGULAR_TOL:g}); the control points "
                    f"{'of this segment ' if segments > 1 else ''}have x0_i = w_i ψ_i = "
                    f"{[float(f'{v:.6g}') for v in x0]}, which need one sign"
                )
        quats = self._quaternion_controls()[first : last + 1]
        norm2 = bern_mul(np.moveaxis(quats, 1, 0), np.moveaxis(quats, 1, 0)).sum(axis=-1).T
        ts, ratios = first_small_values(norm2, lo, hi)
        if np.any(~np.isnan(ts)):
            j = int(np.argmax(~np.isnan(ts)))
            raise SingularMotionError(
                f"the {self._name()} passes through p(t) = 0 (no rotation defined) at "
                f"t = {(first + j + ts[j]) / segments:.6g}: |p(t)|² / max|coefficient| = "
                f"{ratios[j]:.3g}, tolerance {SINGULAR_TOL:g}"
            )

    def _check_segments(self, lo: float, hi: float) -> None:
        segments = self.controls.shape[0]
        if lo == 0.0 and hi == 1.0:
            self._check(0, segments - 1, 0.0, 1.0)
            return
        if lo < 0.0:
            self._check(0, 0, lo * segments, 0.0)
        if hi > 1.0:
            self._check(segments - 1, segments - 1, 1.0, hi * segments - (segments - 1))

    # -- sampling -------------------------------------------------------------------------------
    def _prepare(self, ts) -> tuple[np.ndarray, tuple]:
        arr = check_ts(ts, one_dimensional=False)
        flat = arr.reshape(-1)
        if flat.size and (flat.min() < 0.0 or flat.max() > 1.0):
            self._check_segments(min(0.0, float(flat.min())), max(1.0, float(flat.max())))
        return flat, arr.shape

    def _evaluate(self, flat: np.ndarray) -> np.ndarray:
        segments = self.controls.shape[0]
        out = np.empty((len(flat), self.controls.shape[-1]))
        # Blocks of samples whose basis has at most BASIS_NUMBERS entries: memory stays bounded
        # for any number of controls.
        size = max(1, BASIS_NUMBERS // (self.degree + 1))
        for lo in range(0, len(flat), size):
            scaled = flat[lo : lo + size] * segments
            j = np.clip(np.floor(scaled), 0, segments - 1).astype(int)
            basis = bernstein_basis(scaled - j, self.degree)
            if segments == 1:
                out[lo : lo + size] = basis @ self.controls[0]
            else:
                out[lo : lo + size] = np.einsum("si,sid->sd", basis, self.controls[j])
        return out

    def points(self, ts) -> np.ndarray:
        """The curve itself: points ``(..., 13)`` of R^13 or Study vectors ``(..., 8)``.

        In matrix space these are affine 3x4 matrices (with homogenising coordinate ``x0``) that
        are in general not rigid; μ_m maps them to the poses of :meth:`matrices`.
        """
        flat, shape = self._prepare(ts)
        return self._evaluate(flat).reshape(shape + (self.controls.shape[-1],))

    def _quat_trans_unnormalised(self, flat: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        x = self._evaluate(flat)
        if self.space == "matrix":
            p = x[:, :10] @ self._mu_t
            trans = x[:, 10:] / x[:, :1]
        else:
            p = x[:, :4]
            trans = translation_numerators(p, x[:, 4:]) / np.sum(p * p, axis=-1)[:, None]
        return p, trans

    def matrices(self, ts) -> np.ndarray:
        """Robotics matrices ``(..., 4, 4)`` of the motion at ``ts`` (any shape; or a sample count).

        The rotation is eq. 4 of ``p(t)`` divided by ``|p(t)|²``; the translation is
        ``x_t / x0`` (matrix space, μ_m) or ``(p q̄ − q p̄) / |p|²`` (study space, κ).
        """
        flat, shape = self._prepare(ts)
        p, trans = self._quat_trans_unnormalised(flat)
        out = np.zeros((flat.size, 4, 4))
        out[:, :3, :3] = (rotation_numerators(p) / np.sum(p * p, axis=-1)[:, None]).reshape(
            -1, 3, 3
        )
        out[:, :3, 3] = trans
        out[:, 3, 3] = 1.0
        return out.reshape(shape + (4, 4))

    def quat_trans(self, ts) -> tuple[np.ndarray, np.ndarray]:
        """Unit quaternions ``(..., 4)`` (w, x, y, z) and translations ``(..., 3)``.

        The quaternions come from the curve's own ``p(t)``, so they are continuous in ``t``
        (no sign jumps); at ``t = 0`` the first control pose's quaternion has ``w ≥ 0``.
        """
        flat, shape = self._prepare(ts)
        p, trans = self._quat_trans_unnormalised(flat)
        quat = self._quat_sign * p / np.linalg.norm(p, axis=-1, keepdims=True)
        return quat.reshape(shape + (4,)), trans.reshape(shape + (3,))

    def study(self, ts) -> np.ndarray:
        """Unit Study parameters ``(..., 8)`` (``|p| = 1``, ``q = −½ t p``) of the samples."""
        from ..poses import study_from_quat_trans

        quat, trans = self.quat_trans(ts)
        return study_from_quat_trans(quat, trans)

    def _tables(self) -> np.ndarray:
        """Coefficient tables ``(S, 2n + 1, 14)`` of the segments, as the two-pose modes have
        (:mod:`a2b.motions._rational`): the rotation ``B(p, p) / |p|²`` of eq. 4 and the
        translation ``x_t / x0`` (matrix space) or ``(p q̄ − q p̄) / |p|²`` (study space), each
        numerator and denominator a Bernstein polynomial of degree ``2n`` in the segment's own
        parameter."""
        if getattr(self, "_table_cache", None) is None:
            quats = np.moveaxis(self._quaternion_controls(), 1, 0)  # (n + 1, S, 4)
            rot = bern_mul(quats, quats, rotation_numerators)
            den = bern_mul(quats, quats, lambda a, b: np.sum(a * b, axis=-1))
            if self.space == "matrix":
                points = np.moveaxis(self.controls, 1, 0)
                trans = bern_elevate(points[..., 10:], 2 * self.degree)
                trans_den = bern_elevate(points[..., 0], 2 * self.degree)
            else:
                trans = bern_mul(
                    quats, np.moveaxis(self.controls[..., 4:], 1, 0), translation_numerators
                )
                trans_den = den
            self._table_cache = make_table(
                np.moveaxis(rot, 0, -2),
                np.moveaxis(den, 0, -1),
                np.moveaxis(trans, 0, -2),
                np.moveaxis(trans_den, 0, -1),
            )
        return self._table_cache

    def derivatives(self, ts, order: int = 1, point=None) -> np.ndarray:
        """The matrices and their exact derivatives in ``t`` up to ``order`` (at most 3) at
        1-D ``ts`` (or a count): ``(order + 1, N, 4, 4)``, as :meth:`Motion.derivatives`
        (with ``point``: the body point's path, ``(order + 1, N, 3)``).

        Each segment is a rational curve of degree ``2n`` (:meth:`_tables`); segment ``j`` runs
        at ``S`` times the speed of ``t``, so its ``k``-th derivative is scaled by ``S^k``. At a
        joint the value is that of the segment that starts there (a spline is C¹: its second
        derivatives may jump).
        """
        if order not in (0, 1, 2, 3):
            raise ParameterError(f"order must be 0, 1, 2 or 3, got {order!r}")
        flat, shape = self._prepare(ts)
        if len(shape) != 1:
            raise ParameterError(f"ts must be a 1-D array or a count, got shape {shape}")
        segments = self.controls.shape[0]
        scaled = flat * segments
        j = np.clip(np.floor(scaled), 0, segments - 1).astype(int)
        bases = bernstein_derivatives(scaled - j, 2 * self.degree, order)
        bases *= (float(segments) ** np.arange(order + 1))[:, None, None]
        per_sample = np.moveaxis(bases, 1, 0)[:, :, None, :]  # (N, r + 1, 1, k)
        out = table_derivatives(  # (N, r + 1, 1, 4, 4) or (N, r + 1, 1, 3)
            per_sample, self._tables()[j], None if point is None else check_point(point)
        )
        return np.moveaxis(out[:, :, 0], 0, 1)

    def joints(self) -> list[float]:
        """The parameters ``t`` where segments meet (empty for a single Bézier curve)."""
        segments = self.controls.shape[0]
        return [j / segments for j in range(1, segments)]

    def describe(self) -> dict:
        """The construction as plain data: space, degree, segments, m, weights, choices."""
        out = {
            "kind": self.kind,
            "space": self.space,
            "degree": self.degree,
            "segments": int(self.controls.shape[0]),
            "joints": self.joints(),
        }
        if self.m is not None:
            out["m"] = [float(v) for v in self.m]
        out.update(self.info.get("describe", {}))
        out["choices"] = list(self.choices)
        return out


# -- constructions ------------------------------------------------------------------------------


#: Pose numbers listed in a choice; the rest are counted (a trajectory's spline can flip
#: hundreds of thousands).
NUMBERS_LISTED = 10


def _numbers(indices) -> str:
    """The numbers (from 1) of poses ``indices``: the first :data:`NUMBERS_LISTED`, and how
    many more."""
    indices = list(indices)
    listed = ", ".join(str(i + 1) for i in indices[:NUMBERS_LISTED])
    more = len(indices) - NUMBERS_LISTED
    return listed + (f" and {more} more" if more > 0 else "")


def _matrix_rotation_weights(m: np.ndarray, quats: np.ndarray, label, choices: list) -> np.ndarray:
    """``4 m·p_i`` with the signs of the ``p_i`` made consistent along the poses; checks ``m``."""
    chain, _ = consistent_signs(quats)
    dots = np.array([check_not_orthogonal(m, chain[i], label(i)) for i in range(chain.shape[0])])
    if np.any(dots < 0.0) and np.any(dots > 0.0):
        which = _numbers(np.nonzero(dots * dots[0] < 0.0)[0])
        choices.append(
            f"m·p_i has the opposite sign for pose(s) {which} (quaternion signs consistent along "
            "the poses): μ_m takes their quaternions with the other sign, so the motion turns the "
            "long way round next to them"
        )
    return 4.0 * dots


def bezier_motion(
    control_poses,
    space: str = "matrix",
    *,
    m=None,
    weights=None,
    alphas=None,
    basis: str = "auto",
    offsets=None,
) -> BezierMotion:
    """The Bézier motion of control poses, as an object to sample (see :func:`bezier`)."""
    if space not in SPACES:
        raise ParameterError(f"unknown space {space!r}; expected one of {', '.join(SPACES)}")
    poses = _check_poses(control_poses, "control poses")
    k = poses.shape[0]
    w = _check_weights(weights, k)
    quats, _ = quat_trans_from_matrices(poses)
    choices: list[str] = []

    def label(i: int) -> str:
        return _greville(i, k)

    if space == "matrix":
        if offsets is not None:
            raise ParameterError(
                "space matrix does not take offsets (κ-fiber offsets belong to space study)"
            )
        if basis not in BASES:
            raise ParameterError(f"unknown kernel basis {basis!r}; expected one of {BASES}")
        if m is None:
            m_arr = default_m(quats)
            choices.append(_default_m_choice(m_arr, quats, "control quaternions"))
        else:
            m_arr = check_m(m)
        rot_w = _matrix_rotation_weights(m_arr, quats, label, choices)
        if alphas is None:
            points = model_points_from_matrices(poses)
        else:
            a = _per_control(alphas, k, "alphas", 6)
            points = np.concatenate(
                [mu_fiber_points(poses[i], m_arr, a[i : i + 1], basis) for i in range(k)]
            )
        points = points * w[:, None]
        describe = {
            "weights": [float(v) for v in w],
            "x0": [float(v) for v in points[:, 0]],
            "rotation_weights": [float(v) for v in w * rot_w],
        }
        first = quats[0]
    else:
        if m is not None or alphas is not None or basis != "auto":
            given = [n for n, v in (("m", m), ("alphas", alphas)) if v is not None]
            given += ["basis"] if basis != "auto" else []
            raise ParameterError(
                f"space study does not take {', '.join(given)} (they belong to space matrix)"
            )
        m_arr = None
        h, flipped = consistent_signs(study_from_matrices(poses))
        if flipped:
            choices.append(
                "flipped the sign of the Study vector of control pose(s) "
                + _numbers(flipped)
                + " so that consecutive quaternions have p_i·p_{i+1} ≥ 0"
            )
        s = np.zeros(k) if offsets is None else _per_control(offsets, k, "offsets")
        if offsets is not None:
            h = np.concatenate([kappa_fiber_points(h[i], s[i : i + 1]) for i in range(k)])
        points = h * w[:, None]
        describe = {"weights": [float(v) for v in w], "offsets": [float(v) for v in s]}
        first = h[0, :4]
    return BezierMotion(
        space,
        points[None],
        m_arr,
        "Bézier motion",
        {"first_quaternion": first, "describe": describe},
        choices,
    )


def bezier(control_poses, ts, space: str = "matrix", **parameters) -> np.ndarray:
    """Sample the Bézier motion of control poses (section 6, figure 4).

    Parameters
    ----------
    control_poses : array_like, shape (k, 4, 4)
        ``k ≥ 2`` robotics-layout poses; the curve has degree ``k − 1``.
    ts : array_like or int
        Sample parameters of any shape (``t = 0`` is the first control pose, ``t = 1`` the
        last; values outside extrapolate), or a number of samples equally spaced on ``[0, 1]``.
    space : {"matrix", "study"}
        ``"matrix"``: de Casteljau in R^13, then μ_m in the given frame (eq. 12).
        ``"study"``: de Casteljau over unit Study vectors with consistent signs, then κ.
    **parameters
        ``weights`` (both spaces): ``(k,)`` positive numbers that multiply the homogeneous
        control points (a rational Bézier curve); default all 1.

        matrix space: ``m`` (4 numbers, default :func:`default_m`: the sum of the control
        quaternions with consistent signs); ``alphas``: ``(k, 6)`` fiber coefficients, one
        row per control pose, in the kernel basis ``basis`` (``"auto"``, the default: the paper's
        eq. 13, as in the cubic mode, unless it degenerates for m; or ``"paper"``, ``"rref"``,
        see :func:`a2b.extended.kernel_basis`).

        study space: ``offsets``: ``(k,)`` κ-fiber offsets ``s_i`` (control ``h_i + s_i ε p_i``).

    Returns
    -------
    ndarray, shape ts.shape + (4, 4)
        Robotics-layout matrices; with two controls, ``space="matrix"`` is the cubic mode with
        ``frame="given"`` (``alphas = [alpha, beta]``) and ``space="study"`` is the Darboux mode
        with ``δ = s_1 − s_0``.

    Raises
    ------
    PoseError
        A control pose is not a valid pose.
    ParameterError
        A control pose's quaternion is orthogonal to ``m`` (stating which control and its
        parameter ``t``), or a parameter has the wrong shape or value.
    SingularMotionError
        The curve passes through infinity (``x0(t) = 0``) or through ``p(t) = 0`` for some
        ``t`` in ``[0, 1]`` (or the sampled range), stating ``t``.

    Examples
    --------
    >>> import numpy as np
    >>> from a2b import bezier
    >>> turn = np.eye(4); turn[:2, :2] = [[0, -1], [1, 0]]; turn[0, 3] = 2.0
    >>> bezier([np.eye(4), turn], [0.0, 0.5, 1.0]).shape
    (3, 4, 4)
    """
    return bezier_motion(control_poses, space, **parameters).matrices(ts)


def spline_motion(poses, space: str = "matrix", *, m=None) -> BezierMotion:
    """The C¹ Catmull–Rom spline through key poses, as an object to sample (see :func:`spline`)."""
    if space not in SPACES:
        raise ParameterError(f"unknown space {space!r}; expected one of {', '.join(SPACES)}")
    keys = _check_poses(poses, "poses")
    count = keys.shape[0]
    quats, _ = quat_trans_from_matrices(keys)
    choices = [
        (
            "inner control points by the uniform Catmull–Rom rule T_j = (X_{j+1} − X_{j−1}) / 2, "
            "end tangents X_1 − X_0 and X_N − X_{N−1}"
        )
    ]
    segments = count - 1

    def label(i: int) -> str:
        return f"pose {i + 1} of {count} (t = {i / segments:.6g})"

    if space == "matrix":
        if m is None:
            m_arr = default_m(quats)
            choices.append(_default_m_choice(m_arr, quats, "poses' quaternions"))
        else:
            m_arr = check_m(m)
        _matrix_rotation_weights(m_arr, quats, label, choices)
        points = model_points_from_matrices(keys)
        first = quats[0]
    else:
        if m is not None:
            raise ParameterError("space study does not take m (it belongs to space matrix)")
        m_arr = None
        points, flipped = consistent_signs(study_from_matrices(keys))
        if flipped:
            choices.append(
                "flipped the sign of the Study vector of pose(s) "
                + _numbers(flipped)
                + " so that consecutive quaternions have p_i·p_{i+1} ≥ 0"
            )
        first = points[0, :4]
    tangents = np.empty_like(points)
    tangents[0] = points[1] - points[0]
    tangents[-1] = points[-1] - points[-2]
    tangents[1:-1] = 0.5 * (points[2:] - points[:-2])
    controls = np.stack(
        [
            points[:-1],
            points[:-1] + tangents[:-1] / 3.0,
            points[1:] - tangents[1:] / 3.0,
            points[1:],
        ],
        axis=1,
    )
    describe = {"poses": count}
    return BezierMotion(
        space, controls, m_arr, "spline", {"first_quaternion": first, "describe": describe}, choices
    )


def spline(poses, ts_or_samples, space: str = "matrix", *, m=None) -> np.ndarray:
    """Sample the C¹ spline through key poses: cubic Bézier segments with Catmull–Rom tangents.

    Parameters
    ----------
    poses : array_like, shape (N+1, 4, 4)
        ``N + 1 ≥ 2`` robotics-layout key poses.
    ts_or_samples : array_like or int
        Sample parameters of any shape, or a number of samples equally spaced on ``[0, 1]``.
        Key pose ``j`` is at ``t = j / N``; ``s N + 1`` samples hit every key pose.
    space : {"matrix", "study"}
        Where the tangents and the segments are built: R^13 (mapped by μ_m in the given
        frame), or unit Study vectors with consistent signs (mapped by κ).
    m : array_like, shape (4,), optional
        matrix space only: the parameter of μ_[m], one for all segments (that keeps the motion
        C¹). Default :func:`default_m` of the key poses.

    Returns
    -------
    ndarray, shape ts.shape + (4, 4)

    Notes
    -----
    With the points ``X_j`` of the key poses and the tangents ``T_j = (X_{j+1} − X_{j−1}) / 2``
    (``T_0 = X_1 − X_0``, ``T_N = X_N − X_{N−1}``), segment ``j`` is the cubic Bézier curve
    with the controls ``X_j, X_j + T_j/3, X_{j+1} − T_{j+1}/3, X_{j+1}`` on
    ``t ∈ [j/N, (j+1)/N]``. In matrix space every control point has ``x0 = 1``, so the curve
    never passes through infinity and the translation is the Catmull–Rom spline of the
    translations.

    Raises
    ------
    PoseError, ParameterError, SingularMotionError
        As for :func:`bezier`; a key pose orthogonal to ``m`` is reported with its ``t``.
    """
    return spline_motion(poses, space, m=m).matrices(ts_or_samples)
