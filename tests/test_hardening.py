"""Output is never half-written, and resources stay bounded: real processes, real limits.

* A run that fails or is interrupted (SIGINT, SIGTERM, a full disk, a file-size limit) leaves
  no partial output and no temporary file, and an existing file at the destination keeps its
  bytes. The full disk is ``/dev/full`` (as stdout and as ``-o``: ENOSPC on write); a full
  disk for the temporary file next to the target is simulated with ``RLIMIT_FSIZE`` (``ulimit
  -f``) in the child, which makes the write fail with EFBIG (Python ignores SIGXFSZ) like
  ENOSPC would, without root or a small filesystem.
* 10⁹ samples stream: ``a2b interpolate --samples 1000000000 | head -c`` starts printing at
  once and the child's peak resident memory (``VmHWM`` in ``/proc/PID/status``) stays small.
"""

from __future__ import annotations

import io
import json
import math
import os
import resource
import signal
import stat
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parent.parent
SAMPLES = ROOT / "samples"
QUARTER = SAMPLES / "quarter-turn.yaml"
A2B = [sys.executable, "-c", "from a2b.cli import cli; cli(prog_name='a2b')"]
PRECIOUS = b"precious: an older result that a failed run must not touch\n"

linux_only = pytest.mark.skipif(not Path("/proc/self/status").exists(), reason="needs /proc")


def a2b_cmd(*args):
    return A2B + [str(a) for a in args]


def one_error_line(stderr: bytes) -> str:
    lines = stderr.decode().splitlines()
    assert len(lines) == 1 and lines[0].startswith("Error: "), stderr.decode()[-2000:]
    return lines[0]


def big_jobs(path: Path, samples: int) -> Path:
    path.write_text(
        "- name: big\n"
        f"  samples: {samples}\n"
        "  start: {quaternion_wxyz: [1, 0, 0, 0]}\n"
        "  end: "
        "{quaternion_wxyz: [0.7071067811865476, 0, 0, 0.7071067811865476], translation: [1, 1, "
        "0.5]}\n"
    )
    return path


# -- a full disk ------------------------------------------------------------------------------


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="needs /dev/full")
@pytest.mark.parametrize("fmt", ["csv", "mcap"])
def test_stdout_on_a_full_disk(fmt):
    """``a2b interpolate ... > /dev/full``: one line, status 1, no second error at exit."""
    with open("/dev/full", "wb") as full:
        result = subprocess.run(
            a2b_cmd("interpolate", QUARTER, "--samples", 200_000, "--format", fmt),
            stdout=full,
            stderr=subprocess.PIPE,
            timeout=120,
            check=False,
        )
    assert result.returncode == 1
    assert (
        one_error_line(result.stderr)
        == "Error: cannot write standard output: No space left on device"
    )


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="needs /dev/full")
def test_output_to_dev_full_writes_through_and_keeps_the_device():
    """``-o /dev/full`` is written directly (a rename would replace the device node)."""
    result = subprocess.run(
        a2b_cmd("interpolate", QUARTER, "--samples", 200_000, "-o", "/dev/full"),
        capture_output=True,
        timeout=120,
        check=False,
    )
    assert result.returncode == 1
    assert one_error_line(result.stderr) == "Error: cannot write /dev/full: No space left on device"
    assert stat.S_ISCHR(os.stat("/dev/full").st_mode)
    assert not any(name.startswith(".full.") for name in os.listdir("/dev"))


def _limit_file_size(limit: int):
    def preexec():
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))

    return preexec


FULL_DISK_RUNS = [
    ("interpolate", "csv", lambda tmp: [QUARTER, "--samples", 200_000]),
    ("interpolate", "mcap", lambda tmp: [QUARTER, "--samples", 200_000]),
    ("bezier", "tum", lambda tmp: [SAMPLES / "planar-bezier.yaml", "--samples", 200_000]),
    ("batch", "csv", lambda tmp: [big_jobs(tmp / "jobs.yaml", 200_000)]),
]


@pytest.mark.parametrize(
    "command, fmt, inputs", FULL_DISK_RUNS, ids=[f"{c}-{f}" for c, f, _ in FULL_DISK_RUNS]
)
def test_full_disk_for_the_temporary_file_keeps_the_old_file(tmp_path, command, fmt, inputs):
    """The temporary file next to the target hits a 64 KiB file-size limit (EFBIG)."""
    out = tmp_path / f"out.{fmt}"
    out.write_bytes(PRECIOUS)
    args = inputs(tmp_path) + ["-o", out] + (["--format", fmt] if command != "batch" else [])
    before = sorted(p.name for p in tmp_path.iterdir())
    result = subprocess.run(
        a2b_cmd(command, *args),
        capture_output=True,
        timeout=120,
        check=False,
        preexec_fn=_limit_file_size(64 * 1024),
    )
    assert result.returncode == 1
    assert one_error_line(result.stderr) == f"Error: cannot write {out}: File too large"
    assert out.read_bytes() == PRECIOUS
    assert sorted(p.name for p in tmp_path.iterdir()) == before  # no temporary file left


