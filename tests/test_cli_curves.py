"""Bézier and spline files at the command line: ``a2b bezier``/``spline`` -v, and ``a2b plot``
drawing them or refusing options meant for two poses.

Through click's CliRunner."""

from __future__ import annotations

import pytest

from .clirun import SAMPLES, run, run_split


@pytest.mark.parametrize(
    "command, sample, expected",
    [
        (
            "bezier",
            "planar-bezier.yaml",
            "m defaults to the sum of the control quaternions with consistent signs",
        ),
        ("spline", "spline.yaml", "inner control points by the uniform Catmull–Rom rule"),
    ],
)
def test_verbose_bezier_and_spline(command, sample, expected):
    result = run_split(command, SAMPLES / sample, "--samples", 3, "-v")
    assert result.exit_code == 0
    assert result.stderr.startswith("Choices a2b made:\n")
    assert expected in result.stderr


@pytest.mark.parametrize(
    "sample, args, title, marks",
    [
        ("planar-bezier.yaml", [], "Bézier motion of degree 3 (matrix space)", ["C1", "C2"]),
        (
            "planar-bezier.yaml",
            ["--space", "study"],
            "Bézier motion of degree 3 (study space)",
            ["C1", "C2"],
        ),
        ("spline.yaml", [], "C¹ spline of 4 cubic segments (matrix space)", ["P1", "P2", "P3"]),
    ],
)
def test_plot_draws_curve_files(tmp_path, sample, args, title, marks):
    pytest.importorskip("matplotlib")
    out = tmp_path / "curve.svg"
    result = run("plot", SAMPLES / sample, "-o", out, "--samples", 9, *args)
    assert result.exit_code == 0, result.output
    svg = out.read_text()
    assert title.replace("¹", "") in svg.replace("¹", "") or title in svg
    for mark in marks:
        assert f'id="mark:{mark}:x"' in svg
    assert 'id="screw-axis"' not in svg


@pytest.mark.parametrize(
    "args, message",
    [
        (
            ["--mode", "cubic"],
            "--mode is for two poses; this file is a list of controls (a Bézier motion)",
        ),
        (["--delta", "0.1", "--family"], "--family, --delta are for two poses"),
    ],
)
def test_plot_curve_files_refuse_options_for_two_poses(tmp_path, args, message):
    result = run_split("plot", SAMPLES / "planar-bezier.yaml", "-o", tmp_path / "x.png", *args)
    assert result.exit_code == 2
    assert f"Error: {message}" in result.stderr
    result = run_split(
        "plot", SAMPLES / "quarter-turn.yaml", "-o", tmp_path / "x.png", "--space", "study"
    )
    assert result.exit_code == 2 and "--space is for a list of controls or poses" in result.stderr
    assert list(tmp_path.iterdir()) == []


def test_plot_refuses_more_samples_than_a_figure_shows(tmp_path):
    result = run_split(
        "plot", SAMPLES / "quarter-turn.yaml", "-o", tmp_path / "x.png", "--samples", 10**9
    )
    assert result.exit_code == 2 and "1000000000 is not in the range 2<=x<=100000" in result.stderr
