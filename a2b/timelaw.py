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
to it (an error if it would have to be faster), or without limits a profile of fixed shape
(trapezoid and S-curve: a third of the time to accelerate, a third to brake).
"""

from __future__ import annotations

import numpy as np

from .elements import refuse, value
from .errors import A2bError, ParameterError
from .kinematics import _angular, check_point, path_rates, point_derivatives, reparametrise
from .kinematics import accelerations as _accelerations
from .kinematics import twists as _twists

__all__ = ["LIMITS", "PROFILES", "Profile", "TimedMotion", "arc_lengths", "build", "timing"]

PROFILES = ("linear", "trapezoid", "jerk-limited", "quintic")
#: The limits a law takes, and the time derivative each one bounds.
LIMITS = {
    "speed": 1,
    "accel": 2,
    "jerk": 3,
    "angular_speed": 1,
    "angular_accel": 2,
}
#: Units of the limits and peaks, in words.
UNITS = {
    "speed": "length/s",
    "accel": "length/s²",
    "jerk": "length/s³",
    "total_accel": "length/s²",
    "angular_speed": "rad/s",
    "angular_accel": "rad/s²",
}
LINEAR = ("speed", "accel", "jerk")

#: Arc length: Gauss–Legendre nodes per panel, and the relative agreement asked of two
#: successive panel counts.
NODES = 16
ARC_TOL = 1e-12
MOST_PANELS = 1 << 12
#: The first check: one panel of :data:`FIRST_NODES` against one of :data:`NODES`, agreeing
#: to :data:`FIRST_TOL` relative. For an analytic speed the error of ``n`` Gauss nodes falls
#: like ``ρ^(−2n)``, so that of 16 nodes is about the square of that of 8: agreement to 1e-7
#: leaves 16 nodes within about 1e-14 (measured: at most 8e-14 over 20,000 random motions of
#: each kind, against 1,024 nodes).
FIRST_NODES = 8
FIRST_TOL = 1e-7
#: Motions whose arc lengths are computed together (a few MB of samples).
ARC_BLOCK = 4096
#: Peak search: grid points per phase, values of t evenly spaced whose times are candidates
#: too, and bracketing steps.
GRID = 65
PATH_GRID = 257
STEPS = 40
CANDIDATES = 6
#: Motions evaluated together (bounds memory: a block of derivative stacks is ~70 MB).
BLOCK = 1024


class Profile:
    """Rest-to-rest laws ``σ(τ)`` from 0 to 1, a piecewise polynomial per law, for a batch.

    ``starts`` ``S + (P + 1,)``: phase boundaries, from 0 to the duration. ``coefficients``
    ``S + (P, 6)``: ``σ = Σ_k c_k (τ − start)^k`` in each phase.
    """

    def __init__(self, kind: str, starts: np.ndarray, coefficients: np.ndarray):
        self.kind = kind
        self.starts = starts
        self.coefficients = coefficients

    @property
    def duration(self) -> np.ndarray:
        return self.starts[..., -1]

    @property
    def shape(self) -> tuple:
        return self.starts.shape[:-1]

    def scaled(self, factor) -> Profile:
        """The same law ``factor`` times slower: ``σ_new(τ) = σ(τ / factor)``."""
        factor = np.asarray(factor, dtype=float)[..., None]
        powers = factor[..., None] ** -np.arange(6)
        return Profile(self.kind, self.starts * factor, self.coefficients * powers)

    def phase_values(self, phase: np.ndarray, dt: np.ndarray) -> np.ndarray:
        """``σ, σ̇, σ̈, σ⃛`` ``S + (N, 4)`` at times ``dt`` into phases ``phase`` (``S + (N,)``)."""
        coefficients = np.take_along_axis(
            self.coefficients,
            np.broadcast_to(phase, self.shape + phase.shape[-1:])[..., None],
            axis=-2,
        )
        out = np.zeros(dt.shape + (4,))
        for r in range(4):
            for k in range(r, 6):
                factor = float(np.prod(np.arange(k - r + 1, k + 1)))
                out[..., r] += factor * coefficients[..., k] * dt ** (k - r)
        return out

    def phase_times(self, sigma: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Where the law first reaches ``sigma`` (``S + (N,)`` in ``[0, 1]``): the phase and the
        time into it, ``S + (N,)`` each (safeguarded Newton steps on the phase's polynomial)."""
        sigma = np.broadcast_to(np.asarray(sigma, dtype=float), self.shape + np.shape(sigma)[-1:])
        phases = self.coefficients.shape[-2]
        opening = self.coefficients[..., 0]  # σ where each phase starts, S + (P,)
        phase = np.minimum(np.sum(opening[..., None, 1:] <= sigma[..., None], axis=-1), phases - 1)
        length = np.take_along_axis(np.diff(self.starts, axis=-1), phase, axis=-1)
        first, last = np.take_along_axis(opening, phase, -1), self.phase_values(phase, length)
        low, high = np.zeros(sigma.shape), length.copy()
        with np.errstate(divide="ignore", invalid="ignore"):  # start: the chord of the phase
            dt = length * np.clip((sigma - first) / (last[..., 0] - first), 0.0, 1.0)
            dt = np.where(np.isfinite(dt), dt, 0.0)
            for _ in range(60):
                law = self.phase_values(phase, dt)
                miss = law[..., 0] - sigma
                if np.all(np.abs(miss) <= 1e-15):
                    break
                low = np.where(miss < 0, dt, low)
                high = np.where(miss > 0, dt, high)
                step = dt - miss / law[..., 1]
                inside = (step > low) & (step < high)
                dt = np.where(np.abs(miss) <= 1e-15, dt, np.where(inside, step, (low + high) / 2))
        return phase, dt

    def values(self, times: np.ndarray) -> np.ndarray:
        """``σ, σ̇, σ̈, σ⃛`` at ``times`` in ``[0, duration]`` (``(N,)`` or ``S + (N,)``)."""
        times = np.broadcast_to(times, self.shape + np.shape(times)[-1:])
        phases = self.starts.shape[-1] - 1
        phase = np.sum(times[..., None] >= self.starts[..., None, 1:-1], axis=-1)
        phase = np.minimum(phase, phases - 1)
        start = np.take_along_axis(self.starts, phase, axis=-1)
        end = times >= self.duration[..., None]
        times = np.where(end, self.duration[..., None], times)
        out = self.phase_values(phase, times - start)
        out[..., 0][end] = 1.0  # the end exactly, whatever the rounding of the phases
        return out


