"""A trajectory read from a file: times and poses, and the checks every format's poses pass.

Each reader of a trajectory format (:mod:`a2b.io.tum`, :mod:`a2b.io.kitti`,
:mod:`a2b.io.euroc`, :mod:`a2b.io.csvtable`, MCAP) makes its poses into a :class:`Trajectory`
with :func:`from_quaternions` or :func:`from_matrices`, which check them, and checks that its
times increase with :func:`check_times`. A problem is one :class:`InputFileError` that names
the line (or the message) where it is.
"""

from __future__ import annotations

from dataclasses import dataclass
from decimal import Decimal, InvalidOperation

import numpy as np

from ..errors import InputFileError

__all__ = ["BLOCK", "Trajectory", "check_times", "from_matrices", "from_quaternions", "joined"]

#: Poses converted at a time: the temporaries of a block stay small for any file.
BLOCK = 65536


@dataclass
class Trajectory:
    """Poses in time: ``times (N,)`` increasing seconds (for KITTI without a rate, the indices)
    and the numbers as the file holds them: ``quat_wxyz (N, 4)`` and ``trans (N, 3)`` for
    quaternion formats, ``study (N, 8)`` for study. :attr:`matrices` are the robotics
    matrices ``(N, 4, 4)``, built from the normalised quaternions when first asked for."""

    times: np.ndarray
    quat_wxyz: np.ndarray | None = None
    trans: np.ndarray | None = None
    study: np.ndarray | None = None
    name: str = "<trajectory>"
    fmt: str = ""
    #: With ``orthonormalize``: the largest ``max |R Rᵀ − I|`` repaired.
    repaired: float | None = None
    #: What the reader chose, for ``-v`` (the TF chain it composed).
    notes: tuple = ()
    _matrices: np.ndarray | None = None

    @property
    def matrices(self) -> np.ndarray:
        if self._matrices is None:
            from ..poses import matrices_from_quat_trans

            out = np.empty((len(self.times), 4, 4))
            for lo in range(0, len(out), BLOCK):  # small temporaries for any length
                part = slice(lo, lo + BLOCK)
                out[part] = matrices_from_quat_trans(self.quat_wxyz[part], self.trans[part])
            self._matrices = out
        return self._matrices

    @property
    def translations(self) -> np.ndarray:
        return self.trans if self.trans is not None else self.matrices[:, :3, 3]

    def __len__(self) -> int:
        return len(self.times)


def joined(pieces: list, name: str, fmt: str) -> Trajectory:
    """One trajectory of consecutive pieces."""
    if len(pieces) == 1:
        return pieces[0]
    if not pieces:
        return Trajectory(np.empty(0), name=name, fmt=fmt, _matrices=np.empty((0, 4, 4)))

    def joined(field):
        parts = [getattr(p, field) for p in pieces]
        return None if parts[0] is None else np.concatenate(parts)

    repaired = [p.repaired for p in pieces if p.repaired is not None]
    return Trajectory(
        joined("times"),
        quat_wxyz=joined("quat_wxyz"),
        trans=joined("trans"),
        study=joined("study"),
        name=name,
        fmt=fmt,
        repaired=max(repaired) if repaired else None,
        notes=sum((p.notes for p in pieces), ()),
        _matrices=joined("_matrices"),
    )


def _where(name: str, lines, i: int) -> str:
    """``FILE:LINE:1`` of row ``i`` (``lines``: the line of each row), else its message."""
    return f"{name}:{lines[i]}:1" if lines is not None else f"{name}: message {i + 1}"


def from_quaternions(times, quat, trans, name, fmt, lines) -> Trajectory:
    """A trajectory of quaternions ``(N, 4)`` w, x, y, z and translations ``(N, 3)``; a zero
    quaternion is an error at its line (``lines[i]``; ``None``: the i-th message)."""
    quat, trans = np.ascontiguousarray(quat), np.ascontiguousarray(trans)
    bad = ~(np.einsum("ij,ij->i", quat, quat) > 0.0)
    if bad.any():
        where = _where(name, lines, int(np.argmax(bad)))
        raise InputFileError(f"{where}: the quaternion is zero; a rotation needs a non-zero one")
    return Trajectory(times, quat_wxyz=quat, trans=trans, name=name, fmt=fmt)


