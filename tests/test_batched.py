"""The vectorised path for many jobs (``a2b.motions.batched``, block reading, ``a2b batch``).

Every job the vectorised path takes must be the job that :func:`a2b.motion` builds on its own:
the same table, the same choices, no warning and no error, and samples within 1e-15 of the
job's size. Every job it does not take must be one that a2b.motion refuses, warns about, or
decides near a threshold. Reading in blocks must give the jobs and the errors of reading one
by one, and ``a2b batch`` the chunks, choices, warnings and errors of its per-job loop.
"""

from __future__ import annotations

import io
import itertools
import json
import math
import warnings

import numpy as np
import pytest
from click.testing import CliRunner
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import a2b
from a2b.cli import cli, options
from a2b.errors import A2bError, A2bWarning, InputFileError
from a2b.io import jobscan, readers, writers
from a2b.motions.batched import motions, screw_frames, valid_poses
from a2b.poses import check_matrices, matrices_from_quat_trans

from .conftest import random_pose

#: Samples must agree to this, relative to the size of the job's values.
RTOL = 1e-15
TS = np.linspace(0.0, 1.0, 101)


# -- poses: generic ones and every edge case of the screw frame --------------------------------


def half_turn(axis, translation, start=None):
    """A start pose and the half-turn about ``axis`` (through the origin) after it."""
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    turn = matrices_from_quat_trans(np.concatenate([[0.0], axis]), translation)
    start = np.eye(4) if start is None else start
    return start, turn @ start


def rotated(start, angle, axis, translation):
    """``start`` moved by a rotation of ``angle`` about ``axis`` and then ``translation``."""
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    quat = np.concatenate([[math.cos(angle / 2)], math.sin(angle / 2) * axis])
    return matrices_from_quat_trans(quat, translation) @ start


def edge_pairs(rng) -> list[tuple[np.ndarray, np.ndarray, str]]:
    """(start, end, what) for φ = 0, B = A, half turns, φ = π, tiny and rounding-size turns."""
    a = random_pose(rng)
    out = [(a, a.copy(), "B = A"), (np.eye(4), np.eye(4), "B = A = I")]
    b = a.copy()
    b[:3, 3] += [1.0, -2.0, 0.5]
    out.append((a, b, "pure translation"))
    out.append(
        (np.eye(4), matrices_from_quat_trans([1, 0, 0, 0], [0, 0, 3]), "translation along z")
    )
    for axis in ([0, 0, 1], [1, 0, 0], [0, 1, 1], [0, -1, 1], [0, 0, -1], [-1, 2, 0.5]):
        for translation in ([0, 0, 1], [0, 0, -1], [1, 0, 0], [0, 0, 0], [2, -1, 3]):
            s, e = half_turn(axis, translation)
            out.append((s, e, f"half turn {axis} {translation}"))
    s, e = half_turn([0.3, -0.4, 0.5], [1, 2, 3], start=random_pose(rng))
    out.append((s, e, "half turn after a random pose"))
    for angle in (math.pi, math.pi - 1e-15, math.pi - 1e-9, -math.pi + 1e-12, 3.0, 1e-3, 1e-9):
        out.append((a, rotated(a, angle, rng.normal(size=3), rng.normal(size=3)), f"angle {angle}"))
    for angle in (1e-15, 2e-15, 4e-16, 1e-17):
        out.append((a, rotated(a, angle, [0, 0, 1], [1, 0, 0]), f"rounding-size angle {angle}"))
    out.append((a, rotated(a, 1e-15, [0, 0, 1], [0, 0, 0]), "rounding-size angle, no translation"))
    out.append((a, rotated(a, 2.0, [1, 1, 0], [1e8, 0, 0]), "far translation"))
    out.append((a, rotated(a, 2.0, [1, 1, 0], [1e155, 0, 0]), "huge translation"))
    out.append((a, rotated(a, 2.0, [1, 1, 0], [1e307, 1e307, 0]), "overflowing translation"))
    return out


def random_pairs(rng, n):
    return [(random_pose(rng), random_pose(rng, scale=3.0), "random") for _ in range(n)]


def stacked(pairs):
    return np.stack([p[0] for p in pairs]), np.stack([p[1] for p in pairs])


# -- comparing a batch with the jobs on their own ----------------------------------------------


