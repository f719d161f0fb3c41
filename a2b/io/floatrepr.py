"""Fast, exact text for float64 arrays: Python's ``repr`` of every entry, vectorised.

Writing a million poses as CSV calls for 8 million float-to-text conversions. ``repr`` per
float (or ``numpy.savetxt``) manages a few hundred thousand rows per second. This module
produces the same text with whole-array operations, a few dozen nanoseconds per number, so
CSV and MCAP output keep full round-trip precision at many times that speed.

Method
------
For a finite ``x`` with ``2^-830 <= |x| < 2^830`` (about ``1e-250`` to ``1e250``) let
``e = floor(log10 |x|)``, found from the binary exponent and one comparison with a table of
powers of ten, and ``X = |x| · 10^(16 − e)``, computed as an unevaluated sum of two doubles
with Dekker's exact product [1]_ and a double-double table of powers of ten. The error of
``X`` is below ``1e-14``, in units of the 17th significant digit. ``X`` lies in
``[1e16, 1e17)``. A decimal ``c`` reads back as ``x`` if ``|c − X| < U``, where ``U`` is half
the spacing of doubles at ``x`` in the same units (between 0.55 and 11). ``repr`` prints the
shortest such decimal, and of those the nearest to ``x`` [2]_. Doubles carry 15.95 digits,
so it has 15 or fewer digits exactly when the multiple of 100 nearest to ``X`` reads back
(then its trailing zeros are dropped), else 16 when the multiple of 10 nearest to ``X`` does,
else it is the 17-digit rounding of ``X``. Each test is made with a margin of ``1e-6``; the
rare number within the margin of a decision, at a tie, or a power of two whose digits do not
end exactly (the doubles below a power of two are twice as dense) is formatted with
``repr`` itself, as is everything outside the range above except zero (NaN, infinity,
subnormals, huge numbers).

The 17 digits ``c0 … c16`` are turned into characters four at a time through a table, in
little-endian 64-bit words, and laid out in a cell of four words::

    [separator, sign, "0.00", c0, "."] [c1 … c8] [c9 … c16] [spill | "e-05", line end]

Digits that ``repr`` does not print (trailing zeros) are zero bytes, as are the unused
places; one masked pass (:func:`without_zero_bytes`) removes the zero bytes of all cells at once.
Numbers printed as ``123.456`` (exponent 1 to 15) move their digits after ``c_e`` up by one
byte to make room for the point; the last one spills into the fourth word.
The first word's text ends at its last byte, after at least one unused byte, which takes the
separator before the number in a row (:func:`_row_cells`); the exponent ends in byte 30, before
the line end. So a number of a row is one run of bytes (two with an exponent) between zero
bytes, and the masked pass, which copies run by run, is fastest: 0.22 ms a block of 2,048 rows
of 8 numbers, against 0.33 ms with 2.9 runs a number (each word's text at its start, and the
separator after the number).

References
----------
.. [1] T. J. Dekker, "A floating-point technique for extending the available precision",
   Numerische Mathematik 18 (1971), 224–242.
.. [2] G. L. Steele and J. L. White, "How to print floating-point numbers accurately",
   PLDI 1990; Python's ``float.__repr__`` (``repr`` since Python 3.1).
"""

from __future__ import annotations

import numpy as np

__all__ = ["BLOCK", "format_rows", "integer_words", "number_words", "text_words"]

#: Numbers formatted per pass: large enough to amortise numpy's per-call cost, which is also
#: the part of the work done under the GIL. Two threads formatted 10^6 rows of 8 numbers 1.15×
#: as fast as one with 16,384, 1.47× with 65,536 (one thread the same), where the allocator
#: keeps the few-MB temporaries (see ``a2b.cli``).
BLOCK = 65536

_U64 = np.uint64


def _ix(index: np.ndarray) -> np.ndarray:
    """Indexes for ``take``: unsigned words viewed as int64 (numpy before 2.0 will not cast)."""
    return index.view(np.int64) if index.dtype == _U64 else index


