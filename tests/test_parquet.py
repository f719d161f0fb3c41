"""Parquet output (a2b.io.parquet): the CSV's numbers bit for bit, read back in pandas, polars
and DuckDB with the declared dtypes, streamed in row groups, atomic."""

from __future__ import annotations

import csv
import io
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

pa = pytest.importorskip("pyarrow")
pq = pytest.importorskip("pyarrow.parquet")

from a2b.io.atomic import atomic_output  # noqa: E402
from a2b.io.jobfiles import read_jobs  # noqa: E402
from a2b.io.parquet import (  # noqa: E402
    LAYOUTS,
    TWIST_COLUMNS,
    file_metadata,
    read_parquet,
    write_parquet,
)
from a2b.output import stamped  # noqa: E402
from a2b.samples import JobRuns, Samples  # noqa: E402
from a2b.table import chunks_of_blocks  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
SAMPLES = ROOT / "samples"
REPRESENTATION = {"csv": "quat_trans", "matrix": "matrices", "study": "study"}


@pytest.fixture
def rng():
    return np.random.default_rng(29)


def a2b_csv(*args: str) -> tuple[list[str], np.ndarray]:
    """Run ``a2b`` and parse its CSV with Python's float (the shortest round trip)."""
    done = subprocess.run(
        [sys.executable, "-m", "a2b", *args], cwd=ROOT, capture_output=True, check=True
    )
    rows = list(csv.reader(io.StringIO(done.stdout.decode())))
    header, rows = rows[0], rows[1:]
    return header, rows


def batch_parquet(tmp_path, jobs: str, layout: str, duration=None, start_time=0.0) -> Path:
    """The jobs file as Parquet, through the library (the table's code path)."""
    with open(SAMPLES / jobs, "rb") as stream:
        blocks = read_jobs(stream, str(SAMPLES / jobs)).blocks(1024)
        chunks = chunks_of_blocks(blocks, layout=layout)
        if duration is not None:
            chunks = stamped(chunks, duration, start_time)
        target = tmp_path / f"{jobs}.{layout}.parquet"
        with atomic_output(target) as out:
            write_parquet(out, chunks, motion={"mode": "darboux"})
    return target


@pytest.mark.parametrize("layout", ["csv", "matrix", "study"])
def test_batch_numbers_equal_the_csv_bit_for_bit(tmp_path, layout):
    header, rows = a2b_csv("batch", "samples/jobs.yaml", "--format", layout)
    path = batch_parquet(tmp_path, "jobs.yaml", layout)
    table = pq.read_table(path)
    assert table.schema.names == header
    assert table.column("job").to_pylist() == [row[0] for row in rows]
    expected = np.array([[float(x) for x in row[1:]] for row in rows])
    got = np.column_stack([table.column(name).to_numpy() for name in header[1:]])
    assert got.tobytes() == expected.tobytes()


#: One command line of each command that writes samples, and the columns of its output.
COMMANDS = {
    "interpolate": ["interpolate", "samples/quarter-turn.yaml", "--samples", "33"],
    "bezier": ["bezier", "samples/planar-bezier.yaml", "--samples", "17"],
    "spline": ["spline", "samples/spline.yaml", "--samples", "41"],
    "resample": ["resample", "samples/reference.tum", "--rate", "100", "--mark"],
    "timed": ["interpolate", "samples/quarter-turn.yaml", "--max-speed", "1", "--max-accel",
              "2", "--rate", "50", "--velocities"],
    "batch": ["batch", "samples/jobs.jsonl", "--samples", "11"],
}  # fmt: skip


def a2b_parquet(tmp_path, *args: str) -> Path:
    """Run ``a2b ... --format parquet -o FILE`` and return the file."""
    target = tmp_path / "out.parquet"
    subprocess.run(
        [sys.executable, "-m", "a2b", *args, "--format", "parquet", "-o", str(target)],
        cwd=ROOT, capture_output=True, check=True,
    )  # fmt: skip
    return target


