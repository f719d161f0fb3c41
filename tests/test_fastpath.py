"""The sampling fast path against a straightforward, exact evaluation of the same tables.

``evaluate_table`` and ``evaluate_translations`` divide the basis by the denominators first and
write block after block straight into the output. Here every entry is recomputed as
``Σ_i b_i c_ij / Σ_i b_i d_i`` in exact rational arithmetic (``fractions.Fraction``) and then
rounded once, and the fast path must agree to 1e-15 relative to the size of the terms it sums
(see ``exact_entries``).
"""

from __future__ import annotations

from fractions import Fraction
from math import comb
from types import SimpleNamespace

import numpy as np
import pytest

import a2b
from a2b.errors import A2bError
from a2b.motions import _rational
from a2b.motions._rational import (
    ROT_COLS,
    TRANS_COLS,
    bernstein_basis,
    blocked_product,
    evaluate_table,
    evaluate_translations,
)
from a2b.motions.screw import ScrewMotion
from a2b.poses import rotations_from_quaternions
from a2b.study import quat_mul

from .conftest import random_pose

RTOL = 1e-15
MODES = ("darboux", "cubic", "cubic-given", "screw")


def random_motion(rng, mode):
    """A motion of ``mode`` between random poses with random parameters (retried until valid)."""
    for _ in range(100):
        start, end = random_pose(rng, 2.0), random_pose(rng, 2.0)
        if mode == "darboux":
            params = {"delta": rng.normal(), "long_way": bool(rng.random() < 0.3)}
        elif mode == "cubic":
            params = {"a": 0.5 * rng.normal(), "b": 0.5 * rng.normal()}
        elif mode == "cubic-given":
            params = {
                "frame": "given",
                "m": rng.normal(size=4),
                "a": 0.5 * rng.normal(),
                "b": 0.5 * rng.normal(),
            }
        else:
            params = {}
        try:
            return a2b.motion(start, end, mode.split("-")[0], **params)
        except A2bError:
            continue
    raise AssertionError(f"no valid random {mode} motion in 100 tries")


def random_ts(rng, count, lo=0.0, hi=1.0):
    return np.concatenate([[0.0, 1.0], rng.uniform(lo, hi, count - 2)])


def exact_entries(basis, table, columns, den_column):
    """``x_j = Σ b_i c_ij / Σ b_i d_i`` for each sample and column, computed exactly, rounded once.

    Also returns the size ``(Σ |b_i c_ij| + |x_j| Σ |b_i d_i|) / |Σ b_i d_i|`` of the terms that
    make up ``x_j``, for the tolerance: rounding errors scale with it, not with ``|x_j|``. For
    ``t ∈ [0, 1]`` the denominators' terms do not cancel and it is ``Σ |b_i c_ij| / |d| + |x_j|``.
    """
    n, k = basis.shape
    values = np.empty((n, len(columns)))
    sizes = np.empty((n, len(columns)))
    for s in range(n):
        b = [Fraction(float(x)) for x in basis[s]]
        den_terms = [b[i] * Fraction(float(table[i, den_column])) for i in range(k)]
        den = sum(den_terms)
        den_size = sum(abs(x) for x in den_terms)
        for col, j in enumerate(columns):
            terms = [b[i] * Fraction(float(table[i, j])) for i in range(k)]
            value = sum(terms) / den
            values[s, col] = float(value)
            sizes[s, col] = float((sum(abs(x) for x in terms) + abs(value) * den_size) / abs(den))
    return values, sizes


def assert_matches_exact(fast, basis, table, rows=None):
    """The fast ``(N, 4, 4)`` matrices against the exact entries (for the given sample rows)."""
    rows = np.arange(len(basis)) if rows is None else rows
    rot, rot_size = exact_entries(basis[rows], table, ROT_COLS, 12)
    trans, trans_size = exact_entries(basis[rows], table, TRANS_COLS, 13)
    flat = fast[rows].reshape(len(rows), 16)
    assert np.all(np.abs(flat[:, ROT_COLS] - rot) <= RTOL * rot_size)
    assert np.all(np.abs(flat[:, TRANS_COLS] - trans) <= RTOL * trans_size)
    assert np.array_equal(fast[rows, 3], np.broadcast_to([0.0, 0.0, 0.0, 1.0], (len(rows), 4)))
    assert not np.signbit(fast[rows, 3]).any()  # +0, never −0, in the bottom row


