"""The interface every motion of a2b shares, for any number of pose pairs.

A :class:`Motion` has a leading shape ``S``: the shape of the pose pairs it was built from
(``()`` for one pair). Every per-motion quantity is an array with that leading shape, so one
implementation serves a single motion and a batch of a million; rare or ill-conditioned cases
are masks inside it. Sampling at ``N`` parameters ``ts`` gives ``S + (N, ...)``.
"""

from __future__ import annotations

import numbers
from math import isfinite

import numpy as np

from ..elements import Notes, anywhere, as_numbers, everywhere, refuse, value, warn
from ..errors import ParameterError, SingularMotionError
from ..frames import ScrewFrame
from ..kinematics import Kinematic, check_point
from ..poses import rotations_from_quaternions, study_from_quat_trans
from ..study import dots
from ._rational import (
    EPS,
    FRAGILE_TOL,
    SENSITIVE_TOL,
    SINGULAR_TOL,
    evaluate_table,
    evaluate_translations,
    table_derivatives,
)


def check_ts(ts, one_dimensional: bool = True) -> np.ndarray:
    """Sample parameters: a count ``n ≥ 2`` (``n`` evenly spaced t in [0, 1]) or finite values.

    Values outside [0, 1] extrapolate. ``one_dimensional``: the values must be a 1-D array.
    """
    return _checked_ts(ts, one_dimensional)[0]


def _checked_ts(ts, one_dimensional: bool) -> tuple[np.ndarray, float | None, float | None]:
    """:func:`check_ts`, and the smallest and the largest value (``None`` for no values):
    the values are finite where these two are."""
    if isinstance(ts, numbers.Integral) and not isinstance(ts, (bool, np.bool_)):
        if ts < 2:
            raise ParameterError(f"the number of samples must be at least 2, got {ts}")
        return np.linspace(0.0, 1.0, int(ts)), 0.0, 1.0
    arr = as_numbers(ts, "ts")
    if one_dimensional and arr.ndim != 1:
        raise ParameterError(f"ts must be a 1-D array or a count, got shape {arr.shape}")
    if not arr.size:
        return arr, None, None
    lo, hi = float(np.minimum.reduce(arr, axis=None)), float(np.maximum.reduce(arr, axis=None))
    if not (isfinite(lo) and isfinite(hi)):  # NaN spreads to both, an infinity to one
        raise ParameterError("ts contains NaN or infinity")
    return arr, lo, hi


def check_table(table: np.ndarray, shape: tuple) -> None:
    """Raise if a motion's coefficients overflowed (huge parameters or translations)."""
    finite = np.isfinite(table)
    if everywhere(finite):
        return
    finite = finite.reshape(shape + (-1,))
    refuse(
        ParameterError,
        ~finite.all(axis=-1),
        lambda i: (
            "the motion's coefficients overflow float64 (a parameter or a translation is too "
            "large, largest finite entry "
            f"{_largest_finite(table.reshape((-1,) + table.shape[len(shape) :])[i]):.3g})"
        ),
        shape,
    )


#: How far a motion's computed end poses may be from A and B: rotation entries absolutely,
#: translations relative to ``max(|tA|, |tB|)``. Every mode reproduces them to about 1e-15; a
#: parameter so large that its terms swamp the poses (``delta = 1e16``) would not.
END_TOL = 1e-9
#: The denominator column (12 rotation, 13 translation) of each entry of the rows of [R | t].
_DENOMINATOR_OF = [12, 12, 12, 13] * 3


def check_ends(motion) -> None:
    """Refuse a motion whose samples at t = 0 and t = 1 are not its start and end poses."""
    residual = end_residuals(motion)
    refuse(
        ParameterError,
        ~(residual <= END_TOL),
        lambda i: (
            f"the {motion.what} does not reach its end poses in double precision: its samples at "
            f"t = 0 and 1 are {value(residual, i):.3g} away from A and B (rotation entries, and "
            f"translations relative to the larger of |tA|, |tB|), tolerance {END_TOL:g}; a "
            "parameter is too large for these poses"
        ),
        motion.shape,
    )


