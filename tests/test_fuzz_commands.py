"""Fuzzing the input path at the commands (the readers: tests/test_fuzz_readers.py).

Every generated input is malformed *by construction* (a mutation that no valid file survives:
a wrong type, a wrong length, a missing or unknown or repeated key, a number that is no
finite double, a truncated or garbled text, bytes that are not UTF-8, deep nesting, ...), so
every case must end in one clear message:

* readers (:func:`read_pose`, :func:`read_poses`, :func:`read_jobs`, :func:`read_pose_list`)
  raise :class:`InputFileError` with one line that starts with the file name;
* ``a2b interpolate``, ``a2b fiber`` and ``a2b batch`` (in-process, click's ``CliRunner``)
  exit with status 1 and one line ``Error: ...`` on stderr (status 2 for malformed options),
  with no traceback and no output file, not even a temporary one.

The examples are derandomised (a fixed seed per test), so CI runs the same cases every time;
``A2B_FUZZ_EXAMPLES=200000 pytest -m fuzz`` runs a larger share of each class
(default 10 000 in all), and ``A2B_FUZZ_SEED=n`` explores other cases. Each test counts the
examples it actually ran and asserts its quota; ``test_total_cases`` asserts the sum.
"""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest
from click.testing import CliRunner
from hypothesis import given, settings
from hypothesis import strategies as st

from a2b.cli import cli

from .fuzzing import COUNTS, run_fuzz, written


@pytest.fixture(scope="module")
def workdir():
    path = Path(tempfile.mkdtemp(prefix="a2b-fuzz-"))
    yield path
    shutil.rmtree(path)


RUNNER = CliRunner()


def run_command(workdir: Path, args: list[str], case, stdin_name="<stdin>"):
    """Run ``a2b ARGS INPUT -o OUT`` in-process; the input is a file, or stdin for ``<stdin>``."""
    name, data, _ = case
    for leftover in workdir.iterdir():
        leftover.unlink()
    if name == stdin_name:
        source, stdin = "-", data
    else:
        source, stdin = str(workdir / name), None
        Path(source).write_bytes(data)
    out = workdir / "out.csv"
    command, *options = args
    argv = [command, source, *options] + (["-o", str(out)] if command != "fiber" else [])
    result = RUNNER.invoke(cli, argv, input=stdin, catch_exceptions=True)
    return result, {p.name for p in workdir.iterdir()} - {name}


def expect_one_line_error(result, left, how, status=(1,)):
    assert isinstance(result.exception, SystemExit), (how, result.exception)
    assert result.exit_code in status, (how, result.exit_code, result.output)
    assert result.stdout == "", (how, result.stdout[:200])
    lines = result.stderr.splitlines()
    if result.exit_code == 1:
        assert len(lines) == 1 and lines[0].startswith("Error: "), (how, result.stderr)
    else:
        assert lines[-1].startswith("Error: "), (how, result.stderr)
    assert "Traceback" not in result.stderr
    assert not left, (how, left)


@pytest.mark.parametrize(
    "command, kind", [("interpolate", "poses"), ("fiber", "pose"), ("batch", "jobs")]
)
def test_fuzz_command(workdir, command, kind):
    """a2b interpolate, fiber, batch on malformed files: status 1, one line, no output file."""

    def check(case):
        result, left = run_command(workdir, [command], case)
        expect_one_line_error(result, left, case[2])

    run_fuzz(command, written(kind), check)


GOOD_POSES = (
    b"start: {quaternion_wxyz: [1, 0, 0, 0]}\n"
    b"end: "
    b"{quaternion_wxyz: [0.7071067811865476, 0, 0, 0.7071067811865476], translation: [1, 1, 0.5]}\n"
)
GOOD_POSE = b"quaternion_wxyz: [0.5, 0.5, -0.5, 0.5]\ntranslation: [1, 2, 3]\n"
GOOD_JOBS = b"- " + GOOD_POSES.replace(b"\nend", b"\n  end")

NOT_A_NUMBER = st.one_of(
    st.sampled_from(["nan", "inf", "-inf", "1e999", "", "one", "1,2", "0x", "--1", "NaN"]),
    st.text(max_size=6).filter(
        lambda s: not re.fullmatch(r"\s*[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?\s*", s)
    ),
)