@pytest.mark.parametrize("mode", MODES)
def test_matrices_match_exact_evaluation_of_the_table(rng, mode):
    for _ in range(6):
        motion = random_motion(rng, mode)
        ts = random_ts(rng, 40)
        fast = motion.matrices(ts)
        if motion._rotation_is_fragile(0.0, 1.0):
            # p(t) comes close to 0: matrices() takes the rotation from the normalised p(t)
            # (rigid to rounding) and only the translation from the table.
            quat = motion._quats(ts)
            np.testing.assert_allclose(
                fast[:, :3, :3], rotations_from_quaternions(quat), rtol=0, atol=1e-15
            )
            fast = evaluate_table(motion._basis(ts), motion.table)
        assert_matches_exact(fast, motion._basis(ts), motion.table)


@pytest.mark.parametrize("mode", MODES)
def test_translations_match_exact_evaluation_of_the_table(rng, mode):
    for _ in range(6):
        motion = random_motion(rng, mode)
        ts = random_ts(rng, 40)
        basis = motion._basis(ts)
        trans, size = exact_entries(basis, motion.table, TRANS_COLS, 13)
        fast = evaluate_translations(basis, motion.table)
        assert np.all(np.abs(fast - trans) <= RTOL * size)
        _, fast_trans = motion.quat_trans(ts)
        np.testing.assert_array_equal(fast_trans, fast)


@pytest.mark.parametrize("mode", MODES)
def test_extrapolated_samples_match_exact_evaluation(rng, mode):
    motion = random_motion(rng, mode)
    ts = random_ts(rng, 30, -0.5, 1.5)
    basis = motion._basis(ts)
    assert_matches_exact(evaluate_table(basis, motion.table), basis, motion.table)


@pytest.mark.parametrize("mode", MODES)
def test_many_blocks_and_a_partial_last_block(rng, mode):
    """Indexing across blocks: every row against the plain product, rows near block sizes
    exactly."""
    motion = random_motion(rng, mode)
    n = 3 * _rational.SAMPLE_BLOCK + 123
    ts = np.sort(rng.uniform(0.0, 1.0, n))
    basis = motion._basis(ts)
    fast = evaluate_table(basis, motion.table)
    values = np.ascontiguousarray(basis) @ motion.table
    plain = np.zeros((n, 16))
    plain[:, ROT_COLS] = values[:, ROT_COLS] / values[:, 12:13]
    plain[:, TRANS_COLS] = values[:, TRANS_COLS] / values[:, 13:14]
    terms = np.abs(basis) @ np.abs(motion.table)
    size = np.zeros((n, 16))
    size[:, ROT_COLS] = terms[:, ROT_COLS] / np.abs(values[:, 12:13])
    size[:, TRANS_COLS] = terms[:, TRANS_COLS] / np.abs(values[:, 13:14])
    size += np.abs(plain)
    assert np.all(np.abs(fast.reshape(n, 16) - plain)[:, :12] <= 4 * RTOL * size[:, :12])
    edges = np.arange(0, n, 256)
    rows = np.unique(np.concatenate([edges, edges - 1, edges + 1, [n - 1], rng.integers(0, n, 50)]))
    rows = rows[(rows >= 0) & (rows < n)]
    assert_matches_exact(fast, basis, motion.table, rows)


def test_end_poses_are_the_first_and_last_coefficients(rng):
    for mode in MODES:
        motion = random_motion(rng, mode)
        ends = motion.matrices([0.0, 1.0])
        np.testing.assert_allclose(
            ends[0], motion.start, rtol=0, atol=4e-15 * np.abs(motion.start).max()
        )
        np.testing.assert_allclose(
            ends[1], motion.end, rtol=0, atol=4e-15 * np.abs(motion.end).max()
        )


def test_zero_and_one_sample(rng):
    motion = random_motion(rng, "cubic")
    assert motion.matrices([]).shape == (0, 4, 4)
    assert motion.quat_trans([])[1].shape == (0, 3)
    # not bit for bit: BLAS kernels may round a lone row differently from a full tile
    np.testing.assert_allclose(
        motion.matrices([0.3])[0], motion.matrices([0.1, 0.3])[1], rtol=0, atol=1e-14
    )