def end_residuals(motion) -> np.ndarray:
    """How far each motion's samples at t = 0 and 1 are from its poses: the largest error of a
    rotation entry or of a translation relative to ``max(|tA|, |tB|)``, shape ``S``."""
    # numerators and denominators at t = 0 and 1 (p(t) is a unit quaternion there: no fragile
    # rotation), compared with the poses times their denominators: whole rows of 12 at a time
    values = np.matmul(motion._basis(np.array([0.0, 1.0])), motion.table)
    shape = values.shape[:-2]
    poses = np.stack([motion.start, motion.end], axis=-3).reshape(shape + (2, 16))[..., :12]
    denominators = values[..., _DENOMINATOR_OF]
    miss = poses * denominators
    np.subtract(values[..., :12], miss, out=miss)
    np.divide(miss, denominators, out=miss)
    np.abs(miss, out=miss)
    miss = miss.reshape(shape + (2, 3, 4))
    rotation = miss[..., :3].max(axis=(-3, -2, -1))
    translation = np.sqrt(np.einsum("...ij,...ij->...i", miss[..., 3], miss[..., 3])).max(axis=-1)
    size = np.sqrt(np.einsum("...ij,...ij->...i", poses[..., 3:12:4], poses[..., 3:12:4]))
    size = size.max(axis=-1)
    return np.maximum(rotation, translation / np.where(size > 0.0, size, 1.0))


#: A motion whose moving origin strays farther than this many times the distance of the two
#: positions from the straight segment between them gets a warning. The default motions of
#: every mode stay within 0.5 of it (20,000 random pairs each), so only a motion with a
#: parameter given is checked.
EXCURSION_RATIO = 10.0


def check_excursion(motion) -> None:
    """Warn where the moving origin strays far from the segment between its two positions.

    The path is sampled at 9 parameters in [0, 1]; its largest distance from the segment
    ``tA tB`` is compared with ``|tB − tA|``. A large ratio usually means a parameter (an
    amplitude λ, an offset δ, the cubic's a and b) far larger than these poses call for. A
    motion already warned about (close to p(t) = 0) is not warned about again.
    """
    ts = np.linspace(0.0, 1.0, 9)
    with np.errstate(over="ignore", invalid="ignore"):
        path = evaluate_translations(motion._basis(ts), motion.table)
    a, b = motion.start[..., None, :3, 3], motion.end[..., None, :3, 3]
    chord = b - a
    length2 = np.sum(chord * chord, axis=-1)
    along = np.clip(np.sum((path - a) * chord, axis=-1) / np.where(length2 > 0, length2, 1), 0, 1)
    away = np.linalg.norm(path - a - along[..., None] * chord, axis=-1).max(axis=-1)
    length = np.sqrt(length2[..., 0])
    size = np.maximum(np.abs(a).max(axis=(-2, -1)), np.abs(b).max(axis=(-2, -1)))
    far = (away > EXCURSION_RATIO * length + 1e-9 * size) & ~motion.warning_notes.mask()

    def message(i: int) -> str:
        there = f"{value(away, i):.3g}"
        if value(length, i) > 0:
            ratio = f"{value(away, i) / value(length, i):.3g} times their distance"
            return (
                f"the {motion.what} takes the origin up to {there} away from the straight "
                f"segment between its two positions, {ratio} {value(length, i):.3g}; a parameter "
                "may be far larger than these poses call for"
            )
        return (
            f"the {motion.what} takes the origin up to {there} away from its position, which "
            "the two poses share; a parameter may be far larger than these poses call for"
        )

    motion._warn(far, message)


def _largest_finite(values: np.ndarray) -> float:
    return float(np.max(np.abs(values[np.isfinite(values)]), initial=0.0))


def evenly_spaced(samples: int, size: int):
    """``t = i / (samples − 1)``, ``i = 0 … samples − 1``, as arrays of at most ``size``.

    Bit for bit the values of ``numpy.linspace(0, 1, samples)``, without ever holding them
    all: 10⁹ samples cost one chunk of memory.
    """
    step = 1.0 / (samples - 1)
    for lo in range(0, samples, size):
        hi = min(lo + size, samples)
        ts = np.arange(lo, hi, dtype=np.int64).astype(np.float64)
        ts *= step
        if hi == samples:
            ts[-1] = 1.0
        yield ts


