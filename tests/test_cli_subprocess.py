"""Real processes and real pipes: what CliRunner hides.

Non-seekable stdout for MCAP, a reader that closes the pipe early, Ctrl-C and SIGTERM in the
middle of a write, and how little ``a2b --help`` and ``a2b --version`` import.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import a2b
from a2b.formats import OUTPUT_NAMES
from a2b.io import mcapposes, poseschema

ROOT = Path(__file__).resolve().parent.parent
A2B = [sys.executable, "-c", "from a2b.cli import cli; cli(prog_name='a2b')"]
QUARTER = ROOT / "samples" / "quarter-turn.yaml"


def a2b_cmd(*args):
    return A2B + [str(a) for a in args]


def test_mcap_into_a_pipe(tmp_path):
    """``a2b interpolate ... --format mcap | cat > x.mcap``: stdout is a pipe, not seekable."""
    from mcap.reader import make_reader

    out = tmp_path / "x.mcap"
    with open(out, "wb") as sink:
        producer = subprocess.Popen(
            a2b_cmd("interpolate", QUARTER, "--format", "mcap", "--samples", 50),
            stdout=subprocess.PIPE,
        )
        consumer = subprocess.Popen(["cat"], stdin=producer.stdout, stdout=sink)
        producer.stdout.close()
        assert producer.wait(timeout=60) == 0
        assert consumer.wait(timeout=60) == 0
    with open(out, "rb") as f:
        reader = make_reader(f)
        summary = reader.get_summary()
        counts = {
            summary.channels[i].topic: n
            for i, n in summary.statistics.channel_message_counts.items()
        }
        schemas = {
            summary.channels[i].topic: summary.schemas[summary.channels[i].schema_id].name
            for i in summary.channels
        }
    assert counts == {"/a2b/pose": 50, "/tf": 50}
    assert schemas == {"/a2b/pose": "foxglove.PoseInFrame", "/tf": "foxglove.FrameTransform"}
    assert summary.chunk_indexes and not summary.attachment_indexes and not summary.metadata_indexes
    with open(QUARTER, "rb") as f:
        job = poseschema.read_poses(f)
    ts = np.linspace(0, 1, 50)
    want_quat, want_trans = a2b.motion(*job.poses()).quat_trans(ts)
    with open(out, "rb") as f:
        time_, quat, trans = mcapposes.read_mcap(f)
    assert np.allclose(time_, ts, atol=1e-9, rtol=0)
    assert np.array_equal(quat, want_quat) and np.array_equal(trans, want_trans)
    # every message is valid JSON with the schema's required keys
    with open(out, "rb") as f:
        for schema, channel, message in make_reader(f).iter_messages():
            required = json.loads(schema.data)["required"]
            assert set(required) <= set(json.loads(message.data))


def test_closed_pipe_ends_quietly():
    """``a2b interpolate ... | head -n 2``: no BrokenPipeError noise, exit status 0."""
    producer = subprocess.Popen(
        a2b_cmd("interpolate", QUARTER, "--samples", 300000),
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
    )
    first = producer.stdout.readline()
    producer.stdout.close()  # the reader goes away
    _, err = producer.communicate(timeout=120)
    assert first == b"t,tx,ty,tz,qw,qx,qy,qz\n"
    assert err == b""
    assert producer.returncode == 0


def _interrupt(tmp_path, sig):
    out = tmp_path / "big.csv"
    proc = subprocess.Popen(
        a2b_cmd("interpolate", QUARTER, "--samples", 20_000_000, "-o", out),
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
    )
    deadline = time.monotonic() + 60
    while not any(p.name.endswith(".tmp") for p in tmp_path.iterdir()):  # writing has started
        assert time.monotonic() < deadline and proc.poll() is None
        time.sleep(0.02)
    time.sleep(0.2)
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=60)
    return proc.returncode, err, sorted(p.name for p in tmp_path.iterdir())


@pytest.mark.slow
def test_ctrl_c_leaves_no_file(tmp_path):
    code, err, left = _interrupt(tmp_path, signal.SIGINT)
    assert code == 1 and b"Aborted" in err and b"Traceback" not in err
    assert left == []


TERMINATING = ["SIGTERM", "SIGHUP", "SIGQUIT", "SIGUSR1", "SIGUSR2", "SIGALRM", "SIGPIPE"]


@pytest.mark.parametrize("name", TERMINATING)
def test_every_terminating_signal_leaves_no_file(tmp_path, name):
    sig = getattr(signal, name)
    code, err, left = _interrupt(tmp_path, sig)
    assert code == 128 + sig
    assert b"Traceback" not in err
    assert left == []


def test_error_exit_codes_in_a_real_process(tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text("start: {quaternion_wxyz: [1, 0, 0]}\nend: {quaternion_wxyz: [1, 0, 0, 0]}\n")
    result = subprocess.run(
        a2b_cmd("interpolate", bad), capture_output=True, timeout=60, check=False
    )
    assert result.returncode == 1
    assert result.stdout == b""
    assert result.stderr.decode().splitlines() == [
        f"Error: {bad}:1:9: start.quaternion_wxyz: expected 4 numbers (w, x, y, z), got 3"
    ]
    result = subprocess.run(
        a2b_cmd("interpolate", bad, "--format", "png"), capture_output=True, timeout=60, check=False
    )
    assert result.returncode == 2


@pytest.mark.parametrize("args", [["--version"], ["--help"], ["-h"]])
def test_help_and_version_import_nothing_heavy(args):
    """The lazy group keeps numpy, rich, yaml and mcap out of ``a2b --help`` and ``--version``."""
    code = (
        "import sys\n"
        "from a2b.cli import cli\n"
        "try:\n"
        f"    cli({args!r}, prog_name='a2b')\n"
        "except SystemExit:\n"
        "    pass\n"
        "heavy = [m for m in ('numpy', 'rich', 'yaml', 'mcap', 'a2b.api', 'a2b.poses') if m in "
        "sys.modules]\n"
        "print(heavy, file=sys.stderr)\n"
    )
    result = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, timeout=60, text=True, check=False
    )
    assert result.stderr.strip() == "[]"


def test_version_is_fast():
    """Whole-process ``a2b --version`` costs no more than ``python -c 'import numpy'`` (1.3x, with
    slack for a busy machine); the best of a few runs of each."""

    def best(cmd, n=5):
        times = []
        for _ in range(n):
            start = time.perf_counter()
            subprocess.run(cmd, capture_output=True, check=True, timeout=60)
            times.append(time.perf_counter() - start)
        return min(times)

    numpy_time = best([sys.executable, "-c", "import numpy"])
    version_time = best(a2b_cmd("--version"))
    assert version_time <= 1.3 * numpy_time + 0.05, (version_time, numpy_time)


def test_entry_point_installed():
    """The ``a2b`` script of ``[project.scripts]`` runs (when a2b is installed)."""
    from shutil import which

    exe = which("a2b")
    if exe is None:
        pytest.skip("a2b is not installed as a script")
    result = subprocess.run(
        [exe, "--version"],
        capture_output=True,
        text=True,
        timeout=60,
        env={**os.environ},
        check=False,
    )
    assert result.returncode == 0 and result.stdout.startswith("a2b ")


def test_shell_completion_of_commands_and_formats():
    env = {
        **os.environ,
        "_A2B_COMPLETE": "bash_complete",
        "COMP_WORDS": "a2b inter",
        "COMP_CWORD": "1",
    }
    result = subprocess.run(A2B, capture_output=True, text=True, env=env, timeout=60, check=False)
    assert result.stdout.split() == ["plain,interpolate"]
    env.update(COMP_WORDS="a2b interpolate x --format ", COMP_CWORD="4")
    result = subprocess.run(A2B, capture_output=True, text=True, env=env, timeout=60, check=False)
    assert result.stdout.split() == [f"plain,{f}" for f in OUTPUT_NAMES]


def _job_line(i, quaternion="[1, 0, 0, 0]"):
    return (
        f'{{"name": "j{i}", "start": {{"quaternion_wxyz": {quaternion}, "translation": [{i}, 0, '
        f"0]}}, "
        f'"end": {{"quaternion_wxyz": [0, 0, 0, 1], "translation": [0, {i}, 1]}}}}\n'
    )


def _children(pid):
    found = subprocess.run(["pgrep", "-P", str(pid)], capture_output=True, text=True).stdout
    return [int(p) for p in found.split()]


def _alive(pid):
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().rpartition(")")[2].split()[0] != "Z"
    except OSError:
        return False


@pytest.mark.parametrize(
    "bad, message",
    [
        ("[1, 0, 0]", "expected 4 numbers"),
        ("[NaN, 0, 0, 1]", "NaN is not allowed"),
        ("[0, 0, 0, 0]", "norm 0"),
        ("[1, 0, 0, true]", "quaternion"),
    ],
)
def test_batch_reports_a_bad_job_at_once_while_its_input_stays_open(tmp_path, bad, message):
    """JSON Lines from a pipe that is still open: the error of a line of a wrong form or with
    a number that cannot be right comes as soon as the line arrives (not when its block is
    complete or the input ends), no file is written, and the helper that scans the jobs is
    gone with the main process."""
    out = tmp_path / "never.csv"
    proc = subprocess.Popen(
        a2b_cmd("batch", "-", "-o", out), stdin=subprocess.PIPE, stderr=subprocess.PIPE
    )
    try:
        lines = [_job_line(i) for i in range(20)] + [_job_line(20, bad)]
        proc.stdin.write("".join(lines).encode())
        proc.stdin.flush()
        time.sleep(0.3)
        helpers = _children(proc.pid)
        rc = proc.wait(timeout=20)
        assert rc == 1
        err = proc.stderr.read().decode()
        assert "<stdin>:21:" in err and message in err
        assert not out.exists()
        time.sleep(0.2)
        assert not any(_alive(pid) for pid in helpers)
    finally:
        proc.stdin.close()
        if proc.poll() is None:
            proc.kill()
            proc.wait()
