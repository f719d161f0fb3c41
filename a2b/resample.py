"""A trajectory at new times: one motion per segment between neighbouring poses, or a spline.

A trajectory is poses ``P_0 … P_{n−1}`` at increasing times ``T_0 < … < T_{n−1}``. A time
``τ`` in ``[T_k, T_{k+1}]`` is the parameter ``u = (τ − T_k) / (T_{k+1} − T_k)`` of segment
``k``: the two-pose motion of the chosen mode from ``P_k`` to ``P_{k+1}`` (``screw``, the
default, is ScLERP), or the C¹ spline through all poses (``spline``: Catmull–Rom in the space of
unit Study vectors, pose ``j`` at spline parameter ``j / (n − 1)``, each segment mapped linearly
onto its time interval). A time equal to a stamp returns that pose exactly, as it was read.

The segments a block of new times needs are built together, as one batch of the vectorised
core, so a million segments cost one call per block.
"""

from __future__ import annotations

import warnings
from collections import Counter
from collections.abc import Iterable, Iterator
from dataclasses import dataclass

import numpy as np

from .elements import as_numbers
from .errors import A2bError, A2bWarning, ParameterError
from .names import MODES

__all__ = ["RESAMPLE_MODES", "Located", "NewTimes", "Resampler", "resample", "unshown", "windows"]

RESAMPLE_MODES = MODES + ("spline",)
#: New times sampled at a time.
BLOCK = 65536
#: Warnings about segments issued in one run; the rest are counted (:attr:`Resampler.warned`).
WARNINGS_SHOWN = 10


@dataclass
class Located:
    """Where new times fall: the kept ``times (M,)``, their ``segment`` ``k`` and parameter
    ``u`` in it, ``pose`` (the index of the stamp a time equals, else −1), and how many times
    were dropped ``outside`` the trajectory (with ``clip``) or inside a ``gap``."""

    times: np.ndarray
    segment: np.ndarray
    u: np.ndarray
    pose: np.ndarray
    outside: int = 0
    gap: int = 0


