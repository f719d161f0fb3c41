"""``a2b describe``: JSON and human output, the choices it states, lengths and angles.

Through click's CliRunner."""

from __future__ import annotations

import json
import math

import pytest

import a2b

from .clirun import HALF_TURN_TRANSLATION, SAMPLES, run, run_split


def test_describe_json_has_the_keys_of_a2b_describe(poses):
    path, a, b = poses
    for mode in ("darboux", "cubic", "screw"):
        result = run("describe", path, "--mode", mode, "--json")
        assert result.exit_code == 0, result.output
        got = json.loads(result.output)
        want = a2b.describe(a, b, mode)
        assert set(got) == set(want)
        assert got["phi"] == want["phi"] and got["choices"] == want["choices"]


def test_describe_human(tmp_path):
    path = tmp_path / "p.yaml"
    path.write_text(
        "start: {quaternion_wxyz: [1, 0, 0, 0]}\n"
        "end: "
        "{quaternion_wxyz: [0.7071067811865476, 0, 0, 0.7071067811865476], translation: [0, 0, "
        "1]}\n"
    )
    result = run("describe", path, "--lam", 1.5, "--branch", -1)
    assert result.exit_code == 0
    for text in ("φ", "λ, transmission curve amplitude", "1.5", "pitch at the start", "singular t"):
        assert text in result.output


def test_describe_states_the_default_mode_and_the_choices(tmp_path):
    path = tmp_path / "p.yaml"
    path.write_text(HALF_TURN_TRANSLATION)
    out = run("describe", path, "--lam", 2).output
    assert "Choices a2b made:" in out
    assert "mode darboux: the default" in out and "used branch +1" in out
    out = run("describe", path, "--mode", "screw").output
    assert (
        "mode darboux" not in out
        and "both axis orientations are short; chose the one with d > 0" in out
    )


def test_describe_curve_files_states_their_choices():
    result = run_split("describe", SAMPLES / "spline.yaml", "--json")
    assert result.exit_code == 0
    got = json.loads(result.stdout)
    assert got["kind"] == "spline" and got["segments"] == 4 and got["space"] == "matrix"
    assert any("Catmull–Rom" in c for c in got["choices"])
    human = run_split("describe", SAMPLES / "planar-bezier.yaml", "--space", "study").stdout
    assert "a2b describe: Bézier motion" in human and "study" in human
    assert "Choices a2b made: none" in human  # the file says nothing a2b had to choose
    result = run_split("describe", SAMPLES / "spline.yaml", "--mode", "cubic")
    assert (
        result.exit_code == 2
        and "--mode is for two poses; this file is a list of poses (a spline)" in result.stderr
    )


@pytest.mark.parametrize(
    "end, d",
    [
        ("{quaternion_wxyz: [1, 0, 0, 0], translation: [1e308, 1e308, 0]}", 1e308 * 2**0.5),
        ("{quaternion_wxyz: [1, 0, 0, 0], translation: [1e200, 0, 0]}", 1e200),
        ("{quaternion_wxyz: [1, 0, 0, 0], translation: [3e-200, 4e-200, 0]}", 5e-200),
    ],
)
def test_a_length_that_is_a_double_is_no_overflow(tmp_path, end, d):
    """Lengths come from overflow-safe norms: only a length beyond a double is refused."""
    path = tmp_path / "p.yaml"
    path.write_text(f"start: {{quaternion_wxyz: [1, 0, 0, 0]}}\nend: {end}\n")
    result = run_split("describe", path, "--json")
    assert result.exit_code == 0, result.stderr
    assert json.loads(result.stdout)["d"] == pytest.approx(d, rel=1e-15)


EIGHTH_TURN = (
    "start: {quaternion_wxyz: [1, 0, 0, 0]}\n"
    "end: {quaternion_wxyz: [0.9238795325112867, 0, 0, 0.3826834323650898], "
    "translation: [0, 0, 1]}\n"
)


ANGLES = [("45deg", math.pi / 4), ("-90 deg", -math.pi / 2), ("0.5", 0.5)]


@pytest.mark.parametrize("spelling, radians", ANGLES)
def test_an_angle_takes_degrees_with_a_deg_suffix(tmp_path, spelling, radians):
    """--kappa 45deg means π/4; a number alone is radians, as the help says."""
    path = tmp_path / "p.yaml"
    path.write_text(EIGHTH_TURN)
    from_option = run_split("describe", path, "--json", "--kappa", spelling)
    path.write_text(EIGHTH_TURN + f"parameters: {{kappa: {spelling}}}\n")
    from_file = run_split("describe", path, "--json")
    for result in (from_option, from_file):
        if result.exit_code == 0:
            assert json.loads(result.stdout)["kappa"] == pytest.approx(radians, abs=1e-12)
        else:
            assert "κ is in radians; write 45deg for degrees" in result.stderr


def test_an_unreachable_kappa_says_radians():
    result = run_split("describe", SAMPLES / "canonical.yaml", "--kappa", "45")
    assert result.exit_code == 1
    assert "κ is in radians; write 45deg for degrees" in result.stderr
