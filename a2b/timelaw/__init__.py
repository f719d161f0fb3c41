"""Time laws: a motion timed under speed, acceleration and jerk limits, with exact velocities.

A motion of a2b is a path ``t ↦ C(t)``, ``t ∈ [0, 1]``. A time law is kept apart from it: a
*progress* ``σ(τ)`` that runs from 0 to 1 over the duration ``T``, and the path parameter
``t(σ)``:

* ``t = σ`` by default, or
* with ``constant_speed``, the ``t`` at which the chosen body point has covered the fraction
  ``σ`` of its path length ``L`` (arc length computed by Gauss–Legendre quadrature to 1e-12
  relative, inverted by safeguarded Newton steps). Then the point's speed is ``L σ̇``.

Profiles of ``σ`` (rest to rest, except ``linear``), each a piecewise polynomial in ``τ``:

``linear``
    ``σ = τ / T``: even in ``t`` (or, with ``constant_speed``, a constant speed).
``trapezoid``
    Constant acceleration, cruise, constant deceleration: the time-optimal profile under a
    speed and an acceleration limit.
``jerk-limited``
    The seven-phase S-curve: the time-optimal rest-to-rest profile under speed, acceleration
    and jerk limits (the one Ruckig computes for one degree of freedom).
``quintic``
    ``σ = 10u³ − 15u⁴ + 6u⁵``, ``u = τ / T``: smooth to the acceleration, slowest of the four.

How the limits are met. The linear limits are on the body point: its speed ``|ẋ|`` and the
derivatives of its arc length ``s̈`` and ``s⃛`` (acceleration and jerk along the path, as in
industrial LIN motions); the angular ones on ``|ω|`` and ``|α|``. a2b first turns each limit
into a limit on ``σ̇``, ``σ̈``, ``σ⃛`` through the largest rate of the path per unit ``σ`` and
builds the profile from those. Along a path whose speed per unit ``σ`` varies (and for the
angular limits, whose ratio of rotation to translation varies) that bound is not exact, so
a2b then measures the true peaks of every limited quantity over the whole law (a grid of 65
points per phase, its six largest local maxima refined by 40 bracketing steps) and scales time
uniformly by ``c``: a ``k``-th time derivative scales by ``c^-k``, so with
``c = max (peak / limit)^(1/k)`` every limit holds and the tightest one is reached exactly.
With ``constant_speed`` and only linear limits the bound is exact and the profile is the
time-optimal one for the path length.

With ``duration`` the law lasts exactly that long: the law the limits give is slowed uniformly
to it (an error naming the limit and the time it needs if it would have to be faster). Without
limits, and where the limits given do not determine the profile (a trapezoid with only a speed
limit), the profile has a fixed shape (trapezoid and S-curve: a third of the time to
accelerate, a third to brake) and the limits are checks.

The default profile is ``jerk-limited`` with a jerk limit, else ``trapezoid`` with an
acceleration limit, else ``quintic`` with a speed limit (all at rest at both ends), and
``linear`` with a duration alone. Limits and durations run from 1e-30 to 1e30 in their units.

The package: :mod:`~a2b.timelaw.profiles` (the laws ``σ(τ)``), :mod:`~a2b.timelaw.arclength`,
:mod:`~a2b.timelaw.timed` (:class:`TimedMotion`, :func:`timing`) and :mod:`~a2b.timelaw.grid`
(:class:`TimeGrid`, the times at which a law is sampled, in bounded memory).
"""

from __future__ import annotations

from .arclength import arc_lengths
from .grid import TimeGrid
from .profiles import PROFILES, Profile, build
from .timed import LIMITS, TimedMotion, timing

__all__ = [
    "LIMITS",
    "PROFILES",
    "Profile",
    "TimeGrid",
    "TimedMotion",
    "arc_lengths",
    "build",
    "timing",
]
