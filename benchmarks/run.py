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
``datasets``
    ``a2b batch`` of 2 × ``--jobs`` jobs × 101 samples to Parquet against CSV (rows/s, whole
    processes), and on a local Dask cluster of 1 and 2 workers against the single process at
    the same work (benchmarks/bench_datasets.py; skipped, with the reason, without pyarrow and
    dask: ``pip install ".[dask]"``).

The peers are optional (``pip install ".[bench]"``); a missing one is reported as "not
installed". The OPENBLAS_* variables of some machines select an older BLAS kernel; unsetting
them for this one command is fine, and the header reports the kernel that runs. Before any
timing the ``a2b`` package's bytecode is compiled (untimed), so that a development checkout is
measured as a pip-installed one. Benchmarks are not tests: nothing here fails on a slow machine.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import sys
import tempfile
from collections.abc import Callable
from pathlib import Path

import numpy as np
from bench_common import (
    Row,
    a2b_command,
    compile_bytecode,
    interleaved,
    log,
    machine,
    markdown_table,
    random_pairs,
    rate,
    reference_coefficients,
    reference_matrices,
    test_poses,
    text_table,
)
from bench_datasets import datasets_section
from bench_processes import (
    BATCH_MIN_ROUNDS,
    batch_section,
    csv_section,
    mcap_section,
    resample_section,
    ros2_section,
    startup_section,
)

import a2b

SECTIONS = (
    "library",
    "core",
    "motions",
    "timing",
    "resample",
    "csv",
    "mcap",
    "ros2",
    "startup",
    "batch",
    "datasets",
)
A2B_MODES = [
    ("darboux", "darboux", {}),
    ("cubic (canonical)", "cubic", {}),
    ("cubic (given)", "cubic", {"frame": "given"}),
    ("screw", "screw", {}),
]


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

    return rows + _library_ratios(medians, list(ours), n, rl_rate)


def _library_ratios(medians: dict, ours: list, n: int, rl_rate: float | None) -> list[Row]:
    rows = []
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


#: Issue 26: one a2b.interpolate of 101 samples at most this many times scipy's Slerp + lerp.
SINGLE_VS_SCIPY = {"darboux": 1.0, "screw": 1.0, "cubic": 1.5}
#: Issue 26: J = 10^5 pairs built plus one sample at t = 1/2, at least this many times as fast
#: as pytransform3d's batch conversions plus its ScLERP at t = 1/2.
BUILD_VS_PYTRANSFORM3D = {"darboux": 2.0, "screw": 2.0, "cubic": 1.5}
#: Issue 26: the screw build of J pairs at least this fraction of a plain-NumPy ScLERP's rate.
SCREW_VS_PLAIN = 0.6