@st.composite
def bad_options(draw):
    """A command and an option value it must refuse: (command, arguments, stdin)."""
    command = draw(st.sampled_from(["interpolate", "fiber", "batch"]))
    if command == "interpolate":
        option = draw(st.sampled_from(["--samples", "--m", "--delta", "--duration", "--start-time",
                                       "--format", "--branch", "--alpha", "--mode",
                                       "--frame"]))  # fmt: skip
        if option == "--samples":
            value = draw(
                st.one_of(
                    st.integers(max_value=1),
                    st.integers(min_value=2**53 + 1),
                    NOT_A_NUMBER,
                    st.just("2.5"),
                )
            )
        elif option in ("--m", "--alpha"):
            n = 4 if option == "--m" else 6
            count = draw(st.integers(0, 8).filter(lambda k: k != n))
            value = (
                ",".join(["1"] * count)
                if draw(st.booleans())
                else ",".join(["1"] * (n - 1) + [draw(NOT_A_NUMBER.filter(lambda s: "," not in s))])
            )
        elif option == "--duration":
            value = draw(
                st.one_of(st.sampled_from(["0", "-1", "-0.0", "inf", "nan", "1e999"]), NOT_A_NUMBER)
            )
        elif option == "--branch":
            value = draw(
                st.one_of(st.integers().filter(lambda b: b not in (1, -1)).map(str), NOT_A_NUMBER)
            )
        elif option in ("--format", "--mode", "--frame"):
            allowed = {"--format": ("csv", "matrix", "study", "tum", "kitti", "mcap"),
                       "--mode": ("darboux", "cubic", "screw"),
                       "--frame": ("canonical", "given")}[option]  # fmt: skip
            value = draw(st.text(max_size=8).filter(lambda s: s not in allowed))
        else:
            value = draw(NOT_A_NUMBER)
        return command, [option, str(value)], GOOD_POSES
    if command == "fiber":
        option = draw(st.sampled_from(["--offsets", "--map", "--basis", "--m"]))
        if option == "--offsets":
            args = ["--offsets", draw(NOT_A_NUMBER.filter(lambda s: "," not in s))]
        elif option == "--m":
            args = [
                "--map",
                "mu",
                "--m",
                ",".join(["1"] * draw(st.integers(0, 8).filter(lambda k: k != 4))),
            ]
        else:
            args = [
                option,
                draw(
                    st.text(max_size=8).filter(
                        lambda s: s not in ("kappa", "mu", "paper", "rref", "auto")
                    )
                ),
            ]
        return command, args, GOOD_POSE
    option = draw(st.sampled_from(["--samples", "--chunk-size", "--format", "--mode"]))
    if option == "--samples":
        value = draw(st.one_of(st.integers(max_value=1).map(str), NOT_A_NUMBER))
    elif option == "--chunk-size":
        value = draw(st.one_of(st.integers(max_value=0).map(str), NOT_A_NUMBER))
    else:
        value = draw(
            st.text(max_size=8).filter(
                lambda s: s not in ("csv", "matrix", "study", "darboux", "cubic", "screw")
            )
        )
    return command, [option, value], GOOD_JOBS


def test_fuzz_options(workdir):
    """Malformed option values: status 2 (usage) or 1, one message, no traceback, no file."""

    def check(case):
        command, args, stdin = case
        for leftover in workdir.iterdir():
            leftover.unlink()
        out = ["-o", str(workdir / "out.csv")] if command != "fiber" else []
        result = RUNNER.invoke(cli, [command, "-", *args, *out], input=stdin, catch_exceptions=True)
        expect_one_line_error(result, set(workdir.iterdir()), (command, args), status=(1, 2))

    run_fuzz("options", bad_options(), check)


# -- a handful of cases in real processes: what an in-process run cannot show (a crash) --------

A2B = [sys.executable, "-c", "from a2b.cli import cli; cli(prog_name='a2b')"]

