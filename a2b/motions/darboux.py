"""Vertical Darboux motions: straight lines in the extended dual-quaternion model (section 3).

Take the unit Study vectors ``hA``, ``hB`` (with ``pA·pB ≥ 0``; the long way flips ``hB``),
the fiber points ``hA + sA ε pA`` and ``hB + sB ε pB`` and the line
``h(t) = (1−t)(hA + sA ε pA) + t(hB + sB ε pB)``. The pose at ``t`` is ``κ(h(t))``, with no
normalisation or projection onto the Study quadric. The motion depends on ``δ = sB − sA``
only; a2b uses ``sA = −δ/2``, ``sB = δ/2``.

In canonical coordinates (``docs/math.md``, Theorem 1) the transmission curve is
``z = z0 + λ sin(ω + κ)`` with ``z0 = d/2 + δ cot(φ/2)``, ``λ = √(d²/4 + δ²) / |sin(φ/2)|``,
and the pitch ``dz/dω`` is ``(d/2) cot(φ/2) ∓ δ`` at the start and the end. For the long way
round the same formulas hold with ``φ`` replaced by ``φ − 2π``.
"""

from __future__ import annotations

import math

import numpy as np

from ..elements import anywhere, refuse, value
from ..errors import ParameterError
from ..frames import ScrewFrame
from ..parameters import SOLVERS
from ..poses import check_matrices, quat_trans_from_matrices, rotations_from_quaternions
from ..study import (
    NARROW_FROM,
    bilinear,
    quat_conj,
    quat_mul,
    rotation_rows,
    structure_matrix,
    study_from_quat_trans,
    translation_numerators,
)
from ._rational import (
    CHUNK,
    ROT_COLS,
    TRANS_COLS,
    bernstein_basis,
    bernstein_derivatives,
)
from .base import Motion, boolean_parameter, broadcast_parameter
from .text import angle_text, number_text

#: Relative tolerance for a third pose to count as a member of the cylinder group of A and B.
CYLINDER_TOL = 1e-9


def _wrap(angle):
    """Wrap angles to ``(−π, π]``."""
    angle = np.asarray(angle, dtype=float)
    wrapped = angle - 2 * math.pi * np.round(angle / (2 * math.pi))
    return np.where(wrapped <= -math.pi, math.pi, wrapped)


def _require_rotation(phi, what: str, shape: tuple) -> None:
    refuse(
        ParameterError,
        np.asarray(phi) == 0.0,
        lambda i: (
            f"{what} is undefined for a pure translation (φ = 0): every Darboux interpolant is "
            "the straight translation"
        ),
        shape,
    )


def delta_from_kappa(kappa, phi, d, shape: tuple = ()) -> np.ndarray:
    """δ for a prescribed phase κ of ``z = z0 + λ sin(ω + κ)`` (``docs/math.md``)."""
    _require_rotation(phi, "the phase κ", shape)
    half = np.sin(phi / 2)
    theta = kappa + phi / 2 - np.where(half < 0, math.pi, 0.0)
    refuse(
        ParameterError,
        d == 0.0,
        lambda i: (
            "the phase κ does not determine δ when d = 0 (the transmission curve is "
            "z0 + λ sin(ω + κ) with κ = −φ/2 ± π/2 for every δ); give delta or lam instead"
        ),
        shape,
    )
    cos_t = np.cos(theta)
    refuse(
        ParameterError,
        np.abs(cos_t) < 1e-12,
        lambda i: (
            f"κ = {value(kappa, i):.6g} rad ≡ −φ/2 ± π/2 requires d = 0 (here d = "
            f"{value(d, i):.6g}); no Darboux interpolant has it"
        ),
        shape,
    )
    refuse(
        ParameterError,
        cos_t * d < 0,
        lambda i: (
            f"no Darboux interpolant of these poses has phase κ = {value(kappa, i):.6g} rad "
            f"with λ ≥ 0; κ + π = {float(_wrap(value(kappa, i) + math.pi)):.6g} rad describes "
            "the mirrored sine and is reachable (κ is in radians; write 45deg for degrees)"
        ),
        shape,
    )
    return -(d / 2) * np.tan(theta)


