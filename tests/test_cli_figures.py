"""The figure commands' options (`a2b plot`, `a2b view`): one bounded line for any value."""

from __future__ import annotations

from pathlib import Path

from click.testing import CliRunner

from a2b.cli import cli

SAMPLES = Path(__file__).resolve().parent.parent / "samples"


def test_a_long_compare_list_is_one_bounded_line(tmp_path):
    value = "darboux," + "y" * 1_000_000 + "\x1b[2J"
    for command in ("plot", "view"):
        out = tmp_path / ("x.svg" if command == "plot" else "x.html")
        result = CliRunner().invoke(cli, [command, str(SAMPLES / "quarter-turn.yaml"),
                                          "--compare", value, "-o", str(out)])  # fmt: skip
        assert result.exit_code == 2
        line = result.output.strip().splitlines()[-1]
        assert line.startswith("Error: Invalid value for '--compare': expected modes from ")
        assert line.endswith("(1000012 characters)") and len(line) < 300
        assert "\x1b" not in result.output and not out.exists()
