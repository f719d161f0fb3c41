"""Readers: pose files (JSON, YAML, JSON Lines) in; the trajectory formats of ``writers`` back.

Pose files
----------
A pose is a mapping with exactly one of these forms::

    {matrix: [[r11, r12, r13, t1], ..., [0, 0, 0, 1]], layout: robotics | paper}
    {quaternion: {w: .., x: .., y: .., z: ..}, translation: [x, y, z] | {x, y, z}}
    {quaternion_wxyz: [w, x, y, z], translation: ...}
    {quaternion_xyzw: [x, y, z, w], translation: ...}      # ROS order, read at this edge only
    {rpy_xyz: [roll, pitch, yaw], translation: ...}        # R = Rz(yaw) Ry(pitch) Rx(roll)
    {axis_angle: {axis: [x, y, z], angle: a}, translation: ...}

Angles are radians, or degrees with a ``deg`` suffix (``90deg``).

A bare list under ``quaternion`` is an error: its order is the one thing a reader of the file
cannot tell, and reading ROS's x, y, z, w as w, x, y, z turns the identity into a half turn.
    {study: [p0, p1, p2, p3, q0, q1, q2, q3], kappa: false | true}

``translation`` defaults to zero. ``kappa: true`` reads a Study vector off the Study quadric
through the extended map κ. A *poses file* (``a2b interpolate``) is a mapping with ``start``,
``end`` and optionally ``mode``, ``samples`` and ``parameters``; a *jobs file* (``a2b batch``) is
a list of such mappings (each may have a ``name``), or JSON Lines with one per line; a *pose
list* (``a2b bezier``, ``a2b spline``) is a mapping with a list of poses under ``controls`` or
``poses`` and optionally ``space``, ``samples`` and ``parameters``.

YAML is read with the YAML 1.2 core schema: ``1e-3`` is a number; ``1:20``, ``1_000``, ``yes``
and ``no`` are strings. Numbers must be finite doubles: ``NaN``, ``.inf``, ``1e999`` and
400-digit integers are errors, as are bytes that are not UTF-8 and nesting deeper than
:data:`MAX_DEPTH` levels.

Every structural error is an :class:`a2b.errors.InputFileError` whose message starts with
``FILE:LINE:COLUMN:`` (where the parser gives a position) and names the key, as in
``poses.yaml:4:3: start.quaternion: expected 4 numbers (w, x, y, z), got 3``.

Trajectory files are read by :mod:`a2b.io.trajectories`; ``read_batch_csv`` reads what
``write_batch_csv`` of :mod:`a2b.io.writers` writes.
"""

from __future__ import annotations

import difflib
import gc
import io
import json
import math
import re
import sys
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass, field
from json.decoder import scanstring
from typing import IO, Any

import numpy as np

from ..errors import A2bError, InputFileError
from ..names import FRAMES, MAX_SAMPLES, MIN_SAMPLES, MODES
from ..parameters import BY_NAME, degrees
from .jobscan import JOB_KEYS, PARAMETER_KINDS, POSES_KEYS, Scanned, scan_blocks, sniff
from .jobscan import NUMBER_TYPES as _NUMBER_TYPES
from .jobscan import decode as _decode
from .jobscan import kind_from_suffix as _kind_from_suffix
from .jobscan import lines as _lines
from .jobscan import stream_name as _stream_name

__all__ = [
    "Job",
    "JobBlock",
    "Jobs",
    "PoseList",
    "job_blocks",
    "read_batch_csv",
    "read_jobs",
    "read_motion_file",
    "read_pose",
    "read_pose_list",
    "read_poses",
]

POSE_FORMS = (
    "matrix",
    "quaternion",
    "quaternion_wxyz",
    "quaternion_xyzw",
    "rpy_xyz",
    "axis_angle",
    "study",
)
POSE_KEYS = POSE_FORMS + ("layout", "translation", "kappa")
Path = tuple  # keys (str) and list indexes (int) from the document root


@dataclass(frozen=True)
class Job:
    """One motion to sample: validated poses (robotics 4x4 matrices) and what the file says.

    ``mode`` and ``samples`` are ``None`` where the file does not give them; ``parameters``
    holds only the keys the file gives, with ``through`` already a 4x4 matrix.
    """

    start: np.ndarray
    end: np.ndarray
    mode: str | None = None
    samples: int | None = None
    parameters: dict = field(default_factory=dict)
    name: str | None = None


# --------------------------------------------------------------------------------------------
# Documents: parsed data plus a way back from a key path to a line and column


class _NonFinite:
    """Stands in for a number that is no finite double, so the error can name the key.

    ``NaN``, ``Infinity``, ``.inf`` and ``.nan`` themselves, and numbers written out that
    overflow a double (``1e999``, an integer of 400 digits).
    """

    def __init__(self, token: str):
        self.token = token

    def __str__(self) -> str:  # where it is a key: the text as written
        return self.token

    __repr__ = __str__

    def message(self) -> str:
        token = self.token.strip()
        if re.fullmatch(r"[-+]?(?:NaN|Infinity|\.(?:inf|Inf|INF|nan|NaN|NAN))", token):
            return f"{token} is not allowed; numbers must be finite"
        return (
            f"{_shorten(token)} is too large for a double; numbers must be finite (|x| < 1.8e308)"
        )


def _shorten(token: str) -> str:
    """A long number as its first and last digits and its length."""
    if len(token) <= 24:
        return token
    return f"{token[:12]}…{token[-6:]} ({sum(ch.isdigit() for ch in token)} digits)"


#: Deepest nesting of lists and mappings read (a pose file needs 6); deeper input is an error,
#: never a crash of the C YAML composer, which recurses on the C stack.
MAX_DEPTH = 100


class _Duplicate(Exception):
    def __init__(self, key: str, mark: tuple[int, int] | None = None):
        super().__init__(key)
        self.key = key
        self.mark = mark


@dataclass
class _Document:
    name: str
    data: Any
    locate: Callable[[Path], tuple[int, int] | None]

    def error(self, path: Path, message: str) -> InputFileError:
        try:
            where = self.locate(path) if path is not None else None
        except RecursionError:
            where = None
        prefix = f"{self.name}:{where[0]}:{where[1]}" if where else self.name
        key = _format_path(path)
        return InputFileError(f"{prefix}: {key + ': ' if key else ''}{message}")


def _format_path(path: Path | None) -> str:
    path = tuple(path or ())
    if path and isinstance(path[0], int):  # a job of a jobs file
        rest = _format_path(path[1:])
        return f"job {path[0]}" + (f": {rest}" if rest else "")
    out = ""
    for el in path:
        if not isinstance(el, int):  # keys that would garble the message are quoted
            el = (
                el
                if isinstance(el, str) and el.isprintable() and el.strip() == el and el
                else repr(el)
            )
        out += f"[{el}]" if isinstance(el, int) else (f".{el}" if out else el)
    return out