def _phases(kind: str, durations: np.ndarray, accels: np.ndarray, jerks: np.ndarray) -> Profile:
    """A law from phase durations, the acceleration at the start of each phase and each phase's
    jerk (``S + (P,)`` each), integrated from rest at 0."""
    shape = durations.shape[:-1]
    position = np.zeros(shape)
    speed = np.zeros(shape)
    coefficients = np.zeros((6,) + durations.shape)  # filled by rows, returned by columns
    for k in range(durations.shape[-1]):
        d, a, j = durations[..., k], accels[..., k], jerks[..., k]
        for row, part in enumerate((position, speed, a / 2, j / 6)):
            coefficients[row, ..., k] = part
        position = position + d * (speed + d * (a / 2 + d * j / 6))
        speed = speed + d * (a + d * j / 2)
    coefficients = np.moveaxis(coefficients, 0, -1)
    starts = np.concatenate([np.zeros(shape + (1,)), np.cumsum(durations, axis=-1)], axis=-1)
    return Profile(kind, starts, coefficients)


def trapezoid(speed, accel) -> Profile:
    """The fastest law from 0 to 1 with ``|σ̇| ≤ speed`` and ``|σ̈| ≤ accel`` (``inf``: none)."""
    speed, accel = np.broadcast_arrays(np.asarray(speed, float), np.asarray(accel, float))
    with np.errstate(divide="ignore", invalid="ignore"):
        cruising = speed * speed <= accel  # the speed limit is reached within the distance 1
        t_accel = np.where(cruising, speed / accel, np.sqrt(1.0 / accel))
        t_cruise = np.where(cruising, 1.0 / speed - speed / accel, 0.0)
    durations = np.stack([t_accel, t_cruise, t_accel], axis=-1)
    accels = np.stack([accel, np.zeros_like(accel), -accel], axis=-1)
    return _phases("trapezoid", durations, accels, np.zeros_like(durations))


def jerk_limited(speed, accel, jerk) -> Profile:
    """The fastest rest-to-rest law from 0 to 1 under ``|σ̇| ≤ speed``, ``|σ̈| ≤ accel`` and
    ``|σ⃛| ≤ jerk`` (``speed`` and ``accel`` may be ``inf``; ``jerk`` is finite).

    The S-curve: jerk ``+j, 0, −j`` to the top speed ``v_p``, a cruise, and the mirror image.
    Accelerating to ``v`` takes ``2 t_j + t_a`` and covers ``v (t_j + t_a / 2)``, with
    ``t_j = a / j`` and ``t_a = v / a − a / j`` where ``v ≥ a² / j`` (else ``t_j = √(v / j)``,
    ``t_a = 0``). Where accelerating and braking would cover more than 1, ``v_p < v`` solves
    ``v_p (v_p / a + a / j) = 1`` (``v_p ≥ a² / j``) or ``v_p = (√j / 2)^(2/3)``.
    """
    v, a, j = np.broadcast_arrays(*(np.asarray(x, float) for x in (speed, accel, jerk)))
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        reach_a = v * j >= a * a
        t_j = np.where(reach_a, a / j, np.sqrt(v / j))
        t_a = np.where(reach_a, v / a - a / j, 0.0)
        cover = v * (2 * t_j + t_a)  # accelerating to v and braking from it
        short = ~(cover <= 1.0)
        # v not reached: is a reached?
        ratio = a * a / j
        v_a = (-ratio + np.sqrt(ratio * ratio + 4.0 * a)) / 2.0
        with_a = np.isfinite(a) & (v_a >= ratio)
        v_j = (np.sqrt(j) / 2.0) ** (2.0 / 3.0)
        peak = np.where(short, np.where(with_a, v_a, v_j), v)
        t_j = np.where(short, np.where(with_a, a / j, np.sqrt(peak / j)), t_j)
        t_a = np.where(short, np.where(with_a, peak / a - a / j, 0.0), t_a)
        t_v = np.where(short, 0.0, 1.0 / v - (2 * t_j + t_a))
        a_p = j * t_j
    zero = np.zeros_like(t_j)
    durations = np.stack([t_j, t_a, t_j, t_v, t_j, t_a, t_j], axis=-1)
    accels = np.stack([zero, a_p, a_p, zero, zero, -a_p, -a_p], axis=-1)
    jerks = np.stack([j, zero, -j, zero, -j, zero, j], axis=-1)
    return _phases("jerk-limited", durations, accels, jerks)


#: Peaks of σ̇, σ̈, σ⃛ of the quintic law over unit time: 15/8, 10/√3, 60.
QUINTIC_PEAKS = (15.0 / 8.0, 10.0 / np.sqrt(3.0), 60.0)


