"""Numbers and angles as the figures and the page show them: three significant digits, the
minus sign U+2212, and no negative zero. Used by the motions' summaries and by the scene."""

from __future__ import annotations

import math


def number_text(x: float) -> str:
    """``x`` to three significant digits, ``−`` for the minus sign and ``0`` for ``−0``."""
    text = f"{x:.3g}"
    return "0" if text in ("-0", "0") else text.replace("-", "−")


def angle_text(angle: float, unit: str) -> str:
    """The angle ``angle`` (radians) in ``unit``: ``"deg"`` (``90°``) or ``"rad"``."""
    if unit == "deg":
        return f"{number_text(math.degrees(angle))}°"
    return f"{number_text(angle)} rad"
