"""Arc length of a body point's path over ``t ∈ [0, 1]``, and its inverse: composite
Gauss–Legendre quadrature to 1e-12 relative, inverted by safeguarded Newton steps."""

from __future__ import annotations

import numpy as np

from ..elements import refuse
from ..errors import A2bError
from ..kinematics import check_point

__all__ = ["arc_lengths", "invert_arc_length", "lengths_at"]

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

_RULES = {n: np.polynomial.legendre.leggauss(n) for n in (FIRST_NODES, NODES)}
_NODES, _WEIGHTS = _RULES[NODES]


def _panel_lengths(motion, point, panels: int, nodes: int = NODES) -> np.ndarray:
    """Gauss–Legendre with ``nodes`` nodes on each of ``panels`` equal panels of ``[0, 1]``:
    the path length on each panel, ``S + (panels,)``."""
    ts, half = _panel_nodes(panels, nodes)
    speeds = motion.point_speeds(ts, point).reshape(getattr(motion, "shape", ()) + (panels, nodes))
    return speeds @ _RULES[nodes][1] * half


def _panel_nodes(panels: int, nodes: int) -> tuple[np.ndarray, np.ndarray]:
    """The Gauss–Legendre nodes ``(panels · nodes,)`` of :func:`_panel_lengths` and the half
    widths ``(panels,)`` of the panels."""
    x = _RULES[nodes][0]
    edges = np.linspace(0.0, 1.0, panels + 1)
    half = (edges[1:] - edges[:-1]) / 2
    return ((edges[:-1] + half)[:, None] + half[:, None] * x).reshape(-1), half


def _first_lengths(motion, point, panels: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The point at ``t = 0`` and ``1`` (``S + (2, 3)``), and the panel lengths by
    :data:`FIRST_NODES` and by :data:`NODES` nodes (``S + (panels,)`` each): one evaluation
    of the path for all three."""
    shape = getattr(motion, "shape", ())
    coarse, half = _panel_nodes(panels, FIRST_NODES)
    fine = _panel_nodes(panels, NODES)[0]
    ts = np.concatenate([[0.0, 1.0], coarse, fine])
    path = motion.derivatives(ts, 1, point=check_point(point))
    speeds = np.linalg.norm(path[..., 1, 2:, :], axis=-1)
    split = 2 + panels * FIRST_NODES
    lengths = [
        speeds[..., lo - 2 : hi - 2].reshape(shape + (panels, n)) @ _RULES[n][1] * half
        for lo, hi, n in ((2, split, FIRST_NODES), (split, len(ts), NODES))
    ]
    return path[..., 0, :2, :], lengths[0], lengths[1]


def arc_lengths(motion, point=None) -> tuple[np.ndarray, np.ndarray]:
    """The length of the point's path on ``t ∈ [0, 1]`` and the cumulative lengths at the
    edges of equal panels of ``t``: ``S`` and ``S + (P + 1,)``.

    Composite Gauss–Legendre (:data:`NODES` nodes a panel). Each motion starts with one panel
    (a Bézier spline one a segment), checked against :data:`FIRST_NODES` nodes, and doubles its
    own count until two counts agree to :data:`ARC_TOL` relative (at most :data:`MOST_PANELS`),
    so a smooth path costs a few dozen speeds. The cumulative lengths of a batch are padded
    with ``+inf`` past each motion's last panel edge: a motion's panel count is the number of
    its finite entries less one. Each round runs over every motion still open, in blocks of
    :data:`ARC_BLOCK` that bound memory. A length within the rounding floor (1e-12 of the
    point's distance from the origin at the ends) is 0: the point does not move.

    Raises
    ------
    A2bError
        If two quadratures of a motion still differ by more than 1e-9 relative at the most
        panels (its point passes very close to a singular pose).
    """
    shape = getattr(motion, "shape", ())
    count = int(np.prod(shape))
    if len(shape) > 1:
        motion = motion[np.unravel_index(np.arange(count), shape)]
    total, rows, floor = _converged(motion, point, count, shape)
    cumulative = np.full((count, max(rows) + 1), np.inf)
    cumulative[:, 0] = 0.0
    for width, (which, sums) in rows.items():
        cumulative[which, 1 : width + 1] = sums
    # a length at the rounding floor is 0 to the accuracy reached: the point does not move
    # (a pose to itself gives lengths of 1e-16, which would time a law of 1e-16 s)
    still = total <= floor
    total[still] = 0.0
    cumulative[still] = np.where(np.isfinite(cumulative[still]), 0.0, np.inf)
    if not shape:
        return total[0], cumulative[0]
    return total.reshape(shape), cumulative.reshape(shape + cumulative.shape[-1:])


def _in_blocks(motion, work):
    """``work(part)`` on slices of :data:`ARC_BLOCK` motions of a 1-D batch (views: no copy of
    the motions), the results joined along the first axis; one call for a single motion."""
    size = len(motion) if getattr(motion, "shape", ()) else 0
    if size <= ARC_BLOCK:
        return work(motion)
    parts = [work(motion[lo : lo + ARC_BLOCK]) for lo in range(0, size, ARC_BLOCK)]
    if isinstance(parts[0], tuple):
        return tuple(np.concatenate(column) for column in zip(*parts))
    return np.concatenate(parts)


def _converged(motion, point, count: int, shape: tuple) -> tuple[np.ndarray, dict, np.ndarray]:
    """The lengths ``(count,)`` of :func:`arc_lengths` (a 1-D batch, or one motion for
    ``count = 1`` with no shape), the cumulative panel lengths of the motions that converged
    at each panel count ``{P: (motions, (m, P))}``, and the rounding floor ``(count,)``.

    Each round computes the next panel count of every motion still open, the whole batch
    together: the open motions are gathered once a round, not once a block."""
    single = not shape
    total, rows = np.zeros(count), {}
    # a curve starts with a panel per segment: none straddles a joint, where the speed of a
    # spline is only continuous (its derivative may jump, which Gauss nodes converge on slowly)
    first = len(motion.joints()) + 1 if hasattr(motion, "joints") else 1
    todo, panels, tol = np.arange(count), first, FIRST_TOL
    ends, coarse, fine = _in_blocks(motion, lambda part: _first_lengths(part, point, first))
    # the rounding floor: a point that stands still has speeds of rounding size, about ε times
    # its distance from the origin, and no relative accuracy to reach
    floor = ARC_TOL * np.linalg.norm(ends, axis=-1).sum(axis=-1).reshape(count)
    coarse, fine = coarse.reshape(count, first), fine.reshape(count, first)
    while True:
        if fine is None:
            fine = _in_blocks(motion, lambda part: _panel_lengths(part, point, panels))
            fine = fine.reshape(len(todo), panels)
        length, gap = fine.sum(axis=-1), np.abs(fine.sum(axis=-1) - coarse.sum(axis=-1))
        done = gap <= tol * length + floor[todo]
        if panels >= MOST_PANELS:
            relative = np.zeros(count)
            relative[todo] = np.where(
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
            return total, rows, floor
        todo, coarse, panels, tol = todo[~done], fine[~done], 2 * panels, ARC_TOL
        motion, fine = motion if single else motion[~done], None


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