def linear_path(ts: np.ndarray, ends: np.ndarray) -> np.ndarray:
    """``(1−t) ends[..., 0, :] + t ends[..., 1, :]``: shape ``S + (N, 4)`` for ends ``S + (2,
    4)`` and ``ts`` of shape ``(N,)`` or ``S + (N,)``."""
    u = (1.0 - ts)[..., None]
    return u * ends[..., None, 0, :] + ts[..., None] * ends[..., None, 1, :]


def path_minimum(ends: np.ndarray, lo: float, hi: float) -> tuple[np.ndarray, np.ndarray]:
    """Where ``|p(t)|²`` of ``p(t) = (1−t) p0 + t p1`` is smallest on ``[lo, hi]``, and how small.

    ``ends`` is ``S + (2, 4)``. Returns ``(t_min, ratio)`` of shape ``S``, with
    ``ratio = |p(t_min)|² / max(|p0|², |p1|²)``.
    """
    p_a, p_b = ends[..., 0, :], ends[..., 1, :]
    diff = p_b - p_a
    rows = np.concatenate([ends, diff[..., None, :]], axis=-2)  # pA, pB, pB − pA
    gram = dots(rows[..., :, None, :], rows[..., None, :, :])  # every product in one call
    dd = gram[..., 2, 2]
    flat = dd == 0.0
    if anywhere(flat):
        dd = np.where(flat, 1.0, dd)
    t_min = np.minimum(np.maximum(-gram[..., 0, 2] / dd, lo), hi)
    if anywhere(flat):
        t_min = np.where(flat, 0.0, t_min)
    p_min = p_a + t_min[..., None] * diff
    scale = np.maximum(gram[..., 0, 0], gram[..., 1, 1])
    return t_min, dots(p_min, p_min) / scale


def linear_root(v0, v1) -> np.ndarray:
    """The root of ``(1−t) v0 + t v1`` (NaN where it is a non-zero constant; 0 where zero)."""
    v0, v1 = np.asarray(v0, dtype=float), np.asarray(v1, dtype=float)
    same = v0 == v1
    with np.errstate(divide="ignore", invalid="ignore"):
        root = v0 / (v0 - v1) + 0.0  # + 0.0 turns −0 into 0
    return np.where(same, np.where(v0 != 0.0, np.nan, 0.0), root)


