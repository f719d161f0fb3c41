"""Every input of every command read with a bound, in a real process: ``/dev/zero`` and an
8 MB one-line file are one error line, in under 200 MB and a time limit."""

from __future__ import annotations

import pytest

from .test_hardening_readers import MEMORY_MB, PRECIOUS, hostile_run, linux_only

#: Each command with a file argument, and what it needs besides.
COMMANDS = {
    "interpolate": [],
    "describe": [],
    "fiber": [],
    "spline": [],
    "bezier": [],
    "view": ["-o"],
    "plot": ["-o"],
    "batch": ["-o"],
}


def _argv(command: str, path, out) -> list:
    rest = COMMANDS[command]
    if rest == ["-o"]:
        suffix = {"view": ".html", "plot": ".png", "batch": ".csv"}[command]
        return [command, path, "-o", out.with_suffix(suffix)]
    return [command, path]


@linux_only
@pytest.mark.parametrize("command", COMMANDS)
def test_dev_zero_is_refused_at_once_by_every_command(tmp_path, command):
    out = tmp_path / "out"
    peak, line, status = hostile_run(*_argv(command, "/dev/zero", out))
    assert peak < MEMORY_MB, peak
    assert line == "Error: /dev/zero:1: a NUL byte at byte 0, so this is no text file"
    assert status == 1


@linux_only
@pytest.mark.parametrize("command", COMMANDS)
def test_an_8_mb_line_is_one_bounded_error(tmp_path, command):
    path = tmp_path / "one.yaml"
    path.write_text("a" * 8_000_000 + "\n")
    out = tmp_path / "out"
    peak, line, status = hostile_run(*_argv(command, path, out))
    assert peak < MEMORY_MB, peak
    assert line.startswith(f"Error: {path}:1:1: expected ") and len(line) < 400
    assert status == 1


@linux_only
def test_a_pose_file_over_64_mib_is_refused_before_it_is_read(tmp_path):
    path = tmp_path / "huge.yaml"
    with open(path, "wb") as f:
        f.truncate((64 << 20) + 1)  # sparse: no NUL byte is read before the size is refused
    peak, line, status = hostile_run("interpolate", path)
    assert peak < 60, peak
    assert line == f"Error: {path}: more than 64 MiB, more than a2b reads from a file of this kind"
    assert status == 1


@linux_only
@pytest.mark.parametrize("option", ["--times", "--at"])
def test_dev_zero_as_new_times_is_refused_in_bounded_memory(tmp_path, option):
    out = tmp_path / "out.csv"
    out.write_bytes(PRECIOUS)
    peak, line, status = hostile_run(
        "resample", "samples/reference.tum", option, "/dev/zero", "-o", out
    )
    assert peak < MEMORY_MB, peak
    assert line.startswith("Error: /dev/zero")
    assert status == 1 and out.read_bytes() == PRECIOUS


def test_times_are_read_by_the_one_reader_of_times(tmp_path):
    """``--times`` gives the errors of :func:`a2b.io.textrows.read_times` (its line and its
    column, the written time)."""
    from click.testing import CliRunner

    from a2b.cli import cli

    path = tmp_path / "times.txt"
    path.write_text("1700000000.5\n1700000000.50\n")
    result = CliRunner().invoke(cli, ["resample", "samples/reference.tum", "--times", str(path)])
    assert result.exit_code == 1
    expected = f"Error: {path}:2:1: the time 1700000000.5 repeats the previous one"
    assert result.output.startswith(expected)


# -- options that the input cannot use are refused ------------------------------------------


def _invoke(*args):
    from click.testing import CliRunner

    from a2b.cli import cli

    return CliRunner().invoke(cli, [str(a) for a in args])


@pytest.fixture(scope="module")
def mcap_poses(tmp_path_factory):
    path = tmp_path_factory.mktemp("mcap") / "turn.mcap"
    assert _invoke("interpolate", "samples/quarter-turn.yaml", "--format", "mcap", "-o", path)
    return path


@pytest.mark.parametrize(
    ("command", "rest"),
    [("resample", ["--rate", 10]), ("view", ["-o", "x.html"]), ("spline", [])],
)
def test_topic_on_a_tum_file_is_refused(tmp_path, command, rest):
    out = [tmp_path / "x.html" if r == "x.html" else r for r in rest]
    result = _invoke(command, "samples/reference.tum", "--topic", "/x", *out)
    assert result.exit_code == 1
    assert result.output == (
        "Error: samples/reference.tum: --topic does not apply to tum input; it gives the topic "
        "of an MCAP file or a bag (mcap, rosbag2 only)\n"
    )
    assert not (tmp_path / "x.html").exists()


@pytest.mark.parametrize("command", ["resample", "view"])
def test_input_rate_on_mcap_is_refused(tmp_path, mcap_poses, command):
    rest = ["--rate", 10] if command == "resample" else ["-o", tmp_path / "x.html"]
    result = _invoke(command, mcap_poses, "--input-rate", 5, *rest)
    assert result.exit_code == 1
    assert "--input-rate does not apply to mcap input" in result.output


@pytest.mark.parametrize("option", [["--samples", 5], ["--delta", 0.1], ["--mode", "screw"]])
def test_view_refuses_options_of_poses_files_for_a_trajectory(tmp_path, option):
    out = tmp_path / "x.html"
    result = _invoke("view", "samples/reference.tum", *option, "-o", out)
    assert result.exit_code == 2 and not out.exists()
    assert f"Error: {option[0]} is for poses files; this is a trajectory" in result.output