# -- output targets ---------------------------------------------------------------------------


def test_dev_stdout_appended_by_the_shell_keeps_what_was_there(tmp_path):
    """``-o /dev/stdout >> log`` writes through the descriptor: the log is appended to."""
    log = tmp_path / "log.csv"
    log.write_bytes(PRECIOUS)
    command = a2b_cmd("interpolate", QUARTER, "--samples", 3, "-o", "/dev/stdout")
    script = 'exec "$@" >> "$LOG"'  # the shell opens the log for appending, as `a2b ... >> log`
    done = subprocess.run(
        ["sh", "-c", script, "sh", *command],
        env={**os.environ, "LOG": str(log)},
        capture_output=True,
        timeout=60,
    )
    assert done.returncode == 0, done.stderr
    text = log.read_bytes()
    assert text.startswith(PRECIOUS) and text[len(PRECIOUS) :].startswith(b"t,tx,ty,tz")
    assert len(text[len(PRECIOUS) :].splitlines()) == 4
    assert sorted(p.name for p in tmp_path.iterdir()) == ["log.csv"]


@pytest.mark.parametrize("target", ["/dev/stdout", "/dev/fd/1", "/proc/self/fd/1"])
def test_descriptor_paths_into_a_pipe(target):
    if not Path(target).parent.exists():
        pytest.skip(f"{Path(target).parent} does not exist on this system")
    done = subprocess.run(
        a2b_cmd("interpolate", QUARTER, "--samples", 3, "-o", target),
        capture_output=True,
        timeout=60,
    )
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines()[0] == b"t,tx,ty,tz,qw,qx,qy,qz"
    assert len(done.stdout.splitlines()) == 4


def test_dev_fd_n_writes_that_descriptor(tmp_path):
    out = tmp_path / "via-fd.csv"
    with open(out, "wb") as f:
        f.write(PRECIOUS)
        f.flush()
        fd = f.fileno()
        done = subprocess.run(
            a2b_cmd("interpolate", QUARTER, "--samples", 3, "-o", f"/dev/fd/{fd}"),
            capture_output=True,
            timeout=60,
            pass_fds=(fd,),
        )
    assert done.returncode == 0, done.stderr
    assert out.read_bytes().startswith(PRECIOUS + b"t,tx,ty,tz")


@pytest.mark.parametrize("command", ["interpolate", "batch"])
def test_a_trailing_slash_names_a_directory(tmp_path, command):
    source = QUARTER if command == "interpolate" else SAMPLES / "jobs.yaml"
    done = subprocess.run(
        a2b_cmd(command, source, "-o", f"{tmp_path}/new/"), capture_output=True, timeout=60
    )
    assert done.returncode != 0
    assert b"names a directory" in done.stderr or b"is a directory" in done.stderr
    assert list(tmp_path.iterdir()) == []


def test_a_replaced_file_loses_set_id_bits(tmp_path):
    out = tmp_path / "out.csv"
    out.write_bytes(PRECIOUS)
    os.chmod(out, 0o6755)
    done = subprocess.run(
        a2b_cmd("interpolate", QUARTER, "--samples", 3, "-o", out), capture_output=True, timeout=60
    )
    assert done.returncode == 0, done.stderr
    assert stat.S_IMODE(out.stat().st_mode) == 0o755
    assert out.read_bytes().startswith(b"t,tx")


# -- interrupted runs -------------------------------------------------------------------------


def _start_and_signal(tmp_path, args, sig):
    """Start a long run into ``tmp_path/out``, wait until it writes, send ``sig``."""
    proc = subprocess.Popen(a2b_cmd(*args), stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    deadline = time.monotonic() + 60
    while not any(p.name.endswith(".tmp") for p in tmp_path.iterdir()):  # writing has started
        assert time.monotonic() < deadline and proc.poll() is None, (
            proc.stderr.read() if proc.poll() is not None else ""
        )
        time.sleep(0.02)
    time.sleep(0.2)
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=60)
    return proc.returncode, err


