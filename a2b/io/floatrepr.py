"""Fast, exact text for float64 arrays: Python's ``repr`` of every entry, vectorised.

Writing a million poses as CSV calls for 8 million float-to-text conversions. ``repr`` per
float (or ``numpy.savetxt``) manages a few hundred thousand rows per second. This module
produces the same text with array operations, so CSV output keeps full round-trip precision
at several times that speed.

Method
------
For a finite ``x`` with ``1e-250 < |x| < 1e250`` let ``e = floor(log10 |x|)`` and
``X = |x| · 10^(16 − e)``, computed in double-double arithmetic (Dekker's exact product with a
double-double table of powers of ten). The absolute error of ``X`` is below ``1e-14``, so the
integer ``D17 = round(X)`` is the correctly rounded 17-digit decimal of ``x`` except within
``1e-14`` of a tie, where either neighbour is still within half an ulp of ``x``. A decimal
``v`` reads back as ``x`` if ``|v − X| < U``, where ``U`` is half the spacing of doubles at
``x`` in the same units. The shortest of the nearest 15-, 16- and 17-digit candidates that
passes this test *with a safety margin* is used; the 17-digit one always passes. Stripping its
trailing zeros gives the shortest digits, which is what ``repr`` prints. Everything outside the
fast range (zero, subnormals, huge values, NaN, infinity, and the rare candidate the margin
cannot decide) is formatted with ``repr`` itself (zeros by a table), so the output always reads back bit for bit.
"""

from __future__ import annotations

from fractions import Fraction
from itertools import pairwise

import numpy as np

__all__ = ["format_rows"]

_LO_EXP, _HI_EXP = -250, 250
_K_MIN, _K_MAX = 16 - _HI_EXP - 1, 16 - _LO_EXP + 1
_SPLIT = 134217729.0  # 2**27 + 1, Veltkamp's constant
_MARGIN = 1e-6  # in units of the 17th digit; the error of X is below 1e-14


def _pow10_table() -> tuple[np.ndarray, np.ndarray]:
    hi = np.empty(_K_MAX - _K_MIN + 1)
    lo = np.empty_like(hi)
    for i, k in enumerate(range(_K_MIN, _K_MAX + 1)):
        exact = Fraction(10) ** k
        h = float(exact)
        hi[i] = h
        lo[i] = float(exact - Fraction(h))
    return hi, lo


_P10_HI, _P10_LO = _pow10_table()


