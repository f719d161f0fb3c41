"""Fuzzing the input path: malformed files at the readers and at the commands.

Every generated input is malformed *by construction* (a mutation that no valid file survives:
a wrong type, a wrong length, a missing or unknown or repeated key, a number that is no
finite double, a truncated or garbled text, bytes that are not UTF-8, deep nesting, ...), so
every case must end in one clear message:

* readers (:func:`read_pose`, :func:`read_poses`, :func:`read_jobs`, :func:`read_pose_list`)
  raise :class:`InputFileError` with one line that starts with the file name;
* ``a2b interpolate``, ``a2b fiber`` and ``a2b batch`` (in-process, click's ``CliRunner``)
  exit with status 1 and one line ``Error: ...`` on stderr (status 2 for malformed options),
  with no traceback and no output file, not even a temporary one.

The examples are derandomised (a fixed seed per test), so CI runs the same cases every time;
``A2B_FUZZ_EXAMPLES=200000 pytest tests/test_fuzz.py`` runs a larger share of each class
(default 10 000 in all), and ``A2B_FUZZ_SEED=n`` explores other cases. Each test counts the
examples it actually ran and asserts its quota; ``test_total_cases`` asserts the sum.
"""

from __future__ import annotations

import io
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest
from click.testing import CliRunner
from hypothesis import HealthCheck, Phase, given, seed, settings
from hypothesis import strategies as st

from a2b.cli import cli
from a2b.errors import A2bError, InputFileError
from a2b.io import jobfiles, poseschema

TOTAL = int(os.environ.get("A2B_FUZZ_EXAMPLES", "10000"))
SEED = os.environ.get("A2B_FUZZ_SEED")

#: Share of the examples per test; the shares sum to 1.
SHARES = {
    "pose": 0.12,
    "poses": 0.22,
    "jobs": 0.13,
    "pose_list": 0.10,
    "interpolate": 0.18,
    "fiber": 0.09,
    "batch": 0.10,
    "options": 0.06,
}
assert math.isclose(sum(SHARES.values()), 1.0)
QUOTA = {name: math.ceil(share * TOTAL) for name, share in SHARES.items()}
COUNTS: dict[str, int] = {}


def run_fuzz(name: str, strategy, check) -> None:
    """Run ``check`` on ``QUOTA[name]`` cases drawn from ``strategy``; assert that many ran."""
    count = 0

    @settings(
        max_examples=QUOTA[name],
        derandomize=SEED is None,
        database=None,
        deadline=None,
        phases=(Phase.explicit, Phase.generate),
        suppress_health_check=list(HealthCheck),
    )
    @given(strategy)
    def run(case):
        nonlocal count
        count += 1
        check(case)

    if SEED is not None:
        run = seed(int(SEED))(run)
    run()
    COUNTS[name] = count
    assert count >= QUOTA[name], f"{name}: ran {count} of {QUOTA[name]} cases"


# -- documents: valid trees, mutated so that no valid file survives --------------------------


class Raw:
    """A token written as is (``NaN``, ``.inf``, ``1e999``, a 400-digit integer)."""

    def __init__(self, token: str):
        self.token = token

    def __repr__(self):
        return f"Raw({self.token!r})"


class Pairs(list):
    """A mapping written from a list of (key, value) pairs, so a key can repeat."""


def items(node):
    return list(node) if isinstance(node, Pairs) else list(node.items())


IDENTITY = {"quaternion_wxyz": [1, 0, 0, 0]}
QUARTER = {
    "quaternion_wxyz": [0.7071067811865476, 0, 0, 0.7071067811865476],
    "translation": [1, 1, 0.5],
}
POSES = [
    IDENTITY,
    QUARTER,
    {
        "quaternion": {"w": 0.5, "x": 0.5, "y": -0.5, "z": 0.5},
        "translation": {"x": 1, "y": -2, "z": 0.25},
    },
    {"quaternion_xyzw": [0, 0, 0.7071067811865476, 0.7071067811865476], "translation": [0, 0, 1]},
    {"matrix": [[0, -1, 0, 1], [1, 0, 0, 2], [0, 0, 1, 3], [0, 0, 0, 1]]},
    {"matrix": [[1, 0, 0, 0], [0.5, 1, 0, 0], [0.25, 0, 1, 0], [0, 0, 0, 1]], "layout": "paper"},
    {"study": [1, 0, 0, 0, 0, -0.5, 0, 0]},
    {"study": [1, 0, 0, 0, 0.5, -0.5, 0, 0], "kappa": True},
]
PARAMETERS = [
    {},
    {"delta": 0.2},
    {"lam": 2.0, "branch": -1},
    {"pitch_start": 0.1},
    {"through": QUARTER},
    {"long_way": True},
    {"m": [1, 0, 0, 0.5], "a": 0.1, "b": -0.2},
    {"alpha": [0, 0, 0, 0, 0, 0.1], "frame": "given"},
]
MODE_OF = {"m": "cubic", "alpha": "cubic"}
POSE_FORMS = ("matrix", "quaternion", "quaternion_wxyz", "quaternion_xyzw", "study")
#: Keys whose value is an enumeration, and what they allow.
ENUMS = {
    "mode": ("darboux", "cubic", "screw"),
    "layout": ("robotics", "paper"),
    "frame": ("canonical", "given"),
    "space": ("matrix", "study"),
    "basis": ("paper", "rref", "auto"),
}
BOOLS = ("kappa", "long_way")
#: Lists of a fixed length: key -> length (matrix rows too).
LENGTHS = {
    "quaternion_wxyz": 4,
    "quaternion_xyzw": 4,
    "translation": 3,
    "study": 8,
    "m": 4,
    "alpha": 6,
    "beta": 6,
}
#: Keys each mapping allows, by the key it sits under (None: the top of a file).
POSE_KEYS = set(poseschema.POSE_KEYS)


