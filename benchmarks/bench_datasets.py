"""The ``datasets`` section of benchmarks/run.py (issue 29): Parquet against CSV rows/s, and
``a2b batch`` on a local Dask cluster of 1 and 2 workers against the single process.

Parquet and CSV are whole ``a2b batch`` processes, interleaved. The cluster rates are timed in
this process with the cluster started beforehand (its start-up, a few seconds, is not the
sampling's cost): :func:`a2b.dask.batch` on a client of N local worker processes, against the
single process's pipeline run here (:func:`a2b.jobs.sample` into
:func:`a2b.output.write_samples`, as ``a2b batch --format parquet`` runs it), at the same work.
Besides wall-clock rates it reports the rate per CPU second (this process, its children and
every worker), which carries over from a loaded machine; docs/scaling.md explains the figures.
"""

from __future__ import annotations

import json
import os
import resource
import shutil
import statistics
import time
from pathlib import Path

import numpy as np
from bench_common import Row, interleaved_processes, log, rate


def missing() -> str | None:
    """Why the section cannot run, or ``None``."""
    for module in ("pyarrow", "dask.dataframe", "distributed"):
        try:
            __import__(module)
        except ImportError:
            return f"{module.split('.')[0]} is not installed (pip install '.[dask]')"
    return None


def write_jobs(path: Path, jobs: int, seed: int = 1) -> None:
    """``jobs`` random darboux jobs as JSON Lines."""
    rng = np.random.default_rng(seed)
    quats, trans = rng.normal(size=(jobs, 2, 4)), rng.normal(size=(jobs, 2, 3))
    with open(path, "w") as f:
        for q, t in zip(quats.tolist(), trans.tolist()):
            start = {"quaternion_wxyz": q[0], "translation": t[0]}
            f.write(
                json.dumps({"start": start, "end": {"quaternion_wxyz": q[1], "translation": t[1]}})
            )
            f.write("\n")


def _cpu(client=None) -> float:
    """CPU seconds of this process, its children and the workers of ``client``."""
    total = sum(
        u.ru_utime + u.ru_stime
        for u in map(resource.getrusage, (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN))
    )
    if client is not None:
        total += sum(client.run(_own_cpu).values())
    return total


def _own_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def _remove(path: Path) -> None:
    if path.is_dir():
        shutil.rmtree(path)
    path.unlink(missing_ok=True)


def _timed(run, out: Path, repeats: int, client=None) -> tuple[float, float]:
    """Median wall seconds and median CPU seconds of ``run(out)``, after one warm-up."""
    _remove(out)
    run(out)
    walls, cpus = [], []
    for _ in range(repeats):
        _remove(out)
        cpu, start = _cpu(client), time.perf_counter()
        run(out)
        walls.append(time.perf_counter() - start)
        cpus.append(_cpu(client) - cpu)
    _remove(out)
    return statistics.median(walls), statistics.median(cpus)


def _single(jobs: Path, samples: int):
    """The pipeline of ``a2b batch --format parquet`` in this process."""
    from a2b.formats import BY_NAME
    from a2b.io.jobfiles import read_jobs
    from a2b.jobs import sample
    from a2b.output import stamped, write_samples

    fmt = BY_NAME["parquet"]

    def run(out: Path) -> None:
        with open(jobs, "rb") as stream:
            blocks = read_jobs(stream, str(jobs)).blocks(1024)
            pieces = sample(blocks, samples=samples, representation=fmt.representation)
            write_samples(stamped(pieces, 1.0, 0.0), out, fmt, batch=True)

    return run


def datasets_section(jobs: int, repeats: int, work: Path, exe: list[str] | None) -> list[Row]:
    """Parquet against CSV (whole processes), then 1 and 2 local workers against one process."""
    why = missing()
    if why is not None:
        return [Row("datasets", "Parquet and the Dask cluster", f"skipped: {why}")]
    import distributed

    import a2b.dask as a2b_dask

    samples = 101
    path = work / "datasets-jobs.jsonl"
    write_jobs(path, jobs)
    size, count = path.stat().st_size, jobs * samples
    rows: list[Row] = []
    if exe is None:
        rows.append(Row("datasets", "Parquet against CSV", "skipped: a2b is not installed"))
    else:
        outs = {"csv": work / "d.csv", "parquet": work / "d.parquet"}
        commands = {
            name: exe + ["batch", str(path), "--samples", str(samples), "-o", str(out)]
            for name, out in outs.items()
        }
        log(f"datasets: {jobs} jobs × {samples} samples to CSV and Parquet, {repeats} rounds")
        result = interleaved_processes(commands, repeats, outputs=outs)
        csv_s, parquet_s = result["csv"][0], result["parquet"][0]
        rows += [
            Row("datasets", f"a2b batch {jobs} jobs × {samples} -o d.csv", rate(count, csv_s)),
            Row("datasets", f"a2b batch {jobs} jobs × {samples} -o d.parquet",
                f"{rate(count, parquet_s)} rows", f"{csv_s / parquet_s:.2f}x CSV"),
        ]  # fmt: skip
        rows[0].figure += " rows"
    log("datasets: the single process against 1 and 2 local workers (cluster start untimed)")
    single_s, single_cpu = _timed(_single(path, samples), work / "single.parquet", repeats)
    figure = f"{rate(count, single_s)} rows, {rate(count, single_cpu)} per CPU-s"
    rows.append(Row("datasets", "one process: a2b batch --format parquet's pipeline", figure))
    for workers in (1, 2):
        with (
            distributed.LocalCluster(
                n_workers=workers, threads_per_worker=1, processes=True, host="127.0.0.1",
                dashboard_address="127.0.0.1:0",
            ) as cluster,
            distributed.Client(cluster) as client,
        ):  # fmt: skip
            blocksize = max(size // (4 * workers), 1)
            parts = -(-size // blocksize)

            def run(out: Path, blocksize=blocksize) -> None:
                a2b_dask.batch(path, out, samples=samples, blocksize=blocksize, duration=1.0)

            wall, cpu = _timed(run, work / "dataset", repeats, client)
        rows.append(Row(
            "datasets", f"local cluster, {workers} worker(s), {parts} partitions",
            f"{rate(count, wall)} rows, {rate(count, cpu)} per CPU-s",
            f"{single_s / wall:.2f}x one process",
        ))  # fmt: skip
    rows.append(Row("datasets", "load average (1 min) after the section",
                    f"{os.getloadavg()[0]:.2f}"))  # fmt: skip
    path.unlink()
    return rows
