#!/usr/bin/env python
"""Every speed target of a2b in one run: figures, ratios and whether each target is met.

Usage::

    pip install -e ".[bench]"
    env -u OPENBLAS_CORETYPE -u OPENBLAS_L2_SIZE python benchmarks/run.py
    python benchmarks/run.py --quick                  # N = 10^5 and fewer repeats: a smoke run
    python benchmarks/run.py --only library,startup   # some sections only
    python benchmarks/run.py --markdown results.md    # also write the tables as Markdown

Sections (each target is a ratio of two figures measured side by side in this one run, with
repeats interleaved, so that a busy machine slows both sides alike; figures are medians):

``library``
    ``a2b.interpolate`` to ``(N, 4, 4)`` for darboux, cubic (canonical and given frame) and
    screw, against pytransform3d's ScLERP path, its slerp + lerp path, scipy's ``Slerp`` + lerp,
    rational-linkages (one sample at a time) and the plain-NumPy coefficient reference (the
    Study-vector line as one ``[1, t, t²] @ C`` product and a division).
``motions``
    The vectorised core: J = 10^5 random pose pairs built in one ``a2b.motion`` call per mode
    (motions/s), against a Python loop of single motions and against pytransform3d's batch
    ScLERP on the same pairs (both sides: build and one sample at t = 1/2); and J = 10^4
    motions × 101 samples into ``(J, 101, 4, 4)`` against one motion of 10^6 samples.
``resample``
    ``a2b resample`` of a TUM trajectory of N poses (100 Hz, a robot's wander) at 10 N new
    times (``--rate 1000``) into CSV as a whole process, against ``a2b interpolate --samples
    10N --mode screw`` to CSV; and in the library, N segments resampled once each (screw mode,
    ``Resampler.locate`` + ``sample``) against scipy's ``Slerp`` over the trajectory plus
    ``numpy.interp`` of the translations, and pytransform3d's batch ScLERP of the segments.
``csv``
    ``a2b interpolate --samples N -o out.csv`` as a whole process, against a separate process
    running ``numpy.savetxt(fmt="%.17g")`` on the same eight columns; the CSV is read back and
    compared bit for bit with the library's values.
``mcap``
    ``a2b interpolate --samples N --format mcap`` as a whole process (both channels).
``startup``
    ``a2b --version`` and ``a2b --help`` against ``python -c "import numpy"``.
``batch``
    ``a2b batch`` of 10,000 jobs × 101 samples into CSV: peak resident memory (GNU time) and
    rows per second against the ``csv`` section's single-motion command (``a2b interpolate
    --samples N -o out.csv``, same poses), timed interleaved with it in this section, so the
    ratio does not need the ``csv`` section to run; at least 7 rounds.

The peers are optional (``pip install ".[bench]"``); a missing one is reported as "not
installed". The OPENBLAS_* variables of some machines select an older BLAS kernel; unsetting
them for this one command is fine, and the header reports the kernel that runs. Before any
timing the ``a2b`` package's bytecode is compiled (untimed), so that a development checkout is
measured as a pip-installed one. Benchmarks are not tests: nothing here fails on a slow machine.
"""

from __future__ import annotations

import argparse
import compileall
import contextlib
import datetime
import gc
import importlib.util
import json
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

SECTIONS = ("library", "motions", "timing", "resample", "csv", "mcap", "ros2", "startup", "batch")
A2B_MODES = [
    ("darboux", "darboux", {}),
    ("cubic (canonical)", "cubic", {}),
    ("cubic (given)", "cubic", {"frame": "given"}),
    ("screw", "screw", {}),
]


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


def peer_cases(start: np.ndarray, end: np.ndarray, ts: np.ndarray) -> dict[str, Callable | str]:
    """Each peer's path from the two 4x4 poses to ``(N, 4, 4)``, or why it cannot run."""
    cases: dict[str, Callable | str] = {}
    n = ts.shape[0]
    t_a, t_b = start[:3, 3], end[:3, 3]

    try:
        from pytransform3d.batch_rotations import quaternion_slerp_batch
        from pytransform3d.rotations import quaternion_from_matrix
        from pytransform3d.trajectories import (
            dual_quaternions_from_transforms,
            dual_quaternions_sclerp,
            transforms_from_dual_quaternions,
            transforms_from_pqs,
        )
    except ImportError:
        cases["pytransform3d ScLERP"] = cases["pytransform3d slerp + lerp"] = "not installed"
    else:

        def pt3d_sclerp():
            dqs = dual_quaternions_from_transforms(np.stack([start, end]))
            if dqs[0, :4] @ dqs[1, :4] < 0:
                dqs[1] = -dqs[1]
            starts = np.broadcast_to(dqs[0], (n, 8))
            ends = np.broadcast_to(dqs[1], (n, 8))
            return transforms_from_dual_quaternions(dual_quaternions_sclerp(starts, ends, ts))

        def pt3d_slerp():
            q_a = quaternion_from_matrix(start[:3, :3])
            q_b = quaternion_from_matrix(end[:3, :3])
            pqs = np.empty((n, 7))
            pqs[:, 3:] = quaternion_slerp_batch(q_a, q_b, ts, shortest_path=True)
            np.multiply(ts[:, None], t_b - t_a, out=pqs[:, :3])
            pqs[:, :3] += t_a
            # slerp's quaternions are unit already: skip the normalisation (the faster call)
            return transforms_from_pqs(pqs, normalize_quaternions=False)

        cases["pytransform3d ScLERP"] = pt3d_sclerp
        cases["pytransform3d slerp + lerp"] = pt3d_slerp

    try:
        from scipy.spatial.transform import Rotation, Slerp
    except ImportError:
        cases["scipy Slerp + lerp"] = "not installed"
    else:

        def scipy_slerp():
            slerp = Slerp([0.0, 1.0], Rotation.from_matrix(np.stack([start[:3, :3], end[:3, :3]])))
            out = np.empty((n, 4, 4))
            out[:, :3, :3] = slerp(ts).as_matrix()
            np.multiply(ts[:, None], t_b - t_a, out=out[:, :3, 3])
            out[:, :3, 3] += t_a
            out[:, 3, :3] = 0.0
            out[:, 3, 3] = 1.0
            return out

        cases["scipy Slerp + lerp"] = scipy_slerp

    coefficients = reference_coefficients(start, end)
    cases["plain NumPy [1, t, t²] @ C"] = lambda: reference_matrices(ts, coefficients)
    return cases