def poses_doc(draw, *, job=False):
    doc = {"start": draw(st.sampled_from(POSES)), "end": draw(st.sampled_from(POSES))}
    params = draw(st.sampled_from(PARAMETERS))
    if params:
        doc["parameters"] = params
        if any(k in MODE_OF for k in params):
            doc["mode"] = "cubic"
    if draw(st.booleans()):
        doc["samples"] = draw(st.integers(2, 5))
    if job and draw(st.booleans()):
        doc["name"] = draw(st.sampled_from(["lift", "job 1", "a,b"]))
    return doc


@st.composite
def valid_doc(draw, kind: str):
    """A valid document of ``kind``: pose, poses, jobs or pose_list."""
    if kind == "pose":
        return json.loads(json.dumps(draw(st.sampled_from(POSES))))
    if kind == "poses":
        return json.loads(json.dumps(poses_doc(draw)))
    if kind == "jobs":
        return json.loads(
            json.dumps([poses_doc(draw, job=True) for _ in range(draw(st.integers(1, 3)))])
        )
    key = draw(st.sampled_from(["controls", "poses"]))
    doc = {key: [draw(st.sampled_from(POSES[:5])) for _ in range(draw(st.integers(2, 4)))]}
    if draw(st.booleans()):
        doc["space"] = draw(st.sampled_from(["matrix", "study"]))
    return json.loads(json.dumps(doc))


def walk(node, path=()):
    """Every (path, value) of a tree, the root first."""
    yield path, node
    if isinstance(node, (dict, Pairs)):
        for key, value in items(node):
            yield from walk(value, path + (key,))
    elif isinstance(node, list):
        for i, value in enumerate(node):
            yield from walk(value, path + (i,))


def get(node, path):
    for el in path:
        node = dict(items(node))[el] if isinstance(node, (dict, Pairs)) else node[el]
    return node


def replace(tree, path, value):
    """``tree`` with the node at ``path`` replaced (``path == ()`` replaces the tree)."""
    if not path:
        return value
    parent = get(tree, path[:-1])
    if isinstance(parent, Pairs):
        for i, (k, _) in enumerate(parent):
            if k == path[-1]:
                parent[i] = (k, value)
    else:
        parent[path[-1]] = value
    return tree


def in_pose(path) -> bool:
    return any(el in POSE_FORMS or el == "translation" for el in path if isinstance(el, str))


