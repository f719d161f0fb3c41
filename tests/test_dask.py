"""a2b.dask on a real dask.distributed.LocalCluster (worker processes on localhost): the
dataset equals a2b batch row for row, job errors name the job and leave no dataset, a killed
worker ends in a complete dataset or a clear error, memory per worker stays bounded."""

from __future__ import annotations

import csv
import io
import json
import os
import resource
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("pyarrow")
pd = pytest.importorskip("pandas")
dd = pytest.importorskip("dask.dataframe")
distributed = pytest.importorskip("distributed")

import a2b.dask as a2b_dask  # noqa: E402
import a2b.table as table  # noqa: E402
from a2b.errors import A2bError  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
#: Worker processes on localhost: heavy, run by .ci/run's second step (`pytest -m slow`).
pytestmark = pytest.mark.slow


def cluster(workers: int):
    return distributed.LocalCluster(
        n_workers=workers,
        threads_per_worker=1,
        processes=True,
        host="127.0.0.1",
        dashboard_address="127.0.0.1:0",
    )


@pytest.fixture(scope="module")
def client():
    with cluster(2) as local, distributed.Client(local) as connected:
        yield connected


def write_jobs(path: Path, n: int, seed: int = 29, bad: dict | None = None) -> Path:
    """``n`` jobs as JSON Lines: every mode, some named, some with parameters, sample counts
    of their own and blank lines between; ``bad`` replaces the lines at the given indices."""
    rng = np.random.default_rng(seed)
    q = rng.normal(size=(n, 2, 4)).round(12)
    t = rng.normal(size=(n, 2, 3)).round(12)
    lines = []
    for i in range(n):
        job = {
            "start": {"quaternion_wxyz": q[i, 0].tolist(), "translation": t[i, 0].tolist()},
            "end": {"quaternion_wxyz": q[i, 1].tolist(), "translation": t[i, 1].tolist()},
        }
        if i % 3 == 0:
            job["name"] = f"job-{i}"
        if i % 5 == 1:
            job["mode"] = "screw"
        elif i % 7 == 2:
            job["mode"] = "cubic"
        elif i % 7 == 0:
            job["parameters"] = {"delta": 0.25}
        if i % 4 == 0:
            job["samples"] = 7
        lines.append((bad or {}).get(i, json.dumps(job)))
        if i % 50 == 0:
            lines.append("")
    path.write_text("\n".join(lines) + "\n")
    return path


def a2b_batch(jobs: Path, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "a2b", "batch", str(jobs), *args], cwd=ROOT, capture_output=True
    )


def reference(jobs: Path, samples: int) -> tuple[list[str], np.ndarray]:
    """``a2b batch`` in one process: the job column and the numbers, parsed with Python's float."""
    done = a2b_batch(jobs, "--samples", str(samples))
    assert done.returncode == 0, done.stderr
    rows = list(csv.reader(io.StringIO(done.stdout.decode())))[1:]
    return [row[0] for row in rows], np.array([[float(x) for x in row[1:]] for row in rows])


def assert_dataset_equals(directory: Path, names: list, numbers: np.ndarray) -> None:
    frame = pd.read_parquet(directory)
    assert frame["job"].astype(str).tolist() == names
    columns = ["t", "tx", "ty", "tz", "qw", "qx", "qy", "qz"]
    assert list(frame.columns) == ["job", *columns]
    assert frame[columns].to_numpy().tobytes() == numbers.tobytes()


def leftovers(directory: Path) -> list[str]:
    return sorted(p.name for p in directory.iterdir() if p.name.startswith("."))


def test_dataset_equals_a2b_batch_row_for_row(client, tmp_path):
    jobs = write_jobs(tmp_path / "jobs.jsonl", 10_000)
    out = tmp_path / "out"
    files = a2b_dask.batch(jobs, out, samples=11, blocksize=200_000)
    assert len(files) > 5  # many partitions
    assert sorted(os.listdir(out)) == [os.path.basename(f) for f in files]
    assert_dataset_equals(out, *reference(jobs, 11))
    assert leftovers(tmp_path) == []


def test_a_hundred_thousand_jobs_equal_a2b_batch(client, tmp_path):
    jobs = write_jobs(tmp_path / "jobs.jsonl", 100_000, seed=5)
    out = tmp_path / "out"
    a2b_dask.batch(jobs, out, samples=11)
    assert_dataset_equals(out, *reference(jobs, 11))


def test_a_dask_dataframe_of_jobs_equals_the_single_table(client, tmp_path):
    import pyarrow as pa

    from .test_table import frame_of, random_jobs

    jobs = frame_of(random_jobs(np.random.default_rng(3), 400))
    jobs["m"] = jobs["m"].astype(pd.ArrowDtype(pa.list_(pa.float64())))  # else dask makes text
    partitioned = dd.from_pandas(jobs, npartitions=4)
    samples = a2b_dask.samples(partitioned, samples=9, layout="matrix", duration=2.0)
    expected = table.samples(jobs, samples=9, layout="matrix", duration=2.0)
    got = samples.compute()
    pd.testing.assert_frame_equal(
        got.reset_index(drop=True).astype({"job": str}), expected.astype({"job": str})
    )
    a2b_dask.write_dataset(samples, tmp_path / "ds", layout="matrix")
    back = pd.read_parquet(tmp_path / "ds")
    pd.testing.assert_frame_equal(back.astype({"job": str}), expected.astype({"job": str}))


