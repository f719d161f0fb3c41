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
cannot decide) is formatted with ``repr`` itself, so the output always reads back bit for bit.
"""

from __future__ import annotations

from fractions import Fraction

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
        high = d >= 10**17
        low = d < 10**16
        if not (high.any() or low.any()):
            return d, e, resid
        e = e + high - low
    raise AssertionError("decimal exponent did not settle")  # pragma: no cover


def _shortest(d: np.ndarray, resid: np.ndarray, half_ulp: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Replace ``d`` by its nearest multiple of 100, else of 10, when that surely reads back.

    Returns the chosen integers and a mask of the entries the margin could not decide between
    a shorter candidate and the 17-digit one (those are left to ``repr``).
    """
    out = d.copy()
    undecided = np.zeros(d.shape, dtype=bool)
    decided = np.zeros(d.shape, dtype=bool)
    for unit in (100, 10):
        below = d - d % unit
        for cand in (below, below + unit):
            dist = np.abs((cand - d).astype(float) - resid)
            sure = (dist < half_ulp - _MARGIN) & ~decided
            unsure = (np.abs(dist - half_ulp) <= _MARGIN) & ~decided
            undecided |= unsure
            # Prefer the nearer candidate of the two when both read back.
            other = below + unit if cand is below else below
            other_dist = np.abs((other - d).astype(float) - resid)
            take = sure & ((dist <= other_dist) | ~(other_dist < half_ulp - _MARGIN))
            out = np.where(take, cand, out)
            decided |= take
    return out, undecided & ~decided


def _to_text(neg: np.ndarray, d: np.ndarray, e: np.ndarray) -> np.ndarray:
    """Render ``±d · 10^(e − 16)`` in ``repr`` style into a fixed-width byte matrix.

    Unused cells hold 0 and are dropped later.
    """
    n = d.shape[0]
    width = 25
    powers = 10 ** np.arange(16, -1, -1, dtype=np.int64)
    digits = (d[:, None] // powers) % 10  # (n, 17), most significant first
    nz = digits != 0
    ndig = 17 - np.argmax(nz[:, ::-1], axis=1)  # significant digits after stripping zeros
    chars = digits.astype(np.uint8) + ord("0")
    buf = np.zeros((n, width), dtype=np.uint8)
    rows = np.arange(n)
    col = np.zeros(n, dtype=np.int64)

    def put(mask, values):
        buf[rows[mask], col[mask]] = values
        col[mask] += 1

    put(neg, ord("-"))
    sci = (e < -4) | (e >= 16)
    fixed_pos = ~sci & (e >= 0)
    fixed_neg = ~sci & (e < 0)
    # fixed, e >= 0: integer part = digits[0..e], then ".", then the rest (at least one digit)
    # fixed, e < 0: "0." then -e-1 zeros then the digits
    # scientific: d0 [. d1..] e±XX
    j = np.arange(17)[None, :]
    # Column of digit j in each layout, relative to the start column.
    start = col[:, None]
    pos_fixed = start + j + (j > e[:, None])  # skip the "." after digit e
    pos_fneg = start + 2 + (-e[:, None] - 1) + j
    pos_sci = start + j + (j > 0)
    pos = np.where(sci[:, None], pos_sci, np.where(fixed_pos[:, None], pos_fixed, pos_fneg))
    # Which digits are printed: significant ones, plus integer-part zeros in fixed notation.
    show = j < ndig[:, None]
    show |= fixed_pos[:, None] & (j <= e[:, None])
    r_idx, c_idx = np.nonzero(show)
    buf[r_idx, pos[r_idx, c_idx]] = chars[r_idx, c_idx]
    # Decimal points and leading "0." / zeros
    c0 = col
    fp = np.nonzero(fixed_pos)[0]
    buf[fp, c0[fp] + e[fp] + 1] = ord(".")
    # a trailing ".0" when no fractional digit is significant
    needs_zero = fixed_pos & (ndig <= e + 1)
    nzr = np.nonzero(needs_zero)[0]
    buf[nzr, c0[nzr] + e[nzr] + 2] = ord("0")
    fn = np.nonzero(fixed_neg)[0]
    if fn.size:
        buf[fn, c0[fn]] = ord("0")
        buf[fn, c0[fn] + 1] = ord(".")
        lead = -e[fn] - 1
        for z in range(int(lead.max(initial=0))):
            m = z < lead
            buf[fn[m], c0[fn[m]] + 2 + z] = ord("0")
    sc = np.nonzero(sci)[0]
    if sc.size:
        multi = ndig[sc] > 1
        buf[sc[multi], c0[sc[multi]] + 1] = ord(".")
        ecol = c0[sc] + ndig[sc] + multi
        buf[sc, ecol] = ord("e")
        buf[sc, ecol + 1] = np.where(e[sc] < 0, ord("-"), ord("+"))
        ae = np.abs(e[sc])
        three = ae >= 100
        buf[sc[three], ecol[three] + 2] = (ae[three] // 100) + ord("0")
        off = ecol + 2 + three
        buf[sc, off] = (ae // 10) % 10 + ord("0")
        buf[sc, off + 1] = ae % 10 + ord("0")
    return buf


def format_column(x: np.ndarray) -> list[bytes] | np.ndarray:
    """Text of a 1-d float64 array, one ``repr`` per entry, as a fixed-width byte matrix."""
    raise NotImplementedError


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
    idx = np.nonzero(fast)[0]
    width = 25
    cells = np.zeros((flat.size, width + 1), dtype=np.uint8)
    if idx.size:
        axf = ax[idx]
        d, e, resid = _digits17(axf)
        exp2 = np.frexp(axf)[1].astype(np.int64)  # axf in [2^(exp2-1), 2^exp2)
        # half an ulp of x, in units of the 17th digit: 2^(exp2 - 54) · 10^(16 − e)
        half_ulp = np.ldexp(_P10_HI[16 - e - _K_MIN], exp2 - 54)
        d, undecided = _shortest(d, resid, half_ulp)
        keep = ~undecided
        sub = idx[keep]
        cells[sub, :width] = _to_text(np.signbit(flat[sub]), d[keep], e[keep])
        fast[idx[undecided]] = False
    for i in np.nonzero(~fast)[0]:
        text = repr(float(flat[i])).encode()
        cells[i, : len(text)] = np.frombuffer(text, dtype=np.uint8)
    # Separators: after each cell, `sep` or a newline at the end of a row.
    ends = np.argmax(cells[:, :width] == 0, axis=1)
    full = cells[:, :width].all(axis=1)
    ends[full] = width
    seps = np.full(flat.size, ord(sep), dtype=np.uint8)
    seps[k - 1 :: k] = ord("\n")
    cells[np.arange(flat.size), ends] = seps
    out = cells[cells != 0].tobytes()
    if prefix is None:
        return out
    lines = out.split(b"\n")
    return b"".join(p.encode() + sep.encode() + line + b"\n" for p, line in zip(prefix, lines))
