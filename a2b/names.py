"""The names a2b accepts for modes and frames, and its bounds on samples.

Free of numpy and of the core, so that start-up paths (``a2b --help``, the scanning of JSON
Lines jobs, :mod:`a2b.io.jobscan`) can check them without importing either.
"""

from __future__ import annotations

from .parameters import MODES  # noqa: F401  (listed with their parameters)

#: The frames of a cubic motion (:class:`a2b.motions.cubic.CubicMotion`).
FRAMES = ("canonical", "given")
#: The fewest samples: t = 0 and t = 1.
MIN_SAMPLES = 2
#: The most samples: beyond 2**53 evenly spaced t in [0, 1] are no longer distinct doubles.
MAX_SAMPLES = 2**53
#: The spaces of Bézier motions and splines (:mod:`a2b.motions.bezier`).
SPACES = ("matrix", "study")
#: The kernel bases of M_m (:func:`a2b.extended.kernel_basis`); ``auto`` first, the default.
BASES = ("auto", "paper", "rref")
