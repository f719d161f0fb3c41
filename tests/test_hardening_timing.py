"""What a new user tripped on in the time laws (issue 27): a duration with a speed limit, the
default law, the signs at the end, extreme limits, a pose to itself, one-line messages. Only
the public API (`a2b.timing`) and the command line."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

import a2b
from a2b.cli import cli
from a2b.errors import A2bError, ParameterError

ROOT = Path(__file__).resolve().parent.parent
SAMPLES = ROOT / "samples"
TOOL = """start:
  quaternion: {w: 1, x: 0, y: 0, z: 0}
  translation: [0, 0, 0]
end:
  quaternion: {w: 0.9659258262890683, x: 0, y: 0, z: 0.25881904510252074}
  translation: [0.6, 0.25, 0.0]
"""
SAME = """start:
  quaternion: {w: 0.8660254037844387, x: 0, y: 0, z: 0.5}
  translation: [0.2, 0, 0.5]
end:
  quaternion: {w: 0.8660254037844387, x: 0, y: 0, z: 0.5}
  translation: [0.2, 0, 0.5]
"""


def run(*args, input=None):
    return CliRunner().invoke(cli, list(map(str, args)), input=input)


def _tool(end=(0.6, 0.25, 0.0)):
    """A tool that moves 0.65 m in a straight line and turns 30°, as the user's tool.yaml."""
    b = np.eye(4)
    c, s = np.cos(np.pi / 6), np.sin(np.pi / 6)
    b[:3, :3] = [[c, -s, 0], [s, c, 0], [0, 0, 1]]
    b[:3, 3] = end
    return a2b.motion(np.eye(4), b, "screw")


def _one_line(message: str) -> None:
    assert "\n" not in message.strip() and len(message) < 300, message


# -- a duration with a speed limit -------------------------------------------------------------


@pytest.mark.parametrize("profile", ["trapezoid", "jerk-limited", "quintic", "linear"])
def test_a_duration_with_a_speed_limit_gives_a_law_of_that_duration(profile):
    motion = _tool()
    timed = a2b.timing(motion, profile, duration=2.0, max_speed=1.0)
    assert timed.duration == pytest.approx(2.0, rel=1e-14)
    assert timed.binding == "duration"
    rates = timed.rates(timed.times(samples=2001))
    assert np.max(rates["speed"]) <= 1.0
    if profile != "linear":  # rest to rest
        assert rates["speed"][0] == pytest.approx(0.0, abs=1e-12)
        assert rates["speed"][-1] == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize("profile", ["trapezoid", "jerk-limited"])
def test_the_users_command_runs(tmp_path, profile):
    tool = tmp_path / "tool.yaml"
    tool.write_text(TOOL)
    result = run("interpolate", tool, "--duration", 2, "--max-speed", 0.5, "--time-law", profile,
                 "--rate", 100)  # fmt: skip
    assert result.exit_code == 0, result.output
    rows = result.stdout.strip().splitlines()
    assert len(rows) == 202 and rows[-1].startswith("2.0,")


def test_a_duration_too_short_for_the_speed_limit_names_both():
    with pytest.raises(ParameterError) as info:
        a2b.timing(_tool(), "trapezoid", duration=1.0, max_speed=0.5)
    message = str(info.value)
    _one_line(message)
    assert re.search(r"speed limit \(max_speed, --max-speed\) needs at least 1\.9\d* s", message)
    assert "the duration 1 s is shorter" in message


def test_the_quarter_turn_in_2_s_under_0_5_m_per_s_is_refused_with_both_numbers():
    result = run("interpolate", SAMPLES / "quarter-turn.yaml", "--duration", 2, "--max-speed",
                 0.5, "--time-law", "trapezoid", "--rate", 100)  # fmt: skip
    assert result.exit_code == 1
    assert result.output.count("\n") == 1
    assert "needs at least 5.27" in result.output and "the duration 2 s is shorter" in result.output


# -- the default law ----------------------------------------------------------------------------


def test_a_speed_limit_alone_times_a_law_at_rest_at_both_ends():
    timed = a2b.timing(_tool(), max_speed=0.5)
    assert timed.profile.kind == "quintic"
    speeds = timed.rates(timed.times(samples=1001))["speed"]
    assert speeds[0] == 0.0 and speeds[-1] == pytest.approx(0.0, abs=1e-12)
    assert np.max(speeds) == pytest.approx(0.5, rel=1e-6)
    assert a2b.timing(_tool(), max_angular_speed=1.0).profile.kind == "quintic"
    assert a2b.timing(_tool(), duration=2.0).profile.kind == "linear"  # evenly in t


def test_the_default_law_is_stated_under_v(tmp_path):
    tool = tmp_path / "tool.yaml"
    tool.write_text(TOOL)
    result = run("interpolate", tool, "--max-speed", 0.5, "--rate", 10, "-v")
    assert result.exit_code == 0, result.output
    assert "time law quintic (--time-law to change)" in result.stderr


# -- signs at the end ---------------------------------------------------------------------------


