"""`a2b plot`, the command: what it passes to a2b.plot, the files it writes, its errors."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

pytest.importorskip("matplotlib")

MAGIC = {"png": b"\x89PNG\r\n\x1a\n", "pdf": b"%PDF-"}

SAMPLES_DIR = Path(__file__).resolve().parent.parent / "samples"
QUARTER = str(SAMPLES_DIR / "quarter-turn.yaml")


@pytest.fixture
def calls(monkeypatch):
    """Record the arguments the command passes to plot_motions, and keep the figures small."""
    import a2b.plot

    recorded = []
    original = a2b.plot.plot_motions

    def spy(*args, **kwargs):
        recorded.append((args, kwargs))
        return original(*args, **{**kwargs, "instants": 4})  # at the size the command draws

    monkeypatch.setattr(a2b.plot, "plot_motions", spy)
    return recorded


def run(*args):
    from click.testing import CliRunner

    from a2b.cli import cli

    return CliRunner().invoke(cli, ["plot", *args])


@pytest.mark.parametrize("fmt", ["png", "svg", "pdf"])
def test_command_writes_the_format_of_the_suffix(tmp_path, calls, fmt):
    out = tmp_path / f"turn.{fmt}"
    result = run(QUARTER, "--samples", "5", "-o", str(out))
    assert (result.exit_code, result.output) == (0, "")
    data = out.read_bytes()
    assert data.startswith(MAGIC[fmt]) if fmt != "svg" else b"<svg" in data[:2000]
    ((args, kwargs),) = calls
    assert args[2] == [("darboux", {})] and kwargs["samples"] == 5 and kwargs["family"] is False


def test_command_compare_gives_each_mode_its_parameters(tmp_path, calls):
    out = tmp_path / "compare.png"
    result = run(
        QUARTER,
        "--compare",
        "darboux,cubic,screw",
        "--delta",
        "0.3",
        "--b",
        "1",
        "--samples",
        "5",
        "--family",
        "--angle-unit",
        "rad",
        "--length-unit",
        "m",
        "-o",
        str(out),
    )
    assert (result.exit_code, result.output) == (0, "")
    assert out.read_bytes().startswith(MAGIC["png"])
    ((args, kwargs),) = calls
    assert args[2] == [("darboux", {"delta": 0.3}), ("cubic", {"b": 1.0}), ("screw", {})]
    assert (
        kwargs["family"] is True and kwargs["angle_unit"] == "rad" and kwargs["length_unit"] == "m"
    )


def test_command_points_and_family_of(tmp_path, calls):
    out = tmp_path / "family.svg"
    result = run(
        QUARTER,
        "--mode",
        "cubic",
        "--family-of",
        "m",
        "--points",
        "0,0,0; 1,2,3",
        "--samples",
        "5",
        "-o",
        str(out),
    )
    assert (result.exit_code, result.output) == (0, "")
    ((args, kwargs),) = calls
    assert args[2] == [("cubic", {})] and kwargs["family"] == "m"
    assert kwargs["points"] == ((0.0, 0.0, 0.0), (1.0, 2.0, 3.0))


@pytest.mark.parametrize(
    "args, code, message",
    [
        (
            ["-o", "turn.jpg"],
            1,
            (
                "Error: cannot tell the figure format from 'turn.jpg' (suffix '.jpg'); "
                "use a file name ending in .png, .svg or .pdf\n"
            ),
        ),
        (
            ["--compare", "cubic,screw", "--delta", "1", "-o", "x.png"],
            1,
            "Error: --delta applies to none of the compared modes cubic, screw\n",
        ),
        (
            ["--mode", "screw", "--family", "-o", "x.png"],
            1,
            "Error: a family of transmission curves needs a darboux or cubic motion\n",
        ),
        (
            ["--mode", "screw", "--compare", "darboux,cubic", "-o", "x.png"],
            2,
            "give --mode or --compare, not both",
        ),
        (
            ["--compare", "darboux,helix", "-o", "x.png"],
            2,
            "expected modes from darboux, cubic, screw",
        ),
        (
            ["--points", "1,2", "-o", "x.png"],
            2,
            "expected 3 comma-separated numbers (x, y, z), got 2",
        ),
        (
            ["--mode", "cubic", "--delta", "1", "-o", "x.png"],
            1,
            "Error: mode cubic does not take delta",
        ),
    ],
)
def test_command_errors(tmp_path, monkeypatch, args, code, message):
    monkeypatch.chdir(tmp_path)
    Path("x.png").write_bytes(b"old")
    result = run(QUARTER, *args)
    assert result.exit_code == code
    assert message in result.output
    assert result.exception is None or isinstance(result.exception, SystemExit)
    assert Path("x.png").read_bytes() == b"old"  # an existing output is left alone
    assert sorted(p.name for p in tmp_path.iterdir()) == ["x.png"]  # and no temporary file stays


def test_command_speeds(tmp_path):
    out = tmp_path / "speeds.svg"
    limits = ["--max-speed", "1", "--max-accel", "2", "--max-jerk", "5", "--constant-speed"]
    result = run(
        QUARTER, "--speeds", "--compare", "darboux,cubic,screw", *limits, "-v", "-o", str(out)
    )
    assert result.exit_code == 0, result.output
    svg = out.read_text()
    for gid in ("speed:darboux", "accel:cubic", "angular_speed:screw", "limit:speed"):
        assert f'id="{gid}"' in svg
    assert "darboux: the time law takes" in result.output
    assert "801 samples evenly spaced in time" in result.output
    # a spline and a duration alone (a linear law of 2 s)
    spline = str(SAMPLES_DIR / "spline.yaml")
    out = tmp_path / "spline.png"
    result = run(spline, "--speeds", "--duration", "2", "--samples", "50", "-o", str(out))
    assert (result.exit_code, result.output) == (0, "")
    assert out.read_bytes().startswith(MAGIC["png"])


@pytest.mark.parametrize(
    "args, message",
    [
        (["--max-speed", "1"], "--max-speed is for --speeds"),
        (["--duration", "2"], "--duration is for --speeds"),
        (["--speeds", "--family"], "--family, --family-of and --points are not for --speeds"),
        (["--speeds", "--rate", "10"], "No such option"),
        (["--speeds", "--time-law", "linear", "--max-accel", "1"], "linear law starts and stops"),
    ],
)
def test_command_speeds_errors(tmp_path, monkeypatch, args, message):
    monkeypatch.chdir(tmp_path)
    result = run(QUARTER, *args, "-o", "x.png")
    assert result.exit_code in (1, 2) and message in result.output, result.output
    assert list(tmp_path.iterdir()) == []


def test_command_without_matplotlib(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    result = run(QUARTER, "-o", str(tmp_path / "x.png"))
    assert (result.exit_code, result.output) == (
        1,
        "Error: plotting needs matplotlib, which is not installed: pip install "
        "'a2b-motions[plot]'\n",
    )
    assert not (tmp_path / "x.png").exists()


def test_command_help_does_not_load_matplotlib():
    code = (
        "import sys\n"
        "from a2b.cli import cli\n"
        "try:\n"
        "    cli.main(['plot', '-h'], prog_name='a2b')\n"
        "except SystemExit:\n"
        "    pass\n"
        "print('matplotlib' in sys.modules)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert "Example:" in out.stdout and out.stdout.strip().endswith("False")
