"""The batch entry point (a2b.table): a table of jobs, pandas or Arrow, to a table of samples
that equals ``a2b batch`` on the same jobs, and one-line errors that name the job."""

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
pd = pytest.importorskip("pandas")

import a2b.table as table  # noqa: E402
from a2b.errors import A2bError  # noqa: E402
from a2b.io.parquet import LAYOUTS  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent


@pytest.fixture
def rng():
    return np.random.default_rng(29)


def random_jobs(rng, n: int) -> list[dict]:
    """Jobs of every mode, some named, some with parameters and sample counts of their own."""
    jobs = []
    for i in range(n):
        q = rng.normal(size=(2, 4))
        t = rng.normal(size=(2, 3))
        job = {
            "start": {"quaternion_wxyz": q[0].tolist(), "translation": t[0].tolist()},
            "end": {"quaternion_wxyz": q[1].tolist(), "translation": t[1].tolist()},
        }
        if i % 3 == 0:
            job["name"] = f"job-{i}"
        if i % 5 == 1:
            job["mode"] = "screw"
        elif i % 5 == 2:
            job["mode"] = "cubic"
            if i % 2:
                job["parameters"] = {"m": [1.0, 0.0, 0.0, 0.5]}
        elif i % 7 == 0:
            job["parameters"] = {"delta": 0.25}
        if i % 4 == 0:
            job["samples"] = 7
        jobs.append(job)
    return jobs


def frame_of(jobs: list[dict]) -> pd.DataFrame:
    """The jobs as a dataframe user has them: quaternion and translation columns, a column
    per parameter, missing values where a job gives none."""
    rows = []
    for job in jobs:
        row = {}
        for end in ("start", "end"):
            for c, v in zip(("qw", "qx", "qy", "qz"), job[end]["quaternion_wxyz"]):
                row[f"{end}_{c}"] = v
            for c, v in zip(("tx", "ty", "tz"), job[end]["translation"]):
                row[f"{end}_{c}"] = v
        row["name"] = job.get("name")
        row["mode"] = job.get("mode")
        row["samples"] = job.get("samples")
        parameters = job.get("parameters", {})
        row["delta"] = parameters.get("delta", np.nan)
        row["m"] = parameters.get("m")
        rows.append(row)
    frame = pd.DataFrame(rows)
    frame["samples"] = frame["samples"].astype("Int64")
    return frame


def batch_csv(tmp_path, jobs: list[dict], *args: str) -> tuple[list[str], list[list[str]]]:
    path = tmp_path / "jobs.jsonl"
    path.write_text("".join(json.dumps(job) + "\n" for job in jobs))
    done = subprocess.run(
        [sys.executable, "-m", "a2b", "batch", str(path), *args],
        cwd=ROOT,
        capture_output=True,
        check=True,
    )
    rows = list(csv.reader(io.StringIO(done.stdout.decode())))
    return rows[0], rows[1:]


@pytest.mark.parametrize("layout", ["csv", "matrix", "study"])
@pytest.mark.parametrize("kind", ["pandas", "arrow"])
def test_samples_equal_a2b_batch_bit_for_bit(tmp_path, rng, layout, kind):
    jobs = random_jobs(rng, 60)
    header, rows = batch_csv(tmp_path, jobs, "--format", layout, "--samples", "11")
    frame = frame_of(jobs)
    given = frame if kind == "pandas" else pa.Table.from_pandas(frame, preserve_index=False)
    out = table.samples(given, samples=11, layout=layout)
    if kind == "pandas":
        assert isinstance(out, pd.DataFrame)
        assert isinstance(out["job"].dtype, pd.CategoricalDtype)
        names = out["job"].astype(str).tolist()
        numbers = out[header[1:]].to_numpy()
    else:
        assert isinstance(out, pa.Table)
        assert out.schema.field("job").type == pa.dictionary(pa.int32(), pa.string())
        names = out.column("job").to_pylist()
        numbers = np.column_stack([out.column(c).to_numpy() for c in header[1:]])
    assert list(out.column_names if kind == "arrow" else out.columns) == header
    assert names == [row[0] for row in rows]
    expected = np.array([[float(x) for x in row[1:]] for row in rows])
    assert numbers.tobytes() == expected.tobytes()


