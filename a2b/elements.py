"""What a2b says about each element of a batch: its choices, its warnings, its errors.

Every quantity of the core has a leading shape ``S`` (``()`` for a single motion). A choice or
a warning holds for the elements where a mask is true; an error names the first element where
it holds. A single motion's messages carry no index, so that they read as they always have;
in a batch they begin with ``motion i:`` (``motion (i, j):`` for more than one dimension), and
the exception or warning carries ``index`` (the flat index) and ``reason`` (the message
without the index), so that a caller such as ``a2b batch`` can name the element its own way.
"""

from __future__ import annotations

import contextvars
import reprlib
import warnings
from collections import Counter
from collections.abc import Callable
from contextlib import contextmanager

import numpy as np

from .errors import A2bError, A2bWarning


def as_numbers(values, what: str, error: type[A2bError] | None = None) -> np.ndarray:
    """``values`` as a float array, if they are numbers: a string, a boolean or another object
    that merely converts to a float is an ``error`` (default :class:`ParameterError`) that
    names ``what``."""
    try:
        raw = np.asarray(values)
    except (TypeError, ValueError):  # ragged nesting
        raw = np.asarray(None)
    if raw.dtype.kind not in "iuf":
        from .errors import ParameterError

        shown = reprlib.repr(values)
        raise (error or ParameterError)(
            f"{what} must be a number or an array of numbers, got {shown}"
        )
    return raw.astype(float)


def label(shape: tuple, flat: int) -> str:
    """``""`` for a single element, else ``"motion i: "`` with its (multi-)index."""
    if shape == ():
        return ""
    index = np.unravel_index(flat, shape)
    where = int(index[0]) if len(shape) == 1 else tuple(int(i) for i in index)
    return f"motion {where}: "


def refuse(error: type[A2bError], bad, message: Callable[[int], str], shape: tuple) -> None:
    """Raise ``error`` for the first element where ``bad`` holds, with ``message(flat)``."""
    if not anywhere(bad):
        return
    bad = np.broadcast_to(bad, shape)
    flat = int(np.flatnonzero(bad.ravel())[0]) if shape else 0
    reason = message(flat)
    exception = error(label(shape, flat) + reason)
    exception.index = flat
    exception.reason = reason
    raise exception


#: Set by :func:`noted_only`, in this thread (or task) only.
_NOTED_ONLY = contextvars.ContextVar("a2b_noted_only", default=False)


@contextmanager
def noted_only():
    """Within, :func:`warn` notes its warnings (on the motion, ``warning_notes``) and does not
    issue them: for a caller that issues them itself, in its own words and order, as the
    resampler names its segments. It holds for this thread only, where
    ``warnings.catch_warnings`` would change the warning state of the whole process."""
    token = _NOTED_ONLY.set(True)
    try:
        yield
    finally:
        _NOTED_ONLY.reset(token)


def warn(where, message: Callable[[int], str], shape: tuple, notes: Notes) -> None:
    """Issue an :class:`A2bWarning` for every element where ``where`` holds (not within
    :func:`noted_only`), and note it."""
    if not anywhere(where):
        return
    issue = not _NOTED_ONLY.get()
    mask = np.broadcast_to(where, shape)
    texts = np.full(shape, None, dtype=object)
    for flat in np.flatnonzero(mask.ravel()).tolist() if shape else [0]:
        reason = message(flat)
        texts.flat[flat] = reason
        warning = A2bWarning(label(shape, flat) + reason)
        warning.index = flat
        warning.reason = reason
        if issue:
            warnings.warn(warning, stacklevel=4)
    notes.add(texts, mask)


_SCALAR_BOOLS = (bool, np.bool_)


def anywhere(mask) -> bool:
    """Whether a boolean mask (an array or a bool) holds anywhere: the quick test before the
    work. ``numpy.count_nonzero`` costs a fifth of ``mask.any()`` on the small arrays of one
    motion, where a ufunc reduction's setup is most of the time."""
    if mask.__class__ in _SCALAR_BOOLS:  # one motion's test: a bool already
        return bool(mask)
    return np.count_nonzero(mask) > 0


def everywhere(mask) -> bool:
    """Whether a boolean mask (an array or a bool) holds everywhere (as :func:`anywhere`)."""
    if mask.__class__ in _SCALAR_BOOLS:
        return bool(mask)
    return np.count_nonzero(mask) == (mask.size if isinstance(mask, np.ndarray) else 1)


def value(array, flat: int) -> float:
    """Element ``flat`` of an array of shape ``S`` (or a scalar), as a float."""
    return float(np.asarray(array).reshape(-1)[flat]) if np.ndim(array) else float(array)