def is_number(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


NOT_NUMBERS = st.one_of(
    st.text(max_size=8),  # written quoted: a string in JSON and YAML alike
    st.booleans(),
    st.lists(st.integers(0, 3), max_size=3),
    st.just({"x": 1}),
)
NON_FINITE = st.sampled_from(
    [
        "NaN",
        "Infinity",
        "-Infinity",
        ".inf",
        "-.inf",
        ".nan",
        ".NaN",
        "1e309",
        "-1e999",
        "1.0e+400",
        "1" + "0" * 400,
        "-" + "9" * 320,
        "1" + "0" * 5000,
        "0x1" + "0" * 300,
    ]
).map(Raw)


@st.composite
def mutated(draw, kind: str):
    """A tree of ``kind`` with one change that no valid file survives, and its name."""
    tree = draw(valid_doc(kind))
    nodes = list(walk(tree))
    numbers = [p for p, v in nodes if is_number(v) and p and p[-1] != "name"]
    mappings = [p for p, v in nodes if isinstance(v, dict)]
    choices = ["wrong type", "non-finite", "unknown key", "duplicate key", "missing key",
               "wrong length", "wrong container", "bad enum", "bad samples",
               "bad pose"]  # fmt: skip
    how = draw(st.sampled_from(choices))
    if how == "wrong type" and numbers:
        path = draw(st.sampled_from(numbers))
        return replace(tree, path, draw(NOT_NUMBERS)), how
    if how == "non-finite" and numbers:
        path = draw(st.sampled_from(numbers))
        return replace(tree, path, draw(NON_FINITE)), how
    if how in ("unknown key", "duplicate key") and mappings:
        path = draw(st.sampled_from(mappings))
        node = get(tree, path)
        if how == "unknown key" and not (
            path and path[-1] in ("quaternion", "quaternion_wxyz", "translation")
        ):
            allowed = {"start", "end", "mode", "samples", "parameters", "name", "controls", "poses",
                       "space", *POSE_KEYS, *poseschema.PARAMETER_KINDS, "weights", "alphas",
                       "basis", "offsets", "x", "y", "z", "w"}  # fmt: skip
            key = draw(st.text(min_size=1, max_size=10).filter(lambda k: k not in allowed))
            node[key] = 1
            return tree, how
        if how == "duplicate key" and node:
            pairs = Pairs(node.items())
            pairs.insert(
                draw(st.integers(0, len(pairs))), draw(st.sampled_from(list(node.items())))
            )
            return replace(tree, path, pairs), how
    if how == "missing key":
        if kind in ("poses", "jobs"):
            doc = tree if kind == "poses" else tree[draw(st.integers(0, len(tree) - 1))]
            del doc[draw(st.sampled_from(["start", "end"]))]
            return tree, how
        if kind == "pose":
            form = next(k for k in tree if k in POSE_FORMS)
            del tree[form]
            return tree, how
        key = next(k for k in tree if k in ("controls", "poses"))
        if draw(st.booleans()):
            del tree[key]
        else:
            tree[key] = tree[key][: draw(st.integers(0, 1))]
        return tree, how
    if how == "wrong length":
        lists = [p for p, v in nodes if isinstance(v, list) and p and p[-1] in LENGTHS]
        rows = [
            p
            for p, v in nodes
            if isinstance(v, list)
            and p
            and (p[-1] == "matrix" or (len(p) > 1 and p[-2] == "matrix"))
        ]
        if lists or rows:
            path = draw(st.sampled_from(lists + rows))
            node = get(tree, path)
            n = draw(st.integers(0, len(node) + 3).filter(lambda n: n != len(node)))
            return replace(
                tree, path, (node * 3)[:n] if n <= 3 * len(node) else node + [0] * (n - len(node))
            ), how
    if how == "wrong container":
        pose_paths = [
            p for p, v in nodes if isinstance(v, dict) and any(k in v for k in POSE_FORMS)
        ]
        others = [
            p
            for p, v in nodes
            if p and p[-1] in ("parameters", "controls", "poses") and not isinstance(v, dict)
        ]
        path = draw(st.sampled_from(pose_paths + others + [()]))
        value = draw(st.sampled_from([[1, 2], "pose", 3.5, [[]], True]))
        if path == () and kind == "jobs":
            value = draw(st.sampled_from([{"start": 1}, "jobs", 3.5, [[]], True, [None]]))
        return replace(tree, path, value), how
    if how == "bad enum":
        enums = [p for p, v in nodes if p and p[-1] in ENUMS and isinstance(v, str)]
        bools = [p for p, v in nodes if p and p[-1] in BOOLS]
        if enums or bools:
            path = draw(st.sampled_from(enums + bools))
            if path[-1] in BOOLS:
                return replace(
                    tree, path, draw(st.sampled_from([1, 0, "yes", "no", "on", "true", [True]]))
                ), how
            allowed = ENUMS[path[-1]]
            bad = draw(
                st.one_of(st.text(max_size=10).filter(lambda s: s not in allowed), st.integers())
            )
            return replace(tree, path, bad), how
    if how == "bad samples" and kind in ("poses", "jobs", "pose_list"):
        doc = tree if kind != "jobs" else tree[0]
        doc["samples"] = draw(
            st.sampled_from(
                [0, 1, -3, 2.5, True, "101", 2**53 + 1, 10**30, Raw("1_000"), Raw("1:20")]
            )
        )
        return tree, how
    # a pose that is no pose: zero quaternion, non-orthogonal or non-affine matrix, Study
    # parameters off the quadric, p = 0
    pose_paths = [p for p, v in nodes if isinstance(v, dict) and any(k in v for k in POSE_FORMS)]
    path = draw(st.sampled_from(pose_paths))
    bad = draw(st.sampled_from([
        {"quaternion_wxyz": [0, 0, 0, 0]},
        {"quaternion_wxyz": [-0.0, 0, 0.0, 0]},
        {"quaternion_xyzw": [0.0, 0.0, 0.0, -0.0]},
        {"matrix": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 2, 0], [0, 0, 0, 1]]},
        {"matrix": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [1, 0, 0, 1]]},
        {"matrix": [[0, 1, 0, 0], [1, 0, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]},  # a reflection
        {"study": [1, 0, 0, 0, 1, 0, 0, 0]},
        {"study": [0, 0, 0, 0, 1, 0, 0, 0], "kappa": True},
        {"quaternion_wxyz": [1, 0, 0, 0], "study": [1, 0, 0, 0, 0, 0, 0, 0]},
        {"translation": [1, 2, 3]},
        {"quaternion_wxyz": [1, 0, 0, 0], "kappa": True},
    ]))  # fmt: skip
    return replace(tree, path, bad), "bad pose"