@pytest.mark.parametrize("command", list(COMMANDS))
def test_every_command_writes_the_csv_numbers_in_pandas_polars_and_duckdb(tmp_path, command):
    """Parquet of each command holds the numbers of its CSV output bit for bit, and pandas,
    polars and DuckDB read them with the declared dtypes: job categorical (DuckDB: text),
    the numbers doubles, ``original`` boolean."""
    pd = pytest.importorskip("pandas")
    pl = pytest.importorskip("polars")
    duckdb = pytest.importorskip("duckdb")
    header, rows = a2b_csv(*COMMANDS[command])
    path = a2b_parquet(tmp_path, *COMMANDS[command])
    table = pq.read_table(path)
    names = table.schema.names
    timed = "time" in names
    assert [n for n in names if n != "time"] == header
    assert timed == (command in ("interpolate", "bezier", "spline", "batch"))
    numbers = [n for n in header if n not in ("job", "original")]
    expected = {n: np.array([float(row[header.index(n)]) for row in rows]) for n in numbers}
    if timed:
        expected["time"] = expected["t"]  # duration 1, start time 0
    jobs = [row[0] for row in rows] if "job" in header else None
    marks = [row[-1] == "1" for row in rows] if "original" in header else None

    frame = pd.read_parquet(path)
    polars = pl.read_parquet(path)
    connection = duckdb.connect()
    types = dict(connection.execute(f"DESCRIBE SELECT * FROM '{path}'").fetchall()[i][:2]
                 for i in range(len(names)))  # fmt: skip
    duck = connection.execute(f"SELECT * FROM '{path}'").fetchnumpy()
    for name, values in expected.items():
        assert frame[name].dtype == np.float64 and polars.schema[name] == pl.Float64
        assert types[name] == "DOUBLE"
        for got in (table.column(name).to_numpy(), frame[name].to_numpy(),
                    polars[name].to_numpy(), np.asarray(duck[name])):  # fmt: skip
            assert got.tobytes() == values.tobytes(), name
    if jobs is not None:
        assert isinstance(frame["job"].dtype, pd.CategoricalDtype)
        assert polars.schema["job"] == pl.Categorical and types["job"] == "VARCHAR"
        assert frame["job"].astype(str).tolist() == jobs == list(duck["job"])
        assert polars["job"].cast(pl.String).to_list() == jobs
    if marks is not None:
        assert frame["original"].dtype == bool and polars.schema["original"] == pl.Boolean
        assert types["original"] == "BOOLEAN"
        assert frame["original"].tolist() == marks == polars["original"].to_list()
        assert list(duck["original"]) == marks


def test_the_suffix_names_parquet_and_a_terminal_is_refused(tmp_path):
    from click.testing import CliRunner

    from a2b.cli import cli

    target = tmp_path / "turn.parquet"
    result = CliRunner().invoke(cli, ["interpolate", "samples/quarter-turn.yaml", "-o",
                                      str(target), "-v"])  # fmt: skip
    assert result.exit_code == 0, result.output
    assert "format parquet: from the -o suffix .parquet" in result.output
    assert pq.read_table(target).num_rows == 101


def test_without_pyarrow_one_line_names_the_extra(tmp_path):
    code = (
        "import sys; sys.modules['pyarrow'] = None\n"
        "from a2b.cli import cli\n"
        "cli(['interpolate', 'samples/quarter-turn.yaml', '-o', sys.argv[1]])\n"
    )
    target = tmp_path / "turn.parquet"
    done = subprocess.run(
        [sys.executable, "-c", code, str(target)], cwd=ROOT, capture_output=True, text=True
    )
    assert done.returncode == 1
    assert done.stderr == (
        "Error: Parquet needs pyarrow, which is not installed: pip install 'a2b-motions[parquet]'\n"
    )
    assert list(tmp_path.iterdir()) == []