@contextmanager
def _gc_paused() -> Iterator[None]:
    """Pause the cyclic garbage collector while a parser builds many small containers.

    Parsing allocates hundreds of thousands of lists and dicts that are all alive; each
    allocation burst triggers a full collection that finds nothing. Pausing it makes a large
    YAML jobs file read about eight times faster.
    """
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if enabled:
            gc.enable()


def _line_col(text: str, pos: int) -> tuple[int, int]:
    line = text.count("\n", 0, pos) + 1
    return line, pos - (text.rfind("\n", 0, pos) + 1) + 1


def _read_text(stream: IO, name: str) -> str:
    return _decode(stream.read(), name)


# -- JSON --


def _json_pairs(pairs: list) -> dict:
    out = {}
    for key, value in pairs:
        if key in out:
            raise _Duplicate(key)
        out[key] = value
    return out


def _json_float(token: str):
    value = float(token)
    return value if math.isfinite(value) else _NonFinite(token)


def _json_int(token: str):
    try:
        return int(token)
    except ValueError:  # more digits than int() converts (sys.get_int_max_str_digits)
        return _NonFinite(token)


_JSON = json.JSONDecoder(
    object_pairs_hook=_json_pairs,
    parse_constant=_NonFinite,
    parse_float=_json_float,
    parse_int=_json_int,
)
_JSON_SKIP = json.JSONDecoder()
_WS = re.compile(r"[ \t\n\r]*")


def _ws(text: str, pos: int) -> int:
    return _WS.match(text, pos).end()


def _json_locate(text: str, path: Path, start: int = 0) -> int:
    """Offset of the last key (or list item) of ``path`` that exists in valid JSON ``text``."""
    pos = _ws(text, start)
    found = pos
    for el in path:
        if isinstance(el, str) and text.startswith("{", pos):
            pos = _ws(text, pos + 1)
            while not text.startswith("}", pos):
                key_pos = pos
                key, pos = scanstring(text, pos + 1)
                pos = _ws(text, _ws(text, pos) + 1)  # past ":"
                if key == el:
                    found = key_pos
                    break
                _, pos = _JSON_SKIP.raw_decode(text, pos)
                pos = _ws(text, pos)
                if text.startswith(",", pos):
                    pos = _ws(text, pos + 1)
            else:
                return found
        elif isinstance(el, int) and text.startswith("[", pos):
            pos = _ws(text, pos + 1)
            for _ in range(el):
                if text.startswith("]", pos):
                    return found
                _, pos = _JSON_SKIP.raw_decode(text, pos)
                pos = _ws(text, _ws(text, pos) + 1)  # past ","
            if text.startswith("]", pos):
                return found
            found = pos
        else:
            return found
    return found


def _json_find_duplicate(text: str, pos: int) -> tuple[int | None, int]:
    """``(offset of the first repeated key or None, end of the value at pos)``."""
    pos = _ws(text, pos)
    if text.startswith("{", pos):
        seen = set()
        pos = _ws(text, pos + 1)
        while not text.startswith("}", pos):
            key_pos = pos
            key, pos = scanstring(text, pos + 1)
            if key in seen:
                return key_pos, pos
            seen.add(key)
            dup, pos = _json_find_duplicate(text, _ws(text, pos) + 1)
            if dup is not None:
                return dup, pos
            pos = _ws(text, pos)
            if text.startswith(",", pos):
                pos = _ws(text, pos + 1)
        return None, pos + 1
    if text.startswith("[", pos):
        pos = _ws(text, pos + 1)
        while not text.startswith("]", pos):
            dup, pos = _json_find_duplicate(text, pos)
            if dup is not None:
                return dup, pos
            pos = _ws(text, pos)
            if text.startswith(",", pos):
                pos = _ws(text, pos + 1)
        return None, pos + 1
    _, end = _JSON_SKIP.raw_decode(text, pos)
    return None, end


def _parse_json(text: str, name: str, first_line: int = 1) -> _Document:
    """Parse JSON; ``first_line`` is the line of the file that ``text`` starts on (JSON Lines)."""

    def where(pos: int) -> tuple[int, int]:
        line, col = _line_col(text, pos)
        return line + first_line - 1, col

    try:
        with _gc_paused():
            data = _JSON.decode(text)
    except _Duplicate as e:
        try:
            dup, _ = _json_find_duplicate(text, 0)
        except RecursionError:
            dup = None
        line, col = where(dup or 0)
        raise InputFileError(f"{name}:{line}:{col}: duplicate key {e.key!r}") from None
    except json.JSONDecodeError as e:
        line, col = where(e.pos)
        message = e.msg.removesuffix(" at")  # json's "Invalid control character at"
        raise InputFileError(f"{name}:{line}:{col}: invalid JSON: {message}") from None
    except RecursionError:
        raise InputFileError(f"{name}: invalid JSON: nested too deeply to read") from None
    return _Document(name, data, lambda path: where(_json_locate(text, path)))


# -- YAML --

_YAML_LOADER = None

#: YAML 1.2 core schema scalars. PyYAML resolves YAML 1.1, where ``1:20`` is the number 80,
#: ``1_000`` is 1000, ``yes``/``no``/``on``/``off`` are booleans and ``1e-3`` is a string; a
#: pose file means none of these, so here they are strings, and an error says so.
_YAML_SCALARS = (
    ("bool", r"^(?:true|True|TRUE|false|False|FALSE)$", "tTfF"),
    ("int", r"^(?:[-+]?[0-9]+|0o[0-7]+|0x[0-9a-fA-F]+)$", "-+0123456789"),
    (
        "float",
        (
            r"^(?:[-+]?(?:\.[0-9]+|[0-9]+(?:\.[0-9]*)?)(?:[eE][-+]?[0-9]+)?"
            r"|[-+]?\.(?:inf|Inf|INF)|\.(?:nan|NaN|NAN))$"
        ),
        "-+.0123456789",
    ),
    ("null", r"^(?:~|null|Null|NULL|)$", ["~", "n", "N", ""]),
)


_STR = "tag:yaml.org,2002:str"
_YAML_BOOLEANS = {v: True for v in ("true", "True", "TRUE")} | {
    v: False for v in ("false", "False", "FALSE")
}