PROCESS_CASES = [
    ("interpolate", "deep.yaml", b"[" * 200_000 + b"]" * 200_000),  # crashed the C composer once
    ("interpolate", "deep.json", b"[" * 200_000 + b"]" * 200_000),
    ("fiber", "dashes.yaml", b"- " * 100_000 + b"x\n"),
    ("batch", "garbage.yaml", bytes(range(256)) * 4),
    (
        "interpolate",
        "huge.json",
        b'{"start": {"quaternion_wxyz": [1'
        + b"0" * 5000
        + b', 0, 0, 0]}, "end": {"quaternion_wxyz": [1, 0, 0, 0]}}',
    ),
    ("interpolate", "nul.yaml", GOOD_POSES.replace(b"end", b"e\x00nd")),
    (
        "batch",
        "latin1.jsonl",
        b'{"start": {"quaternion_wxyz": [1, 0, 0, 0]}, '
        b'"end": {"quaternion_wxyz": [1, 0, 0, 0]}, "name": "caf\xe9"}\n',
    ),
]


@pytest.mark.parametrize("command, name, data", PROCESS_CASES, ids=[c[1] for c in PROCESS_CASES])
def test_fuzz_in_a_real_process(tmp_path, command, name, data):
    source = tmp_path / name
    source.write_bytes(data)
    out = tmp_path / "out.csv"
    args = [command, str(source)] + (["-o", str(out)] if command != "fiber" else [])
    result = subprocess.run(A2B + args, capture_output=True, timeout=120, check=False)
    assert result.returncode == 1, result.stderr[-500:]
    lines = result.stderr.decode().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"Error: {source}"), lines
    assert result.stdout == b""
    assert sorted(p.name for p in tmp_path.iterdir()) == [name]
    COUNTS[f"process:{name}"] = 1


# -- output targets -----------------------------------------------------------------------------

ROOT = Path(__file__).resolve().parent.parent

TARGETS = ["new", "existing", "read-only", "set-id", "link", "dangling-link", "directory",
           "slash", "missing-parent", "dev-null", "dev-stdout"]  # fmt: skip


@settings(max_examples=40, derandomize=True, database=None, deadline=None)
@given(
    target=st.sampled_from(TARGETS),
    fmt=st.sampled_from(["csv", "tum", "mcap", "kitti"]),
    command=st.sampled_from(["interpolate", "batch"]),
)
def test_output_targets(target, fmt, command):
    """Every kind of -o target: written where it should be, or one error line and nothing lost;
    never a traceback, never a temporary file left behind."""
    old = b"old bytes that a refused run must keep\n"
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        source = ROOT / "samples" / ("jobs.yaml" if command == "batch" else "quarter-turn.yaml")
        path = work / "out"
        if target in ("existing", "read-only", "set-id", "link"):
            real = work / "real"
            real.write_bytes(old)
            if target == "read-only":
                real.chmod(0o444)
            if target == "set-id":
                real.chmod(0o6755)
            if target == "link":
                path.symlink_to(real)
            else:
                real.rename(path)
        elif target == "dangling-link":
            path.symlink_to(work / "nowhere")
        elif target == "directory":
            path.mkdir()
        arg = {
            "slash": f"{path}/",
            "missing-parent": str(work / "no" / "out"),
            "dev-null": "/dev/null",
            "dev-stdout": "/dev/stdout",
        }.get(target, str(path))
        if command == "batch" and fmt in ("tum", "kitti") and target in ("new", "directory"):
            arg = str(path)  # a directory of files, made if missing
        done = subprocess.run(
            A2B + [command, str(source), "--format", fmt, "-o", arg],
            capture_output=True,
            timeout=120,
        )
        err = done.stderr.decode()
        assert "Traceback" not in err, err
        assert not [p.name for p in work.rglob("*") if p.name.endswith(".tmp")], target
        if done.returncode != 0:
            assert done.returncode in (1, 2) and err.splitlines()[-1].startswith("Error: "), err
            for p in work.rglob("*"):
                if p.is_file() and not p.is_symlink() and p.name in ("out", "real"):
                    assert p.read_bytes() == old, (target, p)
            return
        if target == "dev-stdout":
            assert done.stdout
        elif target == "set-id":
            assert path.stat().st_mode & 0o6000 == 0