def test_result_does_not_depend_on_the_memory_layout_of_the_basis(rng):
    for mode in MODES:
        motion = random_motion(rng, mode)
        basis = motion._basis(random_ts(rng, 500))
        c_order = np.ascontiguousarray(basis)
        assert basis.flags.f_contiguous and c_order.flags.c_contiguous
        np.testing.assert_allclose(
            evaluate_table(c_order, motion.table),
            evaluate_table(basis, motion.table),
            rtol=0,
            atol=1e-14,
        )


def test_a_vanishing_denominator_keeps_the_bottom_row_and_the_other_samples():
    table = np.zeros((3, 14))
    table[:, ROT_COLS] = np.arange(27.0).reshape(3, 9)
    table[:, TRANS_COLS] = [[1.0, 2.0, 3.0], [0.5, 0.5, 0.5], [-1.0, 0.0, 1.0]]
    table[:, 12] = table[:, 13] = [1.0, 0.0, -1.0]  # (1 − t)² − t² = 1 − 2t vanishes at t = ½
    ts = np.array([0.0, 0.25, 0.5, 0.75, 1.0])
    basis = bernstein_basis(ts, 2)
    with np.errstate(divide="ignore", invalid="ignore"):
        out = evaluate_table(basis, table)
    np.testing.assert_array_equal(out[:, 3], np.broadcast_to([0.0, 0.0, 0.0, 1.0], (5, 4)))
    assert not np.isfinite(out[2, :3]).any()
    finite = [0, 1, 3, 4]
    assert_matches_exact(out, basis, table, np.array(finite))


def test_blocked_product_is_the_matrix_product(rng):
    for k, w in ((2, 4), (4, 3), (9, 16)):
        basis = rng.normal(size=(70_001, k))
        coefficients = rng.normal(size=(k, w))
        size = np.abs(basis) @ np.abs(coefficients)
        exact = basis.astype(np.longdouble) @ coefficients.astype(np.longdouble)
        product = blocked_product(basis, coefficients)
        assert product.flags.c_contiguous
        assert np.all(np.abs(product - exact) <= 1e-15 * size)
    assert blocked_product(np.empty((0, 2)), np.ones((2, 4))).shape == (0, 4)


# --------------------------------------------------------------------------------------------
# the bases
# --------------------------------------------------------------------------------------------


@pytest.mark.parametrize("degree", [1, 2, 3, 4, 6])
def test_bernstein_basis_is_the_textbook_formula(rng, degree):
    ts = np.concatenate([[0.0, 1.0, 0.5], rng.uniform(-1.0, 2.0, 200)])
    u = 1.0 - ts
    textbook = np.stack(
        [comb(degree, i) * u ** (degree - i) * ts**i for i in range(degree + 1)], axis=-1
    )
    np.testing.assert_allclose(bernstein_basis(ts, degree), textbook, rtol=RTOL, atol=0)
    # the same products in the same order as a direct np.stack, bit for bit
    if degree == 2:
        direct = np.stack([u * u, 2.0 * u * ts, ts * ts], axis=-1)
        np.testing.assert_array_equal(bernstein_basis(ts, 2), direct)
    if degree == 3:
        uu, tt = u * u, ts * ts
        direct = np.stack([uu * u, 3.0 * uu * ts, 3.0 * u * tt, tt * ts], axis=-1)
        np.testing.assert_array_equal(bernstein_basis(ts, 3), direct)


def test_bernstein_basis_for_0_1_and_3_leading_dimensions(rng):
    ts = rng.uniform(0.0, 1.0, size=(2, 3, 4))
    flat = bernstein_basis(ts.ravel(), 3)
    assert bernstein_basis(ts, 3).shape == (2, 3, 4, 4)
    np.testing.assert_array_equal(bernstein_basis(ts, 3).reshape(-1, 4), flat)
    np.testing.assert_array_equal(bernstein_basis(ts[0, 0, 0], 3), flat[0])
    np.testing.assert_array_equal(bernstein_basis(ts[0, 0, :1], 3), flat[:1])