def single(start, end, mode, **params):
    """``(motion or None, error or None, warnings)`` of a2b.motion."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            motion = a2b.motion(start, end, mode, **params)
        except A2bError as e:
            return None, e, caught
    return motion, None, caught


def assert_close(batch_values, single_values, what):
    scale = max(1.0, float(np.max(np.abs(single_values), initial=0.0)))
    error = float(np.max(np.abs(batch_values - single_values), initial=0.0))
    assert error <= RTOL * scale, f"{what}: differs by {error:.3g} at scale {scale:.3g}"


def check_batch(pairs, mode, params_of, **batch_params):
    """Compare ``motions(...)`` with ``a2b.motion`` job by job; return the ok mask."""
    start, end = stacked(pairs)
    batch = motions(start, end, mode, **batch_params)
    quat, trans = batch.quat_trans(TS)
    mats = batch.matrices(TS)
    study = batch.study(TS)
    for j, (a, b, what) in enumerate(pairs):
        motion, error, caught = single(a, b, mode, **params_of(j))
        if error is not None or caught:
            assert not batch.ok[j], (what, error, caught)
            continue
        if not batch.ok[j]:
            continue
        label = f"{mode} job {j} ({what})"
        assert list(batch.choices[j]) == motion.choices, label
        assert_close(batch.table[j], motion.table, label + " table")
        q1, t1 = motion.quat_trans(TS)
        assert_close(quat[j], q1, label + " quaternions")
        assert_close(trans[j], t1, label + " translations")
        assert_close(study[j], motion.study(TS), label + " study")
        if batch.matrices_ok[j]:
            assert_close(mats[j], motion.matrices(TS), label + " matrices")
    return batch.ok


MODES = [
    ("darboux", {}),
    ("darboux", {"delta": "random"}),
    ("screw", {}),
    ("cubic", {}),
    ("cubic", {"frame": "given"}),
    ("cubic", {"m": "random", "a": "random", "b": "random"}),
    ("cubic", {"m": "random", "a": "random", "frame": "given"}),
]


def parameters(rng, jobs, spec):
    """Per-job arrays for ``motions`` and the per-job keyword arguments for ``a2b.motion``."""
    arrays = {}
    for key, value in spec.items():
        if value != "random":
            arrays[key] = value
        elif key == "m":
            arrays[key] = rng.normal(size=(jobs, 4))
        elif key == "delta":
            arrays[key] = rng.normal(size=jobs)
        else:
            arrays[key] = rng.uniform(-0.6, 2.0, size=jobs)

    def params_of(j):
        out = {}
        for key, value in arrays.items():
            if key == "frame":
                out[key] = value
            elif key == "m":
                out[key] = tuple(value[j])
            else:
                out[key] = float(value[j])
        return out

    return arrays, params_of


@pytest.mark.parametrize(
    "mode, spec", MODES, ids=[f"{m}-{'-'.join(s) or 'defaults'}" for m, s in MODES]
)
def test_random_jobs_are_the_single_motions_and_all_vectorised(rng, mode, spec):
    pairs = random_pairs(rng, 150)
    arrays, params_of = parameters(rng, len(pairs), spec)
    ok = check_batch(pairs, mode, params_of, **arrays)
    if mode != "cubic" or "m" not in spec:  # with a random m, a2b.motion refuses some
        assert ok.all()


@pytest.mark.parametrize(
    "mode, spec", MODES, ids=[f"{m}-{'-'.join(s) or 'defaults'}" for m, s in MODES]
)
def test_edge_cases_are_the_single_motions(rng, mode, spec):
    pairs = edge_pairs(rng)
    arrays, params_of = parameters(rng, len(pairs), spec)
    ok = check_batch(pairs, mode, params_of, **arrays)
    covered = [
        j
        for j, (_, _, what) in enumerate(pairs)
        if what.startswith(("B = A", "pure translation", "translation along", "half turn"))
        or what in ("angle 3.0", "angle 0.001", "angle 1e-09", "rounding-size angle 1e-17")
    ]
    if mode != "cubic" or "m" not in spec:
        assert ok[covered].all(), [pairs[j][2] for j in covered if not ok[j]]


def test_the_frame_choices_are_those_of_screw_frame(rng):
    from a2b.frames import screw_frame

    pairs = edge_pairs(rng) + random_pairs(rng, 20)
    frames = screw_frames(*stacked(pairs))
    made = set()
    for j, (a, b, what) in enumerate(pairs):
        if not frames.ok[j]:
            continue
        frame = screw_frame(check_matrices(a), check_matrices(b))
        assert list(frames.choices[j]) == frame.choices, what
        for name in ("phi", "d", "axis_direction", "axis_point", "r", "p_start", "p_end", "h_start",
                     "h_end", "t_start", "t_end", "t_disp"):  # fmt: skip
            np.testing.assert_array_equal(
                getattr(frames, name)[j], getattr(frame, name), err_msg=what
            )
        made.update(choice[:12] for choice in frame.choices)
    # every kind of choice the frame makes was made here, by the vectorised path
    assert made == {"flipped the ", "the rotation", "φ = π (|pA·p", "pure transla", "B = A: the a"}


def test_half_turn_rule_chooses_like_the_single_frame():
    """d > 0, d < 0 and d = 0 with each sign of the first axis component."""
    from a2b.frames import screw_frame

    cases = [half_turn(axis, t) for axis in ([0, 0, 1], [0, 0, -1], [0, -1, 1], [0, 1, -1], [-1, 0, 0])
             for t in ([0, 0, 2], [0, 0, -2], [1, 1, 0])]  # fmt: skip
    frames = screw_frames(np.stack([c[0] for c in cases]), np.stack([c[1] for c in cases]))
    assert frames.ok.all()
    for j, (a, b) in enumerate(cases):
        frame = screw_frame(a, b)
        assert list(frames.choices[j]) == frame.choices
        assert frames.phi[j] == frame.phi == math.pi
        assert frames.d[j] == frame.d and frames.d[j] >= 0
        np.testing.assert_array_equal(frames.axis_direction[j], frame.axis_direction)


# -- what the vectorised path leaves to a2b.motion ----------------------------------------------


def test_singular_and_sensitive_cubic_motions_are_left_to_the_single_path():
    """p(t) → 0 (refused or warned), x0(t) = 0, m orthogonal to a pose, m = 0, non-finite."""
    a = np.eye(4)
    cases, params = [], []
    for theta in (1e-3, 1e-4, 1e-8):  # wB = −wA: p(t) passes near 0 at t = ½
        b = rotated(a, theta, [0, 0, 1], [1, 0, 0])
        m0 = 1.0
        m3 = -m0 * (1 + math.cos(theta / 2)) / math.sin(theta / 2)
        cases.append((a, b))
        params.append({"m": (m0, 0.0, 0.0, m3), "frame": "canonical"})
    b = rotated(a, 1.0, [0, 0, 1], [1, 0, 0])
    for p in ({"a": -1.0}, {"a": -1.5, "b": 0.5}, {"m": (0.0, 1.0, 0.0, 0.0)},
              {"m": (0.0, 0.0, 0.0, 0.0)}, {"a": float("nan")}, {"m": (1.0, float("inf"), 0.0, 0.0)}):  # fmt: skip
        cases.append((a, b))
        params.append(p)
    start, end = np.stack([c[0] for c in cases]), np.stack([c[1] for c in cases])
    for frame in ("canonical", "given"):
        for j, p in enumerate(params):
            p = dict(p, frame=p.get("frame", frame))
            batch = motions(
                start[j : j + 1], end[j : j + 1], "cubic",
                m=None if "m" not in p else np.array([p["m"]]),
                a=np.array([p.get("a", 0.0)]), b=np.array([p.get("b", 0.0)]), frame=p["frame"],
            )  # fmt: skip
            _, error, caught = single(start[j], end[j], "cubic", **p)
            if error is not None or caught:
                assert not batch.ok[0], (p, error, caught)


def test_invalid_poses_and_parameters_are_not_ok(rng):
    good = random_pose(rng)
    stretched = good.copy()
    stretched[:3, 2] *= 2.0
    reflection = np.diag([-1.0, 1.0, 1.0, 1.0])
    start = np.stack([good, good, good, stretched, reflection, np.full((4, 4), np.nan)])
    end = np.stack([random_pose(rng) for _ in range(6)])
    delta = np.array([0.0, np.nan, np.inf, 0.0, 0.0, 0.0])
    batch = motions(start, end, "darboux", delta=delta)
    assert batch.ok.tolist() == [True, False, False, False, False, False]
    for j in range(1, 6):
        with pytest.raises(A2bError):
            a2b.motion(start[j], end[j], "darboux", delta=float(delta[j]))


def test_valid_poses_accepts_only_what_check_matrices_accepts(rng):
    poses = np.stack([random_pose(rng) for _ in range(200)])
    noise = rng.normal(size=poses.shape) * np.exp(rng.uniform(-30, -15, size=(200, 1, 1)))
    noise[:, 3, :] = 0.0
    noisy = poses + noise
    ok = valid_poses(noisy)
    assert 0 < ok.sum() < 200
    for j in np.flatnonzero(ok):
        check_matrices(noisy[j])


def test_no_jobs_one_job_and_take(rng):
    empty = motions(np.empty((0, 4, 4)), np.empty((0, 4, 4)), "cubic")
    assert len(empty) == 0 and empty.quat_trans(TS)[0].shape == (0, 101, 4)
    pairs = random_pairs(rng, 5)
    batch = motions(*stacked(pairs), "screw")
    one = batch.take([3])
    np.testing.assert_array_equal(one.table[0], batch.table[3])
    np.testing.assert_array_equal(one.quat_trans(TS)[1][0], batch.quat_trans(TS)[1][3])
    with pytest.raises(ValueError, match="unknown mode"):
        motions(*stacked(pairs), "bezier")
    with pytest.raises(ValueError, match=r"\(J, 4, 4\)"):
        motions(np.eye(4), np.eye(4))
    with pytest.raises(ValueError, match="ts in"):
        batch.quat_trans([0.0, 1.5])


# -- reading in blocks --------------------------------------------------------------------------


def outcome(read):
    """The jobs that ``read()`` gives before it stops, and its error message (or None)."""
    jobs = []
    try:
        jobs.extend(read())
    except InputFileError as e:
        return jobs, str(e)
    return jobs, None


def assert_same_jobs(got, expected):
    assert len(got) == len(expected)
    for g, e in zip(got, expected):
        np.testing.assert_array_equal(g.start, e.start)
        np.testing.assert_array_equal(g.end, e.end)
        assert (g.mode, g.samples, g.name) == (e.mode, e.samples, e.name)
        assert g.parameters.keys() == e.parameters.keys()
        for key, value in e.parameters.items():
            np.testing.assert_array_equal(g.parameters[key], value)


def compare_readers(data: bytes, name: str, sizes=(1, 2, 3, 256)):
    """Blocks of every size, read here and (JSON Lines) scanned ahead by a helper process
    in blocks of two, give the jobs and the error of reading one by one."""
    expected = outcome(lambda: readers.read_jobs(io.BytesIO(data), name))
    for size, ahead in [(size, False) for size in sizes] + [(3, True)]:

        def blocks(size=size, ahead=ahead):
            stream = io.BytesIO(data)
            sniffed = jobscan.sniff(stream, name)
            scanned = None
            if ahead and sniffed.json_lines:
                scanned = jobscan.scan_ahead(stream, sniffed, 2)
                assert scanned is not None
            jobs = readers.read_jobs(stream, name, sniffed=sniffed, scanned=scanned)
            for block in jobs.blocks(size):
                assert 0 < len(block) <= size
                yield from block.jobs()

        try:
            got = outcome(blocks)
        except InputFileError as e:  # raised by read_jobs itself, before any job
            got = [], str(e)
        assert got[1] == expected[1], (name, size, ahead, data[:200])
        assert_same_jobs(got[0], expected[0])


def outcome_or_error(data, name):
    try:
        return outcome(lambda: readers.read_jobs(io.BytesIO(data), name))
    except InputFileError as e:
        return [], str(e)


POSE_TEXTS = [
    '{"quaternion": [1, 0, 0, 0]}',
    '{"quaternion": [0.5, 0.5, -0.5, 0.5], "translation": [1, 2, 3]}',
    '{"quaternion": {"w": 2, "x": 0, "y": 0, "z": 1}, "translation": {"x": 1, "y": -2, "z": 0.25}}',
    '{"quaternion_xyzw": [0, 0, 0.7071067811865476, 0.7071067811865476], "translation": [0, 0, 1]}',
    '{"matrix": [[0, -1, 0, 1], [1, 0, 0, 2], [0, 0, 1, 3], [0, 0, 0, 1]]}',
    '{"matrix": [[0, -1, 0, 1], [1, 0, 0, 2], [0, 0, 1, 3], [0, 0, 0, 1]], "layout": "robotics"}',
    '{"matrix": [[1, 0, 0, 0], [0.5, 1, 0, 0], [0.25, 0, 1, 0], [0, 0, 0, 1]], "layout": "paper"}',
    '{"study": [1, 0, 0, 0, 0, -0.5, 0, 0]}',
    # unusual or invalid: the exact path decides
    '{"quaternion": [0, 0, 0, 0]}',
    '{"quaternion": [NaN, 0, 0, 0]}',
    '{"quaternion": [1e999, 0, 0, 0]}',
    '{"quaternion": [1' + "0" * 400 + ", 0, 0, 0]}",
    '{"quaternion": [true, 0, 0, 0]}',
    '{"quaternion": ["1", 0, 0, 0]}',
    '{"quaternion": [1, 0, 0]}',
    '{"quaternion": {"w": 1, "x": 0, "y": 0}}',
    '{"quaternion": {"w": 1, "x": 0, "y": 0, "q": 0}}',
    '{"quaternion": [1, 0, 0, 0], "translation": null}',
    '{"quaternion": [1, 0, 0, 0], "translation": [1, 2, 3], "layout": "robotics"}',
    '{"quaternion": [1, 0, 0, 0], "quaternion": [0, 0, 0, 1]}',
    '{"matrix": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 2, 0], [0, 0, 0, 1]]}',
    '{"matrix": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0], [1e-300, 0, 0, 1]]}',
    '{"matrix": [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1.0000000006, 0], [0, 0, 0, 1]]}',
]
JOB_EXTRAS = [
    "",
    ', "name": "lift"',
    ', "name": 7',
    ', "name": "a:b"',
    ', "name": true',
    ', "mode": "screw", "samples": 3',
    ', "mode": "cubic", "parameters": {"m": [1, 0, 0, 0.5], "a": 0.1, "b": -0.2, "frame": "given"}',
    ', "parameters": {"delta": -0.0}',
    ', "parameters": {"delta": 0.2, "delta": 0.3}',
    ', "parameters": {"lam": 2, "branch": -1.0}',
    ', "parameters": {"long_way": true, "kappa": null}',
    ', "parameters": {"through": {"quaternion": [1, 0, 0, 0]}}',
    ', "parameters": []',
    ', "parameters": 0',
    ', "parameters": {"delta": "0.2"}',
    ', "parameters": {"m": [1, 0, 0]}',
    ', "samples": 1',
    ', "samples": 2.0',
    ', "mode": "bezier"',
    ', "start": {"quaternion": [1, 0, 0, 0]}',
    ', "extra": 1',
]


@st.composite
def job_lines(draw):
    lines = []
    for _ in range(draw(st.integers(1, 7))):
        start = draw(st.sampled_from(POSE_TEXTS))
        end = draw(st.sampled_from(POSE_TEXTS[:8]))
        extra = draw(st.sampled_from(JOB_EXTRAS))
        line = f'{{"start": {start}, "end": {end}{extra}}}'
        lead = draw(st.sampled_from(["", "", "", " ", "\t"]))
        trail = draw(st.sampled_from(["", "", " ", "\r", " x"]))
        lines.append(lead + line + trail)
        if draw(st.integers(0, 5)) == 0:
            lines.append(draw(st.sampled_from(["", "  ", "{", "[1]"])))
    return lines


@settings(max_examples=300, derandomize=True, database=None, deadline=None,
          suppress_health_check=list(HealthCheck))  # fmt: skip
@given(job_lines(), st.booleans())
def test_json_lines_blocks_are_the_jobs_and_errors_of_reading_one_by_one(lines, bom):
    data = ("\ufeff" if bom else "") + "\n".join(lines) + "\n"
    compare_readers(data.encode(), "jobs.jsonl")


@settings(max_examples=200, derandomize=True, database=None, deadline=None,
          suppress_health_check=list(HealthCheck))  # fmt: skip
@given(job_lines(), st.sampled_from(["jobs.json", "jobs.yaml", "<stdin>"]))
def test_list_blocks_are_the_jobs_and_errors_of_reading_one_by_one(lines, name):
    items = [line.strip() for line in lines if line.strip().startswith('{"start"')]
    data = "[" + ",\n".join(items) + "]\n"
    compare_readers(data.encode(), name, sizes=(1, 3, 256))


def test_fuzzed_jobs_files_read_the_same_in_blocks():
    """The malformed files of tests/test_fuzz.py: the same message, the same jobs before it."""
    from .test_fuzz import written

    @settings(max_examples=400, derandomize=True, database=None, deadline=None,
              suppress_health_check=list(HealthCheck))  # fmt: skip
    @given(written("jobs"))
    def run(case):
        name, data, _ = case
        compare_readers(data, name, sizes=(1, 2, 256))

    run()


def test_a_duplicate_key_in_json_lines_is_found_in_blocks():
    good = '{"start": {"quaternion": [1, 0, 0, 0]}, "end": {"quaternion": [1, 0, 0, 0]}}'
    twice = '{"start": {"quaternion": [1, 0, 0, 0], "translation": [1, 2, 3], "translation": [0, 0, 0]}, "end": {"quaternion": [1, 0, 0, 0]}}'
    data = f"{good}\n{twice}\n".encode()
    blocks = readers.read_jobs(io.BytesIO(data), "j.jsonl").blocks(8)
    assert len(next(blocks)) == 1  # the job before the one with the duplicate key
    with pytest.raises(InputFileError, match=r"^j\.jsonl:2:66: duplicate key 'translation'$"):
        next(blocks)


# -- a2b batch: the per-job loop, job by job -----------------------------------------------------


def reference_chunks(jobs, mode, samples, representation, chunk_size, report=None):
    """The per-job loop of ``a2b batch`` before the vectorised path (its chunks and reports)."""
    from a2b.io.writers import CHUNK_SAMPLES, Chunk

    parts, rows, done = [], 0, 0

    def flush():
        nonlocal rows
        rows = 0
        fields = {}
        for key in ("t", "quat_wxyz", "trans", "matrices", "study"):
            values = [getattr(c, key) for _, c in parts]
            fields[key] = None if values[0] is None else np.concatenate(values)
        job_column = [name for name, c in parts for _ in range(len(c.t))]
        parts.clear()
        return Chunk(job=job_column, **fields)

    for index, job in enumerate(jobs):
        name = job.name if job.name is not None else str(index)
        try:
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always", A2bWarning)
                motion = a2b.motion(job.start, job.end, job.mode or mode, **job.parameters)
            for warning in caught:
                warnings.warn_explicit(f"job {name}: {warning.message}", warning.category,
                                       warning.filename, warning.lineno)  # fmt: skip
            if report is not None:
                report(name, motion.choices)
            for chunk in options.motion_chunks(motion, job.samples or samples, representation):
                parts.append((name, chunk))
                rows += len(chunk.t)
                if rows >= CHUNK_SAMPLES:
                    yield flush()
        except A2bError as e:
            raise type(e)(f"job {name}: {e}") from e
        done += 1
        if done == chunk_size:
            if parts:
                yield flush()
            done = 0
    if parts:
        yield flush()


def run_chunks(function, jobs, *args):
    """Chunks, reports, warnings and the error of a batch_chunks-like generator."""
    reports = []
    chunks = []
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            chunks.extend(
                function(jobs, *args, report=lambda name, made: reports.append((name, list(made))))
            )
            error = None
        except A2bError as e:
            error = (type(e), str(e))
    return chunks, reports, [(w.category, str(w.message)) for w in caught], error


def concatenated(chunks):
    """The rows of all chunks: job names, t, and each field, in order."""
    out = {
        "job": [name for c in chunks for name in c.job],
        "t": np.concatenate([c.t for c in chunks]),
    }
    for key in ("quat_wxyz", "trans", "matrices", "study"):
        if getattr(chunks[0], key) is not None:
            out[key] = np.concatenate(
                [np.asarray(getattr(c, key)).reshape(len(c.t), -1) for c in chunks]
            )
    return out


def assert_same_rows(got, expected):
    """The same rows, job by job (each within RTOL of its own size), whatever the chunks."""
    g, e = concatenated(got), concatenated(expected)
    assert g["job"] == e["job"]
    np.testing.assert_array_equal(g["t"], e["t"])
    assert g.keys() == e.keys()
    for key in set(e) - {"job", "t"}:
        start = 0
        for name, run in itertools.groupby(e["job"]):
            n = sum(1 for _ in run)
            assert_close(g[key][start : start + n], e[key][start : start + n], f"{key} of {name}")
            start += n


def assert_bounded(chunks, chunk_size, limit, balance):
    """Chunks of at most ``chunk_size`` jobs, ending once they hold ``limit`` rows, and within
    ``balance`` rows unless one job's rows alone exceed it."""
    for c in chunks:
        runs = [sum(1 for _ in run) for _, run in itertools.groupby(c.job)]
        assert len(runs) <= chunk_size
        assert len(c.t) - runs[-1] < limit
        assert len(c.t) <= balance or len(runs) == 1