def test_pandas_polars_and_duckdb_read_the_same_numbers_and_dtypes(tmp_path):
    pd = pytest.importorskip("pandas")
    pl = pytest.importorskip("polars")
    duckdb = pytest.importorskip("duckdb")
    path = batch_parquet(tmp_path, "jobs.yaml", "csv", duration=2.0, start_time=10.0)
    table = pq.read_table(path)
    names = ["job", "t", "time", *LAYOUTS["csv"]]
    assert table.schema.names == names
    assert table.schema.field("job").type == pa.dictionary(pa.int32(), pa.string())
    expected = {name: table.column(name).to_numpy() for name in names[1:]}
    np.testing.assert_array_equal(expected["time"], expected["t"] * 2.0 + 10.0)

    frame = pd.read_parquet(path)
    assert isinstance(frame["job"].dtype, pd.CategoricalDtype)
    assert all(frame[name].dtype == np.float64 for name in names[1:])
    polars = pl.read_parquet(path)
    assert polars.schema["job"] == pl.Categorical
    assert all(polars.schema[name] == pl.Float64 for name in names[1:])
    connection = duckdb.connect()
    described = connection.execute(f"DESCRIBE SELECT * FROM '{path}'").fetchall()
    types = {row[0]: row[1] for row in described}
    assert types == {"job": "VARCHAR", **dict.fromkeys(names[1:], "DOUBLE")}
    duck = connection.execute(f"SELECT * FROM '{path}'").fetchnumpy()

    jobs = table.column("job").to_pylist()
    assert frame["job"].astype(str).tolist() == jobs
    assert polars["job"].cast(pl.String).to_list() == jobs
    assert list(duck["job"]) == jobs
    for name in names[1:]:
        for got in (frame[name].to_numpy(), polars[name].to_numpy(), duck[name]):
            assert np.asarray(got, dtype=float).tobytes() == expected[name].tobytes()


def test_metadata_holds_the_layout_units_and_motion(tmp_path):
    path = batch_parquet(tmp_path, "jobs.yaml", "matrix", duration=2.0)
    metadata = file_metadata(pq.read_schema(path))
    assert metadata["layout"] == "matrix"
    assert metadata["motion"] == {"mode": "darboux"}
    assert metadata["units"]["time"] == "s"
    assert metadata["units"]["tx"] == "length"
    assert metadata["units"]["r11"] == ""
    assert "job" not in metadata["units"]


@pytest.mark.parametrize(
    "given, stated",
    [
        (["--delta", "0.2"], {"mode": "darboux", "delta": 0.2, "solved_from": "delta"}),
        (["--mode", "cubic", "--m", "1,0,0,0.5"], {"mode": "cubic", "m": [1.0, 0.0, 0.0, 0.5]}),
    ],
)
def test_interpolate_states_the_motion_s_parameters_in_the_metadata(tmp_path, given, stated):
    """``a2b interpolate --format parquet``: pyarrow reads the mode and the parameters given
    (and those chosen) back from the key-value metadata, with the units."""
    args = ["interpolate", "samples/quarter-turn.yaml", "--samples", "7", *given]
    raw = pq.read_schema(a2b_parquet(tmp_path, *args)).metadata
    motion = json.loads(raw[b"a2b.motion"])
    assert {key: motion[key] for key in stated} == stated
    assert motion["samples"] == 7 and motion["duration"] == 1.0
    assert motion["axis_direction"] == [0.0, 0.0, 1.0]  # chosen: the screw axis of the turn
    assert json.loads(raw[b"a2b.units"])["tx"] == "length"


@pytest.mark.parametrize(
    "args, stated",
    [
        (["bezier", "samples/planar-bezier.yaml"], {"kind": "Bézier motion", "degree": 3}),
        (["spline", "samples/spline.yaml"], {"kind": "spline", "degree": 3}),
        (["interpolate", "samples/quarter-turn.yaml", "--max-speed", "1"], {"mode": "darboux"}),
    ],
)
def test_the_other_motion_commands_state_their_motion(tmp_path, args, stated):
    motion = file_metadata(pq.read_schema(a2b_parquet(tmp_path, *args)))["motion"]
    assert {key: motion[key] for key in stated} == stated and motion["samples"] == 101
    if "--max-speed" in args:
        assert motion["time_law"]["limits"] == {"speed": 1.0}


def test_resample_and_batch_state_the_mode(tmp_path):
    args = ["resample", "samples/reference.tum", "--rate", "50", "--mode", "darboux"]
    resampled = file_metadata(pq.read_schema(a2b_parquet(tmp_path, *args, "--delta", "0.1")))
    assert resampled["motion"] == {"mode": "darboux", "delta": 0.1}
    batch = file_metadata(pq.read_schema(a2b_parquet(tmp_path, "batch", "samples/jobs.yaml")))
    assert batch["motion"]["mode"] == "darboux" and batch["motion"]["samples"] == 101
    assert "jobs file" in batch["motion"]["jobs"]