# -- writing trees as JSON and YAML ------------------------------------------------------------


def scalar(v, style: str) -> str:
    if isinstance(v, Raw):
        return v.token
    if isinstance(v, bool):
        return "true" if v else "false"
    if v is None:
        return "null"
    if isinstance(v, str):
        return json.dumps(v)  # double-quoted: a string in YAML too
    return repr(v) if isinstance(v, float) else str(v)


def flow(v, style: str) -> str:
    """JSON (``style == "json"``) or YAML flow style."""
    if isinstance(v, (dict, Pairs)):
        # keys double-quoted: a string in YAML too
        return "{" + ", ".join(f"{json.dumps(str(k))}: {flow(x, style)}" for k, x in items(v)) + "}"
    if isinstance(v, list):
        return "[" + ", ".join(flow(x, style) for x in v) + "]"
    return scalar(v, style)


def block(v, indent: int = 0) -> str:
    """YAML block style, leaves and short lists in flow style."""
    pad = " " * indent
    if isinstance(v, (dict, Pairs)) and v:
        out = []
        for k, x in items(v):
            if (
                isinstance(x, (dict, Pairs))
                and x
                or isinstance(x, list)
                and x
                and isinstance(x[0], (dict, Pairs))
            ):
                out.append(f"{pad}{json.dumps(str(k))}:\n{block(x, indent + 2)}")
            else:
                out.append(f"{pad}{json.dumps(str(k))}: {flow(x, 'yaml')}\n")
        return "".join(out)
    if isinstance(v, list) and v and isinstance(v[0], (dict, Pairs)):
        return "".join(f"{pad}-\n{block(x, indent + 2)}" for x in v)
    return f"{pad}{flow(v, 'yaml')}\n"


#: YAML that is no number where a number belongs: YAML 1.1 numbers and tags.
YAML_TOKENS = {
    "1.1 number": ["1:20", "1_000", "0b11", "+.5e", "1,5", "1e", "0x", "08.5.1"],
    "1.1 type": [
        "2001-02-30",
        "2024-01-01",
        "2001-12-14t21:59:43.10-05:00",
        "yes",
        "off",
        "=",
        "<<",
        "~x",
    ],  # fmt: skip
    "huge": ["0x" + "F" * 5000, "0o" + "7" * 3000, "9" * 5000, "-0x" + "F" * 300, "1e400"],
    "tag": [
        "!!python/object/apply:os.system ['true']",
        "!!binary aGk=",
        "!!set {a}",
        "!!timestamp 2001-01-01",
        "!custom 1",
        "!!bool maybe",
        "!!omap [a: 1]",
        "!!float abc",
        "!!int 1.5",
        "!!str 1",
        "!!null x",
    ],
}