@pytest.mark.parametrize("constant_speed", [False, True])
def test_acceleration_and_jerk_at_both_ends_take_the_laws_sign(constant_speed):
    motion = _tool()
    trapezoid = a2b.timing(motion, "trapezoid", max_speed=1.0, max_accel=2.0,
                           constant_speed=constant_speed)  # fmt: skip
    ends = np.array([0.0, trapezoid.duration])
    np.testing.assert_allclose(trapezoid.rates(ends)["accel"], [2.0, -2.0], rtol=1e-9)
    s_curve = a2b.timing(motion, "jerk-limited", max_speed=1.0, max_accel=2.0, max_jerk=5.0,
                         constant_speed=constant_speed)  # fmt: skip
    ends = np.array([0.0, s_curve.duration])
    rates = s_curve.rates(ends)
    np.testing.assert_allclose(rates["jerk"], [5.0, 5.0], rtol=1e-9)
    np.testing.assert_allclose(rates["accel"], [0.0, 0.0], atol=1e-9)


def test_the_end_is_continuous_with_the_times_before_it():
    timed = a2b.timing(_tool(), "trapezoid", max_speed=1.0, max_accel=2.0, constant_speed=True)
    end = timed.duration
    rates = timed.rates(np.array([end * (1 - 1e-9), end]))
    assert rates["accel"][0] == pytest.approx(rates["accel"][1], rel=1e-6)


# -- extreme limits ------------------------------------------------------------------------------


@pytest.mark.parametrize("value", [1e-300, 1e300, 1e-31, 1e31, -1.0, 0.0])
@pytest.mark.parametrize("name", ["speed", "accel", "jerk", "angular_speed", "angular_accel"])
def test_a_limit_out_of_range_names_the_option_the_value_and_the_range(name, value):
    profile = "quintic"
    with pytest.raises(ParameterError) as info:
        a2b.timing(_tool(), profile, **{f"max_{name}": value})
    message = str(info.value)
    _one_line(message)
    assert f"(max_{name}, --max-{name.replace('_', '-')}) is {value:g}" in message
    assert "usable values run from 1e-30 to 1e+30" in message


@pytest.mark.parametrize("value", [1e-30, 1e30])
def test_limits_at_the_ends_of_the_range_give_finite_laws(value):
    for kw in ({"max_speed": value}, {"max_accel": value}, {"max_jerk": value}):
        timed = a2b.timing(_tool(), "quintic", **kw)
        times = timed.times(samples=11)
        assert np.isfinite(timed.duration) and timed.duration > 0
        assert all(np.isfinite(v).all() for v in timed.rates(times).values())
        assert np.isfinite(timed.matrices(times)).all()


@pytest.mark.parametrize("option", ["--max-speed", "--max-jerk", "--duration"])
@pytest.mark.parametrize("value", ["1e-300", "1e300"])
def test_extreme_limits_on_the_command_line_are_one_line(option, value):
    extra = ["--max-speed", "1"] if option == "--duration" else []
    result = run("interpolate", SAMPLES / "quarter-turn.yaml", option, value, *extra,
                 "--rate", 10)  # fmt: skip
    assert result.exit_code == 1
    assert result.output.count("\n") == 1 and "usable values run from 1e-30" in result.output
    assert "NaN" not in result.output


# -- a pose to itself ----------------------------------------------------------------------------


@pytest.mark.parametrize("mode", ["darboux", "cubic", "screw"])
def test_constant_speed_from_a_pose_to_itself_is_refused_as_a_point_that_does_not_move(mode):
    pose = a2b.motion(np.eye(4), np.eye(4), "screw").matrices([0.0])[0]
    pose[:3, 3] = [0.2, 0.0, 0.5]
    motion = a2b.motion(pose, pose, mode)
    for point in (None, [1.0, 2.0, 3.0]):
        with pytest.raises(ParameterError, match="the point does not move") as info:
            a2b.timing(motion, max_speed=1.0, constant_speed=True, point=point)
        _one_line(str(info.value))
        with pytest.raises(ParameterError, match="does not move"):
            a2b.timing(motion, max_speed=1.0, point=point)  # no law of 1e-16 s either
        assert a2b.timing(motion, max_speed=1.0, duration=2.0, point=point).duration == 2.0


def test_constant_speed_from_a_pose_to_itself_on_the_command_line(tmp_path):
    same = tmp_path / "same.yaml"
    same.write_text(SAME)
    result = run("interpolate", same, "--constant-speed", "--max-speed", 1, "--rate", 10)
    assert result.exit_code == 1 and result.output.count("\n") == 1
    assert "the point does not move" in result.output


# -- every message one line ----------------------------------------------------------------------


def test_every_time_law_error_is_one_bounded_line():
    motion = _tool()
    batch = a2b.motion(np.stack([np.eye(4)] * 300), np.stack([np.eye(4)] * 300), "screw")
    cases = [
        lambda: a2b.timing(motion),
        lambda: a2b.timing(motion, "trapezoid", max_accel=1, max_jerk=1),
        lambda: a2b.timing(motion, "linear", max_accel=1),
        lambda: a2b.timing(motion, "cubic", duration=1),
        lambda: a2b.timing(motion, max_speed=np.nan),
        lambda: a2b.timing(motion, duration=-1.0),
        lambda: a2b.timing(batch, max_speed=1.0, constant_speed=True),
        lambda: a2b.timing(batch, max_speed=1.0),
        lambda: a2b.timing(motion, max_speed=0.1, duration=1.0),
    ]
    for case in cases:
        with pytest.raises(A2bError) as info:
            case()
        _one_line(str(info.value))