@pytest.mark.parametrize(
    ("bad", "kind"),
    [
        ({2500: '{"start": {"quaternion_wxyz": [1, 0, 0, 0]}, "end": 5}'}, "file"),
        ({2501: '{"start": {"quaternion_wxyz": [1, 0, 0, 0]}, "end"'}, "file"),
        (
            {
                2499: json.dumps(
                    {
                        "name": "broken",
                        "start": {"quaternion_wxyz": [1, 0, 0, 0]},
                        "end": {"quaternion_wxyz": [0, 0, 0, 1], "translation": [1, 0, 0]},
                        "mode": "cubic",
                        "parameters": {"m": [0, 0, 0, 0]},
                    }
                )
            },
            "mathematics",
        ),
    ],
)
def test_a_job_error_names_the_job_and_leaves_no_dataset(client, tmp_path, bad, kind):
    jobs = write_jobs(tmp_path / "jobs.jsonl", 3_000, bad=bad)
    done = a2b_batch(jobs, "-o", str(tmp_path / "ref.csv"))
    assert done.returncode == 1
    message = done.stderr.decode().strip().removeprefix("Error: ")
    assert ("job broken: " if kind == "mathematics" else f"{jobs}:") in message
    out = tmp_path / "out"
    with pytest.raises(A2bError) as caught:
        a2b_dask.batch(jobs, out, blocksize=50_000)
    assert str(caught.value) == message
    assert not out.exists()
    assert leftovers(tmp_path) == []


def test_an_existing_dataset_is_never_merged(client, tmp_path):
    jobs = write_jobs(tmp_path / "jobs.jsonl", 50)
    out = tmp_path / "out"
    out.mkdir()
    (out / "part.00000.parquet").write_bytes(b"old")
    with pytest.raises(A2bError, match="the directory is not empty"):
        a2b_dask.batch(jobs, out)
    assert (out / "part.00000.parquet").read_bytes() == b"old"


def test_a_list_of_jobs_is_refused(tmp_path):
    with pytest.raises(A2bError, match=r"jobs.yaml: a jobs file read in partitions must be JSON"):
        a2b_dask.batch(ROOT / "samples" / "jobs.yaml", tmp_path / "out")
    assert list(tmp_path.iterdir()) == []


def test_a_file_without_jobs_is_an_error(client, tmp_path):
    jobs = tmp_path / "jobs.jsonl"
    jobs.write_text("\n  \n")
    with pytest.raises(A2bError, match="no jobs"):
        a2b_dask.batch(jobs, tmp_path / "out")


def test_byte_ranges_start_at_the_first_line_after_their_offset(tmp_path):
    path = tmp_path / "lines"
    path.write_bytes(b"aa\nbbbb\n\ncc\nd")
    ranges = a2b_dask.byte_ranges(str(path), 3)
    parts = [a2b_dask.read_range(str(path), lo, hi) for lo, hi in ranges]
    assert b"".join(parts) == path.read_bytes()
    assert parts == [b"aa\n", b"bbbb\n", b"\n", b"cc\n", b"d"]  # lines start at 0, 3, 8, 9, 12


@pytest.mark.parametrize("retries", [3, 0])
def test_killing_a_worker_ends_in_a_complete_dataset_or_a_clear_error(tmp_path, retries):
    """Dask reruns the tasks of a lost worker (3 times by default); with no retries, the
    partition fails, and the error says so in one line."""
    import dask

    jobs = write_jobs(tmp_path / "jobs.jsonl", 10_000, seed=11)
    out = tmp_path / "out"
    outcome: dict = {}
    with (
        dask.config.set({"distributed.scheduler.allowed-failures": retries}),
        cluster(2) as local,
        distributed.Client(local) as connected,
    ):

        def run():
            try:
                outcome["files"] = a2b_dask.batch(jobs, out, samples=11, blocksize=50_000)
            except Exception as e:  # noqa: BLE001 - the outcome is checked below
                outcome["error"] = e

        worker = threading.Thread(target=run)
        worker.start()
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline and not any(
            p.name.startswith(".out.") and any(p.iterdir()) for p in tmp_path.iterdir()
        ):  # a partition is written: the run is under way
            time.sleep(0.05)
        pids = connected.run(os.getpid)
        os.kill(next(iter(pids.values())), signal.SIGKILL)
        worker.join(300)
    assert not worker.is_alive()
    print("killed a worker:", repr(outcome.get("error", "the dataset is complete")))
    if "error" in outcome:  # a clear error and no dataset
        assert isinstance(outcome["error"], A2bError)
        assert str(outcome["error"]).startswith(f"cannot write the dataset {out}: ")
        assert "\n" not in str(outcome["error"])
        assert not out.exists()
    else:
        assert_dataset_equals(out, *reference(jobs, 11))
    assert leftovers(tmp_path) == []


