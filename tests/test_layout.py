"""The shape of the package, read from its source: where click and the exception classes may
live, and how long a module or a function may grow (tests are exempt).

These are the limits of docs/architecture.md: a newcomer should be able to hold a module and a
function in their head, the library never speaks click, and every error class is in one file.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parent.parent / "a2b"
SOURCES = sorted(PACKAGE.rglob("*.py"))
#: The longest module and the longest function (from ``def`` to its last line) allowed.
MODULE_LINES = 800
FUNCTION_LINES = 80


def relative(path: Path) -> str:
    return path.relative_to(PACKAGE.parent).as_posix()


def tree(path: Path) -> ast.Module:
    return ast.parse(path.read_text(encoding="utf-8"), filename=str(path))


def imported_roots(module: ast.Module) -> set[str]:
    """The top-level names of every package a module imports, at the top or in a function."""
    roots = set()
    for node in ast.walk(module):
        if isinstance(node, ast.Import):
            roots |= {alias.name.split(".")[0] for alias in node.names}
        elif isinstance(node, ast.ImportFrom) and not node.level and node.module:
            roots.add(node.module.split(".")[0])
    return roots


def test_click_is_imported_only_under_cli():
    outside = [
        relative(p)
        for p in SOURCES
        if "click" in imported_roots(tree(p)) and not relative(p).startswith("a2b/cli/")
    ]
    assert outside == []


def exception_classes(module: ast.Module, known: set[str]) -> list[str]:
    """Classes whose bases name an exception: a builtin one, or one of ``known``."""
    import builtins

    found = []
    for node in ast.walk(module):
        if not isinstance(node, ast.ClassDef):
            continue
        for base in node.bases:
            name = base.id if isinstance(base, ast.Name) else getattr(base, "attr", None)
            builtin = getattr(builtins, name or "", None)
            if name in known or (isinstance(builtin, type) and issubclass(builtin, BaseException)):
                found.append(node.name)
                break
    return found


def test_every_exception_class_is_in_errors_py():
    errors = tree(PACKAGE / "errors.py")
    known = {node.name for node in ast.walk(errors) if isinstance(node, ast.ClassDef)}
    elsewhere = {
        relative(p): exception_classes(tree(p), known) for p in SOURCES if p.name != "errors.py"
    }
    assert {path: names for path, names in elsewhere.items() if names} == {}


def test_the_exception_check_sees_a_class_outside(tmp_path):
    """The check can fail: a subclass of a builtin or of an a2b error is found."""
    module = ast.parse("class A(Exception): pass\nclass B(errors.A2bError): pass\nclass C: pass")
    assert exception_classes(module, {"A2bError"}) == ["A", "B"]


@pytest.mark.parametrize("path", SOURCES, ids=relative)
def test_no_module_is_over_the_limit(path):
    lines = len(path.read_text(encoding="utf-8").splitlines())
    assert lines <= MODULE_LINES, f"{relative(path)} has {lines} lines"


def function_lines(node: ast.FunctionDef | ast.AsyncFunctionDef) -> int:
    """The lines from ``def`` to the function's last line, less its docstring (a command's
    docstring is its ``--help`` text, prose rather than structure)."""
    lines = node.end_lineno - node.lineno + 1
    first = node.body[0]
    if (
        isinstance(first, ast.Expr)
        and isinstance(first.value, ast.Constant)
        and isinstance(first.value.value, str)
    ):
        lines -= first.end_lineno - first.lineno + 1
    return lines


def long_functions(module: ast.Module) -> list[str]:
    return [
        f"{node.name} ({function_lines(node)} lines, from line {node.lineno})"
        for node in ast.walk(module)
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef))
        and function_lines(node) > FUNCTION_LINES
    ]


@pytest.mark.parametrize("path", SOURCES, ids=relative)
def test_no_function_is_over_the_limit(path):
    assert long_functions(tree(path)) == []


def test_the_length_check_sees_a_long_function():
    body = "\n".join(f"    x{i} = {i}" for i in range(FUNCTION_LINES))
    assert long_functions(ast.parse(f"def f():\n{body}\n")) == ["f (81 lines, from line 1)"]
    documented = f'def f():\n    """Help\n\n    text."""\n{body}\n'
    assert long_functions(ast.parse(documented)) == ["f (81 lines, from line 1)"]
