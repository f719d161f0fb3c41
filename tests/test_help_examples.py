"""Every example in every command's ``--help`` runs as written, from the repository root.

The examples are read from the help text a user sees (the indented lines after ``Example:``)
and run by a real shell, redirections and pipes included, in a copy of ``samples/``, with an
``a2b`` on the PATH that runs this Python's a2b.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import click
import pytest
from click.testing import CliRunner

from a2b.cli import COMMANDS, cli

ROOT = Path(__file__).resolve().parent.parent


def help_examples(group: click.Group, name: str | None) -> list[str]:
    """The command lines of the ``Example:`` block in ``a2b [NAME] --help``."""
    argv = ([name] if name else []) + ["--help"]
    result = CliRunner().invoke(group, argv, prog_name="a2b")
    assert result.exit_code == 0, result.output
    lines = result.output.splitlines()
    examples: list[str] = []
    for i, line in enumerate(lines):
        if line.strip() == "Example:":
            for following in lines[i + 1 :]:
                if not following.strip():
                    break
                examples.append(following.strip())
    return examples


def run_example(line: str, workdir: Path) -> subprocess.CompletedProcess:
    """Run one example with bash in ``workdir`` (a copy of samples/ inside)."""
    bin_dir = workdir / "bin"
    bin_dir.mkdir(exist_ok=True)
    shim = bin_dir / "a2b"
    shim.write_text(f'#!/bin/sh\nexec "{sys.executable}" -m a2b "$@"\n')
    shim.chmod(0o755)
    if not (workdir / "samples").exists():
        shutil.copytree(ROOT / "samples", workdir / "samples")
    env = dict(os.environ, PATH=f"{bin_dir}{os.pathsep}{os.environ.get('PATH', '')}")
    return subprocess.run(
        ["bash", "-o", "pipefail", "-c", line],
        cwd=workdir,
        env=env,
        capture_output=True,
        text=True,
        timeout=120,
    )


EXAMPLES = [(None, line) for line in help_examples(cli, None)] + [
    (name, line) for name in COMMANDS for line in help_examples(cli, name)
]


@pytest.mark.parametrize("name", [None, *COMMANDS])
def test_every_help_shows_an_example(name):
    examples = help_examples(cli, name)
    assert examples, f"a2b {name or ''} --help shows no example"
    assert all(line.startswith(("a2b ", "cat ")) for line in examples), examples


#: The examples that draw a figure with matplotlib (`a2b plot`, several seconds each in a process
#: of their own) are `slow`: README's `pytest` leaves them out, `.ci/run` runs them.
RUNS = [
    pytest.param(name, line, id=line, marks=[pytest.mark.slow] if " plot " in f" {line} " else [])
    for name, line in EXAMPLES
]


@pytest.mark.parametrize("name, line", RUNS)
def test_help_example_runs(name, line, tmp_path):
    if " plot " in f" {line} ":
        pytest.importorskip("matplotlib")
    result = run_example(line, tmp_path)
    assert result.returncode == 0, f"a2b {name or ''} --help: {line}\n{result.stderr}"
    assert "Traceback" not in result.stderr


def test_a_broken_example_is_caught(tmp_path):
    """The collector finds the example of a command it has never seen, and the runner fails it."""

    @click.command()
    def broken():
        """A command whose example names a file that does not ship.

        \b
        Example:
          a2b interpolate samples/no-such-file.yaml --samples 5
        """

    group = click.Group("a2b", commands={"broken": broken})
    examples = help_examples(group, "broken")
    assert examples == ["a2b interpolate samples/no-such-file.yaml --samples 5"]
    result = run_example(examples[0], tmp_path)
    assert result.returncode == 2
    assert "no-such-file.yaml" in result.stderr
