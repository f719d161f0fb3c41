"""The time grid: times every ``step`` seconds from an origin in integer nanoseconds.

Times are never accumulated. The ``i``-th time is the offset ``i · step`` from the origin,
computed for each block of indices at once, so no loop can stall however far the grid
reaches, and memory stays bounded for any count. Where the step is a whole number of
nanoseconds (``--rate 200``: 5,000,000 ns; ``--dt 0.001``) offsets are computed in integers
first, so stamps are exact: ``origin_ns + i · step_ns``.

How a writer uses a grid::

    grid = TimeGrid.covering(duration, rate=200.0, origin=start_time)
    for lo, offsets in grid.blocks(65536):    # float64 seconds from the origin
        stamps = grid.stamps_ns(np.arange(lo, lo + len(offsets)))  # int64 ns, exact
        ...                                   # sample at offsets, stamp with stamps

``grid.count`` is known before the first block: a writer refuses what its format cannot hold
(more than 2**32 MCAP messages, stamps beyond 2**63 ns) before it writes a byte.
"""

from __future__ import annotations

from collections.abc import Iterator
from decimal import Decimal

import numpy as np

from ..errors import ParameterError

__all__ = ["MOST_TIMES", "TimeGrid", "nanoseconds"]

#: The most times a grid holds: beyond 2**53 a double no longer tells the indices apart.
MOST_TIMES = 1 << 53
#: The latest offset in integer nanoseconds (int64).
MOST_NANOSECONDS = (1 << 63) - 1
#: A step is a whole number of nanoseconds if it is one to this relative rounding.
WHOLE = 4 * np.finfo(float).eps


def nanoseconds(seconds: float) -> int:
    """``seconds`` in integer nanoseconds, from its shortest decimal form (what the user
    wrote): ``1700000000.123`` is ``1700000000123000000``, not the double's binary value."""
    seconds = float(seconds)
    if not np.isfinite(seconds):
        raise ParameterError(f"a time must be a finite number of seconds, got {seconds}")
    return int(Decimal(repr(seconds)).scaleb(9).to_integral_value())


def _whole_ns(step: float) -> int | None:
    """``step`` (seconds) in whole nanoseconds, or ``None`` if it is no whole number of them."""
    ns = step * 1e9
    whole = round(ns) if np.isfinite(ns) and ns < MOST_NANOSECONDS else 0
    return whole if whole >= 1 and abs(ns - whole) <= WHOLE * ns else None