def test_matrix_columns_give_what_quaternion_columns_give(rng):
    jobs = frame_of(random_jobs(rng, 20))
    quat = jobs[[f"start_{c}" for c in ("qw", "qx", "qy", "qz")]].to_numpy()
    trans = jobs[[f"start_{c}" for c in ("tx", "ty", "tz")]].to_numpy()
    from a2b.poses import matrices_from_quat_trans

    as_matrices = jobs.drop(columns=[c for c in jobs.columns if c.startswith("start_")])
    as_matrices["start"] = list(matrices_from_quat_trans(quat, trans))  # (4, 4) arrays
    as_arrow = pa.Table.from_pandas(
        as_matrices.assign(start=[m.ravel() for m in as_matrices.start])
    )
    expected = table.samples(jobs, samples=5)
    pd.testing.assert_frame_equal(table.samples(as_matrices, samples=5), expected)
    pd.testing.assert_frame_equal(table.samples(as_arrow, samples=5).to_pandas(), expected)


def test_default_names_are_the_index_labels_or_positions():
    jobs = pd.DataFrame(
        {"start_qw": [1.0, 1.0], "start_qx": 0.0, "start_qy": 0.0, "start_qz": 0.0}
        | {"end_qw": 1.0, "end_qx": 0.0, "end_qy": 0.0, "end_qz": 0.0, "end_tx": [1.0, 2.0]}
        | {"end_ty": 0.0, "end_tz": 0.0},
        index=[10, 20],
    )
    out = table.samples(jobs, samples=2)
    assert out["job"].astype(str).tolist() == ["10", "10", "20", "20"]
    assert out["tx"].tolist() == [0.0, 1.0, 0.0, 2.0]
    arrow = table.samples(pa.Table.from_pandas(jobs, preserve_index=False), samples=2)
    assert arrow.column("job").to_pylist() == ["job0", "job0", "job1", "job1"]


def test_time_column_and_layouts():
    jobs = pd.DataFrame({"start": [np.eye(4).ravel()], "end": [np.eye(4).ravel()]})
    out = table.samples(jobs, samples=3, layout="study", duration=2.0, start_time=5.0)
    assert list(out.columns) == ["job", "t", "time", *LAYOUTS["study"]]
    assert out["time"].tolist() == [5.0, 6.0, 7.0]


def test_parameters_of_every_kind_reach_the_motion():
    import a2b

    a = np.eye(4)
    b = np.array([[0.0, -1, 0, 1], [1, 0, 0, 1], [0, 0, 1, 0.5], [0, 0, 0, 1]])
    jobs = pd.DataFrame(
        {
            "start": [a.ravel()] * 4,
            "end": [b.ravel()] * 4,
            "mode": ["darboux", "darboux", "cubic", "darboux"],
            "kappa": [0.3, None, None, None],
            "lam": [None, 0.8, None, None],
            "branch": [None, -1, None, None],
            "alpha": [None, None, [0.1, 0, 0, 0, 0, 0], None],
            "m": [None, None, [1.0, 0.1, 0.2, 0.5], None],
            "frame": [None, None, "given", None],
            "long_way": [None, None, None, True],
        }
    )
    out = table.samples(jobs, samples=5, layout="matrix")
    cases = [
        {"kappa": 0.3},
        {"lam": 0.8, "branch": -1},
        {"alpha": [0.1, 0, 0, 0, 0, 0], "m": [1.0, 0.1, 0.2, 0.5], "frame": "given"},
        {"long_way": True},
    ]
    for i, (mode, parameters) in enumerate(zip(jobs["mode"], cases)):
        expected = a2b.interpolate(a, b, np.linspace(0, 1, 5), mode, **parameters)
        rows = out[out["job"] == f"job{i}"]
        got = rows[list(LAYOUTS["matrix"])].to_numpy()
        np.testing.assert_array_equal(got, expected[:, :3, :].reshape(5, 12))