INTERRUPTED_RUNS = [
    ("interpolate", lambda tmp: ["interpolate", QUARTER, "--samples", 50_000_000]),
    (
        "interpolate-mcap",
        lambda tmp: ["interpolate", QUARTER, "--samples", 50_000_000, "--format", "mcap"],
    ),
    ("batch", lambda tmp: ["batch", big_jobs(tmp / "jobs.yaml", 50_000_000)]),
]


@pytest.mark.slow
@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
@pytest.mark.parametrize("name, args", INTERRUPTED_RUNS, ids=[n for n, _ in INTERRUPTED_RUNS])
def test_interrupted_run_keeps_the_old_file(tmp_path, name, args, sig):
    out = tmp_path / "out.csv"
    out.write_bytes(PRECIOUS)
    argv = args(tmp_path)
    before = sorted(p.name for p in tmp_path.iterdir())
    code, err = _start_and_signal(tmp_path, argv + ["-o", out], sig)
    if sig == signal.SIGINT:
        assert code == 1 and err.decode().strip() == "Aborted!"
    else:
        assert code == 128 + signal.SIGTERM and err == b""
    assert out.read_bytes() == PRECIOUS
    assert sorted(p.name for p in tmp_path.iterdir()) == before


def test_failed_run_in_a_real_process_keeps_the_old_file(tmp_path):
    """A job that fails after others were written: status 1, old file intact."""
    jobs = tmp_path / "jobs.yaml"
    good = (
        "  start: {quaternion_wxyz: [1, 0, 0, 0]}\n"
        "  end: {quaternion_wxyz: [0, 0, 0, 1], translation: [0, 0, 1]}\n"
    )
    jobs.write_text(f"- samples: 300000\n{good}- samples: 3\n  parameters: {{lam: 0.1}}\n{good}")
    out = tmp_path / "out.csv"
    out.write_bytes(PRECIOUS)
    result = subprocess.run(
        a2b_cmd("batch", jobs, "-o", out), capture_output=True, timeout=120, check=False
    )
    assert result.returncode == 1
    assert one_error_line(result.stderr).startswith("Error: job job1: ")
    assert out.read_bytes() == PRECIOUS
    assert sorted(p.name for p in tmp_path.iterdir()) == ["jobs.yaml", "out.csv"]


# -- bounded resources ------------------------------------------------------------------------

#: The peak resident memory a streaming run may reach: the interpreter with numpy (~35 MB)
#: and one chunk of 65 536 samples with its text (~120 MB).
RSS_LIMIT_MB = 300


def _peak_rss_mb(pid: int) -> float:
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) / 1024
    return 0.0