def from_matrices(times, rows, lines, name, fmt, orthonormalize) -> Trajectory:
    """A trajectory of the rows ``(N, 12)`` of ``[R | t]``, each rotation block checked (or,
    with ``orthonormalize``, repaired up to :data:`a2b.poses.REPAIR_TOL`)."""
    from ..poses import ORTHO_TOL, REPAIR_TOL, determinants, orthogonality_residuals
    from ..poses import orthonormalize as project

    matrices = np.zeros((len(rows), 4, 4))
    matrices[:, :3, :] = rows.reshape(-1, 3, 4)
    matrices[:, 3, 3] = 1.0
    rotations = matrices[:, :3, :3]
    residual = orthogonality_residuals(rotations)
    tol = REPAIR_TOL if orthonormalize else ORTHO_TOL
    bad = ~(residual <= tol) | (determinants(rotations) < 0)
    if bad.any():
        i = int(np.argmax(bad))
        if determinants(rotations[i]) < 0:
            message = "the rotation block is a reflection (det R < 0), not a rotation"
        else:
            message = (
                f"the rotation block is not orthogonal: max |R Rᵀ − I| = {residual[i]:.3g} "
                f"exceeds tolerance {tol:g}"
            )
            if not orthonormalize and residual[i] <= REPAIR_TOL:
                message += (
                    "; if the file rounds its rotations to a few digits, --orthonormalize "
                    f"projects each onto the nearest rotation (up to {REPAIR_TOL:g})"
                )
        raise InputFileError(f"{name}:{lines[i]}:1: {message}")
    trajectory = Trajectory(times, name=name, fmt=fmt, _matrices=matrices)
    if orthonormalize:
        trajectory.repaired = float(residual.max(initial=0.0))
        trajectory._matrices = project(matrices)
    return trajectory


def check_times(
    times: np.ndarray, name: str, lines, previous: float | None = None, written=None
) -> None:
    """Times must increase (``previous``: the time before the first of these).

    ``written(i)``, if given, is the time of row ``i`` as the file writes it (``i = -1``: the
    row before these): where two rows hold the same double, it tells a repeated time from
    two times closer than a double can tell apart at their magnitude.
    """
    before = np.concatenate([[previous], times]) if previous is not None else times
    steps = np.diff(before)
    bad = ~(steps > 0.0)
    if not bad.any():
        return
    i = int(np.argmax(bad)) + 1
    row = i - (previous is not None)  # the row of these times
    now, then = repr(float(before[i])), repr(float(before[i - 1]))
    step = Decimal(float(steps[i - 1]))
    if step == 0 and written is not None:  # the same double: are the times as written?
        as_written = written(row - 1), written(row)
        if _step(*as_written):
            then, now = as_written
            step = _step(*as_written)
    if step > 0:  # two rows that a double cannot tell apart
        magnitude = float(before[i])
        raise InputFileError(
            f"{_where(name, lines, row)}: the time {now} is {float(step):.3g} s after the "
            f"previous one, {then}, closer than a double tells apart at {magnitude:.3g} s (its "
            f"spacing there is {float(np.spacing(magnitude)):.2g} s); subtract a start time "
            "from the stamps, or drop the pose"
        )
    what = "repeats" if step == 0 else "goes back from"
    raise InputFileError(
        f"{_where(name, lines, row)}: the time {now} {what} the previous one, {then}; "
        "times must increase (sort the file, or drop the repeated pose)"
    )


def _step(before: str, after: str) -> Decimal:
    """``after - before`` of two times as written (0 if either is no decimal)."""
    try:
        return Decimal(after) - Decimal(before)
    except (InvalidOperation, TypeError, ValueError):
        return Decimal(0)