def mixed_jobs(rng, n=40, samples=(2, 3, 5, 17)):
    """Jobs of every mode and kind of parameter, the edge cases among them, some by name."""
    from a2b.io.readers import Job

    pairs = edge_pairs(rng)[:-1] + random_pairs(rng, n)  # (the overflowing job errors: below)
    kinds = [
        (None, {}), ("darboux", {"delta": 0.3}), ("darboux", {"delta": -0.0}), ("screw", {}),
        ("cubic", {}), ("cubic", {"frame": "given"}), ("cubic", {"m": (1.0, 0.2, -0.1, 0.5), "a": 0.2}),
        ("cubic", {"m": (0.5, 0.0, 0.0, 1.0), "b": -0.3, "frame": "given"}),
        ("darboux", {"lam": 5.0}), ("darboux", {"long_way": False}), ("cubic", {"alpha": (0, 0, 0, 0, 0, 0.1)}),
        ("darboux", {"kappa": None, "delta": 0.1}),
    ]  # fmt: skip
    jobs = []
    for i, (a, b, _) in enumerate(pairs):
        mode, params = kinds[int(rng.integers(len(kinds)))]
        count = int(rng.choice(samples)) if rng.random() < 0.7 else None
        name = f"j{i}" if rng.random() < 0.5 else None
        jobs.append(Job(a, b, mode=mode, samples=count, parameters=dict(params), name=name))
    return jobs


