"""a2b's command group as a whole: help, version, usage errors, and how an error or a bug
ends a run.

Through click's CliRunner."""

from __future__ import annotations

import math

import pytest
from click.testing import CliRunner

import a2b
from a2b.cli import COMMANDS, cli

from .clirun import run, run_split


@pytest.mark.parametrize("name", list(COMMANDS))
def test_every_command_has_h_and_an_example(name):
    result = run(name, "-h")
    assert result.exit_code == 0
    assert result.output.startswith(f"Usage: a2b {name}")
    assert "Example:" in result.output


def test_group_help_lists_every_command_and_completion():
    result = run("-h")
    assert result.exit_code == 0
    for name in COMMANDS:
        assert name in result.output
    assert "_A2B_COMPLETE=bash_source a2b" in result.output


def test_version():
    result = run("--version")
    assert result.exit_code == 0
    assert result.output == f"a2b {a2b.__version__}\n"


def test_unknown_command_and_option_are_usage_errors(poses):
    path, _, _ = poses
    assert run("interpolat").exit_code == 2
    result = run("interpolate", path, "--samplez", "3")
    assert result.exit_code == 2
    assert "--samplez" in result.output and "Usage: a2b interpolate" in result.output
    assert run("interpolate", path, "--m", "1,2,3").exit_code == 2
    assert run("interpolate", path, "--delta", "nan").exit_code == 2
    assert run("interpolate", path, "--samples", "0").exit_code == 2
    assert run("interpolate", path, "--branch", "2").exit_code == 2


def test_a2b_error_is_one_line_exit_1(tmp_path):
    path = tmp_path / "p.yaml"
    path.write_text(
        "start: {quaternion_wxyz: [1, 0, 0, 0]}\nend: "
        "{quaternion_wxyz: [1, 0, 0, 0], translation: [0, 0, "
        "1]}\n"
    )
    out = tmp_path / "o.csv"
    result = CliRunner().invoke(cli, ["interpolate", str(path), "--lam", "0.1", "-o", str(out)])
    assert result.exit_code == 1
    assert result.output.count("\n") == 1 and result.output.startswith("Error: ")
    assert "Traceback" not in result.output
    assert not out.exists()


def test_a_bug_keeps_its_traceback(poses, monkeypatch):
    path, _, _ = poses

    def broken(*args, **kwargs):
        raise RuntimeError("a bug")

    monkeypatch.setattr(a2b, "motion", broken)
    result = CliRunner().invoke(cli, ["interpolate", str(path)])
    assert result.exit_code == 1
    assert isinstance(result.exception, RuntimeError)


@pytest.mark.parametrize(
    "args, message",
    [
        (["--samples", 1], "1 is not in the range 2<=x<=9007199254740992"),
        (["--samples", 0], "0 is not in the range"),
        (["--samples", -5], "-5 is not in the range"),
        (["--samples", 2**53 + 1], "is not in the range"),
        (["--duration", "inf"], "'inf' is not a decimal number"),
        (["--duration", "0"], "'0' is not greater than 0"),
        (["--duration", "nan"], "'nan' is not a decimal number"),
    ],
)
def test_absurd_requests_are_usage_errors(poses, args, message):
    path, _, _ = poses
    result = run_split("interpolate", path, *args)
    assert result.exit_code == 2
    assert message in result.stderr


NON_FINITE_RESULTS = [
    ("interpolate",
     "end: {quaternion_wxyz: [0, 0, 0, 1], translation: [0, 0, 1]}\nparameters: {lam: 1e200}\n",
     "the motion's coefficients overflow float64"),
    ("describe", "end: {quaternion_wxyz: [1, 0, 0, 0], translation: [1.5e308, 1.5e308, 0]}\n",
     "the displacement from start to end overflows float64 (d = inf)"),
    ("describe",
     "end: {quaternion_wxyz: [0, 0, 0, 1], translation: [0, 0, 1]}\nparameters: {lam: 1e200}\n",
     "the motion's coefficients overflow float64"),
]  # fmt: skip


