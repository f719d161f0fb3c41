"""The screw axis of a displacement and the canonical frame of two poses.

For poses ``A`` and ``B`` (robotics matrices) the displacement ``D = B A⁻¹`` (so ``B = D A``)
is a screw: a rotation by ``φ ∈ [0, π]`` about an axis with unit direction ``u`` through the
point ``c``, and a translation ``d`` along it. In **canonical coordinates** (``docs/math.md``) the
axis is the z-axis, ``A = I`` and ``B`` is the rotation by ``φ`` about z with the translation
``d`` along z. a2b never needs the change of frame ``F`` to sample a motion (the formulas in
:mod:`a2b.motions` are written in the given coordinates and stay well conditioned for tiny
``φ``), but :meth:`ScrewFrame.to_canonical` provides it for analysis and tests.

Every function takes pairs of any leading shape ``S``; one pair is the case ``S = ()``.
The choices a2b makes are recorded in :attr:`ScrewFrame.choices` (see :func:`screw_frame`).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from .elements import Notes, anywhere, everywhere, refuse, safe_norm
from .errors import ParameterError
from .poses import (
    canonical_sign,
    inverse_matrices,
    quat_trans_from_matrices,
    quaternions_from_rotations,
    rotations_from_quaternions,
    study_from_quat_trans,
)
from .study import (
    CROSS,
    MATRIX_VECTOR,
    ROTATION,
    TURN,
    bilinear,
    dots,
    quat_conj,
    quat_mul,
    vector_form,
)

#: ``|sin(φ/2)|`` at or below which the relative rotation of two poses is rounding noise.
ROTATION_NOISE = 4 * np.finfo(float).eps

_FLIP = "flipped the sign of B's quaternion so that pA·pB ≥ 0 (the short way round)"
_PURE_TRANSLATION = (
    "pure translation (φ = 0): the axis is the line through A's origin along the translation"
)
_SAME_POSE = "B = A: the axis is chosen parallel to z through A's origin"


@dataclass(frozen=True)
class ScrewFrame:
    """The screws ``D = B A⁻¹`` of pairs of poses, with consistent unit Study vectors.

    Every attribute has the leading shape ``S`` of the pairs (``()`` for one pair, where
    ``phi`` and ``d`` are floats).

    Attributes
    ----------
    phi : ndarray, shape S
        Rotation angle in ``[0, π]``.
    d : ndarray, shape S
        Translation along the axis (signed, in the poses' length unit).
    axis_direction : ndarray, shape S + (3,)
        Unit vector ``u``.
    axis_point : ndarray, shape S + (3,)
        The point of the axis closest to the origin of the fixed frame.
    r : ndarray, shape S + (4,)
        Unit quaternion ``pB p̄A = (cos φ/2, sin φ/2 u)`` of ``D``'s rotation.
    p_start, p_end : ndarray, shape S + (4,)
        Unit quaternions of A and B, with ``p_end p̄_start = r``.
    h_start, h_end : ndarray, shape S + (8,)
        Unit Study vectors of A and B with these primal parts.
    t_start, t_end : ndarray, shape S + (3,)
        Translations of A and B.
    t_disp : ndarray, shape S + (3,)
        Translation of ``D``; ``t_perp = t_disp − d u``.
    notes : Notes
        Every choice made for the user, in words (:attr:`choices`).
    """

    phi: np.ndarray
    r: np.ndarray
    p_start: np.ndarray
    p_end: np.ndarray
    t_start: np.ndarray
    t_end: np.ndarray
    notes: Notes

    @cached_property
    def shape(self) -> tuple:
        return np.shape(self.phi)

    @property
    def choices(self):
        """The choices made: a list of str for one pair, nested lists of shape ``S`` else."""
        return self.notes.tolist()

    def __getitem__(self, index) -> ScrewFrame:
        fields = {
            name: _scalar(np.asarray(getattr(self, name))[index])
            for name in self.__dataclass_fields__
            if name != "notes"
        }
        out = ScrewFrame(**fields, notes=self.notes[index])
        if "screws" in self.__dict__:  # made already (a rare case made them with the frame)
            out.__dict__["screws"] = tuple(_scalar(np.asarray(x)[index]) for x in self.screws)
        return out

    @cached_property
    def screws(self) -> tuple:
        """``(axis_direction, d, t_disp)``, made when first asked for (a Darboux motion is
        built without them), by :func:`_screws` from :attr:`r` and the translations, as
        :func:`screw_frame` makes them where a pair turns by π or not at all."""
        shape = self.shape
        r, t_a, t_b = (
            _by_component(x, k) for x, k in ((self.r, 4), (self.t_start, 3), (self.t_end, 3))
        )
        with np.errstate(over="ignore", invalid="ignore"):
            s = np.sqrt(dots(r[1:].T, r[1:].T))
            rotating = s > ROTATION_NOISE
            u, d, t_disp, _ = _screws(r, t_a, t_b, s, rotating, everywhere(rotating))
        return _leading(u.T, shape), _leading(d, shape), _leading(t_disp.T, shape)

    @property
    def axis_direction(self) -> np.ndarray:
        """Unit vector ``u`` of the axes, ``S + (3,)``."""
        return self.screws[0]

    @property
    def d(self) -> np.ndarray:
        """Translation along the axes, shape ``S`` (a float for one pair)."""
        return self.screws[1]

    @property
    def t_disp(self) -> np.ndarray:
        """Translation of ``D``, ``S + (3,)``."""
        return self.screws[2]

    @cached_property
    def axis_point(self) -> np.ndarray:
        """The point of the axis closest to the origin of the fixed frame, ``S + (3,)``: made
        when asked for (no motion needs it to be built). For a rotation it is
        ``½ (t⊥ + cot(φ/2) u × t⊥)``; without one, A's origin moved onto the axis along ``u``."""
        u, t_perp, r = self.axis_direction, self.t_perp, np.asarray(self.r)
        with np.errstate(over="ignore", invalid="ignore"):
            s = np.sqrt(dots(r[..., 1:], r[..., 1:]))  # sin(φ/2) and cos(φ/2), as _frames has
            c = np.abs(r[..., 0])
            rotating = s > ROTATION_NOISE
            turning = everywhere(rotating)
            safe_s = s if turning else np.where(rotating, s, 1.0)
            point = 0.5 * (t_perp + vector_form(CROSS, u, t_perp) * (c / safe_s)[..., None])
            if turning:
                return point
            t_a = self.t_start
            still = t_a - dots(u, t_a)[..., None] * u
            return np.where(rotating[..., None], point, still)

    @property
    def h_start(self) -> np.ndarray:
        """A's unit Study vector with primal part ``p_start``, ``S + (8,)`` (made when asked
        for: the screw motion and the cubic do not need it)."""
        return study_from_quat_trans(self.p_start, self.t_start)

    @property
    def h_end(self) -> np.ndarray:
        """B's unit Study vector with primal part ``p_end``, ``S + (8,)``."""
        return study_from_quat_trans(self.p_end, self.t_end)

    @property
    def t_perp(self) -> np.ndarray:
        """Component of the displacement's translation perpendicular to the axis, ``S + (3,)``."""
        return self.t_disp - np.asarray(self.d)[..., None] * self.axis_direction

    def canonical_transform(self) -> np.ndarray:
        """Rigid ``F`` (``S + (4, 4)``) taking the axis to the z-axis, the axis point to the
        origin."""
        u = np.asarray(self.axis_direction)
        ez = np.array([0.0, 0.0, 1.0])
        v = np.cross(u, ez)
        sin_a = np.linalg.norm(v, axis=-1)
        cos_a = u @ ez
        tiny = sin_a < 1e-15
        k = v / np.where(tiny, 1.0, sin_a)[..., None]
        kx = np.zeros(u.shape + (3,))
        kx[..., 0, 1], kx[..., 0, 2], kx[..., 1, 2] = -k[..., 2], k[..., 1], -k[..., 0]
        kx[..., 1, 0], kx[..., 2, 0], kx[..., 2, 1] = k[..., 2], -k[..., 1], k[..., 0]
        rot = np.eye(3) + sin_a[..., None, None] * kx + (1 - cos_a)[..., None, None] * (kx @ kx)
        flip = np.where((cos_a > 0)[..., None, None], np.eye(3), np.diag([1.0, -1.0, -1.0]))
        rot = np.where(tiny[..., None, None], flip, rot)
        out = np.zeros(u.shape[:-1] + (4, 4))
        out[..., :3, :3] = rot
        out[..., :3, 3] = -(rot @ self.axis_point[..., None])[..., 0]
        out[..., 3, 3] = 1.0
        return out

    def to_canonical(self, matrices: np.ndarray, start: np.ndarray) -> np.ndarray:
        """Poses in canonical coordinates: ``X ↦ F X A⁻¹ F⁻¹`` (``F``, ``A`` per pair)."""
        f = self.canonical_transform()
        return f @ np.asarray(matrices, dtype=float) @ inverse_matrices(start) @ inverse_matrices(f)

    def transmission(self, matrices: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Rotation angle ω and translation z of poses ``S + (N, 4, 4)`` relative to A.

        ``ω`` is measured about ``u`` (unwrapped along the samples, starting from the branch
        nearest 0) and ``z = u · t_D`` where ``D = X A⁻¹``. Meaningful for motions in this
        cylinder group.
        """
        quat, trans = quat_trans_from_matrices(matrices)
        u = np.asarray(self.axis_direction)[..., None, :]
        rel = quat_mul(quat, quat_conj(np.asarray(self.p_start)[..., None, :]))
        omega = 2.0 * np.arctan2(np.sum(rel[..., 1:] * u, axis=-1), rel[..., 0])
        omega = np.where(omega > np.pi, omega - 2 * np.pi, omega)
        omega = np.where(omega <= -np.pi, omega + 2 * np.pi, omega)
        omega = np.unwrap(omega, axis=-1)
        mats = np.asarray(matrices, dtype=float)
        # Rᵀ_A t_A: with X = D A, t_X = R_D t_A + t_D and R_D = R_X R_Aᵀ.
        rot_a = rotations_from_quaternions(self.p_start)
        local = np.sum(rot_a * np.asarray(self.t_start)[..., :, None], axis=-2)
        t_disp = trans - (mats[..., :3, :3] @ local[..., None, :, None])[..., 0]
        return omega, np.sum(t_disp * u, axis=-1)


def _by_component(values, k: int) -> np.ndarray:
    """Vectors ``S + (k,)`` as a component-major view ``(k, J)``."""
    return np.asarray(values).reshape(-1, k).T


def _leading(array: np.ndarray, shape: tuple) -> np.ndarray:
    """A field ``(J, ...)`` of ``J`` pairs in the shape ``S + (...)`` of the frame: element 0
    for one pair (a float for ``phi`` and ``d``)."""
    if not shape:
        return array[0]
    return array if len(shape) == 1 else array.reshape(shape + array.shape[1:])


def _scalar(value):
    """A 0-d array as a numpy float (which is a float); other arrays as they are."""
    return value[()] if isinstance(value, np.ndarray) and value.ndim == 0 else value


def screw_frame(
    start: np.ndarray, end: np.ndarray, quaternions=None, axes: bool = True
) -> ScrewFrame:
    """The screw axis of ``D = B A⁻¹`` for robotics matrices ``start = A`` and ``end = B``.

    Parameters
    ----------
    start, end : ndarray, shape S + (4, 4)
        Valid poses (see :func:`a2b.poses.check_matrices`), of one shape ``S``.
    quaternions : (ndarray, ndarray), shapes S + (4,), optional
        The quaternions of A and B as :func:`a2b.poses.quaternions_from_rotations` gives them,
        where the caller has them already (a trajectory's pose starts one segment and ends
        the one before).
    axes : bool
        Make the axis directions, ``d`` and ``t_disp`` now (default), or, where no pair
        calls for them (every pair rotates, none by π), when first asked for
        (:attr:`ScrewFrame.screws`): a Darboux motion is built without them.

    Returns
    -------
    ScrewFrame
        Of shape ``S``. The choices, for each pair:

        * the sign of B's quaternion, so that ``pA·pB ≥ 0`` (the short way round);
        * for ``φ = π`` (both signs are short), the axis orientation with ``d > 0`` or, for
          ``d = 0``, with the first non-zero component of ``u`` positive;
        * for a pure translation (``φ = 0``), the axis along the translation through A's
          origin; for ``B = A``, the axis parallel to z through A's origin.

    Raises
    ------
    ParameterError
        Where the displacement overflows float64.
    """
    start = np.asarray(start, dtype=float)
    end = np.asarray(end, dtype=float)
    shape = start.shape[:-2]
    if quaternions is not None:
        quaternions = [np.asarray(p, dtype=float).reshape(-1, 4) for p in quaternions]
    with np.errstate(over="ignore", invalid="ignore"):
        fields, screws, large, notes = _frames(
            start.reshape(-1, 4, 4), end.reshape(-1, 4, 4), quaternions, axes
        )
    if not shape:  # one pair: element 0 of each (a float for phi)
        fields = {name: array[0] for name, array in fields.items()}
    elif len(shape) > 1:
        fields = {name: _leading(array, shape) for name, array in fields.items()}
    frame = ScrewFrame(**fields, notes=Notes(shape, [(
        None if mask is None else mask.reshape(shape),
        text if isinstance(text, str) else text.reshape(shape),
    ) for mask, text in notes]))  # fmt: skip
    frame.__dict__["shape"] = shape  # the cached_property, known here
    if screws is not None:
        frame.__dict__["screws"] = tuple(_leading(x, shape) for x in screws)
    if not large:  # translations of at most LARGE: every displacement is finite
        return frame
    if everywhere(np.isfinite(frame.t_disp)) and everywhere(np.isfinite(frame.d)):
        return frame
    finite = np.isfinite(frame.d) & np.isfinite(frame.t_disp).all(axis=-1)
    refuse(
        ParameterError,
        ~finite,
        lambda i: (
            "the displacement from start to end overflows float64 "
            f"(d = {np.ravel(frame.d)[i]}); use a smaller length unit"
        ),
        shape,
    )
    return frame


#: Translations up to this size give finite displacements (``|t_B − R_D t_A| ≤ 4 · 10³⁰⁰``):
#: :func:`screw_frame` needs to check them only beyond.
LARGE = 1e300


def _frames(start: np.ndarray, end: np.ndarray, quaternions, axes: bool) -> tuple:
    """The fields of the screw frames of ``J`` pairs ``(J, 4, 4)``, their :func:`_screws`
    ``(u, d, t_disp)`` if ``axes``, or where a pair turns by π or not at all or a
    translation exceeds :data:`LARGE` (else ``None``: :attr:`ScrewFrame.screws` makes them
    when asked for), whether a translation does, and the choices made.

    The work arrays are component-major, ``(k, J)``: every bilinear form (``pB p̄A``, eq. 4's
    rotation, ``u × t``) is one :func:`a2b.study.bilinear` over all pairs, and the fields are
    returned as ``(J, k)`` views of them."""
    count = len(start)
    if quaternions is None:  # both poses in one call
        both = quaternions_from_rotations(np.concatenate([start[:, :3, :3], end[:, :3, :3]]))
        quaternions = both[:count], both[count:]
    p_a, p_b = quaternions
    translations = np.empty((2, 3, count))  # (3, J) each
    translations[0] = start[:, :3, 3].T
    translations[1] = end[:, :3, 3].T
    t_a, t_b = translations
    r = bilinear(TURN, p_b.T, p_a.T)
    if not everywhere(p_a[:, 0] != p_b[:, 0]):  # identical rotations: no residue from p p̄
        same = (p_a == p_b).all(axis=-1)
        r[:, same] = [[1.0], [0.0], [0.0], [0.0]]
    s = np.sqrt(dots(r[1:].T, r[1:].T))
    c = np.abs(r[0])  # |pA·pB|, which no change of sign below changes
    rotating = s > ROTATION_NOISE
    turning = everywhere(rotating)  # the rare cases below run only where they occur
    # A half-turn (pA·pB = 0 within rounding): u and −u are equally short; one is picked and
    # said, rather than let the sign of rounding noise decide.
    half_turn = rotating & (c <= ROTATION_NOISE)
    halves = anywhere(half_turn)
    flip = (r[0] < 0) & ~half_turn if halves else r[0] < 0
    flipped = anywhere(flip)
    if flipped:
        sign = np.where(flip, -1.0, 1.0)  # × −1 is negation, bit for bit
        p_b = p_b * sign[:, None]
        r *= sign
    phi = 2.0 * np.arctan2(s, c)
    notes = [(flip, _FLIP)] if flipped else []
    screws = None
    large = not float(np.maximum.reduce(np.abs(translations), axis=None)) <= LARGE  # or NaN
    if axes or not turning or halves or large:
        u, d, t_disp, moving = _screws(r, t_a, t_b, s, rotating, turning)
        if halves:  # the half-turn rule
            turn = half_turn & ((d < 0) | ((d == 0) & (canonical_sign(u.T)[:, 0] != u[0])))
            u = np.where(turn, -u, u)
            d = np.where(turn, -d, d)
            p_b = np.where(turn[:, None], -p_b, p_b)
            r = np.where(turn, -r, r)
        if not turning:
            phi = np.where(rotating, phi, 0.0)
        if not turning or halves:
            notes += _rare_notes(s, rotating, half_turn, moving, d, c)
        screws = (u.T, d, t_disp.T)
    fields = {
        "phi": phi,
        "r": r.T,
        "p_start": p_a,
        "p_end": p_b,
        "t_start": t_a.T,
        "t_end": t_b.T,
    }
    return fields, screws, large, notes


def _screws(r, t_a, t_b, s, rotating, turning: bool) -> tuple:
    """The axis direction ``u`` ``(3, J)``, the slide ``d`` ``(J,)`` along it and the
    translation ``t_disp`` ``(3, J)`` of the displacements ``D = B A⁻¹`` with rotations ``r``
    ``(4, J)`` (``s = |vec r|``), and which of those that do not rotate move (``(J,)``).

    ``t_disp = tB − R_D tA`` (eq. 4 of ``r``); ``u`` is the axis of ``r`` where it rotates,
    else along the translation, or z for ``B = A``; ``d = u · t_disp``."""
    numerators = bilinear(ROTATION, r, r)  # eq. 4 of r, and |r|²
    t_disp = t_b - bilinear(MATRIX_VECTOR, numerators[:9], t_a) / numerators[9]
    safe_s = s if turning else np.where(rotating, s, 1.0)
    u = r[1:] / safe_s
    d = dots(u.T, t_disp.T)
    moving = np.zeros(len(s), dtype=bool)
    if not turning:  # no rotation: the axis along the translation, or parallel to z for B = A
        norm_t = safe_norm(t_disp, axis=0)  # a translation of 1e200 has a length
        moving = norm_t > 0.0
        z = np.array([[0.0], [0.0], [1.0]])
        u_t = np.where(moving, t_disp / np.where(moving, norm_t, 1.0), z)
        u = np.where(rotating, u, u_t)
        d = np.where(rotating, d, np.where(moving, norm_t, 0.0))
    return u, d, t_disp, moving


def _rare_notes(s, rotating, half_turn, moving, d, c) -> list:
    """The choices :func:`_frames` made where a pair does not rotate or turns by π, after
    the flips: (mask, text) rules for :class:`Notes`, only those that hold somewhere, in this
    order."""
    notes: list = []
    still = ~rotating
    noise = (s > 0.0) & still if anywhere(still) else None
    if noise is not None and anywhere(noise):
        texts = np.full(len(s), None, dtype=object)
        for j in np.flatnonzero(noise).tolist():
            texts[j] = (
                f"the rotations of A and B differ by |sin(φ/2)| = {float(s[j]):.3g}, within "
                f"rounding ({ROTATION_NOISE:.3g}): treated as a pure translation"
            )
        notes.append((noise, texts))
    if anywhere(half_turn):
        texts = np.full(len(s), None, dtype=object)
        for j in np.flatnonzero(half_turn).tolist():
            side = "d > 0" if d[j] > 0 else "d = 0 and the first non-zero axis component positive"
            texts[j] = (
                f"φ = π (|pA·pB| = {float(c[j]):.3g} ≤ {ROTATION_NOISE:.3g}): both axis "
                f"orientations are short; chose the one with {side}"
            )
        notes.append((half_turn, texts))
    if noise is not None:  # somewhere no rotation
        for mask, text in ((still & moving, _PURE_TRANSLATION), (still & ~moving, _SAME_POSE)):
            if anywhere(mask):
                notes.append((mask, text))
    return notes