_E_MIN, _E_MAX = -260, 260  # decimal exponents the tables cover
_NE = _E_MAX - _E_MIN + 1
_BEXP_LO, _BEXP_HI = 1023 - 830, 1023 + 830  # biased binary exponents of the fast range
_LOG10_2 = 0.30102999566398120
_MARGIN = 1e-6  # in units of the 17th digit; the error of X is below 1e-14
_ABS = _U64(2**63 - 1)
_HIGH_26 = _U64(2**64 - 2**27)  # the top 26 bits of the significand (with sign and exponent)


def _word(text: bytes) -> int:
    """Up to eight bytes as a little-endian integer: the first byte is the lowest."""
    return int.from_bytes(text.ljust(8, b"\0"), "little")


def _power_of_ten(k: int) -> tuple[float, float]:
    """``10^k`` as the nearest double and the nearest double to the rest (int arithmetic is
    exact, and int / int is correctly rounded)."""
    if k >= 0:
        hi = float(10**k)
        return hi, float(10**k - int(hi))
    hi = 1 / 10**-k
    a, b = hi.as_integer_ratio()
    return hi, (b - a * 10**-k) / (b * 10**-k)


def _exponent_tables():
    es = range(_E_MIN, _E_MAX + 1)
    next_p10 = np.array([_power_of_ten(e + 1)[0] for e in es])
    hi, lo = np.array([_power_of_ten(16 - e) for e in es]).T
    # the first word, at index i + 1024 (if negative) + 2048 (if c0 stands alone): the sign and
    # "0.000", then c0 (here "0"), then "." if the point follows c0, ending at byte 7
    head = np.zeros(4096, _U64)
    digit_at = np.zeros(4096, _U64)  # the bit where c0 starts: 56, or 48 before a point
    before = np.zeros(4096, _U64)  # the bit where the zero byte before the text starts
    head_len = np.zeros(4096, np.int64)  # the characters of everything but c1 … c16
    suffix = np.zeros(_NE, _U64)  # "e-05" ending at byte 6 of the fourth word, before byte 7
    keep = np.ones(_NE, np.int8)  # c0, and if positional the digits to the point and one after
    for j, e in enumerate(es):
        positional = 0 <= e < 16
        small = -4 <= e < 0
        exp_text = b"" if positional or small else f"e{e:+03d}".encode()
        if exp_text:
            suffix[j] = _word(exp_text) << 8 * (7 - len(exp_text))
        if positional:
            keep[j] = e + 2
        for alone in (0, 1):
            for neg in (0, 1):
                text = (b"-" if neg else b"") + (b"0." + b"0" * (-e - 1) if small else b"")
                point = e == 0 or (not positional and not small and not alone)
                at = j + 1024 * neg + 2048 * alone
                first = text + b"0" + b"." * point
                head[at] = _word(first) << 8 * (8 - len(first))
                digit_at[at] = 56 - 8 * point
                before[at] = 8 * (7 - len(first))
                head_len[at] = len(text) + 1 + (point or 1 <= e < 16) + len(exp_text)
    c = 134217729.0 * hi  # Veltkamp's split of hi into two 26-bit halves
    hh = c - (c - hi)
    # and with each digit c0 in its place: at index 16 · (the index above) + c0
    head = (head[:, None] + (np.arange(16, dtype=_U64) << digit_at[:, None])).reshape(-1)
    return next_p10, hi, hh, hi - hh, lo, head, head_len, suffix, keep, before


_NEXT_P10, _HI, _HH, _HL, _LO, _HEAD, _HEAD_LEN, _SUFFIX, _KEEP, _BEFORE = _exponent_tables()
_ALONE = np.where(np.arange(18) == 0, 2048, 0)  # the head's offset by significant digits
#: The table index of floor(log10 |x|), or of one less, by the biased binary exponent of x.
_FROM_BINARY = np.clip(
    np.floor((np.arange(2048) - 1023) * _LOG10_2).astype(np.intp) - _E_MIN, 0, _NE - 2
)