def chunks_of(rng, n: int, names: list, size: int, layout: str, twist=False, original=False):
    """Random samples of ``n`` rows named by ``names`` in runs, in blocks of ``size``."""
    from a2b.poses import matrices_from_quat_trans, study_from_matrices

    quat = rng.normal(size=(n, 4))
    quat /= np.linalg.norm(quat, axis=1)[:, None]
    trans = rng.normal(size=(n, 3)) * 10
    matrices = matrices_from_quat_trans(quat, trans)
    runs = np.repeat(names, n // len(names)).tolist()
    out = []
    for lo in range(0, n, size):
        part = slice(lo, lo + size)
        chunk = Samples(np.linspace(0, 1, n)[part], job=runs[part])
        if layout == "csv":
            chunk.quat_wxyz, chunk.trans = quat[part], trans[part]
        elif layout == "matrix":
            chunk.matrices = matrices[part]
        else:
            chunk.study = study_from_matrices(matrices[part])
        if twist:
            chunk.twist = rng.normal(size=(len(chunk.t), 6))
        if original:
            chunk.original = rng.random(len(chunk.t)) < 0.5
        out.append(chunk)
    return out


@pytest.mark.parametrize("layout", ["csv", "matrix", "study"])
def test_round_trip_through_the_reader(tmp_path, rng, layout):
    chunks = chunks_of(rng, 600, ["a", "b,c", "ü\n"], 128, layout, twist=True, original=True)
    path = tmp_path / "x.parquet"
    with open(path, "wb") as out:
        rows = write_parquet(out, chunks, row_group_rows=250, motion={"m": np.ones(4)})
    assert rows == 600
    samples, time, metadata = read_parquet(path)
    assert time is None
    assert metadata["motion"] == {"m": [1.0, 1.0, 1.0, 1.0]}
    np.testing.assert_array_equal(samples.t, np.concatenate([c.t for c in chunks]))
    field = {"csv": "quat_wxyz", "matrix": "matrices", "study": "study"}[layout]
    np.testing.assert_array_equal(
        getattr(samples, field), np.concatenate([getattr(c, field) for c in chunks])
    )
    np.testing.assert_array_equal(samples.twist, np.concatenate([c.twist for c in chunks]))
    np.testing.assert_array_equal(samples.original, np.concatenate([c.original for c in chunks]))
    assert samples.job.names == ["a", "b,c", "ü\n"]
    assert samples.job.counts == [200, 200, 200]
    names = pq.read_schema(path).names
    assert names[-7:] == [*TWIST_COLUMNS, "original"]
    groups = pq.ParquetFile(path).metadata
    assert [groups.row_group(i).num_rows for i in range(groups.num_row_groups)] == [250, 250, 100]


def test_row_groups_keep_memory_bounded(tmp_path):
    """Two million rows (134 MB of numbers) written by a process that grows by far less."""
    code = """if True:
        import resource, sys, numpy as np
        from a2b.io.parquet import write_parquet
        from a2b.samples import JobRuns, Samples
        n = 1 << 16
        rng = np.random.default_rng(1)
        block = Samples(np.linspace(0, 1, n), quat_wxyz=rng.normal(size=(n, 4)),
                      trans=rng.normal(size=(n, 3)), job=JobRuns(["a", "b"], [n // 2, n // 2]))
        def peak():
            return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss << 10
        with open(sys.argv[1], "wb") as out:  # warm up: the libraries' first allocations
            write_parquet(out, [block] * 4)
        before = peak()
        with open(sys.argv[1], "wb") as out:
            rows = write_parquet(out, (block for _ in range(32)))
        print(rows, peak() - before)
    """
    done = subprocess.run(
        [sys.executable, "-c", code, str(tmp_path / "big.parquet")],
        cwd=ROOT, capture_output=True, text=True, check=True,
    )  # fmt: skip
    rows, grown = map(int, done.stdout.split())
    assert rows == 32 << 16
    assert grown < 48 << 20, f"grew by {grown >> 20} MB"
    metadata = pq.ParquetFile(tmp_path / "big.parquet").metadata
    assert metadata.num_row_groups == 16


def test_a_failure_leaves_no_file_and_the_old_one_untouched(tmp_path, rng):
    path = tmp_path / "x.parquet"
    path.write_bytes(b"old")

    def failing():
        yield from chunks_of(rng, 256, ["a"], 128, "csv")
        raise RuntimeError("stop")

    with pytest.raises(RuntimeError, match="stop"), atomic_output(path) as out:
        write_parquet(out, failing())
    assert path.read_bytes() == b"old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["x.parquet"]


def test_no_chunks_write_an_empty_file_with_its_columns(tmp_path):
    path = tmp_path / "empty.parquet"
    with open(path, "wb") as out:
        assert write_parquet(out, []) == 0
    table = pq.read_table(path)
    assert table.num_rows == 0
    assert table.schema.names == ["t", *LAYOUTS["csv"]]


def test_a_pipe_takes_parquet(tmp_path):
    code = (
        "import sys, numpy as np\n"
        "from a2b.io.parquet import write_parquet\n"
        "from a2b.samples import Samples\n"
        "c = Samples(np.array([0.0, 1.0]), study=np.eye(8)[:2], job=['a', 'b'])\n"
        "write_parquet(sys.stdout.buffer, [c])\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", code], cwd=ROOT, stdout=subprocess.PIPE, check=True
    )
    table = pq.read_table(pa.BufferReader(done.stdout))
    assert table.column("job").to_pylist() == ["a", "b"]
    assert table.column("p0").to_pylist() == [1.0, 0.0]


