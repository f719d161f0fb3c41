"""A motion under a time law: :class:`TimedMotion` and :func:`timing` (see :mod:`a2b.timing`)."""

from __future__ import annotations

import numpy as np

from ..elements import refuse, value
from ..errors import ParameterError
from ..kinematics import _angular, check_point, path_rates, point_derivatives, reparametrise
from ..kinematics import accelerations as _accelerations
from ..kinematics import twists as _twists
from ..study import dots
from .arclength import arc_lengths, invert_arc_length, lengths_at
from .grid import TimeGrid
from .profiles import PROFILES, QUINTIC_PEAKS, Profile, _profile_peaks, build, shaped

__all__ = ["LIMITS", "TimedMotion", "timing"]

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

#: Peak search: grid points per phase, values of t evenly spaced whose times are candidates
#: too, and bracketing steps.
GRID = 65
PATH_GRID = 257
STEPS = 40
CANDIDATES = 6
#: The usable range of every limit and of a duration, in its units: beyond it a law's powers
#: of time (up to the fifth) overflow or underflow double precision.
USABLE = (1e-30, 1e30)
#: The most times :meth:`TimedMotion.times` returns in one array (128 MB).
MOST_IN_MEMORY = 1 << 24
#: The largest rotation per unit σ (rad) that is rounding: a rotation that does not move.
STILL_TURN = 1e-12
#: Motions evaluated together (bounds memory: a block of derivative stacks is ~70 MB).
BLOCK = 1024


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


def _limit_values(limits: dict, shape: tuple) -> dict:
    out = {}
    for name, given in limits.items():
        if name not in LIMITS:
            raise ParameterError(f"unknown limit {name!r}; expected one of {', '.join(LIMITS)}")
        if given is not None:
            out[name] = _in_range(given, _limit_words(name), UNITS[name], shape)
    return out


