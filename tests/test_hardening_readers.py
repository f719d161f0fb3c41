"""Hostile trajectory inputs in a real process: one line on stderr, status 1 or 2, no
traceback, no file changed, memory under 200 MB and a time limit."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
A2B = [sys.executable, "-c", "from a2b.cli import cli; cli(prog_name='a2b')"]
PRECIOUS = b"precious: an older result that a failed run must not touch\n"
MEMORY_MB = 200

linux_only = pytest.mark.skipif(not Path("/proc/self/status").exists(), reason="needs /proc")

#: Runs a command and writes the peak resident memory (kB) of its children on fd ``argv[1]``;
#: its address space is capped, so that a reader without bounds fails fast instead of
#: filling the machine.
_PEAK = (
    "import os, resource, subprocess, sys\n"
    "cap = 2 << 30\n"
    "def limit(): resource.setrlimit(resource.RLIMIT_AS, (cap, cap))\n"
    "code = subprocess.run(sys.argv[2:], preexec_fn=limit).returncode\n"
    "peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss\n"
    "os.write(int(sys.argv[1]), str(peak).encode())\n"
    "sys.exit(code)\n"
)


def hostile_run(*args, timeout: float = 60) -> tuple[float, str, int]:
    """``(peak MB, the one error line, status)`` of ``a2b ARGS``; a timeout fails."""
    return capped_run([*A2B, *map(str, args)], timeout)


def capped_run(argv: list, timeout: float = 60) -> tuple[float, str, int]:
    """``(peak MB, the one error line, status)`` of a command; a timeout fails."""
    read, write = os.pipe()
    try:
        done = subprocess.run(
            [sys.executable, "-c", _PEAK, str(write), *argv],
            capture_output=True, pass_fds=(write,), timeout=timeout, cwd=ROOT,
        )  # fmt: skip
        os.close(write)
        write = None
        peak_kb = int(os.read(read, 64) or b"0")
    finally:
        os.close(read)
        if write is not None:
            os.close(write)
    lines = done.stderr.decode(errors="replace").splitlines()
    assert len(lines) == 1 and lines[0].startswith("Error: "), done.stderr[-2000:]
    assert done.returncode in (1, 2)
    return peak_kb / 1024, lines[0], done.returncode


@linux_only
@pytest.mark.parametrize(
    "fmt", [[], ["--input-format", "tum"], ["--input-format", "mcap"], ["--input-format", "csv"]]
)
def test_dev_zero_as_input_is_refused_in_bounded_memory(tmp_path, fmt):
    out = tmp_path / "out.csv"
    out.write_bytes(PRECIOUS)
    peak, line, _ = hostile_run("resample", "/dev/zero", *fmt, "--rate", 10, "-o", out)
    assert peak < MEMORY_MB, peak
    assert line.startswith("Error: /dev/zero")
    assert out.read_bytes() == PRECIOUS


@pytest.mark.slow
@linux_only
@pytest.mark.parametrize("line", [" ".join(["1.5"] * 2_000_000), "a" * 8_000_000])
def test_an_8_mb_line_stays_in_bounded_memory(tmp_path, line):
    path = tmp_path / "one.tum"
    path.write_text(line + "\n")
    out = tmp_path / "out.csv"
    out.write_bytes(PRECIOUS)
    peak, message, status = hostile_run("resample", path, "--rate", 10, "-o", out)
    assert peak < MEMORY_MB, peak
    assert message.startswith(f"Error: {path}:1:1: expected 8 numbers per line (tum), got ")
    assert status == 1 and out.read_bytes() == PRECIOUS


@linux_only
@pytest.mark.parametrize("names", [5000, 1_000_000])
def test_a_header_of_many_names_is_one_bounded_line(tmp_path, names):
    path = tmp_path / "wide.csv"
    path.write_text("t,tx,ty,tz,qw,qx,qy,qz," + ",".join(["x\x1b[31m"] * names) + "\n")
    peak, message, status = hostile_run("resample", path, "--rate", 10, "--input-format", "csv")
    assert peak < MEMORY_MB, peak
    assert len(message) < 500 and "\x1b" not in message and status == 1
    if names < 6000:
        assert f"'x\\x1b[31m' and {names - 5} more" in message
    else:
        assert message.endswith("the first line, a header, is longer than 65536 bytes")


@linux_only
def test_dev_zero_as_a_list_of_times_is_refused_in_bounded_memory():
    """The reader that ``resample --times`` can call (:func:`a2b.io.textrows.read_times`)."""
    script = (
        "import sys\n"
        "from a2b.errors import A2bError\n"
        "from a2b.io.textrows import read_times\n"
        "try:\n"
        "    read_times(open('/dev/zero', 'rb'))\n"
        "except A2bError as e:\n"
        "    sys.exit(f'Error: {e}')\n"
    )
    peak, line, status = capped_run([sys.executable, "-c", script])
    assert peak < MEMORY_MB, peak
    assert line == "Error: /dev/zero:1: a NUL byte at byte 0, so this is no text file"
