"""Structure matrices: a2b's bilinear forms evaluated in bulk (``a2b.study.bilinear``)."""

from __future__ import annotations

import mpmath
import numpy as np
import pytest

import a2b
from a2b.motions._rational import CHUNK
from a2b.study import (
    IN_TURN_CHUNK,
    IN_TURN_FROM,
    NARROW_FROM,
    Structure,
    bilinear,
    linear,
    quat_mul,
    rotation_numerators,
    structure_matrix,
    translation_numerators,
)

from .conftest import random_pose


def test_a_structure_matrix_evaluates_its_form(rng):
    for form, n_a, n_b in (
        (quat_mul, 4, 4),
        (rotation_numerators, 4, 4),
        (translation_numerators, 4, 4),
    ):
        matrix = structure_matrix(form, n_a, n_b)
        a, b = rng.normal(size=(5, 7, n_a)), rng.normal(size=(5, 7, n_b))
        direct = form(a, b)
        bulk = bilinear(matrix, np.moveaxis(a, -1, 0), np.moveaxis(b, -1, 0))
        np.testing.assert_allclose(np.moveaxis(bulk, 0, -1), direct, rtol=0, atol=1e-14)


def test_bilinear_broadcasts_the_trailing_shapes(rng):
    matrix = structure_matrix(quat_mul, 4, 4)
    a, b = rng.normal(size=(4, 3, 1)), rng.normal(size=(4, 1, 5))
    out = bilinear(matrix, a, b)
    assert out.shape == (4, 3, 5)
    np.testing.assert_allclose(out[:, 2, 4], quat_mul(a[:, 2, 0], b[:, 0, 4]), atol=1e-15)


@pytest.mark.parametrize("count", [3, NARROW_FROM + 5, IN_TURN_FROM + 5])
def test_bilinear_broadcasts_an_operand_of_fewer_dimensions_at_every_size(rng, count):
    """One quaternion against many (the frames of a long trajectory in ``a2b view``), at the
    sizes of each of bilinear's ways: numpy's broadcasting, and each element bit for bit the
    element alone."""
    matrix = structure_matrix(quat_mul, 4, 4)
    many, one = rng.normal(size=(4, count)), rng.normal(size=4)
    for a, b in ((many, one), (one, many), (many, one[:, None]), (one[:, None], many)):
        out = bilinear(matrix, a, b)
        assert out.shape == (4, count)
        direct = quat_mul(np.broadcast_to(a.T, (count, 4)), np.broadcast_to(b.T, (count, 4)))
        np.testing.assert_allclose(out.T, direct, rtol=0, atol=1e-14)
        for j in (0, count - 1):  # the element j of each (of one with one column: that one)
            alone = bilinear(matrix, *(x if x.ndim == 1 else x[:, min(j, x.shape[1] - 1)]
                                       for x in (a, b)))  # fmt: skip
            np.testing.assert_array_equal(out[:, j], alone)
    grid = bilinear(matrix, rng.normal(size=(4, count, 1)), rng.normal(size=(4, 1, 3)))
    assert grid.shape == (4, count, 3)


def _exact_table(start, end):
    """The Darboux table (δ = 0) in 40 digits, from the unit Study vectors of the frame."""
    mpmath.mp.dps = 40
    frame = a2b.motion(start, end).frame
    p = [[mpmath.mpf(float(x)) for x in frame.p_start], [mpmath.mpf(float(x)) for x in frame.p_end]]
    t = [[mpmath.mpf(float(x)) for x in frame.t_start], [mpmath.mpf(float(x)) for x in frame.t_end]]

    def dual(t, p):  # q = −½ (0, t) p
        t1, t2, t3 = t
        p0, p1, p2, p3 = p
        return [
            (t1 * p1 + t2 * p2 + t3 * p3) / 2,
            -(t1 * p0 + t2 * p3 - t3 * p2) / 2,
            -(-t1 * p3 + t2 * p0 + t3 * p1) / 2,
            -(t1 * p2 - t2 * p1 + t3 * p0) / 2,
        ]

    q = [dual(t[0], p[0]), dual(t[1], p[1])]
    rows = []
    for i, j in ((0, 0), (0, 1), (1, 1)):
        rot = rotation_numerators(np.array(p[i], dtype=object), np.array(p[j], dtype=object))
        half = [
            (x + y) / 2
            for x, y in zip(
                translation_numerators(np.array(p[i], object), np.array(q[j], object)),
                translation_numerators(np.array(p[j], object), np.array(q[i], object)),
            )
        ]
        den = sum(a * b for a, b in zip(p[i], p[j]))
        rows.append([*rot[0:3], half[0], *rot[3:6], half[1], *rot[6:9], half[2], den, den])
    return rows


