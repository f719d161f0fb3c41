"""The 1-D time laws ``σ(τ)`` of a2b: rest-to-rest profiles from 0 to 1, piecewise polynomials
in time, for a batch of motions at once (see :mod:`a2b.timing`)."""

from __future__ import annotations

import numpy as np

__all__ = ["PROFILES", "Profile", "build", "jerk_limited", "quintic", "shaped", "trapezoid"]

PROFILES = ("linear", "trapezoid", "jerk-limited", "quintic")


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
    jerk (``(P,) + S`` each, phases first), integrated from rest at 0.

    The arrays are component-major (a coefficient of a phase is one contiguous row over the
    motions, written once); the profile's ``S + (P, 6)`` and ``S + (P + 1,)`` are views."""
    phases, shape = durations.shape[0], durations.shape[1:]
    position = np.zeros(shape)
    speed = np.zeros(shape)
    coefficients = np.zeros((6, phases) + shape)
    for k in range(phases):
        d, a, j = durations[k], accels[k], jerks[k]
        for row, part in enumerate((position, speed, a / 2, j / 6)):
            coefficients[row, k] = part
        position = position + d * (speed + d * (a / 2 + d * j / 6))
        speed = speed + d * (a + d * j / 2)
    starts = np.zeros((phases + 1,) + shape)
    starts[1] = durations[0]
    for k in range(1, phases):  # the running sum, row by row (cumsum down axis 0 is slow)
        starts[k + 1] = starts[k] + durations[k]
    return Profile(kind, np.moveaxis(starts, 0, -1), np.moveaxis(coefficients, (0, 1), (-1, -2)))


def trapezoid(speed, accel) -> Profile:
    """The fastest law from 0 to 1 with ``|σ̇| ≤ speed`` and ``|σ̈| ≤ accel`` (``inf``: none)."""
    speed, accel = np.broadcast_arrays(np.asarray(speed, float), np.asarray(accel, float))
    with np.errstate(divide="ignore", invalid="ignore"):
        cruising = speed * speed <= accel  # the speed limit is reached within the distance 1
        t_accel = np.where(cruising, speed / accel, np.sqrt(1.0 / accel))
        t_cruise = np.where(cruising, 1.0 / speed - speed / accel, 0.0)
    durations = np.stack([t_accel, t_cruise, t_accel])
    accels = np.stack([accel, np.zeros_like(accel), -accel])
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
    durations = np.stack([t_j, t_a, t_j, t_v, t_j, t_a, t_j])
    accels = np.stack([zero, a_p, a_p, zero, zero, -a_p, -a_p])
    jerks = np.stack([j, zero, -j, zero, -j, zero, j])
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
