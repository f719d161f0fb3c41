"""The interface every motion of a2b shares."""

from __future__ import annotations

import warnings

import numpy as np

from ..errors import A2bWarning, ParameterError
from ..frames import ScrewFrame
from ._rational import evaluate_table, evaluate_translations


def check_ts(ts) -> np.ndarray:
    """Validate sample parameters: a finite 1-D array (values outside [0, 1] extrapolate)."""
    arr = np.asarray(ts, dtype=float)
    if arr.ndim != 1:
        raise ParameterError(f"ts must be a 1-D array, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ParameterError("ts contains NaN or infinity")
    return arr


def _check_finite(ts: np.ndarray, values: np.ndarray) -> None:
    """Raise if extrapolating to far-away ``t`` overflowed (values ``(N, ...)`` per sample)."""
    bad = ~np.isfinite(values.reshape(len(ts), -1)).all(axis=1)
    if bad.any():
        raise ParameterError(
            f"the motion overflows float64 at t = {float(ts[bad][0]):.6g}: extrapolate less far"
        )


def check_table(table: np.ndarray) -> None:
    """Raise if a motion's coefficients overflowed (huge parameters or translations)."""
    if not np.all(np.isfinite(table)):
        raise ParameterError(
            "the motion's coefficients overflow float64 (a parameter or a translation is too large, "
            f"largest finite entry {float(np.max(np.abs(table[np.isfinite(table)]), initial=0.0)):.3g})"
        )


def linear_path(ts: np.ndarray, ends: np.ndarray) -> np.ndarray:
    """``(1−t) ends[0] + t ends[1]`` for every t, shape ``(len(ts), 4)``, without BLAS.

    (A ``(N, 2) @ (2, 4)`` product is slow under some OpenBLAS core types; this is not.)
    """
    out = np.multiply.outer(1.0 - ts, ends[0])
    out += np.multiply.outer(ts, ends[1])
    return out


def _vec(a) -> list:
    return [float(x) for x in np.asarray(a, dtype=float).ravel()]


class Motion:
    """A motion ``C(t)`` with ``C(0) = A`` and ``C(1) = B``, sampled from a coefficient table.

    Values of ``t`` outside ``[0, 1]`` extrapolate along the same rational (or, for the screw,
    helical) motion; a2b checks the extended range for singularities too.

    Subclasses set ``mode``, ``table`` (``(k, 14)``), ``frame`` and implement ``_basis``,
    ``_quats``, ``_check_interval`` and ``_describe``.
    """

    mode: str = ""
    table: np.ndarray
    frame: ScrewFrame

    def __init__(self, start: np.ndarray, end: np.ndarray, frame: ScrewFrame):
        self.start = start
        self.end = end
        self.frame = frame
        self.choices: list[str] = list(frame.choices)
        self.warnings: list[str] = []

    def _warn(self, message: str) -> None:
        """Record a sensitivity warning for ``describe`` and issue it as an ``A2bWarning``."""
        if message not in self.warnings:
            self.warnings.append(message)
            warnings.warn(A2bWarning(message), stacklevel=3)

    # -- to implement ------------------------------------------------------------------------
    def _basis(self, ts: np.ndarray) -> np.ndarray:  # pragma: no cover - abstract
        raise NotImplementedError

    def _quats(self, ts: np.ndarray) -> np.ndarray:  # pragma: no cover - abstract
        raise NotImplementedError

    def _check_interval(self, lo: float, hi: float) -> None:
        """Raise :class:`SingularMotionError` if the motion is singular on ``[lo, hi]``."""

    def singular_t(self) -> list[float]:
        """Real ``t`` (any value) where the motion is undefined, for ``describe``."""
        return []

    def _describe(self) -> dict:  # pragma: no cover - abstract
        raise NotImplementedError

    # -- shared ------------------------------------------------------------------------------
    def _prepare(self, ts) -> np.ndarray:
        arr = check_ts(ts)
        if arr.size and (arr.min() < 0.0 or arr.max() > 1.0):
            self._check_interval(min(0.0, float(arr.min())), max(1.0, float(arr.max())))
        return arr

    def _rotation_is_fragile(self, lo: float, hi: float) -> bool:
        """True where the table's rotation would lose rigidity (``p(t)`` close to 0 on [lo, hi])."""
        return False

    def matrices(self, ts) -> np.ndarray:
        """Sample the motion: robotics matrices ``(len(ts), 4, 4)`` for a 1-D ``ts``.

        Where ``p(t)`` comes close to 0 (``|p|²/max|p|² < 1e-2``), the rotation block is taken
        from the normalised ``p(t)`` instead of the coefficient table, so that every sample stays
        rigid to rounding.
        """
        arr = self._prepare(ts)
        with np.errstate(over="ignore", invalid="ignore"):  # far extrapolation: checked below
            out = evaluate_table(self._basis(arr), self.table)
        if arr.size and self._rotation_is_fragile(
            min(0.0, float(arr.min())), max(1.0, float(arr.max()))
        ):
            from ..poses import rotations_from_quaternions

            out[:, :3, :3] = rotations_from_quaternions(self._quats(arr))
        if arr.size and (arr.min() < 0.0 or arr.max() > 1.0):
            _check_finite(arr, out[:, :3, :])
        return out

    def quat_trans(self, ts) -> tuple[np.ndarray, np.ndarray]:
        """Unit quaternions ``(N, 4)`` (w, x, y, z) and translations ``(N, 3)``.

        The quaternions come from the motion's own ``p(t)`` and are therefore continuous in
        ``t`` (no sign jumps), starting at the sign of A's quaternion with ``w ≥ 0``.
        """
        arr = self._prepare(ts)
        quat = self._quats(arr)
        quat /= np.sqrt(np.einsum("ij,ij->i", quat, quat))[:, None]
        with np.errstate(over="ignore", invalid="ignore"):  # far extrapolation: checked below
            trans = evaluate_translations(self._basis(arr), self.table)
        if arr.size and (arr.min() < 0.0 or arr.max() > 1.0):
            _check_finite(arr, trans)
        return quat, trans

    def study(self, ts) -> np.ndarray:
        """Unit Study parameters ``(N, 8)`` of the samples (``|p| = 1``, ``q = −½ t p``)."""
        from ..poses import study_from_quat_trans

        quat, trans = self.quat_trans(ts)
        return study_from_quat_trans(quat, trans)

    def describe(self) -> dict:
        """The canonical frame, the essential parameters and the choices made, as plain data."""
        f = self.frame
        out = {
            "mode": self.mode,
            "phi": f.phi,
            "phi_degrees": float(np.degrees(f.phi)),
            "d": f.d,
            "axis_point": _vec(f.axis_point),
            "axis_direction": _vec(f.axis_direction),
        }
        out.update(self._describe())
        out["singular_t"] = [float(t) for t in self.singular_t()]
        out["choices"] = list(self.choices)
        out["warnings"] = list(self.warnings)
        return out