def quintic(speed, accel, jerk) -> Profile:
    """``σ = 10u³ − 15u⁴ + 6u⁵`` over the shortest ``T`` within the limits."""
    v, a, j = np.broadcast_arrays(*(np.asarray(x, float) for x in (speed, accel, jerk)))
    with np.errstate(divide="ignore"):
        duration = np.maximum.reduce(
            [QUINTIC_PEAKS[0] / v, np.sqrt(QUINTIC_PEAKS[1] / a), np.cbrt(QUINTIC_PEAKS[2] / j)]
        )
    return _fixed("quintic", duration)


def _fixed(kind: str, duration) -> Profile:
    """``linear`` or ``quintic`` over ``duration``, one phase."""
    duration = np.asarray(duration, float)
    coefficients = np.zeros(duration.shape + (1, 6))
    if kind == "linear":
        coefficients[..., 0, 1] = 1.0 / duration
    else:
        coefficients[..., 0, 3:] = np.stack(
            [10.0 / duration**3, -15.0 / duration**4, 6.0 / duration**5], axis=-1
        )
    starts = np.stack([np.zeros_like(duration), duration], axis=-1)
    return Profile(kind, starts, coefficients)


def shaped(kind: str, duration) -> Profile:
    """A law of ``duration`` without limits: trapezoid and S-curve accelerate for a third of
    the time and brake for a third; linear and quintic are what they are."""
    duration = np.asarray(duration, float)
    if kind in ("linear", "quintic"):
        return _fixed(kind, duration)
    if kind == "trapezoid":
        return trapezoid(1.5 / duration, 4.5 / duration**2)
    return jerk_limited(1.5 / duration, np.inf, 54.0 / duration**3)


def build(kind: str, speed, accel, jerk) -> Profile:
    """The fastest law of ``kind`` under limits on ``σ̇, σ̈, σ⃛`` (``inf``: none)."""
    if kind == "linear":
        return _fixed("linear", 1.0 / np.asarray(speed, float))
    if kind == "trapezoid":
        return trapezoid(speed, accel)
    if kind == "jerk-limited":
        return jerk_limited(speed, accel, jerk)
    return quintic(speed, accel, jerk)


def _in_blocks(motion, work, *parts):
    """``work(motion, *parts)`` on blocks of :data:`BLOCK` motions along the first axis (each
    part sliced alike), the results joined: bounds memory for any batch."""
    shape = getattr(motion, "shape", ())
    if not shape or shape[0] <= BLOCK:
        return work(motion, *parts)
    results = [
        work(motion[lo : lo + BLOCK], *(None if p is None else p[lo : lo + BLOCK] for p in parts))
        for lo in range(0, shape[0], BLOCK)
    ]
    if isinstance(results[0], tuple):
        return tuple(np.concatenate(r) for r in zip(*results))
    if isinstance(results[0], dict):
        return {k: np.concatenate([r[k] for r in results]) for k in results[0]}
    return np.concatenate(results)


# -- arc length ----------------------------------------------------------------------------------

_RULES = {n: np.polynomial.legendre.leggauss(n) for n in (FIRST_NODES, NODES)}
_NODES, _WEIGHTS = _RULES[NODES]


def _panel_lengths(motion, point, panels: int, nodes: int = NODES) -> np.ndarray:
    """Gauss–Legendre with ``nodes`` nodes on each of ``panels`` equal panels of ``[0, 1]``:
    the path length on each panel, ``S + (panels,)``."""
    x, weights = _RULES[nodes]
    edges = np.linspace(0.0, 1.0, panels + 1)
    half = (edges[1:] - edges[:-1]) / 2
    ts = ((edges[:-1] + half)[:, None] + half[:, None] * x).reshape(-1)
    speeds = motion.point_speeds(ts, point).reshape(getattr(motion, "shape", ()) + (panels, nodes))
    return speeds @ weights * half


def arc_lengths(motion, point=None) -> tuple[np.ndarray, np.ndarray]:
    """The length of the point's path on ``t ∈ [0, 1]`` and the cumulative lengths at the
    edges of equal panels of ``t``: ``S`` and ``S + (P + 1,)``.

    Composite Gauss–Legendre (:data:`NODES` nodes a panel). Each motion starts with one panel
    (a Bézier spline one a segment), checked against :data:`FIRST_NODES` nodes, and doubles its
    own count until two counts agree to :data:`ARC_TOL` relative (at most :data:`MOST_PANELS`),
    so a smooth path costs a few dozen speeds. The cumulative lengths of a batch are padded
    with ``+inf`` past each motion's last panel edge: a motion's panel count is the number of
    its finite entries less one. Blocks of :data:`ARC_BLOCK` motions bound memory.

    Raises
    ------
    A2bError
        If two quadratures of a motion still differ by more than 1e-9 relative at the most
        panels (its point passes very close to a singular pose).
    """
    shape = getattr(motion, "shape", ())
    if not shape:
        total, cumulative = _arc_lengths(motion, point, 1)
        return total[0], cumulative[0]
    flat = int(np.prod(shape))
    if len(shape) > 1:
        motion = motion[np.unravel_index(np.arange(flat), shape)]
    parts = [
        _arc_lengths(motion[lo : lo + ARC_BLOCK], point, min(ARC_BLOCK, flat - lo), lo, shape)
        for lo in range(0, flat, ARC_BLOCK)
    ]
    width = max(part[1].shape[-1] for part in parts)
    total = np.concatenate([part[0] for part in parts]).reshape(shape)
    cumulative = np.full((flat, width), np.inf)
    row = 0
    for _, part in parts:
        cumulative[row : row + len(part), : part.shape[-1]] = part
        row += len(part)
    return total, cumulative.reshape(shape + (width,))


