"""What every section of the benchmarks shares: the results table, the machine, interleaved
timing of calls and of whole processes, and the poses and pairs they run on."""

from __future__ import annotations

import compileall
import datetime
import gc
import os
import platform
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

import a2b
from a2b.poses import matrices_from_quat_trans, study_from_matrices

# ------------------------------------------------------------------------------------------
# reporting
# ------------------------------------------------------------------------------------------


@dataclass
class Row:
    """One line of the results table."""

    section: str
    what: str
    figure: str
    ratio: str = ""
    target: str = ""
    met: bool | None = None

    def cells(self) -> list[str]:
        met = {True: "yes", False: "NO", None: ""}[self.met]
        return [self.section, self.what, self.figure, self.ratio, self.target, met]


HEADERS = ["section", "measurement", "figure", "ratio", "target", "met"]


def text_table(rows: list[Row]) -> str:
    cells = [HEADERS] + [r.cells() for r in rows]
    widths = [max(len(c[i]) for c in cells) for i in range(len(HEADERS))]
    lines = ["  ".join(c.ljust(w) for c, w in zip(cells[0], widths))]
    lines.append("  ".join("-" * w for w in widths))
    lines += ["  ".join(c.ljust(w) for c, w in zip(line, widths)) for line in cells[1:]]
    return "\n".join(lines)


def markdown_table(rows: list[Row]) -> str:
    lines = ["| " + " | ".join(HEADERS) + " |", "|" + " --- |" * len(HEADERS)]
    lines += ["| " + " | ".join(c.replace("|", "\\|") for c in r.cells()) + " |" for r in rows]
    return "\n".join(lines)


def rate(count: float, seconds: float) -> str:
    per_second = count / seconds
    if per_second >= 1e6:
        return f"{per_second / 1e6:.2f} M/s"
    if per_second >= 1e3:
        return f"{per_second / 1e3:.1f} k/s"
    return f"{per_second:.0f} /s"


def log(message: str) -> None:
    print(message, file=sys.stderr, flush=True)


# ------------------------------------------------------------------------------------------
# the machine
# ------------------------------------------------------------------------------------------


def machine() -> dict[str, str]:
    """CPU, cores, memory, Python, numpy and its BLAS (threadpoolctl), date, BLAS variables."""
    cpu = platform.processor() or platform.machine()
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    memory = ""
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemTotal"):
                memory = f"{int(line.split()[1]) / 2**20:.1f} GiB"
    except OSError:
        pass
    try:
        from threadpoolctl import threadpool_info

        blas = "; ".join(
            f"{i.get('internal_api')} {i.get('version')} kernel {i.get('architecture')}, "
            f"{i.get('num_threads')} threads"
            for i in threadpool_info()
            if i.get("user_api") == "blas"
        )
    except ImportError:
        blas = "threadpoolctl not installed"
    variables = ", ".join(
        f"{name}={os.environ[name]}"
        for name in ("OPENBLAS_CORETYPE", "OPENBLAS_L2_SIZE")
        if name in os.environ
    )
    return {
        "CPU": cpu,
        "cores": str(os.cpu_count()),
        "memory": memory,
        "Python": platform.python_version(),
        "numpy": np.__version__,
        "BLAS": blas or "unknown",
        "OPENBLAS_* variables": variables or "unset",
        "date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
        "load average (1 min) at start": f"{os.getloadavg()[0]:.2f}",
    }


# ------------------------------------------------------------------------------------------
# timing
# ------------------------------------------------------------------------------------------


def interleaved(cases: dict[str, Callable[[], object]], repeats: int) -> dict[str, float]:
    """Median seconds of each case; repeats interleaved, the order rotated every round."""
    times: dict[str, list[float]] = {name: [] for name in cases}
    names = list(cases)
    for round_ in range(repeats):
        order = names[round_ % len(names) :] + names[: round_ % len(names)]
        for name in order:
            gc.collect()
            start = time.perf_counter()
            result = cases[name]()
            times[name].append(time.perf_counter() - start)
            del result
    return {name: statistics.median(values) for name, values in times.items()}


