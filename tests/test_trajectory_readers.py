"""The trajectory readers (``a2b.io.trajectories`` and one module per format), as a careless
user and an attacker meet them: columns read by their names, text oddities reported at their
line, every a2b output read back, and options that do not apply refused."""

from __future__ import annotations

import io

import numpy as np
import pytest
from click.testing import CliRunner

from a2b.cli import cli
from a2b.errors import InputFileError
from a2b.io import csvtable
from a2b.io.textrows import read_times
from a2b.io.trajectories import read_trajectory

IDENTITY = [1.0, 0.0, 0.0, 0.0]


def read(text: str | bytes, name: str = "t.csv", **options):
    data = text.encode() if isinstance(text, str) else text
    return read_trajectory(io.BytesIO(data), name, **options)


def run(*args):
    return CliRunner().invoke(cli, [str(a) for a in args], catch_exceptions=False)


# -- columns by name --------------------------------------------------------------------------


@pytest.mark.parametrize(
    "header",
    [
        "#timestamp [ns],tx,ty,tz,qx,qy,qz,qw",
        "#timestamp [ns],p_RS_R_x [m],p_RS_R_y [m],p_RS_R_z [m],q_RS_x [],q_RS_y [],q_RS_z [],"
        "q_RS_w []",
    ],
)
def test_a_euroc_header_in_another_order_is_read_by_its_names(header):
    """Read by position, ``qx,qy,qz,qw`` made the identity a half turn."""
    path = read(f"{header}\n1000000000,1,2,3,0,0,0,1\n2000000000,4,5,6,0,0,0,1\n")
    assert path.fmt == "euroc"
    assert path.quat_wxyz.tolist() == [IDENTITY, IDENTITY]
    assert path.trans.tolist() == [[1, 2, 3], [4, 5, 6]]
    assert path.times.tolist() == [1.0, 2.0]


def test_an_a2b_csv_with_its_columns_in_another_order():
    path = read("qx,qy,qz,qw,t,tx,ty,tz\n0,0,0,1,0.5,1,2,3\n0,0,1,0,1.5,4,5,6\n")
    assert path.fmt == "csv"
    assert path.times.tolist() == [0.5, 1.5]
    assert path.quat_wxyz.tolist() == [IDENTITY, [0, 0, 0, 1]]
    assert path.trans.tolist() == [[1, 2, 3], [4, 5, 6]]


def test_a_stamp_in_seconds_by_its_unit():
    path = read("#timestamp [s],tx,ty,tz,qw,qx,qy,qz\n0.25,0,0,0,1,0,0,0\n0.5,0,0,0,1,0,0,0\n")
    assert path.times.tolist() == [0.25, 0.5]


def test_unknown_and_missing_names_are_an_error_naming_them():
    with pytest.raises(InputFileError) as e:
        read("#timestamp [ns],tx,ty,tz,qx,qy,qz,speed\n1,0,0,0,0,0,0,1\n")
    assert str(e.value).startswith("t.csv:1:1: the header of this euroc file names its columns")
    assert "unknown column 'speed'" in str(e.value) and "no column for 'qw'" in str(e.value)


def test_many_unknown_names_are_named_a_few_and_counted():
    header = "t,tx,ty,tz,qw,qx,qy,qz," + ",".join(f"extra{i}" for i in range(5000))
    with pytest.raises(InputFileError) as e:
        read(header + "\n", fmt="csv")
    message = str(e.value)
    assert "'extra0', 'extra1', 'extra2', 'extra3', 'extra4' and 4995 more" in message
    assert "\n" not in message and len(message) < 400


def test_a_batch_csv_is_told_to_be_one():
    with pytest.raises(InputFileError, match=r"^t\.csv:1:1: a batch CSV \(its first column"):
        read("job,t,tx,ty,tz,qw,qx,qy,qz\na,0,0,0,0,1,0,0,0\n")


# -- text oddities at their line --------------------------------------------------------------