@st.composite
def written(draw, kind: str):
    """A malformed file of ``kind``: (name, bytes, how)."""
    how = draw(st.sampled_from(["tree"] * 6 + ["truncated", "garbled", "control", "binary",
                                              "empty", "deep", "yaml-only",
                                              "json-syntax"]))  # fmt: skip
    suffix = draw(
        st.sampled_from([".json", ".yaml", ".yml", ""] + ([".jsonl"] if kind == "jobs" else []))
    )
    name = f"input{suffix}" if suffix else "<stdin>"

    def text_of(tree, style=None):
        style = style or (
            "json"
            if suffix in (".json", ".jsonl")
            else draw(st.sampled_from(["json", "flow", "block"]))
        )
        if suffix == ".jsonl":
            return "\n".join(flow(job, "json") for job in tree) + "\n"
        if style == "block" and not isinstance(tree, list):
            return block(tree)
        return flow(tree, "json" if style == "json" else "yaml")

    if how == "tree":
        tree, what = draw(mutated(kind))
        if suffix == ".jsonl" and not isinstance(tree, list):
            suffix, name = ".json", "input.json"
        return name, text_of(tree).encode(), what
    if how == "truncated":
        tree = draw(valid_doc(kind))
        text = text_of(tree, "json" if suffix in (".json", ".jsonl", "") else "flow")
        if suffix == ".jsonl":  # cut inside the last line: a line boundary would be valid
            start = text.rstrip("\n").rfind("\n") + 1
            cut = draw(st.integers(start + 1, len(text.rstrip("\n")) - 1))
        else:  # an unclosed {...} or [...] is neither JSON nor YAML
            cut = draw(st.integers(0, len(text.rstrip()) - 1))
        return name, text[:cut].encode(), how
    if how in ("garbled", "control"):
        data = text_of(draw(valid_doc(kind))).encode()
        at = draw(st.integers(0, len(data)))
        if how == "garbled":  # never UTF-8
            bad = draw(
                st.sampled_from(
                    [
                        b"\xff",
                        b"\xfe",
                        b"\x80",
                        b"\xc0\x80",
                        b"\xed\xa0\x80",
                        b"\xf5\x80\x80\x80",
                        b"\xe2\x82",
                    ]
                )
            )
        else:  # characters neither JSON nor YAML allow
            bad = bytes([draw(st.sampled_from([*range(9), 11, 12, *range(14, 32), 127]))])
        if at == len(data) and bad == b"\xe2\x82":
            bad = b"\xe2\x82("  # a truncated sequence at the very end may read as a shorter one
        return name, data[:at] + bad + data[at:], how
    if how == "binary":
        data = bytearray(draw(st.binary(max_size=300)))
        data.insert(draw(st.integers(0, len(data))), 0xFF)
        return name, bytes(data), how
    if how == "empty":
        empties = [
            "",
            " ",
            "\n\n",
            "\ufeff",
            "\t\n",
            "# only a comment\n",
            "null",
            "~",
            "---\n",
            "...\n",
            "[]",
        ]
        return name, draw(st.sampled_from(empties)).encode(), how
    if how == "deep":
        n = draw(st.integers(2, 3000))
        opener, closer = draw(
            st.sampled_from([("[", "]"), ('{"a": ', "}"), ("{a: ", "}"), ("- ", "")])
        )
        if closer == "" and suffix in (".json", ".jsonl"):
            opener, closer = "[", "]"
        if opener.startswith("{a") and suffix in (".json", ".jsonl"):
            opener = '{"a": '
        text = opener * n + "1" + closer * n
        if draw(st.booleans()) and kind != "jobs":  # deep inside an otherwise good file
            tree = draw(valid_doc(kind))
            numbers = [p for p, v in walk(tree) if is_number(v) and p and p[-1] != "name"]
            tree = replace(tree, draw(st.sampled_from(numbers)), Raw(text))
            text = text_of(tree, "json" if suffix in (".json", ".jsonl") else "flow")
        if suffix == ".jsonl":
            suffix, name = ".json", "input.json"
        return name, text.encode(), how
    if how == "yaml-only":
        suffix = draw(st.sampled_from([".yaml", ".yml"]))
        name = f"input{suffix}"
        tree = draw(valid_doc(kind))
        numbers = [p for p, v in walk(tree) if is_number(v) and p and p[-1] != "name"]
        trick = draw(st.sampled_from([*YAML_TOKENS, "alias", "multi", "python"]))
        if trick in YAML_TOKENS:  # in place of a number
            token = Raw(draw(st.sampled_from(YAML_TOKENS[trick])))
            tree = replace(tree, draw(st.sampled_from(numbers)), token)
            return name, flow(tree, "yaml").encode(), trick
        if trick == "alias":
            text = (
                "x: &a [1, 0, 0, 0]\n" + block(tree)
                if not isinstance(tree, list)
                else "- &a [1]\n" + block(tree)
            )
            return name, text.encode(), trick
        if trick == "multi":
            text = block(tree) if not isinstance(tree, list) else flow(tree, "yaml") + "\n"
            return name, (text + "---\n" + text).encode(), trick
        return name, b"!!python/name:os.system\n", trick
    # JSON syntax that is no JSON: a .json file
    name = "input.json"
    text = flow(draw(valid_doc(kind)), "json")
    trick = draw(
        st.sampled_from(["trailing comma", "single quotes", "comment", "bare key", "two values"])
    )
    if trick == "trailing comma":
        at = draw(st.sampled_from([m.start() for m in re.finditer(r"[\]}]", text)]))
        text = text[:at] + "," + text[at:]
    elif trick == "single quotes":
        text = text.replace('"', "'")
    elif trick == "comment":
        text = "// a comment\n" + text
    elif trick == "bare key":
        text = re.sub(r'"(\w+)":', r"\1:", text, count=1)
    else:
        text = text + " " + text
    return name, text.encode(), trick


# -- the checks ---------------------------------------------------------------------------


def read_fully(kind: str, data: bytes, name: str):
    stream = io.BytesIO(data)
    if kind == "pose":
        return poseschema.read_pose(stream, name)
    if kind == "poses":
        return poseschema.read_poses(stream, name)
    if kind == "jobs":
        return list(jobfiles.read_jobs(stream, name))
    key = b"controls" if b"controls" in data else b"poses"
    return poseschema.read_pose_list(stream, key.decode(), name)


