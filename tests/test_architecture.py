"""The arrows of the package point one way: cli → plot → scene → datasets → output → io →
jobs → api → motions → core.

Every import of every module (at the top or inside a function) is read from the source. A
module may import its own layer or a lower one, never a higher one, and no two modules import
each other, directly or around a cycle.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parent.parent / "a2b"

#: Layers, lowest first: a module's layer is that of its longest matching prefix.
LAYERS = [
    ("core", ["a2b.errors", "a2b.names", "a2b.parameters", "a2b.elements", "a2b.study",
              "a2b.poses", "a2b.extended", "a2b.frames", "a2b.fibers", "a2b.kinematics",
              "a2b.formats"]),
    ("motions", ["a2b.motions"]),
    ("api", ["a2b.api"]),
    ("jobs", ["a2b.jobs", "a2b.resample", "a2b.timelaw", "a2b.samples"]),
    ("io", ["a2b.io"]),
    ("output", ["a2b.output"]),
    ("datasets", ["a2b.table", "a2b.dask"]),
    ("scene", ["a2b.scene"]),
    ("plot", ["a2b.plot", "a2b.view"]),
    ("cli", ["a2b.cli", "a2b.__main__"]),
]  # fmt: skip
RANK = {prefix: rank for rank, (_, prefixes) in enumerate(LAYERS) for prefix in prefixes}


def module_name(path: Path) -> str:
    parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def rank(module: str) -> int | None:
    best = None
    for prefix, value in RANK.items():
        if (module == prefix or module.startswith(prefix + ".")) and (
            best is None or len(prefix) > len(best[0])
        ):
            best = (prefix, value)
    return None if best is None else best[1]


def imports(path: Path) -> set[str]:
    """The a2b modules ``path`` imports, resolved to full names."""
    name = module_name(path)
    package = name if path.name == "__init__.py" else name.rsplit(".", 1)[0]
    found = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            found |= {alias.name for alias in node.names if alias.name.startswith("a2b")}
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - node.level + 1]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            if not target.startswith("a2b"):
                continue
            for alias in node.names:  # `from . import api` imports the module a2b.api
                candidate = f"{target}.{alias.name}"
                found.add(candidate if rank(candidate) is not None and
                          (PACKAGE.parent / candidate.replace(".", "/")).with_suffix(".py").exists()
                          else target)  # fmt: skip
    return found - {"a2b"}


MODULES = {module_name(p): imports(p) for p in sorted(PACKAGE.rglob("*.py"))}


def test_every_module_has_a_layer():
    assert [m for m in MODULES if m != "a2b" and rank(m) is None] == []


@pytest.mark.parametrize("module", sorted(m for m in MODULES if m != "a2b"))
def test_no_upward_arrow(module):
    upward = sorted(
        dep for dep in MODULES[module] if rank(dep) is not None and rank(dep) > rank(module)
    )
    assert not upward, f"{module} imports the higher layer(s) {upward}"


def test_no_import_cycle():
    graph = {m: {d for d in deps if d in MODULES} for m, deps in MODULES.items() if m != "a2b"}
    state: dict[str, int] = {}
    path: list[str] = []

    def visit(node):
        state[node] = 1
        path.append(node)
        for nxt in graph.get(node, ()):
            if state.get(nxt) == 1:
                cycle = path[path.index(nxt) :] + [nxt]
                raise AssertionError("import cycle: " + " → ".join(cycle))
            if nxt not in state:
                visit(nxt)
        path.pop()
        state[node] = 2

    for node in graph:
        if node not in state:
            visit(node)


def test_the_checks_see_an_upward_arrow_and_a_cycle(tmp_path):
    """The reader of imports finds function-level and relative imports (so the checks can fail)."""
    assert "a2b.api" in MODULES["a2b.jobs"]
    assert "a2b.output" in MODULES["a2b.cli.batch"]
    assert rank("a2b.cli.batch") > rank("a2b.io.writers") > rank("a2b.motions.base")
