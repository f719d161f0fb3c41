"""Text trajectories read by pyarrow's CSV reader (where installed) as numpy.loadtxt reads them.

A large text file (``textrows.ARROW_FROM``) is parsed by pyarrow where it is plain; anything
else, and every error, is numpy.loadtxt's. These tests compare both ways on the same texts."""

from __future__ import annotations

import numpy as np
import pytest

from a2b.errors import A2bError
from a2b.io import textrows
from a2b.io.textrows import TextLayout, read_rows

pytest.importorskip("pyarrow", reason="pyarrow (the parquet extra) parses large texts")

TUM = TextLayout(None, 0, 8, (0, 1, 2, 3, 7, 4, 5, 6), fmt="tum")
PLAIN = TextLayout(None, 0, 3, (0, 1, 2), fmt="plain")
CSV = TextLayout(",", 1, None, (2, 0), fmt="csv")  # named columns, by the header
SOME = TextLayout(None, 0, 3, (2, 0), fmt="some")  # field 1 is not read


def both(text: bytes, layout: TextLayout, monkeypatch):
    """``read_rows`` both ways: the rows, or the error's text, and whether pyarrow parsed."""
    out = []
    for bulk in (False, True):
        try:
            rows, _ = read_rows(text, "f.txt", layout, bulk=bulk)
            out.append(rows)
        except A2bError as e:
            out.append(str(e))
    return out


def same(a, b) -> bool:
    if isinstance(a, str) or isinstance(b, str):
        return a == b
    return a.shape == b.shape and np.array_equal(a.view(np.int64), b.view(np.int64))


def test_random_doubles_in_every_spelling_are_the_same_bits(rng, monkeypatch):
    values = np.concatenate([
        rng.normal(size=3000) * 10.0 ** rng.integers(-300, 300, 3000),
        rng.normal(size=3000),
        [0.0, -0.0, 1e-310, -5e-324, 1.7976931348623157e308, 0.1, 1 / 3],
    ])  # fmt: skip
    values = values[: len(values) // 3 * 3].reshape(-1, 3)
    for spell in (repr, "{:.17g}".format, "{:.6e}".format, "{:g}".format, "{:.3f}".format,
                  lambda v: f"{v:+.17e}".upper()):  # fmt: skip
        text = "\n".join(" ".join(spell(float(v)) for v in row) for row in values) + "\n"
        slow, fast = both(text.encode(), PLAIN, monkeypatch)
        assert not isinstance(fast, str) and same(slow, fast), spell


def test_pyarrow_parses_a_plain_text_and_leaves_the_rest_to_loadtxt(monkeypatch):
    plain = b"1 2 3 4 5 6 7 8\n0.5 0 0 0 0 0 0 1\n"
    calls = []
    real = textrows._loadtxt
    monkeypatch.setattr(textrows, "_loadtxt", lambda *a, **k: calls.append(1) or real(*a, **k))
    for text in (plain, b"# time tx ty tz qx qy qz qw\n#\n" + plain):  # comments at the top
        read_rows(text, "f", TUM, bulk=True)
        assert calls == [], text  # pyarrow's
    for other in (plain + b"# a comment\n", plain.replace(b" ", b"\t"), plain.replace(b" ", b"  "),
                  b" " + plain, plain.replace(b"\n", b"\r\n"), plain + b"1 2 3\n",
                  b"#\n #\n" + plain):  # fmt: skip
        calls.clear()
        try:
            read_rows(other, "f", TUM, bulk=True)
        except A2bError:
            pass
        assert calls, other  # loadtxt's


@pytest.mark.parametrize(
    "text, layout",
    [
        (b"1 2 3\n4 5 6\n", PLAIN),
        (b"1 2 3\n4 5\n", PLAIN),  # a short row
        (b"1 2 3\n4 5 6 7\n", PLAIN),  # a long row
        (b"1 2 3\n4 x 6\n", PLAIN),
        (b"1 2 3\n4 nan 6\n", PLAIN),
        (b"1 2 3\n4 inf 6\n", PLAIN),
        (b"1 2 3\n4 1e999 6\n", PLAIN),
        (b"1 2 3\n\n4 5 6\n", PLAIN),  # a blank line
        (b"1 2 3\n4 5 6", PLAIN),  # no line end at the end
        (b'1 2 3\n"4" 5 6\n', PLAIN),
        (b"1 2 3\n4 5 6 \n", PLAIN),
        (b"1 2 3\n+4 .5 6.\n", PLAIN),
        (b"1 2 3\n4 0x10 6\n", PLAIN),
        (b"1 2 3\n4 1_0 6\n", PLAIN),
        (b"1 2 3\n4 5,6 7\n", PLAIN),
        (b"", PLAIN),
        (b"a,b,c\n1,2,3\n4,5,6\n", CSV),
        (b"a,b,c\n1,2,3\n4,5\n", CSV),
        (b"a,b,c\n1,2,3,9\n4,5,6\n", CSV),  # more fields than named: loadtxt takes them
        (b"a,b,c\n1, 2,3\n4,5,6\n", CSV),
        (b"a,b,c\n1,,3\n", CSV),
        # blanks next to blanks or line ends: pyarrow refuses them where every field is read,
        # and they are looked for where one is not (a blank standing in for its number)
        (b"1 2 3\n4  5 6\n", PLAIN),
        (b"1 2 3\n4  6\n", PLAIN),
        (b" 1 2 3\n4 5 6\n", PLAIN),
        (b"1 2 3\n \n4 5 6\n", PLAIN),
        (b"1 2 3\n  \n4 5 6\n", PLAIN),
        (b"1 2 3\n4 5 6 ", PLAIN),
        (b"1 2 3\n4 5 \n", PLAIN),
        (b"1 2 3\n4 5 6\n", SOME),
        (b"1 2 3\n4  6\n", SOME),
        (b"1 2 3\n4 5 \n", SOME),
        (b"1 2 3\n 5 6\n", SOME),
        (b"1 2 3\n4 5 6 \n", SOME),
    ],
)
def test_both_ways_give_the_same_rows_or_the_same_error(text, layout, monkeypatch):
    slow, fast = both(text, layout, monkeypatch)
    assert same(slow, fast), (slow, fast)


@pytest.mark.parametrize(
    "text",
    [b"1 2 3\n4 5 6\n", b"1 2 3\n4 5 6", b"# h\n#\n1 2 3\n4 5 6\n", b"1 2 3\n\n4 5 6\n",
     b"\n1 2 3\n4 5 6\n", b"# h\n\n1 2 3\n", b"1 2 3\n# c\n4 5 6\n", b"1 2 3\n4 5 6\n\n"],
)  # fmt: skip
def test_the_lines_of_a_piece_are_counted_from_its_rows_only_where_that_is_exact(text):
    """The next piece's line numbers start after this piece's line ends: where pyarrow parsed
    a text without blank lines they are its rows and the comments at its top, else counted."""
    for skip in (0, 1):
        layout = TextLayout(None, skip, 3, (0, 1, 2), fmt="plain")
        try:
            _, lines = read_rows(text, "f", layout, bulk=True)
        except A2bError:
            continue
        assert lines.count() == text.count(b"\n"), (text, skip, lines.plain)
