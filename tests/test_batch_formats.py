"""``a2b batch`` into every format of ``a2b interpolate``: tum and kitti as a directory with a
file per job, mcap as one file with a topic per job, each read back by its reader (the ``mcap``
package's reader for MCAP) and compared with the motion of each job built alone."""

from __future__ import annotations

import json

import numpy as np
import pytest
from click.testing import CliRunner
from mcap.reader import make_reader

import a2b
from a2b.cli import cli
from a2b.io import documents, mcapposes, poseschema, trajectories

from .conftest import random_pose


def run(*args):
    return CliRunner().invoke(cli, [str(a) for a in args], catch_exceptions=False)


def pose(matrix):
    quat, trans = a2b.poses.quat_trans_from_matrices(matrix)
    return {"quaternion_wxyz": quat.tolist(), "translation": trans.tolist()}


def make_jobs(rng, n=7):
    jobs = []
    for i in range(n):
        job = {"start": pose(random_pose(rng)), "end": pose(random_pose(rng))}
        job["samples"] = int(rng.integers(2, 9))
        if i % 3 == 1:
            job["mode"] = "cubic"
        if i % 3 == 2:
            job["name"] = f"joint {i}"
            job["parameters"] = {"delta": float(rng.normal())}
        jobs.append(job)
    return jobs


def alone(job, representation):
    """The samples of a job's motion built alone, the way a2b reads its poses."""
    doc = documents.Document("x", None, lambda p: None)
    start, end = (poseschema.pose_from_node(doc, (), job[k]) for k in ("start", "end"))
    motion = a2b.motion(start, end, job.get("mode", "darboux"), **job.get("parameters", {}))
    ts = np.linspace(0.0, 1.0, job["samples"])
    return ts, getattr(motion, representation)(ts)


def names(jobs):
    return [job.get("name", f"job{i}") for i, job in enumerate(jobs)]


@pytest.fixture
def jobs_file(tmp_path, rng):
    jobs = make_jobs(rng)
    path = tmp_path / "jobs.jsonl"
    path.write_text("".join(json.dumps(job) + "\n" for job in jobs))
    return path, jobs


def test_tum_writes_a_file_per_job(tmp_path, jobs_file):
    path, jobs = jobs_file
    out = tmp_path / "motions"
    result = run("batch", path, "--format", "tum", "--duration", 2.5, "--start-time", 10, "-o", out)
    assert result.exit_code == 0, result.output
    assert sorted(p.name for p in out.iterdir()) == sorted(f"{n}.tum" for n in names(jobs))
    for name, job in zip(names(jobs), jobs):
        with open(out / f"{name}.tum", "rb") as f:
            times, quat_wxyz, trans = trajectories.read_tum(f)
        ts, (quat, expected) = alone(job, "quat_trans")
        np.testing.assert_array_equal(times, ts * 2.5 + 10)
        np.testing.assert_allclose(trans, expected, rtol=0, atol=1e-15 * np.abs(expected).max())
        np.testing.assert_allclose(quat_wxyz, quat, rtol=0, atol=1e-15)


def test_kitti_writes_a_file_per_job(tmp_path, jobs_file):
    path, jobs = jobs_file
    out = tmp_path / "motions"
    out.mkdir()
    (out / "notes.txt").write_text("kept")
    result = run("batch", path, "--format", "kitti", "--chunk-size", 2, "-o", out)
    assert result.exit_code == 0, result.output
    assert (out / "notes.txt").read_text() == "kept"
    for name, job in zip(names(jobs), jobs):
        with open(out / f"{name}.kitti", "rb") as f:
            matrices = trajectories.read_kitti(f)
        _, expected = alone(job, "matrices")
        np.testing.assert_allclose(matrices, expected, rtol=0, atol=1e-15 * np.abs(expected).max())


def test_mcap_has_a_topic_per_job_read_by_the_mcap_reader(tmp_path, jobs_file):
    path, jobs = jobs_file
    out = tmp_path / "motions.mcap"
    result = run("batch", path, "--duration", 3, "--frame-id", "map", "-o", out)  # by suffix
    assert result.exit_code == 0, result.output
    with open(out, "rb") as f:
        reader = make_reader(f)
        summary = reader.get_summary()
        topics = {c.id: c.topic for c in summary.channels.values()}
        assert sorted(topics.values()) == sorted(f"/a2b/{n}/pose" for n in names(jobs))
        counts = {topics[i]: n for i, n in summary.statistics.channel_message_counts.items()}
        assert counts == {f"/a2b/{n}/pose": j["samples"] for n, j in zip(names(jobs), jobs)}
        got: dict = {}
        for _, channel, message in reader.iter_messages(log_time_order=True):
            got.setdefault(channel.topic, []).append(message)
    for name, job in zip(names(jobs), jobs):
        messages = got[f"/a2b/{name}/pose"]
        assert [m.sequence for m in messages] == list(range(job["samples"]))
        ts, (quat, trans) = alone(job, "quat_trans")
        assert [m.log_time for m in messages] == [round(t * 3e9) for t in ts]
        for m, q, x in zip(messages, quat, trans):
            data = json.loads(m.data)
            assert data["frame_id"] == "map"
            position = data["pose"]["position"]
            orientation = data["pose"]["orientation"]
            got_x = [position[k] for k in "xyz"]
            got_q = [orientation[k] for k in "wxyz"]
            np.testing.assert_allclose(got_x, x, rtol=0, atol=1e-15 * max(1, np.abs(x).max()))
            np.testing.assert_allclose(got_q, q, rtol=0, atol=1e-15)
        with open(out, "rb") as f:  # a2b's own reader, by topic
            t_read, trans_read, _ = mcapposes.read_mcap(f, topic=f"/a2b/{name}/pose")
        assert len(t_read) == job["samples"]