def _in_range(given, words: str, unit: str, shape: tuple) -> np.ndarray:
    """``given`` broadcast to ``shape``, refused unless every element lies in
    :data:`USABLE` (beyond it the laws overflow or underflow double precision)."""
    arr = np.broadcast_to(np.asarray(given, dtype=float), shape)
    low, high = USABLE
    refuse(
        ParameterError,
        ~((arr >= low) & (arr <= high)),
        lambda i: (
            f"the {words} is {value(arr, i):.6g} {unit}; usable values run from {low:g} to "
            f"{high:g} {unit}"
        ),
        shape,
    )
    return arr


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

    def grid(self, rate=None, dt=None, samples=None, origin: float = 0.0) -> TimeGrid:
        """The times to sample, from 0 to the duration: every ``dt`` (or ``1 / rate``) seconds
        and the end, or ``samples`` evenly spaced, as a :class:`~a2b.timelaw.grid.TimeGrid` whose
        offset 0 is at ``origin`` seconds. A single motion only (a batch has a duration per
        motion)."""
        if self.shape:
            raise ParameterError("times() is for one motion; give each motion its own times")
        return TimeGrid.covering(
            float(self.profile.duration), rate=rate, dt=dt, samples=samples, origin=origin
        )

    def times(self, rate=None, dt=None, samples=None) -> np.ndarray:
        """The offsets of :meth:`grid` as one array, at most :data:`MOST_IN_MEMORY` (for plots:
        a writer takes the grid's blocks, in bounded memory, for any count)."""
        grid = self.grid(rate, dt, samples)
        if grid.count > MOST_IN_MEMORY:
            raise ParameterError(
                f"{grid.count} times of {self.duration:.9g} s every {grid.step:.3g} s are more "
                f"than times() holds in memory ({MOST_IN_MEMORY}); take grid() block by block"
            )
        return grid.offsets(0, grid.count)

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
        g1 = dots(d1, d2) / g
        g2 = (dots(d2, d2) + dots(d1, d3) - g1 * g1) / g
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
        """The limited rates at ``times``, ``S + (N,)`` each (:func:`a2b.kinematics.path_rates`).

        At rest (``τ = 0`` and ``τ = T``) the point's velocity is zero and gives ``s̈`` and
        ``s⃛`` no sign; there they are the law's: ``s̈ = g σ̈`` and ``s⃛ = g σ⃛``, with ``g`` the
        point's speed per unit ``σ`` (``σ̇ = 0``, so the terms in ``σ̇`` vanish)."""
        arr = self._check_times(times)
        law = self.profile.values(arr)
        t, stack = self._stack_at(law, 3)
        out = path_rates(stack, self.point)
        rest = (arr <= 0) | (arr >= np.asarray(self.profile.duration)[..., None])
        if rest.any():
            if self.constant_speed:
                gain = np.broadcast_to(np.asarray(self._lengths[0])[..., None], t.shape)
            else:
                gain = self.motion.point_speeds(t, self.point)
            out["accel"] = np.where(rest, gain * law[..., 2], out["accel"])
            out["jerk"] = np.where(rest, gain * law[..., 3], out["jerk"])
        return out

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
    spline) by a law ``profile`` under limits and/or a ``duration``: see :mod:`a2b.timing`.

    ``profile``: ``linear``, ``trapezoid``, ``jerk-limited`` or ``quintic``; by default
    ``jerk-limited`` with ``max_jerk``, else ``trapezoid`` with an acceleration limit, else
    ``quintic`` with a speed limit (every default with a limit is at rest at both ends), and
    ``linear`` with a duration alone (evenly in t, as without a law). Limits are positive
    numbers from 1e-30 to 1e30 (broadcast against the motions); ``point`` is the body point
    ``(x, y, z)`` in the moving frame whose speed is limited (the origin by default). With a
    ``duration``, a profile that the limits do not determine (a trapezoid with only a speed
    limit) takes its fixed shape over that duration, and the limits are checks. Returns a
    :class:`TimedMotion`.

    Raises
    ------
    ParameterError
        If no duration or limit is given, the profile cannot meet a limit given (``linear`` has
        no acceleration bound, ``trapezoid`` no jerk bound), a limit or the duration is not a
        number from 1e-30 to 1e30, ``duration`` is shorter than the limits allow, the limits
        do not bound a motion and no duration is given, or ``constant_speed`` is asked of a
        point that does not move.
    """
    shape = motion.shape if hasattr(motion, "table") else ()
    point = check_point(point)
    given = {
        "speed": max_speed,
        "accel": max_accel,
        "jerk": max_jerk,
        "angular_speed": max_angular_speed,
        "angular_accel": max_angular_accel,
    }
    limits = _limit_values(given, shape)
    profile = _profile_for(profile, limits)
    if duration is not None:
        duration = _in_range(duration, "duration (--duration)", "s", shape)
    if not limits and duration is None:
        raise ParameterError("a time law needs a duration or at least one limit")
    lengths = None
    if constant_speed or (limits.keys() & set(LINEAR)):
        lengths = arc_lengths(motion, point)
        if constant_speed:
            refuse(
                ParameterError,
                ~(lengths[0] > 0),
                lambda i: (
                    "the point does not move (its path length is 0 to rounding): it has no "
                    "constant speed to keep; choose another --point"
                ),
                shape,
            )
    timed = TimedMotion(motion, None, point, constant_speed, limits, lengths)
    if not limits:
        timed.profile = shaped(profile, duration)
        return timed
    exact = constant_speed and not ({"angular_speed", "angular_accel"} & set(limits))
    bounds = _sigma_limits(motion, timed, exact, shape)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        timed.profile = build(profile, *_fill(profile, bounds, duration))
    factor, binding = _slowest(timed, exact, shape)
    if not exact:
        timed.profile = timed.profile.scaled(factor)
    if duration is not None:
        binding = _stretch(timed, duration, binding, shape)
    _check_finite_law(timed, shape)
    timed.binding = binding if shape else str(binding)
    return timed


def _profile_for(profile: str | None, limits: dict) -> str:
    """The profile asked for, or the default for ``limits`` (see :func:`timing`)."""
    if profile is None:
        profile = (
            "jerk-limited"
            if "jerk" in limits
            else "trapezoid"
            if {"accel", "angular_accel"} & set(limits)
            else "quintic"
            if limits
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
    return profile


def _sigma_limits(motion, timed: TimedMotion, exact: bool, shape: tuple) -> tuple:
    """The limits turned into limits on ``σ̇, σ̈, σ⃛`` through the largest rates of the path per
    unit ``σ`` (``inf`` where none applies, or where the limited quantity does not move)."""
    limits, lengths = timed.limits, timed._lengths
    if exact:  # |dx/dσ| = L; the rotation is not limited
        along, turn = np.asarray(lengths[0]), np.zeros(shape)
    else:
        along, turn = _gains(motion, timed.point, timed.constant_speed, lengths)
        # what does not move to rounding does not bound the law (a pose to itself)
        turn = np.where(turn > STILL_TURN, turn, 0.0)
        if lengths is not None:
            along = np.where(np.asarray(lengths[0]) > 0, along, 0.0)
    inf = np.full(shape, np.inf)
    with np.errstate(divide="ignore", invalid="ignore"):

        def bound(linear, angular):
            out = inf
            if linear in limits:
                out = np.minimum(out, np.where(along > 0, limits[linear] / along, np.inf))
            if angular in limits:
                out = np.minimum(out, np.where(turn > 0, limits[angular] / turn, np.inf))
            return out

        return bound("speed", "angular_speed"), bound("accel", "angular_accel"), bound("jerk", None)


#: What each profile needs of the limits on ``σ̇, σ̈, σ⃛`` to be determined, in words.
NEEDS = {
    "linear": "a speed limit",
    "trapezoid": "an acceleration limit",
    "jerk-limited": "a jerk limit",
    "quintic": "a limit",
}


def _fill(profile: str, bounds: tuple, duration) -> tuple:
    """``σ̇, σ̈, σ⃛`` limits that determine ``profile``: where those given do not (a trapezoid
    with only a speed limit), the profile's fixed shape over ``duration`` (:func:`shaped`),
    whose peaks the limits then check; without a duration that is an error."""
    speed, accel, jerk = bounds
    need = {"linear": speed, "trapezoid": accel, "jerk-limited": jerk}.get(
        profile, np.minimum.reduce([speed, accel, jerk])
    )
    missing = ~np.isfinite(need)
    if not missing.any():
        return bounds
    if duration is None:
        raise ParameterError(
            f"the {profile} profile needs {NEEDS[profile]} or a duration (the limits given do "
            "not bound this motion: its point or its rotation does not move)"
        )
    d, inf = np.broadcast_to(duration, missing.shape), np.inf
    fixed = {  # the limits that build shaped(profile, d)
        "linear": (1.0 / d, inf, inf),
        "trapezoid": (1.5 / d, 4.5 / d**2, inf),
        "jerk-limited": (1.5 / d, inf, 54.0 / d**3),
        "quintic": (QUINTIC_PEAKS[0] / d, inf, inf),
    }[profile]
    return tuple(np.where(missing, f, b) for f, b in zip(fixed, bounds))


def _slowest(timed: TimedMotion, exact: bool, shape: tuple) -> tuple:
    """The factor ``c = max (peak / limit)^(1/k)`` by which time must stretch for every limit
    to hold (the tightest reached), and the name of that limit, per motion."""
    limits = timed.limits
    if exact:
        found = _profile_peaks(timed.profile, np.asarray(timed._lengths[0]))
    else:
        found = timed.peaks(list(limits))
    ratios = {n: (np.asarray(found[n]) / limits[n]) ** (1.0 / LIMITS[n]) for n in limits}
    names = list(ratios)
    stacked = np.stack([np.broadcast_to(ratios[n], shape) for n in names], axis=-1)
    factor = stacked.max(axis=-1)
    binding = np.array(names, dtype=object)[np.argmax(stacked, axis=-1)]
    # 0 where nothing limited moves: a law of fixed shape over a duration (see _fill) stays
    moves = factor > 0
    return np.where(moves, factor, 1.0), np.where(moves, binding, "duration")


def _stretch(timed: TimedMotion, duration, binding, shape: tuple):
    """Slow the law uniformly to ``duration`` (an error where the limits need longer); the
    binding becomes ``duration`` where it is longer than the limits need."""
    shortest = timed.profile.duration
    name = np.broadcast_to(binding, shape)
    refuse(
        ParameterError,
        duration < shortest * (1 - 1e-12),
        lambda i: (
            f"the {_limit_words(name.flat[i])} needs at least "
            f"{value(shortest, i):.9g} s; the duration {value(duration, i):.9g} s is shorter"
        ),
        shape,
    )
    timed.profile = timed.profile.scaled(duration / shortest)
    return np.where(duration > shortest * (1 + 1e-12), "duration", binding)


def _limit_words(name: str) -> str:
    """A limit in words, with its keyword and its option: ``acceleration limit (max_accel,
    --max-accel)``."""
    words = name.replace("_", " ").replace("accel", "acceleration")
    return f"{words} limit (max_{name}, --max-{name.replace('_', '-')})"


def _check_finite_law(timed: TimedMotion, shape: tuple) -> None:
    """Refuse a law that overflowed double precision on the way (extreme limits and paths)."""
    profile = timed.profile
    bad = ~np.isfinite(profile.coefficients).all(axis=(-2, -1)) | ~np.isfinite(profile.starts).all(
        axis=-1
    )
    bad |= ~(profile.duration > 0)
    refuse(
        ParameterError,
        bad,
        lambda i: (
            f"the time law overflows double precision (its duration is "
            f"{value(profile.duration, i):.3g} s): the limits are too extreme for this path"
        ),
        shape,
    )
