"""The generators and the quota of the fuzz tests (tests/test_fuzz_readers.py and
tests/test_fuzz_commands.py): valid documents, mutated so that no valid file survives, written
as JSON and YAML; and :func:`run_fuzz`, which runs a share of ``A2B_FUZZ_EXAMPLES`` cases
and counts them in :data:`COUNTS`."""

from __future__ import annotations

import json
import math
import os
import re

from hypothesis import HealthCheck, Phase, given, seed, settings
from hypothesis import strategies as st

from a2b.io import poseschema

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