def expect_reader_error(kind: str, case) -> None:
    name, data, how = case
    with pytest.raises(InputFileError) as info:
        read_fully(kind, data, name)
    message = str(info.value)
    assert "\n" not in message and message.startswith(f"{name}"), (how, message)


@pytest.mark.parametrize("kind", ["pose", "poses", "jobs", "pose_list"])
def test_fuzz_reader(kind):
    """read_pose, read_poses, read_jobs, read_pose_list: InputFileError, one line, the name."""
    run_fuzz(kind, written(kind), lambda case: expect_reader_error(kind, case))


@pytest.fixture(scope="module")
def workdir():
    path = Path(tempfile.mkdtemp(prefix="a2b-fuzz-"))
    yield path
    shutil.rmtree(path)


RUNNER = CliRunner()


def run_command(workdir: Path, args: list[str], case, stdin_name="<stdin>"):
    """Run ``a2b ARGS INPUT -o OUT`` in-process; the input is a file, or stdin for ``<stdin>``."""
    name, data, _ = case
    for leftover in workdir.iterdir():
        leftover.unlink()
    if name == stdin_name:
        source, stdin = "-", data
    else:
        source, stdin = str(workdir / name), None
        Path(source).write_bytes(data)
    out = workdir / "out.csv"
    command, *options = args
    argv = [command, source, *options] + (["-o", str(out)] if command != "fiber" else [])
    result = RUNNER.invoke(cli, argv, input=stdin, catch_exceptions=True)
    return result, {p.name for p in workdir.iterdir()} - {name}


def expect_one_line_error(result, left, how, status=(1,)):
    assert isinstance(result.exception, SystemExit), (how, result.exception)
    assert result.exit_code in status, (how, result.exit_code, result.output)
    assert result.stdout == "", (how, result.stdout[:200])
    lines = result.stderr.splitlines()
    if result.exit_code == 1:
        assert len(lines) == 1 and lines[0].startswith("Error: "), (how, result.stderr)
    else:
        assert lines[-1].startswith("Error: "), (how, result.stderr)
    assert "Traceback" not in result.stderr
    assert not left, (how, left)


@pytest.mark.parametrize(
    "command, kind", [("interpolate", "poses"), ("fiber", "pose"), ("batch", "jobs")]
)
def test_fuzz_command(workdir, command, kind):
    """a2b interpolate, fiber, batch on malformed files: status 1, one line, no output file."""

    def check(case):
        result, left = run_command(workdir, [command], case)
        expect_one_line_error(result, left, case[2])

    run_fuzz(command, written(kind), check)


GOOD_POSES = (
    b"start: {quaternion_wxyz: [1, 0, 0, 0]}\n"
    b"end: "
    b"{quaternion_wxyz: [0.7071067811865476, 0, 0, 0.7071067811865476], translation: [1, 1, 0.5]}\n"
)
GOOD_POSE = b"quaternion_wxyz: [0.5, 0.5, -0.5, 0.5]\ntranslation: [1, 2, 3]\n"
GOOD_JOBS = b"- " + GOOD_POSES.replace(b"\nend", b"\n  end")

NOT_A_NUMBER = st.one_of(
    st.sampled_from(["nan", "inf", "-inf", "1e999", "", "one", "1,2", "0x", "--1", "NaN"]),
    st.text(max_size=6).filter(
        lambda s: not re.fullmatch(r"\s*[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?\s*", s)
    ),
)


