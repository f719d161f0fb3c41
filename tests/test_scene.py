"""a2b.scene: what the figures and the page show, without a renderer."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

import a2b
from a2b.errors import ParameterError
from a2b.scene import family_members, make_scene, transmission_curve

from .conftest import pose_about_axis, random_pose


@pytest.fixture
def poses(rng):
    """A random start pose and an end pose a generic screw away from it (φ ≈ 100°)."""
    start = random_pose(rng)
    screw = pose_about_axis(1.75, rng.normal(size=3), rng.normal(size=3), 0.8)
    return start, screw @ start


def test_the_scene_needs_no_renderer():
    code = "import sys, a2b.scene; print('matplotlib' in sys.modules, 'plotly' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.split() == ["False", "False"]


def test_the_scene_samples_each_motion_once(poses):
    scene = make_scene(*poses, ["darboux", "screw"], samples=5, instants=3)
    assert [t.label for t in scene.tracks] == ["darboux", "screw"]
    for track in scene.tracks:
        expected = a2b.motion(*poses, track.mode).matrices(np.linspace(0, 1, 5))
        np.testing.assert_allclose(track.mats, expected, atol=1e-12)
        assert track.inst.shape == (3, 4, 4)
    assert scene.in_group == [True, True] and scene.show_axis and not scene.single
    paths = scene.trajectories(scene.tracks[0])  # the axis tips
    np.testing.assert_allclose(
        paths[0], scene.tracks[0].mats[:, :3, 0] + scene.tracks[0].mats[:, :3, 3]
    )


def test_titles(poses):
    one = make_scene(*poses, "screw", samples=3, instants=2, angle_unit="rad")
    pitch = one.tracks[0].motion.summary("rad")
    assert one.figure_title() == f"screw motion: {pitch}   (A to B: {one.ends_text()})"
    assert one.page_title() == f"screw motion, A to B: {one.ends_text()}"
    assert one.ends_text().startswith("φ = 1.75 rad, d = ")
    two = make_scene(*poses, ["darboux", "cubic"], samples=3, instants=2)
    assert two.page_title().startswith("darboux, cubic motions, A to B: φ = 100°")


def test_the_same_mode_twice_is_told_apart_by_its_parameters(poses):
    scene = make_scene(*poses, [("darboux", {"delta": 0.5}), "darboux", "darboux"],
                       samples=3, instants=2)  # fmt: skip
    labels = [t.label for t in scene.tracks]
    assert labels == ["darboux (delta=0.5)", "darboux (defaults) #2", "darboux (defaults) #3"]
    assert len({t.colour for t in scene.tracks}) == 3


def test_transmission_curve_has_the_closed_form_beyond_its_ends(poses):
    scene = make_scene(*poses, "darboux", samples=5, instants=2)
    curve = transmission_curve(scene, scene.tracks[0], margin=0.1)
    phi = scene.frame.phi
    assert curve.dense[0] == pytest.approx(-0.1 * phi) and curve.dense[-1] == pytest.approx(
        1.1 * phi
    )
    np.testing.assert_allclose(curve.closed, scene.tracks[0].motion.transmission(curve.dense))


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"samples": 1}, "samples must be an integer ≥ 2, got 1"),
        ({"samples": float("nan")}, "samples must be an integer ≥ 2, got nan"),
        ({"instants": 2.5}, "instants must be an integer ≥ 2, got 2.5"),
        ({"angle_unit": "grad"}, "unknown angle unit 'grad'"),
        ({"marks": [("m", np.stack([np.eye(4)] * 2))]}, "each mark is a"),
        ({"axis_length": -1.0}, "axis_length must be a positive number"),
    ],
)
def test_invalid_scenes(poses, kwargs, match):
    arguments = {"samples": 3, "instants": 2, **kwargs}
    with pytest.raises(ParameterError, match=match):
        make_scene(*poses, "darboux", **arguments)


def test_a_span_beyond_a_double_is_one_clear_error():
    mats = np.repeat(np.eye(4)[None], 3, axis=0)
    mats[:, 0, 3] = [1e308, -1.5e308, 1.5e308]
    with pytest.raises(ParameterError, match=r"^the poses reach coordinates of 1.5e\+308, too far "
                       "apart to draw: their span overflows a double$"):  # fmt: skip
        make_scene(mats[0], mats[-1], [("trajectory", mats)], samples=3, instants=2)


def test_family_of_darboux_varies_delta(poses):
    motion = a2b.motion(*poses, "darboux", delta=0.2)
    name, members, chosen = family_members(motion)
    assert name == "δ" and chosen == 0.2
    deltas = [m.delta for _, m in members]
    assert deltas == sorted(deltas) and len(set(deltas)) == len(deltas)


def test_family_errors(poses):
    with pytest.raises(ParameterError, match="no family"):
        family_members(a2b.motion(*poses, "screw"))
    with pytest.raises(ParameterError, match="varies delta"):
        family_members(a2b.motion(*poses, "darboux"), "m")
    with pytest.raises(ParameterError, match="given frame"):
        family_members(a2b.motion(*poses, "cubic", frame="given"))


FIGURE_MODULES = ["scene.py", "plot.py", "view.py", "cli/plot.py", "cli/view.py",
                  "cli/describe.py", "motions/__init__.py", "motions/text.py"]  # fmt: skip


@pytest.mark.parametrize("name", FIGURE_MODULES)
def test_the_figure_modules_stay_small(name):
    """No module over 800 lines; no function over 80 lines of code (its docstring aside)."""
    import ast
    from pathlib import Path

    source = (Path(__file__).resolve().parent.parent / "a2b" / name).read_text()
    assert len(source.splitlines()) <= 800
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            doc = node.body[0] if ast.get_docstring(node) else None
            lines = node.end_lineno - node.lineno + 1
            if doc is not None:
                lines -= doc.end_lineno - doc.lineno + 1
            assert lines <= 80, (node.name, lines)


def test_messages_are_one_bounded_line(poses):
    long = "x" * 100_000 + "\n\x1b[31m"
    for call in (
        lambda: make_scene(*poses, (long, {}), samples=3, instants=2),
        lambda: make_scene(*poses, "darboux", samples=3, instants=2, angle_unit=long),
        lambda: make_scene(*poses, [(long, np.eye(4))], samples=3, instants=2),
    ):
        with pytest.raises(ParameterError) as info:
            call()
        message = str(info.value)
        assert "\n" not in message and "\x1b" not in message and len(message) < 300, message
        assert "(100006 characters)" in message