def plain_sclerp_build(starts: np.ndarray, ends: np.ndarray) -> tuple[np.ndarray, ...]:
    """A plain-NumPy ScLERP build without checks, the bar of issue 26: the unit dual
    quaternions of both poses (Shepperd's largest diagonal), the displacement ``B A*`` the short
    way round, and its screw parameters: angle θ, axis direction l, slide d and moment m."""
    m = np.stack([starts, ends])  # (2, J, 4, 4)
    r, t = m[..., :3, :3], m[..., :3, 3]
    r00, r11, r22 = r[..., 0, 0], r[..., 1, 1], r[..., 2, 2]
    trace = r00 + r11 + r22
    diagonal = np.stack([1 + trace, 1 + 2 * r00 - trace, 1 + 2 * r11 - trace, 1 + 2 * r22 - trace])
    wx, wy, wz = (
        r[..., 2, 1] - r[..., 1, 2],
        r[..., 0, 2] - r[..., 2, 0],
        r[..., 1, 0] - r[..., 0, 1],
    )
    xy, xz, yz = (
        r[..., 1, 0] + r[..., 0, 1],
        r[..., 2, 0] + r[..., 0, 2],
        r[..., 2, 1] + r[..., 1, 2],
    )
    rows = np.stack(
        [
            np.stack([diagonal[0], wx, wy, wz]),
            np.stack([wx, diagonal[1], xy, xz]),
            np.stack([wy, xy, diagonal[2], yz]),
            np.stack([wz, xz, yz, diagonal[3]]),
        ]
    )  # (4 rows, 4 components, 2, J)
    best = np.argmax(diagonal, axis=0)
    p = np.take_along_axis(rows, best[None, None], axis=0)[0]
    p /= np.sqrt(np.sum(p * p, axis=0))
    tx, ty, tz = t[..., 0], t[..., 1], t[..., 2]
    p0, p1, p2, p3 = p
    q = 0.5 * np.stack(  # ½ (0, t) p
        [
            -tx * p1 - ty * p2 - tz * p3,
            tx * p0 + ty * p3 - tz * p2,
            -tx * p3 + ty * p0 + tz * p1,
            tx * p2 - ty * p1 + tz * p0,
        ]
    )
    (a0, a1, a2, a3), (b0, b1, b2, b3) = np.moveaxis(p, 1, 0)
    (c0, c1, c2, c3), (e0, e1, e2, e3) = np.moveaxis(q, 1, 0)
    # B A*: primal b ā, dual b c̄ + e ā (ā = (a0, −a1, −a2, −a3))
    primal = np.stack(
        [
            b0 * a0 + b1 * a1 + b2 * a2 + b3 * a3,
            -b0 * a1 + b1 * a0 - b2 * a3 + b3 * a2,
            -b0 * a2 + b1 * a3 + b2 * a0 - b3 * a1,
            -b0 * a3 - b1 * a2 + b2 * a1 + b3 * a0,
        ]
    )
    dual = np.stack(
        [
            b0 * c0 + b1 * c1 + b2 * c2 + b3 * c3 + e0 * a0 + e1 * a1 + e2 * a2 + e3 * a3,
            -b0 * c1 + b1 * c0 - b2 * c3 + b3 * c2 - e0 * a1 + e1 * a0 - e2 * a3 + e3 * a2,
            -b0 * c2 + b1 * c3 + b2 * c0 - b3 * c1 - e0 * a2 + e1 * a3 + e2 * a0 - e3 * a1,
            -b0 * c3 - b1 * c2 + b2 * c1 + b3 * c0 - e0 * a3 - e1 * a2 + e2 * a1 + e3 * a0,
        ]
    )
    sign = np.where(primal[0] < 0, -1.0, 1.0)
    primal *= sign
    dual *= sign
    s = np.sqrt(np.sum(primal[1:] * primal[1:], axis=0))
    theta = 2.0 * np.arctan2(s, primal[0])
    axis = primal[1:] / s
    slide = -2.0 * dual[0] / s
    moment = (dual[1:] - 0.5 * slide * primal[0] * axis) / s
    return theta, axis, slide, moment


def core_section(jobs: int, repeats: int) -> list[Row]:
    """Issue 26: one ``a2b.interpolate`` of 101 samples against scipy's Slerp + lerp into
    ``(101, 4, 4)``, and the screw build of J pairs against a plain-NumPy ScLERP build."""
    import warnings

    warnings.simplefilter("ignore")
    start, end = test_poses()
    ts = np.linspace(0.0, 1.0, 101)
    cases = {mode: (lambda m=mode: a2b.interpolate(start, end, ts, m)) for mode in SINGLE_VS_SCIPY}
    scipy = peer_cases(start, end, ts).get("scipy Slerp + lerp")
    if callable(scipy):
        cases["scipy Slerp + lerp"] = scipy
    for f in cases.values():
        f()
    log(f"core: one interpolate of 101 samples, {20 * repeats} interleaved repeats")
    medians = interleaved(cases, 20 * repeats)
    rows = [Row("core", f"{name}, 101 samples", f"{medians[name] * 1e6:.0f} µs") for name in cases]
    for mode, need in SINGLE_VS_SCIPY.items():
        if not callable(scipy):
            rows.append(Row("core", f"{mode} vs scipy", "scipy not installed"))
            continue
        ratio = medians[mode] / medians["scipy Slerp + lerp"]
        rows.append(
            Row(
                "core",
                f"one a2b.interpolate {mode} / scipy Slerp + lerp (time ratio)",
                "",
                f"{ratio:.2f}",
                f"≤ {need:g}",
                ratio <= need,
            )
        )
    starts, ends = random_pairs(jobs)
    builds = {
        "a2b.motion screw": lambda: a2b.motion(starts, ends, "screw"),
        "plain-NumPy ScLERP build": lambda: plain_sclerp_build(starts, ends),
    }
    for f in builds.values():
        f()
    frame = a2b.motion(starts[:100], ends[:100], "screw").frame
    theta, _, slide, _ = plain_sclerp_build(starts[:100], ends[:100])
    difference = max(np.abs(theta - frame.phi).max(), np.abs(slide - frame.d).max())
    log(f"same screws: plain-NumPy ScLERP build vs a2b's frames: max |difference| {difference:.1e}")
    log(f"core: the screw build of {jobs} pairs, {repeats} interleaved repeats")
    seconds = interleaved(builds, repeats)
    rows += [Row("core", f"{name} of {jobs} pairs", rate(jobs, seconds[name])) for name in builds]
    ratio = seconds["plain-NumPy ScLERP build"] / seconds["a2b.motion screw"]
    rows.append(
        Row(
            "core",
            "a2b screw build / plain-NumPy ScLERP build (rate ratio)",
            "",
            f"{ratio:.2f}",
            f"≥ {SCREW_VS_PLAIN:g}",
            ratio >= SCREW_VS_PLAIN,
        )
    )
    return rows


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
    return _motions_rows(medians, jobs, n, loop, sample_jobs)