@st.composite
def bad_options(draw):
    """A command and an option value it must refuse: (command, arguments, stdin)."""
    command = draw(st.sampled_from(["interpolate", "fiber", "batch"]))
    if command == "interpolate":
        option = draw(st.sampled_from(["--samples", "--m", "--delta", "--duration", "--start-time",
                                       "--format", "--branch", "--alpha", "--mode",
                                       "--frame"]))  # fmt: skip
        if option == "--samples":
            value = draw(
                st.one_of(
                    st.integers(max_value=1),
                    st.integers(min_value=2**53 + 1),
                    NOT_A_NUMBER,
                    st.just("2.5"),
                )
            )
        elif option in ("--m", "--alpha"):
            n = 4 if option == "--m" else 6
            count = draw(st.integers(0, 8).filter(lambda k: k != n))
            value = (
                ",".join(["1"] * count)
                if draw(st.booleans())
                else ",".join(["1"] * (n - 1) + [draw(NOT_A_NUMBER.filter(lambda s: "," not in s))])
            )
        elif option == "--duration":
            value = draw(
                st.one_of(st.sampled_from(["0", "-1", "-0.0", "inf", "nan", "1e999"]), NOT_A_NUMBER)
            )
        elif option == "--branch":
            value = draw(
                st.one_of(st.integers().filter(lambda b: b not in (1, -1)).map(str), NOT_A_NUMBER)
            )
        elif option in ("--format", "--mode", "--frame"):
            allowed = {"--format": ("csv", "matrix", "study", "tum", "kitti", "mcap"),
                       "--mode": ("darboux", "cubic", "screw"),
                       "--frame": ("canonical", "given")}[option]  # fmt: skip
            value = draw(st.text(max_size=8).filter(lambda s: s not in allowed))
        else:
            value = draw(NOT_A_NUMBER)
        return command, [option, str(value)], GOOD_POSES
    if command == "fiber":
        option = draw(st.sampled_from(["--offsets", "--map", "--basis", "--m"]))
        if option == "--offsets":
            args = ["--offsets", draw(NOT_A_NUMBER.filter(lambda s: "," not in s))]
        elif option == "--m":
            args = [
                "--map",
                "mu",
                "--m",
                ",".join(["1"] * draw(st.integers(0, 8).filter(lambda k: k != 4))),
            ]
        else:
            args = [
                option,
                draw(
                    st.text(max_size=8).filter(
                        lambda s: s not in ("kappa", "mu", "paper", "rref", "auto")
                    )
                ),
            ]
        return command, args, GOOD_POSE
    option = draw(st.sampled_from(["--samples", "--chunk-size", "--format", "--mode"]))
    if option == "--samples":
        value = draw(st.one_of(st.integers(max_value=1).map(str), NOT_A_NUMBER))
    elif option == "--chunk-size":
        value = draw(st.one_of(st.integers(max_value=0).map(str), NOT_A_NUMBER))
    else:
        value = draw(
            st.text(max_size=8).filter(
                lambda s: s not in ("csv", "matrix", "study", "darboux", "cubic", "screw")
            )
        )
    return command, [option, value], GOOD_JOBS


def test_fuzz_options(workdir):
    """Malformed option values: status 2 (usage) or 1, one message, no traceback, no file."""

    def check(case):
        command, args, stdin = case
        for leftover in workdir.iterdir():
            leftover.unlink()
        out = ["-o", str(workdir / "out.csv")] if command != "fiber" else []
        result = RUNNER.invoke(cli, [command, "-", *args, *out], input=stdin, catch_exceptions=True)
        expect_one_line_error(result, set(workdir.iterdir()), (command, args), status=(1, 2))

    run_fuzz("options", bad_options(), check)


# -- a handful of cases in real processes: what an in-process run cannot show (a crash) --------

A2B = [sys.executable, "-c", "from a2b.cli import cli; cli(prog_name='a2b')"]

PROCESS_CASES = [
    ("interpolate", "deep.yaml", b"[" * 200_000 + b"]" * 200_000),  # crashed the C composer once
    ("interpolate", "deep.json", b"[" * 200_000 + b"]" * 200_000),
    ("fiber", "dashes.yaml", b"- " * 100_000 + b"x\n"),
    ("batch", "garbage.yaml", bytes(range(256)) * 4),
    (
        "interpolate",
        "huge.json",
        b'{"start": {"quaternion_wxyz": [1'
        + b"0" * 5000
        + b', 0, 0, 0]}, "end": {"quaternion_wxyz": [1, 0, 0, 0]}}',
    ),
    ("interpolate", "nul.yaml", GOOD_POSES.replace(b"end", b"e\x00nd")),
    (
        "batch",
        "latin1.jsonl",
        b'{"start": {"quaternion_wxyz": [1, 0, 0, 0]}, '
        b'"end": {"quaternion_wxyz": [1, 0, 0, 0]}, "name": "caf\xe9"}\n',
    ),
]


@pytest.mark.parametrize("command, name, data", PROCESS_CASES, ids=[c[1] for c in PROCESS_CASES])
def test_fuzz_in_a_real_process(tmp_path, command, name, data):
    source = tmp_path / name
    source.write_bytes(data)
    out = tmp_path / "out.csv"
    args = [command, str(source)] + (["-o", str(out)] if command != "fiber" else [])
    result = subprocess.run(A2B + args, capture_output=True, timeout=120, check=False)
    assert result.returncode == 1, result.stderr[-500:]
    lines = result.stderr.decode().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"Error: {source}"), lines
    assert result.stdout == b""
    assert sorted(p.name for p in tmp_path.iterdir()) == [name]
    COUNTS[f"process:{name}"] = 1


def test_total_cases():
    """At least A2B_FUZZ_EXAMPLES (10 000) malformed inputs ran, when the whole file ran."""
    if set(SHARES) - set(COUNTS):
        pytest.skip("not every fuzz test ran")
    total = sum(COUNTS.values())
    print(f"\nfuzz cases run: {total} ({', '.join(f'{k} {v}' for k, v in COUNTS.items())})")
    assert total >= TOTAL


# -- homogeneous inputs at every scale ---------------------------------------------------------