def test_the_darboux_table_agrees_with_40_digits(rng):
    """The bulk build sums its terms in another order than the formulas read: its table agrees
    with a 40-digit evaluation of the same formulas to 1e-15, the rotation numerators and
    denominators (of size 1) absolutely, the translation numerators relative to the larger
    translation of A and B."""
    for _ in range(20):
        start, end = random_pose(rng, 3.0), random_pose(rng, 3.0)
        table = a2b.motion(start, end).table
        exact = _exact_table(start, end)
        miss = np.array(
            [[float(abs(mpmath.mpf(float(table[r, c])) - exact[r][c])) for c in range(14)]
             for r in range(3)]
        )  # fmt: skip
        size = max(np.abs(start[:3, 3]).max(), np.abs(end[:3, 3]).max())
        assert miss[:, [0, 1, 2, 4, 5, 6, 8, 9, 10, 12, 13]].max() <= 1e-15
        assert miss[:, [3, 7, 11]].max() <= 1e-15 * size


def test_a_batch_larger_than_a_chunk_is_its_elements_bit_for_bit(rng):
    count = CHUNK + 3
    start = np.stack([random_pose(rng) for _ in range(count)])
    end = np.stack([random_pose(rng) for _ in range(count)])
    for mode, params in (("darboux", {"delta": 0.25}), ("screw", {}), ("cubic", {})):
        batch = a2b.motion(start, end, mode, **params)
        for i in (0, CHUNK - 1, CHUNK, count - 1):
            single = a2b.motion(start[i], end[i], mode, **params)
            np.testing.assert_array_equal(batch.table[i], single.table, err_msg=mode)
            np.testing.assert_array_equal(batch.quat_ends[i], single.quat_ends, err_msg=mode)


def test_bilinear_gives_an_element_of_a_batch_bit_for_bit_as_alone(rng):
    form = structure_matrix(rotation_numerators, 4, 4)
    count = IN_TURN_CHUNK + 100  # in two chunks
    a, b = rng.normal(size=(4, count)), rng.normal(size=(4, count))
    full = bilinear(form, a, b)
    for j in (0, 1, 7, IN_TURN_CHUNK - 1, IN_TURN_CHUNK, count - 2):
        np.testing.assert_array_equal(full[:, j], bilinear(form, a[:, j], b[:, j]))
        np.testing.assert_array_equal(
            full[:, j : j + 2], bilinear(form, a[:, j : j + 2], b[:, j : j + 2])
        )


def _every_structure():
    import a2b.motions.cubic
    import a2b.motions.darboux
    import a2b.poses

    for module in (a2b.study, a2b.poses, a2b.motions.darboux, a2b.motions.cubic):
        for name, value in vars(module).items():
            if isinstance(value, Structure):
                yield f"{module.__name__}.{name}", value
    # rows of 3, 1 and 2 terms: the padding terms are evaluated too (0 · a₀b₀ is ±0 or NaN)
    yield "padded", structure_matrix(
        lambda a, b: np.stack(
            [a[..., 0] * b[..., 1] - a[..., 2] * b[..., 0] + 2 * a[..., 1] * b[..., 1],
             a[..., 2] * b[..., 2],
             a[..., 1] * b[..., 0] + a[..., 0] * b[..., 2]],
            axis=-1,
        ),
        3,
        3,
    )  # fmt: skip