def test_blocks_must_carry_the_columns_of_the_first(rng):
    first, second = chunks_of(rng, 256, ["a"], 128, "csv")
    second.job = None
    with pytest.raises(ValueError, match="columns"):
        write_parquet(io.BytesIO(), [first, second])


def test_runs_in_the_job_column_read_back(tmp_path):
    chunk = Samples(
        np.zeros(5), study=np.tile(np.eye(8)[0], (5, 1)), job=JobRuns(["a", "b", "a"], [2, 1, 2])
    )
    path = tmp_path / "runs.parquet"
    with open(path, "wb") as out:
        write_parquet(out, [chunk])
    samples, _, _ = read_parquet(path)
    assert (samples.job.names, samples.job.counts) == (["a", "b", "a"], [2, 1, 2])
    json.dumps(file_metadata(pq.read_schema(path)))  # plain data


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--workers", "2", "-o", "out/"], "--scheduler and --workers write a Parquet dataset"),
        (
            [
                "--format",
                "parquet",
                "--workers",
                "2",
                "--scheduler",
                "tcp://127.0.0.1:1",
                "-o",
                "out/",
            ],
            "give --scheduler or --workers, not both",
        ),  # fmt: skip
        (["--format", "parquet", "--workers", "2"], "give JOBS as a file and -o DIR/"),
        (
            ["--format", "parquet", "--workers", "2", "--orthonormalize", "-o", "out/"],
            "--orthonormalize: not on a cluster",
        ),  # fmt: skip
    ],
)
def test_a_dataset_needs_parquet_a_file_and_a_directory(tmp_path, monkeypatch, args, message):
    from click.testing import CliRunner

    from a2b.cli import cli

    monkeypatch.chdir(tmp_path)
    jobs = str(SAMPLES / "jobs.jsonl")
    result = CliRunner().invoke(cli, ["batch", jobs, *args])
    assert result.exit_code == 2
    assert message in " ".join(result.output.split())
    assert list(tmp_path.iterdir()) == []


def test_without_dask_a_cluster_run_names_the_extra(tmp_path):
    code = (
        "import sys; sys.modules['distributed'] = None\n"
        "from a2b.cli import cli\n"
        "cli(['batch', 'samples/jobs.jsonl', '--format', 'parquet', '--workers', '1', '-o',"
        " sys.argv[1]])\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", code, str(tmp_path / "out")], cwd=ROOT, capture_output=True,
        text=True,
    )  # fmt: skip
    assert done.returncode == 1
    assert done.stderr == (
        "Error: a Dask cluster needs distributed, which is not installed: "
        "pip install 'a2b-motions[dask]'\n"
    )
    assert list(tmp_path.iterdir()) == []
