"""README.md documents every command, every option, every output format and the quick-start
files, and its command lines run."""

from __future__ import annotations

import re
import shlex
import shutil
from pathlib import Path

import click
import pytest
from click.testing import CliRunner

from a2b.cli import COMMANDS, cli
from a2b.formats import OUTPUT_NAMES as FORMATS

ROOT = Path(__file__).resolve().parent.parent
README = (ROOT / "README.md").read_text()
SH_BLOCKS = re.findall(r"```sh\n(.*?)```", README, re.DOTALL)


def test_the_two_opening_commands_come_first():
    assert SH_BLOCKS[0].strip() == "pip install . && a2b interpolate samples/quarter-turn.yaml"
    assert SH_BLOCKS[1].strip() == 'pip install ".[test]" && pytest'


@pytest.mark.parametrize("name", list(COMMANDS))
def test_every_command_has_a_section_in_the_readme(name):
    assert re.search(rf"^### .*`a2b {name}\b", README, re.MULTILINE), f"no section for `a2b {name}`"


@pytest.mark.parametrize("name", list(COMMANDS))
def test_every_option_is_in_the_readme(name):
    command = cli.get_command(click.Context(cli), name)
    options = [
        opt
        for param in command.params
        if isinstance(param, click.Option)
        for opt in param.opts
        if opt.startswith("--") and opt != "--help"
    ]
    missing = [opt for opt in options if not re.search(rf"`[^`]*{re.escape(opt)}\b", README)]
    assert not missing, f"a2b {name}: {', '.join(missing)} not in README.md"


@pytest.mark.parametrize("fmt", FORMATS)
def test_every_format_is_documented_with_a_sample(fmt):
    assert f"`{fmt}`" in README


def test_sample_files_named_in_the_readme_exist():
    for name in set(re.findall(r"samples/[\w.-]+\.yaml", README)):
        assert (ROOT / name).exists(), name


EXAMPLES = [
    line.strip()
    for block in SH_BLOCKS
    for line in block.splitlines()
    if line.strip().startswith("a2b ") and not re.search(r"[|<>]", line)
]
#: Lines that start a cluster (worker processes): run with the slow tests.
CLUSTER = re.compile(r"--(workers|scheduler)\b")


def run_readme_line(line: str, tmp_path: Path, monkeypatch) -> None:
    """Run one ``a2b ...`` line of README in ``tmp_path`` (with a copy of ``samples/``); the
    address of ``--scheduler`` is that of a local cluster started for it."""
    if " plot " in f" {line} ":
        pytest.importorskip("matplotlib")
    if "parquet" in line:
        pytest.importorskip("pyarrow")
    if not (tmp_path / "samples").exists():
        shutil.copytree(ROOT / "samples", tmp_path / "samples")
        (tmp_path / "docs").mkdir()
    monkeypatch.chdir(tmp_path)
    argv = shlex.split(line.split("#")[0])[1:]
    if "--scheduler" not in argv:
        result = CliRunner().invoke(cli, argv, catch_exceptions=False)
        assert result.exit_code == 0, result.output
        return
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(
        n_workers=1, threads_per_worker=1, host="127.0.0.1", dashboard_address="127.0.0.1:0"
    ) as cluster:
        argv[argv.index("--scheduler") + 1] = cluster.scheduler_address
        result = CliRunner().invoke(cli, argv, catch_exceptions=False)
    assert result.exit_code == 0, result.output


@pytest.mark.parametrize(
    "line",
    [pytest.param(x, marks=pytest.mark.slow) if CLUSTER.search(x) else x for x in EXAMPLES],
)
def test_the_readme_command_lines_run(line, tmp_path, monkeypatch):
    """Every ``a2b ...`` line of the README's shell blocks (without pipes) exits with status 0."""
    run_readme_line(line, tmp_path, monkeypatch)


def test_the_datasets_section_reads_back_in_pandas_polars_and_duckdb(tmp_path, monkeypatch):
    """The Datasets section's files, written by its command lines, read as its Python says."""
    for module in ("pyarrow", "pandas", "polars", "duckdb"):
        pytest.importorskip(module)
    section = README[README.index("## Datasets") : README.index("## Benchmarks")]
    blocks = re.findall(r"```sh\n(.*?)```", section, re.DOTALL)
    lines = [x for x in blocks[0].splitlines() if x.startswith("a2b ")]
    assert {shlex.split(x)[1] for x in lines} == {
        "interpolate", "bezier", "spline", "resample", "batch",
    }  # fmt: skip
    for line in lines:
        run_readme_line(line, tmp_path, monkeypatch)
    code = re.findall(r"```python\n(.*?)```", section, re.DOTALL)[0]
    namespace: dict = {}
    exec(compile(code, "README.md", "exec"), namespace)
    frame = namespace["frame"]
    assert list(frame.columns[:3]) == ["job", "t", "time"] and len(frame) == 404
    assert len(namespace["lazy"].collect()) == 101
    assert sorted(namespace["counts"]) == [(name, 101) for name in sorted(set(frame["job"]))]


def test_the_readme_counts_every_command():
    words = ["Two", "Three", "Four", "Five", "Six", "Seven", "Eight", "Nine", "Ten", "Eleven"]
    line = next(line for line in README.splitlines() if " commands: `a2b " in line)
    assert line.startswith(f"{words[len(COMMANDS) - 2]} commands:"), line
    listed = README[README.index(line) :].split("Every command", 1)[0]
    assert all(f"`a2b {name}`" in listed for name in COMMANDS)
