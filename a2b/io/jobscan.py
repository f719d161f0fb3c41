"""JSON Lines jobs scanned line by line, the common forms of a job checked fast.

Each line of a JSON Lines jobs file is parsed by the C scanner of :mod:`json` and checked for
the common forms of a job (:meth:`Scanned.add_fast`); a line of any unusual form is read the
exact way by the caller's reader, which also words its error. The numbers of each block are
checked in bulk afterwards (:func:`a2b.io.jobfiles.finish_block`): the jobs, the errors and
their order are those of reading the file line by line with the exact reader.
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import IO

from ..errors import InputFileError
from ..names import FRAMES, MAX_SAMPLES, MIN_SAMPLES, MODES
from .documents import decode, kind_from_suffix, stream_name
from .poseschema import JOB_KEYS, MATRIX_LAYOUTS, PARAMETER_KINDS, POSE_FORMS, TRANSLATION, Numbers

__all__ = ["NUMBER_TYPES", "Scanned", "Sniffed", "lines", "scan_blocks", "sniff"]


def is_complete_json(line: str) -> bool:
    try:
        json.loads(line)
    except (ValueError, RecursionError):
        return False
    return True


def lines(stream: IO, name: str, first: str | None = None) -> Iterator[str]:
    number = 0
    if first is not None:
        number += 1
        yield first
    for raw in stream:
        number += 1
        if number > 1 and type(raw) is bytes:
            try:
                yield raw.decode("utf-8")
                continue
            except UnicodeDecodeError:
                pass
        yield decode(raw, name, number)  # the first line (a byte-order mark), text, an error


@dataclass
class Sniffed:
    """What the start of a jobs file says: its ``name`` for messages, the ``kind`` its suffix
    names (``None``: none), whether it is ``json_lines``, and ``first``: the first line if it
    was read to tell (text for JSON Lines, else as read), else ``None``."""

    name: str
    kind: str | None
    json_lines: bool
    first: str | bytes | None


def sniff(stream: IO, name: str | None = None) -> Sniffed:
    """Tell JSON Lines from a YAML or JSON document: by the suffix ``.jsonl`` or ``.ndjson``,
    or, without a suffix that says, by a first line that is a whole JSON object."""
    name = stream_name(stream, name)
    kind = kind_from_suffix(name)
    if kind == "jsonl":
        return Sniffed(name, kind, True, None)
    raw_start = stream.readline()
    first = raw_start.strip()
    if kind is None and first.startswith(b"{" if isinstance(first, bytes) else "{"):
        text_start = decode(raw_start, name)
        if is_complete_json(text_start):
            return Sniffed(name, kind, True, text_start)
    return Sniffed(name, kind, False, raw_start)


# --------------------------------------------------------------------------------------------
# Scanning: the common forms of a job, checked line by line

#: The C scanner of a plain decoder: no hooks, so duplicate keys are counted (see
#: :func:`scan_blocks`) and numbers that are no finite double arrive as inf or NaN,
#: which the bulk check sends to the exact path.
_JSON_SCAN = json.JSONDecoder().scan_once


_JOB_KEY_SET = frozenset(JOB_KEYS)
NUMBER_TYPES = frozenset({int, float})
_ZERO_TRANSLATION = (0.0, 0.0, 0.0)


def _fast_reading(numbers: Numbers) -> tuple:
    """``(list order or None, mapping keys or None)``: how the fast path takes a group of
    numbers written as ``numbers`` says; the list order is ``None`` when it needs no picking."""
    pick = numbers.pick if numbers.pick != tuple(range(len(numbers.wanted))) else None
    as_list = (pick, len(numbers.written)) if "list" in numbers.layouts else None
    as_mapping = tuple(numbers.wanted) if "mapping" in numbers.layouts else None
    return as_list, as_mapping


#: The quaternion forms of :data:`a2b.io.poseschema.POSE_FORMS`, as the fast path reads them.
_QUATERNION_FORMS = {
    key: _fast_reading(form.numbers) for key, form in POSE_FORMS.items() if form.numbers
}
_TRANSLATION = _fast_reading(TRANSLATION)
#: The length of a translation list in the order the readers take (0: none such).
_PLAIN_TRANSLATION = _TRANSLATION[0][1] if _TRANSLATION[0] and not _TRANSLATION[0][0] else 0
#: The one form common enough to be read inline (a list in the order the readers take).
_INLINE = next(k for k, (as_list, _) in _QUATERNION_FORMS.items() if as_list and not as_list[0])
_MATRIX = POSE_FORMS["matrix"]


def _fast_numbers(value, reading: tuple, out: list) -> int:
    """Append the numbers of ``value`` read as ``reading`` says to ``out``; return the count
    of mapping keys read (0 for a list), or ``-1`` if it is written otherwise."""
    as_list, as_mapping = reading
    kind = type(value)
    if kind is list and as_list is not None and len(value) == as_list[1]:
        pick = as_list[0]
        if pick is None:
            out += value
        else:
            out += map(value.__getitem__, pick)
        return 0
    if kind is dict and as_mapping is not None and len(value) == len(as_mapping):
        out += map(value.get, as_mapping)  # a missing key: None, refused later
        return len(as_mapping)
    return -1


def _fast_pose(v, q: list, m: list) -> int:
    """Append the numbers of a pose in a common form to ``q`` (quaternion forms: ``w, x, y, z,
    tx, ty, tz``) or ``m`` (a robotics matrix: its 16 entries); return the count of mapping
    keys read, or ``-1`` for any other form (the caller then undoes the appends).

    The forms, their keys and orders come from :data:`a2b.io.poseschema.POSE_FORMS`. Only the
    structure is checked here: the numbers are checked by :meth:`Scanned.add_fast` once the
    whole job is read, and in bulk by :func:`a2b.io.jobfiles.finish_block`.
    """
    if type(v) is not dict:
        return -1
    size = len(v)
    if size > 2:
        return -1
    for key in v:
        reading = _QUATERNION_FORMS.get(key)
        if reading is not None:
            break
    else:
        return _fast_matrix(v, m)
    more = _fast_numbers(v[key], reading, q)
    if more < 0:
        return -1
    if size == 1:
        q += _ZERO_TRANSLATION
        return more + 1
    t = v.get("translation")
    if type(t) is list and len(t) == _PLAIN_TRANSLATION:  # the common case, inline
        q += t
        return more + 2
    added = _fast_numbers(t, _TRANSLATION, q) if t is not None else -1
    return -1 if added < 0 else more + added + 2


def _fast_matrix(v: dict, m: list) -> int:
    """The robotics matrix form for :func:`_fast_pose`."""
    rows = v.get(_MATRIX.key)
    if type(rows) is not list or len(rows) != 4:
        return -1
    if len(v) == 2 and v.get(_MATRIX.extras[0]) != MATRIX_LAYOUTS[0]:  # the paper's: exact
        return -1
    for row in rows:
        if type(row) is not list or len(row) != 4:
            return -1
        m += row
    return len(v)


def _fast_parameters(params: dict) -> dict | None:
    """Parameters of the kinds that need no pose, checked as :func:`_parameters` does."""
    out = {}
    for key, value in params.items():
        kind = PARAMETER_KINDS.get(key) if type(key) is str else None
        if kind is None:
            return None
        if value is None:
            continue
        if kind == "number":
            if type(value) not in NUMBER_TYPES:
                return None
            value = float(value)
            if not math.isfinite(value):
                return None
        elif type(kind) is int:
            if type(value) is not list or len(value) != kind:
                return None
            numbers = []
            for x in value:
                if type(x) not in NUMBER_TYPES:
                    return None
                x = float(x)
                if not math.isfinite(x):
                    return None
                numbers.append(x)
            value = tuple(numbers)
        elif kind == "branch":
            if type(value) not in NUMBER_TYPES or value not in (1, -1):
                return None
            value = int(value)
        elif kind == "bool":
            if type(value) is not bool:
                return None
        elif kind == "frame":
            if type(value) is not str or value not in FRAMES:
                return None
        else:  # a pose (through): the exact path
            return None
        out[key] = value
    return out


def _plain_numbers(q: list, nq: int, m: list, nm: int) -> bool:
    """Whether the numbers added from ``q[nq]`` and ``m[nm]`` (a job's two poses) are ints and
    floats whose sum is finite (so is each of them: a false alarm, a sum that overflows, only
    sends the job to the exact reading), and no quaternion (the first four of each seven in
    ``q``) is all zeros. An integer beyond the doubles raises :class:`OverflowError`."""
    added = q[nq:] + m[nm:]
    if not NUMBER_TYPES.issuperset(map(type, added)) or not math.isfinite(sum(added)):
        return False
    poses = (len(q) - nq) // 7
    return (poses < 1 or any(q[nq : nq + 4])) and (poses < 2 or any(q[nq + 7 : nq + 11]))


class Scanned:
    """The jobs of one block as scanned: their numbers in flat lists, made poses and checked
    in bulk later (:func:`a2b.io.jobfiles.finish_block`), and the jobs read the exact way."""

    def __init__(self):
        self.q: list = []  # 7 numbers per pose in a quaternion form
        self.m: list = []  # 16 numbers per pose in matrix form
        #: per job: (start slot, end slot, mode, samples, parameters, name, where): a slot is
        #: k >= 0 for the k-th pose in q, ~k < 0 for the k-th in m, None for a job read the
        #: exact way; ``where`` is what the exact reading needs
        self.records: list = []
        #: job -> its Job, for jobs read the exact way
        self.exact: dict = {}

    def __len__(self) -> int:
        return len(self.records)

    def add_fast(self, v, colons: int | None, where) -> bool:
        """Add the job mapping ``v`` if it has a common form, checked as :func:`_job` checks it
        (what needs numpy, in bulk later); False, adding nothing, for anything else.

        Numbers that cannot be right (not an int or a float, not finite, a quaternion of
        zeros) make it False at once, so that the exact reading words their error as soon as
        the line is scanned, not when its block is complete.

        ``colons``: the count of colons in the JSON text of ``v``, which must equal the count
        of keys (no duplicates), or ``None`` when the parser has checked that.
        """
        q, m = self.q, self.m
        nq, nm = len(q), len(m)
        try:
            if type(v) is not dict:
                return False
            for key in v:
                if key not in _JOB_KEY_SET:
                    return False
            keys = len(v)
            slots = []
            for pose in (v.get("start"), v.get("end")):
                if type(pose) is dict and len(pose) == 2:  # the commonest form, inline
                    quat, t = pose.get(_INLINE), pose.get("translation")
                    if type(quat) is list and len(quat) == 4 and type(t) is list and len(t) == 3:
                        slots.append(len(q) // 7)
                        q += quat
                        q += t
                        keys += 2
                        continue
                before_q, before_m = len(q), len(m)
                more = _fast_pose(pose, q, m)
                if more < 0:
                    break
                slots.append(before_q // 7 if len(q) > before_q else ~(before_m // 16))
                keys += more
            else:
                # the checks of _job, in the cases it accepts
                mode = v.get("mode")
                samples = v.get("samples")
                name = v.get("name")
                params = v.get("parameters") or {}  # as _job: a falsy value means none
                if (
                    (mode is None or (type(mode) is str and mode in MODES))
                    and (
                        samples is None
                        or (type(samples) is int and MIN_SAMPLES <= samples <= MAX_SAMPLES)
                    )
                    and (
                        name is None
                        or (type(name) is str and "\0" not in name and _writable(name))
                        or type(name) is int
                    )
                    and type(params) is dict
                ):
                    if params:
                        keys += len(params)
                        params = _fast_parameters(params)
                    if (
                        params is not None
                        and (colons is None or keys == colons)
                        and _plain_numbers(q, nq, m, nm)
                    ):
                        if type(name) is int:
                            name = str(name)
                        record = (slots[0], slots[1], mode, samples, params, name, where)
                        self.records.append(record)
                        return True
        except (TypeError, ValueError, OverflowError):
            pass
        del q[nq:], m[nm:]
        return False

    def add_job(self, job, where) -> None:
        """Add a job read the exact way (a :class:`a2b.io.poseschema.Job`)."""
        self.exact[len(self.records)] = job
        self.records.append((None, None, job.mode, job.samples, job.parameters, job.name, where))


def scan_blocks(
    lines: Iterator[str], name: str, size: int, exact: Callable[[str, str, int, int], object]
) -> Iterator[Scanned]:
    """The jobs of JSON Lines scanned in blocks of ``size``: each line parsed by the plain C
    scanner and checked by :meth:`Scanned.add_fast`, or, if anything about it is unusual, read
    the exact way by ``exact(line, name, number, index)`` (the
    :func:`a2b.io.jobfiles.json_line_job`, which makes every error message). An
    error of a line (no UTF-8, or found by the exact reading) or of the stream is raised after
    the block of the jobs before it; what needs numpy to check (a matrix that is no rotation)
    is checked later, in bulk (:func:`a2b.io.jobfiles.finish_block`).

    A duplicate key is caught by counting: the keys of the parsed mappings must number the
    colons of the line (a duplicate drops a key; a colon inside a string sends the line to the
    exact path, which finds duplicates itself).
    """
    scanned = Scanned()
    records = scanned.records
    add_fast = scanned.add_fast
    index = 0
    scan = _JSON_SCAN
    for number, line in enumerate(_guarded(lines), start=1):
        if type(line) is not str:  # an error of reading: after the jobs before it
            if records:
                yield scanned
            raise line
        if not line.strip():
            continue
        where = (line, name, number, index)
        try:
            data, end = scan(line, 0)
        except Exception:  # noqa: BLE001 - any failure: the exact path says what is wrong
            fast = False
        else:
            tail = line[end:]
            fast = (tail == "\n" or not tail.strip(" \t\n\r")) and add_fast(
                data, line.count(":"), where
            )
        if not fast:
            try:
                job = exact(line, name, number, index)
            except InputFileError:
                if records:
                    yield scanned
                raise
            scanned.add_job(job, where)
        index += 1
        if len(records) == size:
            yield scanned
            scanned = Scanned()
            records = scanned.records
            add_fast = scanned.add_fast
    if records:
        yield scanned
    if index == 0:
        raise InputFileError(f"{name}: no jobs: the file has no lines with a job")


def _writable(name: str) -> bool:
    """Whether UTF-8 can write ``name`` (JSON can escape a lone surrogate; UTF-8 cannot)."""
    if name.isascii():
        return True
    try:
        name.encode("utf-8")
    except UnicodeEncodeError:
        return False
    return True


def _guarded(lines: Iterator[str]) -> Iterator:
    """The lines, and in place of the rest the error that reading raised (an
    :class:`InputFileError` for bytes that are no UTF-8, an :class:`OSError` of the stream)."""
    try:
        yield from lines
    except Exception as e:  # noqa: BLE001 - raised in turn, after the jobs before it
        yield e
