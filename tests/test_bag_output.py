"""``--format ros2 --storage sqlite3`` (issue 28): a rosbag2 bag folder with a .db3 and its
metadata.yaml, holding the same CDR messages as a2b's ROS 2 MCAP output, read by rosbags'
AnyReader and evo, and by a2b itself; written whole or not at all."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from a2b.cli import cli
from a2b.io.mcapreader import McapFile
from tests.conftest import evo_full_check

SAMPLES = Path(__file__).resolve().parent.parent / "samples"
TURN = SAMPLES / "quarter-turn.yaml"


def run(*args):
    return CliRunner().invoke(cli, [str(a) for a in args])


def _mcap_messages(path) -> dict:
    """``{topic: [(log time, bytes)]}`` of an MCAP file, read by a2b's reader."""
    mcap = McapFile(Path(path).read_bytes(), str(path))
    found = mcap.messages(list(mcap.channels))
    return {
        channel.topic: list(zip(found[key].log_time.tolist(), found[key].as_bytes()))
        for key, channel in mcap.channels.items()
    }


def _bag_messages(path) -> dict:
    """``{topic: [(log time, bytes)]}`` of a bag, read by rosbags' AnyReader."""
    from rosbags.highlevel import AnyReader

    found: dict = {}
    with AnyReader([Path(path)]) as reader:
        for connection, timestamp, data in reader.messages():
            found.setdefault(connection.topic, []).append((timestamp, bytes(data)))
            reader.deserialize(data, connection.msgtype)  # rosbags decodes every message
    return found


@pytest.mark.parametrize(
    "args",
    [
        ["--samples", "7", "--duration", "3", "--start-time", "1700000000.25"],
        ["--time-law", "trapezoid", "--velocities", "--rate", "10", "--frame-id", "map",
         "--child-frame-id", "base_link"],
    ],
    ids=["motion", "timed-with-velocities"],
)  # fmt: skip
def test_the_bag_holds_the_messages_of_the_mcap_output(tmp_path, args):
    pytest.importorskip("rosbags")
    mcap, bag = tmp_path / "turn.mcap", tmp_path / "turn"
    assert run("interpolate", TURN, "--format", "ros2", "-o", mcap, *args).exit_code == 0
    result = run("interpolate", TURN, "--format", "ros2", "--storage", "sqlite3", "-o", bag, *args)
    assert result.exit_code == 0, result.output
    assert sorted(os.listdir(bag)) == ["metadata.yaml", "turn_0.db3"]
    theirs, ours = _bag_messages(bag), _mcap_messages(mcap)
    topics = {"/a2b/pose", "/tf", "/a2b/path"} | (
        {"/a2b/twist"} if "--velocities" in args else set()
    )
    assert set(theirs) == set(ours) == topics
    for topic in topics:
        assert theirs[topic] == ours[topic], topic


def test_a2b_reads_its_sqlite_bag_as_its_mcap(tmp_path):
    mcap, bag = tmp_path / "turn.mcap", tmp_path / "turn"
    for target, storage in ((mcap, []), (bag, ["--storage", "sqlite3"])):
        made = run("interpolate", TURN, "--format", "ros2", "--samples", 9, "-o", target, *storage)
        assert made.exit_code == 0, made.output
    out = {}
    for source in (mcap, bag, bag / "turn_0.db3"):
        target = tmp_path / f"{source.name}.csv"
        result = run("resample", source, "--rate", 8, "-o", target)
        assert result.exit_code == 0, result.output
        out[source] = target.read_text()
    assert out[mcap] == out[bag] == out[bag / "turn_0.db3"]
    assert len(out[mcap].splitlines()) == 10


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--storage", "sqlite3"], "--storage: not for csv output"),
        (["--format", "tum", "--storage", "mcap"], "--storage: not for tum output"),
        (["--format", "ros2", "--storage", "sqlite3"], "writes a bag folder: give its path"),
        (["--format", "ros2", "--storage", "sqlite3", "--frame-id", "/w", "-o", "{tmp}/bag"],
         "--frame-id '/w' is not a ROS 2 frame id"),
    ],
)  # fmt: skip
def test_what_a_bag_cannot_be_is_refused_and_nothing_is_left(tmp_path, args, message):
    args = [a.format(tmp=tmp_path) for a in args]
    result = run("interpolate", TURN, *args)
    assert result.exit_code != 0 and message in result.output, result.output
    assert os.listdir(tmp_path) == []


def test_the_python_api_writes_a_bag(tmp_path):
    import a2b

    motion = a2b.motion(np.eye(4), np.diag([1.0, -1.0, -1.0, 1.0]))
    a2b.write(motion, tmp_path / "bag", "ros2", samples=4, storage="sqlite3")
    with open(tmp_path / "bag" / "bag_0.db3", "rb") as f:
        path = a2b.io.trajectories.read_trajectory(f, fmt="rosbag2", topic="/a2b/pose")
    ns = np.rint(path.times * 1e9)  # stamps of whole nanoseconds
    assert np.array_equal(ns, [0, 333_333_333, 666_666_667, 10**9])
    with pytest.raises(a2b.errors.OptionError, match="--storage: not for mcap output"):
        a2b.write(motion, tmp_path / "x.mcap", samples=4, storage="sqlite3")


def test_evo_reads_the_sqlite_bag_with_a_full_check(tmp_path, clients):
    bag = tmp_path / "turn"
    result = run("interpolate", TURN, "--format", "ros2", "--storage", "sqlite3", "--samples",
                 200, "--duration", 4, "-o", bag)  # fmt: skip
    assert result.exit_code == 0, result.output
    out = evo_full_check(clients, str(bag), tmp_path)
    assert "nr. of poses\t200" in out and "duration (s)\t4.0" in out


def test_a_batch_bag_holds_the_messages_of_the_batch_mcap(tmp_path):
    pytest.importorskip("rosbags")
    jobs = SAMPLES / "jobs.yaml"
    mcap, bag = tmp_path / "jobs.mcap", tmp_path / "jobs"
    assert run("batch", jobs, "--format", "ros2", "--samples", 5, "-o", mcap).exit_code == 0
    result = run("batch", jobs, "--format", "ros2", "--storage", "sqlite3", "--samples", 5,
                 "-o", bag)  # fmt: skip
    assert result.exit_code == 0, result.output
    theirs, ours = _bag_messages(bag), _mcap_messages(mcap)
    names = ("lift", "lift_offset", "lift_cubic", "slide")
    assert set(theirs) == set(ours) == {f"/a2b/{name}/pose" for name in names}
    for topic in theirs:
        assert theirs[topic] == ours[topic], topic


def test_a_batch_bag_with_a_job_name_too_long_is_one_error_and_no_folder(tmp_path):
    pose = "{matrix: [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}"
    jobs = tmp_path / "jobs.yaml"
    jobs.write_text(f"- {{name: {'n' * 300}, start: {pose}, end: {pose}}}\n")
    result = run("batch", jobs, "--format", "ros2", "--storage", "sqlite3", "-o", tmp_path / "b")
    assert result.exit_code == 1
    assert "it has 310 characters; ROS 2 allows at most 247" in result.output
    assert result.output.count("\n") == 1
    assert sorted(os.listdir(tmp_path)) == ["jobs.yaml"]