def _arc_lengths(
    motion, point, count: int, offset: int = 0, shape: tuple = ()
) -> tuple[np.ndarray, np.ndarray]:
    """:func:`arc_lengths` of ``count`` motions (a 1-D batch, or one motion for ``count = 1``
    with no shape): ``(count,)`` and ``(count, P + 1)``, padded with ``+inf``. The block
    starts at flat index ``offset`` of a batch of ``shape`` (to name a motion in an error)."""
    single = not getattr(motion, "shape", ())
    # the rounding floor: a point that stands still has speeds of rounding size, about ε times
    # its distance from the origin, and no relative accuracy to reach
    ends = motion.derivatives(np.array([0.0, 1.0]), 0, point=check_point(point))
    floor = ARC_TOL * np.linalg.norm(ends, axis=-1).sum(axis=(-2, -1)).reshape(count)
    total, rows = np.zeros(count), {}
    # a curve starts with a panel per segment: none straddles a joint, where the speed of a
    # spline is only continuous (its derivative may jump, which Gauss nodes converge on slowly)
    first = len(motion.joints()) + 1 if hasattr(motion, "joints") else 1
    todo, panels, tol = np.arange(count), first, FIRST_TOL
    coarse = _panel_lengths(motion, point, first, FIRST_NODES).reshape(count, first)
    while True:
        fine = _panel_lengths(motion, point, panels).reshape(len(todo), panels)
        length, gap = fine.sum(axis=-1), np.abs(fine.sum(axis=-1) - coarse.sum(axis=-1))
        done = gap <= tol * length + floor[todo]
        if panels >= MOST_PANELS:
            relative = np.zeros(int(np.prod(shape)))
            relative[offset + todo] = np.where(
                gap <= 1e-9 * length + floor[todo], 0.0, gap / np.maximum(length, 1e-300)
            )
            refuse(
                A2bError,
                relative.reshape(shape) > 1e-9,
                lambda i: (
                    "the path length of the point did not converge: two quadratures differ "
                    f"by {relative[i]:.3g} relative, tolerance 1e-09 (the motion comes very "
                    "close to a singular pose)"
                ),
                shape,
            )
            done[:] = True
        total[todo[done]] = length[done]
        rows[panels] = (todo[done], np.cumsum(fine[done], axis=-1))
        if done.all():
            break
        todo, coarse, panels, tol = todo[~done], fine[~done], 2 * panels, ARC_TOL
        motion = motion if single else motion[~done]
    cumulative = np.full((count, panels + 1), np.inf)
    cumulative[:, 0] = 0.0
    for width, (which, sums) in rows.items():
        cumulative[which, 1 : width + 1] = sums
    return total, cumulative


def _length_to(motion, point, lo: np.ndarray, ts: np.ndarray) -> np.ndarray:
    """``∫_lo^t |dx/dt|`` for per-sample ``lo ≤ t`` (``S + (N,)``), Gauss–Legendre."""
    half = (ts - lo) / 2
    nodes = (lo + half)[..., None] + half[..., None] * _NODES
    speeds = motion.point_speeds(nodes.reshape(nodes.shape[:-2] + (-1,)), point)
    return speeds.reshape(nodes.shape) @ _WEIGHTS * half


def _panel_counts(cumulative: np.ndarray) -> np.ndarray:
    """Each motion's panel count, ``S + (1,)``: the finite cumulative lengths less one (the rest
    is ``+inf`` padding, see :func:`arc_lengths`)."""
    return np.sum(np.isfinite(cumulative), axis=-1)[..., None] - 1


def lengths_at(motion, point, cumulative: np.ndarray, ts: np.ndarray) -> np.ndarray:
    """The path length covered from 0 to ``ts`` (``(N,)`` or ``S + (N,)`` in ``[0, 1]``), from
    the cumulative lengths of :func:`arc_lengths`: ``S + (N,)``."""
    shape = getattr(motion, "shape", ())
    panels = _panel_counts(cumulative)
    ts = np.broadcast_to(np.asarray(ts, dtype=float), shape + np.shape(ts)[-1:])
    panel = np.minimum(np.floor(ts * panels), panels - 1).astype(int)
    base = np.take_along_axis(np.broadcast_to(cumulative, shape + cumulative.shape[-1:]), panel, -1)
    return base + _length_to(motion, point, panel / panels, ts)


def invert_arc_length(motion, point, cumulative: np.ndarray, fractions: np.ndarray) -> np.ndarray:
    """The ``t`` at which the point has covered ``fractions`` (``S + (N,)``) of its path, from
    the cumulative lengths of :func:`arc_lengths` (safeguarded Newton steps in its panel)."""
    shape = getattr(motion, "shape", ())
    panels = _panel_counts(cumulative)
    total = np.take_along_axis(cumulative, panels, axis=-1)
    target = fractions * total
    # the panel of each target: count the panel ends below it
    below = np.sum(cumulative[..., None, 1:] <= target[..., None], axis=-1)
    panel = np.minimum(below, panels - 1)
    lo_t = panel / panels
    hi_t = (panel + 1) / panels
    cumulative = np.broadcast_to(cumulative, shape + cumulative.shape[-1:])
    base = np.take_along_axis(cumulative, panel.reshape(shape + (-1,)), axis=-1)
    top = np.take_along_axis(cumulative, (panel + 1).reshape(shape + (-1,)), axis=-1)
    base, top = base.reshape(panel.shape), top.reshape(panel.shape)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(top > base, lo_t + (target - base) / (top - base) / panels, lo_t)
    low, high = lo_t.copy(), hi_t.copy()
    for _ in range(60):
        covered = base + _length_to(motion, point, lo_t, t)
        miss = covered - target
        done = np.abs(miss) <= 1e-13 * np.maximum(total, 1e-300)
        if done.all():
            break
        low = np.where(miss < 0, t, low)
        high = np.where(miss > 0, t, high)
        speed = motion.point_speeds(t, point)
        with np.errstate(divide="ignore", invalid="ignore"):
            step = t - miss / speed
        inside = (step > low) & (step < high)
        t = np.where(done, t, np.where(inside, step, (low + high) / 2))
    return np.clip(t, 0.0, 1.0)