def _awkward(rng, shape):
    """Random numbers with signed zeros, infinities, NaN, subnormals and huge ones among them."""
    x = rng.normal(size=shape)
    special = np.array([0.0, -0.0, np.inf, -np.inf, np.nan, 5e-324, -1e-310, 1e300, -1e300])
    where = rng.random(shape) < 0.3
    x[where] = rng.choice(special, size=int(where.sum()))
    return x


def _same_signs(a, b) -> bool:
    """The same signs, zeros included; a NaN's sign bit means nothing (and numpy < 2 makes
    some of them otherwise in its vector loops)."""
    number = ~np.isnan(a)
    return np.array_equal(np.signbit(a[number]), np.signbit(b[number]))


def test_every_way_of_evaluating_a_structure_gives_the_same_bits(rng):
    """bilinear and linear gather every term for a few columns (and broadcast a term's constant
    factor from NARROW_FROM), and go row by row and term by term from IN_TURN_FROM: the same
    bits every way, signed zeros, infinities and NaN included, so that an element of a batch
    is the element alone."""
    count = IN_TURN_FROM + 37
    found = 0
    for name, form in _every_structure():
        found += 1
        n_in = form.matrix.shape[1]
        if form.left is None:  # a linear map: its input row 0 is the constant 1
            x = _awkward(rng, (n_in, count))
            x[0] = 1.0
            with np.errstate(all="ignore"):
                full = linear(form, x)
                for lo, hi in ((0, 1), (5, 5 + NARROW_FROM + 1), (3, IN_TURN_FROM - 1)):
                    part = linear(form, x[:, lo:hi])
                    assert np.array_equal(full[:, lo:hi], part, equal_nan=True), name
                    assert _same_signs(full[:, lo:hi], part), name
            continue
        n_a, n_b = int(form.left.max()) + 1, int(form.right.max()) + 1
        a, b = _awkward(rng, (n_a, count)), _awkward(rng, (n_b, count))
        with np.errstate(all="ignore"):
            full = bilinear(form, a, b)
            for lo, hi in ((0, 1), (5, 5 + NARROW_FROM + 1), (3, IN_TURN_FROM - 1)):
                part = bilinear(form, a[:, lo:hi], b[:, lo:hi])
                assert np.array_equal(full[:, lo:hi], part, equal_nan=True), name
                assert _same_signs(full[:, lo:hi], part), name
            one = bilinear(form, a[:, 9], b[:, 9])
        assert np.array_equal(full[:, 9], one, equal_nan=True), name
        assert _same_signs(full[:, 9], one), name
    assert found >= 10


def test_terms_and_dot_products_are_added_in_order_at_every_size(rng):
    from a2b.study import ACCUMULATE_UP_TO, DOTS_ACCUMULATE_UP_TO, dots, sum_terms

    def in_order(terms):  # ((t0 + t1) + t2) + …, one number at a time
        out = terms[0].copy()
        for term in terms[1:]:
            out = out + term
        return out

    for size in (1, 3, ACCUMULATE_UP_TO // 4, ACCUMULATE_UP_TO // 4 + 1, 500):
        terms = rng.normal(size=(4, size)) * 10.0 ** rng.integers(-8, 8, size=(4, size))
        terms[:, 0] = [-0.0, -0.0, 0.0, -0.0]  # a signed zero that a reordering would lose
        expected = in_order(terms)
        assert sum_terms(terms.copy()).tobytes() == expected.tobytes()
    for count in (1, DOTS_ACCUMULATE_UP_TO // 4, DOTS_ACCUMULATE_UP_TO // 4 + 1, 300):
        a, b = rng.normal(size=(2, count, 4)) * 1e3
        expected = in_order(np.moveaxis(a * b, -1, 0))
        assert dots(a, b).tobytes() == expected.tobytes()
    one = dots(np.array([1.0, 2.0, 3.0, 4.0]), np.array([0.5, 0.25, 1.0, 2.0]))
    assert isinstance(one, np.float64) and one == 12.0  # a number for one pair of vectors