def rational_linkages_case(start: np.ndarray, end: np.ndarray, ts: np.ndarray) -> Callable | str:
    """The same Study-vector line as a rational-linkages curve, evaluated one sample at a time."""
    try:
        from rational_linkages import RationalCurve, TransfMatrix
    except ImportError:
        return "not installed"
    q_a = np.asarray(TransfMatrix.from_standard(start).matrix2dq(), dtype=float)
    q_b = np.asarray(TransfMatrix.from_standard(end).matrix2dq(), dtype=float)
    q_a /= np.linalg.norm(q_a[:4])
    q_b /= np.linalg.norm(q_b[:4])
    if q_a[:4] @ q_b[:4] < 0:
        q_b = -q_b
    curve = RationalCurve.from_coeffs(np.column_stack([q_b - q_a, q_a]))  # highest degree first

    def sample():
        return [curve.evaluate_as_matrix(float(t)) for t in ts]

    return sample


# ------------------------------------------------------------------------------------------
# sections
# ------------------------------------------------------------------------------------------


def library_section(n: int, repeats: int, rl_samples: int) -> list[Row]:
    start, end = test_poses()
    ts = np.linspace(0.0, 1.0, n)
    ours = {
        label: (lambda m=mode, p=p: a2b.interpolate(start, end, ts, m, **p))
        for label, mode, p in A2B_MODES
    }
    peers = peer_cases(start, end, ts)
    runnable = {name: f for name, f in peers.items() if callable(f)}

    # the same motions: the reference is darboux with δ = 0, ScLERP is the screw motion
    small = np.linspace(0.0, 1.0, 1001)
    small_peers = peer_cases(start, end, small)
    for name, mode in (
        ("plain NumPy [1, t, t²] @ C", "darboux"),
        ("pytransform3d ScLERP", "screw"),
    ):
        if callable(small_peers.get(name)):
            difference = np.abs(
                small_peers[name]() - a2b.interpolate(start, end, small, mode)
            ).max()
            log(f"same motion: {name} vs a2b {mode}: max |difference| {difference:.1e}")

    log(f"library: N = {n}, {repeats} interleaved repeats of {len(ours) + len(runnable)} cases")
    for f in list(ours.values()) + list(runnable.values()):  # warm up: imports, caches
        f()
    medians = interleaved({**ours, **runnable}, repeats)

    rows = []
    for label in ours:
        rows.append(Row("library", f"a2b.interpolate {label}", rate(n, medians[label])))
    for name, f in peers.items():
        rows.append(Row("library", name, rate(n, medians[name]) if callable(f) else f))

    rl = rational_linkages_case(start, end, np.linspace(0.0, 1.0, rl_samples))
    rl_rate = None
    if callable(rl):
        rl()
        rl_seconds = interleaved({"rl": rl}, max(3, repeats // 2))["rl"]
        rl_rate = rl_samples / rl_seconds
        rows.append(
            Row(
                "library",
                f"rational-linkages, one sample at a time ({rl_samples} samples)",
                rate(rl_samples, rl_seconds),
            )
        )
    else:
        rows.append(Row("library", "rational-linkages, one sample at a time", rl))

    bars = [
        ("pytransform3d ScLERP", 25.0),
        ("pytransform3d slerp + lerp", 3.0),
        ("plain NumPy [1, t, t²] @ C", 1.5),
    ]
    for label in ours:
        for peer, need in bars:
            if peer not in medians:
                rows.append(
                    Row("library", f"{label} vs {peer}", "", "not measured", f"≥ {need:g}×")
                )
                continue
            ratio = medians[peer] / medians[label]
            rows.append(
                Row(
                    "library",
                    f"{label} vs {peer}",
                    "",
                    f"{ratio:.2f}×",
                    f"≥ {need:g}×",
                    ratio >= need,
                )
            )
        if "scipy Slerp + lerp" in medians:
            rows.append(
                Row(
                    "library",
                    f"{label} vs scipy Slerp + lerp",
                    "",
                    f"{medians['scipy Slerp + lerp'] / medians[label]:.1f}×",
                )
            )
        if rl_rate:
            rows.append(
                Row(
                    "library",
                    f"{label} vs rational-linkages",
                    "",
                    f"{n / medians[label] / rl_rate:.0f}×",
                )
            )
    return rows


def random_pairs(count: int, seed: int = 7) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    starts = matrices_from_quat_trans(rng.normal(size=(count, 4)), rng.normal(size=(count, 3)))
    ends = matrices_from_quat_trans(rng.normal(size=(count, 4)), rng.normal(size=(count, 3)))
    return starts, ends


def motions_section(jobs: int, n: int, repeats: int) -> list[Row]:
    """Many motions at once: building J pairs in one call, and sampling J × 101."""
    import warnings

    warnings.simplefilter("ignore")  # a random batch has a few sensitive motions; not timed
    starts, ends = random_pairs(jobs)
    loop = min(jobs, 2000)
    half = np.array([0.5])
    cases = {}
    for mode in ("darboux", "cubic", "screw"):
        cases[f"build {mode}"] = lambda m=mode: a2b.motion(starts, ends, m).matrices(half)
    cases["loop of single darboux motions"] = lambda: [
        a2b.motion(starts[i], ends[i], "darboux").matrices(half) for i in range(loop)
    ]
    try:
        from pytransform3d.trajectories import (
            dual_quaternions_from_transforms,
            dual_quaternions_sclerp,
            transforms_from_dual_quaternions,
        )
    except ImportError:
        pt3d = None
    else:

        def pt3d():
            a = dual_quaternions_from_transforms(starts)
            b = dual_quaternions_from_transforms(ends)
            b[np.sum(a[:, :4] * b[:, :4], axis=1) < 0] *= -1
            return transforms_from_dual_quaternions(
                dual_quaternions_sclerp(a, b, np.full(jobs, 0.5))
            )

        cases["pytransform3d batch ScLERP"] = pt3d
    sample_jobs = jobs // 10
    batch = a2b.motion(starts[:sample_jobs], ends[:sample_jobs], "darboux")
    single = a2b.motion(starts[0], ends[0], "darboux")
    ts101 = np.linspace(0.0, 1.0, 101)
    ts_n = np.linspace(0.0, 1.0, n)
    log(f"motions: J = {jobs} pairs, {repeats} interleaved repeats of {len(cases)} cases")
    for f in cases.values():
        f()
    medians = interleaved(cases, repeats)
    # Sampling is timed apart from building: after the build cases have fragmented memory, the
    # kernel's compaction for the huge pages numpy asks for (THP "madvise") can stall the first
    # touch of a 130 MB output for ten times the work, on either side, at random.
    sampling = {
        "sample J × 101": lambda: batch.matrices(ts101),
        "sample one motion × N": lambda: single.matrices(ts_n),
    }
    for f in sampling.values():
        f()
    medians.update(interleaved(sampling, repeats))
    rows = []
    for mode in ("darboux", "cubic", "screw"):
        seconds = medians[f"build {mode}"]
        rows.append(
            Row(
                "motions",
                f"a2b.motion of {jobs} pairs, {mode}, one call (+ one sample each)",
                rate(jobs, seconds),
                "",
                "≥ 1 M motions/s",
                jobs / seconds >= 1e6,
            )
        )
    per_single = medians["loop of single darboux motions"] / loop
    rows.append(
        Row("motions", "Python loop of single darboux motions", f"{per_single * 1e6:.0f} µs each")
    )
    rows.append(
        Row(
            "motions",
            "darboux batch vs the loop of single motions",
            "",
            f"{per_single * jobs / medians['build darboux']:.0f}×",
        )
    )
    if pt3d is not None:
        ratio = medians["pytransform3d batch ScLERP"] / medians["build screw"]
        rows.append(
            Row(
                "motions",
                f"pytransform3d batch ScLERP of {jobs} pairs at t = 1/2",
                rate(jobs, medians["pytransform3d batch ScLERP"]),
            )
        )
        rows.append(
            Row("motions", "a2b screw batch vs pytransform3d batch ScLERP", "", f"{ratio:.1f}×")
        )
    else:
        rows.append(Row("motions", "pytransform3d batch ScLERP", "not installed"))
    batch_rate = sample_jobs * 101 / medians["sample J × 101"]
    single_rate = n / medians["sample one motion × N"]
    rows.append(
        Row(
            "motions",
            f"sample {sample_jobs} darboux motions × 101 to (J, 101, 4, 4)",
            rate(sample_jobs * 101, medians["sample J × 101"]),
        )
    )
    rows.append(
        Row(
            "motions",
            f"J × 101 samples/s vs one motion × {n}",
            "",
            f"{batch_rate / single_rate:.2f}",
            "≥ 0.8",
            batch_rate / single_rate >= 0.8,
        )
    )
    return rows


def timing_section(count: int, repeats: int) -> list[Row]:
    """Timing ``count`` motions with jerk-limited profiles (constant speed, linear limits) in one
    call of ``a2b.timing``, arc lengths included, against Ruckig computing the time-optimal
    profile of each path length under the same limits, one profile at a time (its C++ core
    through its Python binding, as a Python user calls it)."""
    import warnings

    warnings.simplefilter("ignore")
    starts, ends = random_pairs(count, seed=11)
    rng = np.random.default_rng(5)
    v, a, j = np.exp(rng.uniform(-1, 1, (3, count)))
    motion = a2b.motion(starts, ends, "darboux")
    from a2b.timelaw import arc_lengths

    lengths = arc_lengths(motion)[0]
    cases: dict = {
        "a2b.timing, jerk-limited, constant speed": lambda: a2b.timing(
            motion, "jerk-limited", max_speed=v, max_accel=a, max_jerk=j, constant_speed=True
        ),
        "a2b profiles alone (lengths known)": lambda: __import__("a2b.timelaw").timelaw.build(
            "jerk-limited", v / lengths, a / lengths, j / lengths
        ),
    }
    try:
        import ruckig
    except ImportError:
        ruckig = None
    else:

        def ruckig_loop():
            otg = ruckig.Ruckig(1)
            inp, out = ruckig.InputParameter(1), ruckig.Trajectory(1)
            for i in range(count):
                inp.current_position, inp.target_position = [0.0], [float(lengths[i])]
                inp.max_velocity = [float(v[i])]
                inp.max_acceleration, inp.max_jerk = [float(a[i])], [float(j[i])]
                otg.calculate(inp, out)

        cases["Ruckig, one profile at a time"] = ruckig_loop
    times = interleaved(cases, repeats)
    rows = []
    peer = times.get("Ruckig, one profile at a time")
    for name, seconds in times.items():
        rows.append(Row("timing", f"{name} ({count:,} motions)", rate(count, seconds) + " motions"))
    if peer is not None:
        for name in (
            "a2b profiles alone (lengths known)",
            "a2b.timing, jerk-limited, constant speed",
        ):
            ratio = peer / times[name]
            rows.append(
                Row(
                    "timing",
                    f"{name} against Ruckig (rate ratio)",
                    f"{ratio:.2f}x",
                    f"{ratio:.2f}",
                    ">= 0.2",
                    ratio >= 0.2,
                )
            )
    else:
        rows.append(Row("timing", "Ruckig", "not installed: pip install ruckig"))
    return rows


def wander(n: int, seed: int = 1) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A trajectory of ``n`` poses at 100 Hz: times, unit quaternions (w, x, y, z) and
    translations of a body whose roll, pitch and yaw and position drift a little each step."""
    from a2b.poses import quaternions_from_rpy_xyz

    rng = np.random.default_rng(seed)
    times = np.arange(n) * 0.01
    quat = quaternions_from_rpy_xyz(np.cumsum(rng.normal(0, 0.01, (n, 3)), axis=0))
    trans = np.cumsum(rng.normal(0, 0.01, (n, 3)), axis=0)
    return times, quat, trans


def resample_section(n: int, repeats: int, work: Path, exe: list[str] | None) -> list[Row]:
    """``a2b resample`` as a process against ``a2b interpolate``; and the library against
    scipy's Slerp + interp and pytransform3d's batch ScLERP on the same segments."""
    from a2b.io.floatrepr import format_rows
    from a2b.poses import matrices_from_quat_trans
    from a2b.resample import Resampler

    times, quat, trans = wander(n)
    rows: list[Row] = []
    if exe is not None:
        tum = work / "wander.tum"
        table = np.column_stack([times, trans, quat[:, [1, 2, 3, 0]]])
        tum.write_bytes(b"# time tx ty tz qx qy qz qw\n" + format_rows(table, sep=" "))
        poses = work / "poses.json"
        poses.write_text(json.dumps(poses_document(*test_poses())))
        out, ref = work / "resampled.csv", work / "interpolated.csv"
        samples = 10 * n
        commands = {
            "resample": exe + ["resample", str(tum), "--rate", "1000", "-o", str(out)],
            "interpolate": exe
            + [
                "interpolate",
                str(poses),
                "--samples",
                str(samples),
                "--mode",
                "screw",
                "-o",
                str(ref),
            ],
        }
        log(f"resample: {n} poses to {samples} times, {repeats} interleaved repeats")
        result = interleaved_processes(
            commands, repeats, rss=True, outputs={"resample": out, "interpolate": ref}
        )
        (seconds, peak), (reference, _) = result["resample"], result["interpolate"]
        written = sum(1 for _ in open(out, "rb")) - 1
        rows.append(
            Row(
                "resample",
                f"a2b resample of {n} TUM poses to {written} CSV rows",
                f"{seconds:.2f} s, {peak / 2**20:.0f} MiB",
            )
        )
        rows.append(
            Row(
                "resample",
                f"a2b interpolate --samples {samples} (screw) to CSV",
                f"{reference:.2f} s",
            )
        )
        ratio = seconds / reference
        rows.append(
            Row(
                "resample",
                "resample vs interpolate, whole process",
                "",
                f"{ratio:.2f}",
                "≤ 1.5",
                ratio <= 1.5,
            )
        )
    else:
        rows.append(Row("resample", "the a2b command is not installed", "not measured"))

    matrices = matrices_from_quat_trans(quat, trans)
    middle = times[:-1] + 0.005  # one new time in each of the n − 1 segments

    def ours():
        resampler = Resampler(times, matrices, "screw", quat_wxyz=quat, checked=True)
        return resampler.sample(resampler.locate(middle))

    cases = {"a2b": ours}
    try:
        from scipy.spatial.transform import Rotation, Slerp
    except ImportError:
        pass
    else:

        def scipy_slerp():
            rotations = Slerp(times, Rotation.from_quat(quat[:, [1, 2, 3, 0]]))(middle)
            out = np.zeros((len(middle), 4, 4))
            out[:, :3, :3] = rotations.as_matrix()
            for axis in range(3):
                out[:, axis, 3] = np.interp(middle, times, trans[:, axis])
            out[:, 3, 3] = 1.0
            return out

        cases["scipy Slerp + interp"] = scipy_slerp
    try:
        from pytransform3d.trajectories import (
            dual_quaternions_from_transforms,
            dual_quaternions_sclerp,
            transforms_from_dual_quaternions,
        )
    except ImportError:
        pass
    else:

        def pt3d():
            k = np.searchsorted(times, middle, side="right") - 1
            u = (middle - times[k]) / (times[k + 1] - times[k])
            dq = dual_quaternions_from_transforms(matrices)
            a, b = dq[k], dq[k + 1]
            b[np.sum(a[:, :4] * b[:, :4], axis=1) < 0] *= -1
            return transforms_from_dual_quaternions(dual_quaternions_sclerp(a, b, u))

        cases["pytransform3d batch ScLERP"] = pt3d
    # The peers' per-segment ways (one interpolator per segment, in a Python loop), timed on
    # the first segments and counted per segment
    loop = min(n - 1, 2000)
    if "scipy Slerp + interp" in cases:

        def scipy_loop():
            for k in range(loop):
                pair = Rotation.from_quat(quat[k : k + 2, [1, 2, 3, 0]])
                Slerp(times[k : k + 2], pair)(middle[k]).as_matrix()
                np.interp(middle[k], times[k : k + 2], trans[k : k + 2, 0])

        cases["scipy Slerp per segment"] = scipy_loop
    if "pytransform3d batch ScLERP" in cases:
        from pytransform3d.transformations import (
            dual_quaternion_from_transform,
            dual_quaternion_sclerp,
            transform_from_dual_quaternion,
        )

        def pt3d_loop():
            for k in range(loop):
                a = dual_quaternion_from_transform(matrices[k])
                b = dual_quaternion_from_transform(matrices[k + 1])
                u = (middle[k] - times[k]) / (times[k + 1] - times[k])
                transform_from_dual_quaternion(dual_quaternion_sclerp(a, b, u))

        cases["pytransform3d ScLERP per segment"] = pt3d_loop
    for f in cases.values():
        f()
    medians = interleaved(cases, repeats)
    for peer in ("scipy Slerp per segment", "pytransform3d ScLERP per segment"):
        if peer in medians:
            medians[peer] *= (n - 1) / loop
    rows.append(
        Row(
            "resample",
            f"a2b: {n - 1} segments resampled once each (screw)",
            rate(n - 1, medians["a2b"]),
        )
    )
    for peer in ("scipy Slerp per segment", "pytransform3d ScLERP per segment"):
        if peer not in medians:
            rows.append(Row("resample", peer, "not installed"))
            continue
        ratio = medians[peer] / medians["a2b"]
        rows.append(
            Row("resample", f"{peer} (loop of {loop}, per segment)", rate(n - 1, medians[peer]))
        )
        rows.append(Row("resample", f"a2b vs {peer}", "", f"{ratio:.1f}×", "≥ 5×", ratio >= 5))
    for peer in ("scipy Slerp + interp", "pytransform3d batch ScLERP"):
        if peer not in medians:
            rows.append(Row("resample", peer, "not installed"))
            continue
        ratio = medians[peer] / medians["a2b"]
        rows.append(Row("resample", f"{peer}, same segments", rate(n - 1, medians[peer])))
        rows.append(Row("resample", f"a2b vs {peer} (vectorised, no target)", "", f"{ratio:.2f}×"))
    return rows


def csv_section(n: int, repeats: int, work: Path, exe: list[str]) -> tuple[list[Row], float | None]:
    start, end = test_poses()
    poses = work / "poses.json"
    poses.write_text(json.dumps(poses_document(start, end)))
    out_csv, ref_csv, columns = work / "out.csv", work / "savetxt.csv", work / "columns.npy"

    # the eight columns, computed exactly as the command computes them (sample by chunk)
    motion = a2b.motion(start, end, "darboux")
    ts = np.linspace(0.0, 1.0, n)
    try:
        from a2b.output import motion_samples

        parts = [(c.t, c.trans, c.quat_wxyz) for c in motion_samples(motion, n, "quat_trans")]
        expected = np.column_stack([np.concatenate([p[i] for p in parts]) for i in range(3)])
    except ImportError:
        quat, trans = motion.quat_trans(ts)
        expected = np.column_stack([ts, trans, quat])
    np.save(columns, expected)

    savetxt = (
        "import sys, numpy as np; "
        "np.savetxt(sys.argv[2], np.load(sys.argv[1]), fmt='%.17g', delimiter=',')"
    )
    commands = {
        "a2b": exe + ["interpolate", str(poses), "--samples", str(n), "-o", str(out_csv)],
        "savetxt": [sys.executable, "-c", savetxt, str(columns), str(ref_csv)],
    }
    # the CSV writers the issue names as possible dependencies, when they are importable
    for name, script in CSV_LIBRARIES.items():
        if importlib.util.find_spec(name) is not None:
            commands[name] = [sys.executable, "-c", script, str(columns), str(work / f"{name}.csv")]
    log(f"csv: {n} rows, {repeats} interleaved repeats of {', '.join(commands)}")
    outputs = {"a2b": out_csv, "savetxt": ref_csv}
    outputs.update({name: work / f"{name}.csv" for name in CSV_LIBRARIES})
    result = interleaved_processes(commands, repeats, outputs=outputs)
    a2b_s, sav_s = result["a2b"][0], result["savetxt"][0]

    exact, mismatches, header = read_back(out_csv, expected)
    ratio = a2b_s / sav_s
    rows = [
        Row(
            "csv",
            f"a2b interpolate --samples {n} -o out.csv (whole process)",
            f"{a2b_s:.2f} s, {rate(n, a2b_s)} rows",
        ),
        Row(
            "csv",
            "numpy.savetxt(fmt='%.17g'), same 8 columns, separate process",
            f"{sav_s:.2f} s, {rate(n, sav_s)} rows",
        ),
        Row("csv", "a2b time / savetxt time", "", f"{ratio:.3f}", "≤ 0.2", ratio <= 0.2),
        Row(
            "csv",
            f"read back bit for bit ({header})",
            "all values" if exact else f"{mismatches} differ",
            "",
            "all",
            exact,
        ),
    ]
    for name in CSV_LIBRARIES:
        if name not in result:
            rows.append(Row("csv", f"{name} CSV writer, same 8 columns", "not installed"))
            continue
        seconds = result[name][0]
        same = read_back(work / f"{name}.csv", expected)[0]
        rows.append(
            Row(
                "csv",
                f"{name} CSV writer, same 8 columns, separate process"
                + ("" if same else " (does NOT read back bit for bit)"),
                f"{seconds:.2f} s, {rate(n, seconds)} rows",
                f"{seconds / sav_s:.3f} of savetxt",
            )
        )
    for path in work.glob("*.csv"):
        path.unlink()
    return rows, n / a2b_s


#: Whole-process scripts for the CSV writers the issue compares: columns.npy -> CSV.
CSV_LIBRARIES = {
    "polars": (
        "import sys, numpy as np, polars as pl; a = np.load(sys.argv[1]); "
        "names = ['t', 'tx', 'ty', 'tz', 'qw', 'qx', 'qy', 'qz']; "
        "pl.DataFrame({k: a[:, i] for i, k in enumerate(names)}).write_csv(sys.argv[2])"
    ),
    "pyarrow": (
        "import sys, numpy as np, pyarrow as pa, pyarrow.csv as csv; a = np.load(sys.argv[1]); "
        "names = ['t', 'tx', 'ty', 'tz', 'qw', 'qx', 'qy', 'qz']; "
        "csv.write_csv(pa.table({k: a[:, i] for i, k in enumerate(names)}), sys.argv[2])"
    ),
}


def read_back(path: Path, expected: np.ndarray) -> tuple[bool, str, str]:
    """Whether a CSV (with a header line) reads back as ``expected`` bit for bit, with Python's
    correctly rounded ``float``; the number of differing values; the header."""
    with open(path) as f:
        header = f.readline().strip()
        values = np.array([[float(x) for x in line.split(",")] for line in f])
    if values.shape != expected.shape:
        return False, f"shape {values.shape} instead of {expected.shape}", header
    same = np.array_equal(values.view(np.int64), expected.view(np.int64))
    return same, str(int((values.view(np.int64) != expected.view(np.int64)).sum())), header


#: The same MCAP with the ``mcap`` package's ``Writer``: a2b samples the motion (as in a2b's
#: own command), then every sample becomes the same two JSON messages, zstd chunks of about the
#: same size. argv: poses.json, samples, output.
MCAP_LIBRARY = """
import json, sys
import numpy as np
from mcap.writer import CompressionType, Writer
import a2b
from a2b.io.poseschema import read_poses
from a2b.io.mcapwriter import _json_schema as _schema

job = read_poses(open(sys.argv[1], "rb"))
n = int(sys.argv[2])
quat, trans = a2b.motion(job.start, job.end, "darboux").quat_trans(np.linspace(0.0, 1.0, n))
ns = np.rint(np.linspace(0.0, 1.0, n) * 1e9).astype(np.int64).tolist()
with open(sys.argv[3], "wb") as f:
    w = Writer(f, chunk_size=2 << 20, compression=CompressionType.ZSTD)
    w.start(profile="", library="peer")
    ids = []
    for name, topic in (("foxglove.PoseInFrame", "/a2b/pose"), ("foxglove.FrameTransform", "/tf")):
        schema = w.register_schema(name=name, encoding="jsonschema", data=_schema(name))
        ids.append(w.register_channel(topic=topic, message_encoding="json", schema_id=schema))
    for i, (t, (x, y, z), (qw, qx, qy, qz)) in enumerate(zip(ns, trans.tolist(), quat.tolist())):
        stamp = {"sec": t // 1_000_000_000, "nsec": t % 1_000_000_000}
        xyz, xyzw = {"x": x, "y": y, "z": z}, {"x": qx, "y": qy, "z": qz, "w": qw}
        pose = {"timestamp": stamp, "frame_id": "world",
                "pose": {"position": xyz, "orientation": xyzw}}
        tf = {"timestamp": stamp, "parent_frame_id": "world", "child_frame_id": "a2b",
              "translation": xyz, "rotation": xyzw}
        for channel, message in zip(ids, (pose, tf)):
            data = json.dumps(message, separators=(",", ":")).encode()
            w.add_message(channel, log_time=t, data=data, publish_time=t, sequence=i)
    w.finish()
"""


def mcap_section(n: int, repeats: int, work: Path, exe: list[str]) -> list[Row]:
    start, end = test_poses()
    poses = work / "poses.json"
    poses.write_text(json.dumps(poses_document(start, end)))
    out = work / "out.mcap"
    command = exe + [
        "interpolate",
        str(poses),
        "--samples",
        str(n),
        "--format",
        "mcap",
        "-o",
        str(out),
    ]
    log(f"mcap: {n} poses, {repeats} repeats")
    seconds = interleaved_processes({"mcap": command}, repeats, outputs={"mcap": out})["mcap"][0]
    counts = ""
    try:
        from mcap.reader import make_reader

        with open(out, "rb") as f:
            stats = make_reader(f).get_summary().statistics
        counts = f", {stats.message_count} messages on {stats.channel_count} channels"
    except Exception as e:  # noqa: BLE001 - a summary we cannot read is reported, not fatal
        counts = f", summary not read: {e}"
    size = out.stat().st_size / 2**20
    out.unlink(missing_ok=True)
    per_second = n / seconds
    rows = [
        Row(
            "mcap",
            f"a2b interpolate --samples {n} --format mcap (whole process{counts}, {size:.0f} MiB)",
            f"{seconds:.2f} s, {rate(n, seconds)} poses",
            "",
            "≥ 500 k/s",
            per_second >= 500_000,
        )
    ]
    peer_n = max(n // 10, 1000)  # the peer takes about 10 µs a message: a tenth of the poses
    script = work / "mcap_peer.py"
    script.write_text(MCAP_LIBRARY)
    peer = [sys.executable, str(script), str(poses), str(peer_n), str(out)]
    log(f"mcap: the mcap package's Writer, {peer_n} poses, {repeats} repeats")
    peer_seconds = interleaved_processes({"peer": peer}, repeats, outputs={"peer": out})["peer"][0]
    out.unlink(missing_ok=True)
    peer_rate = peer_n / peer_seconds
    rows.append(
        Row(
            "mcap",
            f"mcap package's Writer, same messages, json.dumps, zstd ({peer_n} poses, whole "
            "process)",
            f"{peer_seconds:.2f} s, {rate(peer_n, peer_seconds)} poses",
        )
    )
    rows.append(
        Row(
            "mcap",
            "a2b's chunk builder vs the mcap package's Writer (poses/s)",
            "",
            f"{per_second / peer_rate:.1f}×",
            "≥ 2× (to stay)",
            per_second / peer_rate >= 2,
        )
    )
    return rows


#: The same ROS 2 messages (PoseStamped on /a2b/pose, TFMessage on /tf) with a peer's writer:
#: a2b samples the motion, as in a2b's own command, then the peer serialises and writes every
#: message. argv: poses.json, samples, output, rosbags|mcap_ros2.
ROS2_PEERS = """
import sys
import numpy as np
import a2b
from a2b.io.poseschema import read_poses
from a2b.io.ros2 import schema_text

job = read_poses(open(sys.argv[1], "rb"))
n, out, peer = int(sys.argv[2]), sys.argv[3], sys.argv[4]
quat, trans = a2b.motion(job.start, job.end, "darboux").quat_trans(np.linspace(0.0, 1.0, n))
ns = np.rint(np.linspace(0.0, 1.0, n) * 1e9).astype(np.int64).tolist()
rows = zip(ns, trans.tolist(), quat.tolist())
if peer == "rosbags":
    from pathlib import Path
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS2_HUMBLE)
    T = {name.split("/")[-1]: kind for name, kind in store.types.items()}
    pose_t, tf_t = "geometry_msgs/msg/PoseStamped", "tf2_msgs/msg/TFMessage"
    with Writer(Path(out), version=8, storage_plugin=StoragePlugin.MCAP) as w:
        pose_c = w.add_connection("/a2b/pose", pose_t, typestore=store)
        tf_c = w.add_connection("/tf", tf_t, typestore=store)
        for t, (x, y, z), (qw, qx, qy, qz) in rows:
            stamp = T["Time"](sec=t // 1_000_000_000, nanosec=t % 1_000_000_000)
            header = T["Header"](stamp=stamp, frame_id="world")
            q = T["Quaternion"](x=qx, y=qy, z=qz, w=qw)
            p = T["Pose"](position=T["Point"](x=x, y=y, z=z), orientation=q)
            pose = T["PoseStamped"](header=header, pose=p)
            transform = T["Transform"](translation=T["Vector3"](x=x, y=y, z=z), rotation=q)
            stamped = T["TransformStamped"](
                header=header, child_frame_id="a2b", transform=transform
            )
            tf = T["TFMessage"](transforms=[stamped])
            w.write(pose_c, t, store.serialize_cdr(pose, pose_t))
            w.write(tf_c, t, store.serialize_cdr(tf, tf_t))
else:
    from mcap_ros2.writer import Writer

    with open(out, "wb") as f:
        w = Writer(f)
        schemas = [
            w.register_msgdef(name.replace("/", "/msg/"), schema_text(name).decode())
            for name in ("geometry_msgs/PoseStamped", "tf2_msgs/TFMessage")
        ]
        pose_s, tf_s = schemas
        for i, (t, (x, y, z), (qw, qx, qy, qz)) in enumerate(rows):
            stamp = {"sec": t // 1_000_000_000, "nanosec": t % 1_000_000_000}
            header = {"stamp": stamp, "frame_id": "world"}
            q, xyz = {"x": qx, "y": qy, "z": qz, "w": qw}, {"x": x, "y": y, "z": z}
            pose = {"header": header, "pose": {"position": xyz, "orientation": q}}
            transform = {"translation": xyz, "rotation": q}
            stamped = {"header": header, "child_frame_id": "a2b", "transform": transform}
            tf = {"transforms": [stamped]}
            w.write_message("/a2b/pose", pose_s, pose, log_time=t, publish_time=t, sequence=i)
            w.write_message("/tf", tf_s, tf, log_time=t, publish_time=t, sequence=i)
        w.finish()
"""


def ros2_section(n: int, repeats: int, work: Path, exe: list[str]) -> list[Row]:
    """``--format ros2`` (whole process) against ``--format mcap`` (JSON) in the same
    interleaved runs, and against rosbags' and mcap-ros2-support's writers (whole processes
    that sample with a2b, then serialise and write with the peer)."""
    start, end = test_poses()
    poses = work / "poses.json"
    poses.write_text(json.dumps(poses_document(start, end)))
    commands, outputs = {}, {}
    for fmt in ("ros2", "mcap"):
        outputs[fmt] = work / f"{fmt}.mcap"
        commands[fmt] = exe + [
            "interpolate",
            str(poses),
            "--samples",
            str(n),
            "--format",
            fmt,
            "-o",
            str(outputs[fmt]),
        ]
    log(f"ros2: {n} poses, ros2 and mcap (JSON) interleaved, {repeats} repeats")
    seconds = {k: v[0] for k, v in interleaved_processes(commands, repeats, outputs).items()}
    rows = [
        Row(
            "ros2",
            f"a2b interpolate --samples {n} --format ros2 (whole process: PoseStamped, "
            "TFMessage, and the Path of every pose)",
            f"{seconds['ros2']:.2f} s, {rate(n, seconds['ros2'])} poses",
            "",
            "≥ 1 M/s",
            n / seconds["ros2"] >= 1_000_000,
        ),
        Row(
            "ros2",
            f"a2b interpolate --samples {n} --format mcap (JSON, same run)",
            f"{seconds['mcap']:.2f} s, {rate(n, seconds['mcap'])} poses",
            f"ros2 {seconds['mcap'] / seconds['ros2']:.1f}× faster",
        ),
    ]
    peer_n = max(n // 10, 1000)  # the peers take 10 to 50 µs a pose: a tenth of the poses
    script = work / "ros2_peer.py"
    script.write_text(ROS2_PEERS)
    for peer, name in (
        ("rosbags", "rosbags' Writer (serialize_cdr)"),
        ("mcap_ros2", "mcap-ros2-support's Writer"),
    ):
        out = work / f"{peer}.out"
        try:
            __import__(peer)
        except ImportError:
            rows.append(Row("ros2", name, "not installed (pip install -e '.[bench]')"))
            continue
        argv = [sys.executable, str(script), str(poses), str(peer_n), str(out), peer]
        log(f"ros2: {name}, {peer_n} poses, {repeats} repeats")
        peer_seconds = interleaved_processes({peer: argv}, repeats, outputs={peer: out})[peer][0]
        shutil.rmtree(out, ignore_errors=True)
        out.unlink(missing_ok=True)
        ratio = (n / seconds["ros2"]) / (peer_n / peer_seconds)
        rows.append(
            Row(
                "ros2",
                f"{name}, same messages ({peer_n} poses, whole process)",
                f"{peer_seconds:.2f} s, {rate(peer_n, peer_seconds)} poses",
                f"a2b {ratio:.0f}× faster",
            )
        )
    return rows


def startup_section(repeats: int, exe: list[str]) -> list[Row]:
    commands = {
        "a2b --version": exe + ["--version"],
        "a2b --help": exe + ["--help"],
        'python -c "import numpy"': [sys.executable, "-c", "import numpy"],
    }
    log(f"startup: {repeats} interleaved repeats")
    interleaved_processes(commands, 2)  # warm the file cache
    result = interleaved_processes(commands, repeats)
    base = result['python -c "import numpy"'][0]
    rows = [
        Row("startup", name, f"{seconds * 1e3:.0f} ms") for name, (seconds, _) in result.items()
    ]
    for name in ("a2b --version", "a2b --help"):
        ratio = result[name][0] / base
        rows.append(
            Row("startup", f"{name} / import numpy", "", f"{ratio:.2f}", "≤ 1.3", ratio <= 1.3)
        )
    return rows


#: Fewest interleaved rounds of the batch section: its ratio is sensitive to drift and noise.
BATCH_MIN_ROUNDS = 7


def batch_section(
    jobs: int, samples: int, n: int, repeats: int, work: Path, exe: list[str]
) -> list[Row]:
    """``a2b batch`` against the ``csv`` section's single-motion command (``n`` samples, same
    poses), the two interleaved here so that the machine's drift slows both alike."""
    rng = np.random.default_rng(4)
    path = work / "jobs.jsonl"
    with open(path, "w") as f:
        for i in range(jobs):
            quats, trans = rng.normal(size=(2, 4)), rng.normal(size=(2, 3))
            job = {
                "name": f"job{i}",
                "start": {"quaternion_wxyz": quats[0].tolist(), "translation": trans[0].tolist()},
                "end": {"quaternion_wxyz": quats[1].tolist(), "translation": trans[1].tolist()},
            }
            f.write(json.dumps(job) + "\n")
    out = work / "batch.csv"
    start, end = test_poses()
    poses = work / "poses.json"
    poses.write_text(json.dumps(poses_document(start, end)))
    single_out = work / "out.csv"
    commands = {
        "batch": exe + ["batch", str(path), "--samples", str(samples), "-o", str(out)],
        "single": exe + ["interpolate", str(poses), "--samples", str(n), "-o", str(single_out)],
    }
    rounds = max(repeats, BATCH_MIN_ROUNDS)
    log(
        f"batch: {jobs} jobs × {samples} samples and single-motion CSV of {n} rows, "
        f"{rounds} interleaved rounds (at least {BATCH_MIN_ROUNDS}: the ratio is sensitive)"
    )
    result = interleaved_processes(
        commands, rounds, rss=True, outputs={"batch": out, "single": single_out}
    )
    seconds, peak = result["batch"]
    single_s = result["single"][0]
    with open(out, "rb") as f:
        lines = sum(1 for _ in f)
    out.unlink(missing_ok=True)
    single_out.unlink(missing_ok=True)
    rows_out = jobs * samples
    ratio = rows_out / seconds / (n / single_s)
    rows = [
        Row(
            "batch",
            f"a2b batch {jobs} jobs × {samples} samples -o batch.csv ({lines - 1} rows)",
            f"{seconds:.2f} s, {rate(rows_out, seconds)} rows",
        ),
        Row(
            "batch",
            f"a2b interpolate --samples {n} -o out.csv (single motion, interleaved with batch)",
            f"{single_s:.2f} s, {rate(n, single_s)} rows",
        ),
        Row(
            "batch",
            "peak resident memory of a2b batch (GNU time %M)",
            f"{peak / 1e6:.0f} MB",
            "",
            "≤ 150 MB",
            peak <= 150e6,
        ),
        Row(
            "batch",
            "rows/s vs single-motion CSV rows/s (interleaved)",
            "",
            f"{ratio:.2f}",
            "≥ 0.8",
            ratio >= 0.8,
        ),
    ]
    return rows


# ------------------------------------------------------------------------------------------


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--samples", type=int, default=1_000_000, help="N for library, csv, mcap (default 10^6)"
    )
    parser.add_argument(
        "--repeats", type=int, default=5, help="repeats of in-process timings (default 5)"
    )
    parser.add_argument(
        "--process-repeats",
        type=int,
        default=3,
        help=f"repeats of whole-process timings (default 3; batch: at least {BATCH_MIN_ROUNDS})",
    )
    parser.add_argument(
        "--jobs", type=int, default=10_000, help="jobs in the batch section (default 10,000)"
    )
    parser.add_argument("--quick", action="store_true", help="N = 10^5, 1,000 jobs, fewer repeats")
    parser.add_argument(
        "--only",
        default=",".join(SECTIONS),
        help=f"comma-separated sections of {', '.join(SECTIONS)}",
    )
    parser.add_argument(
        "--markdown", type=Path, help="also write the machine and the table as Markdown here"
    )
    parser.add_argument(
        "--blas-threads",
        type=int,
        help="limit BLAS threads in the library section (threadpoolctl); default: BLAS's own",
    )
    args = parser.parse_args(argv)
    if args.quick:
        args.samples, args.repeats, args.process_repeats, args.jobs = 100_000, 3, 2, 1_000
    sections = [s.strip() for s in args.only.split(",") if s.strip()]
    unknown = set(sections) - set(SECTIONS)
    if unknown:
        parser.error(f"unknown sections {', '.join(sorted(unknown))}")

    info = machine()
    command = " ".join(["python", "benchmarks/run.py"] + (sys.argv[1:] if argv is None else argv))
    rows: list[Row] = []
    exe = a2b_command()
    compile_bytecode()
    with tempfile.TemporaryDirectory(prefix="a2b-bench-") as tmp:
        work = Path(tmp)
        for section in sections:
            if section == "library":
                limit = contextlib.nullcontext()
                if args.blas_threads:
                    from threadpoolctl import threadpool_limits

                    limit = threadpool_limits(args.blas_threads, user_api="blas")
                    info["BLAS threads in the library section"] = str(args.blas_threads)
                with limit:
                    rl_samples = 50 if args.quick else 300
                    rows += library_section(args.samples, args.repeats, rl_samples)
                continue
            if section == "motions":
                rows += motions_section(10 * args.jobs, args.samples, args.repeats)
                continue
            if section == "timing":
                rows += timing_section(10 * args.jobs, max(1, args.repeats // 2))
                continue
            if section == "resample":
                rows += resample_section(args.samples, args.process_repeats, work, exe)
                continue
            if exe is None:
                rows.append(Row(section, "the a2b command is not installed", "not measured"))
                continue
            if section == "csv":
                rows += csv_section(args.samples, args.process_repeats, work, exe)[0]
            elif section == "mcap":
                rows += mcap_section(args.samples, args.process_repeats, work, exe)
            elif section == "ros2":
                rows += ros2_section(args.samples, args.process_repeats, work, exe)
            elif section == "startup":
                rows += startup_section(max(11, 4 * args.repeats), exe)
            elif section == "batch":
                rows += batch_section(args.jobs, 101, args.samples, args.process_repeats, work, exe)
    info["load average (1 min) at end"] = f"{os.getloadavg()[0]:.2f}"

    print("\n".join(f"{key}: {value}" for key, value in info.items()))
    print(f"command: {command}\n")
    print(text_table(rows))
    if args.markdown:
        lines = ["| machine | |", "| --- | --- |"] + [f"| {k} | {v} |" for k, v in info.items()]
        text = "\n".join(lines) + f"\n\nCommand: `{command}`\n\n" + markdown_table(rows) + "\n"
        args.markdown.write_text(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