# -- the timed motion ----------------------------------------------------------------------------


def _limit_values(limits: dict, shape: tuple) -> dict:
    out = {}
    for name, given in limits.items():
        if name not in LIMITS:
            raise ParameterError(f"unknown limit {name!r}; expected one of {', '.join(LIMITS)}")
        if given is None:
            continue
        arr = np.broadcast_to(np.asarray(given, dtype=float), shape)
        refuse(
            ParameterError,
            ~(arr > 0) | ~np.isfinite(arr),
            lambda i, n=name, a=arr: (
                f"the {n.replace('_', ' ')} limit must be a positive "
                f"finite number, got {value(a, i):g}"
            ),
            shape,
        )
        out[name] = arr
    return out


class TimedMotion:
    """A motion with a time law: poses, twists and accelerations at times in seconds.

    Build it with :func:`timing`. Attributes (leading shape ``S`` of the motion):
    ``duration``, ``path_length`` (of the point; ``None`` unless needed), ``profile``,
    ``limits``, ``binding`` (the name of the limit that is reached, per motion).
    """

    def __init__(
        self, motion, profile: Profile, point, constant_speed: bool, limits: dict, lengths
    ):
        self.motion = motion
        self.profile = profile
        self.point = point
        self.constant_speed = constant_speed
        self.limits = limits
        self._lengths = lengths
        self.binding = None

    @property
    def shape(self) -> tuple:
        return self.profile.shape

    @property
    def duration(self):
        d = self.profile.duration
        return float(d) if not self.shape else d

    @property
    def path_length(self):
        if self._lengths is None:
            self._lengths = arc_lengths(self.motion, self.point)
        total = self._lengths[0]
        return float(total) if not self.shape else total

    def times(self, rate: float | None = None, dt: float | None = None, samples=None):
        """Times from 0 to the duration: every ``dt`` (or ``1 / rate``) seconds and the end, or
        ``samples`` evenly spaced. A single motion only (a batch has a duration per motion)."""
        if self.shape:
            raise ParameterError("times() is for one motion; give each motion its own times")
        total = float(self.profile.duration)
        if samples is not None:
            return np.linspace(0.0, total, int(samples))
        step = dt if dt is not None else 1.0 / rate
        if not step > 0:
            raise ParameterError(f"the time step must be positive, got {step:g}")
        count = int(np.floor(total / step * (1 + 1e-12))) + 1
        out = np.arange(count) * dt if dt is not None else np.arange(count) / rate
        if out[-1] < total * (1 - 1e-12):
            out = np.append(out, total)
        else:
            out[-1] = total
        return out

    def _check_times(self, times) -> np.ndarray:
        arr = np.asarray(times, dtype=float)
        if arr.ndim == 0 or (arr.ndim > 1 and arr.shape[:-1] != self.shape):
            raise ParameterError(
                f"times must be a 1-D array or an array of shape {self.shape + ('N',)}, got "
                f"shape {arr.shape}"
            )
        duration = np.asarray(self.profile.duration)[..., None]
        bad = ~((arr >= 0) & (arr <= duration * (1 + 1e-12)))
        if bad.any():
            raise ParameterError(
                f"times must lie in [0, duration]; got {float(arr[bad].flat[0]):.9g} s (the "
                f"duration is {float(np.max(duration)):.9g} s)"
            )
        return arr

    def _progress(self, sigma: np.ndarray) -> np.ndarray:
        """``t`` and its derivatives in ``σ`` (``S + (N, 4)``: ``t, t_σ, t_σσ, t_σσσ``)."""
        out = np.zeros(sigma.shape + (4,))
        if not self.constant_speed:
            out[..., 0] = sigma
            out[..., 1] = 1.0
            return out
        total, cumulative = self._lengths
        t = invert_arc_length(self.motion, self.point, cumulative, sigma)
        x = self.motion.derivatives(t, 3, point=self.point)  # the point's path only
        d1, d2, d3 = x[..., 1, :, :], x[..., 2, :, :], x[..., 3, :, :]
        g = np.linalg.norm(d1, axis=-1)
        g1 = np.einsum("...i,...i->...", d1, d2) / g
        g2 = (
            np.einsum("...i,...i->...", d2, d2) + np.einsum("...i,...i->...", d1, d3) - g1 * g1
        ) / g
        length = np.asarray(total)[..., None]
        out[..., 0] = t
        out[..., 1] = length / g
        out[..., 2] = -(length**2) * g1 / g**3
        out[..., 3] = -(length**3) * (g2 * g - 3 * g1 * g1) / g**5
        return out

    def _stack(self, times: np.ndarray, order: int = 3) -> tuple[np.ndarray, np.ndarray]:
        """``t`` at ``times`` and the derivative stack in time, ``S + (order + 1, N, 4, 4)``."""
        law = self.profile.values(times)
        return self._stack_at(law, order)

    def _stack_at(self, law: np.ndarray, order: int) -> tuple[np.ndarray, np.ndarray]:
        progress = self._progress(law[..., 0])
        t = progress[..., 0]
        s1, s2, s3 = law[..., 1], law[..., 2], law[..., 3]
        p1, p2, p3 = progress[..., 1], progress[..., 2], progress[..., 3]
        rates = np.stack(
            [p1 * s1, p2 * s1**2 + p1 * s2, p3 * s1**3 + 3 * p2 * s1 * s2 + p1 * s3], axis=-1
        )
        stack = self.motion.derivatives(t, order)
        return t, reparametrise(stack, rates[..., :order])

    # -- public sampling ---------------------------------------------------------------------
    def parameters(self, times) -> np.ndarray:
        """The motion's ``t`` at ``times`` (seconds from the start), ``S + (N,)``."""
        arr = self._check_times(times)
        return self._progress(self.profile.values(arr)[..., 0])[..., 0]

    def sample(self, times, velocities: bool = False) -> tuple[np.ndarray, np.ndarray | None]:
        """The motion's ``t`` at ``times`` and, with ``velocities``, the :meth:`twists` in the
        world frame (``None`` without): one inversion of the arc length serves both."""
        arr = self._check_times(times)
        if not velocities:
            return self.parameters(arr), None
        t, stack = self._stack(arr, 1)
        return t, _twists(stack, "world", self.point)

    def matrices(self, times) -> np.ndarray:
        """The poses at ``times``: ``S + (N, 4, 4)``."""
        return self.motion.matrices(self.parameters(times))

    def quat_trans(self, times):
        return self.motion.quat_trans(self.parameters(times))

    def twists(self, times, frame: str = "world", point=None) -> np.ndarray:
        """Velocities in time at ``times``, ``S + (N, 6)`` ``(v, w)``; see :mod:`a2b.kinematics`.
        ``point`` defaults to the point of the law."""
        point = self.point if point is None and frame != "spatial" else point
        return _twists(self._stack(self._check_times(times), 1)[1], frame, point)

    def accelerations(self, times, frame: str = "world", point=None) -> np.ndarray:
        """The time derivatives of :meth:`twists`, ``S + (N, 6)``."""
        point = self.point if point is None and frame != "spatial" else point
        return _accelerations(self._stack(self._check_times(times), 2)[1], frame, point)

    def rates(self, times) -> dict:
        """The limited rates at ``times``, ``S + (N,)`` each (:func:`a2b.kinematics.path_rates`)."""
        return path_rates(self._stack(self._check_times(times), 3)[1], self.point)

    # -- peaks --------------------------------------------------------------------------------
    def _rates_in_phase(self, phase: np.ndarray, dt: np.ndarray) -> dict:
        law = self.profile.phase_values(phase, dt)
        law[..., 0] = np.clip(law[..., 0], 0.0, 1.0)
        return path_rates(self._stack_at(law, 3)[1], self.point)

    def _part(self, lo: int, hi: int) -> TimedMotion:
        """Motions ``lo`` to ``hi`` along the first axis, as a timed motion of their own."""
        profile = Profile(
            self.profile.kind, self.profile.starts[lo:hi], self.profile.coefficients[lo:hi]
        )
        lengths = None if self._lengths is None else tuple(x[lo:hi] for x in self._lengths)
        return TimedMotion(
            self.motion[lo:hi], profile, self.point, self.constant_speed, {}, lengths
        )

    def peaks(self, names=None) -> dict:
        """The largest value over the whole law of each rate in ``names`` (default: all six of
        :func:`a2b.kinematics.path_rates`, acceleration and jerk as magnitudes), ``S`` each."""
        names = list(
            names or ("speed", "accel", "jerk", "total_accel", "angular_speed", "angular_accel")
        )
        if self.shape and self.shape[0] > BLOCK:
            parts = [
                self._part(lo, lo + BLOCK)._peaks(names) for lo in range(0, self.shape[0], BLOCK)
            ]
            return {k: np.concatenate([p[k] for p in parts]) for k in names}
        return self._peaks(names)

    def _peaks(self, names: list) -> dict:
        """Candidates: :data:`GRID` times a phase, and the times at which the law passes
        :data:`PATH_GRID` values of ``t`` evenly spaced (a rate can peak sharply in time
        where the path does in t: a long cruise crosses a narrow turn of the path in a few
        hundredths of its time). The :data:`CANDIDATES` largest local maxima are refined by
        ternary search within their phase, between their neighbours."""
        profile = self.profile
        phases = profile.coefficients.shape[-2]
        lengths = np.diff(profile.starts, axis=-1)  # S + (P,)
        grid = np.linspace(0.0, 1.0, GRID)
        phase = np.broadcast_to(np.repeat(np.arange(phases), GRID), self.shape + (phases * GRID,))
        dt = (lengths[..., :, None] * grid).reshape(self.shape + (-1,))
        ts = np.linspace(0.0, 1.0, PATH_GRID)
        if self.constant_speed:
            total, cumulative = self._lengths
            with np.errstate(divide="ignore", invalid="ignore"):
                sigma = (
                    lengths_at(self.motion, self.point, cumulative, ts)
                    / np.asarray(total)[..., None]
                )
            sigma = np.clip(np.where(np.isfinite(sigma), sigma, 0.0), 0.0, 1.0)
        else:
            sigma = np.broadcast_to(ts, self.shape + ts.shape)
        path_phase, path_dt = profile.phase_times(sigma)
        phase = np.concatenate([phase, path_phase], axis=-1)
        dt = np.concatenate([dt, path_dt], axis=-1)
        # in order of time, each candidate's neighbours bracket it
        when = np.take_along_axis(profile.starts, phase, -1) + dt
        order = np.argsort(when, axis=-1, kind="stable")
        phase, dt, when = (np.take_along_axis(x, order, -1) for x in (phase, dt, when))
        values = self._rates_in_phase(phase, dt)
        opening = np.take_along_axis(profile.starts, phase, -1)
        phase_len = np.take_along_axis(lengths, phase, -1)
        # the neighbours in time; where two candidates coincide (a time of the path grid on the
        # phase grid, to rounding), the one beyond, so that each side is searched
        pad = np.concatenate(
            [when[..., :1], when[..., :1], when, when[..., -1:], when[..., -1:]], -1
        )
        near = 1e-9 * profile.duration[..., None]
        before = np.where(when - pad[..., 1:-3] > near, pad[..., 1:-3], pad[..., :-4])
        after = np.where(pad[..., 3:-1] - when > near, pad[..., 3:-1], pad[..., 4:])
        out = {}
        for name in names:
            magnitude = np.abs(values[name])
            rise = np.ones(magnitude.shape, dtype=bool)
            rise[..., 1:] &= magnitude[..., 1:] >= magnitude[..., :-1]
            rise[..., :-1] &= magnitude[..., :-1] >= magnitude[..., 1:]
            score = np.where(rise, magnitude, -1.0)
            count = min(CANDIDATES, score.shape[-1])
            best = np.argsort(-score, axis=-1)[..., :count]
            which = np.take_along_axis(phase, best, -1)
            start = np.take_along_axis(opening, best, -1)
            span = np.take_along_axis(phase_len, best, -1)
            lo = np.clip(np.take_along_axis(before, best, -1) - start, 0.0, span)
            hi = np.clip(np.take_along_axis(after, best, -1) - start, 0.0, span)
            top = magnitude.max(axis=-1, keepdims=True)
            for _ in range(STEPS):
                a = lo + (hi - lo) / 3
                b = hi - (hi - lo) / 3
                both = np.concatenate([a, b], axis=-1)
                found = np.abs(self._rates_in_phase(np.concatenate([which, which], -1), both)[name])
                fa, fb = found[..., :count], found[..., count:]
                top = np.maximum(top, np.maximum(fa, fb).max(axis=-1, keepdims=True))
                left = fa >= fb
                hi = np.where(left, b, hi)
                lo = np.where(left, lo, a)
            out[name] = top[..., 0] if self.shape else float(top[..., 0])
        return out

    def describe(self) -> dict:
        """Duration, path length, peaks and the binding limit of a single timed motion."""
        if self.shape:
            raise ParameterError("describe() is for one timed motion")
        out = {
            "profile": self.profile.kind,
            "duration": self.duration,
            "constant_speed": self.constant_speed,
            "point": [float(v) for v in self.point],
            "path_length": self.path_length,
            "peaks": {k: float(v) for k, v in self.peaks().items()},
            "limits": {k: float(v) for k, v in self.limits.items()},
            "binding": self.binding,
        }
        return out