def exact_screw_basis(ts, phi):
    """``(1, t, sin tφ, 2 sin²(tφ/2))`` in extended precision, from the rounded ``tφ``."""
    angle = (ts * phi).astype(np.longdouble)
    return np.stack([np.ones_like(angle), ts, np.sin(angle), 2 * np.sin(angle / 2) ** 2], axis=-1)


def test_screw_basis_is_accurate_on_0_1(rng):
    """Computed from tan(tφ/2) there: 1e-15 relative to the exact functions, every entry."""
    for _ in range(5):
        motion = random_motion(rng, "screw")
        ts = random_ts(rng, 1000)
        basis = motion._basis(ts)
        exact = exact_screw_basis(ts, motion.frame.phi)
        assert np.all(np.abs(basis - exact) <= RTOL * np.abs(exact))
    # the pole of tan at tφ = π, and tiny angles
    for phi in (np.pi, np.nextafter(np.pi, 0), 3.0, 1e-8, 1e-300):
        ts = np.concatenate([[0.0, 1e-9, 0.5, 1.0, -1.0, 1.01], np.linspace(0.999, 1.0, 100)])
        basis = ScrewMotion._basis(SimpleNamespace(frame=SimpleNamespace(phi=phi)), ts)
        exact = exact_screw_basis(ts, phi)
        # vers (tφ)²/2 underflows for φ = 1e-300, in float64 whatever the formula
        assert np.all(np.abs(basis - exact) <= RTOL * np.abs(exact) + np.finfo(float).tiny)


def test_screw_basis_far_out_is_the_textbook_formula(rng):
    """Beyond |tφ/2| = 1.6 the basis comes from np.sin, bit for bit the textbook formula."""
    motion = random_motion(rng, "screw")
    ts = random_ts(rng, 300, -4.0, 5.0)
    angle = ts * motion.frame.phi
    half = np.sin(0.5 * angle)
    textbook = np.stack([np.ones_like(ts), ts, np.sin(angle), 2.0 * half * half], axis=-1)
    np.testing.assert_array_equal(motion._basis(ts), textbook)


def _angle_weights(phi, ts):
    """``(cos(tφ/2), sin(tφ/2))`` as :meth:`ScrewMotion._quats` weighs pA and u pA."""
    ends = np.zeros((2, 4))
    ends[0, 0] = ends[1, 1] = 1.0  # the weights themselves
    motion = SimpleNamespace(frame=SimpleNamespace(phi=phi), quat_ends=ends)
    return ScrewMotion._quats(motion, ts)[:, :2]


def test_screw_quaternion_weights_are_accurate_to_the_half_turn(rng):
    """From tan(tφ/2) up to |tφ/2| = π/2: within 2.5e-16 of the exact cos and sin, at the
    half-turn and for tiny angles too; beyond, np.cos and np.sin bit for bit."""
    for phi in (np.pi, np.nextafter(np.pi, 0), 3.0, 1.0, 1e-8, 1e-300):
        ts = np.concatenate([[0.0, 1e-9, 0.5, 1.0], np.linspace(0.999, 1.0, 100),
                             rng.uniform(0.0, 1.0, 200)])  # fmt: skip
        angle = (0.5 * phi * ts).astype(np.longdouble)  # rounded as _quats rounds it
        exact = np.stack([np.cos(angle), np.sin(angle)], axis=-1)
        assert np.all(np.abs(_angle_weights(phi, ts) - exact) <= 2.5e-16)
    ts = rng.uniform(-1.0, 2.0, 300)
    angle = 0.5 * 3.0 * ts
    textbook = np.stack([np.cos(angle), np.sin(angle)], axis=-1)
    np.testing.assert_array_equal(_angle_weights(3.0, ts), textbook)


def test_screw_quaternions_are_the_textbook_formula(rng):
    for _ in range(5):
        motion = random_motion(rng, "screw")
        ts = random_ts(rng, 300, -1.0, 2.0)
        half_angle = 0.5 * ts * motion.frame.phi
        rel = np.empty(ts.shape + (4,))
        rel[:, 0] = np.cos(half_angle)
        rel[:, 1:] = np.sin(half_angle)[:, None] * motion.frame.axis_direction
        reference = quat_mul(rel, motion.frame.p_start)
        np.testing.assert_allclose(motion._quats(ts), reference, rtol=0, atol=1e-15)
