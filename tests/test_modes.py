"""a2b.motions.REGISTRY: the modes carry their own behaviour, and nothing outside a2b/motions/
branches on a mode's name."""

from __future__ import annotations

import ast
from pathlib import Path

import numpy as np
import pytest

import a2b
from a2b.errors import ParameterError
from a2b.motions import REGISTRY
from a2b.motions.base import Motion
from a2b.names import MODES
from a2b.parameters import OF_MODE, TABLE

PACKAGE = Path(__file__).resolve().parent.parent / "a2b"


def _names_mode(node) -> bool:
    """``mode``, ``x.mode`` or ``getattr(x, "mode", ...)``."""
    if isinstance(node, ast.Name):
        return node.id == "mode"
    if isinstance(node, ast.Attribute):
        return node.attr == "mode"
    return (
        isinstance(node, ast.Call)
        and getattr(node.func, "id", None) == "getattr"
        and len(node.args) >= 2
        and getattr(node.args[1], "value", None) == "mode"
    )


def _strings(node) -> bool:
    """A string, or a tuple, list or set of them."""
    if isinstance(node, ast.Constant):
        return isinstance(node.value, str)
    return isinstance(node, (ast.Tuple, ast.List, ast.Set)) and any(
        isinstance(e, ast.Constant) and isinstance(e.value, str) for e in node.elts
    )


def mode_comparisons(source: str) -> list[int]:
    """The lines that compare a mode against a string (``==``, ``!=``, ``in``, ``not in``)."""
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Compare):
            sides = [node.left, *node.comparators]
            if any(map(_names_mode, sides)) and any(map(_strings, sides)):
                found.append(node.lineno)
    return found


def test_the_finder_finds_what_it_looks_for():
    source = (
        'if mode == "darboux": pass\n'
        'x = motion.mode in ("darboux", "cubic")\n'
        'y = getattr(m, "mode", "") != "screw"\n'
        "z = mode in MODES\n"  # a table, not a branch
        'w = kind == "ab"\n'
    )
    assert mode_comparisons(source) == [1, 2, 3]


def test_no_mode_is_compared_with_a_string_outside_the_motions():
    # cli/resample.py's --mode spline is resample's own mode, not a motion's (the lead's)
    exempt = {PACKAGE / "motions", PACKAGE / "resample.py", PACKAGE / "cli" / "resample.py"}
    found = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        if any(path == e or e in path.parents for e in exempt):
            continue
        lines = mode_comparisons(path.read_text())
        if lines:
            found[str(path.relative_to(PACKAGE))] = lines
    assert found == {}


def test_the_registry_is_the_table_of_modes():
    assert tuple(REGISTRY) == MODES
    assert {p.mode for p in TABLE} <= set(MODES)
    for name, mode in REGISTRY.items():
        assert issubclass(mode.motion, Motion) and mode.motion.mode == name
        assert mode.parameters == OF_MODE[name] and mode.description


@pytest.fixture
def ends():
    b = np.eye(4)
    b[:3, :3] = [[0, -1, 0], [1, 0, 0], [0, 0, 1]]
    b[:3, 3] = [1, 0, 1]
    return np.eye(4), b


@pytest.mark.parametrize("mode", MODES)
def test_each_mode_draws_its_transmission_curve_through_its_samples(ends, mode):
    motion = a2b.motion(*ends, mode)
    omega, z = motion.frame.transmission(motion.matrices(np.linspace(0, 1, 9)))
    assert np.allclose(motion.transmission(omega), z, atol=1e-12)
    assert motion.transmission_form in ("sine", "tangent", "line")


def test_the_given_frame_has_no_curve_and_no_family(ends):
    motion = a2b.motion(*ends, "cubic", frame="given")
    assert motion.transmission(np.zeros(3)) is None
    with pytest.raises(ParameterError, match="given frame is not in a cylinder group"):
        motion.family("ab", 3)
    with pytest.raises(ParameterError, match="no family .* for a screw motion"):
        a2b.motion(*ends, "screw").family("ab", 3)


@pytest.mark.parametrize("mode", ["darboux", "cubic"])
def test_the_members_of_a_family_are_motions_through_a_and_b(ends, mode):
    motion = a2b.motion(*ends, mode)
    for kind in motion.family_kinds:
        name, members, chosen = motion.family(kind, 2)
        assert len(members) == 5 and members[2][0] == pytest.approx(chosen)
        for _value, parameters in members:
            member = a2b.motion(*ends, mode, **parameters)
            assert np.allclose(member.matrices([0.0, 1.0]), np.stack(ends), atol=1e-9)


def test_summaries(ends):
    assert a2b.motion(*ends, "darboux").summary("rad") == (
        "δ = 0, z0 = 0.5, λ = 0.707, κ = −0.785 rad"
    )
    assert a2b.motion(*ends, "cubic").summary() == "m0:m3 = 1.71:0.707, a = 0, b = 0"
    assert a2b.motion(*ends, "screw").summary() == "pitch = 0.637 per rad"
    assert a2b.motion(*ends, "screw").pose_degree() == "not rational (trigonometric)"
    assert a2b.motion(*ends, "cubic").pose_degree() == 3