def test_through_is_a_pose_column():
    import a2b

    b = np.array([[0.0, -1, 0, 1], [1, 0, 0, 1], [0, 0, 1, 0.5], [0, 0, 0, 1]])
    through = a2b.interpolate(np.eye(4), b, [0.4], delta=0.3)[0]
    jobs = pd.DataFrame({"start": [np.eye(4)], "end": [b], "through": [through]})
    out = table.samples(jobs, samples=3, layout="matrix")
    expected = a2b.interpolate(np.eye(4), b, np.linspace(0, 1, 3), through=through)
    np.testing.assert_array_equal(
        out[list(LAYOUTS["matrix"])].to_numpy(), expected[:, :3, :].reshape(3, 12)
    )


def test_empty_table_gives_the_columns():
    jobs = pd.DataFrame({"start": [], "end": []})
    out = table.samples(jobs, layout="matrix", duration=1.0)
    assert len(out) == 0
    assert list(out.columns) == ["job", "t", "time", *LAYOUTS["matrix"]]


def one_job(**columns) -> pd.DataFrame:
    base = {"name": ["j0", "bad"], "start": [np.eye(4).ravel()] * 2}
    base["end"] = [np.eye(4).ravel()] * 2
    return pd.DataFrame(base | columns)


@pytest.mark.parametrize(
    ("columns", "message"),
    [
        ({"detla": [0.1, 0.2]}, r"^jobs table: unknown column 'detla'; the columns are"),
        (
            {"start": [np.eye(4).ravel(), np.zeros(16)]},
            r"^job bad: start: the bottom row of a robotics-layout pose matrix",
        ),
        ({"end": [np.eye(4).ravel(), [1, 2, 3]]}, r"^job bad: end: expected 16 numbers"),
        ({"samples": [3, 1]}, r"^job bad: samples: expected a whole number from 2 to 2\*\*53"),
        ({"samples": [3, 2.5]}, r"^job bad: samples: expected a whole number"),
        ({"mode": ["darboux", "spiral"]}, r"^job bad: unknown mode 'spiral'"),
        ({"mode": ["darboux", 3]}, r"^job bad: mode: expected text, got 3"),
        ({"delta": [0.1, "x"]}, r"^job bad: delta: expected a number, got 'x'"),
        ({"delta": [0.1, np.inf]}, r"^job bad: delta: expected a finite number, got inf"),
        ({"branch": [None, 2]}, r"^job bad: branch: expected \+1 or -1, got 2"),
        ({"long_way": [None, 1]}, r"^job bad: long_way: expected true or false, got 1"),
        ({"frame": [None, "world"]}, r"^job bad: frame: expected canonical or given"),
        ({"m": [None, [1, 2]]}, r"^job bad: m: expected 4 numbers"),
        (
            {"mode": ["darboux", "screw"], "delta": [None, 0.5]},
            r"^job bad: mode screw does not take delta",
        ),
        ({"name": ["j0", 7]}, r"^job job1: name: expected text, got 7"),
    ],
)
def test_errors_are_one_line_that_names_the_job(columns, message):
    with pytest.raises(A2bError, match=message) as caught:
        table.samples(one_job(**columns), samples=3)
    assert "\n" not in str(caught.value)


def test_quaternion_errors_name_the_job():
    jobs = pd.DataFrame(
        {"name": ["a", "b"], "start_qw": [1.0, 0.0], "start_qx": 0.0, "start_qy": 0.0}
        | {"start_qz": 0.0, "end_qw": 1.0, "end_qx": 0.0, "end_qy": 0.0, "end_qz": 0.0}
    )
    with pytest.raises(A2bError, match=r"^job b: start: the quaternion has norm 0"):
        table.samples(jobs)
    with pytest.raises(A2bError, match=r"^jobs table: no column 'end_ty'"):
        table.samples(jobs.assign(end_tx=1.0, start_qw=1.0))
    with pytest.raises(A2bError, match=r"^jobs table: give the start pose once"):
        table.samples(jobs.assign(start=[np.eye(4).ravel()] * 2))
    with pytest.raises(A2bError, match=r"^a jobs table must be a pandas DataFrame"):
        table.samples([{"start": np.eye(4)}])


def test_a_mathematical_error_names_the_job():
    """A cubic motion with m0 = 0 has no cylinder group element: the core's message, named."""
    jobs = one_job(mode=["cubic", "cubic"], m=[None, [0.0, 0.0, 0.0, 0.0]])
    with pytest.raises(A2bError, match=r"^job bad: ") as caught:
        table.samples(jobs, samples=3)
    assert "\n" not in str(caught.value)