def test_memory_per_worker_stays_bounded(tmp_path):
    """A jobs file of ~110 partitions whose samples hold ~290 MB of numbers: the worker's
    peak grows by far less than that."""
    jobs = write_jobs(tmp_path / "jobs.jsonl", 12_000, seed=13)
    assert jobs.stat().st_size > 100 * 25_000

    def peak():
        return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss << 10

    with cluster(1) as local, distributed.Client(local) as connected:
        a2b_dask.batch(write_jobs(tmp_path / "warm.jsonl", 300), tmp_path / "warm", samples=501)
        before = next(iter(connected.run(peak).values()))
        a2b_dask.batch(jobs, tmp_path / "out", samples=501, blocksize=25_000)
        after = next(iter(connected.run(peak).values()))
    frame = pd.read_parquet(tmp_path / "out", columns=["t"])
    print(f"{len(frame)} rows; worker peak {before >> 20} MB before, {after >> 20} MB after")
    assert len(frame) * 8 * 8 > 250 << 20  # the numbers of the samples
    assert after - before < 100 << 20, f"the worker grew by {(after - before) >> 20} MB"


def test_client_of_a_scheduler_or_of_local_workers(client, tmp_path):
    with pytest.raises(A2bError, match="not both or neither"):
        with a2b_dask.client():
            pass
    with pytest.raises(A2bError, match="not both or neither"):
        with a2b_dask.client("tcp://127.0.0.1:1", 2):
            pass
    address = client.scheduler.address
    with a2b_dask.client(scheduler=address) as connected:
        assert connected.scheduler.address == address
        assert len(connected.scheduler_info()["workers"]) == 2


def test_import_a2b_imports_none_of_the_heavy_dependencies():
    code = (
        "import sys, a2b, a2b.cli\n"
        "heavy = {'pyarrow', 'pandas', 'dask', 'distributed', 'polars', 'duckdb'}\n"
        "print(sorted({m.split('.')[0] for m in sys.modules} & heavy))\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "[]"


def test_batch_on_a_local_cluster_equals_one_parquet_file(tmp_path):
    """``a2b batch --format parquet --workers 2 -o DIR/``: real worker processes, several
    partitions; the dataset holds the rows of the single-process Parquet file, with the same
    columns and dtypes."""
    jobs = write_jobs(tmp_path / "jobs.jsonl", 20_000, seed=7)
    assert jobs.stat().st_size > 2 * a2b_dask.BLOCKSIZE  # three partitions or more
    single = tmp_path / "one.parquet"
    done = a2b_batch(jobs, "--samples", "11", "-o", str(single))
    assert done.returncode == 0, done.stderr
    out = tmp_path / "out"
    args = ("--samples", "11", "--format", "parquet", "--workers", "2", "-o", f"{out}/", "-v")
    done = a2b_batch(jobs, *args)
    assert done.returncode == 0, done.stderr
    files = sorted(os.listdir(out))
    assert len(files) >= 3 and files[0] == "part.00000.parquet"
    assert f"a dataset of {len(files)} Parquet files in {out}/" in done.stderr.decode()
    got, want = pd.read_parquet(out), pd.read_parquet(single)
    assert got.dtypes.to_dict() == want.dtypes.to_dict()
    assert got["job"].astype(str).tolist() == want["job"].astype(str).tolist()
    # Row for row and bit for bit: a job's samples do not depend on the block it is built in.
    columns = ["t", "time", "tx", "ty", "tz", "qw", "qx", "qy", "qz"]
    assert got[columns].to_numpy().tobytes() == want[columns].to_numpy().tobytes()
    assert leftovers(tmp_path) == []


def test_batch_on_a_scheduler_names_the_failed_job_and_leaves_no_dataset(client, tmp_path):
    bad = {1234: json.dumps({"name": "broken", "start": {"quaternion_wxyz": [1, 0, 0, 0]},
                             "end": {"quaternion_wxyz": [0, 0, 0, 1]}, "mode": "cubic",
                             "parameters": {"m": [0, 0, 0, 0]}})}  # fmt: skip
    jobs = write_jobs(tmp_path / "jobs.jsonl", 3_000, bad=bad)
    single = a2b_batch(jobs, "--format", "parquet", "-o", str(tmp_path / "one.parquet"))
    assert single.returncode == 1 and b"job broken: " in single.stderr
    out = tmp_path / "out"
    address = client.scheduler.address
    done = a2b_batch(jobs, "--format", "parquet", "--scheduler", address, "-o", f"{out}/")
    assert done.returncode == 1
    assert done.stderr == single.stderr  # the same one line
    assert not out.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["jobs.jsonl"]