@pytest.mark.parametrize("command, end, message", NON_FINITE_RESULTS)
def test_results_that_overflow_are_refused(tmp_path, command, end, message):
    path = tmp_path / "p.yaml"
    path.write_text("start: {quaternion_wxyz: [1, 0, 0, 0]}\n" + end)
    args = ["-o", tmp_path / "o.csv"] if command == "interpolate" else ["--json"]
    result = run_split(command, path, *args)
    assert result.exit_code == 1
    assert result.stderr.startswith(f"Error: {message}") and result.stderr.count("\n") == 1
    assert result.stdout == ""
    assert sorted(p.name for p in tmp_path.iterdir()) == ["p.yaml"]


def test_a_sensitive_result_is_one_warning_line_and_the_run_goes_on(tmp_path):
    half = 0.5e-4  # a turn of 1e-4 rad, taken the long way round: p(½) nearly vanishes
    path = tmp_path / "p.yaml"
    path.write_text(
        "start: {quaternion_wxyz: [1, 0, 0, 0]}\n"
        f"end: {{quaternion_wxyz: [{math.cos(half)!r}, 0, 0, {math.sin(half)!r}], translation: [1, "
        f"0, "
        f"0]}}\n"
        "parameters: {long_way: true}\n"
    )
    result = run_split("interpolate", path, "--samples", 3, "-o", tmp_path / "o.csv")
    assert result.exit_code == 0
    lines = result.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith(
        "Warning: the Darboux motion passes close to p(t) = 0"
    )
    assert (tmp_path / "o.csv").exists()


def test_a_command_lets_glibc_keep_freed_memory_unless_the_environment_says(monkeypatch):
    """Every command raises glibc's mmap and trim thresholds to the limits of its own adaptive
    ones (the formatter's temporaries are then not mapped afresh for each block); an
    allocator setting in the environment wins, and without glibc nothing happens."""
    import ctypes

    import a2b.cli as cli_module

    calls = []

    class Libc:
        def mallopt(self, parameter, value):
            calls.append((parameter, value))
            return 1

    monkeypatch.setattr(ctypes, "CDLL", lambda name: Libc())
    for key in ("MALLOC_MMAP_THRESHOLD_", "MALLOC_TRIM_THRESHOLD_", "GLIBC_TUNABLES"):
        monkeypatch.delenv(key, raising=False)
    cli_module._keep_freed_memory()
    assert calls == [(-3, 32 << 20), (-1, 64 << 20)]
    calls.clear()
    monkeypatch.setenv("GLIBC_TUNABLES", "glibc.malloc.trim_threshold=0")
    cli_module._keep_freed_memory()
    assert calls == []
    monkeypatch.delenv("GLIBC_TUNABLES")
    monkeypatch.setattr(ctypes, "CDLL", lambda name: object())  # no mallopt: not glibc
    cli_module._keep_freed_memory()
    assert calls == []


def test_fiber_states_the_repair_of_orthonormalize(tmp_path):
    """--orthonormalize repairs only when asked, and says so among the choices (table and
    JSON), with the largest residual."""
    import json

    import numpy as np

    from a2b.poses import matrices_from_quat_trans

    rough = np.round(matrices_from_quat_trans([0.9, 0.1, -0.3, 0.2], [0.5, 1.0, 2.0]), 7)
    path = tmp_path / "rough.yaml"
    path.write_text("matrix: " + json.dumps(rough.tolist()) + "\n")
    refused = CliRunner().invoke(cli, ["fiber", str(path)])
    assert refused.exit_code == 1 and "--orthonormalize" in refused.output
    result = CliRunner().invoke(cli, ["fiber", str(path), "--orthonormalize", "--json"])
    assert result.exit_code == 0, result.output
    choices = json.loads(result.output)["choices"]
    assert choices and choices[0].startswith("orthonormalized 1 matrix pose: largest max |R Rᵀ")
    table = CliRunner().invoke(cli, ["fiber", str(path), "--orthonormalize"])
    assert "orthonormalized 1 matrix pose" in table.output