def delta_from_lam(lam, phi, d, branch=1, shape: tuple = ()) -> np.ndarray:
    """δ for a prescribed amplitude λ: ``|δ| = √(λ² sin²(φ/2) − d²/4)``, sign from ``branch``."""
    _require_rotation(phi, "the amplitude λ", shape)
    half = np.abs(np.sin(phi / 2))
    with np.errstate(divide="ignore"):
        minimum = np.abs(d) / (2 * half)
    refuse(
        ParameterError,
        ~(lam >= minimum * (1 - 1e-12)),
        lambda i: (
            f"amplitude λ = {value(lam, i):.6g} is below the minimum |d| / (2 sin(φ/2)) = "
            f"{value(minimum, i):.6g} of the Darboux interpolants of these poses"
        ),
        shape,
    )
    return branch * np.sqrt(np.maximum(lam * lam * half * half - d * d / 4, 0.0))


def delta_from_pitch(pitch, phi, d, at: str, shape: tuple = ()) -> np.ndarray:
    """δ for a prescribed pitch ``dz/dω`` (translation per radian) at the start or the end."""
    _require_rotation(phi, f"the pitch at the {at}", shape)
    with np.errstate(divide="ignore", invalid="ignore"):
        base = (d / 2) * (np.cos(phi / 2) / np.sin(phi / 2))
    return base - pitch if at == "start" else pitch - base


def delta_from_third_pose(omega_c, z_c, phi, d, shape: tuple = ()) -> np.ndarray:
    """δ of the one Darboux interpolant through the cylinder-group pose ``(ωC, zC)``."""
    _require_rotation(phi, "a third pose", shape)
    denom = np.cos(omega_c - phi / 2) - np.cos(phi / 2)
    refuse(
        ParameterError,
        np.abs(denom) < 1e-12,
        lambda i: (
            f"the third pose has the rotation angle of A or B (ωC = {value(omega_c, i):.6g}); "
            "no Darboux interpolant is singled out by it"
        ),
        shape,
    )
    return ((d / 2) * np.sin(omega_c - phi / 2) - (z_c - d / 2) * np.sin(phi / 2)) / denom