class Notes:
    """Remarks (choices or warnings) on the elements of a batch of shape ``S``, in order.

    Each rule is a text, or an object array of texts of shape ``S``, with the mask of the
    elements it concerns (``None``: all). Masks are kept, not expanded, so that a remark
    that holds for many elements costs one array, not one list per element.
    """

    def __init__(self, shape: tuple, rules: list | None = None):
        self.shape = tuple(shape)
        self.rules: list = [] if rules is None else rules

    def add(self, text, where=None) -> None:
        """Note ``text`` (a str, or texts of shape ``S``) for the elements ``where`` holds."""
        if where is not None and not anywhere(where):
            return
        mask = None if where is None else np.broadcast_to(where, self.shape)
        self.rules.append((mask, text))

    def extend(self, other: Notes) -> None:
        self.rules.extend(other.rules)

    def __getitem__(self, index) -> Notes:
        shape = np.empty(self.shape, dtype=bool)[index].shape
        rules = [
            (
                None if mask is None else mask[index],
                text if isinstance(text, str) else text[index],
            )
            for mask, text in self.rules
        ]
        return Notes(shape, rules)

    def of(self, flat: int) -> list[str]:
        """The remarks on element ``flat``, in order, each once."""
        out: list[str] = []
        for mask, text in self.rules:
            if mask is not None and not mask.reshape(-1)[flat]:
                continue
            item = text if isinstance(text, str) else text.reshape(-1)[flat]
            if item is not None and item not in out:
                out.append(item)
        return out

    def mask(self) -> np.ndarray:
        """Which elements have any remark, shape ``S``."""
        out = np.zeros(self.shape, dtype=bool)
        for mask, text in self.rules:
            if isinstance(text, str):
                out |= True if mask is None else mask
            else:
                out |= (np.asarray(text) != None) & (True if mask is None else mask)  # noqa: E711
        return out

    def counts(self, where=None) -> Counter:
        """How many elements (of those ``where`` holds) each remark concerns: a batch's summary."""
        out: Counter = Counter()
        size = int(np.prod(self.shape, dtype=np.int64))
        keep = np.ones(size, dtype=bool) if where is None else np.asarray(where).reshape(-1)
        for mask, text in self.rules:
            chosen = keep if mask is None else keep & np.asarray(mask).reshape(-1)
            if isinstance(text, str):
                count = int(np.count_nonzero(chosen))
                if count:
                    out[text] += count
            else:
                out.update(t for t in np.asarray(text).reshape(-1)[chosen].tolist() if t)
        return out

    def tolist(self):
        """The remarks: a list of str for a single element, else nested lists of shape ``S``."""
        if self.shape == ():
            return self.of(0)
        flat = np.empty(int(np.prod(self.shape)), dtype=object)
        for i in range(flat.size):
            flat[i] = self.of(i)
        return _nested(flat.reshape(self.shape))


def _nested(array: np.ndarray):
    if array.ndim == 1:
        return list(array)
    return [_nested(part) for part in array]


def unit_scale(values: np.ndarray, axis=-1, extreme_only: bool = False) -> np.ndarray:
    """``values`` divided by a power of two near their largest magnitude along ``axis``.

    With ``extreme_only``, only rows whose largest magnitude lies outside [2^-300, 2^300] are
    scaled, so that values of ordinary size (and what is reported of them) stay as given.

    For homogeneous quantities (quaternions, Study parameters, m, weights), where any non-zero
    multiple means the same: the result's largest entry lies in [0.5, 1), so squares and
    products neither overflow nor underflow for any finite input (``[1e-200, 0, 0, 0]``,
    Study parameters of 1e300). A power of two is exact, so every later result is bit for bit
    what it was for inputs of ordinary size. Zero and non-finite rows are returned as they are.
    """
    values = np.asarray(values, dtype=float)
    with np.errstate(invalid="ignore"):
        largest = largest_magnitudes(values, axis)
    _, exponent = np.frexp(np.where(np.isfinite(largest), largest, 0.0))
    if extreme_only:
        exponent = np.where(np.abs(exponent) > 300, exponent, 0)
    return np.ldexp(values, -exponent)


def largest_magnitudes(values: np.ndarray, axis=-1) -> np.ndarray:
    """``max |values|`` along ``axis``, kept as an axis of length 1 (NaN where a NaN is).

    Along a short last axis (a quaternion's, a Study vector's) as the elementwise maximum of
    its components: numpy's reduction of a short contiguous axis costs 30 ns a row, 7x as
    much (a maximum is exact: the same numbers)."""
    if values.ndim and 0 < values.shape[-1] <= 16 and axis in (-1, values.ndim - 1):
        largest = np.abs(values[..., :1])
        for i in range(1, values.shape[-1]):
            np.maximum(largest, np.abs(values[..., i : i + 1]), out=largest)
        return largest
    return np.max(np.abs(values), axis=axis, keepdims=True)


def safe_norm(values: np.ndarray, axis=-1) -> np.ndarray:
    """Euclidean norms along ``axis`` that overflow or underflow only when the norm itself does."""
    values = np.asarray(values, dtype=float)
    with np.errstate(over="ignore", invalid="ignore"):
        plain = np.sqrt(np.add.reduce(values * values, axis=axis))
    if plain.size and np.all((plain > 1e-150) & (plain < 1e150)):  # no square under- or overflowed
        return plain
    with np.errstate(invalid="ignore"):
        largest = np.max(np.abs(values), axis=axis, keepdims=True)
    _, exponent = np.frexp(np.where(np.isfinite(largest), largest, 0.0))
    norm = np.linalg.norm(np.ldexp(values, -exponent), axis=axis, keepdims=True)
    return np.squeeze(np.ldexp(norm, exponent), axis=axis)
