"""ROS 2 topic and frame names: the rules of rmw_validate_full_topic_name and tf2, each broken
rule named, and batch's per-job topics checked (issue 28)."""

from __future__ import annotations

import pytest
from click.testing import CliRunner

from a2b.cli import cli
from a2b.errors import ParameterError
from a2b.io import ros2

LONGEST = "/" + "a" * (ros2.MAX_TOPIC_LENGTH - 1)


def test_the_limit_is_rmws():
    assert ros2.MAX_TOPIC_LENGTH == 247  # RMW_TOPIC_MAX_NAME_LENGTH: 255 less 8 for prefixes


@pytest.mark.parametrize("topic", ["/a2b/pose", "/a/b_2/c", "/x", "/_a/B9", LONGEST])
def test_topics_ros_2_accepts(topic):
    assert ros2.check_topic(topic) == topic


@pytest.mark.parametrize(
    ("topic", "problem"),
    [
        ("", "it is empty"),
        ("a2b/pose", "it must start with /"),
        ("/a2b/pose/", "it must not end with /"),
        ("/", "it must not end with /"),
        ("/a-b", "it holds '-'; only ASCII letters, digits, _ and / are allowed"),
        ("/a b", "it holds ' '"),
        ("/pós", "it holds 'ó'"),
        ("/a\x1b[31m", r"it holds '\\x1b'"),
        ("/a2b//pose", "it must not hold //"),
        ("/a2b/2nd/pose", "a part between slashes starts with a digit"),
        (LONGEST + "b", "it has 248 characters; ROS 2 allows at most 247"),
    ],
)
def test_topics_ros_2_refuses_name_the_rule(topic, problem):
    with pytest.raises(ParameterError, match="is not a ROS 2 topic name: " + problem) as e:
        ros2.check_topic(topic)
    assert "\n" not in str(e.value) and len(str(e.value)) < 200


@pytest.mark.parametrize(
    ("frame", "problem"),
    [
        ("", "it is empty"),
        ("/world", "it must not start with /"),
        ("my body", "whitespace"),
        ("a\x00b", "unprintable"),
    ],
)
def test_frame_ids_tf2_refuses(frame, problem):
    with pytest.raises(ParameterError, match="is not a ROS 2 frame id: .*" + problem):
        ros2.check_frame_id(frame)
    assert ros2.check_frame_id("base_link") == "base_link"


def test_a_frame_id_of_a_megabyte_makes_a_short_message():
    with pytest.raises(ParameterError) as e:
        ros2.check_frame_id("/" + "w" * 10**6)
    assert len(str(e.value)) < 200 and "(1000001 characters)" in str(e.value)


def test_a_job_name_too_long_for_a_topic_is_one_error_and_no_file(tmp_path):
    """`/a2b/{name}/pose` of a 300-character name has 310 characters: refused, naming the job."""
    pose = "{matrix: [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}"
    name = "n" * 300
    jobs = tmp_path / "jobs.yaml"
    jobs.write_text(f"- {{name: ok, start: {pose}, end: {pose}}}\n"
                    f"- {{name: {name}, start: {pose}, end: {pose}}}\n")  # fmt: skip
    out = tmp_path / "j.mcap"
    result = CliRunner().invoke(cli, ["batch", str(jobs), "--format", "ros2", "-o", str(out)])
    assert result.exit_code == 1
    error = result.output.strip()
    assert error.count("\n") == 0 and len(error) < 300, error
    assert "(300 characters): the topic '/a2b/nnn" in error
    assert "it has 310 characters; ROS 2 allows at most 247" in error
    assert not out.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["jobs.yaml"]
