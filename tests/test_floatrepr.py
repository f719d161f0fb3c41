"""The float formatter against Python's ``repr`` on a seeded sample of every kind of double."""

from __future__ import annotations

import numpy as np

from a2b.io.floatrepr import format_rows, number_words

N = 100_000


def _neighbours(values: np.ndarray) -> np.ndarray:
    """Each value and the doubles just below and above it."""
    with np.errstate(over="ignore"):
        return np.concatenate([values, np.nextafter(values, -np.inf), np.nextafter(values, np.inf)])


def _ties(rng, n: int) -> np.ndarray:
    """Exact binary fractions whose decimals end in 5, and decimals with a 5 at the 16th to
    18th significant digit: halfway cases for the 15-, 16- and 17-digit roundings."""
    binary = rng.integers(1, 2000, n // 2) * 2 + 1.0
    binary *= 2.0 ** rng.integers(-70, 70, n // 2)
    widths = rng.integers(14, 18, n - n // 2)
    decimal = [
        float(f"{rng.integers(10 ** (w - 1), 10**w)}5e{rng.integers(-320, 290)}") for w in widths
    ]
    return np.concatenate([binary, decimal])


def _every_kind(rng) -> np.ndarray:
    """``N`` doubles of all magnitudes and signs, with the special ones, in random order."""
    with np.errstate(over="ignore", under="ignore"):
        scaled = rng.standard_normal(20_000) * 10.0 ** rng.integers(-330, 309, 20_000)
    places = 10.0 ** rng.integers(0, 15, 10_000)
    short = np.rint(rng.standard_normal(10_000) * 1e3 * places) / places  # the nearest doubles
    parts = [
        np.array([0.0, -0.0, np.nan, np.inf, -np.inf, 5e-324, 2.2250738585072014e-308]),
        rng.integers(0, 2**64, 20_000, dtype=np.uint64).view(np.float64),  # every bit pattern
        scaled,
        rng.integers(1, 2**52, 5_000, dtype=np.uint64).view(np.float64),  # subnormals
        _neighbours(2.0 ** np.arange(-1074, 1024)),  # powers of two
        _neighbours(np.array([float(f"1e{k}") for k in range(-323, 309)])),  # powers of ten
        _ties(rng, 20_000),
        short,
    ]
    values = np.concatenate(parts)
    assert values.size <= N
    values = np.concatenate([values, rng.standard_normal(N - values.size)])
    with np.errstate(invalid="ignore"):  # signalling NaNs among the bit patterns
        values *= rng.choice([-1.0, 1.0], N)
    return rng.permutation(values)


def test_number_words_is_repr_for_every_kind_of_double(rng):
    values = _every_kind(rng)
    words, lengths = number_words(values, lengths=True)
    texts = [repr(float(v)) for v in values]
    got = [row.tobytes().translate(None, b"\0").decode() for row in words]
    wrong = [(t, g) for t, g in zip(texts, got) if t != g]
    assert wrong == []
    assert lengths.tolist() == [len(t) for t in texts]


def test_format_rows_is_repr_for_every_kind_of_double(rng):
    values = _every_kind(rng).reshape(-1, 8)
    expected = "".join(",".join(repr(float(v)) for v in row) + "\n" for row in values)
    assert format_rows(values).decode() == expected


def test_each_cell_leaves_the_byte_before_its_text_and_its_last_byte_free(rng):
    words = number_words(_every_kind(rng)).view(np.uint8).reshape(-1, 32)
    text = words != 0
    first = np.argmax(text, axis=1)
    assert (first >= 1).all()
    assert not text[:, 31].any()


def test_a_row_is_one_run_of_bytes_a_number_without_exponent(rng):
    from a2b.io.floatrepr import _row_cells

    shape = (2048, 8)
    values = rng.uniform(1, 10, shape) * rng.choice([-1.0, 1.0], shape)
    values *= 10.0 ** rng.integers(-4, 16, shape)  # every exponent repr writes without "e"
    text = _row_cells(values, ord(",")).view(np.uint8).reshape(-1) != 0
    runs = np.count_nonzero(text[1:] & ~text[:-1]) + text[0]
    assert runs == values.size + len(values)  # and the line end of each row