class Motion(Kinematic):
    """Motions ``C(t)`` with ``C(0) = A`` and ``C(1) = B``, sampled from coefficient tables.

    Values of ``t`` outside ``[0, 1]`` extrapolate along the same rational (or, for the screw,
    helical) motion; a2b checks the extended range for singularities too.

    Every ndarray attribute has the leading shape :attr:`shape` (``motion[i]`` takes elements
    of all of them at once). Subclasses set ``mode``, ``table`` (``S + (k, 14)``),
    ``quat_ends`` (``S + (2, 4)``) and implement ``_basis``, ``_quats``, ``_check_interval``
    and ``_describe``.
    """

    mode: str = ""
    #: Short name of the motion in messages.
    what: str = "motion"
    table: np.ndarray
    quat_ends: np.ndarray
    #: ``S + (2, 4)``: the quaternions of A and B as given (:func:`a2b.api.motion` of
    #: ``(quat_wxyz, translation)`` poses), or ``None``: see :attr:`end_quaternions`.
    given_ends: np.ndarray | None = None

    def __init__(self, start: np.ndarray, end: np.ndarray, frame: ScrewFrame):
        self.start = start
        self.end = end
        self.frame = frame
        self.notes = Notes(frame.shape, list(frame.notes.rules))
        self.warning_notes = Notes(frame.shape)

    # -- the batch -----------------------------------------------------------------------------
    @property
    def shape(self) -> tuple:
        return self.frame.shape

    def __len__(self) -> int:
        if not self.shape:
            raise TypeError("a single motion has no length")
        return self.shape[0]

    def __getitem__(self, index) -> Motion:
        """The motions ``index`` (any numpy index into the leading shape) as a new Motion."""
        if not self.shape:
            raise TypeError("a single motion cannot be indexed")
        out = object.__new__(type(self))
        ndim = len(self.shape)
        for name, item in self.__dict__.items():
            if isinstance(item, np.ndarray) and item.shape[:ndim] == self.shape:
                item = item[index]
                item = item[()] if item.ndim == 0 else item
            elif isinstance(item, (ScrewFrame, Notes)):
                item = item[index]
            out.__dict__[name] = item
        return out

    @property
    def choices(self):
        """Every choice made for the user: a list of str, or nested lists of shape ``S``."""
        return self.notes.tolist()

    @property
    def warnings(self):
        """The sensitivity warnings issued, as :attr:`choices`."""
        return self.warning_notes.tolist()

    def _refuse(self, error, bad, message) -> None:
        refuse(error, bad, message, self.shape)

    def _warn(self, where, message) -> None:
        """Issue an :class:`A2bWarning` where ``where`` holds and record it for ``describe``."""
        warn(where, message, self.shape, self.warning_notes)

    def _check_path(self, lo: float, hi: float) -> None:
        """Refuse where ``p(t)`` (nearly) vanishes on ``[lo, hi]``; warn where it comes close.

        ``|p(t)|²`` is a quadratic in t; its minimum on the interval, relative to
        ``max(|p0|², |p1|²)``, must exceed ``SINGULAR_TOL = 1e-12``. Between that and
        ``SENSITIVE_TOL = 1e-7`` the motion is defined but amplifies rounding of the input by
        about ``ε / ratio``, and a2b warns.
        """
        t_min, ratio = path_minimum(self.quat_ends, lo, hi)
        if lo == 0.0 and hi == 1.0:  # kept for _rotation_is_fragile: sampling in [0, 1]
            self._unit_ratio = ratio
        self._refuse(
            SingularMotionError,
            ratio <= SINGULAR_TOL,
            lambda i: (
                f"the {self.what} passes through p(t) = 0 (no rotation defined) at "
                f"t = {value(t_min, i):.6g}: |p(t)|² / |p|²_max = {value(ratio, i):.3g}, "
                f"tolerance {SINGULAR_TOL:g}"
            ),
        )
        self._warn(
            ratio <= SENSITIVE_TOL,
            lambda i: (
                f"the {self.what} passes close to p(t) = 0 at t = {value(t_min, i):.6g} "
                f"(|p(t)|² / |p|²_max = {value(ratio, i):.3g}): its poses near there change by "
                f"about {EPS / value(ratio, i):.1g} of the motion's size under rounding of the "
                f"input"
            ),
        )

    # -- to implement --------------------------------------------------------------------------
    def _basis(self, ts: np.ndarray) -> np.ndarray:  # pragma: no cover - abstract
        """The basis at ``ts``: ``(N, k)`` shared by every motion, or ``S + (N, k)``."""
        raise NotImplementedError

    def _basis_derivatives(self, ts: np.ndarray, order: int) -> np.ndarray:
        """The basis and its derivatives in t: ``(r + 1, N, k)`` or ``S + (r + 1, N, k)``."""
        raise NotImplementedError  # pragma: no cover - abstract

    def _quats(self, ts: np.ndarray) -> np.ndarray:
        """``p(t)``, not normalised, shape ``S + (N, 4)``."""
        return linear_path(ts, self.quat_ends)

    def _check_interval(self, lo: float, hi: float) -> None:
        """Raise :class:`SingularMotionError` if a motion is singular on ``[lo, hi]``."""
        self._check_path(lo, hi)

    def _rotation_is_fragile(self, lo: float, hi: float) -> np.ndarray:
        """Where the table's rotation would lose rigidity (``p(t)`` close to 0 on [lo, hi])."""
        ratio = self.__dict__.get("_unit_ratio") if lo == 0.0 and hi == 1.0 else None
        if ratio is None:
            ratio = path_minimum(self.quat_ends, lo, hi)[1]
        return ratio < FRAGILE_TOL

    def singular_t(self) -> list[float]:
        """Real ``t`` (any value) where a single motion is undefined, for ``describe``."""
        return []

    def _describe(self) -> dict:  # pragma: no cover - abstract
        raise NotImplementedError

    # -- sampling ------------------------------------------------------------------------------
    def _prepare(self, ts) -> np.ndarray:
        """``ts`` checked: a count, ``(N,)`` shared by every motion, or ``S + (N,)``, one row of
        parameters per motion (``S = ()``: 1-D only)."""
        return self._sampled(ts)[0]

    def _sampled(self, ts) -> tuple[np.ndarray, tuple[float, float] | None]:
        """:meth:`_prepare`'s ``ts``, and ``[lo, hi]``: ``[0, 1]`` widened to hold them
        (``None`` for no ``ts``)."""
        arr, lo, hi = _checked_ts(ts, one_dimensional=False)
        if arr.ndim == 0 or (arr.ndim > 1 and arr.shape[:-1] != self.shape):
            raise ParameterError(
                f"ts must be a count, a 1-D array shared by every motion or an array of shape "
                f"{self.shape + ('N',)} (one row per motion), got shape {arr.shape}"
            )
        if not arr.size:
            return arr, None
        span = min(0.0, lo), max(1.0, hi)
        if span != (0.0, 1.0):
            self._check_interval(*span)
        return arr, span

    def _check_finite(self, ts: np.ndarray, values: np.ndarray) -> None:
        """Raise if extrapolating to far-away ``t`` overflowed (values ``S + (N, ...)``)."""
        n = ts.shape[-1]
        bad = ~np.isfinite(values.reshape(self.shape + (n, -1))).all(axis=-1)
        first = np.argmax(bad, axis=-1)
        rows = np.broadcast_to(ts, bad.shape).reshape(-1, n)
        self._refuse(
            ParameterError,
            bad.any(axis=-1),
            lambda i: (
                f"the motion overflows float64 at t = {float(rows[i, np.ravel(first)[i]]):.6g}: "
                "extrapolate less far"
            ),
        )

    def matrices(self, ts) -> np.ndarray:
        """Sample the motions: robotics matrices ``S + (N, 4, 4)``.

        ``ts`` is a 1-D array of ``N`` parameters, a count ``N`` (evenly spaced in [0, 1]), or
        an array ``S + (N,)`` that gives each motion parameters of its own.
        Where ``p(t)`` comes close to 0 (``|p|²/max|p|² < 1e-2``), the rotation block is taken
        from the normalised ``p(t)`` instead of the coefficient table, so that every sample
        stays rigid to rounding.
        """
        arr, span = self._sampled(ts)
        with np.errstate(over="ignore", invalid="ignore"):  # far extrapolation: checked below
            out = evaluate_table(self._basis(arr), self.table)
            if span is not None:
                fragile = self._rotation_is_fragile(*span)
                if not self.shape and fragile:
                    out[..., :3, :3] = rotations_from_quaternions(self._quats(arr))
                elif self.shape and anywhere(fragile):
                    own = arr if arr.ndim == 1 else arr[fragile]
                    rotations = rotations_from_quaternions(self[fragile]._quats(own))
                    out[fragile, :, :3, :3] = rotations
        if span is not None and span != (0.0, 1.0):
            self._check_finite(arr, out[..., :3, :])
        return out

    def derivatives(self, ts, order: int = 1, point=None) -> np.ndarray:
        """The matrices and their derivatives in ``t`` up to ``order`` (at most 3):
        ``S + (order + 1, N, 4, 4)``, index ``k`` along the new axis holding ``d^k M / dt^k``.
        With ``point`` (``(x, y, z)`` in the moving frame), the path of that body point and
        its derivatives instead, ``S + (order + 1, N, 3)``, at a fraction of the cost.

        Exact: the derivatives of the motion's coefficient tables (quotient rule for the
        rational modes, derivatives of ``sin tφ`` and ``vers tφ`` for the screw), not finite
        differences. ``ts`` as for :meth:`matrices`. The velocities of :mod:`a2b.kinematics`
        (:meth:`twists`, :meth:`accelerations`) come from here.
        """
        if order not in (0, 1, 2, 3):
            raise ParameterError(f"order must be 0, 1, 2 or 3, got {order!r}")
        arr = self._prepare(ts)
        with np.errstate(over="ignore", invalid="ignore"):
            out = table_derivatives(
                self._basis_derivatives(arr, order),
                self.table,
                None if point is None else check_point(point),
            )
        if arr.size and (arr.min() < 0.0 or arr.max() > 1.0):
            if point is None:  # the samples' rows of [R | t] and of the derivatives
                rows = np.moveaxis(out, len(self.shape), -3)[..., :3, :]
            else:
                rows = np.moveaxis(out, len(self.shape), -2)
            self._check_finite(arr, rows)
        return out

    def quat_trans(self, ts) -> tuple[np.ndarray, np.ndarray]:
        """Unit quaternions ``S + (N, 4)`` (w, x, y, z) and translations ``S + (N, 3)``.

        The quaternions come from the motion's own ``p(t)`` and are therefore continuous in
        ``t`` (no sign jumps), starting at the sign of A's quaternion with ``w ≥ 0``. At
        ``t = 0`` and ``t = 1`` they are A's and B's quaternions exactly as the motion was
        built from them (:attr:`end_quaternions`), at the sign of ``p(t)`` there.
        """
        arr = self._prepare(ts)
        quat = self._quats(arr)
        quat /= np.sqrt(dots(quat, quat))[..., None]
        self._pin_ends(arr, quat)
        with np.errstate(over="ignore", invalid="ignore"):  # far extrapolation: checked below
            trans = evaluate_translations(self._basis(arr), self.table)
        if arr.size and (arr.min() < 0.0 or arr.max() > 1.0):
            self._check_finite(arr, trans)
        return quat, trans

    @property
    def end_quaternions(self) -> np.ndarray:
        """The unit quaternions ``S + (2, 4)`` (w, x, y, z) of A and B: as given, where the
        poses were given as quaternions (:attr:`given_ends`), else those the motion was built
        from (the screw frame's ``p_start`` and ``p_end``)."""
        if self.given_ends is not None:
            return self.given_ends
        return np.stack([self.frame.p_start, self.frame.p_end], axis=-2)

    def _pin_ends(self, ts: np.ndarray, quat: np.ndarray) -> None:
        """Put :attr:`end_quaternions` into the rows of ``quat`` (``S + (N, 4)``) at ``ts`` 0
        and 1, each at the sign that the computed row has."""
        for k, t in enumerate((0.0, 1.0)):
            at = np.broadcast_to(ts == t, quat.shape[:-1])
            if not anywhere(at):
                continue
            end = np.broadcast_to(self.end_quaternions[..., k, None, :], quat.shape)[at]
            sign = np.where(dots(quat[at], end) < 0.0, -1.0, 1.0)
            quat[at] = sign[:, None] * end + 0.0  # and −0.0 written as 0.0

    def study(self, ts) -> np.ndarray:
        """Unit Study parameters ``S + (N, 8)`` of the samples (``|p| = 1``, ``q = −½ t p``)."""
        quat, trans = self.quat_trans(ts)
        return study_from_quat_trans(quat, trans)

    def describe(self):
        """The canonical frame, the essential parameters and the choices made, as plain data.

        A dict for a single motion; nested lists of dicts, of shape ``S``, for a batch.
        """
        if self.shape:
            return _nested_map(self, self.shape)
        f = self.frame
        out = {
            "mode": self.mode,
            "phi": float(f.phi),
            "phi_degrees": float(np.degrees(f.phi)),
            "d": float(f.d),
            "axis_point": _vec(f.axis_point),
            "axis_direction": _vec(f.axis_direction),
        }
        out.update(self._describe())
        out["singular_t"] = [float(t) for t in self.singular_t()]
        out["choices"] = self.choices
        out["warnings"] = self.warnings
        return out

    # -- what the mode tells describe, plot and view (a2b.motions.REGISTRY) -------------------
    #: Whether building the motion with its default parameters reads the frame's axes
    #: (``axis_direction``, ``d``, ``t_disp``): :func:`a2b.motion` has
    #: :func:`a2b.frames.screw_frame` make them at once then, else when first asked for.
    frame_axes: bool = True
    #: One line for ``--help`` and the docs.
    description: str = ""
    #: The closed form of the transmission curve z(ω) (:meth:`transmission`), for legends:
    #: ``"sine"``, ``"tangent"``, ``"line"``; ``""`` when the mode has none.
    transmission_form: str = ""
    #: What :meth:`family` can vary, the default first; empty when the mode has no family.
    family_kinds: tuple = ()

    @classmethod
    def from_parameters(cls, start, end, frame: ScrewFrame, params: dict) -> Motion:
        """The motion of the mode from :func:`a2b.motion`'s checked parameters; a mode takes
        out of ``params`` what is no constructor keyword (so that :func:`a2b.motion` sees what
        was left)."""
        return cls(start, end, frame, **params)

    def transmission(self, omega: np.ndarray) -> np.ndarray | None:
        """The closed-form transmission curve ``z(ω)`` in canonical coordinates, or None when
        the mode has none (a Darboux, cubic and screw motion override it)."""
        return None

    def family(self, kind: str, side: int) -> tuple[str, list, float]:
        """The one-parameter family of motions through A and B that this motion belongs to:
        ``(name, [(value, parameters of a2b.motion), ...], chosen)``, ``2 side + 1`` members
        ordered by value, the middle one this motion. ``kind`` is one of :attr:`family_kinds`.

        Raises
        ------
        ParameterError
            When the mode has no family.
        """
        raise ParameterError(f"there is no family of transmission curves to draw for a {self.what}")

    def summary(self, angle_unit: str = "deg") -> str:
        """A one-line summary of the essential parameters, as in a figure's title."""
        return ""

    def pose_degree(self) -> int | str:
        """The degree in t of the pose entries, for ``a2b describe``."""
        return int(self.table.shape[-2] - 1)


