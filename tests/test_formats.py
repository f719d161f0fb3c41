"""The one table of formats (:mod:`a2b.formats`): nothing else lists them, every format with a
reader reads back what its writer wrote, and the help texts and README derive from it."""

from __future__ import annotations

import ast
import re
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

import a2b
from a2b import formats
from a2b.cli import cli

from .conftest import random_pose

ROOT = Path(__file__).resolve().parent.parent
PACKAGE = ROOT / "a2b"

#: Files that another branch is splitting; the lead points them at the table when merging.
NOT_YET: set = set()
#: ``matrix`` and ``study`` are also the two spaces of Bézier curves and pose forms.
SPACES = {"matrix", "study"}


def format_lists(path: Path):
    """The tuples, lists, sets and dict keys of ``path`` that hold two or more format names."""
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, (ast.Tuple, ast.List, ast.Set)):
            items = node.elts
        elif isinstance(node, ast.Dict):
            items = [key for key in node.keys if key is not None]
        else:
            continue
        names = {
            e.value for e in items if isinstance(e, ast.Constant) and e.value in formats.BY_NAME
        }
        if len(names) >= 2 and not names <= SPACES:
            yield node.lineno, sorted(names)


def test_no_list_of_format_names_outside_the_table():
    found = [
        (str(path.relative_to(ROOT)), line, names)
        for path in sorted(PACKAGE.rglob("*.py"))
        if path.name != "formats.py" and str(path.relative_to(ROOT)) not in NOT_YET
        for line, names in format_lists(path)
    ]
    assert found == []


def test_the_scan_sees_a_list_of_format_names(tmp_path):
    path = tmp_path / "m.py"
    path.write_text(
        'KNOWN = ("csv", "tum")\nSPACES = ("matrix", "study")\nx = {"mcap": 1, "ros2": 2}\n'
    )
    assert list(format_lists(path)) == [(1, ["csv", "tum"]), (3, ["mcap", "ros2"])]


def test_the_table_is_consistent():
    for row in formats.TABLE:
        assert (row.writer is None) == (row.representation is None)
        assert (row.batch is None) == (row.batch_writer is None)
        assert row.batch in (None, "rows", "files", "topics")
        assert row.holds <= {"poses", "times", "velocities", "mark"}
        for reference in (row.writer, row.batch_writer, row.reader, row.limits.stamps):
            if reference is not None:
                assert callable(formats.resolve(reference)), reference
        assert row.read_as is None or formats.BY_NAME[row.read_as].reader
    assert formats.from_suffix("out/turn.MCAP") == ("mcap", ".mcap")
    assert formats.from_suffix("motions.tum", batch=True) is None  # a batch of tum: a directory
    assert formats.from_suffix("motions.csv") is None


def test_the_table_imports_nothing_heavy():
    import subprocess
    import sys

    code = (
        "import sys, a2b.formats; "
        "print(sorted(m for m in sys.modules if m.startswith(('numpy', 'a2b.io'))))"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT)
    assert done.stdout.strip() == "[]", done.stderr


@pytest.fixture
def motion(rng):
    return a2b.motion(random_pose(rng), random_pose(rng), "darboux")


READ_BACK = [r for r in formats.TABLE if r.writer and (r.reader or r.read_as)]


@pytest.mark.parametrize("row", READ_BACK, ids=lambda r: r.name)
def test_every_written_format_reads_back(tmp_path, motion, row):
    """What the writer of a format wrote, the reader of the table reads back: the same numbers
    bit for bit (times to the nanosecond in MCAP)."""
    from a2b.io.trajectories import read_trajectory

    target = tmp_path / f"out{row.suffixes[0] if row.suffixes else ''}"
    timing = {"duration": 2.0, "start_time": 3.0} if row.timed else {}
    a2b.write(motion, target, row.name, samples=9, **timing)
    reader = row.name if row.reader else row.read_as
    with open(target, "rb") as f:
        path = read_trajectory(f, str(target), None if reader == "euroc" else reader)
    ts = np.linspace(0, 1, 9)
    quat, trans = motion.quat_trans(ts)
    trans[[0, -1]] = motion.start[:3, 3], motion.end[:3, 3]
    if row.representation == "quat_trans":
        assert np.array_equal(path.quat_wxyz, quat) and np.array_equal(path.translations, trans)
    elif row.representation == "study":
        want = a2b.api.pin_ends(motion, ts, {"study": motion.study(ts)})["study"]
        assert np.array_equal(path.study, want)
    else:
        want = motion.matrices(ts)
        want[[0, -1]] = motion.start, motion.end
        assert np.array_equal(path.matrices, want)
    if "times" in row.holds:
        want_times = ts * 2.0 + 3.0 if row.timed else ts
        assert np.allclose(path.times, want_times, rtol=0, atol=1e-9 if row.binary else 0)


@pytest.mark.parametrize("row", [r for r in formats.TABLE if r.reader], ids=lambda r: r.name)
def test_every_format_with_a_reader_has_its_function(row):
    reader = formats.resolve(row.reader)
    assert reader.__name__.startswith("read_")


def choices(command: str, option: str) -> list[str]:
    """The choices of ``option`` in ``a2b COMMAND -h``."""
    text = CliRunner().invoke(cli, [command, "-h"], terminal_width=200).output
    flat = " ".join(text.split())
    match = re.search(re.escape(option) + r" \[([a-z0-9|]+)\]", flat)
    assert match, flat
    return match.group(1).split("|")


@pytest.mark.parametrize("command", ["interpolate", "bezier", "spline", "resample"])
def test_each_command_lists_the_formats_it_writes(command):
    assert choices(command, "--format") == list(formats.OUTPUT_NAMES)
    help_ = " ".join(CliRunner().invoke(cli, [command, "-h"]).output.split())
    durations = command != "resample"  # resample's times are the new times, not t · duration
    for row in formats.TABLE:
        described = " ".join(row.described(durations).split())
        assert (described in help_) == (row.writer is not None), row.name
    assert ("t · duration + start_time" in help_) == durations


def test_batch_lists_the_formats_it_writes():
    assert choices("batch", "--format") == [r.name for r in formats.TABLE if r.batch_writer]


@pytest.mark.parametrize("command", ["resample", "spline", "bezier"])
def test_input_formats_are_the_readers_of_the_table(command):
    assert choices(command, "--input-format") == list(formats.INPUT_NAMES)


def test_readme_table_is_the_table():
    readme = (ROOT / "README.md").read_text()
    start = readme.index("<!-- formats: generated from a2b/formats.py")
    start = readme.index("\n", start) + 1
    end = readme.index("<!-- end of formats -->")
    assert readme[start:end] == formats.markdown_table(), (
        "regenerate: python -c 'import a2b.formats as f; print(f.markdown_table())'"
    )
