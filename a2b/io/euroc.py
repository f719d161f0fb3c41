"""EuRoC ground truth: ``#timestamp [ns],p_RS_R_x [m],…,q_RS_w [],q_RS_x [],…`` and more.

The header names the columns, and they are read by their names (:func:`a2b.io.textrows.
named_layout`): the stamp, the position and the quaternion, in any order; EuRoC's velocity
and bias columns are allowed and not read. Stamps are whole nanoseconds, read as integers
(they exceed 2**53), unless the stamp's name gives the unit ``[s]``.
"""

from __future__ import annotations

from ..errors import InputFileError
from .textrows import TextLayout, header_line, named_layout
from .trajectory import Trajectory, from_quaternions

__all__ = ["POSE_COLUMNS", "layout", "trajectory"]

#: The columns of a quaternion pose, in the order its reader takes them.
POSE_COLUMNS = ("t", "tx", "ty", "tz", "qw", "qx", "qy", "qz")


def layout(data: bytes, name: str, fmt: str) -> TextLayout:
    """The layout the header line names."""
    head = header_line(data, name)
    if not head.startswith("#"):
        raise InputFileError(f"{name}:1:1: expected EuRoC's '#timestamp [ns],…' header line")
    return named_layout(head, name, "euroc", POSE_COLUMNS, nanoseconds=True)


def trajectory(rows, lines, name: str, fmt: str, rate, orthonormalize, row: int) -> Trajectory:
    """The poses of rows ``t, tx, ty, tz, qw, qx, qy, qz``."""
    return from_quaternions(rows[:, 0], rows[:, 4:8], rows[:, 1:4], name, fmt, lines)