def _nested_map(motion: Motion, shape: tuple) -> list:
    return [
        motion[i].describe() if len(shape) == 1 else _nested_map(motion[i], shape[1:])
        for i in range(shape[0])
    ]


def _vec(a) -> list:
    return [float(x) for x in np.asarray(a, dtype=float).ravel()]


def broadcast_parameter(values, shape: tuple, name: str, width: int | None = None) -> np.ndarray:
    """A float parameter broadcast to ``shape`` (``+ (width,)``), finite, or a clear error.

    Numbers only: a string, a boolean or an object that merely converts to a float is refused.
    """
    arr = as_numbers(values, name)
    trailing = () if width is None else (width,)
    if arr.shape[len(arr.shape) - len(trailing) :] != trailing or (width and arr.ndim < 1):
        raise ParameterError(f"{name} needs {width} numbers, got shape {arr.shape}")
    try:
        arr = np.broadcast_to(arr, shape + trailing)
    except ValueError:
        raise ParameterError(
            f"{name} of shape {np.shape(values)} does not broadcast against the poses' "
            f"shape {shape}"
        ) from None
    bad = ~np.isfinite(arr)
    if width:
        bad = bad.any(axis=-1)
    refuse(
        ParameterError,
        bad,
        lambda i: f"{name} must be finite, got {_show(arr.reshape((-1,) + trailing)[i])}",
        shape,
    )
    return arr


def boolean_parameter(values, shape: tuple, name: str) -> np.ndarray:
    """A boolean parameter (``True``, ``False`` or an array of them) broadcast to ``shape``."""
    arr = np.asarray(values)
    if arr.dtype.kind != "b":
        raise ParameterError(f"{name} must be True or False (or an array of them), got {values!r}")
    if arr.shape == shape:
        return arr.copy()
    try:
        return np.broadcast_to(arr, shape).copy()
    except ValueError:
        raise ParameterError(
            f"{name} of shape {arr.shape} does not broadcast against the poses' shape {shape}"
        ) from None


def _show(item) -> str:
    return str(float(item)) if np.ndim(item) == 0 else str(np.asarray(item).tolist())
