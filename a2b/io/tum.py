"""TUM trajectories: ``time tx ty tz qx qy qz qw`` per line, blank-separated, ``#`` comments.

The time is in seconds; the quaternion is rolled from TUM's x, y, z, w to a2b's w, x, y, z
here, at the edge, and nowhere else.
"""

from __future__ import annotations

from .textrows import TextLayout
from .trajectory import Trajectory, from_quaternions

__all__ = ["layout", "trajectory"]

#: t, tx, ty, tz, qw, qx, qy, qz: the fields of a line in the order of a2b's quaternions.
_LAYOUT = TextLayout(None, 0, 8, (0, 1, 2, 3, 7, 4, 5, 6), fmt="tum")


def layout(data: bytes, name: str, fmt: str) -> TextLayout:
    """The layout of a TUM file (fixed: TUM has no header)."""
    return _LAYOUT


def trajectory(rows, lines, name: str, fmt: str, rate, orthonormalize, row: int) -> Trajectory:
    """The poses of rows ``t, tx, ty, tz, qw, qx, qy, qz``."""
    return from_quaternions(rows[:, 0], rows[:, 4:8], rows[:, 1:4], name, fmt, lines)