def _stream_through_head(args, nbytes: int):
    """``a2b ARGS | head -c NBYTES``: seconds to the first line, peak RSS (MB), status, stderr."""
    producer = subprocess.Popen(a2b_cmd(*args), stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    head = subprocess.Popen(
        ["head", "-c", str(nbytes)], stdin=producer.stdout, stdout=subprocess.PIPE
    )
    producer.stdout.close()  # head owns the pipe now
    start = time.monotonic()
    first = head.stdout.readline()
    to_first = time.monotonic() - start
    peak, received = 0.0, len(first)
    while True:
        block = head.stdout.read(1 << 20)
        if not block:
            break
        received += len(block)
        try:
            peak = max(peak, _peak_rss_mb(producer.pid))
        except FileNotFoundError:  # pragma: no cover - already gone
            break
    head.wait(timeout=60)
    _, err = producer.communicate(timeout=60)
    return first, to_first, peak, received, producer.returncode, err


@pytest.mark.slow
@linux_only
@pytest.mark.parametrize("fmt", ["csv", "mcap"])
def test_a_billion_samples_stream_in_bounded_memory(fmt):
    """``a2b interpolate --samples 1000000000 | head -c 80000000``."""
    nbytes = 80_000_000 if fmt == "csv" else 20_000_000
    first, to_first, peak, received, code, err = _stream_through_head(
        ["interpolate", QUARTER, "--samples", 1_000_000_000, "--format", fmt], nbytes
    )
    if fmt == "csv":
        assert first == b"t,tx,ty,tz,qw,qx,qy,qz\n"
    assert to_first < 10, to_first
    assert received == nbytes
    assert 0 < peak < RSS_LIMIT_MB, peak
    assert code == 0 and err == b""


@pytest.mark.slow
@linux_only
def test_a_billion_sample_job_streams_in_bounded_memory(tmp_path):
    first, to_first, peak, _, code, err = _stream_through_head(
        ["batch", big_jobs(tmp_path / "jobs.yaml", 1_000_000_000), "--format", "matrix"], 40_000_000
    )
    assert first.startswith(b"job,t,r11")
    assert to_first < 10 and 0 < peak < RSS_LIMIT_MB, (to_first, peak)
    assert code == 0 and err == b""


#: Runs a command and writes the peak resident memory (kB) of its children on fd ``argv[1]``.
_PEAK = (
    "import os, resource, subprocess, sys\n"
    "code = subprocess.run(sys.argv[2:]).returncode\n"
    "peak = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss\n"
    "os.write(int(sys.argv[1]), str(peak).encode())\n"
    "sys.exit(code)\n"
)


def _peak_of_run(args) -> tuple[float, subprocess.CompletedProcess]:
    """Peak resident memory (MB) of a whole ``a2b`` run, measured by a parent of its own (the
    kernel's count for the children of this test process would include earlier tests)."""
    return _peak_of_command(a2b_cmd(*args))


def _peak_of_command(argv) -> tuple[float, subprocess.CompletedProcess]:
    """Peak resident memory (MB) of a command, as :func:`_peak_of_run`."""
    read, write = os.pipe()
    try:
        done = subprocess.run(
            [sys.executable, "-c", _PEAK, str(write), *argv],
            capture_output=True,
            pass_fds=(write,),
        )
        os.close(write)
        write = None
        peak_kb = int(os.read(read, 64) or b"0")
    finally:
        os.close(read)
        if write is not None:
            os.close(write)
    assert peak_kb > 0, done.stderr.decode()
    return peak_kb / 1024, done


@pytest.mark.slow
@linux_only
def test_a_100_kb_job_name_keeps_batch_memory_bounded(tmp_path):
    """One job named with 100 kB among 300: memory stays bounded by the chunk size."""
    long_name = "n" * 100_000
    jobs = tmp_path / "jobs.jsonl"
    with open(jobs, "w") as f:
        for i in range(300):
            name = long_name if i == 150 else f"job{i}"
            f.write(
                json.dumps(
                    {
                        "name": name,
                        "start": {"quaternion_wxyz": [1, 0, 0, 0]},
                        "end": {"quaternion_wxyz": [0, 0, 0, 1], "translation": [1, 2, i]},
                    }
                )
                + "\n"
            )
    out = tmp_path / "out.csv"
    peak, done = _peak_of_run(["batch", jobs, "-o", out])
    assert done.returncode == 0, done.stderr.decode()
    assert peak < 150, peak
    with open(out, "rb") as f:
        rows = [line.split(b",", 1)[0] for line in f]
    assert len(rows) == 1 + 300 * 101
    assert rows.count(long_name.encode()) == 101


# -- user text in messages --------------------------------------------------------------------

HOSTILE = [
    "two\nlines",
    "Error: forged\r",
    "\x1b[31mred\x1b[0m",
    "bidi\u202eevil",
    "bell\x07",
    "tab\there",
]


@pytest.mark.parametrize("name", HOSTILE)
def test_a_job_name_reaches_stderr_escaped(tmp_path, name):
    job = {
        "name": name,
        "start": {"quaternion_wxyz": [1, 0, 0, 0]},
        "end": {"quaternion_wxyz": [0, 0, 0, 1], "translation": [0, 0, 1]},
        "parameters": {"lam": 1e-6},
    }
    path = tmp_path / "jobs.json"
    path.write_text(json.dumps([job]))
    done = subprocess.run(
        a2b_cmd("batch", path, "-o", tmp_path / "out.csv"), capture_output=True, timeout=60
    )
    assert done.returncode == 1
    err = done.stderr.decode()
    assert err.count("\n") == 1 and err.startswith("Error: job ")
    assert all(ch.isprintable() for ch in err[:-1]), repr(err)
    from a2b.errors import printable

    assert f"job {printable(name)}:" in err


@pytest.mark.parametrize("name", HOSTILE)
def test_a_file_name_in_a_usage_error_is_escaped(tmp_path, name):
    done = subprocess.run(a2b_cmd("interpolate", tmp_path / name), capture_output=True, timeout=60)
    assert done.returncode == 2
    last = done.stderr.decode().splitlines()[-1]
    assert last.startswith("Error: ") and "No such file or directory" in last
    assert all(ch.isprintable() for ch in last), repr(last)


def test_printable_escapes_only_what_is_not_printable():
    from a2b.errors import printable

    assert printable("Gelenk-ä 関節 a b") == "Gelenk-ä 関節 a b"
    assert printable("a\nb\x1b[0m\u202e\t") == "a\\nb\\x1b[0m\\u202e\\t"


# -- one number grammar -----------------------------------------------------------------------


@pytest.mark.parametrize("spelling", ["1_0", "١٠", "𝟙", "0x10", "inf", "-nan", "1e", "", "½"])
def test_options_take_only_decimal_numbers(spelling):
    from click.testing import CliRunner

    from a2b.cli import cli

    result = CliRunner().invoke(cli, ["interpolate", str(QUARTER), "--delta", spelling])
    assert result.exit_code == 2
    assert "is not a decimal number" in result.output


@pytest.mark.parametrize("spelling", ["1_0", "١٠", "1e3", "0x10", "10.0", "--5"])
def test_counts_take_only_decimal_digits(spelling):
    from click.testing import CliRunner

    from a2b.cli import cli

    result = CliRunner().invoke(cli, ["interpolate", str(QUARTER), "--samples", spelling])
    assert result.exit_code == 2
    assert "is not a whole number of decimal digits" in result.output


@pytest.mark.parametrize("spelling", ["2", "-0.5", ".5", "5.", "+1e-3", "1E+2", " 3 "])
def test_decimal_spellings_are_read_as_float_reads_them(spelling):
    from a2b.cli.options import FLOAT

    assert FLOAT.convert(spelling, None, None) == float(spelling)


# -- memory for long names, long frame ids and many controls --------------------------------

MEGABYTE_NAME = "n" * 1_000_000
MEMORY_CAP_MB = 200


def _jobs_with_a_long_name(path: Path) -> Path:
    with open(path, "w") as f:
        for i in range(20):
            job = {
                "name": MEGABYTE_NAME if i == 10 else f"job{i}",
                "start": {"quaternion_wxyz": [1, 0, 0, 0]},
                "end": {"quaternion_wxyz": [0, 0, 0, 1], "translation": [1, 2, i]},
            }
            f.write(json.dumps(job) + "\n")
    return path


@pytest.mark.slow
@linux_only
@pytest.mark.parametrize("fmt", ["csv", "mcap"])
def test_a_1_mb_job_name_stays_under_the_memory_cap(tmp_path, fmt):
    jobs = _jobs_with_a_long_name(tmp_path / "jobs.jsonl")
    out = tmp_path / f"out.{fmt}"
    peak, done = _peak_of_run(["batch", jobs, "--format", fmt, "-o", out])
    assert done.returncode == 0, done.stderr.decode()[:500]
    assert peak < MEMORY_CAP_MB, peak
    if fmt == "csv":
        with open(out, "rb") as f:
            names = [line.split(b",", 1)[0] for line in f]
        assert names.count(MEGABYTE_NAME.encode()) == 101 and len(names) == 1 + 20 * 101


#: The longest single argument Linux passes to a program (MAX_ARG_STRLEN is 128 kB).
LONGEST_ARGUMENT = "f" * (128 * 1024 - 1)

#: Writes 1,000 poses as MCAP with a 1 MB frame id and child frame id, through the library.
_MCAP_WITH_LONG_FRAMES = """
import sys
import numpy as np
import a2b
motion = a2b.motion(np.eye(4), np.eye(4))
a2b.write(motion, sys.argv[1], "mcap", samples=1_000, frame_id="w" * 1_000_000,
          child_frame_id="c" * 1_000_000)
"""  # fmt: skip


@pytest.mark.slow
@linux_only
@pytest.mark.parametrize("option", ["--frame-id", "--child-frame-id"])
def test_the_longest_frame_id_a_shell_passes_stays_under_the_memory_cap(tmp_path, option):
    from mcap.reader import make_reader

    out = tmp_path / "out.mcap"
    args = ["interpolate", QUARTER, "--samples", 10_000, "--format", "mcap", option]
    peak, done = _peak_of_run([*args, LONGEST_ARGUMENT, "-o", out])
    assert done.returncode == 0, done.stderr.decode()[:500]
    assert peak < MEMORY_CAP_MB, peak
    with open(out, "rb") as f:
        assert make_reader(f).get_summary().statistics.message_count == 20_000


@pytest.mark.slow
@linux_only
def test_a_1_mb_frame_id_stays_under_the_memory_cap(tmp_path):
    from mcap.reader import make_reader

    out = tmp_path / "out.mcap"
    peak, done = _peak_of_command([sys.executable, "-c", _MCAP_WITH_LONG_FRAMES, str(out)])
    assert done.returncode == 0, done.stderr.decode()[:500]
    assert peak < MEMORY_CAP_MB, peak
    with open(out, "rb") as f:
        reader = make_reader(f)
        assert reader.get_summary().statistics.message_count == 2_000
        _, _, message = next(reader.iter_messages())
        assert json.loads(message.data)["frame_id"] == "w" * 1_000_000


@pytest.mark.slow
@linux_only
def test_200_bezier_controls_stay_under_the_memory_cap(tmp_path):
    rng = np.random.default_rng(7)
    controls = []
    for _ in range(200):
        quaternion = np.array([1.0, 0, 0, 0]) + 0.3 * rng.normal(size=4)
        controls.append(
            {"quaternion_wxyz": quaternion.tolist(), "translation": rng.normal(size=3).tolist()}
        )
    path = tmp_path / "controls.json"
    path.write_text(json.dumps({"controls": controls}))
    out = tmp_path / "out.csv"
    peak, done = _peak_of_run(["bezier", path, "--samples", 100_000, "-o", out])
    assert done.returncode == 0, done.stderr.decode()[:500]
    assert peak < MEMORY_CAP_MB, peak
    rows = out.read_text().splitlines()
    assert len(rows) == 100_001
    first = np.array(rows[1].split(","), dtype=float)
    quat, trans = controls[0]["quaternion_wxyz"], controls[0]["translation"]
    np.testing.assert_allclose(first[1:4], trans, atol=1e-12)
    np.testing.assert_allclose(np.abs(first[4:] @ quat) / np.linalg.norm(quat), 1, atol=1e-12)


# -- closed and failing streams ---------------------------------------------------------------


def test_closed_stdout_is_one_error_line():
    err_r, err_w = os.pipe()
    done = subprocess.run(
        a2b_cmd("interpolate", QUARTER),
        stderr=err_w,
        timeout=60,
        preexec_fn=lambda: os.close(1),
    )
    os.close(err_w)
    err = os.read(err_r, 65536)
    os.close(err_r)
    assert done.returncode == 1
    assert err == b"Error: cannot write standard output: it is closed (give -o FILE)\n"


def test_closed_stdout_does_not_matter_with_o(tmp_path):
    out = tmp_path / "out.csv"
    done = subprocess.run(
        a2b_cmd("interpolate", QUARTER, "--samples", 3, "-o", out),
        stderr=subprocess.PIPE,
        timeout=60,
        preexec_fn=lambda: os.close(1),
    )
    assert done.returncode == 0, done.stderr
    assert len(out.read_text().splitlines()) == 4


@pytest.mark.parametrize("args", [["interpolate", "-"], ["interpolate", QUARTER, "--through", "-"]])
def test_closed_stdin_is_a_usage_error(args):
    done = subprocess.run(
        a2b_cmd(*args), capture_output=True, timeout=60, preexec_fn=lambda: os.close(0)
    )
    assert done.returncode == 2
    assert b"standard input is closed" in done.stderr and b"Traceback" not in done.stderr


@linux_only
def test_a_read_error_is_one_error_line():
    """Reading /proc/self/mem at offset 0 fails with EIO."""
    done = subprocess.run(a2b_cmd("interpolate", "/proc/self/mem"), capture_output=True, timeout=60)
    assert done.returncode == 1
    assert done.stderr == b"Error: cannot read an input file: Input/output error\n"


# -- YAML 1.2 core schema, exactly ------------------------------------------------------------

POSES_YAML = "start: {quaternion_wxyz: [1, 0, 0, 0]}\nend: {quaternion_wxyz: [0, 0, 0, 1]}\n"


@pytest.mark.parametrize(
    "line, message",
    [
        ("x: !!set {a, b}", "3:4: invalid YAML: the tag !!set is not read by a2b"),
        ("x: !!timestamp 2001-01-01", "3:4: invalid YAML: the tag !!timestamp is not read"),
        ("x: !!binary aGVsbG8=", "3:4: invalid YAML: the tag !!binary is not read"),
        ("x: !!omap [a: 1]", "3:4: invalid YAML: the tag !!omap is not read"),
        ("x: !local 1", "3:4: invalid YAML: the tag !local is not read"),
        ("x: !!python/name:os.system", "3:4: invalid YAML: the tag !!python/name:os.system"),
        ("x: !!bool maybe", "3:4: invalid YAML: cannot read 'maybe' as true or false"),
        (
            "samples: 2001-02-30",
            "3:1: samples: expected a whole number of samples, at least 2, got the string "
            "'2001-02-30'",
        ),
        ("samples: yes", "got the string 'yes'"),
        ("samples: 1_000", "got the string '1_000'"),
        ("mode: =", "mode: expected one of darboux, cubic, screw, got the string '='"),
        ("<<: {samples: 3}", "3:1: <<: unknown key '<<'"),
        ("samples: 0x" + "F" * 5000, "got a number too large for a double"),
        ("samples: " + "9" * 5000, "got a number too large for a double"),
    ],
)
def test_yaml_is_the_1_2_core_schema(tmp_path, line, message):
    from a2b.errors import InputFileError
    from a2b.io.poseschema import read_poses

    path = tmp_path / "p.yaml"
    path.write_text(POSES_YAML + line + "\n")
    with open(path, "rb") as f, pytest.raises(InputFileError) as caught:
        read_poses(f, "p.yaml")
    assert message in str(caught.value)
    assert str(caught.value).startswith("p.yaml:")


@pytest.mark.parametrize(
    "written", ["007", "7", "true", "null", "0x1F", "1e3", "2024-01-01", "=", "1_0"]
)
def test_a_job_name_is_the_text_as_written(tmp_path, written):
    from a2b.io.jobfiles import read_jobs

    path = tmp_path / "jobs.yaml"
    path.write_text(
        f"- name: {written}\n" + "".join("  " + ln + "\n" for ln in POSES_YAML.splitlines())
    )
    with open(path, "rb") as f:
        (job,) = list(read_jobs(f, "jobs.yaml"))
    assert job.name == written


def test_explicitly_tagged_core_scalars_are_read():
    import io

    from a2b.io.poseschema import read_poses

    text = POSES_YAML + "samples: !!int 0x1F\nparameters: {delta: !!float 2}\n"
    job = read_poses(io.BytesIO(text.encode()), "p.yaml")
    assert job.samples == 31 and job.parameters == {"delta": 2.0}


# -- homogeneous inputs of any scale ----------------------------------------------------------


@pytest.mark.parametrize("scale", [1e-300, 1e-200, 1e-100, 1.0, 1e100, 1e200, 1e300])
def test_quaternions_study_parameters_m_and_weights_of_any_scale(scale):
    """Homogeneous inputs are scaled before use: any finite non-zero multiple is the same."""
    import a2b
    from a2b.io.poseschema import read_poses
    from a2b.motions.bezier import bezier

    def pose(**form):
        text = json.dumps({"start": {"quaternion_wxyz": [1, 0, 0, 0]}, "end": form})
        return read_poses(io.BytesIO(text.encode()), "p.json").end

    identity = np.eye(4)
    assert np.array_equal(
        pose(quaternion_wxyz=[5e-324 if scale < 1 else 1.7e308, 0, 0, 0]), identity
    )
    c, s = math.cos(0.4), math.sin(0.4)
    expected = pose(quaternion_wxyz=[c, 0, 0, s], translation=[1, 2, 3])
    got = pose(quaternion_wxyz=[c * scale, 0, 0, s * scale], translation=[1, 2, 3])
    np.testing.assert_allclose(got, expected, rtol=0, atol=1e-15)
    from a2b.poses import study_from_matrices

    study = study_from_matrices(expected) * scale
    np.testing.assert_allclose(pose(study=study.tolist()), expected, rtol=0, atol=1e-14)
    start = np.eye(4)
    m = np.array([1.0, 0.2, -0.3, 0.5])
    plain = a2b.motion(start, expected, "cubic", m=m).matrices(np.linspace(0, 1, 5))
    scaled = a2b.motion(start, expected, "cubic", m=m * scale).matrices(np.linspace(0, 1, 5))
    np.testing.assert_allclose(scaled, plain, rtol=0, atol=1e-13)
    weights = np.array([1.0, 2.0])
    plain = bezier([start, expected], 5, weights=weights)
    np.testing.assert_allclose(
        bezier([start, expected], 5, weights=weights * scale), plain, atol=1e-13
    )


def test_a_non_finite_key_is_named_as_written(tmp_path):
    path = tmp_path / "k.yaml"
    path.write_text(POSES_YAML + ".nan: 1\n")
    done = subprocess.run(a2b_cmd("interpolate", path), capture_output=True, timeout=60)
    assert done.returncode == 1
    assert b"k.yaml:3:1: .nan: unknown key .nan in a poses file" in done.stderr
    assert b"object at 0x" not in done.stderr


@pytest.mark.parametrize("start_time, samples", [(1e17, 3), (1.7e9, 10_000_000)])
def test_tum_times_that_a_double_cannot_tell_apart_are_refused(tmp_path, start_time, samples):
    out = tmp_path / "out.tum"
    args = ["--format", "tum", "--start-time", start_time, "--samples", samples, "-o", out]
    done = subprocess.run(a2b_cmd("interpolate", QUARTER, *args), capture_output=True, timeout=60)
    assert done.returncode == 1
    assert b"cannot tell apart" in done.stderr and not out.exists()


def test_tum_times_of_a_unix_epoch_are_distinct(tmp_path):
    out = tmp_path / "out.tum"
    args = ["--format", "tum", "--start-time", 1.7e9, "--samples", 1000, "-o", out]
    done = subprocess.run(a2b_cmd("interpolate", QUARTER, *args), capture_output=True, timeout=60)
    assert done.returncode == 0, done.stderr
    times = [float(line.split()[0]) for line in out.read_text().splitlines()[1:]]
    assert len(set(times)) == 1000 and times == sorted(times)


@pytest.mark.parametrize("size", ["1e308", "1e101"])
def test_body_points_too_large_to_draw_are_one_error(tmp_path, size):
    pytest.importorskip("matplotlib", reason="a2b plot needs the plot extra")
    points = ",".join([size] * 3)
    out = tmp_path / "p.png"
    done = subprocess.run(
        a2b_cmd("plot", QUARTER, "--points", points, "-o", out), capture_output=True, timeout=120
    )
    assert done.returncode == 1
    assert done.stderr.startswith(b"Error: the drawing reaches coordinates of")
    assert not out.exists()


def test_fiber_with_an_m_of_1e78_is_one_error_line():
    done = subprocess.run(
        a2b_cmd("fiber", SAMPLES / "pose.yaml", "--map", "mu", "--m", "1,1e78,1,1"),
        capture_output=True,
        timeout=60,
    )
    assert done.returncode in (0, 1), done.stderr
    assert b"Traceback" not in done.stderr
    if done.returncode == 1:
        assert done.stderr.count(b"\n") == 1 and done.stderr.startswith(b"Error: ")


def test_1100_bezier_controls_need_no_recursion():
    """1,100 controls gave RecursionError; the singularity search is a loop now."""
    import a2b
    from a2b.poses import matrices_from_quat_trans

    rng = np.random.default_rng(3)
    quats = np.array([1.0, 0, 0, 0]) + 0.3 * rng.normal(size=(1100, 4))
    poses = matrices_from_quat_trans(quats, rng.normal(size=(1100, 3)))
    samples = a2b.bezier(poses, 50, space="study")
    assert samples.shape == (50, 4, 4) and np.isfinite(samples).all()
    np.testing.assert_allclose(samples[0], poses[0], atol=1e-12)
    np.testing.assert_allclose(samples[-1], poses[-1], atol=1e-12)


@pytest.mark.parametrize("suffix", ["json", "jsonl"])
def test_a_json_job_name_of_true_is_no_name(tmp_path, suffix):
    """JSON `true` would become the name "True", which is not the text as written."""
    job = (
        '{"name": true, "start": {"quaternion_wxyz": [1, 0, 0, 0]}, '
        '"end": {"quaternion_wxyz": [1, 0, 0, 0]}}'
    )
    path = tmp_path / f"jobs.{suffix}"
    path.write_text(f"[{job}]\n" if suffix == "json" else job + "\n")
    done = subprocess.run(a2b_cmd("batch", path), capture_output=True, timeout=60)
    assert done.returncode == 1
    assert b"name: expected a string, got the boolean true" in done.stderr


# -- the tables of describe and fiber, and the help, on a closed pipe or a full disk ----------

TABLES = [("describe", QUARTER), ("fiber", SAMPLES / "pose.yaml")]


@pytest.mark.parametrize("command, sample", TABLES)
def test_a_table_into_a_closed_pipe_ends_quietly_with_status_0(command, sample):
    """rich ends a closed pipe with status 1 on its own; a2b's tables end like every command."""
    producer = subprocess.Popen(a2b_cmd(command, sample), stdout=subprocess.PIPE,
                                stderr=subprocess.PIPE)  # fmt: skip
    producer.stdout.close()  # nobody reads: the first write meets a closed pipe
    _, err = producer.communicate(timeout=60)
    assert producer.returncode == 0 and err == b"", err.decode()[-2000:]


@pytest.mark.skipif(not Path("/dev/full").exists(), reason="needs /dev/full")
@pytest.mark.parametrize(
    "args",
    [*[(c, s) for c, s in TABLES], *[(c, s, "--json") for c, s in TABLES], ("--help",),
     ("--version",)],
)  # fmt: skip
def test_a_table_json_or_help_on_a_full_disk_is_one_line_of_writing(args):
    with open("/dev/full", "wb") as full:
        result = subprocess.run(a2b_cmd(*args), stdout=full, stderr=subprocess.PIPE,
                                timeout=60, check=False)  # fmt: skip
    assert result.returncode == 1
    assert (
        one_error_line(result.stderr)
        == "Error: cannot write standard output: No space left on device"
    )
