"""a2b: interpolate two rigid-body poses.

The motions of H.-P. Schröcker, *From A to B: New Methods to Interpolate Two Poses*:
vertical Darboux motions (a straight line in the extended dual-quaternion model), cubic
circular motions (a straight line in the extended matrix model, mapped by μ_[m]) and, as the
baseline, the screw motion (ScLERP).

>>> import numpy as np, a2b
>>> poses = a2b.interpolate(np.eye(4), np.eye(4), np.linspace(0, 1, 5))
>>> poses.shape
(5, 4, 4)
"""

from .errors import A2bError

__version__ = "0.1.0"

__all__ = [
    "A2bError",
    "__version__",
    "bezier",
    "describe",
    "fiber",
    "interpolate",
    "motion",
    "spline",
    "timing",
    "write",
]


def __getattr__(name):  # lazy: keep `import a2b` (and so `a2b --version`) light
    if name in ("interpolate", "describe", "motion"):
        from . import api

        return getattr(api, name)
    if name == "fiber":
        from .fibers import fiber

        return fiber
    if name == "timing":
        from .timelaw import timing

        return timing
    if name == "write":
        from .output import write

        return write
    if name in ("bezier", "spline"):
        from .motions import bezier

        return getattr(bezier, name)
    raise AttributeError(f"module 'a2b' has no attribute {name!r}")