#: Reports the peak RSS of its child in KiB. A child's ``ru_maxrss`` from ``wait4`` here would
#: count this (large) process too: Linux starts the child's high-water mark from the memory of
#: the process that forked it. A small launcher in between keeps the figure honest.
_RSS_LAUNCHER = (
    "import os, subprocess, sys; p = subprocess.Popen(sys.argv[2:]); "
    "_, status, usage = os.wait4(p.pid, 0); open(sys.argv[1], 'w').write(str(usage.ru_maxrss)); "
    "sys.exit(os.waitstatus_to_exitcode(status))"
)


def run_process(argv: list[str], rss: bool = False) -> tuple[float, int]:
    """Wall-clock seconds of one whole process and, with ``rss``, its peak resident bytes.

    The peak comes from GNU time (``/usr/bin/time -f %M``), else from a small Python launcher
    whose own few MiB are then included.
    """
    with tempfile.TemporaryFile() as err, tempfile.NamedTemporaryFile("r") as report:
        if rss and os.access("/usr/bin/time", os.X_OK):
            argv = ["/usr/bin/time", "-f", "%M", "-o", report.name] + argv
        elif rss:
            argv = [sys.executable, "-c", _RSS_LAUNCHER, report.name] + argv
        start = time.perf_counter()
        proc = subprocess.run(
            argv, check=False, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=err
        )
        seconds = time.perf_counter() - start
        if proc.returncode != 0:
            err.seek(0)
            raise RuntimeError(
                f"{' '.join(argv)} exited {proc.returncode}: {err.read().decode()[-2000:]}"
            )
        peak = int(report.read().split()[-1]) * 1024 if rss else 0
    return seconds, peak


def interleaved_processes(
    commands: dict[str, list[str]],
    repeats: int,
    rss: bool = False,
    outputs: dict[str, Path] | None = None,
) -> dict[str, tuple[float, int]]:
    """Median wall-clock seconds and largest peak RSS of each command, repeats interleaved.

    ``outputs`` names each command's output file, removed (untimed) before every run, so that
    a run writes a new file instead of first releasing the previous run's.
    """
    times: dict[str, list[float]] = {name: [] for name in commands}
    peaks: dict[str, int] = {name: 0 for name in commands}
    names = list(commands)
    for round_ in range(repeats):
        for name in names[round_ % len(names) :] + names[: round_ % len(names)]:
            if outputs and name in outputs:
                if outputs[name].is_dir():  # rosbags writes a bag directory
                    shutil.rmtree(outputs[name])
                outputs[name].unlink(missing_ok=True)
            seconds, peak = run_process(commands[name], rss)
            times[name].append(seconds)
            peaks[name] = max(peaks[name], peak)
    return {name: (statistics.median(times[name]), peaks[name]) for name in names}


def compile_bytecode() -> None:
    """Write the ``.pyc`` files of the imported ``a2b`` package, untimed, before any timing.

    pip compiles them when it installs the package. An editable or development checkout does
    not, and with PYTHONDONTWRITEBYTECODE set importing never writes them either, so every
    ``a2b`` process timed here would compile its modules from source again: tens of
    milliseconds that a user's install does not pay. ``compileall`` writes them regardless of
    that variable, where the child processes (same environment) look for them.
    """
    package = Path(a2b.__file__).resolve().parent
    ok = compileall.compile_dir(package, quiet=1)
    failed = "" if ok else "; some modules failed, see above"
    log(f"compiled the bytecode of {package} (untimed), as pip does at install{failed}")


def a2b_command() -> list[str] | None:
    """The ``a2b`` console script that pip installed beside this Python, as users run it.

    Found beside ``sys.executable`` first, so that a version manager's shim on PATH (pyenv's is
    a shell script) does not add its own start-up time.
    """
    beside = Path(sys.executable).with_name("a2b")
    if beside.is_file() and os.access(beside, os.X_OK):
        return [str(beside)]
    exe = shutil.which("a2b")
    return [exe] if exe else None


# ------------------------------------------------------------------------------------------
# the poses
# ------------------------------------------------------------------------------------------


def test_poses() -> tuple[np.ndarray, np.ndarray]:
    """Two fixed generic poses: a 2.2 rad turn about a skew axis with a slide."""
    start = matrices_from_quat_trans([0.9, -0.2, 0.3, 0.25], [0.4, -1.1, 0.7])
    end = matrices_from_quat_trans([-0.1, 0.6, 0.5, 0.6], [1.9, 0.8, -0.6])
    return start, end


def poses_document(start: np.ndarray, end: np.ndarray) -> dict:
    return {"start": {"matrix": start.tolist()}, "end": {"matrix": end.tolist()}}


