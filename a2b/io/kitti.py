"""KITTI poses: the 12 numbers of ``[R | t]``, row by row, blank-separated, one pose a line.

KITTI holds no times: a pose's time is its index in the file, or ``index / rate`` seconds.
"""

from __future__ import annotations

import numpy as np

from .textrows import TextLayout
from .trajectory import Trajectory, from_matrices

__all__ = ["layout", "trajectory"]

_LAYOUT = TextLayout(None, 0, 12, tuple(range(12)), fmt="kitti")


def layout(data: bytes, name: str, fmt: str) -> TextLayout:
    """The layout of a KITTI file (fixed: KITTI has no header)."""
    return _LAYOUT


def trajectory(rows, lines, name: str, fmt: str, rate, orthonormalize, row: int) -> Trajectory:
    """The poses of rows of ``[R | t]``; ``row`` poses of the file came before these."""
    times = np.arange(row, row + len(rows), dtype=float)
    if rate is not None:
        times /= rate
    return from_matrices(times, rows, lines, name, fmt, orthonormalize)