class TimeGrid:
    """``count`` times ``i · step`` seconds after an origin of ``origin_ns`` nanoseconds, the
    last exactly ``end`` (seconds after the origin) when given.

    Build it with :meth:`covering` (from 0 to a duration, as a time law is sampled) or
    :meth:`at_rate` (an open-ended grid, as ``a2b resample --rate`` samples a trajectory).
    """

    def __init__(
        self, origin_ns: int, step: float, count: int, end: float | None = None, rate=None
    ):
        if not (np.isfinite(step) and step > 0):
            raise ParameterError(f"the time step must be a positive number, got {step:g} s")
        if not 1 <= count <= MOST_TIMES:
            raise ParameterError(
                f"a time grid holds 1 to 2**53 times (what a double can count), got {count:.4g}"
            )
        self.origin_ns = int(origin_ns)
        self.step = float(step)
        self.count = int(count)
        self.end = None if end is None else float(end)
        #: The step in whole nanoseconds, where it is one (then stamps are exact).
        self.step_ns = _whole_ns(self.step)
        #: The rate the step came from, if any: offsets are then ``i / rate``, correctly
        #: rounded (``i · (1 / rate)`` can be an ulp off).
        self.rate = None if rate is None else float(rate)

    @classmethod
    def covering(cls, duration: float, *, rate=None, dt=None, samples=None, origin: float = 0.0):
        """Times from 0 to ``duration`` s: every ``dt`` (or ``1 / rate``) s and the end, or
        ``samples`` evenly spaced. ``origin`` (seconds) is the time of offset 0.

        Raises
        ------
        ParameterError
            If the step is not a positive number, or the grid would hold more than 2**53
            times (the count is named with the duration and the step).
        """
        duration = float(duration)
        if not (np.isfinite(duration) and duration > 0):
            raise ParameterError(f"the duration must be a positive number, got {duration:g} s")
        if samples is not None:
            if not 2 <= samples <= MOST_TIMES:
                raise ParameterError(f"give 2 to 2**53 samples, got {samples}")
            return cls(nanoseconds(origin), duration / (samples - 1), int(samples), duration)
        if rate is None and dt is None:
            raise ParameterError("give a rate, a time step or a number of samples")
        rate = None if dt is not None else float(rate)
        step = float(dt) if dt is not None else 1.0 / rate
        if not (np.isfinite(step) and step > 0):
            raise ParameterError(f"the time step must be a positive number, got {step:g} s")
        steps = duration / step
        if not steps < MOST_TIMES - 1:
            raise ParameterError(
                f"sampling {duration:.9g} s every {step:.3g} s takes {steps:.3g} times, more "
                "than 2**53 (what a double can count); give a lower --rate or a larger --dt"
            )
        # a time within a billionth of a step of the end is the end; else the end is added
        whole = int(np.floor(steps + 1e-9))
        count = whole + 1 + (steps - whole > 1e-9)
        return cls(nanoseconds(origin), step, count, duration, rate)

    @classmethod
    def at_rate(cls, rate: float, origin: float) -> TimeGrid:
        """An open-ended grid every ``1 / rate`` s from ``origin`` s: :meth:`upto` says how
        many of its times lie up to a time."""
        return cls(nanoseconds(origin), 1.0 / rate, MOST_TIMES, None, rate)

    def offsets(self, lo: int, hi: int) -> np.ndarray:
        """The offsets in seconds of times ``lo`` to ``hi`` (``hi`` excluded), float64."""
        hi = min(hi, self.count)
        i = np.arange(lo, hi, dtype=np.int64)
        if self.step_ns is not None and hi * self.step_ns <= MOST_NANOSECONDS:
            out = (i * self.step_ns) / 1e9
        elif self.rate is not None:
            out = i / self.rate
        else:
            out = i * self.step
        if self.end is not None and hi == self.count and hi > lo:
            out[-1] = self.end
        return out

    def blocks(self, size: int) -> Iterator[tuple[int, np.ndarray]]:
        """``(lo, offsets)`` for every block of ``size`` times, in order: at most ``size``
        times in memory at once."""
        for lo in range(0, self.count, size):
            yield lo, self.offsets(lo, lo + size)

    def stamps_ns(self, index) -> np.ndarray:
        """The times of the grid's indices ``index`` (ints) as int64 nanoseconds: ``origin_ns``
        + the offset, exact when the step is a whole number of nanoseconds, else the offset
        rounded.

        Raises
        ------
        ParameterError
            If a stamp would be 2**63 ns or later (the year 2262 after the epoch).
        """
        index = np.asarray(index, dtype=np.int64)
        if not index.size:
            return np.zeros(0, dtype=np.int64)
        top = int(index.max())
        last = self.end if self.end is not None and top == self.count - 1 else top * self.step
        if not self.origin_ns + last * 1e9 < MOST_NANOSECONDS * (1 - 1e-9):
            raise ParameterError(
                f"time stamps are nanoseconds below 2**63 (the year 2262); the time "
                f"{self.origin_ns / 1e9 + last:.9g} s is later"
            )
        if self.step_ns is not None:
            out = index * self.step_ns
        else:
            out = np.rint(index * (self.step * 1e9)).astype(np.int64)
        if self.end is not None:
            out[index == self.count - 1] = round(self.end * 1e9)
        return self.origin_ns + out

    def index(self, times, start: float) -> np.ndarray:
        """The grid's indices of ``times`` (seconds, each ``start`` + an offset of the grid, as
        :meth:`upto` counts them): int64."""
        return np.rint((np.asarray(times, dtype=float) - start) / self.step).astype(np.int64)

    def upto(self, limit: float, start: float = 0.0) -> int:
        """How many times ``start + offset`` (seconds, in doubles) of the grid are at most
        ``limit``: arithmetic, with the three candidates around the quotient checked, so no
        loop runs however far the grid reaches.

        Raises
        ------
        ParameterError
            If that is more than 2**53 times.
        """
        guess = np.floor((limit - start) / self.step)
        if guess < 0:
            return 0
        if not guess < self.count - 2:
            raise ParameterError(
                f"{limit - start:.4g} s at a step of {self.step:.3g} s are {guess + 1:.3g} "
                "times, more than 2**53 (what a double can count)"
            )
        first = max(int(guess) - 1, 0)
        near = start + self.offsets(first, first + 3)
        return first + int(np.count_nonzero(near <= limit))