def good_jobs(jobs):
    """The jobs that a2b.motion builds without an error (in order)."""
    return [
        j for j in jobs if single(j.start, j.end, j.mode or "darboux", **j.parameters)[1] is None
    ]


@pytest.mark.parametrize("representation", ["quat_trans", "matrices", "study"])
@pytest.mark.parametrize("chunk_size", [1, 4, 1024])
def test_batch_chunks_are_those_of_the_per_job_loop(rng, representation, chunk_size, monkeypatch):
    from a2b.cli.batch import batch_chunks

    monkeypatch.setattr(writers, "CHUNK_SAMPLES", 40)  # jobs of 41 samples stream in pieces
    jobs = good_jobs(mixed_jobs(rng, samples=(2, 3, 7, 41)))
    got = run_chunks(batch_chunks, jobs, "darboux", 5, representation, chunk_size)
    expected = run_chunks(reference_chunks, jobs, "darboux", 5, representation, chunk_size)
    assert got[1:] == expected[1:]  # reports, warnings, no error
    assert got[3] is None
    assert_same_rows(got[0], expected[0])
    assert_bounded(got[0], chunk_size, 40, 2**20)


@pytest.mark.parametrize("representation", ["quat_trans", "matrices"])
def test_chunks_of_about_one_writer_task(rng, representation, monkeypatch):
    """Chunks end before a job would take them past one task of the writer (here 60 numbers)."""
    from a2b.cli.batch import _COLUMNS, batch_chunks

    monkeypatch.setattr(writers, "TASK", 60 * _COLUMNS[representation])
    jobs = good_jobs(mixed_jobs(rng, samples=(2, 3, 7, 41, 90)))
    got = run_chunks(batch_chunks, jobs, "darboux", 5, representation, 16)
    expected = run_chunks(reference_chunks, jobs, "darboux", 5, representation, 16)
    assert got[1:] == expected[1:]
    assert_same_rows(got[0], expected[0])
    assert_bounded(got[0], 16, writers.CHUNK_SAMPLES, 60)
    assert max(len(c.t) for c in got[0]) > 40  # some chunks are full