def _yaml_loader():
    """A safe loader with YAML 1.2 core-schema scalars that rejects duplicate keys.

    Numbers that are no finite double (``.inf``, ``.nan``, ``1e999``, 400-digit integers)
    become :class:`_NonFinite`, so the error names the key and the text as written.
    """
    global _YAML_LOADER
    if _YAML_LOADER is not None:
        return _YAML_LOADER
    import yaml

    base = getattr(yaml, "CSafeLoader", yaml.SafeLoader)

    class Loader(base):  # type: ignore[misc, valid-type]
        def construct_mapping(self, node, deep=False):
            seen = set()
            for key_node, value_node in node.value:
                key = self.construct_object(key_node, deep=deep)
                if key == "name" and isinstance(value_node, yaml.ScalarNode):
                    value_node.tag = _STR  # a name is the text as written: 007, true, 1e3
                try:
                    repeated = key in seen
                except TypeError:  # an unhashable key; the constructor reports it
                    break
                if repeated:
                    mark = key_node.start_mark
                    raise _Duplicate(str(key), (mark.line + 1, mark.column + 1))
                seen.add(key)
            return super().construct_mapping(node, deep=deep)

        def construct_yaml_int(self, node):
            text = self.construct_scalar(node)
            digits = text.lstrip("+-")
            try:
                if digits.startswith(("0o", "0x")):
                    value = int(digits[2:], 8 if digits[1] == "o" else 16)
                    if value > sys.float_info.max:  # beyond a double (and beyond str())
                        return _NonFinite(text)
                    return -value if text.startswith("-") else value
                return int(text)
            except ValueError:
                if re.fullmatch(r"[-+]?[0-9]+", text):  # more digits than int() converts
                    return _NonFinite(text)
                raise yaml.constructor.ConstructorError(
                    None, None, f"cannot read {text!r} as an integer", node.start_mark
                ) from None

        def construct_yaml_bool(self, node):
            text = self.construct_scalar(node)
            if text not in _YAML_BOOLEANS:
                raise yaml.constructor.ConstructorError(
                    None, None, f"cannot read {text!r} as true or false", node.start_mark
                )
            return _YAML_BOOLEANS[text]

        def construct_undefined(self, node):
            raise yaml.constructor.ConstructorError(
                None,
                None,
                f"the tag {node.tag.replace('tag:yaml.org,2002:', '!!')} is not read by a2b, "
                "which reads the YAML 1.2 core schema: strings, numbers, true and false, null, "
                "lists and mappings",
                node.start_mark,
            )

        def construct_yaml_float(self, node):
            text = self.construct_scalar(node)
            if text.lstrip("+-").lower() in (".inf", ".nan"):
                return _NonFinite(text)
            try:
                value = float(text)
            except ValueError:
                raise yaml.constructor.ConstructorError(
                    None, None, f"cannot read {text!r} as a number", node.start_mark
                ) from None
            return value if math.isfinite(value) else _NonFinite(text)

    # Only the core schema's implicit types: no YAML 1.1 timestamps (2001-02-30), merge keys
    # (<<) or value keys (=), which are strings here.
    Loader.yaml_implicit_resolvers = {}
    for name, pattern, first in _YAML_SCALARS:
        Loader.add_implicit_resolver(f"tag:yaml.org,2002:{name}", re.compile(pattern), list(first))
    core = {f"tag:yaml.org,2002:{t}" for t in ("str", "seq", "map", "null")}
    Loader.yaml_constructors = {
        tag: constructor for tag, constructor in base.yaml_constructors.items() if tag in core
    }
    Loader.add_constructor("tag:yaml.org,2002:int", Loader.construct_yaml_int)
    Loader.add_constructor("tag:yaml.org,2002:float", Loader.construct_yaml_float)
    Loader.add_constructor("tag:yaml.org,2002:bool", Loader.construct_yaml_bool)
    Loader.add_constructor(None, Loader.construct_undefined)  # every other tag: !!set, !foo
    Loader.yaml_multi_constructors = {}
    _YAML_LOADER = Loader
    return Loader


def _yaml_depth_bound(text: str) -> int:
    """An upper bound of the nesting depth of YAML ``text``, cheap to compute.

    Every level is opened by ``[``, ``{``, a ``-``, ``?`` or ``:`` indicator, or a deeper
    line; counting all of them (in scalars and comments too) over-estimates safely.
    """
    return sum(text.count(ch) for ch in "[{-?:\n") + 1


def _check_yaml_depth(text: str, name: str) -> None:
    """Raise if YAML ``text`` nests deeper than :data:`MAX_DEPTH`, before composing it.

    The C composer recurses once per level on the C stack, so a file of 50 000 ``[`` would
    crash the interpreter. The parser's events come from a loop, not recursion; counting
    them is safe. Files too small to nest that deep are not scanned.

    libyaml 0.2.5 and newer stop at 1000 levels of their own, and may do so while scanning
    ahead, before the first event. So when the fast C events end in any error, the events are
    counted again with PyYAML's pure-Python parser, which has no limit of its own: the message
    names a2b's limit at the same place whatever version of PyYAML is installed.
    """
    if _yaml_depth_bound(text) <= MAX_DEPTH:
        return
    import yaml

    try:
        _count_yaml_depth(_yaml_loader()(text), name)
    except yaml.YAMLError:
        try:
            _count_yaml_depth(yaml.SafeLoader(text), name)
        except yaml.YAMLError:
            return  # composing stops at the same place and reports the syntax error


def _count_yaml_depth(loader, name: str) -> None:
    import yaml

    opening = (yaml.MappingStartEvent, yaml.SequenceStartEvent)
    closing = (yaml.MappingEndEvent, yaml.SequenceEndEvent)
    depth = 0
    try:
        while loader.check_event():
            event = loader.get_event()
            if isinstance(event, opening):
                depth += 1
                if depth > MAX_DEPTH:
                    mark = event.start_mark
                    raise InputFileError(
                        f"{name}:{mark.line + 1}:{mark.column + 1}: nested too deeply "
                        f"(a2b reads at most {MAX_DEPTH} levels)"
                    )
            elif isinstance(event, closing):
                depth -= 1
    finally:
        loader.dispose()


def _yaml_locate(root, path: Path) -> tuple[int, int] | None:
    node, mark = root, root.start_mark if root is not None else None
    for el in path:
        value = getattr(node, "value", None)
        if isinstance(value, list) and value and isinstance(value[0], tuple):  # a mapping
            text = el if isinstance(el, str) else str(el)  # a key as written: .nan, 1
            for key_node, value_node in value:
                if getattr(key_node, "value", None) == text:
                    node, mark = value_node, key_node.start_mark
                    break
            else:
                break
        elif (
            isinstance(el, int)
            and isinstance(value, list)
            and el < len(value)
            and not isinstance(value[el], tuple)
        ):
            node = value[el]
            mark = node.start_mark
        else:
            break
    return (mark.line + 1, mark.column + 1) if mark is not None else None


def _parse_yaml(text: str, name: str) -> _Document:
    import yaml

    _check_yaml_depth(text, name)
    loader = _yaml_loader()(text)
    try:
        with _gc_paused():
            node = loader.get_single_node()
            data = loader.construct_document(node) if node is not None else None
    except _Duplicate as e:
        line, col = e.mark
        raise InputFileError(f"{name}:{line}:{col}: duplicate key {e.key!r}") from None
    except yaml.MarkedYAMLError as e:
        mark = e.problem_mark or e.context_mark
        where = f":{mark.line + 1}:{mark.column + 1}" if mark else ""
        problem = e.problem or e.context or "syntax error"
        raise InputFileError(f"{name}{where}: invalid YAML: {problem}") from None
    except yaml.reader.ReaderError as e:  # a character YAML does not allow
        line, col = _offset_line_col(
            text, e.position, isinstance(loader, getattr(yaml, "CParser", ()))
        )
        char = e.character if isinstance(e.character, int) else ord(e.character or "\0")
        raise InputFileError(
            f"{name}:{line}:{col}: invalid YAML: {e.reason} (#x{char:04x})"
        ) from None
    except yaml.YAMLError as e:
        first = str(e).splitlines()[0] if str(e) else "syntax error"
        raise InputFileError(f"{name}: invalid YAML: {first}") from None
    finally:
        loader.dispose()
    return _Document(name, data, lambda path: _yaml_locate(node, path))