@pytest.mark.filterwarnings("ignore::a2b.errors.A2bWarning")  # near-zero rotations: expected
@settings(max_examples=300, derandomize=True, database=None, deadline=None)
@given(
    exponent=st.integers(-300, 300),
    kind=st.sampled_from(["quaternion", "study", "m", "weights"]),
    quaternion=st.lists(st.floats(-1, 1), min_size=4, max_size=4).filter(
        lambda q: 0.1 < math.hypot(*q)
    ),
    translation=st.lists(st.floats(-10, 10), min_size=3, max_size=3),
)
def test_homogeneous_inputs_at_every_scale(exponent, kind, quaternion, translation):
    """Quaternions, Study parameters, m and weights times 10^±300 mean what they meant."""
    import numpy as np

    import a2b
    from a2b.io.poseschema import read_poses
    from a2b.motions.bezier import bezier
    from a2b.poses import matrices_from_quat_trans, study_from_matrices

    scale = 10.0**exponent
    end = matrices_from_quat_trans(np.array(quaternion), np.array(translation))
    start = np.eye(4)
    if kind in ("quaternion", "study"):
        form = (
            {"quaternion_wxyz": [q * scale for q in quaternion], "translation": translation}
            if kind == "quaternion"
            else {"study": (study_from_matrices(end) * scale).tolist()}
        )
        text = json.dumps({"start": {"quaternion_wxyz": [1, 0, 0, 0]}, "end": form})
        got = read_poses(io.BytesIO(text.encode()), "p.json").end
        np.testing.assert_allclose(got, end, rtol=0, atol=1e-12 * (1 + np.abs(end).max()))
        return
    ts = np.linspace(0.0, 1.0, 5)
    if kind == "m":
        m = np.array([1.0, 0.2, -0.3, 0.5])
        try:
            plain = a2b.motion(start, end, "cubic", m=m).matrices(ts)
        except A2bError:
            return  # no motion for this m and these poses, at any scale
        scaled = a2b.motion(start, end, "cubic", m=m * scale).matrices(ts)
    else:
        weights = np.array([1.0, 3.0])
        try:
            plain = bezier([start, end], ts, weights=weights)
        except A2bError:
            return
        scaled = bezier([start, end], ts, weights=weights * scale)
    np.testing.assert_allclose(scaled, plain, rtol=0, atol=1e-9 * (1 + np.abs(plain).max()))


# -- output targets -----------------------------------------------------------------------------

ROOT = Path(__file__).resolve().parent.parent

TARGETS = ["new", "existing", "read-only", "set-id", "link", "dangling-link", "directory",
           "slash", "missing-parent", "dev-null", "dev-stdout"]  # fmt: skip


@settings(max_examples=40, derandomize=True, database=None, deadline=None)
@given(
    target=st.sampled_from(TARGETS),
    fmt=st.sampled_from(["csv", "tum", "mcap", "kitti"]),
    command=st.sampled_from(["interpolate", "batch"]),
)
def test_output_targets(target, fmt, command):
    """Every kind of -o target: written where it should be, or one error line and nothing lost;
    never a traceback, never a temporary file left behind."""
    old = b"old bytes that a refused run must keep\n"
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        source = ROOT / "samples" / ("jobs.yaml" if command == "batch" else "quarter-turn.yaml")
        path = work / "out"
        if target in ("existing", "read-only", "set-id", "link"):
            real = work / "real"
            real.write_bytes(old)
            if target == "read-only":
                real.chmod(0o444)
            if target == "set-id":
                real.chmod(0o6755)
            if target == "link":
                path.symlink_to(real)
            else:
                real.rename(path)
        elif target == "dangling-link":
            path.symlink_to(work / "nowhere")
        elif target == "directory":
            path.mkdir()
        arg = {
            "slash": f"{path}/",
            "missing-parent": str(work / "no" / "out"),
            "dev-null": "/dev/null",
            "dev-stdout": "/dev/stdout",
        }.get(target, str(path))
        if command == "batch" and fmt in ("tum", "kitti") and target in ("new", "directory"):
            arg = str(path)  # a directory of files, made if missing
        done = subprocess.run(
            A2B + [command, str(source), "--format", fmt, "-o", arg],
            capture_output=True,
            timeout=120,
        )
        err = done.stderr.decode()
        assert "Traceback" not in err, err
        assert not [p.name for p in work.rglob("*") if p.name.endswith(".tmp")], target
        if done.returncode != 0:
            assert done.returncode in (1, 2) and err.splitlines()[-1].startswith("Error: "), err
            for p in work.rglob("*"):
                if p.is_file() and not p.is_symlink() and p.name in ("out", "real"):
                    assert p.read_bytes() == old, (target, p)
            return
        if target == "dev-stdout":
            assert done.stdout
        elif target == "set-id":
            assert path.stat().st_mode & 0o6000 == 0