def test_a_byte_order_mark_before_a_comment_is_no_bad_row():
    path = read(b"\xef\xbb\xbf# time tx ty tz qx qy qz qw\n0 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 1\n", "a")
    assert path.fmt == "tum" and path.times.tolist() == [0.0, 1.0]


def test_cr_only_line_ends_are_reported_at_a_line():
    with pytest.raises(InputFileError, match=r"^a\.tum:1:4: a carriage return ends no line"):
        read("# c\r0 0 0 0 0 0 0 1\r1 0 0 0 0 0 0 1\r", "a.tum")


def test_times_a_double_cannot_tell_apart_are_said_to_be_so():
    """Unix stamps 1 ns apart are one double: not "the time repeats"."""
    text = "1700000000.000000001 0 0 0 0 0 0 1\n1700000000.000000002 0 0 0 0 0 0 1\n"
    with pytest.raises(InputFileError) as e:
        read(text, "a.tum")
    message = str(e.value)
    assert message.startswith("a.tum:2:1: the time 1700000000.000000002 is 1e-09 s after the ")
    assert "closer than a double tells apart at 1.7e+09 s" in message
    assert "repeats" not in message


def test_euroc_stamps_a_double_cannot_tell_apart():
    text = (
        "#timestamp [ns],tx,ty,tz,qw,qx,qy,qz\n"
        "1700000000000000001,0,0,0,1,0,0,0\n1700000000000000002,0,0,0,1,0,0,0\n"
    )
    with pytest.raises(InputFileError, match=r"^t\.csv:3:1: the time 1700000000\.000000002 is"):
        read(text)


def test_a_repeated_time_still_repeats():
    with pytest.raises(InputFileError, match="the time 1.0 repeats the previous one, 1.0"):
        read("1 0 0 0 0 0 0 1\n1.0 0 0 0 0 0 0 1\n", "a.tum")


def test_a_time_list_is_read_with_the_same_checks():
    assert read_times(io.BytesIO(b"# t\n0.5\n1.5 # a comment\n\n2\n"), "s").tolist() == [
        0.5,
        1.5,
        2.0,
    ]
    with pytest.raises(InputFileError, match=r"^s:2:1: the time 1\.0 goes back from"):
        read_times(io.BytesIO(b"2\n1\n"), "s")
    with pytest.raises(InputFileError, match=r"^s:2:1: expected a number, got 'x'"):
        read_times(io.BytesIO(b"1\nx\n"), "s")


# -- every output reads back ------------------------------------------------------------------


@pytest.mark.parametrize("fmt", ["csv", "matrix", "study"])
def test_velocities_read_back(tmp_path, fmt):
    out = tmp_path / f"v.{fmt}"
    result = run("interpolate", "samples/quarter-turn.yaml", "--max-speed", 1, "--rate", 20,
                 "--velocities", "--format", fmt, "-o", out)  # fmt: skip
    assert result.exit_code == 0, result.output
    assert out.read_text().startswith(",".join(csvtable.COLUMNS[fmt]) + ",vx,vy,vz,wx,wy,wz\n")
    with open(out, "rb") as f:
        path = read_trajectory(f, fmt=fmt)
    rows = np.loadtxt(out, delimiter=",", skiprows=1)
    assert path.times.tolist() == rows[:, 0].tolist()
    np.testing.assert_array_equal(path.translations[-1], path.matrices[-1, :3, 3])


@pytest.mark.parametrize("fmt", ["csv", "matrix", "study"])
def test_marked_output_reads_back(tmp_path, fmt):
    out = tmp_path / f"m.{fmt}"
    result = run("resample", "samples/reference.tum", "--times", "samples/stamps.txt", "--mark",
                 "--format", fmt, "-o", out)  # fmt: skip
    assert result.exit_code == 0, result.output
    assert out.read_text().split("\n", 1)[0].endswith(",original")
    with open(out, "rb") as f:
        path = read_trajectory(f)
    assert path.fmt == fmt
    assert path.times.tolist() == np.loadtxt(out, delimiter=",", skiprows=1)[:, 0].tolist()