def _offset_line_col(text: str, offset: int, in_bytes: bool) -> tuple[int, int]:
    """Line and column of a character offset, or of a UTF-8 byte offset (libyaml's)."""
    if not in_bytes:
        return _line_col(text, offset)
    data = text.encode("utf-8")
    start = data.rfind(b"\n", 0, offset) + 1
    return data.count(b"\n", 0, offset) + 1, len(data[start:offset].decode("utf-8", "replace")) + 1


def _parse(text: str, name: str, kind: str | None) -> _Document:
    """Parse ``text`` as JSON or YAML: by ``kind`` if known, else JSON when it looks like it."""
    if not text.strip():
        raise InputFileError(f"{name}: the file is empty")
    if kind == "json":
        return _parse_json(text, name)
    if kind == "yaml":
        return _parse_yaml(text, name)
    if text.lstrip()[:1] in ("{", "["):
        try:
            return _parse_json(text, name)
        except InputFileError as json_error:
            try:
                return _parse_yaml(text, name)
            except InputFileError:
                raise json_error from None
    return _parse_yaml(text, name)


# --------------------------------------------------------------------------------------------
# Validation of the parsed data


def _is_number(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _number(doc: _Document, path: Path, v) -> float:
    if isinstance(v, _NonFinite):
        raise doc.error(path, v.message())
    if not _is_number(v):
        raise doc.error(path, f"expected a number, got {_describe(v)}")
    try:
        f = float(v)
    except OverflowError:  # an integer beyond the doubles
        raise doc.error(path, _NonFinite(str(v)).message()) from None
    if not math.isfinite(f):
        raise doc.error(path, f"{v!r} is not allowed; numbers must be finite")
    return f


def _describe(v) -> str:
    if isinstance(v, _NonFinite):
        return f"the number {v.token}" if len(v.token) <= 24 else "a number too large for a double"
    if isinstance(v, bool):
        return f"the boolean {str(v).lower()}"
    if isinstance(v, str):
        return (
            f"the string {v!r}" if len(v) <= 60 else f"the string {v[:50]!r}… ({len(v)} characters)"
        )
    if v is None:
        return "nothing (null)"
    if isinstance(v, dict):
        return "a mapping"
    if isinstance(v, list):
        return f"a list of {len(v)}"
    return type(v).__name__


def _numbers(doc: _Document, path: Path, v, n: int, what: str) -> list[float]:
    if not isinstance(v, list):
        raise doc.error(path, f"expected a list of {n} numbers {what}, got {_describe(v)}".rstrip())
    if len(v) != n:
        raise doc.error(path, f"expected {n} numbers {what}, got {len(v)}".replace("  ", " "))
    return [_number(doc, path + (i,), x) for i, x in enumerate(v)]


def _list(doc: _Document, path: Path, v, n: int) -> list:
    if not isinstance(v, list) or len(v) != n:
        got = f"{len(v)}" if isinstance(v, list) else _describe(v)
        raise doc.error(path, f"expected a list of {n} angles, got {got}")
    return v


def _angle(doc: _Document, path: Path, v) -> float:
    """An angle: a number (radians) or a string with a ``deg`` suffix (``45deg``)."""
    if isinstance(v, str) and degrees(v) is not None:
        return degrees(v)
    return _number(doc, path, v)


def _mapping(doc: _Document, path: Path, v, what: str) -> dict:
    if not isinstance(v, dict):
        hint = ""
        if not path and isinstance(v, (str, int, float)) and not isinstance(v, bool):
            hint = (  # a file of numbers or a CSV header read as one YAML string
                " (a trajectory file? a2b resample reads TUM, KITTI, EuRoC, CSV and MCAP; "
                "a2b spline and bezier take their poses)"
            )
        raise doc.error(path, f"expected {what}, got {_describe(v)}{hint}")
    return v


def _check_keys(doc: _Document, path: Path, mapping: dict, allowed: tuple, what: str) -> None:
    for key in mapping:
        if key not in allowed:
            hint = difflib.get_close_matches(str(key), allowed, n=1)
            suggestion = f"; did you mean {hint[0]!r}?" if hint else ""
            raise doc.error(
                path + (key,),
                f"unknown key {key!r} in {what} (expected {', '.join(allowed)}){suggestion}",
            )


#: Set by :func:`orthonormalizing`: the residuals of the matrix poses repaired so far.
_REPAIRS: ContextVar[list | None] = ContextVar("a2b_repairs", default=None)


@contextmanager
def orthonormalizing() -> Iterator[list]:
    """Within this context, matrix poses that are orthogonal only to a few digits (up to
    :data:`a2b.poses.REPAIR_TOL`) are projected onto the nearest rotation
    (:func:`a2b.poses.orthonormalize`); the list yielded collects the residual of each repair.
    This is what ``--orthonormalize`` turns on."""
    repairs: list = []
    token = _REPAIRS.set(repairs)
    try:
        yield repairs
    finally:
        _REPAIRS.reset(token)


def current_repairs() -> list | None:
    """The residuals collected by the :func:`orthonormalizing` context in force, else None."""
    return _REPAIRS.get()


def _matrix_pose(rows: list, layout: str) -> np.ndarray:
    """A matrix pose, checked, or repaired within :func:`orthonormalizing`."""
    from ..poses import REPAIR_TOL, check_matrices, orthogonality_residuals, orthonormalize

    repairs = _REPAIRS.get()
    if repairs is None:
        return check_matrices(np.array(rows), layout=layout)
    pose = check_matrices(np.array(rows), layout=layout, tol=REPAIR_TOL)
    residual = float(orthogonality_residuals(pose[:3, :3]))
    if residual > 0.0:
        pose = orthonormalize(pose)
        repairs.append(residual)
    return pose


def _pose(doc: _Document, path: Path, v) -> np.ndarray:
    """Validate one pose mapping and return its robotics 4x4 matrix."""
    from ..poses import (
        matrices_from_quat_trans,
        matrices_from_study,
        quaternions_from_axis_angle,
        quaternions_from_rpy_xyz,
    )

    pose = _mapping(
        doc,
        path,
        v,
        "a pose mapping (matrix, quaternion, quaternion_wxyz, quaternion_xyzw, rpy_xyz, "
        "axis_angle or study)",
    )
    if "start" in pose or "end" in pose:
        raise doc.error(
            path,
            "expected one pose, got start and end poses (a poses file); give a file with one pose",
        )
    _check_keys(doc, path, pose, POSE_KEYS, "a pose")
    forms = [k for k in POSE_FORMS if k in pose]
    if len(forms) != 1:
        found = f"got {' and '.join(forms)}" if forms else "got none"
        raise doc.error(path, f"a pose needs exactly one of {', '.join(POSE_FORMS)} ({found})")
    form = forms[0]
    extras = {"matrix": ("layout",), "study": ("kappa",)}.get(form, ("translation",))
    for key in ("layout", "translation", "kappa"):
        if key in pose and key not in extras:
            raise doc.error(path + (key,), f"{key!r} does not go with {form!r}")
    try:
        if form == "matrix":
            rows = pose["matrix"]
            if not isinstance(rows, list) or len(rows) != 4:
                got = (
                    f"{len(rows)} row{'s' * (len(rows) != 1)}"
                    if isinstance(rows, list)
                    else _describe(rows)
                )
                raise doc.error(path + ("matrix",), f"expected 4 rows of 4 numbers, got {got}")
            m = [_numbers(doc, path + ("matrix", i), r, 4, "") for i, r in enumerate(rows)]
            layout = pose.get("layout", "robotics")
            if layout not in ("robotics", "paper"):
                raise doc.error(
                    path + ("layout",), f"expected robotics or paper, got {_describe(layout)}"
                )
            return _matrix_pose(m, layout)
        if form == "study":
            h = _numbers(
                doc, path + ("study",), pose["study"], 8, "(p0, p1, p2, p3, q0, q1, q2, q3)"
            )
            through = pose.get("kappa", False)
            if not isinstance(through, bool):
                raise doc.error(
                    path + ("kappa",), f"expected true or false, got {_describe(through)}"
                )
            try:
                return matrices_from_study(np.array(h), through_kappa=through)
            except A2bError as e:
                message = str(e)
                if "Study condition" in message:  # say how the file reads it through κ instead
                    message += " (add kappa: true to read it through κ)"
                raise doc.error(path + ("study",), message) from e
        q = pose[form]
        if form == "quaternion" and isinstance(q, dict):
            _check_keys(doc, path + (form,), q, ("w", "x", "y", "z"), "a quaternion")
            missing = [k for k in "wxyz" if k not in q]
            if missing:
                raise doc.error(path + (form,), f"the quaternion lacks {', '.join(missing)}")
            wxyz = [_number(doc, path + (form, k), q[k]) for k in "wxyz"]
        elif form == "quaternion":
            raise doc.error(
                path + (form,),
                "a bare list is ambiguous: a2b once read it as w, x, y, z, ROS writes x, y, z, "
                "w; write quaternion_wxyz: [w, x, y, z] or quaternion_xyzw: [x, y, z, w], or "
                "quaternion: {w: .., x: .., y: .., z: ..}",
            )
        elif form == "quaternion_wxyz":
            wxyz = _numbers(doc, path + (form,), q, 4, "(w, x, y, z)")
        elif form == "rpy_xyz":
            rpy = [
                _angle(doc, path + (form, i), x)
                for i, x in enumerate(_list(doc, path + (form,), q, 3))
            ]
            wxyz = quaternions_from_rpy_xyz(np.array(rpy))
        elif form == "axis_angle":
            turn = _mapping(doc, path + (form,), q, "{axis: [x, y, z], angle: ANGLE}")
            _check_keys(doc, path + (form,), turn, ("axis", "angle"), "an axis_angle")
            missing = [k for k in ("axis", "angle") if k not in turn]
            if missing:
                raise doc.error(path + (form,), f"the axis_angle lacks {', '.join(missing)}")
            axis = _numbers(doc, path + (form, "axis"), turn["axis"], 3, "(x, y, z)")
            angle = _angle(doc, path + (form, "angle"), turn["angle"])
            wxyz = quaternions_from_axis_angle(np.array(axis), angle)
        else:
            x, y, z, w = _numbers(doc, path + (form,), q, 4, "(x, y, z, w)")
            wxyz = [w, x, y, z]  # ROS order is converted here and nowhere else
        t = pose.get("translation", [0.0, 0.0, 0.0])
        if isinstance(t, dict):
            _check_keys(doc, path + ("translation",), t, ("x", "y", "z"), "a translation")
            missing = [k for k in "xyz" if k not in t]
            if missing:
                raise doc.error(
                    path + ("translation",), f"the translation lacks {', '.join(missing)}"
                )
            xyz = [_number(doc, path + ("translation", k), t[k]) for k in "xyz"]
        else:
            xyz = _numbers(doc, path + ("translation",), t, 3, "(x, y, z)")
        return matrices_from_quat_trans(np.array(wxyz), np.array(xyz))
    except InputFileError:
        raise
    except A2bError as e:
        raise doc.error(path + (form,), str(e)) from e


def _samples(doc: _Document, path: Path, v) -> int | None:
    """A file's ``samples``: a whole number in ``[MIN_SAMPLES, MAX_SAMPLES]``, or ``None``."""
    if v is None:
        return None
    here = path + ("samples",)
    if not isinstance(v, int) or isinstance(v, bool):
        shown = _describe(v) if not _is_number(v) else repr(v)
        raise doc.error(
            here, f"expected a whole number of samples, at least {MIN_SAMPLES}, got {shown}"
        )
    if v < MIN_SAMPLES:
        raise doc.error(here, f"expected at least {MIN_SAMPLES} samples (t = 0 and t = 1), got {v}")
    if v > MAX_SAMPLES:
        raise doc.error(
            here,
            f"expected at most 2**53 = {MAX_SAMPLES} samples (more evenly spaced t in [0, 1] "
            f"than doubles tell apart), got {_shorten(str(v))}",
        )
    return v


def _parameters(doc: _Document, path: Path, v) -> dict:
    params = _mapping(doc, path, v, "a mapping of motion parameters")
    _check_keys(doc, path, params, tuple(PARAMETER_KINDS), "parameters")
    out = {}
    for key, value in params.items():
        kind = PARAMETER_KINDS[key]
        here = path + (key,)
        if value is None:
            continue
        if kind == "number":
            angle = (
                degrees(value) if isinstance(value, str) and BY_NAME[key].unit == "radian" else None
            )
            out[key] = angle if angle is not None else _number(doc, here, value)
        elif isinstance(kind, int):
            out[key] = tuple(_numbers(doc, here, value, kind, ""))
        elif kind == "branch":
            if not _is_number(value) or value not in (1, -1):
                raise doc.error(
                    here,
                    f"expected +1 or -1, got "
                    f"{_describe(value) if not _is_number(value) else value}",
                )
            out[key] = int(value)
        elif kind == "bool":
            if not isinstance(value, bool):
                raise doc.error(here, f"expected true or false, got {_describe(value)}")
            out[key] = value
        elif kind == "frame":
            if value not in FRAMES:
                raise doc.error(
                    here, f"expected one of {', '.join(FRAMES)}, got {_describe(value)}"
                )
            out[key] = value
        else:  # pose
            out[key] = _pose(doc, here, value)
    return out


def _job(doc: _Document, path: Path, v, allowed: tuple) -> Job:
    job = _mapping(doc, path, v, "a mapping with start and end")
    if any(k in job for k in POSE_FORMS) and "start" not in job and "end" not in job:
        raise doc.error(
            path, "this is one pose, but start and end poses are needed (see a2b interpolate -h)"
        )
    if "start" not in job and "end" not in job:
        for key, command in (("controls", "a2b bezier"), ("poses", "a2b spline")):
            if key in job:
                raise doc.error(
                    path, f"this is a list of {key} ({command}), but start and end poses are needed"
                )
    _check_keys(doc, path, job, allowed, "a poses file" if allowed is POSES_KEYS else "a job")
    for key in ("start", "end"):
        if key not in job:
            raise doc.error(path, f"missing {key!r}: a poses file needs start and end poses")
    mode = job.get("mode")
    if mode is not None and mode not in MODES:
        raise doc.error(
            path + ("mode",), f"expected one of {', '.join(MODES)}, got {_describe(mode)}"
        )
    samples = _samples(doc, path, job.get("samples"))
    name = job.get("name")
    if name is not None and (isinstance(name, bool) or not isinstance(name, (str, int))):
        raise doc.error(path + ("name",), f"expected a string, got {_describe(name)}")
    if isinstance(name, str):
        _check_name(doc, path + ("name",), name)
    return Job(
        start=_pose(doc, path + ("start",), job["start"]),
        end=_pose(doc, path + ("end",), job["end"]),
        mode=mode,
        samples=samples,
        parameters=_parameters(doc, path + ("parameters",), job.get("parameters") or {}),
        name=None if name is None else str(name),
    )


def _check_name(doc: _Document, path: Path, name: str) -> None:
    """A job's name is written into the ``job`` column: no NUL, and text that UTF-8 can write
    (JSON's ``\\udcff`` escapes a lone surrogate, which it cannot)."""
    if "\0" in name:
        raise doc.error(path, f"{name!r} contains a NUL character")
    try:
        name.encode("utf-8")
    except UnicodeEncodeError as e:
        raise doc.error(
            path, f"{name!r} is no text UTF-8 can write: a lone surrogate, {name[e.start]!r}"
        ) from None


# --------------------------------------------------------------------------------------------
# Public pose-file readers


def _document(stream: IO, name: str | None) -> _Document:
    """Read and parse a whole pose file, JSON or YAML by its suffix or content."""
    name = _stream_name(stream, name)
    return _parse(_read_text(stream, name), name, _kind_from_suffix(name))


def read_pose(stream: IO, name: str | None = None) -> np.ndarray:
    """Read a file holding one pose mapping (``a2b fiber``, ``--through``).

    Returns
    -------
    ndarray, shape (4, 4)
        The pose, robotics layout.

    Raises
    ------
    InputFileError
        Naming the file, the key and the line and column.
    """
    doc = _document(stream, name)
    return _pose(doc, (), doc.data)


def read_poses(stream: IO, name: str | None = None) -> Job:
    """Read a poses file: ``start``, ``end`` and optional ``mode``, ``samples``, ``parameters``.

    Raises
    ------
    InputFileError
        Naming the file, the key and the line and column.
    """
    doc = _document(stream, name)
    return _job(doc, (), doc.data, POSES_KEYS)


#: Curve spaces and kernel bases of a pose list (``a2b bezier``, ``a2b spline``).
SPACES = ("matrix", "study")
BASES = ("paper", "rref", "auto")
#: The parameters a pose list may give, per list key: name -> kind ("m": 4 numbers,
#: "per-pose": one number per pose, "per-pose-6": 6 numbers per pose, "basis": a basis name).
#: The names are those of :func:`a2b.motions.bezier.bezier_motion` and ``spline_motion``.
POSE_LIST_PARAMETERS = {
    "controls": {
        "m": "m",
        "weights": "per-pose",
        "alphas": "per-pose-6",
        "basis": "basis",
        "offsets": "per-pose",
    },
    "poses": {"m": "m"},
}


@dataclass(frozen=True)
class PoseList:
    """The poses of a pose-list file (robotics matrices ``(k, 4, 4)``) and what it says.

    ``key`` is the list's key, ``controls`` (a Bézier curve) or ``poses`` (a spline).
    ``space`` and ``samples`` are ``None`` where the file does not give them; ``parameters``
    holds only the keys the file gives.
    """

    key: str
    poses: np.ndarray
    space: str | None = None
    samples: int | None = None
    parameters: dict = field(default_factory=dict)


def read_pose_list(stream: IO, key: str, name: str | None = None) -> PoseList:
    """Read a file with a list of at least two poses under ``key`` (``controls`` or ``poses``).

    The mapping may also give ``space`` (matrix or study), ``samples`` and ``parameters``
    (:data:`POSE_LIST_PARAMETERS`). Every pose may be in any pose form; errors name the file,
    the line and column and the key, e.g.
    ``curve.yaml:7:5: controls[2].quaternion: expected 4 numbers (w, x, y, z), got 3``.

    Raises
    ------
    InputFileError
    """
    if key not in POSE_LIST_PARAMETERS:
        raise ValueError(f"key must be one of {', '.join(POSE_LIST_PARAMETERS)}, got {key!r}")
    return _pose_list(_document(stream, name), key)


def _pose_list(doc: _Document, key: str) -> PoseList:
    top = _mapping(doc, (), doc.data, f"a mapping with {key}")
    if "start" in top and "end" in top and key not in top:
        raise doc.error(
            (),
            f"this is a poses file (start and end); this command needs a list of poses under "
            f"{key!r}",
        )
    _check_keys(doc, (), top, (key, "space", "samples", "parameters"), f"a {key} file")
    if key not in top:
        raise doc.error((), f"missing {key!r}: a list of at least two poses")
    items = top[key]
    if not isinstance(items, list) or len(items) < 2:
        got = f"{len(items)}" if isinstance(items, list) else _describe(items)
        raise doc.error((key,), f"expected a list of at least two poses, got {got}")
    poses = np.stack([_pose(doc, (key, i), item) for i, item in enumerate(items)])
    k = len(items)
    space = top.get("space")
    if space is not None and space not in SPACES:
        raise doc.error(("space",), f"expected one of {', '.join(SPACES)}, got {_describe(space)}")
    samples = _samples(doc, (), top.get("samples"))
    given = _mapping(
        doc, ("parameters",), top.get("parameters") or {}, "a mapping of curve parameters"
    )
    kinds = POSE_LIST_PARAMETERS[key]
    _check_keys(doc, ("parameters",), given, tuple(kinds), "parameters")
    parameters = {}
    for pname, value in given.items():
        here = ("parameters", pname)
        kind = kinds[pname]
        if value is None:
            continue
        if kind == "m":
            parameters[pname] = tuple(_numbers(doc, here, value, 4, "(m0, m1, m2, m3)"))
        elif kind == "per-pose":
            parameters[pname] = tuple(_numbers(doc, here, value, k, f"(one per pose in {key})"))
        elif kind == "per-pose-6":
            if not isinstance(value, list) or len(value) != k:
                got = len(value) if isinstance(value, list) else _describe(value)
                raise doc.error(
                    here, f"expected {k} lists of 6 numbers (one per pose in {key}), got {got}"
                )
            rows = [_numbers(doc, here + (i,), row, 6, "(α0 … α5)") for i, row in enumerate(value)]
            parameters[pname] = tuple(tuple(row) for row in rows)
        else:
            if value not in BASES:
                raise doc.error(here, f"expected one of {', '.join(BASES)}, got {_describe(value)}")
            parameters[pname] = value
    return PoseList(key, poses, space, samples, parameters)


def read_motion_file(stream: IO, name: str | None = None) -> Job | PoseList:
    """Read a poses file (``start``, ``end``) or a pose list (``controls`` or ``poses``).

    The top-level keys tell which: ``controls`` makes a Bézier curve's :class:`PoseList`,
    ``poses`` a spline's, anything else is read as a poses file (:func:`read_poses`).
    """
    doc = _document(stream, name)
    if isinstance(doc.data, dict):
        for key in POSE_LIST_PARAMETERS:
            if key in doc.data:
                return _pose_list(doc, key)
    return _job(doc, (), doc.data, POSES_KEYS)


@dataclass
class JobBlock:
    """Consecutive jobs of a jobs file, validated, with their poses stacked.

    ``start`` and ``end`` are robotics matrices ``(n, 4, 4)``; ``modes``, ``samples``,
    ``parameters`` and ``names`` are lists of ``n`` entries, as the fields of :class:`Job`
    (``None`` where the file does not give one). ``checked``: every pose passed
    :func:`a2b.poses.check_matrices` (true for the blocks of a jobs file).
    """

    start: np.ndarray
    end: np.ndarray
    modes: list
    samples: list
    parameters: list
    names: list
    _jobs: list | None = None
    checked: bool = False

    def __len__(self) -> int:
        return len(self.modes)

    def job(self, i: int) -> Job:
        """Job ``i`` of the block (the object given to :meth:`from_jobs`, if any)."""
        if self._jobs is not None:
            return self._jobs[i]
        return Job(
            self.start[i],
            self.end[i],
            self.modes[i],
            self.samples[i],
            self.parameters[i],
            self.names[i],
        )

    def jobs(self) -> list[Job]:
        """The jobs one by one."""
        return [self.job(i) for i in range(len(self))]

    def split(self, n: int) -> tuple[JobBlock, JobBlock]:
        """The first ``n`` jobs and the rest."""

        def part(sl):
            return JobBlock(
                self.start[sl], self.end[sl], self.modes[sl], self.samples[sl],
                self.parameters[sl], self.names[sl], None if self._jobs is None else self._jobs[sl],
                self.checked,
            )  # fmt: skip

        return part(slice(None, n)), part(slice(n, None))

    @classmethod
    def concatenate(cls, blocks: list[JobBlock]) -> JobBlock:
        """One block of the jobs of ``blocks``, in order."""
        if len(blocks) == 1:
            return blocks[0]
        jobs = None
        if all(b._jobs is not None for b in blocks):
            jobs = [job for b in blocks for job in b._jobs]
        elif any(b._jobs is not None for b in blocks):
            jobs = [job for b in blocks for job in b.jobs()]
        return cls(
            np.concatenate([b.start for b in blocks]),
            np.concatenate([b.end for b in blocks]),
            [m for b in blocks for m in b.modes],
            [s for b in blocks for s in b.samples],
            [p for b in blocks for p in b.parameters],
            [n for b in blocks for n in b.names],
            jobs,
            all(b.checked for b in blocks),
        )

    @classmethod
    def from_jobs(cls, jobs: list[Job]) -> JobBlock:
        """A block of the given jobs. Poses that are no 4x4 arrays of numbers are stacked as
        NaN; :meth:`job` still returns them as given."""

        def stack(poses):
            out = np.full((len(poses), 4, 4), np.nan)
            for i, pose in enumerate(poses):
                try:
                    value = np.asarray(pose, dtype=float)
                except (ValueError, TypeError):
                    continue
                if value.shape == (4, 4):
                    out[i] = value
            return out

        return cls(
            stack([j.start for j in jobs]),
            stack([j.end for j in jobs]),
            [j.mode for j in jobs],
            [j.samples for j in jobs],
            [j.parameters for j in jobs],
            [j.name for j in jobs],
            list(jobs),
        )


@dataclass
class Jobs:
    """The jobs of a jobs file: iterate to validate and get them one by one, or take them in
    blocks (:meth:`blocks`); use one or the other.

    ``count`` is the number of jobs, or ``None`` for JSON Lines, which are read lazily.
    """

    count: int | None
    _iter: Iterator[Job]
    _blocks: Callable[[int], Iterator[JobBlock]] | None = None

    def __iter__(self) -> Iterator[Job]:
        return self._iter

    def blocks(self, size: int = 256) -> Iterator[JobBlock]:
        """The jobs in :class:`JobBlock` s of ``size`` (the last may be shorter).

        The same jobs and the same errors, raised at the same job, as iterating: a block holds
        the jobs before an invalid one, and the error comes when the next block is asked for.
        Blocks are read a block ahead at most, and validated in bulk: the poses of the
        common forms (quaternion and translation, robotics matrix) with array operations,
        anything else job by job.
        """
        if size < 1:
            raise ValueError(f"a block holds at least one job, got size {size}")
        if self._blocks is None:
            return job_blocks(self._iter, size)
        return self._blocks(size)


def job_blocks(jobs: Iterable[Job], size: int) -> Iterator[JobBlock]:
    """Any jobs in :class:`JobBlock` s of ``size``, taken from ``jobs`` a block at a time.

    An :class:`A2bError` while taking them (a lazily validated file) comes after a block of
    the jobs before it, as with :meth:`Jobs.blocks`.
    """
    block: list[Job] = []
    try:
        for job in jobs:
            block.append(job)
            if len(block) == size:
                yield JobBlock.from_jobs(block)
                block = []
    except A2bError:
        if block:
            yield JobBlock.from_jobs(block)
        raise
    if block:
        yield JobBlock.from_jobs(block)


def read_jobs(stream: IO, name: str | None = None) -> Jobs:
    """Read a jobs file: a YAML or JSON list of job mappings, or JSON Lines (one per line).

    A job has ``start``, ``end`` and optionally ``name``, ``mode``, ``samples`` and
    ``parameters``. JSON Lines are read line by line as the jobs are consumed, so a large file
    never sits in memory, and the error of a line comes as soon as the line arrives, after
    the jobs before it. A list is parsed and validated at once (the parsed tree is then
    dropped, before Python's cyclic collector would walk it); the error of an invalid job is
    raised when the jobs before it have been taken.
    """
    sniffed = sniff(stream, name)
    name, kind = sniffed.name, sniffed.kind
    if sniffed.json_lines:
        return _json_lines_jobs(_lines(stream, name, sniffed.first), name)
    raw_start = sniffed.first
    with _gc_paused():
        doc = _parse(_decode(raw_start + stream.read(), name), name, kind)
        if not isinstance(doc.data, list):
            hint = " (one motion: a2b interpolate)" if isinstance(doc.data, dict) else ""
            raise doc.error((), f"expected a list of jobs, got {_describe(doc.data)}{hint}")
        if not doc.data:
            raise doc.error((), "expected a list of jobs, got an empty list")
        count = len(doc.data)
        block, error = _list_jobs(doc)
        del doc

    def jobs() -> Iterator[Job]:
        for i in range(len(block)):
            yield block.job(i)
        if error is not None:
            raise error

    def blocks(size: int) -> Iterator[JobBlock]:
        rest = block
        while len(rest):
            piece, rest = rest.split(size)
            yield piece
        if error is not None:
            raise error

    return Jobs(count, jobs(), blocks)


def _list_jobs(doc: _Document) -> tuple[JobBlock, InputFileError | None]:
    """The jobs of a parsed list before the first invalid one, and that one's error."""
    builder = Scanned()
    for i, item in enumerate(doc.data):
        if not builder.add_fast(item, None, (doc, i, item)):
            try:
                job = _job(doc, (i,), item, JOB_KEYS)
            except InputFileError as e:
                return _finished(builder, e)
            builder.add_job(job, (doc, i, item))
    return _finished(builder, None)


def _finished(builder: Scanned, error):
    """:func:`finish_block` as one block and the error that comes first."""
    blocks = []
    try:
        blocks.extend(finish_block(builder))
    except InputFileError as e:
        error = e
    if not blocks:
        empty = np.empty((0, 4, 4))
        return JobBlock(empty, empty, [], [], [], [], checked=True), error
    return blocks[0], error


def _json_lines_jobs(lines: Iterator[str], name: str) -> Jobs:
    def blocks(size: int) -> Iterator[JobBlock]:
        for scanned in scan_blocks(lines, name, size, json_line_job):
            yield from finish_block(scanned)

    return Jobs(None, _json_lines(lines, name), blocks)


def _json_lines(lines: Iterator[str], name: str) -> Iterator[Job]:
    index = 0
    for number, line in enumerate(lines, start=1):
        if not line.strip():
            continue
        yield json_line_job(line, name, number, index)
        index += 1
    if index == 0:
        raise InputFileError(f"{name}: no jobs: the file has no lines with a job")


def json_line_job(line: str, name: str, number: int, index: int) -> Job:
    """The job on line ``number`` of a JSON Lines file, the ``index``-th job, fully checked."""
    doc = _parse_json(line.rstrip("\r\n"), name, first_line=number)  # an error at its end: here
    inner = doc.locate
    doc.locate = lambda path, _inner=inner: _inner(path[1:])  # the job index is the line
    return _job(doc, (index,), doc.data, JOB_KEYS)


def _exact_job(where: tuple) -> Job:
    """The exact reading of a job that the bulk check did not accept: it raises the error."""
    if isinstance(where[0], str):
        return json_line_job(*where)
    doc, i, item = where
    return _job(doc, (i,), item, JOB_KEYS)


def _poses(scanned: Scanned) -> tuple[np.ndarray, np.ndarray]:
    """The matrices of every slot, quaternion slots first, and which of them are valid."""
    from ..elements import unit_scale
    from ..poses import rotations_from_quaternions, valid_matrices

    q, m = _numbers_of(scanned.q, 7), _numbers_of(scanned.m, 16)
    q_ok, m_ok = q[1], m[1]
    q, m = q[0].reshape(-1, 7), m[0].reshape(-1, 4, 4)
    with np.errstate(all="ignore"):
        quat = unit_scale(q[:, :4])
        norm = np.linalg.norm(quat, axis=-1)
        q_ok &= np.isfinite(q).all(axis=1) & (norm != 0.0) & np.isfinite(norm)
        mats = np.zeros((len(q) + len(m), 4, 4))
        mats[: len(q), :3, :3] = rotations_from_quaternions(quat / norm[:, None])
        mats[: len(q), :3, 3] = q[:, 4:]
        mats[: len(q), 3, 3] = 1.0
        mats[len(q) :] = m
        m_ok &= valid_matrices(m)
    return mats, np.concatenate([q_ok, m_ok])


def finish_block(scanned: Scanned) -> Iterator[JobBlock]:
    """The :class:`JobBlock` of scanned jobs (none if there are none): their numbers checked
    in bulk; at a job they fail, read it the exact way, which raises its error after the block
    of the jobs before it."""
    n = len(scanned)
    if not n:
        return
    mats, ok = _poses(scanned)
    quaternions = len(scanned.q) // 7
    ok = np.append(ok, False)  # where the jobs read the exact way point
    starts, ends, modes, samples, parameters, names, where = map(list, zip(*scanned.records))

    def index(slots):
        arr = np.array([len(mats) if s is None else s for s in slots], dtype=np.intp)
        return np.where(arr >= 0, arr, quaternions + ~arr)

    start_at, end_at = index(starts), index(ends)
    mats = np.concatenate([mats, np.zeros((1, 4, 4))])
    start, end = mats[start_at], mats[end_at]

    def block(k: int) -> JobBlock:
        return JobBlock(
            start[:k], end[:k], modes[:k], samples[:k], parameters[:k], names[:k], checked=True
        )

    for i in np.flatnonzero(~(ok[start_at] & ok[end_at])).tolist():
        job = scanned.exact.get(i)
        if job is None:
            try:
                job = _exact_job(where[i])
            except InputFileError:
                if i:
                    yield block(i)
                raise
        start[i], end[i] = job.start, job.end
    yield block(n)


def _numbers_of(values: list, width: int) -> tuple[np.ndarray, np.ndarray]:
    """``values`` as a float array, and which groups of ``width`` are all ints and floats.

    A group with anything else (a bool, a string, ``None``, a YAML number that is no finite
    double) is zeroed and marked, as are all groups if an integer is beyond the doubles.
    """
    groups = len(values) // width
    ok = np.ones(groups, dtype=bool)
    if not _NUMBER_TYPES.issuperset(map(type, values)):
        values = list(values)
        for g in range(groups):
            if not _NUMBER_TYPES.issuperset(map(type, values[g * width : (g + 1) * width])):
                ok[g] = False
                values[g * width : (g + 1) * width] = [0.0] * width
    try:
        return np.array(values, dtype=float), ok
    except OverflowError:  # an integer beyond the doubles
        return np.zeros(len(values)), np.zeros(groups, dtype=bool)


# --------------------------------------------------------------------------------------------
# The batch CSV of the writers (the trajectory formats are read by :mod:`a2b.io.trajectories`)


def _text_stream(stream: IO):
    if isinstance(stream, io.TextIOBase):
        return stream
    return io.TextIOWrapper(stream, encoding="utf-8", newline="")


def read_batch_csv(stream: IO) -> tuple[list[str], np.ndarray]:
    """Read ``a2b batch`` output: the ``job`` column and the remaining columns as floats."""
    import csv

    reader = csv.reader(_text_stream(stream))
    header = next(reader)
    if header[0] != "job":
        raise InputFileError("batch csv: the first column must be 'job'")
    jobs, values = [], []
    for row in reader:
        jobs.append(row[0])
        values.append([float(x) for x in row[1:]])
    return jobs, np.array(values, dtype=float).reshape(len(values), len(header) - 1)
