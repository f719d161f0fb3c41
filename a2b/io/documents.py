"""Documents: JSON and YAML text parsed, with a way back from a key path to a line and column.

A pose file, a jobs file and a pose list are documents: :func:`read_document` parses one, JSON
or YAML by its suffix or its content, into a :class:`Document` whose :meth:`Document.error`
words an :class:`a2b.errors.InputFileError` that starts ``FILE:LINE:COLUMN:`` and names the key.

YAML is read with the YAML 1.2 core schema: ``1e-3`` is a number; ``1:20``, ``1_000``, ``yes``
and ``no`` are strings. Numbers must be finite doubles: ``NaN``, ``.inf``, ``1e999`` and
400-digit integers stand in as :class:`NonFinite` (so the error can name the key), and bytes
that are not UTF-8, duplicate keys and nesting deeper than :data:`MAX_DEPTH` levels are errors.
What the pose forms mean is :mod:`a2b.io.poseschema`'s concern.
"""

from __future__ import annotations

import gc
import json
import math
import re
import sys
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from json.decoder import scanstring
from typing import IO, Any

from ..errors import DuplicateKey, InputFileError, printable

__all__ = [
    "MAX_DEPTH",
    "Document",
    "NonFinite",
    "decode",
    "gc_paused",
    "kind_from_suffix",
    "parse",
    "parse_json",
    "read_document",
    "shorten",
    "stream_name",
]

Path = tuple  # keys (str) and list indexes (int) from the document root


def stream_name(stream: IO, name: str | None) -> str:
    """``name`` if given, else the stream's file name, else ``<stdin>``: the name in messages,
    with its control characters escaped (:func:`a2b.errors.printable`)."""
    if not name:
        name = getattr(stream, "name", None)
    return printable(name) if isinstance(name, str) and name else "<stdin>"


def kind_from_suffix(name: str) -> str | None:
    """``json``, ``jsonl`` or ``yaml`` by the suffix of ``name``, else ``None``."""
    lower = name.lower()
    for suffixes, kind in (
        ((".json",), "json"),
        ((".jsonl", ".ndjson"), "jsonl"),
        ((".yaml", ".yml"), "yaml"),
    ):
        if lower.endswith(suffixes):
            return kind
    return None


def decode(raw: bytes | str, name: str, first_line: int = 1) -> str:
    """UTF-8 text (a leading byte-order mark dropped); bytes that are not UTF-8 are an error."""
    if isinstance(raw, str):
        return raw
    try:
        return raw.decode("utf-8-sig" if first_line == 1 else "utf-8")
    except UnicodeDecodeError as e:
        line = raw.count(b"\n", 0, e.start) + first_line
        column = e.start - (raw.rfind(b"\n", 0, e.start) + 1) + 1
        raise InputFileError(
            f"{name}:{line}:{column}: not UTF-8 text (byte 0x{raw[e.start]:02x})"
        ) from None


class NonFinite:
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
        return f"{shorten(token)} is too large for a double; numbers must be finite (|x| < 1.8e308)"


def shorten(token: str) -> str:
    """A long number as its first and last digits and its length."""
    if len(token) <= 24:
        return token
    return f"{token[:12]}…{token[-6:]} ({sum(ch.isdigit() for ch in token)} digits)"


#: Deepest nesting of lists and mappings read (a pose file needs 6); deeper input is an error,
#: never a crash of the C YAML composer, which recurses on the C stack.
MAX_DEPTH = 100


@dataclass
class Document:
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
            el = shorten_key(el)
        out += f"[{el}]" if isinstance(el, int) else (f".{el}" if out else el)
    return out


def shorten_key(text: str) -> str:
    """A key for a message: a long one as its start and its length."""
    return text if len(text) <= 60 else f"{text[:50]}… ({len(text)} characters)"


@contextmanager
def gc_paused() -> Iterator[None]:
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


# -- JSON --


def _json_pairs(pairs: list) -> dict:
    out = {}
    for key, value in pairs:
        if key in out:
            raise DuplicateKey(key)
        out[key] = value
    return out


def _json_float(token: str):
    value = float(token)
    return value if math.isfinite(value) else NonFinite(token)


def _json_int(token: str):
    try:
        return int(token)
    except ValueError:  # more digits than int() converts (sys.get_int_max_str_digits)
        return NonFinite(token)