# ------------------------------------------------------------------------------------------
# the plain-NumPy reference and the peers
# ------------------------------------------------------------------------------------------


def _numerators(h: np.ndarray) -> np.ndarray:
    """The 12 entries of ``[R | t]`` times ``|p|²``, and ``|p|²``, of a Study vector ``(8,)``.

    ``R |p|²`` is quadratic in p; ``t |p|² = −2 vec(q p̃)`` for ``q = −½ t p``.
    """
    p0, p1, p2, p3, q0, q1, q2, q3 = h
    rot = [
        [p0 * p0 + p1 * p1 - p2 * p2 - p3 * p3, 2 * (p1 * p2 - p0 * p3), 2 * (p1 * p3 + p0 * p2)],
        [2 * (p1 * p2 + p0 * p3), p0 * p0 - p1 * p1 + p2 * p2 - p3 * p3, 2 * (p2 * p3 - p0 * p1)],
        [2 * (p1 * p3 - p0 * p2), 2 * (p2 * p3 + p0 * p1), p0 * p0 - p1 * p1 - p2 * p2 + p3 * p3],
    ]
    # vec(q p̃) with p̃ = (p0, −p1, −p2, −p3)
    qp = [
        -q0 * p1 + q1 * p0 - q2 * p3 + q3 * p2,
        -q0 * p2 + q1 * p3 + q2 * p0 - q3 * p1,
        -q0 * p3 - q1 * p2 + q2 * p1 + q3 * p0,
    ]
    out = []
    for i in range(3):
        out += rot[i] + [-2.0 * qp[i]]
    return np.array(out + [p0 * p0 + p1 * p1 + p2 * p2 + p3 * p3])


def reference_coefficients(start: np.ndarray, end: np.ndarray) -> np.ndarray:
    """``C`` ``(3, 13)``: monomial coefficients of the 12 numerators and the denominator of the
    line ``h(t) = (1 − t) hA + t hB`` of unit Study vectors (``pA·pB ≥ 0``), mapped by κ.

    ``F(h)`` is quadratic, so ``F(h(t)) = (1−t)² F(hA) + 2t(1−t) B + t² F(hB)`` with the polar
    form ``B = (F(hA + hB) − F(hA) − F(hB)) / 2``.
    """
    h_a, h_b = study_from_matrices(np.stack([start, end]))
    if h_a[:4] @ h_b[:4] < 0:
        h_b = -h_b
    f_a, f_b = _numerators(h_a), _numerators(h_b)
    polar = 0.5 * (_numerators(h_a + h_b) - f_a - f_b)
    return np.stack([f_a, 2.0 * (polar - f_a), f_a - 2.0 * polar + f_b])


def reference_matrices(ts: np.ndarray, coefficients: np.ndarray) -> np.ndarray:
    """The issue's plain-NumPy bar: one ``[1, t, t²] @ C`` product and a division, written
    into a preallocated ``(N, 4, 4)``."""
    n = ts.shape[0]
    powers = np.empty((n, 3))
    powers[:, 0] = 1.0
    powers[:, 1] = ts
    np.multiply(ts, ts, out=powers[:, 2])
    values = powers @ coefficients
    out = np.empty((n, 4, 4))
    np.divide(values[:, :12], values[:, 12:], out=out.reshape(n, 16)[:, :12])
    out[:, 3, :3] = 0.0
    out[:, 3, 3] = 1.0
    return out


def random_pairs(count: int, seed: int = 7) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    starts = matrices_from_quat_trans(rng.normal(size=(count, 4)), rng.normal(size=(count, 3)))
    ends = matrices_from_quat_trans(rng.normal(size=(count, 4)), rng.normal(size=(count, 3)))
    return starts, ends


def wander(n: int, seed: int = 1) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A trajectory of ``n`` poses at 100 Hz: times, unit quaternions (w, x, y, z) and
    translations of a body whose roll, pitch and yaw and position drift a little each step."""
    from a2b.poses import quaternions_from_rpy_xyz

    rng = np.random.default_rng(seed)
    times = np.arange(n) * 0.01
    quat = quaternions_from_rpy_xyz(np.cumsum(rng.normal(0, 0.01, (n, 3)), axis=0))
    trans = np.cumsum(rng.normal(0, 0.01, (n, 3)), axis=0)
    return times, quat, trans