#: Four digits as characters, in the low and the high half of a word.
_GROUPS = np.arange(10000)
_DIGITS_LO = np.zeros(10000, _U64)
for _k, _unit in enumerate((1000, 100, 10, 1)):
    _DIGITS_LO |= (_GROUPS // _unit % 10 + 48).astype(_U64) << _U64(8 * _k)
_DIGITS_HI = _DIGITS_LO << _U64(32)
_SIGNIFICANT = 4 - sum((_GROUPS % m == 0).astype(np.int8) for m in (10, 100, 1000))


def _digit_count(offset: int) -> np.ndarray:
    """Digits up to the last non-zero one of a group that starts after ``offset`` digits."""
    return np.where(_GROUPS == 0, 0, offset + _SIGNIFICANT).astype(np.int8)


_COUNT1, _COUNT2, _COUNT3, _COUNT4 = (_digit_count(o) for o in (1, 5, 9, 13))


def _mask_tables():
    # keep c_d (d = 1 … 16, byte d − 1 of words 1 and 2) if d < shown
    keep1 = np.zeros(18, _U64)
    keep2 = np.zeros(18, _U64)
    for shown in range(18):
        for d in range(1, min(shown, 17)):
            w, o = divmod(d - 1, 8)
            (keep1, keep2)[w][shown] |= _U64(0xFF << (8 * o))
    # the point after c_e, e = 1 … 15: c1 … c_e stay, the rest move up one byte
    low1 = np.zeros(16, _U64)
    low2 = np.zeros(16, _U64)
    point1 = np.zeros(16, _U64)
    point2 = np.zeros(16, _U64)
    for e in range(1, 16):
        for byte in range(e):
            w, o = divmod(byte, 8)
            (low1, low2)[w][e] |= _U64(0xFF << (8 * o))
        w, o = divmod(e, 8)
        (point1, point2)[w][e] |= _U64(ord(".") << (8 * o))
    return keep1, keep2, low1, low2, point1, point2


_KEEP1, _KEEP2, _LOW1, _LOW2, _POINT1, _POINT2 = _mask_tables()


def _scaled(x: np.ndarray):
    """The decimal exponent of each ``|x|`` and Dekker's product ``X = |x| · 10^(16 − e)``.

    Parameters
    ----------
    x : ndarray of float64, shape (n,)
        Contiguous.

    Returns
    -------
    abits : ndarray of uint64
        The bits of ``|x|``; 1.0 stands in for the numbers outside the fast range.
    bexp : ndarray of uint64
        The biased binary exponent of ``|x|`` (1023 for the stand-ins).
    slow : ndarray of bool, or None
        The numbers outside the fast range (zeros, subnormals, huge ones, NaN, infinity);
        ``None`` if there are none.
    i : ndarray of intp
        ``e − E_MIN``, the index of the decimal exponent ``e = floor(log10 |x|)`` into the
        tables; one too large for the double nearest ``10^k`` where that lies below ``10^k``
        (:func:`_settled` hands these to ``repr``).
    hi : ndarray of float64
        ``10^(16 − e)`` to the nearest double.
    s, r : ndarray of float64
        ``X = s + r``: ``s`` an integer (``X > 2^53``), ``r`` the rest, ``|r| <= 8``.
    """
    abits = x.view(_U64) & _ABS
    ax = abits.view(np.float64)
    bexp = abits >> _U64(52)
    fast = (bexp - _U64(_BEXP_LO)) < _U64(_BEXP_HI - _BEXP_LO)  # wraps below the range
    slow = None
    if not fast.all():  # stand-ins for now; ax is a view of abits
        slow = ~fast
        ax[slow] = 1.0
        bexp[slow] = 1023
    # the decimal exponent from the binary one, then one comparison with the next power of ten
    i = _FROM_BINARY.take(_ix(bexp))
    i += ax >= _NEXT_P10.take(_ix(i))
    # Dekker's product of |x| = ah + al and 10^(16 − e) = hi + lo, hi = hh + hl
    hi = _HI.take(_ix(i))
    p = ax * hi
    ah = (abits & _HIGH_26).view(np.float64)
    al = ax - ah
    hh = _HH.take(_ix(i))
    hl = _HL.take(_ix(i))
    err = ah * hh
    err -= p
    err += ah * hl
    err += al * hh
    err += al * hl
    err += ax * _LO.take(_ix(i))
    s = p + err
    p -= s
    p += err  # now the rest r
    return abits, bexp, slow, i, hi, s, p


def _rounded(abits: np.ndarray, bexp: np.ndarray, hi: np.ndarray, s: np.ndarray, r: np.ndarray):
    """The shortest digits that read back: the 15-, 16- or 17-digit rounding of ``X = s + r``.

    Parameters
    ----------
    abits, bexp, hi, s, r : ndarray
        As :func:`_scaled` returns them; ``s`` and ``r`` are overwritten.

    Returns
    -------
    high : ndarray of float64
        ``c0 … c8`` as an integer, in ``[1e8, 1e9]`` (``1e9``: rounded up to ``10^(e + 1)``;
        below ``1e8``: ``e`` came out one too large).
    low : ndarray of float64
        ``c9 … c16`` as an integer in ``[0, 1e8)``, trailing zeros where fewer digits suffice.
    unsure : ndarray of bool
        The numbers within the margin of a decision, at a tie, or powers of two whose
        digits do not end exactly: :func:`number_words` hands these to ``repr``.
    """
    high = np.floor(s * 1e-8)  # c0 … c8, or one less
    s -= high * 1e8  # in [0, 2e8)
    step = np.rint(r)
    xl = s + r  # X − high · 1e8, within 1e-8
    low = s  # c9 … c16 of the 17-digit rounding, before carries
    low += step
    r -= step  # its distance to X
    half = ((bexp - _U64(53)) << _U64(52)).view(np.float64)  # half an ulp of |x| …
    half *= hi  # … in units of the 17th digit
    c2 = np.rint(xl * 0.01)
    c2 *= 100.0  # the nearest 15-digit decimal (a tie is never near enough)
    d2 = np.abs(c2 - xl)
    d2 -= half
    c1 = np.rint(xl * 0.1)
    c1 *= 10.0  # the nearest 16-digit decimal (a tie is flagged below)
    d1 = np.abs(c1 - xl)
    d1 -= half
    # low = c1 where d1 < −margin, then c2 where d2 < −margin: integers below 2^53, so the
    # differences and sums are exact. (numpy.where branches on each element, and a number
    # needs 16 digits about as often as not: 200 µs for 65,536 numbers, these passes 43 µs.)
    np.subtract(c1, low, out=step)
    step *= d1 < -_MARGIN
    low += step
    np.subtract(c2, low, out=step)
    step *= d2 < -_MARGIN
    low += step
    np.abs(d2, out=d2)
    np.abs(d1, out=d1)
    unsure = np.minimum(d1, d2) <= _MARGIN
    d1 = np.abs(c1 - xl)
    unsure |= d1 >= 5.0 - _MARGIN  # a tie between two 16-digit decimals
    unsure |= np.abs(r) >= 0.5 - _MARGIN  # a tie between two 17-digit decimals
    power_of_two = (abits << _U64(12)) == 0
    if power_of_two.any():
        unsure |= power_of_two & ~((r == 0.0) & (c2 == xl))
    carry = np.floor(low / 1e8)  # -1, 0, 1 or 2: low is within [-8, 2e8]; exact division
    high += carry
    low -= carry * 1e8
    return high, low, unsure


def _settled(x, slow, i, high, low, bad) -> bool:
    """Settle the edge cases in place, and say whether any number is left to ``repr``.

    Zeros get ``c0 = 0``; a rounding up to ``10^(e + 1)`` moves ``i`` up one; the numbers
    outside the fast range and those ``e`` came out too large for join ``bad``, and their
    digits become ``1`` followed by zeros, harmless stand-ins for :func:`number_words` to
    overwrite.
    """
    bad |= high < 1e8  # |x| = 10^k rounded down: e came out one too large
    if slow is not None:
        zero = x == 0.0
        bad |= slow & ~zero
        high[zero] = 0.0  # "0.0" comes out of the positional layout with c0 = 0
    up = high >= 1e9  # rounded up to 10^(e + 1)
    if up.any():
        high[up] = 1e8
        i += up
    any_bad = bool(bad.any())
    if any_bad:
        high[bad] = 1e8
        low[bad] = 0.0
    return any_bad


def _groups(high: np.ndarray, low: np.ndarray, i: np.ndarray):
    """The digits in groups of four, and how many of them ``repr`` shows.

    Parameters
    ----------
    high, low : ndarray of float64
        ``c0 … c8`` and ``c9 … c16`` as integers, settled by :func:`_settled`.
    i : ndarray of intp
        The index of the decimal exponent.

    Returns
    -------
    c0 : ndarray of int64
        The first digit.
    g1, g2, g3, g4 : ndarray of int64
        ``c1 … c4``, ``c5 … c8``, ``c9 … c12``, ``c13 … c16``, each in ``[0, 10^4)``.
    count : ndarray of int8
        The significant digits up to the last non-zero one (0: ``c0`` alone).
    shown : ndarray of intp
        The digits shown: ``count``, and if positional at least the digits before the point
        and one after it, ``1 + e + 1``.
    """
    high_i = high.astype(np.int64)  # c0 … c8
    g4 = low.astype(np.int64)  # c9 … c16
    c0 = high_i // 100_000_000
    high_i -= c0 * 100_000_000
    g1 = high_i // 10_000
    g2 = high_i
    g2 -= g1 * 10_000
    g3 = g4 // 10_000
    g4 -= g3 * 10_000
    count = np.maximum(_COUNT1.take(_ix(g1)), _COUNT2.take(_ix(g2)))
    np.maximum(count, _COUNT3.take(_ix(g3)), out=count)
    np.maximum(count, _COUNT4.take(_ix(g4)), out=count)
    shown = np.maximum(count, _KEEP.take(_ix(i))).astype(np.intp)
    return c0, g1, g2, g3, g4, count, shown


def _cells(sign, i, c0, g1, g2, g3, g4, count, shown):
    """The four words of each cell: head, digits ``c1 … c8``, ``c9 … c16``, tail.

    Parameters
    ----------
    sign : ndarray of uint64
        The bits of ``x`` (only the sign bit is read).
    i, c0, g1, g2, g3, g4, count, shown : ndarray
        As :func:`_groups` returns them (and ``i`` as settled).

    Returns
    -------
    out : ndarray of uint64, shape (n, 4)
        The cells as :func:`number_words` describes them.
    head : ndarray of int64
        Each cell's index into the head tables (sign, exponent, ``c0`` alone).
    """
    w1 = _DIGITS_LO.take(_ix(g1))
    w1 |= _DIGITS_HI.take(_ix(g2))
    w1 &= _KEEP1.take(_ix(shown))
    w2 = _DIGITS_LO.take(_ix(g3))
    w2 |= _DIGITS_HI.take(_ix(g4))
    w2 &= _KEEP2.take(_ix(shown))
    head = ((sign >> _U64(53)) & _U64(1024)).view(np.int64)  # the sign, as 1024
    head |= i
    head |= _ALONE.take(_ix(count))
    first = head << 4
    first |= c0
    w0 = _HEAD.take(_ix(first))
    w3 = _SUFFIX.take(_ix(i))
    positional = (i - (1 - _E_MIN)).view(_U64) < _U64(15)  # 1 <= e <= 15: "123.456"
    if positional.any():
        _insert_point(np.flatnonzero(positional), i, w1, w2, w3)
    out = np.empty((len(i), 4), _U64)
    out[:, 0] = w0
    out[:, 1] = w1
    out[:, 2] = w2
    out[:, 3] = w3
    return out, head


def _insert_point(at, i, w1, w2, w3) -> None:
    """Put the point after ``c_e`` in the cells ``at`` (``1 <= e <= 15``), in place.

    ``c1 … c_e`` stay; the digits after them move up one byte in ``w1`` and ``w2``, the
    last byte of ``w1`` into ``w2`` and the last of ``w2`` into ``w3``.
    """
    e = i.take(_ix(at)) + _E_MIN
    a = w1.take(_ix(at))
    b = w2.take(_ix(at))
    la = a & _LOW1.take(_ix(e))
    a ^= la
    lb = b & _LOW2.take(_ix(e))
    b ^= lb
    w1[at] = la | (a << _U64(8)) | _POINT1.take(_ix(e))
    w2[at] = lb | (b << _U64(8)) | (a >> _U64(56)) | _POINT2.take(_ix(e))
    w3[at] = b >> _U64(56)


def number_words(x: np.ndarray, lengths: bool = False):
    """``repr`` of each entry of ``x`` as a cell of four little-endian words, zero-padded.

    The stages: :func:`_scaled` (decimal exponent and Dekker's product), :func:`_rounded`
    (the shortest rounding and the unsure cases), :func:`_settled` (zeros, carries, the
    numbers left to ``repr``), :func:`_groups` (digit groups and counts) and :func:`_cells`
    (the four words).

    Parameters
    ----------
    x : ndarray, shape (n,)
        Contiguous float64.
    lengths : bool
        Also return the number of characters of each entry.

    Returns
    -------
    words : ndarray of uint64, shape (n, 4)
        The characters of ``repr(x[i])`` in order, with zero bytes between them; byte 31
        (the top byte of the last word) and the byte before the text are zero, free for a
        line end and a separator.
    length : ndarray of int64, shape (n,)
        Only if ``lengths``.
    """
    x = np.ascontiguousarray(x, dtype=np.float64).reshape(-1)
    out, head, shown, bad = _number_cells(x)
    if not lengths:
        return out
    length = _HEAD_LEN.take(_ix(head))
    length += shown
    length -= 1
    for j in bad:
        length[j] = len(repr(float(x[j])))
    return out, length


def _number_cells(x: np.ndarray):
    """:func:`number_words` of contiguous float64 ``x``, and for each number its index into
    the head tables and the digits shown; and the indexes of the numbers ``repr`` formatted
    (their text starts at byte 1)."""
    abits, bexp, slow, i, hi, s, r = _scaled(x)
    high, low, bad = _rounded(abits, bexp, hi, s, r)
    any_bad = _settled(x, slow, i, high, low, bad)
    c0, g1, g2, g3, g4, count, shown = _groups(high, low, i)
    out, head = _cells(x.view(_U64), i, c0, g1, g2, g3, g4, count, shown)
    bad = np.flatnonzero(bad) if any_bad else np.empty(0, np.intp)
    for j in bad:
        out[j] = np.frombuffer(b"\0" + repr(float(x[j])).encode().ljust(31, b"\0"), _U64)
    return out, head, shown, bad


def integer_words(v: np.ndarray, lengths: bool = False):
    """Decimal text of non-negative integers below ``10^16``, as two zero-padded words each.

    Leading zeros are zero bytes (``0`` itself is ``"0"``), so :func:`without_zero_bytes`
    turns the cells into the numbers' text. With ``lengths``, also return the number of
    digits of each.
    """
    v = np.asarray(v, dtype=np.int64).reshape(-1)
    if v.size and (v.min() < 0 or v.max() >= 10**16):
        raise ValueError("integer_words takes integers in [0, 10**16)")
    high = v // 100_000_000
    low = v - high * 100_000_000
    groups = np.empty((v.size, 4), np.intp)
    groups[:, 0] = high // 10000
    groups[:, 1] = high - groups[:, 0] * 10000
    groups[:, 2] = low // 10000
    groups[:, 3] = low - groups[:, 2] * 10000
    digits = np.empty((v.size, 2), _U64)
    digits[:, 0] = _DIGITS_LO.take(_ix(groups[:, 0])) | _DIGITS_HI.take(_ix(groups[:, 1]))
    digits[:, 1] = _DIGITS_LO.take(_ix(groups[:, 2])) | _DIGITS_HI.take(_ix(groups[:, 3]))
    # blank the leading zeros: keep the last ``width`` of 16 bytes
    width = np.ones(v.size, np.intp)
    for k in range(1, 16):
        width += v >= 10**k
    digits &= _LEADING.take(_ix(width), axis=0)
    return (digits, width) if lengths else digits


def _leading_masks() -> np.ndarray:
    masks = np.zeros((17, 2), _U64)
    for width in range(17):
        for byte in range(16 - width, 16):
            w, o = divmod(byte, 8)
            masks[width, w] |= _U64(0xFF << (8 * o))
    return masks


_LEADING = _leading_masks()


def _row_cells(a: np.ndarray, sep: int) -> np.ndarray:
    """The cells of a 2-d array, separators and line ends in place: (n, 4 k) words.

    Each separator goes in the zero byte before the text of the next number, and the line end
    in byte 31 of the last: the text of a row is then one run of bytes per number (two where
    an exponent ends in byte 30), which :func:`without_zero_bytes` copies fastest.
    """
    n, k = a.shape
    cells, head, _, bad = _number_cells(a.reshape(-1))
    cells = cells.reshape(n, k, 4)
    cells[:, -1, 3] |= _U64(ord("\n") << 56)
    if k > 1:
        before = _BEFORE.take(_ix(head))
        before[bad] = 0
        cells[:, 1:, 0] |= _U64(sep) << before.reshape(n, k)[:, 1:]
    return cells.reshape(n, 4 * k)


def format_rows(values, sep: str = ",", prefix=None, array: bool = False):
    """Render a 2-d float array as delimited text, one line per row, ``repr`` of every entry.

    Parameters
    ----------
    values : array_like, shape (n, k)
        Any floats, including NaN, infinity, zero and subnormals.
    sep : str
        The one-character field separator.
    prefix : sequence of str, or ndarray, optional
        Leading fields per row (for example a job name), written before the numbers. Strings
        get a separator after them. An ``S`` array is taken as already encoded, separators
        included, and so is a ``uint64`` array ``(n, w)`` of text words as
        :func:`number_words` makes them (little-endian, zero bytes skipped).
    array : bool
        Return the text as an array of bytes (``uint8``), as it is made, rather than copied
        into ``bytes``: a stream writes either.

    Returns
    -------
    bytes, or ndarray of uint8
        ``n`` lines, each ending in ``"\\n"``; ``float(field) == value`` for every entry.
    """
    sep_b = sep.encode()
    if len(sep_b) != 1 or sep_b == b"\0":
        raise ValueError(f"the separator must be one character, got {sep!r}")
    a = np.ascontiguousarray(values, dtype=np.float64)
    if a.ndim != 2:
        raise ValueError(f"format_rows takes a 2-d array, got shape {a.shape}")
    n, k = a.shape
    if n == 0:
        return np.empty(0, np.uint8) if array else b""
    head = None if prefix is None else _prefix_words(prefix, sep_b)
    if head is not None and len(head) != n:
        raise ValueError(f"{len(head)} prefixes for {n} rows")
    rows = max(1, BLOCK // max(k, 1))
    parts = []
    for lo in range(0, n, rows):
        cells = _row_cells(a[lo : lo + rows], sep_b[0])
        if head is not None:
            lead = head[lo : lo + rows]
            line = np.empty((len(cells), lead.shape[1] + cells.shape[1]), _U64)
            line[:, : lead.shape[1]] = lead
            line[:, lead.shape[1] :] = cells
            cells = line
        parts.append(_nonzero(cells))
    if len(parts) > 1:
        return np.concatenate(parts) if array else b"".join(parts)
    return parts[0] if array else parts[0].tobytes()


def without_zero_bytes(cells: np.ndarray) -> bytes:
    """The bytes of ``cells`` with every zero byte removed: the text the cells hold.

    A boolean index, which releases the GIL, so two formatting threads run side by side (not
    :meth:`bytes.translate`, which holds it). Not ``numpy.compress``: it was 0.1 ms a block of
    2,048 rows of 8 numbers faster, but it turns the mask into 8-byte indices first, eight
    times the text, and the MCAP messages of a 128 kB frame id doubled the peak memory
    (245 MB against 119 MB; ``tests/test_hardening.py`` caps it at 200).
    """
    return _nonzero(cells).tobytes()


def _nonzero(cells: np.ndarray) -> np.ndarray:
    """:func:`without_zero_bytes` as an array of bytes (``bytes.join`` takes it uncopied)."""
    flat = np.ascontiguousarray(cells).view(np.uint8).reshape(-1)
    return flat[flat != 0]


def text_words(texts: np.ndarray) -> np.ndarray:
    """An ``S`` array's entries as zero-padded little-endian words ``(n, w)``."""
    width = -(-max(texts.itemsize, 1) // 8)
    padded = np.ascontiguousarray(texts, dtype=f"S{8 * width}")
    return padded.view(_U64).reshape(len(texts), width)


def _prefix_words(prefix, sep: bytes) -> np.ndarray:
    if isinstance(prefix, np.ndarray) and prefix.dtype == _U64:
        if prefix.ndim != 2:
            raise ValueError(f"prefix words must be 2-d, got shape {prefix.shape}")
        return prefix
    if not isinstance(prefix, np.ndarray):
        if any("\0" in p for p in set(prefix)):
            raise ValueError("a prefix contains a NUL character")
        prefix = np.array([p.encode() + sep for p in prefix], dtype=bytes)
    if prefix.dtype.kind != "S":
        raise ValueError(f"a prefix array must be of bytes or uint64 words, got {prefix.dtype}")
    return text_words(prefix)
