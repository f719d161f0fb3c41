"""The time grid (a2b.timelaw.grid) and the new times of `a2b resample --rate` (a2b.resample
NewTimes): offsets computed arithmetically, exact ends, integer-nanosecond stamps, huge counts
lazily, and spans that a double cannot count or resolve refused at once."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

import a2b
from a2b.cli import cli
from a2b.errors import ParameterError
from a2b.resample import NewTimes
from a2b.timelaw.grid import MOST_TIMES, TimeGrid, nanoseconds

ROOT = Path(__file__).resolve().parent.parent


def run(*args, input=None):
    return CliRunner().invoke(cli, list(map(str, args)), input=input)


def _all(grid: TimeGrid, size: int = 7) -> np.ndarray:
    return np.concatenate([offsets for _, offsets in grid.blocks(size)])


# -- the grid ---------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "duration, rate, count",
    [(1.0, 100.0, 101), (1.005, 100.0, 102), (0.3, 10.0, 4), (2.0, 3.0, 7), (1e-3, 1e6, 1001)],
)
def test_a_law_is_sampled_every_step_and_exactly_at_its_end(duration, rate, count):
    grid = TimeGrid.covering(duration, rate=rate)
    times = _all(grid)
    assert grid.count == count == len(times)
    assert times[0] == 0.0 and times[-1] == duration
    np.testing.assert_array_equal(times[:-1], np.arange(count - 1) / rate)
    assert np.all(np.diff(times) > 0)


def test_blocks_of_any_size_give_the_same_times_and_their_indices():
    grid = TimeGrid.covering(1.2345, dt=0.01)
    whole = grid.offsets(0, grid.count)
    for size in (1, 2, 5, 64, 1000):
        blocks = list(grid.blocks(size))
        assert [lo for lo, _ in blocks] == list(range(0, grid.count, size))
        np.testing.assert_array_equal(np.concatenate([b for _, b in blocks]), whole)
    assert whole[-1] == 1.2345


def test_samples_are_evenly_spaced_like_linspace():
    grid = TimeGrid.covering(3.7, samples=11)
    np.testing.assert_allclose(_all(grid), np.linspace(0.0, 3.7, 11), rtol=0, atol=1e-15)
    assert _all(grid)[-1] == 3.7


def test_a_timed_motion_gives_its_grid_and_times():
    motion = a2b.motion(np.eye(4), np.diag([1.0, 1.0, 1.0, 1.0]) + np.eye(4, k=3) * 0.0, "screw")
    end = np.eye(4)
    end[:3, 3] = [0.4, 0.1, 0.0]
    timed = a2b.timing(a2b.motion(np.eye(4), end, "screw"), "linear", duration=2.5)
    grid = timed.grid(rate=100, origin=1700000000.5)
    assert grid.count == 251 and grid.origin_ns == 1700000000500000000
    np.testing.assert_array_equal(timed.times(rate=100), grid.offsets(0, grid.count))
    assert motion.shape == ()


def test_whole_nanosecond_steps_give_exact_integer_stamps():
    grid = TimeGrid.covering(1e4, rate=200.0, origin=1700000000.123)
    assert grid.step_ns == 5_000_000
    assert grid.origin_ns == 1_700_000_000_123_000_000
    index = np.array([0, 1, 2, 10**6 - 1, 2 * 10**6 - 1, grid.count - 1])
    stamps = grid.stamps_ns(index)
    assert stamps.dtype == np.int64
    np.testing.assert_array_equal(stamps[:-1], grid.origin_ns + index[:-1] * 5_000_000)
    assert stamps[-1] == grid.origin_ns + 10**13
    # and the float offsets round back to them
    offsets = grid.offsets(0, 2 * 10**6)
    np.testing.assert_array_equal(
        np.rint(offsets * 1e9).astype(np.int64), np.arange(2 * 10**6) * 5_000_000
    )


def test_a_step_that_is_no_whole_number_of_nanoseconds_is_rounded_per_time():
    grid = TimeGrid.covering(1.0, rate=3.0)
    assert grid.step_ns is None
    np.testing.assert_array_equal(
        grid.stamps_ns(np.arange(grid.count)), [0, 333333333, 666666667, 1000000000]
    )


def test_nanoseconds_follow_the_decimal_a_user_wrote():
    assert nanoseconds(1700000000.123) == 1700000000123000000
    assert nanoseconds(0.1) == 100000000
    assert nanoseconds(-2.5) == -2500000000
    with pytest.raises(ParameterError, match="finite number of seconds"):
        nanoseconds(float("inf"))


def test_a_huge_grid_is_lazy_and_its_last_block_is_exact():
    grid = TimeGrid.covering(1e6, rate=1e9)  # 10^15 + 1 times
    assert grid.count == 10**15 + 1
    lo, first = next(iter(grid.blocks(4096)))
    assert lo == 0 and len(first) == 4096 and first[1] == 1e-9
    last = grid.offsets(grid.count - 3, grid.count)
    assert last[-1] == 1e6 and np.all(np.diff(last) > 0)
    assert grid.stamps_ns([grid.count - 1])[0] == 10**15


@pytest.mark.parametrize("duration, rate", [(1e7, 1e9), (1e30, 200.0), (1.0, 1e300)])
def test_more_times_than_a_double_counts_are_refused_in_one_line(duration, rate):
    with pytest.raises(ParameterError, match=r"more than 2\*\*53") as info:
        TimeGrid.covering(duration, rate=rate)
    assert "\n" not in str(info.value) and len(str(info.value)) < 200


def test_bad_steps_and_counts_are_refused():
    with pytest.raises(ParameterError, match="time step must be a positive number"):
        TimeGrid.covering(1.0, dt=0.0)
    with pytest.raises(ParameterError, match="time step must be a positive number"):
        TimeGrid.covering(1.0, rate=float("inf"))
    with pytest.raises(ParameterError, match="duration must be a positive number"):
        TimeGrid.covering(float("nan"), rate=1.0)
    with pytest.raises(ParameterError, match="2 to 2\\*\\*53 samples"):
        TimeGrid.covering(1.0, samples=1)
    with pytest.raises(ParameterError, match="1 to 2\\*\\*53 times"):
        TimeGrid(0, 1.0, MOST_TIMES + 1)


def test_stamps_beyond_int64_nanoseconds_are_refused():
    grid = TimeGrid.covering(1e10, rate=1.0, origin=0.0)
    with pytest.raises(ParameterError, match=r"below 2\*\*63 \(the year 2262\)"):
        grid.stamps_ns([grid.count - 1])


def test_upto_counts_arithmetically_with_no_loop():
    grid = TimeGrid.at_rate(100.0, 5.0)
    assert grid.upto(4.99, 5.0) == 0
    assert grid.upto(5.0, 5.0) == 1
    assert grid.upto(6.0, 5.0) == 101  # 5 + 100 · 0.01 is 6.0 exactly
    assert grid.upto(6.004, 5.0) == 101
    with pytest.raises(ParameterError, match=r"more than 2\*\*53"):
        grid.upto(1e30, 5.0)


# -- the new times of resample --rate -----------------------------------------------------------


def test_new_times_from_unix_stamps_have_exact_nanosecond_steps():
    """Stamps near 1.7e9 s: the doubles are 238 ns apart there, so the times as doubles step
    unevenly; their stamps in integer nanoseconds step by exactly 5,000,000 ns."""
    start = 1700000000.25
    new = NewTimes(rate=200.0)
    times = np.concatenate(list(new.upto(start + 30.0, start)))
    assert len(times) == 6001 and times[0] == start
    stamps = new.stamps_ns(times)
    assert stamps[0] == 1_700_000_000_250_000_000
    assert set(np.diff(stamps).tolist()) == {5_000_000}
    assert len(set(np.diff(np.rint(times * 1e9).astype(np.int64)).tolist())) > 1  # why


def test_new_times_continue_across_windows():
    new = NewTimes(rate=10.0)
    first = np.concatenate(list(new.upto(1.05, 0.0)))
    second = np.concatenate(list(new.upto(2.0, 0.9)))  # the window's start does not matter
    np.testing.assert_array_equal(np.concatenate([first, second]), np.arange(21) / 10.0)
    assert list(new.upto(None, None)) == []
    assert new.described() == "21 new times from 0.0 s every 1/10 s"


def test_new_times_that_a_double_cannot_tell_apart_are_refused():
    new = NewTimes(rate=1e9)
    with pytest.raises(ParameterError, match="cannot be told apart near") as info:
        list(new.upto(1700000001.0, 1700000000.0))
    assert "\n" not in str(info.value)


def _tum(path: Path, times) -> Path:
    lines = [f"{t!r} {i * 0.1} 0 0 0 0 0 1" for i, t in enumerate(times)]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_resample_at_a_rate_a_double_cannot_resolve_is_one_line_and_writes_nothing(tmp_path):
    src = _tum(tmp_path / "unix.tum", [1700000000.0, 1700000000.5, 1700000001.0])
    out = tmp_path / "out.tum"
    result = run("resample", src, "--rate", "1e9", "-o", out)
    assert result.exit_code == 1, result.output
    assert result.output.count("\n") == 1 and "cannot be told apart" in result.output
    assert not out.exists()


def test_resample_over_a_span_of_1e30_seconds_is_refused_at_once(tmp_path):
    """The old grid loop stalled here (end ± 1 does not change 1e30 in a double)."""
    src = _tum(tmp_path / "far.tum", [0.0, 1e30])
    code = (
        "import sys; from a2b.cli import cli; "
        f"sys.argv = ['a2b', 'resample', {str(src)!r}, '--rate', '200', '-o', "
        f"{str(tmp_path / 'out.tum')!r}]; cli()"
    )
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, timeout=60, cwd=ROOT
    )
    assert done.returncode == 1, done.stderr
    assert done.stderr.count("\n") == 1 and "more than 2**53" in done.stderr
    assert not (tmp_path / "out.tum").exists()


def test_a_timed_motion_keeps_huge_grids_out_of_memory():
    end = np.eye(4)
    end[:3, 3] = [0.4, 0.1, 0.0]
    timed = a2b.timing(a2b.motion(np.eye(4), end, "screw"), max_speed=0.5)
    grid = timed.grid(rate=1e9)  # 10^9 times a second: lazily
    assert grid.count == int(np.floor(timed.duration * 1e9 + 1e-9)) + 2
    assert next(iter(grid.blocks(8)))[1][-1] == 7e-9
    with pytest.raises(ParameterError, match="more than times\\(\\) holds in memory") as info:
        timed.times(rate=1e9)
    assert "\n" not in str(info.value)