@pytest.mark.parametrize(
    "fail", ["cubic a = -1", "m orthogonal", "overflow", "lam too small", "bad pose"]
)
def test_a_failing_job_stops_the_run_as_in_the_per_job_loop(rng, fail):
    from a2b.cli.batch import batch_chunks
    from a2b.io.readers import Job

    jobs = good_jobs(mixed_jobs(rng, n=10))
    a, b = random_pose(rng), random_pose(rng)
    bad = {
        "cubic a = -1": Job(a, b, mode="cubic", parameters={"a": -1.0}, name="bad"),
        "m orthogonal": Job(np.eye(4), b, mode="cubic", parameters={"m": (0.0, 1.0, 0.0, 0.0), "frame": "given"}),
        "overflow": Job(a, rotated(a, 2.0, [0, 0, 1], [1.0, 0, 0]), parameters={"delta": 1.5e308}),
        "lam too small": Job(a, b, parameters={"lam": 1e-9}),
        "bad pose": Job(a, np.ones((4, 4))),
    }[fail]  # fmt: skip
    jobs.insert(7, bad)
    got = run_chunks(batch_chunks, jobs, "darboux", 4, "quat_trans", 3)
    expected = run_chunks(reference_chunks, jobs, "darboux", 4, "quat_trans", 3)
    assert got[3] is not None and got[3] == expected[3]
    assert got[1:3] == expected[1:3]
    # the chunks before the error: rows of the jobs before it, as the per-job loop samples them
    before = run_chunks(reference_chunks, jobs[:7], "darboux", 4, "quat_trans", 3)[0]
    rows = sum(len(c.t) for c in got[0])
    assert rows < sum(len(c.t) for c in before)
    if rows:
        assert_same_rows(got[0], [truncated(before, rows)])