class Resampler:
    """Sample a trajectory (``times (n,)`` increasing, robotics ``poses (n, 4, 4)``) at new times.

    ``quat_wxyz`` and ``study``, when given, are the poses as the file holds them: a time
    equal to a stamp returns them bit for bit, and the quaternions of a segment take the sign
    of the one at its start. Instead of ``poses``, ``quat_wxyz`` (any non-zero scale) and
    ``translations (n, 3)`` may be given: the matrices are then made for the segments in use.
    ``max_gap``: segments longer than this many seconds are not bridged; times strictly
    inside them are dropped. ``checked``: the poses were validated already (by
    :func:`a2b.io.trajectories.read_trajectory`). ``first``: the number of the first pose in
    a longer trajectory, of which these are a window (messages name poses by their number in
    it). ``parameters`` go to every segment's motion
    (:func:`a2b.motion`) or, for ``spline``, to :func:`a2b.motions.bezier.spline_motion`
    (``space``, default ``study``, and ``m``).
    """

    def __init__(
        self,
        times,
        poses=None,
        mode: str = "screw",
        *,
        max_gap: float | None = None,
        quat_wxyz=None,
        translations=None,
        study=None,
        checked: bool = False,
        first: int = 0,
        **parameters,
    ):
        from .poses import check_matrices, check_quaternions

        if mode not in RESAMPLE_MODES:
            raise ParameterError(
                f"unknown mode {mode!r}; expected one of {', '.join(RESAMPLE_MODES)}"
            )
        self.times = as_numbers(times, "times")
        n = len(self.times)
        self.quat_wxyz = None if quat_wxyz is None else np.asarray(quat_wxyz, dtype=float)
        self.translations = None
        if poses is not None:
            self.poses = np.asarray(poses, dtype=float) if checked else check_matrices(poses)
            shape = self.poses.shape
        elif quat_wxyz is not None and translations is not None:  # matrices made as needed
            self.poses = None
            self.translations = np.asarray(translations, dtype=float)
            if not checked:
                check_quaternions(self.quat_wxyz)
            shape = self.quat_wxyz.shape[:1] + (4, 4)
            if self.translations.shape != (len(self.quat_wxyz), 3):
                shape = self.translations.shape
        else:
            raise ParameterError("give the poses, or their quat_wxyz and translations")
        if self.times.ndim != 1 or shape != (n, 4, 4):
            raise ParameterError(
                f"times {self.times.shape} and poses {shape} need shapes (n,) and (n, 4, 4)"
            )
        if n < 2:
            raise ParameterError(f"a trajectory to resample needs at least 2 poses, got {n}")
        steps = np.diff(self.times)
        if not (np.isfinite(self.times).all() and (steps > 0).all()):
            i = int(np.argmax(~(steps > 0))) + 1 if not (steps > 0).all() else 0
            raise ParameterError(
                f"the trajectory's times must be finite and increase; time {i} is "
                f"{float(self.times[i])!r} after {float(self.times[max(i - 1, 0)])!r}"
            )
        if max_gap is not None and not max_gap > 0:
            raise ParameterError(f"max_gap must be greater than 0, got {max_gap!r}")
        if mode != "spline":
            from .parameters import OF_MODE

            unknown = sorted(set(parameters) - set(OF_MODE[mode]))
            if unknown:
                raise ParameterError(
                    f"mode {mode} does not take {', '.join(unknown)} (its parameters: "
                    f"{', '.join(OF_MODE[mode]) or 'none'})"
                )
        self.mode = mode
        self.max_gap = max_gap
        self.first = first
        self.study = None if study is None else np.asarray(study, dtype=float)
        self.parameters = parameters
        self.choices: Counter = Counter()
        self.segments_built = 0
        #: Which segments a block has built already: a segment whose new times fall in two
        #: blocks is built in both, but counted, and its choices and warnings stated, once.
        self._built = np.zeros(max(n - 1, 0), dtype=bool)
        #: Segments warned about (the first :data:`WARNINGS_SHOWN` are issued).
        self.warned = 0
        self.spline = None
        if mode == "spline":
            from .motions.bezier import spline_motion

            space = parameters.pop("space", "study")
            self.spline = spline_motion(self._pose_matrices(slice(None)), space, **parameters)
            self.choices.update(self.spline.choices)

    # -- where the new times fall ------------------------------------------------------------
    def locate(self, new_times, clip: bool = False) -> Located:
        """The segment and parameter of each new time (finite, any order).

        Times outside ``[T_0, T_{n−1}]`` are an error, or with ``clip`` dropped and counted;
        times inside a segment longer than ``max_gap`` are dropped and counted.
        """
        t = self.times
        new = as_numbers(new_times, "new times")
        if new.ndim != 1 or not np.isfinite(new).all():
            raise ParameterError("the new times must be a 1-D array of finite numbers")
        inside = (new >= t[0]) & (new <= t[-1])
        outside = int(new.size - np.count_nonzero(inside))
        if outside and not clip:
            first = float(new[np.argmax(~inside)])
            raise ParameterError(
                f"the time {first!r} is outside the trajectory, which runs from {float(t[0])!r} "
                f"to {float(t[-1])!r}; a2b does not extrapolate (clip=True, --clip on the command "
                "line, drops such times and counts them)"
            )
        if outside:
            new = new[inside]
        k = _segments_of(t, new)
        np.clip(k, 0, len(t) - 2, out=k)
        before, after = t[k], t[1:][k]
        pose = np.where(new == before, k, -1)
        last = new == after  # only at the last stamp: side="right" puts a stamp at its start
        if last.any():
            pose[last] = k[last] + 1
        gap = 0
        if self.max_gap is not None:
            long = (after - before > self.max_gap) & (pose < 0)
            gap = int(np.count_nonzero(long))
            if gap:
                keep = ~long
                new, k, pose, before, after = (a[keep] for a in (new, k, pose, before, after))
        # 0 at a time equal to the segment's start, 1 at one equal to its end: exactly
        u = (new - before) / (after - before)
        return Located(new, k, u, pose, outside, gap)

    # -- the poses ---------------------------------------------------------------------------
    def sample(self, located: Located, representation: str = "matrices") -> np.ndarray | tuple:
        """The poses at located times: robotics ``matrices (M, 4, 4)``, ``quat_trans``
        (``(M, 4)`` w, x, y, z and ``(M, 3)``) or unit ``study (M, 8)``.

        Times are taken :data:`BLOCK` at a time: the segments of a block are built together,
        small enough to stay in cache. The segments are counted, and their warnings issued
        (:meth:`account`)."""
        values, built = self.sample_apart(located, representation)
        self.account(built, stacklevel=2)
        return values

    def sample_apart(self, located: Located, representation: str = "matrices"):
        """:meth:`sample`, without counting the segments or issuing their warnings: ``(values,
        built)``, where ``built`` goes to :meth:`account`. Blocks of times may be sampled so on
        several threads at once, and accounted for in their order."""
        if len(located.times) > BLOCK:
            parts = [
                self.sample_apart(
                    Located(*(a[lo : lo + BLOCK] for a in _arrays(located))), representation
                )
                for lo in range(0, len(located.times), BLOCK)
            ]
            built = [entry for _, entries in parts for entry in entries]
            if isinstance(parts[0][0], tuple):
                return tuple(np.concatenate(p) for p in zip(*(v for v, _ in parts))), built
            return np.concatenate([v for v, _ in parts]), built
        k, u, pose = located.segment, located.u, located.pose
        on_stamp = pose >= 0
        if on_stamp.all():  # (or no time at all)
            return self._own(pose, representation), []
        stamps = np.flatnonzero(on_stamp)
        if len(stamps) <= len(k) // 8:  # the usual case: a few on stamps
            # each sampled where the time before it between stamps is (its segment is built
            # anyway), then set to the stamp's own pose: cheaper than taking them apart
            if len(stamps):
                between = np.flatnonzero(~on_stamp)
                donor = between[np.maximum(np.searchsorted(between, stamps) - 1, 0)]
                k, u = k.copy(), u.copy()
                k[stamps], u[stamps] = k[donor], u[donor]
            values, places, built = self._evaluate(k, u, representation)
            values = _taken(values, places)
            if len(stamps):
                own = self._own(pose[stamps], representation)
                for out, given in zip(
                    *(v if isinstance(v, tuple) else (v,) for v in (values, own))
                ):
                    out[stamps] = given
            return values, built
        # many on stamps: the samples' rows taken, in the order of the times, from those of the
        # times between stamps followed by the poses of the times on stamps: one gather
        # (numpy's take copies whole rows, several times faster than assigning through a mask)
        between = ~on_stamp
        values, places, built = self._evaluate(k[between], u[between], representation)
        own = self._own(pose[on_stamp], representation)
        index = np.empty(len(k), dtype=np.intp)
        index[between] = _all(places, np.count_nonzero(between))
        index[on_stamp] = len(_first(values)) + np.arange(len(_first(own)))
        if isinstance(values, tuple):
            return _taken(tuple(map(np.concatenate, zip(values, own))), index), built
        return _taken(np.concatenate([values, own]), index), built

    def account(self, built: list, stacklevel: int = 1) -> None:
        """Count the segments that :meth:`sample_apart` built (``built``: what it returned, in
        the order of the blocks) and issue their warnings, naming the segment: a segment whose
        times fall in two blocks is counted, and warned about, once. The first
        :data:`WARNINGS_SHOWN` warnings of the resampler are issued, the rest counted
        (:attr:`warned`). ``stacklevel`` as for ``warnings.warn``, counted from the caller."""
        for rows, notes, warned in built:
            first = np.ones(len(rows), dtype=bool)  # the first row of each segment
            first[1:] = rows[1:] != rows[:-1]
            first &= ~self._built[rows]
            self._built[rows] = True
            for index, reason in _noted(warned):
                if first[index]:
                    self.warned += 1
                    if self.warned <= WARNINGS_SHOWN:
                        warnings.warn(
                            A2bWarning(f"{self._segment(rows[index])}: {reason}"),
                            stacklevel=stacklevel + 1,
                        )
            self.segments_built += int(np.count_nonzero(first))
            self.choices.update(notes.counts(first))

    def _own(self, index: np.ndarray, representation: str):
        """The poses ``index`` as read, in ``representation``."""
        if representation == "matrices":
            return self._pose_matrices(index)
        if representation == "study":
            return self._own_study(index)
        return self._own_quat_trans(index)

    def _start_quaternions(self, k: np.ndarray) -> np.ndarray:
        """The quaternions of the poses that start segments ``k``, as the file gives them."""
        return self.quat_wxyz[k] if self.quat_wxyz is not None else self._own_quat_trans(k)[0]

    def _evaluate(self, k: np.ndarray, u: np.ndarray, representation: str):
        """The poses at parameters ``u`` of segments ``k``, and where each is: ``(values,
        places)``, the pose of the ``i``-th parameter the row ``places[i]`` of ``values`` (an
        array or a tuple of arrays; ``places`` ``None``: row ``i``). Quaternions take the sign
        of the one at the start of their segment. And what :meth:`account` takes of the
        segments built."""
        if self.spline is not None:
            out = getattr(self.spline, representation)((k + u) / (len(self.times) - 1))
            if representation == "quat_trans":  # each sample against its segment's start
                quat = out[0]
                quat[np.einsum("ij,ij->i", quat, self._start_quaternions(k)) < 0] *= -1.0
            return out, None, []
        rows, ts, places = _rows(k, u)
        motion = self._segments(rows)
        out = getattr(motion, representation)(ts)
        if representation == "quat_trans":
            # a motion's quaternions are continuous from its p(0): one sign per segment, the
            # one that makes p(0) the file's quaternion of the start (not one per sample,
            # which rounding could flip where p(t) is at right angles to it)
            start = self._start_quaternions(rows)
            flip = np.einsum("ij,ij->i", motion.quat_ends[:, 0, :], start) < 0
            if flip.any():
                out[0][flip] *= -1.0
        built = [(rows, motion.notes, motion.warning_notes)]
        if isinstance(out, tuple):
            return tuple(o.reshape((-1,) + o.shape[2:]) for o in out), places, built
        return out.reshape((-1,) + out.shape[2:]), places, built

    def _own_quat_trans(self, index: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        from .poses import quat_trans_from_matrices

        if self.quat_wxyz is not None:
            trans = self.translations if self.poses is None else self.poses[:, :3, 3]
            return self.quat_wxyz[index], trans[index]
        return quat_trans_from_matrices(self.poses[index])

    def _own_study(self, index: np.ndarray) -> np.ndarray:
        from .poses import study_from_matrices

        if self.study is not None:
            return self.study[index]
        return study_from_matrices(self._pose_matrices(index))

    def _segments(self, rows: np.ndarray):
        """The motions of the segments ``rows`` (one per row, built in one batch), their
        warnings noted, not issued (:meth:`account` issues them)."""
        from .api import checked_motion
        from .elements import noted_only
        from .poses import quaternions_from_rotations

        lo, hi = int(rows[0]), int(rows[-1]) + 2
        quaternions = None
        if hi - lo <= 2 * len(rows) and np.all(rows[1:] >= rows[:-1]):
            # segments in order (the usual case): each pose made once, and its quaternion
            # found once, for both its segments
            poses = self._pose_matrices(slice(lo, hi))
            quat = quaternions_from_rotations(poses[:, :3, :3])
            if len(rows) == hi - lo - 1 and np.all(rows[1:] > rows[:-1]):
                # every segment from lo on, one row each: its ends are views, not copies
                ends, quaternions = (poses[:-1], poses[1:]), (quat[:-1], quat[1:])
            else:
                ends = poses[rows - lo], poses[rows + 1 - lo]
                quaternions = quat[rows - lo], quat[rows + 1 - lo]
        else:
            ends = self._pose_matrices(rows), self._pose_matrices(rows + 1)
        try:
            with noted_only():
                return checked_motion(*ends, self.mode, quaternions=quaternions, **self.parameters)
        except A2bError as e:
            if getattr(e, "index", None) is None:
                raise
            raise type(e)(f"{self._segment(rows[e.index])}: {e.reason}") from None

    def _pose_matrices(self, index) -> np.ndarray:
        """The robotics matrices of poses ``index``: given, or made from their quaternions."""
        if self.poses is not None:
            return self.poses[index]
        from .poses import matrices_from_quat_trans

        return matrices_from_quat_trans(self.quat_wxyz[index], self.translations[index])

    def _segment(self, k: int) -> str:
        t, number = self.times, self.first + k
        return (
            f"the segment from pose {number} (time {float(t[k])!r}) to pose {number + 1} "
            f"(time {float(t[k + 1])!r})"
        )


class NewTimes:
    """New times taken in order, up to a limit at a time: every ``1 / rate`` s from the first
    stamp (up to the last), or the increasing ``times`` given.

    With ``rate`` the times are a :class:`~a2b.timelaw.grid.TimeGrid` from the first stamp
    (:attr:`grid`, made by the first :meth:`upto`): the ``i``-th is the first stamp plus
    ``i / rate``, computed, never accumulated, and :meth:`stamps_ns` gives their exact integer
    nanoseconds for writers.
    """

    def __init__(self, rate: float | None = None, times=None, source: str = ""):
        self.rate, self.times, self.source = rate, times, source
        self.start: float | None = None
        self.grid = None
        self.taken = 0

    def upto(self, limit: float | None, start: float | None) -> Iterator[np.ndarray]:
        """The times not taken yet up to ``limit`` (``None``: all that are left), in blocks of
        :data:`BLOCK`; ``start`` is the trajectory's first stamp so far.

        Raises
        ------
        ParameterError
            With ``rate``: if the times up to ``limit`` number more than 2**53, or a double
            near ``limit`` cannot tell times ``1 / rate`` apart (they would repeat).
        """
        if self.rate is None:
            end = (
                len(self.times)
                if limit is None
                else int(np.searchsorted(self.times, limit, "right"))
            )
            for lo in range(self.taken, end, BLOCK):
                yield self.times[lo : min(lo + BLOCK, end)]
            self.taken = max(self.taken, end)
            return
        if limit is None:  # the times every 1/rate s end at the last stamp
            return
        if self.grid is None:
            from .timelaw.grid import TimeGrid

            self.start, self.grid = start, TimeGrid.at_rate(self.rate, start)
        end = self.grid.upto(limit, self.start)
        _check_resolution(self.rate, self.grid.step, self.start, limit)
        for lo in range(self.taken, end, BLOCK):
            yield self.start + self.grid.offsets(lo, min(lo + BLOCK, end))
        self.taken = max(self.taken, end)

    def stamps_ns(self, times: np.ndarray) -> np.ndarray:
        """Times that :meth:`upto` gave, as int64 nanoseconds: with ``rate`` exact (the first
        stamp's nanoseconds plus ``i`` steps), else the times rounded to nanoseconds."""
        if self.grid is None:
            return np.rint(np.asarray(times, dtype=float) * 1e9).astype(np.int64)
        return self.grid.stamps_ns(self.grid.index(times, self.start))

    def described(self) -> str:
        if self.rate is None:
            return f"{self.taken} new times from {self.source}"
        return f"{self.taken} new times from {self.start!r} s every 1/{self.rate:g} s"


def _check_resolution(rate: float, step: float, start: float, limit: float) -> None:
    """Refuse new times ``step`` s apart that the doubles between ``start`` and ``limit`` do not
    resolve to a quarter step: they would repeat, or their steps vary."""
    largest = max(abs(start), abs(limit))
    resolution = float(np.spacing(largest))
    if not step > 4 * resolution:
        raise ParameterError(
            f"new times every 1/{rate:g} s = {step:.3g} s cannot be told apart near "
            f"{largest:.9g} s, where a double resolves {resolution:.3g} s: they would repeat; "
            f"give a rate below {1 / (4 * resolution):.3g} Hz"
        )


def windows(pieces: Iterable, repaired: list | None = None) -> Iterator[dict]:
    """A trajectory that arrives in pieces (each with ``times``, ``quat_wxyz``, ``trans``,
    ``study``, ``matrices``, ``repaired``, as :mod:`a2b.io.trajectories` reads them) as the
    keyword arguments of one :class:`Resampler` per piece. Each window starts with the last
    pose of the piece before, so every segment lies in one window; ``last`` counts the poses so
    far. Repairs are collected in ``repaired``."""
    previous: dict | None = None
    count = 0
    for piece in pieces:
        window = {
            "times": piece.times,
            "quat_wxyz": piece.quat_wxyz,
            "translations": piece.trans,
            "study": piece.study,
            "poses": None if piece.quat_wxyz is not None else piece.matrices,
        }
        if repaired is not None and piece.repaired is not None:
            repaired.append(piece.repaired)
        if previous is not None:
            window = {
                key: None if value is None else np.concatenate([previous[key][-1:], value])
                for key, value in window.items()
            }
        count += len(piece.times)
        previous = window
        yield dict(window, last=count)


def _segments_of(t: np.ndarray, new: np.ndarray) -> np.ndarray:
    """For each new time (within ``[t[0], t[-1]]``), the index of the last stamp ``t`` at or
    before it: ``searchsorted(t, new, "right") − 1``.

    New times in order (the usual case) are found the other way round: each stamp among them,
    and the counts of stamps summed up. That is O(stamps · log(times) + times) instead of
    O(times · log(stamps)): four times as fast at ten new times a stamp."""
    if len(new) < 2 or not np.all(new[1:] >= new[:-1]):
        return np.searchsorted(t, new, side="right") - 1
    lo, hi = np.searchsorted(t, new[[0, -1]], side="right")
    # stamp s (new[0] < s <= new[-1]) is at or before new[j] from j = searchsorted(new, s) on
    k = np.cumsum(np.bincount(np.searchsorted(new, t[lo:hi]), minlength=len(new)))
    k += lo - 1
    return k


def _noted(notes) -> Iterator[tuple[int, str]]:
    """The element and text of each warning noted (:func:`a2b.elements.warn`), in the order
    they would have been issued."""
    size = int(np.prod(notes.shape, dtype=np.int64))
    for mask, texts in notes.rules:
        where = np.ones(size, dtype=bool) if mask is None else np.reshape(mask, -1)
        for index in np.flatnonzero(where).tolist():
            yield index, texts if isinstance(texts, str) else np.reshape(texts, -1)[index]


def _arrays(located: Located) -> tuple:
    return located.times, located.segment, located.u, located.pose


def _rows(k: np.ndarray, u: np.ndarray):
    """Parameters ``u`` of segments ``k`` as rows of one motion each: ``(rows (R,), ts (R, W),
    places)``.

    The motions of a batch share the number ``W`` of parameters, so the times of a segment
    fill rows of ``W`` (the mean count): at most about twice the samples, for any spread of
    times over segments. Unused places hold ½, inside the segment, where the motion pins no
    end pose. ``ts.ravel()[places]`` are the parameters ``u``; ``places`` is ``None`` where
    they are ``ts.ravel()`` (in order, no place unused), a slice where they are in order with
    the unused places before and after them (times in order, every segment but the first and
    the last with ``W``: a block of a regular rate), else indexes.
    """
    ordered = bool(np.all(k[1:] >= k[:-1]))  # new times in order: nothing to sort
    order = None if ordered else np.argsort(k, kind="stable")
    ks, us = (k, u) if ordered else (k[order], u[order])
    start = np.flatnonzero(np.concatenate([[True], ks[1:] != ks[:-1]]))
    segments, counts = ks[start], np.diff(np.append(start, len(ks)))
    width = -(-len(ks) // len(segments))
    per_segment = -(-counts // width)
    rows = np.repeat(segments, per_segment)
    if len(rows) * width == len(ks):  # every segment fills its rows
        flat, ts = None, us.reshape(-1, width)
    elif len(rows) == len(segments) and (counts[1:-1] == width).all():
        lead = width - int(counts[0])  # the first segment's row ends with its times
        flat, ts = slice(lead, lead + len(ks)), np.full(len(rows) * width, 0.5)
        ts[flat] = us
    else:
        first = (np.cumsum(per_segment) - per_segment) * width  # each segment's first place
        flat = np.repeat(first - start, counts) + np.arange(len(ks))
        ts = np.full(len(rows) * width, 0.5)
        ts[flat] = us
    if order is None:
        return rows, ts.reshape(-1, width), flat
    places = np.empty(len(ks), dtype=np.intp)
    places[order] = _all(flat, len(ks))
    return rows, ts.reshape(-1, width), places


def _all(places, count: int) -> np.ndarray:
    """``places`` of ``count`` parameters, as :func:`_rows` gives them, as indexes."""
    if places is None:
        return np.arange(count)
    if isinstance(places, slice):
        return np.arange(places.start, places.stop)
    return places


def _first(values) -> np.ndarray:
    return values[0] if isinstance(values, tuple) else values


def _taken(values, index: np.ndarray | slice | None):
    """The rows ``index`` of ``values`` (an array or a tuple of arrays; ``None``: all)."""
    if index is None:
        return values
    if isinstance(index, slice):  # views
        return tuple(v[index] for v in values) if isinstance(values, tuple) else values[index]
    if isinstance(values, tuple):
        return tuple(np.take(v, index, axis=0) for v in values)
    return np.take(values, index, axis=0)


def resample(
    times,
    poses,
    new_times,
    mode: str = "screw",
    *,
    clip: bool = False,
    max_gap: float | None = None,
    **parameters,
) -> tuple[np.ndarray, np.ndarray]:
    """A trajectory's poses at new times: ``(kept times (M,), robotics matrices (M, 4, 4))``.

    ``times (n,)`` increase; ``poses (n, 4, 4)`` are robotics matrices. ``mode`` is a
    two-pose mode per segment (``screw``, the default, ``darboux``, ``cubic``) or ``spline``.
    A time equal to a stamp gives that pose exactly. Times outside the trajectory raise
    :class:`ParameterError` unless ``clip`` drops them; times inside a segment longer than
    ``max_gap`` seconds are dropped. The first :data:`WARNINGS_SHOWN` warnings about segments
    are issued, then one that counts the rest. See :class:`Resampler`.

    >>> import numpy as np, a2b
    >>> from a2b.resample import resample
    >>> poses = np.stack([np.eye(4), np.eye(4)]); poses[1, 0, 3] = 2.0
    >>> kept, out = resample([0.0, 1.0], poses, [0.0, 0.25, 1.0])
    >>> out[:, 0, 3].tolist()
    [0.0, 0.5, 2.0]
    """
    resampler = Resampler(times, poses, mode, max_gap=max_gap, **parameters)
    located = resampler.locate(new_times, clip)
    values, built = resampler.sample_apart(located)
    resampler.account(built, stacklevel=2)
    if resampler.warned > WARNINGS_SHOWN:
        warnings.warn(A2bWarning(unshown(resampler.warned)), stacklevel=2)
    return located.times, values


def unshown(warned: int) -> str:
    """What to say of the segments warned about beyond the first :data:`WARNINGS_SHOWN`."""
    return (
        f"{warned - WARNINGS_SHOWN} more segments were warned about (the first "
        f"{WARNINGS_SHOWN} are shown above)"
    )
