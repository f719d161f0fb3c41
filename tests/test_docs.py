"""docs/math.md names the tests that check its facts: each of them exists."""

from __future__ import annotations

import ast
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
MATH = (ROOT / "docs" / "math.md").read_text()


def test_every_test_named_in_docs_math_exists():
    cited = set(re.findall(r"tests/(test_\w+)\.py::(test_\w+)", MATH))
    # bare names in the table of darboux solvers live in test_core_motions.py
    cited |= {("test_core_motions", name) for name in re.findall(r"`(test_darboux_\w+)`", MATH)}
    assert len(cited) > 30
    missing = []
    for module, name in sorted(cited):
        tree = ast.parse((ROOT / "tests" / f"{module}.py").read_text())
        names = {node.name for node in tree.body if isinstance(node, ast.FunctionDef)}
        if name not in names:
            missing.append(f"{module}::{name}")
    assert missing == []


def test_every_correction_has_a_heading_and_a_test():
    for n in range(1, 7):
        section = MATH.split(f"### Correction {n}:")[1].split("###")[0]
        assert "tests/test_" in section, f"correction {n} names no test"


def test_the_documentation_stays_inside_the_repository():
    for path in [ROOT / "README.md", *ROOT.glob("docs/*.md"), *ROOT.glob("a2b/**/*.py")]:
        text = path.read_text()
        assert "MATH.md" not in text and "STYLE.md" not in text, path
        assert "'a2b[" not in text and '"a2b[' not in text, path


def test_the_bench_extra_installs_what_the_benchmarks_import():
    import tomllib

    extras = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"][
        "optional-dependencies"
    ]
    assert any(requirement.startswith("ruckig") for requirement in extras["bench"])