def truncated(chunks, rows: int):
    """One chunk of the first ``rows`` rows of ``chunks``."""
    from a2b.io.writers import Chunk

    all_rows = concatenated(chunks)
    fields = {k: all_rows[k][:rows] for k in ("quat_wxyz", "trans") if k in all_rows}
    return Chunk(all_rows["t"][:rows], job=all_rows["job"][:rows], **fields)


def test_warnings_name_their_job_as_in_the_per_job_loop(rng):
    from a2b.cli.batch import batch_chunks
    from a2b.io.readers import Job

    theta = 1e-4
    b = rotated(np.eye(4), theta, [0, 0, 1], [1, 0, 0])
    m3 = -(1 + math.cos(theta / 2)) / math.sin(theta / 2)
    jobs = good_jobs(mixed_jobs(rng, n=6))
    jobs.insert(
        3, Job(np.eye(4), b, mode="cubic", parameters={"m": (1.0, 0.0, 0.0, m3)}, name="near")
    )
    jobs.insert(5, Job(np.eye(4), rotated(np.eye(4), 1e-9, [0, 0, 1], [1, 0, 0]), mode="cubic",
                       parameters={"a": 0.5}, name="axis"))  # fmt: skip
    got = run_chunks(batch_chunks, jobs, "darboux", 4, "quat_trans", 8)
    expected = run_chunks(reference_chunks, jobs, "darboux", 4, "quat_trans", 8)
    assert [w for w in expected[2] if w[0] is A2bWarning]  # the jobs do warn
    assert got[1:] == expected[1:]
    assert_same_rows(got[0], expected[0])