_JSON = json.JSONDecoder(
    object_pairs_hook=_json_pairs,
    parse_constant=NonFinite,
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


def parse_json(text: str, name: str, first_line: int = 1) -> Document:
    """Parse JSON; ``first_line`` is the line of the file that ``text`` starts on (JSON Lines)."""

    def where(pos: int) -> tuple[int, int]:
        line, col = _line_col(text, pos)
        return line + first_line - 1, col

    try:
        with gc_paused():
            data = _JSON.decode(text)
    except DuplicateKey as e:
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
    return Document(name, data, lambda path: where(_json_locate(text, path)))


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


def _yaml():
    import yaml

    return yaml


class _CoreSchema:
    """The constructors of :func:`_yaml_loader`'s loader, mixed into PyYAML's safe loader:
    duplicate keys refused, names as written, YAML 1.2 core-schema numbers and booleans."""

    def construct_mapping(self, node, deep=False):
        seen = set()
        for key_node, value_node in node.value:
            key = self.construct_object(key_node, deep=deep)
            if key == "name" and isinstance(value_node, _yaml().ScalarNode):
                value_node.tag = _STR  # a name is the text as written: 007, true, 1e3
            try:
                repeated = key in seen
            except TypeError:  # an unhashable key; the constructor reports it
                break
            if repeated:
                mark = key_node.start_mark
                raise DuplicateKey(str(key), (mark.line + 1, mark.column + 1))
            seen.add(key)
        return super().construct_mapping(node, deep=deep)

    def construct_yaml_int(self, node):
        text = self.construct_scalar(node)
        digits = text.lstrip("+-")
        try:
            if digits.startswith(("0o", "0x")):
                value = int(digits[2:], 8 if digits[1] == "o" else 16)
                if value > sys.float_info.max:  # beyond a double (and beyond str())
                    return NonFinite(text)
                return -value if text.startswith("-") else value
            return int(text)
        except ValueError:
            if re.fullmatch(r"[-+]?[0-9]+", text):  # more digits than int() converts
                return NonFinite(text)
            raise _yaml().constructor.ConstructorError(
                None, None, f"cannot read {text!r} as an integer", node.start_mark
            ) from None

    def construct_yaml_bool(self, node):
        text = self.construct_scalar(node)
        if text not in _YAML_BOOLEANS:
            raise _yaml().constructor.ConstructorError(
                None, None, f"cannot read {text!r} as true or false", node.start_mark
            )
        return _YAML_BOOLEANS[text]

    def construct_undefined(self, node):
        raise _yaml().constructor.ConstructorError(
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
            return NonFinite(text)
        try:
            value = float(text)
        except ValueError:
            raise _yaml().constructor.ConstructorError(
                None, None, f"cannot read {text!r} as a number", node.start_mark
            ) from None
        return value if math.isfinite(value) else NonFinite(text)


def _yaml_loader():
    """A safe loader with YAML 1.2 core-schema scalars that rejects duplicate keys.

    Numbers that are no finite double (``.inf``, ``.nan``, ``1e999``, 400-digit integers)
    become :class:`NonFinite`, so the error names the key and the text as written.
    """
    global _YAML_LOADER
    if _YAML_LOADER is not None:
        return _YAML_LOADER
    import yaml

    base = getattr(yaml, "CSafeLoader", yaml.SafeLoader)

    class Loader(_CoreSchema, base):  # type: ignore[misc, valid-type]
        pass

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


def _parse_yaml(text: str, name: str) -> Document:
    import yaml

    _check_yaml_depth(text, name)
    loader = _yaml_loader()(text)
    try:
        with gc_paused():
            node = loader.get_single_node()
            data = loader.construct_document(node) if node is not None else None
    except DuplicateKey as e:
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
    return Document(name, data, lambda path: _yaml_locate(node, path))


def _offset_line_col(text: str, offset: int, in_bytes: bool) -> tuple[int, int]:
    """Line and column of a character offset, or of a UTF-8 byte offset (libyaml's)."""
    if not in_bytes:
        return _line_col(text, offset)
    data = text.encode("utf-8")
    start = data.rfind(b"\n", 0, offset) + 1
    return data.count(b"\n", 0, offset) + 1, len(data[start:offset].decode("utf-8", "replace")) + 1


def parse(text: str, name: str, kind: str | None) -> Document:
    """Parse ``text`` as JSON or YAML: by ``kind`` if known, else JSON when it looks like it."""
    if not text.strip():
        raise InputFileError(f"{name}: the file is empty")
    if kind == "json":
        return parse_json(text, name)
    if kind == "yaml":
        return _parse_yaml(text, name)
    if text.lstrip()[:1] in ("{", "["):
        try:
            return parse_json(text, name)
        except InputFileError as json_error:
            try:
                return _parse_yaml(text, name)
            except InputFileError:
                raise json_error from None
    return _parse_yaml(text, name)


def read_document(stream: IO, name: str | None = None) -> Document:
    """Read and parse a whole document, JSON or YAML by its suffix or content."""
    name = stream_name(stream, name)
    return parse(decode(stream.read(), name), name, kind_from_suffix(name))
