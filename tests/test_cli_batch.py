"""``a2b batch``: many jobs in bounded chunks, errors and warnings that name their job, -v.

Through click's CliRunner."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import a2b
from a2b.io import csvtable, documents, poseschema

from .clirun import BATCH_SUFFIXES, SAMPLES, pose_json, run, run_split
from .conftest import random_pose


def _jobs(rng, n):
    jobs = []
    for i in range(n):
        a, b = random_pose(rng), random_pose(rng)
        job = {"start": pose_json(a), "end": pose_json(b), "samples": int(rng.integers(2, 6))}
        if i % 3 == 1:
            job["mode"] = "screw"
        if i % 3 == 2:
            job["parameters"] = {"delta": float(rng.normal())}
            job["name"] = f"job {i}, offset"
        jobs.append(job)
    return jobs


def _check_batch(jobs, out):
    with open(out, "rb") as f:
        names, values = csvtable.read_batch_csv(f)
    row = 0
    for i, job in enumerate(jobs):
        doc = documents.Document("x", None, lambda p: None)
        start = poseschema.pose_from_node(doc, (), job["start"])
        end = poseschema.pose_from_node(doc, (), job["end"])
        ts = np.linspace(0, 1, job["samples"])
        quat, trans = a2b.motion(
            start, end, job.get("mode", "darboux"), **job.get("parameters", {})
        ).quat_trans(ts)
        n = len(ts)
        assert names[row : row + n] == [job.get("name", f"job{i}")] * n
        assert np.array_equal(values[row : row + n, 0], ts)
        # batch builds the jobs together through the one core: the same to 1e-15 of their size
        scale = max(1.0, float(np.abs(trans).max()))
        np.testing.assert_allclose(values[row : row + n, 1:4], trans, rtol=0, atol=1e-15 * scale)
        np.testing.assert_allclose(values[row : row + n, 4:8], quat, rtol=0, atol=1e-15)
        row += n
    assert row == len(names)


@pytest.mark.parametrize("suffix", [".yaml", ".json", ".jsonl"])
def test_batch_more_jobs_than_one_chunk(tmp_path, rng, suffix):
    jobs = _jobs(rng, 8)
    path = tmp_path / f"jobs{suffix}"
    if suffix == ".jsonl":
        path.write_text("\n".join(json.dumps(j) for j in jobs) + "\n")
    else:
        path.write_text(json.dumps(jobs))
    out = tmp_path / "out.csv"
    result = run("batch", path, "--chunk-size", 3, "-o", out)
    assert result.exit_code == 0, result.output
    assert result.output == ""  # no progress bar when stderr is not a terminal
    assert out.read_text().splitlines()[0] == "job,t,tx,ty,tz,qw,qx,qy,qz"
    _check_batch(jobs, out)


def test_batch_streams_in_bounded_chunks(rng):
    from a2b.io.jobfiles import JobBlock
    from a2b.io.poseschema import Job
    from a2b.jobs import sample

    consumed = []

    def blocks():
        for i in range(3):
            consumed.append(i)
            jobs = [Job(random_pose(rng), random_pose(rng), samples=3) for _ in range(4)]
            yield JobBlock.from_jobs(jobs)

    pieces = sample(blocks())
    first = next(pieces)
    assert consumed == [0] and len(first.t) == 12
    assert [len(p.t) for p in pieces] == [12, 12]
    assert consumed == [0, 1, 2]


def test_batch_error_names_the_job_and_leaves_no_file(tmp_path, rng):
    jobs = _jobs(rng, 5)
    jobs[3]["parameters"] = {"lam": 1e-6}
    jobs[3]["mode"] = "darboux"
    path = tmp_path / "jobs.json"
    path.write_text(json.dumps(jobs))
    out = tmp_path / "out.csv"
    result = run("batch", path, "--chunk-size", 2, "-o", out)
    assert result.exit_code == 1
    assert "job job3: " in result.output
    assert not out.exists()
    assert [p.name for p in tmp_path.iterdir()] == ["jobs.json"]


def test_batch_sample_file():
    result = run("batch", SAMPLES / "jobs.yaml", "--format", "study")
    assert result.exit_code == 0
    lines = result.output.splitlines()
    assert lines[0] == "job,t,p0,p1,p2,p3,q0,q1,q2,q3"
    assert {line.split(",")[0] for line in lines[1:]} == {
        "lift",
        "lift_offset",
        "lift_cubic",
        "slide",
    }


def test_batch_progress_bar_only_on_a_terminal(monkeypatch):
    import sys

    from a2b.cli.batch import _progress

    monkeypatch.setattr(sys.stderr, "isatty", lambda: False, raising=False)
    with _progress(3) as progress:
        assert progress is None
    monkeypatch.setattr(sys.stderr, "isatty", lambda: True, raising=False)
    with _progress(3) as progress:
        assert progress is not None
        task = progress.add_task("jobs", total=3)
        progress.advance(task, 3)


def test_verbose_batch_names_the_job_of_each_choice():
    result = run_split("batch", SAMPLES / "jobs.yaml", "-v", "--mode", "darboux", "--samples", 3)
    assert result.exit_code == 0
    assert result.stderr.splitlines() == [
        "Choices a2b made:",
        f"  • format csv: the default (--format or an -o suffix {BATCH_SUFFIXES} to change)",
        "  • job lift_cubic: m defaults to pA + pB in canonical coordinates, so both weights are "
        "equal",
        "  • job slide: pure translation (φ = 0): the axis is the line through A's origin along "
        "the translation",
    ]


def test_batch_splits_a_large_job_into_bounded_chunks(rng):
    from a2b.io.jobfiles import JobBlock
    from a2b.io.poseschema import Job
    from a2b.jobs import sample

    jobs = [Job(random_pose(rng), random_pose(rng), samples=n) for n in (3, 25, 4)]
    pieces = list(sample([JobBlock.from_jobs(jobs)], rows=10))
    assert [len(p.t) for p in pieces] == [3, 10, 10, 5, 4]
    names = [name for p in pieces for name in p.job]
    assert names == ["job0"] * 3 + ["job1"] * 25 + ["job2"] * 4
    t = np.concatenate([p.t for p in pieces])
    assert np.array_equal(t[3:28], np.linspace(0, 1, 25))


def test_batch_names_the_job_whose_samples_overflow(tmp_path):
    path = tmp_path / "jobs.yaml"
    path.write_text(
        "- {name: fine, start: {quaternion_wxyz: [1, 0, 0, 0]}, "
        "end: {quaternion_wxyz: [1, 0, 0, 0]}, samples: 2}\n"
        "- "
        "{name: huge, start: {quaternion_wxyz: [1, 0, 0, 0]}, end: {quaternion_wxyz: [0, 0, 0, 1], "
        "translation: [0, 0, 1]}, "
        "parameters: {lam: 1e200}}\n"
    )
    result = run_split("batch", path, "-o", tmp_path / "o.csv")
    assert result.exit_code == 1
    assert result.stderr.startswith("Error: job huge: the motion's coefficients overflow float64")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["jobs.yaml"]


def test_batch_warnings_name_their_job(tmp_path):
    half = 0.5e-4
    job = (
        "  start: {quaternion_wxyz: [1, 0, 0, 0]}\n"
        f"  end: {{quaternion_wxyz: [{math.cos(half)!r}, 0, 0, {math.sin(half)!r}], translation: "
        f"[1, "
        f"0, 0]}}\n"
        "  parameters: {long_way: true}\n"
    )
    path = tmp_path / "jobs.yaml"
    path.write_text(f"- name: near\n{job}-\n{job}")
    result = run_split("batch", path, "--samples", 3)
    assert result.exit_code == 0
    lines = result.stderr.splitlines()
    assert len(lines) == 2
    assert lines[0].startswith("Warning: job near: the Darboux motion passes close to p(t) = 0")
    assert lines[1].startswith("Warning: job job1: the Darboux motion passes close to p(t) = 0")