def write_jobs(path, jobs):
    def pose(m):
        return {"matrix": m.tolist()}

    with open(path, "w") as f:
        for job in jobs:
            doc = {"start": pose(job.start), "end": pose(job.end)}
            for key in ("mode", "samples", "name"):
                if getattr(job, key) is not None:
                    doc[key] = getattr(job, key)
            if job.parameters:
                doc["parameters"] = {
                    k: list(v) if isinstance(v, tuple) else v for k, v in job.parameters.items()
                }
            f.write(json.dumps(doc) + "\n")


@pytest.mark.parametrize("fmt", ["csv", "matrix", "study"])
def test_batch_command_verbose_choices_and_rows_are_job_by_job(rng, tmp_path, fmt):
    jobs = good_jobs(mixed_jobs(rng, n=30))
    path = tmp_path / "jobs.jsonl"
    write_jobs(path, jobs)
    result = CliRunner().invoke(
        cli, ["batch", str(path), "-v", "--format", fmt, "--chunk-size", "7"]
    )
    assert result.exit_code == 0, result.output
    reports = []

    def report(name, made):
        reports.extend(f"  • job {name}: {c}" for c in made)

    with open(path, "rb") as f:
        expected_choices = list(
            reference_chunks(
                readers.read_jobs(f), "darboux", 101, writers.REPRESENTATION[fmt], 7, report
            )
        )
    lines = result.stderr.splitlines()
    assert lines[0] == "Choices a2b made:"
    assert [line for line in lines if line.startswith("  • job ")] == reports
    names, values = readers.read_batch_csv(io.BytesIO(result.stdout.encode()))
    expected_names = [n for c in expected_choices for n in c.job]
    assert names == expected_names
    rows = np.concatenate([writers._rows(fmt, c) for c in expected_choices])
    start = 0
    for _, run in itertools.groupby(names):
        n = sum(1 for _ in run)
        assert_close(values[start : start + n], rows[start : start + n], names[start])
        start += n