def test_a_failing_job_leaves_the_directory_as_it_was(tmp_path, jobs_file, rng):
    path, jobs = jobs_file
    jobs[5]["parameters"] = {"lam": 1e-6}
    jobs[5].pop("mode", None)
    path.write_text("".join(json.dumps(job) + "\n" for job in jobs))
    out = tmp_path / "motions"
    out.mkdir()
    (out / "0.tum").write_text("old")
    result = run("batch", path, "--format", "tum", "--chunk-size", 2, "-o", out)
    assert result.exit_code == 1
    assert "job joint 5: amplitude" in result.output
    assert [p.name for p in out.iterdir()] == ["0.tum"]
    assert (out / "0.tum").read_text() == "old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["jobs.jsonl", "motions"]


@pytest.mark.parametrize("fmt", ["tum", "kitti", "mcap"])
def test_two_jobs_of_one_name_are_refused(tmp_path, rng, fmt):
    jobs = make_jobs(rng, 4)
    jobs[1]["name"] = "arm"
    jobs[3]["name"] = "arm"
    path = tmp_path / "jobs.json"
    path.write_text(json.dumps(jobs))
    out = tmp_path / ("out.mcap" if fmt == "mcap" else "out")
    result = run("batch", path, "--format", fmt, "-o", out)
    assert result.exit_code == 1
    assert "job 'arm' (job 3): an earlier job has this name" in result.output
    assert not out.exists()


def test_the_index_of_a_job_counts_as_its_name(tmp_path, rng):
    jobs = make_jobs(rng, 3)
    jobs[2]["name"] = "job0"  # job 0 has no name: it is called job0
    path = tmp_path / "jobs.json"
    path.write_text(json.dumps(jobs))
    result = run("batch", path, "--format", "kitti", "-o", tmp_path / "out")
    assert result.exit_code == 1
    assert "job 'job0' (job 2)" in result.output


@pytest.mark.parametrize("name", ["a/b", "..", "", "x" * 300])
def test_a_name_that_is_no_file_name_is_refused(tmp_path, rng, name):
    jobs = make_jobs(rng, 2)
    jobs[1]["name"] = name
    path = tmp_path / "jobs.json"
    path.write_text(json.dumps(jobs))
    result = run("batch", path, "--format", "tum", "-o", tmp_path / "out")
    assert result.exit_code == 1
    assert "cannot be a file name" in result.output and "rename the job" in result.output
    assert not (tmp_path / "out").exists()
    assert [p.name for p in tmp_path.iterdir()] == ["jobs.json"]


def test_a_directory_format_needs_a_directory(tmp_path, jobs_file):
    path, _ = jobs_file
    result = run("batch", path, "--format", "kitti")
    assert result.exit_code == 2
    assert "kitti writes one file per job: give a directory with -o DIR" in result.output
    (tmp_path / "file").write_text("mine")
    result = run("batch", path, "--format", "tum", "-o", tmp_path / "file")
    assert result.exit_code == 1
    assert "it is a file, not a directory" in result.output
    assert (tmp_path / "file").read_text() == "mine"
    result = run("batch", path, "-o", tmp_path)
    assert result.exit_code == 2
    assert "is a directory" in result.output


def test_a_failing_move_into_the_directory_changes_nothing(tmp_path, jobs_file, monkeypatch):
    """The files of a batch are moved into DIR all or none: a move that fails after others
    (here the fourth) takes the moved ones back and restores the files they replaced."""
    import os

    path, jobs = jobs_file
    out = tmp_path / "motions"
    out.mkdir()
    old = {"0.tum": "old 0", "1.tum": "old 1", "keep.txt": "mine"}
    for name, text in old.items():
        (out / name).write_text(text)
    real, moves = os.replace, []

    def failing(src, dst):
        if str(dst).startswith(str(out)) and str(src).startswith(str(tmp_path / ".motions")):
            moves.append(dst)
            if len(moves) == 4:
                raise OSError(28, "No space left on device")
        return real(src, dst)

    monkeypatch.setattr(os, "replace", failing)
    result = run("batch", path, "--format", "tum", "-o", out)
    assert result.exit_code == 1 and "No space left on device" in result.output
    assert {p.name: p.read_text() for p in out.iterdir()} == old
    assert sorted(p.name for p in tmp_path.iterdir()) == ["jobs.jsonl", "motions"]


def test_a_directory_in_the_way_is_refused_before_any_file_moves(tmp_path, jobs_file):
    path, _ = jobs_file
    out = tmp_path / "motions"
    (out / "job1.tum").mkdir(parents=True)
    (out / "0.tum").write_text("old")
    result = run("batch", path, "--format", "tum", "-o", out)
    assert result.exit_code == 1
    assert "'job1.tum' already there as a directory" in result.output
    assert (out / "0.tum").read_text() == "old"
    assert sorted(p.name for p in out.iterdir()) == ["0.tum", "job1.tum"]


def test_batch_refuses_options_its_format_does_not_take(tmp_path, jobs_file):
    path, _ = jobs_file
    result = run("batch", path, "--frame-id", "map", "-o", tmp_path / "m.csv")
    assert result.exit_code == 2 and "--frame-id: not for csv output" in result.output
    result = run("batch", path, "--duration", 2, "--format", "kitti", "-o", tmp_path / "k")
    assert result.exit_code == 2 and "--duration: not for kitti output" in result.output
    assert sorted(p.name for p in tmp_path.iterdir()) == ["jobs.jsonl"]


def test_batch_help_says_what_ros2_writes():
    result = run("batch", "-h")
    assert "PoseStamped per job" in result.output
    assert "TFMessage" not in result.output and "Path" not in result.output.split("--profile")[1]