def third_pose_coordinates(frame: ScrewFrame, pose: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(ωC, zC)`` of poses ``S + (4, 4)`` in the cylinder groups of A and B, or a clear error."""
    p_c, t_c = quat_trans_from_matrices(pose)
    rel = quat_mul(p_c, quat_conj(frame.p_start))
    u = frame.axis_direction
    along = np.sum(rel[..., 1:] * u, axis=-1)
    off_axis = rel[..., 1:] - along[..., None] * u
    rot_residual = np.linalg.norm(off_axis, axis=-1)
    rot_e = rotations_from_quaternions(rel)
    t_e = t_c - (rot_e @ np.asarray(frame.t_start)[..., None])[..., 0]
    c = frame.axis_point
    t_along = np.sum(u * t_e, axis=-1)
    expected = c - (rot_e @ np.asarray(c)[..., None])[..., 0] + t_along[..., None] * u
    scale = np.maximum.reduce(
        [
            np.ones(np.shape(frame.d)),
            np.linalg.norm(t_e, axis=-1),
            np.linalg.norm(c, axis=-1),
            np.abs(frame.d),
        ]
    )
    trans_residual = np.linalg.norm(t_e - expected, axis=-1) / scale
    refuse(
        ParameterError,
        (rot_residual > CYLINDER_TOL) | (trans_residual > CYLINDER_TOL),
        lambda i: (
            "the third pose is not in the cylinder group of A and B (a rotation about and a "
            f"translation along their screw axis): rotation residual {value(rot_residual, i):.3g}, "
            f"relative translation residual {value(trans_residual, i):.3g}, tolerance "
            f"{CYLINDER_TOL:g}"
        ),
        frame.shape,
    )
    return 2.0 * np.arctan2(along, rel[..., 0]), t_along


#: The structure matrices (:func:`a2b.study.structure_matrix`) of the bilinear forms of the
#: build, from a2b's own formulas: ``q = −½ t p``, and eq. 4 (with the denominator) and eq. 5
#: as one form ``(p, (r, q)) ↦ (B(p, r), T(p, q))`` with 13 rows.
_DUAL = structure_matrix(lambda t, p: study_from_quat_trans(p, t)[..., 4:], 3, 4)
_ENTRIES = structure_matrix(
    lambda p, x: np.concatenate(
        [rotation_rows(p, x[..., :4]), translation_numerators(p, x[..., 4:])], axis=-1
    ),
    4,
    8,
)
#: The pairs of ends that :data:`_ENTRIES` takes, ``(A, A), (A, B), (B, A), (B, B)``.
_FIRST, _SECOND = np.array([0, 0, 1, 1]), np.array([0, 1, 0, 1])
#: The table's 14 columns of the three Bernstein rows from the flattened ``(13 · 4, J)``
#: values of :data:`_ENTRIES` on those pairs: the rotation numerators (rows 0–8) at
#: ROT_COLS, the translations (10–12) at TRANS_COLS, the denominator (9) twice, each of the
#: pairs ``(A, A), (A, B), (B, B)`` (the translation's middle one is ``½(T(pA, qB) + T(pB,
#: qA))``, put in the place of ``(A, B)``).
_COLUMNS = np.empty(14, dtype=np.intp)
_COLUMNS[list(ROT_COLS)] = range(9)
_COLUMNS[list(TRANS_COLS)] = range(10, 13)
_COLUMNS[12:] = 9
_TABLE_ROWS = (4 * _COLUMNS[:, None] + np.array([0, 1, 3])).ravel()  # (14 · 3,)


def darboux_tables(frame: ScrewFrame, long_way, offsets) -> tuple[np.ndarray, np.ndarray]:
    """``p(t)``'s ends ``S + (2, 4)`` and the Bernstein tables ``S + (3, 14)`` of the lines
    ``h(t) = (1−t)(hA + sA ε pA) + t(±hB + sB ε (±pB))`` (``offsets`` ``S + (2,)`` are
    ``sA, sB``; ``long_way`` flips hB).

    Component-major work arrays hold both poses of every pair, ``(4, 2, J)``; each bilinear
    form is one :func:`a2b.study.bilinear` over them: ``q``, then, in one, the rotation
    numerators and denominators ``B(pA, pA), B(pA, pB), B(pB, pB)`` of eq. 4 and the
    translation numerators ``T(pA, qA), ½(T(pA, qB) + T(pB, qA)), T(pB, qB)`` of eq. 5.
    Large batches go in chunks of :data:`CHUNK` pairs.
    """
    shape = frame.shape
    count = math.prod(shape)
    p_all = np.empty((4, 2, count))  # component-major: both ends of every pair
    p_all[:, 0] = frame.p_start.reshape((count, 4)).T
    p_all[:, 1] = frame.p_end.reshape((count, 4)).T
    if anywhere(long_way):
        p_all[:, 1] *= np.where(long_way.reshape(-1), -1.0, 1.0)
    t_all = np.empty((3, 2, count))
    t_all[:, 0] = frame.t_start.reshape((count, 3)).T
    t_all[:, 1] = frame.t_end.reshape((count, 3)).T
    s_all = offsets.reshape(count, 2).T
    offset = anywhere(s_all)  # δ ≠ 0 somewhere
    table = np.empty((count, 3, 14))
    for lo in range(0, count, CHUNK):
        hi = min(lo + CHUNK, count)
        p = p_all[..., lo:hi]
        pq = np.empty((8, 2, hi - lo))  # p and q of both ends
        pq[:4] = p
        pq[4:] = bilinear(_DUAL, t_all[..., lo:hi], p)
        if offset:
            pq[4:] += s_all[:, lo:hi] * p
        entries = bilinear(_ENTRIES, p.take(_FIRST, axis=1), pq.take(_SECOND, axis=1))
        middle = entries[10:, 1]  # (3, J): T(pA, qB), then ½(T(pA, qB) + T(pB, qA))
        middle += entries[10:, 2]
        middle *= 0.5
        ordered = entries.reshape(52, -1).take(_TABLE_ROWS, axis=0).reshape(14, 3, -1)
        if hi - lo <= NARROW_FROM:  # a few pairs: one copy, the fewest calls
            table[lo:hi] = ordered.T
            continue
        for row in range(3):  # three 2-d transposing copies: twice as fast as one 3-d
            table[lo:hi, row] = ordered[:, row].T
    quat_ends = p_all.transpose(2, 1, 0).reshape(shape + (2, 4))
    return quat_ends, table.reshape(shape + (3, 14))


class DarbouxMotion(Motion):
    """Vertical Darboux motions between pairs of poses (Theorem 1).

    Parameters
    ----------
    start, end : ndarray, shape S + (4, 4)
        Robotics matrices A and B.
    frame : ScrewFrame
        ``a2b.frames.screw_frame(start, end)``.
    delta, kappa, lam, pitch_start, pitch_end, through :
        At most one of them fixes the essential parameter δ (default ``delta = 0``), each a
        number or an array that broadcasts against ``S`` (``through``: poses ``(..., 4, 4)``).
        ``kappa`` is the phase in radians, ``lam`` the amplitude (with ``branch`` ±1 choosing
        the sign of δ), the pitches are translations per radian, ``through`` a pose in the
        cylinder group of A and B.
    long_way : bool or array of bool
        Rotate by ``2π − φ`` instead of ``φ`` (flip the sign of ``hB``).
    """

    mode = "darboux"
    what = "Darboux motion"

    def __init__(
        self,
        start,
        end,
        frame: ScrewFrame,
        *,
        delta=None,
        kappa=None,
        lam=None,
        branch=None,
        pitch_start=None,
        pitch_end=None,
        through=None,
        long_way=False,
    ):
        super().__init__(start, end, frame)
        shape = self.shape
        given = {
            "delta": delta,
            "kappa": kappa,
            "lam": lam,
            "pitch_start": pitch_start,
            "pitch_end": pitch_end,
            "through": through,
        }
        given = {name: item for name, item in given.items() if item is not None}
        if len(given) > 1:
            raise ParameterError(
                "darboux has one essential parameter; give at most one of "
                f"{', '.join(SOLVERS)} (got {', '.join(given)})"
            )
        if branch is not None and lam is None:
            raise ParameterError("branch chooses between the two solutions for lam; give lam too")
        self.long_way = boolean_parameter(long_way, shape, "long_way")
        phi = np.asarray(frame.phi)
        turning = phi > 0
        if anywhere(self.long_way):
            self.phi_eff = np.where(
                self.long_way, np.where(turning, phi - 2 * math.pi, -2 * math.pi), phi
            )
        else:
            self.phi_eff = phi.copy()
        phi_e = np.where(turning, self.phi_eff, 0.0) if given else None  # for solving only
        solved_from = next(iter(given), "delta")
        delta_v = self._solve(solved_from, given, branch, phi_e)
        delta_v = np.asarray(delta_v, dtype=float)
        if delta_v.shape != shape:
            delta_v = np.broadcast_to(delta_v, shape)
        self.delta = delta_v + 0.0
        self.solved_from = solved_from
        if given:  # δ = 0 else
            translating = (phi == 0.0) & (self.delta != 0.0)
            self.notes.add("δ has no effect on a pure translation", translating)
        self.notes.add("long way round: flipped the sign of hB", self.long_way)

        self.fiber_offsets = np.empty(shape + (2,))
        np.multiply(self.delta, 0.5, out=self.fiber_offsets[..., 1])
        np.subtract(0.0, self.fiber_offsets[..., 1], out=self.fiber_offsets[..., 0])
        self.quat_ends, self.table = darboux_tables(frame, self.long_way, self.fiber_offsets)
        self._check_interval(0.0, 1.0)
        if not shape:
            self.delta = self.delta[()]
            self.phi_eff = self.phi_eff[()]
            self.long_way = bool(self.long_way)

    def _solve(self, solved_from: str, given: dict, branch, phi_e) -> np.ndarray:
        """δ from the one essential parameter given (``docs/math.md``), or 0."""
        shape, frame = self.shape, self.frame
        if not given:
            return np.zeros(shape)
        d = np.asarray(frame.d)
        if solved_from == "through":
            _require_rotation(phi_e, "a third pose", shape)
            poses = check_matrices(given["through"])
            omega_c, z_c = third_pose_coordinates(frame, np.broadcast_to(poses, shape + (4, 4)))
            delta_v = delta_from_third_pose(omega_c, z_c, phi_e, d, shape)
        else:
            item = broadcast_parameter(given[solved_from], shape, solved_from)
            if solved_from == "kappa":
                delta_v = delta_from_kappa(item, phi_e, d, shape)
            elif solved_from == "lam":
                sign = 1 if branch is None else broadcast_parameter(branch, shape, "branch")
                refuse(
                    ParameterError,
                    (sign != 1) & (sign != -1),
                    lambda i: f"branch must be +1 or -1, got {value(sign, i):g}",
                    shape,
                )
                delta_v = delta_from_lam(item, phi_e, d, sign, shape)
                self.notes.add(
                    f"lam has two mirror solutions ±|δ|; used branch {int(sign):+d}"
                    if np.ndim(sign) == 0
                    else np.vectorize(
                        lambda b: f"lam has two mirror solutions ±|δ|; used branch {int(b):+d}",
                        otypes=[object],
                    )(sign)
                )
            elif solved_from == "pitch_start":
                delta_v = delta_from_pitch(item, phi_e, d, "start", shape)
            elif solved_from == "pitch_end":
                delta_v = delta_from_pitch(item, phi_e, d, "end", shape)
            else:
                delta_v = item
        return delta_v

    def _short_way_on(self, lo: float, hi: float) -> bool:
        """Whether ``[lo, hi]`` is ``[0, 1]`` and every motion goes the short way round: there
        ``p(t) = (1−t) pA + t pB`` with unit ``pA``, ``pB`` and ``c = pA·pB ≥ 0`` has
        ``|p(t)|² = 1 − 2t(1−t)(1 − c) ≥ ½`` (``docs/math.md``), far from every tolerance of
        the singularity checks, which then have nothing to find."""
        return lo == 0.0 and hi == 1.0 and not anywhere(self.long_way)

    def _check_interval(self, lo, hi):
        if not self._short_way_on(lo, hi):
            super()._check_interval(lo, hi)

    def _rotation_is_fragile(self, lo, hi):
        if self._short_way_on(lo, hi):
            return np.zeros(self.shape, dtype=bool)
        return super()._rotation_is_fragile(lo, hi)

    def _basis(self, ts):
        return bernstein_basis(ts, 2)

    def _basis_derivatives(self, ts, order):
        return bernstein_derivatives(ts, 2, order)

    def singular_t(self):
        p_a, p_b = self.quat_ends[..., 0, :], self.quat_ends[..., 1, :]
        return [0.5] if np.allclose(p_a, -p_b, rtol=0, atol=1e-12) else []

    def closed_form(self) -> dict:
        """The transmission curve's parameters in canonical coordinates (``docs/math.md``).

        Arrays of shape ``S`` (floats for one motion); NaN (``None`` for one motion) for a
        pure translation, where they are undefined.
        """
        phi, d, delta = np.asarray(self.phi_eff), np.asarray(self.frame.d), np.asarray(self.delta)
        turning = phi != 0.0
        phi_safe = np.where(turning, phi, math.pi)
        half_sin = np.sin(phi_safe / 2)
        cot = np.cos(phi_safe / 2) / half_sin
        amplitude = np.hypot(d / 2, delta)
        theta = np.arctan2(-delta, d / 2)
        kappa = -phi_safe / 2 + theta + np.where(half_sin < 0, math.pi, 0.0)
        out = {
            "z0": d / 2 + delta * cot,
            "lam": amplitude / np.abs(half_sin),
            "kappa": np.where(amplitude > 0, _wrap(kappa), np.nan),
            "pitch_start": (d / 2) * cot - delta,
            "pitch_end": (d / 2) * cot + delta,
        }
        out = {key: np.where(turning, item, np.nan) for key, item in out.items()}
        if self.shape:
            return out
        return {key: None if np.isnan(item) else float(item) for key, item in out.items()}

    def transmission(self, omega: np.ndarray) -> np.ndarray:
        """The closed-form ``z(ω)`` in canonical coordinates (``docs/math.md``).

        Raises
        ------
        ParameterError
            For a pure translation (φ = 0), where z is no function of ω.
        """
        phi, d, delta = np.asarray(self.phi_eff), np.asarray(self.frame.d), np.asarray(self.delta)
        _require_rotation(
            np.where(np.asarray(self.frame.phi) > 0, phi, 0.0),
            "the transmission curve z(ω)",
            self.shape,
        )
        if self.shape:
            phi, d, delta = phi[..., None], d[..., None], delta[..., None]
        half = np.sin(phi / 2)
        z = (d / 2) * np.sin(omega - phi / 2) - delta * (np.cos(omega - phi / 2) - np.cos(phi / 2))
        return d / 2 + z / half

    def omega_of_t(self, ts: np.ndarray) -> np.ndarray:
        """The closed-form ``ω(t)``: ``tan(ω/2) = t sin(φ/2) / (1 − t + t cos(φ/2))``."""
        phi = np.asarray(self.phi_eff)
        phi = phi[..., None] if self.shape else phi
        t = np.asarray(ts, dtype=float)
        return 2.0 * np.arctan2(t * np.sin(phi / 2), 1 - t + t * np.cos(phi / 2))

    def _describe(self):
        out = {
            "delta": float(self.delta),
            "solved_from": self.solved_from,
            "long_way": bool(self.long_way),
        }
        out["rotation_angle"] = float(self.phi_eff)
        out.update(self.closed_form())
        out["fiber_offsets"] = [float(x) for x in self.fiber_offsets]
        out["transmission_curve"] = "z = z0 + lam * sin(omega + kappa)"
        return out

    frame_axes = False  # the table needs the quaternions and translations only
    description = "the vertical Darboux motion (a line in the extended dual-quaternion model)"
    transmission_form = "sine"
    family_kinds = ("delta",)

    def family(self, kind: str, side: int) -> tuple[str, list, float]:
        """δ varies: the curves' midpoints step by a quarter of the length scale (|d|, else the
        size of the displacement, else 1)."""
        frame = self.frame
        scale = abs(frame.d) or float(np.linalg.norm(frame.t_disp)) or 1.0
        step = 0.25 * scale / abs(math.tan(self.phi_eff / 4))
        chosen = self.delta
        values = [chosen + k * step for k in range(-side, side + 1)]
        return "δ", [(v, {"delta": v, "long_way": self.long_way}) for v in values], chosen

    def summary(self, angle_unit: str = "deg") -> str:
        info = self.describe()
        if self.frame.phi == 0.0:
            text = "pure translation, δ has no effect"
        else:
            text = f"δ = {number_text(info['delta'])}"
            if info.get("kappa") is not None:
                text += (
                    f", z0 = {number_text(info['z0'])}, λ = {number_text(info['lam'])}, "
                    f"κ = {angle_text(info['kappa'], angle_unit)}"
                )
        return text + (", long way round" if info["long_way"] else "")