def _split(a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    c = _SPLIT * a
    high = c - (c - a)
    return high, a - high


def _scaled(ax: np.ndarray, k: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``ax · 10^k`` as an unevaluated sum ``s + r`` (double-double)."""
    hi = _P10_HI[k - _K_MIN]
    lo = _P10_LO[k - _K_MIN]
    p = ax * hi
    ah, al = _split(ax)
    hh, hl = _split(hi)
    err = ((ah * hh - p) + ah * hl + al * hh) + al * hl
    tail = err + ax * lo
    s = p + tail
    r = tail - (s - p)
    return s, r


def _digits17(ax: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """17-digit integers ``D`` in ``[1e16, 1e17)``, decimal exponents ``e`` and residuals
    ``X − D`` (in units of the 17th digit) for positive ``ax`` in the fast range."""
    e = np.floor(np.log10(ax)).astype(np.int64)
    for _ in range(3):  # log10 can be off by one next to powers of ten
        s, r = _scaled(ax, 16 - e)
        base = np.floor(s)
        frac = (s - base) + r
        step = np.floor(frac + 0.5)
        d = base.astype(np.int64) + step.astype(np.int64)
        resid = frac - step
        tie = (resid == -0.5) & (d % 2 == 1)  # round half to even, as repr does
        d = d - tie
        resid = resid + tie
        high = d >= 10**17
        low = d < 10**16
        if not (high.any() or low.any()):
            return d, e, resid
        e = e + high - low
    raise AssertionError("decimal exponent did not settle")  # pragma: no cover


def _shortest(
    d: np.ndarray, e: np.ndarray, resid: np.ndarray, half_ulp: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Replace ``d`` by its nearest multiple of 100, else of 10, where that surely reads back.

    A candidate ``c`` reads back as ``x`` when ``|c − X| < U`` (``U = half_ulp``). Returns the
    chosen integers, their exponents, and a mask of the entries whose choice the margin cannot
    decide (they are left to ``repr``).
    """
    out = d.copy()
    done = np.zeros(d.shape, dtype=bool)
    undecided = np.zeros(d.shape, dtype=bool)
    for unit in (100, 10):
        below = d - d % unit
        above = below + unit
        dist_below = np.abs((below - d).astype(float) - resid)
        dist_above = np.abs((above - d).astype(float) - resid)
        ok_below = dist_below < half_ulp - _MARGIN
        ok_above = dist_above < half_ulp - _MARGIN
        unsure = (np.abs(dist_below - half_ulp) <= _MARGIN) | (np.abs(dist_above - half_ulp) <= _MARGIN)
        nearer_above = (dist_above < dist_below) | (
            (dist_above == dist_below) & ((above // unit) % 2 == 0)  # a tie goes to even, as repr
        )
        pick_above = ok_above & (~ok_below | nearer_above)
        take = (ok_below | ok_above) & ~done & ~undecided
        out = np.where(take, np.where(pick_above, above, below), out)
        undecided |= unsure & ~done & ~take
        done |= take
    carry = out >= 10**17
    out = np.where(carry, out // 10, out)
    return out, e + carry, undecided


_WIDTH = 25  # longest repr: "-1.2345678901234567e-250" has 24 characters
_ZERO = ord("0")
_PAIRS = np.frombuffer("".join(f"{i:02d}" for i in range(100)).encode(), dtype=np.uint16)


def _render(cells: np.ndarray, rows: np.ndarray, neg: np.ndarray, d: np.ndarray, e: np.ndarray) -> None:
    """Write ``±d · 10^(e − 16)`` in ``repr`` style into ``cells[rows]``.

    ``d`` has 17 digits. Cells that stay 0 are dropped when the text is joined, so digits
    are blanked rather than moved. Entries are grouped by exponent, which fixes the layout.
    """
    pairs = np.empty((d.shape[0], 9), dtype=np.uint16)  # base-100 digits as two characters
    rest = d
    for i in range(8, -1, -1):
        quotient = rest // 100  # a scalar divisor takes numpy's fast path; divmod does not
        pairs[:, i] = _PAIRS[rest - 100 * quotient]
        rest = quotient
    chars = pairs.view(np.uint8)[:, 1:]  # (n, 17): drop the leading pad digit
    nonzero = chars != _ZERO
    ndig = 17 - np.argmax(nonzero[:, ::-1], axis=1)  # significant digits
    chars *= np.arange(17)[None, :] < ndig[:, None]  # blank trailing zeros
    order = np.argsort(e.astype(np.int16), kind="stable")  # a radix sort for 16-bit keys
    e, chars, ndig = e[order], chars[order], ndig[order]
    sign = np.where(neg[order], np.uint8(ord("-")), np.uint8(0))[:, None]
    out = np.zeros((len(order), _WIDTH), dtype=np.uint8)
    bounds = np.concatenate([[0], np.flatnonzero(np.diff(e)) + 1, [len(e)]])
    for lo, hi in pairwise(bounds):
        ex = int(e[lo])
        g = chars[lo:hi]
        n = hi - lo
        if 0 <= ex < 16:
            integer = g[:, : ex + 1]
            integer[integer == 0] = _ZERO  # integer-part zeros are printed
            frac = g[:, ex + 1 :]
            frac[:, 0] |= np.uint8(_ZERO)  # at least "x.0" (a blank 0 becomes "0")
            block = np.hstack([sign[lo:hi], integer, np.full((n, 1), ord("."), np.uint8), frac])
        elif -4 <= ex < 0:
            lead = np.frombuffer(b"0." + b"0" * (-ex - 1), dtype=np.uint8)
            block = np.hstack([sign[lo:hi], np.broadcast_to(lead, (n, len(lead))), g])
        else:
            tail = np.frombuffer(f"e{ex:+03d}".encode(), dtype=np.uint8)
            block = np.hstack(
                [
                    sign[lo:hi],
                    g[:, :1],
                    np.full((n, 1), ord("."), np.uint8) * (ndig[lo:hi] > 1)[:, None],
                    g[:, 1:],
                    np.broadcast_to(tail, (n, len(tail))),
                ]
            )
        out[lo:hi, : block.shape[1]] = block
    cells[rows[order], :_WIDTH] = out


def format_rows(values: np.ndarray, sep: str = ",", prefix: list[str] | None = None) -> bytes:
    """Render a 2-d float array as delimited text, one line per row, ``repr`` of every entry.

    Parameters
    ----------
    values : array_like, shape (n, k)
        Any floats, including NaN, infinity, zero and subnormals.
    sep : str
        The one-character field separator.
    prefix : list of str, optional
        A first field per row (for example a job name), written before the numbers.

    Returns
    -------
    bytes
        ``n`` lines, each ending in ``"\\n"``; ``float(field) == value`` for every entry.
    """
    a = np.ascontiguousarray(values, dtype=np.float64)
    n, k = a.shape
    if n == 0:
        return b""
    flat = a.ravel()
    ax = np.abs(flat)
    fast = (ax > 10.0**_LO_EXP) & (ax < 10.0**_HI_EXP)  # excludes 0, NaN, inf, subnormals
    idx = np.flatnonzero(fast)
    cells = np.zeros((flat.size, _WIDTH + 1), dtype=np.uint8)
    if idx.size:
        axf = ax[idx]
        d, e, resid = _digits17(axf)
        exp2 = np.frexp(axf)[1].astype(np.int64)  # axf in [2^(exp2-1), 2^exp2)
        # half an ulp of x, in units of the 17th digit: 2^(exp2 - 54) · 10^(16 − e)
        half_ulp = np.ldexp(_P10_HI[16 - e - _K_MIN], exp2 - 54)
        d, e, undecided = _shortest(d, e, resid, half_ulp)
        keep = ~undecided
        _render(cells, idx[keep], np.signbit(flat[idx[keep]]), d[keep], e[keep])
        fast[idx[undecided]] = False
    zero = flat == 0.0
    negative_zero = zero & np.signbit(flat)
    cells[zero & ~negative_zero, :3] = np.frombuffer(b"0.0", dtype=np.uint8)
    cells[negative_zero, :4] = np.frombuffer(b"-0.0", dtype=np.uint8)
    fast |= zero
    for i in np.flatnonzero(~fast):
        text = repr(float(flat[i])).encode()
        cells[i, : len(text)] = np.frombuffer(text, dtype=np.uint8)
    sep_b = sep.encode()
    if len(sep_b) != 1:
        raise ValueError(f"the separator must be one character, got {sep!r}")
    last = cells[:, _WIDTH].reshape(n, k)
    last[:, :-1] = sep_b[0]
    last[:, -1] = ord("\n")
    if prefix is not None:
        head = np.zeros((n, max(len(p) for p in prefix) + 1), dtype=np.uint8)
        for i, p in enumerate(prefix):
            b = p.encode() + sep_b
            head[i, : len(b)] = np.frombuffer(b, dtype=np.uint8)
        table = np.hstack([head, cells.reshape(n, k * (_WIDTH + 1))])
        return table[table != 0].tobytes()
    return cells[cells != 0].tobytes()