def _motions_rows(medians: dict, jobs: int, n: int, loop: int, sample_jobs: int) -> list[Row]:
    pt3d = "pytransform3d batch ScLERP" in medians
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
    if pt3d:
        rows.append(
            Row(
                "motions",
                f"pytransform3d batch conversions + ScLERP of {jobs} pairs at t = 1/2",
                rate(jobs, medians["pytransform3d batch ScLERP"]),
            )
        )
        for mode, need in BUILD_VS_PYTRANSFORM3D.items():
            ratio = medians["pytransform3d batch ScLERP"] / medians[f"build {mode}"]
            rows.append(
                Row(
                    "motions",
                    f"a2b {mode} build + one sample vs pytransform3d (time ratio)",
                    "",
                    f"{ratio:.2f}×",
                    f"≥ {need:g}×",
                    ratio >= need,
                )
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
        for name, need in (
            ("a2b profiles alone (lengths known)", 0.2),
            ("a2b.timing, jerk-limited, constant speed", 0.4),  # issue 26: up from 0.2
        ):
            ratio = peer / times[name]
            rows.append(
                Row(
                    "timing",
                    f"{name} against Ruckig (rate ratio)",
                    f"{ratio:.2f}x",
                    f"{ratio:.2f}",
                    f">= {need:g}",
                    ratio >= need,
                )
            )
    else:
        rows.append(Row("timing", "Ruckig", "not installed: pip install ruckig"))
    return rows


def parse_arguments(argv: list[str] | None) -> argparse.Namespace:
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
        "--baseline",
        type=Path,
        help="a checkout of an earlier a2b (git worktree add /tmp/a727 a727f64): the csv "
        "section also times its CSV beside this one's (issue 26: at least 1.0x)",
    )
    parser.add_argument(
        "--blas-threads",
        type=int,
        help="limit BLAS threads in the library section (threadpoolctl); default: BLAS's own",
    )
    args = parser.parse_args(argv)
    if args.quick:
        args.samples, args.repeats, args.process_repeats, args.jobs = 100_000, 3, 2, 1_000
    args.sections = [s.strip() for s in args.only.split(",") if s.strip()]
    unknown = set(args.sections) - set(SECTIONS)
    if unknown:
        parser.error(f"unknown sections {', '.join(sorted(unknown))}")
    return args


def main(argv: list[str] | None = None) -> int:
    args = parse_arguments(argv)
    sections = args.sections

    info = machine()
    command = " ".join(["python", "benchmarks/run.py"] + (sys.argv[1:] if argv is None else argv))
    rows: list[Row] = []
    exe = a2b_command()
    compile_bytecode()
    if args.baseline is not None:  # as pip would have compiled it
        import compileall

        compileall.compile_dir(args.baseline / "a2b", quiet=1)
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
            if section == "core":
                rows += core_section(10 * args.jobs, args.repeats)
                continue
            if section == "motions":
                rows += motions_section(10 * args.jobs, args.samples, args.repeats)
                continue
            if section == "timing":
                rows += timing_section(10 * args.jobs, max(1, args.repeats // 2))
                continue
            if section == "datasets":
                rows += datasets_section(2 * args.jobs, args.process_repeats, work, exe)
                continue
            if section == "resample":
                rows += resample_section(args.samples, args.process_repeats, work, exe)
                continue
            if exe is None:
                rows.append(Row(section, "the a2b command is not installed", "not measured"))
                continue
            if section == "csv":
                rows += csv_section(args.samples, args.process_repeats, work, exe, args.baseline)[0]
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