@pytest.mark.parametrize("fmt", ["csv", "matrix", "study"])
def test_batch_csv_reads_back(tmp_path, fmt):
    out = tmp_path / "b.csv"
    result = run("batch", "samples/jobs.yaml", "--samples", 3, "--format", fmt, "-o", out)
    assert result.exit_code == 0, result.output
    with open(out, "rb") as f:
        names, values = csvtable.read_batch_csv(f)
    assert len(names) == len(values) and values.shape[1] == len(csvtable.COLUMNS[fmt])
    assert values[0, 0] == 0.0 and values[-1, 0] == 1.0
    assert names[0] == "lift" and len(set(names)) > 1


def test_a_damaged_batch_csv_is_one_error_at_its_line():
    with pytest.raises(InputFileError, match=r"^b:3: expected a finite number, got 'x'"):
        csvtable.read_batch_csv(io.BytesIO(b"job,t\na,0\nb,x\n"), "b")
    with pytest.raises(InputFileError, match=r"^b:2: expected 2 fields, got 3"):
        csvtable.read_batch_csv(io.BytesIO(b"job,t\na,0,1\n"), "b")


# -- options that do not apply ----------------------------------------------------------------

TUM = "0 0 0 0 0 0 0 1\n1 0 0 0 0 0 0 1\n"


@pytest.mark.parametrize(
    ("option", "value", "flag"),
    [("topic", "/pose", "--topic"), ("rate", 5.0, "--input-rate"),
     ("child_frame", "base", "--input-child-frame")],
)  # fmt: skip
def test_an_option_for_other_formats_is_refused(option, value, flag):
    with pytest.raises(InputFileError) as e:
        read(TUM, "a.tum", **{option: value})
    assert str(e.value).startswith(f"a.tum: {flag} does not apply to tum input")


def test_an_input_rate_on_mcap_is_refused(tmp_path):
    out = tmp_path / "q.mcap"
    assert run("interpolate", "samples/quarter-turn.yaml", "-o", out).exit_code == 0
    result = run("resample", out, "--rate", 10, "--input-rate", 3)
    assert result.exit_code == 1
    assert result.output == (
        f"Error: {out}: --input-rate does not apply to mcap input; it gives the times of poses "
        "that have none (kitti only)\n"
    )


def test_a_topic_on_a_tum_file_is_refused_by_the_command():
    result = run("resample", "samples/reference.tum", "--rate", 10, "--topic", "/x")
    assert result.exit_code == 1
    assert result.output.startswith("Error: samples/reference.tum: --topic does not apply to tum")


def test_kitti_takes_an_input_rate():
    path = read("1 0 0 0 0 1 0 0 0 0 1 0\n1 0 0 1 0 1 0 0 0 0 1 0\n", "a.kitti", rate=4.0)
    assert path.times.tolist() == [0.0, 0.25]


def test_a_file_name_cannot_forge_a_second_line(tmp_path):
    path = tmp_path / "a\nError: forged.tum"
    path.write_text("0 0 0 0 0 0 0 1\n0 0 0 0 0 0 0 1\n")
    with open(path, "rb") as f, pytest.raises(InputFileError) as e:
        read_trajectory(f)
    assert "\n" not in str(e.value) and "a\\nError: forged.tum:2:1: the time 0.0 repeats" in str(
        e.value
    )


# -- a line's count of fields ---------------------------------------------------------------

_ROW = "1.5 0.1 -2e-3 3 0 0 0.7071067811865476 0.7071067811865476"


def test_a_line_of_too_few_fields_is_not_made_up_by_the_next():
    data = f"{_ROW}\n1 2 3 4 5 6 7\n{_ROW} 9\n".encode()
    result = CliRunner().invoke(cli, ["resample", "-", "--input-format", "tum", "--rate", "1"],
                                input=data)  # fmt: skip
    assert result.exit_code == 1
    assert result.output == "Error: <stdin>:2:1: expected 8 numbers per line (tum), got 7\n"