def _gains(motion, point, constant_speed: bool, lengths) -> tuple[np.ndarray, np.ndarray]:
    """The largest ``|dx/dσ|`` and ``|ω|`` per unit σ over the path, on a grid of t."""
    total = None if lengths is None else lengths[0]
    return _in_blocks(motion, lambda m, length: _gains_of(m, point, constant_speed, length), total)


def _gains_of(motion, point, constant_speed: bool, total) -> tuple[np.ndarray, np.ndarray]:
    ts = np.linspace(0.0, 1.0, 257)
    stack = motion.derivatives(ts, 1)
    speed = np.linalg.norm(point_derivatives(stack, point)[..., 1, :, :], axis=-1)
    turn = np.linalg.norm(_angular(stack, 1), axis=-1)
    if constant_speed:
        length = np.asarray(total)[..., None]
        with np.errstate(divide="ignore", invalid="ignore"):
            turn = np.where(speed > 0, turn * length / speed, np.inf)
        speed = np.broadcast_to(length, speed.shape)
    return speed.max(axis=-1), turn.max(axis=-1)


def timing(
    motion,
    profile: str | None = None,
    *,
    duration=None,
    max_speed=None,
    max_accel=None,
    max_jerk=None,
    max_angular_speed=None,
    max_angular_accel=None,
    point=None,
    constant_speed: bool = False,
) -> TimedMotion:
    """Time ``motion`` (a :class:`~a2b.motions.base.Motion` of any shape, or a Bézier motion or
    spline) by a law ``profile`` under limits and/or a ``duration``: see the module.

    ``profile``: ``linear``, ``trapezoid``, ``jerk-limited`` or ``quintic``; by default
    ``jerk-limited`` with ``max_jerk``, else ``trapezoid`` with an acceleration limit, else
    ``linear``. Limits are positive numbers (broadcast against the motions); ``point`` is the
    body point ``(x, y, z)`` in the moving frame whose speed is limited (the origin by
    default). Returns a :class:`TimedMotion`.

    Raises
    ------
    ParameterError
        If no duration or limit is given, the profile cannot meet a limit given (``linear`` has
        no acceleration bound, ``trapezoid`` no jerk bound), a limit is not a positive number,
        or ``duration`` is shorter than the limits allow.
    """
    shape = motion.shape if hasattr(motion, "table") else ()
    point = check_point(point)
    limits = _limit_values(
        {
            "speed": max_speed,
            "accel": max_accel,
            "jerk": max_jerk,
            "angular_speed": max_angular_speed,
            "angular_accel": max_angular_accel,
        },
        shape,
    )
    if profile is None:
        profile = (
            "jerk-limited"
            if "jerk" in limits
            else "trapezoid"
            if {"accel", "angular_accel"} & set(limits)
            else "linear"
        )
    if profile not in PROFILES:
        raise ParameterError(f"profile must be one of {', '.join(PROFILES)}, got {profile!r}")
    if profile == "linear" and {"accel", "jerk", "angular_accel"} & set(limits):
        raise ParameterError(
            "the linear law starts and stops at once (unbounded acceleration); with an "
            "acceleration or jerk limit use the trapezoid, jerk-limited or quintic profile"
        )
    if profile == "trapezoid" and "jerk" in limits:
        raise ParameterError(
            "the trapezoid changes its acceleration at once (unbounded jerk); with --max-jerk "
            "use the jerk-limited or quintic profile"
        )
    if duration is not None:
        duration = np.broadcast_to(np.asarray(duration, dtype=float), shape)
        refuse(
            ParameterError,
            ~(duration > 0) | ~np.isfinite(duration),
            lambda i: f"the duration must be a positive number, got {value(duration, i):g}",
            shape,
        )
    if not limits and duration is None:
        raise ParameterError("a time law needs a duration or at least one limit")
    linear_only = not ({"angular_speed", "angular_accel"} & set(limits))
    lengths = None
    if constant_speed or (limits.keys() & set(LINEAR)):
        lengths = arc_lengths(motion, point)
        if constant_speed:
            refuse(
                ParameterError,
                ~(lengths[0] > 0),
                lambda i: (
                    "the point does not move: it has no constant speed to keep; choose "
                    "another --point"
                ),
                shape,
            )
    timed = TimedMotion(motion, None, point, constant_speed, limits, lengths)
    if not limits:
        timed.profile = shaped(profile, duration)
        return timed
    exact = constant_speed and linear_only
    if exact:  # |dx/dσ| = L; the rotation is not limited
        along, turn = np.asarray(lengths[0]), np.zeros(shape)
    else:
        along, turn = _gains(motion, point, constant_speed, lengths)
    inf = np.full(shape, np.inf)
    with np.errstate(divide="ignore", invalid="ignore"):

        def bound(linear, angular):
            out = inf
            if linear in limits:
                out = np.minimum(out, np.where(along > 0, limits[linear] / along, np.inf))
            if angular in limits:
                out = np.minimum(out, np.where(turn > 0, limits[angular] / turn, np.inf))
            return out

        speed, accel, jerk = (
            bound("speed", "angular_speed"),
            bound("accel", "angular_accel"),
            bound("jerk", None),
        )
    needs = {"linear": speed, "trapezoid": accel, "jerk-limited": jerk}
    needs["quintic"] = np.minimum.reduce([speed, accel, jerk])
    missing = ~np.isfinite(needs[profile])
    if missing.any():
        what = {
            "linear": "a speed limit",
            "trapezoid": "an acceleration limit",
            "jerk-limited": "a jerk limit",
            "quintic": "a limit",
        }[profile]
        raise ParameterError(
            f"the {profile} profile needs {what} or a duration (the limits given do not bound "
            "this motion: its point or its rotation does not move)"
        )
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        timed.profile = build(profile, speed, accel, jerk)
    if exact:
        ratios = {}
        base_peaks = _profile_peaks(timed.profile, np.asarray(lengths[0]))
        for name in limits:
            ratios[name] = (base_peaks[name] / limits[name]) ** (1.0 / LIMITS[name])
    else:
        found = timed.peaks(list(limits))
        ratios = {n: (np.asarray(found[n]) / limits[n]) ** (1.0 / LIMITS[n]) for n in limits}
    names = list(ratios)
    stacked = np.stack([np.broadcast_to(ratios[n], shape) for n in names], axis=-1)
    factor = stacked.max(axis=-1)
    binding = np.array(names, dtype=object)[np.argmax(stacked, axis=-1)]
    if not exact:
        timed.profile = timed.profile.scaled(factor)
    if duration is not None:
        shortest = timed.profile.duration
        refuse(
            ParameterError,
            duration < shortest * (1 - 1e-12),
            lambda i: (
                f"the limits need at least {value(shortest, i):.9g} s; the duration "
                f"{value(duration, i):.9g} s is shorter"
            ),
            shape,
        )
        timed.profile = timed.profile.scaled(duration / shortest)
        binding = np.where(duration > shortest * (1 + 1e-12), "duration", binding)
    timed.binding = binding if shape else str(binding)
    return timed


def _profile_peaks(profile: Profile, length: np.ndarray) -> dict:
    """Peaks of ``L σ̇``, ``L σ̈``, ``L σ⃛`` of a law built from limits (closed forms)."""
    coefficients = profile.coefficients
    lengths = np.diff(profile.starts, axis=-1)
    speed = np.max(
        np.abs(
            coefficients[..., 1]
            + 2 * coefficients[..., 2] * lengths
            + 3 * coefficients[..., 3] * lengths**2
        ),
        axis=-1,
    )
    accel = np.max(np.abs(2 * coefficients[..., 2]), axis=-1)
    jerk = np.max(np.abs(6 * coefficients[..., 3]), axis=-1)
    if profile.kind == "quintic":
        d = profile.duration
        speed, accel, jerk = (
            QUINTIC_PEAKS[0] / d,
            QUINTIC_PEAKS[1] / d**2,
            QUINTIC_PEAKS[2] / d**3,
        )
    return {"speed": length * speed, "accel": length * accel, "jerk": length * jerk}