def test_a_job_whose_vectorised_samples_are_not_finite_is_sampled_on_its_own(rng, monkeypatch):
    """(No finite table of [0, 1] gives such samples; the check stays, and hands the job on.)"""
    from a2b.cli.batch import batch_chunks
    from a2b.motions.batched import MotionBatch

    sample = MotionBatch.quat_trans

    def spoiled(self, ts):
        quat, trans = sample(self, ts)
        if len(self) > 2:
            trans[2, 5, 1] = np.inf
        return quat, trans

    monkeypatch.setattr(MotionBatch, "quat_trans", spoiled)
    jobs = good_jobs(mixed_jobs(rng, n=12))
    got = run_chunks(batch_chunks, jobs, "darboux", 4, "quat_trans", 6)
    expected = run_chunks(reference_chunks, jobs, "darboux", 4, "quat_trans", 6)
    assert got[1:] == expected[1:]
    assert_same_rows(got[0], expected[0])


def test_einsum_order_check_tells_the_orders_apart():
    """The values the einsum check uses give another sum for each other order of the four
    squares, so the check can fail; and it agrees with einsum here."""
    from a2b.motions import batched

    k = np.arange(2048.0)
    q = (np.sin(1.7 * k) * np.exp(4.0 * np.cos(0.37 * k))).reshape(512, 4)
    s = q * q
    pairs = (s[:, 0] + s[:, 2]) + (s[:, 1] + s[:, 3])
    others = [
        ((s[:, 0] + s[:, 1]) + s[:, 2]) + s[:, 3],
        (s[:, 0] + s[:, 1]) + (s[:, 2] + s[:, 3]),
        (s[:, 0] + s[:, 3]) + (s[:, 1] + s[:, 2]),
    ]
    assert all((other != pairs).any() for other in others)
    assert batched._einsum_order() == np.array_equal(np.einsum("ij,ij->i", q, q), pairs)
