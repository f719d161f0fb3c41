"""README.md documents every command, every output format and the quick-start files."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from a2b.cli import COMMANDS
from a2b.cli.options import FORMATS

README = (Path(__file__).resolve().parent.parent / "README.md").read_text()


def test_the_two_opening_commands_come_first():
    blocks = re.findall(r"```sh\n(.*?)```", README, re.DOTALL)
    assert blocks[0].strip() == "pip install . && a2b interpolate samples/quarter-turn.yaml"
    assert blocks[1].strip() == 'pip install ".[test]" && pytest'


@pytest.mark.parametrize("name", list(COMMANDS))
def test_every_command_is_in_the_readme(name):
    assert re.search(rf"`a2b {name}\b", README), f"README.md does not document `a2b {name}`"


@pytest.mark.parametrize("fmt", FORMATS)
def test_every_format_is_documented_with_a_sample(fmt):
    assert f"`{fmt}`" in README


def test_sample_files_named_in_the_readme_exist():
    root = Path(__file__).resolve().parent.parent
    for name in set(re.findall(r"samples/[\w.-]+\.yaml", README)):
        assert (root / name).exists(), name
