"""Dask: the batch entry point over partitions, and datasets of Parquet (``a2b-motions[dask]``).

:func:`samples` maps :func:`a2b.table.samples` over the partitions of a Dask DataFrame of jobs;
:func:`jsonl_samples` reads a JSON Lines jobs file in partitions by byte ranges, so that no
machine holds the whole list, and samples each; both return a Dask DataFrame of samples with
the columns of :mod:`a2b.io.parquet`. :func:`write_dataset` writes such a frame as a directory
of Parquet files (``part.00000.parquet`` …, one per partition) with ``to_parquet``, whole or not
at all; :func:`batch` is the three together, and :func:`client` gives the cluster to run on.

A partition of a jobs file holds the lines that start in its byte range: it starts at the
first line after its offset and ends with the line that runs past its end. A first pass
counts the lines and jobs of every range (a few milliseconds a megabyte), so that each job
keeps its name (its index in the file, where it has none) and each error its line: the
samples and the errors are those of ``a2b batch`` on the same file. Memory per worker is
bounded by the range (``blocksize``) and the jobs sampled together.
"""

from __future__ import annotations

import os
import shutil
import tempfile
import time
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from functools import partial

from .errors import A2bError, InputFileError, MissingDependencyError

__all__ = [
    "BLOCKSIZE",
    "batch",
    "byte_ranges",
    "client",
    "jsonl_samples",
    "read_range",
    "samples",
    "write_dataset",
]

#: Bytes of a jobs file per partition: about 10^4 jobs, 10^6 samples at 101 each.
BLOCKSIZE = 1 << 21


def _require() -> None:
    """Dask, distributed and pyarrow, or a one-line error that names the extra."""
    try:
        import dask.dataframe  # noqa: F401
        import distributed  # noqa: F401
        import pyarrow  # noqa: F401
    except ImportError as e:
        raise MissingDependencyError(
            f"a Dask cluster needs {e.name or 'dask'}, which is not installed: "
            "pip install 'a2b-motions[dask]'"
        ) from e


def _meta(layout: str, duration: float | None):
    """The empty samples frame: the columns and dtypes of every partition."""
    from .table import samples_table

    return samples_table([], layout, duration=duration).to_pandas()


def samples(
    jobs,
    *,
    mode: str = "darboux",
    samples: int = 101,
    layout: str = "csv",
    duration: float | None = None,
    start_time: float = 0.0,
):
    """The samples of a Dask DataFrame of jobs (the columns of :mod:`a2b.table`), partition
    by partition through :func:`a2b.table.samples`, as a Dask DataFrame.

    A job without a name is named by its index label, so give the frame a global index (as
    ``dask.dataframe.from_pandas`` keeps it) for names that do not repeat across partitions.
    Give list columns (``start``, ``m`` …) a pyarrow list dtype,
    ``pandas.ArrowDtype(pyarrow.list_(pyarrow.float64()))``: Dask turns columns of Python
    objects into text.
    """
    from . import table

    options = dict(mode=mode, samples=samples, layout=layout, duration=duration)
    return jobs.map_partitions(
        table.samples, **options, start_time=start_time, meta=_meta(layout, duration)
    )


def byte_ranges(path: str, blocksize: int = BLOCKSIZE) -> list[tuple[int, int]]:
    """``(start, stop)`` byte ranges that cover the file ``path``, each ``blocksize`` long."""
    try:
        size = os.path.getsize(path)
    except OSError as e:
        raise InputFileError(f"{path}: cannot read: {e.strerror or e}") from e
    if blocksize < 1:
        raise ValueError(f"a partition needs at least one byte, got blocksize {blocksize}")
    return [(lo, min(lo + blocksize, size)) for lo in range(0, max(size, 1), blocksize)]


def read_range(path: str, start: int, stop: int) -> bytes:
    """The lines of ``path`` that start in ``[start, stop)``: from the first line after
    ``start`` (or the file's start) to the end of the line that holds byte ``stop - 1``."""
    with open(path, "rb") as stream:
        if start > 0:
            stream.seek(start - 1)
            stream.readline()  # the rest of the line that starts before the range
        here = stream.tell()
        if here >= stop:
            return b""
        data = stream.read(stop - here)
        if data and not data.endswith(b"\n"):
            data += stream.readline()
    return data


def _lines(data: bytes, name: str, first_line: int) -> list[str]:
    """The lines of ``data`` as text, each with its ``\\n`` (the last may have none)."""
    from .io.documents import decode

    try:
        text = data.decode("utf-8-sig" if first_line == 1 else "utf-8")
    except UnicodeDecodeError:  # the line of the error, as the single-process reader words it
        for number, raw in enumerate(data.split(b"\n"), start=first_line):
            decode(raw, name, number)
        raise
    parts = text.split("\n")
    return [part + "\n" for part in parts[:-1]] + [parts[-1]] * bool(parts[-1])


def _counted(path: str, start: int, stop: int) -> tuple[int, int]:
    """The lines and the jobs (lines that are not blank) of a range."""
    data = read_range(path, start, stop)
    text = data.decode("utf-8-sig" if start == 0 else "utf-8", errors="replace")
    lines = text.split("\n")
    if not lines[-1]:
        lines.pop()
    return len(lines), sum(1 for line in lines if line.strip())


def _partitions(path: str, blocksize: int) -> list[tuple]:
    """``(start, stop, lines before, jobs before)`` of every range that holds a job."""
    import dask

    ranges = byte_ranges(path, blocksize)
    counts = dask.compute(*[dask.delayed(_counted)(path, lo, hi) for lo, hi in ranges])
    parts, lines, jobs = [], 0, 0
    for (lo, hi), (n_lines, n_jobs) in zip(ranges, counts):
        if n_jobs:
            parts.append((lo, hi, lines, jobs))
        lines, jobs = lines + n_lines, jobs + n_jobs
    if not parts:
        raise InputFileError(f"{path}: no jobs: the file has no lines with a job")
    return parts


def _job_blocks(path: str, part: tuple, size: int) -> Iterator:
    """The :class:`a2b.io.jobfiles.JobBlock` s of one partition, named and located as the
    whole file would name and locate them."""
    from .io.jobfiles import finish_block, json_line_job
    from .io.jobscan import scan_blocks
    from .jobs import job_names

    start, stop, lines_before, jobs_before = part

    def exact(line, name, number, index):
        return json_line_job(line, name, number + lines_before, index + jobs_before)

    lines = _lines(read_range(path, start, stop), path, lines_before + 1)
    for scanned in scan_blocks(iter(lines), path, size, exact):
        scanned.records = [  # where a job is read again for its error: its line in the file
            (*record[:6], (where[0], where[1], where[2] + lines_before, where[3] + jobs_before))
            if isinstance(where[0], str) else record
            for record in scanned.records
            for where in (record[6],)
        ]  # fmt: skip
        for block in finish_block(scanned):
            first = scanned.records[0][6][3]  # the index of its first job in the file
            block.names = job_names(block.names, first)
            yield block


def _jsonl_partition(part: tuple, path, mode, samples, layout, duration, start_time, size):
    from .table import chunks_of_blocks, samples_table

    blocks = _job_blocks(path, part, size)
    chunks = chunks_of_blocks(blocks, mode=mode, samples=samples, layout=layout)
    return samples_table(chunks, layout, duration=duration, start_time=start_time).to_pandas()


def jsonl_samples(
    path: str,
    *,
    blocksize: int = BLOCKSIZE,
    mode: str = "darboux",
    samples: int = 101,
    layout: str = "csv",
    duration: float | None = None,
    start_time: float = 0.0,
    block_jobs: int | None = None,
):
    """The samples of a JSON Lines jobs file as a Dask DataFrame, one partition per
    ``blocksize`` bytes of the file (on a file system every worker sees).

    The file must be JSON Lines (a ``.json`` or ``.yaml`` name is refused: a list cannot be
    split by bytes). The first pass (counting the lines of each range) runs at once, on the current
    scheduler; the samples are computed when the frame is. Job errors are those of
    ``a2b batch``: ``FILE:LINE:COLUMN: job N: ...`` for the file, ``job NAME: ...`` for
    the mathematics. ``block_jobs``: jobs built together (default
    :data:`a2b.table.BLOCK_JOBS`).
    """
    import dask.dataframe as dd

    from .io.documents import kind_from_suffix
    from .table import BLOCK_JOBS

    if kind_from_suffix(os.fspath(path)) in ("json", "yaml"):
        raise InputFileError(
            f"{path}: a jobs file read in partitions must be JSON Lines (.jsonl), one job a line"
        )
    parts = _partitions(os.fspath(path), blocksize)
    return dd.from_map(
        _jsonl_partition,
        parts,
        path=os.fspath(path),
        mode=mode,
        samples=samples,
        layout=layout,
        duration=duration,
        start_time=start_time,
        size=block_jobs or BLOCK_JOBS,
        meta=_meta(layout, duration),
        label="a2b-samples",
        enforce_metadata=False,
    )


@contextmanager
def _dataset_directory(path: str) -> Iterator[str]:
    """A temporary directory beside ``path``, renamed to ``path`` when the block ends
    normally; removed, with ``path`` untouched, if it raises. ``path`` must not exist or be
    an empty directory: a dataset is never merged with the files of another."""
    from .io.atomic import OutputFileError

    target = os.path.realpath(os.fspath(path))

    def check():
        if os.path.isdir(target) and os.listdir(target):
            raise OutputFileError(
                f"cannot write the dataset {path}: the directory is not empty (a dataset goes "
                "into a new or empty directory)"
            )
        if os.path.exists(target) and not os.path.isdir(target):
            raise OutputFileError(f"cannot write the dataset {path}: it is a file")

    check()
    parent = os.path.dirname(target)
    try:
        tmp = tempfile.mkdtemp(prefix=f".{os.path.basename(target)}.", suffix=".tmp", dir=parent)
    except OSError as e:
        raise OutputFileError(f"cannot write {path}: {e.strerror or e}") from e
    try:
        yield tmp
        check()
        os.chmod(tmp, 0o777 & ~_umask())
        os.replace(tmp, target)
    except BaseException:
        _remove(tmp)
        raise


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def _remove(directory: str) -> None:
    """Remove a directory that a task still running elsewhere may write a last file into."""
    for _ in range(50):
        shutil.rmtree(directory, ignore_errors=True)
        if not os.path.exists(directory):
            return
        time.sleep(0.1)


def write_dataset(
    frame, path: str, *, layout: str = "csv", motion: Mapping | None = None
) -> list[str]:
    """Write a Dask DataFrame of samples as a Parquet dataset in the directory ``path``.

    One file per partition, ``part.NNNNN.parquet`` (numbered to sort as text), with the schema
    and metadata of :func:`a2b.io.parquet.schema` (``motion`` goes into ``a2b.motion``). The
    files are written into a temporary directory beside ``path``, renamed to ``path`` when
    every partition is written; if any fails (a job error, a lost worker beyond Dask's
    retries), the temporary directory is removed and nothing appears at ``path``, which must
    not exist or be empty.

    Returns
    -------
    list of str
        The files of the dataset, in partition order.
    """
    from .io.parquet import schema

    names = list(frame.columns)
    shape = schema(
        layout,
        job="job" in names,
        time="time" in names,
        twist="vx" in names,
        original="original" in names,
        motion=motion,
    )
    name = partial(_part_name, len(str(frame.npartitions - 1)))
    with _dataset_directory(path) as tmp:
        work = frame.to_parquet(
            tmp, schema=shape, write_index=False, name_function=name, compute=False
        )
        _computed(work, path)
    return [os.path.join(path, name(i)) for i in range(frame.npartitions)]


def _part_name(width: int, i: int) -> str:
    """``part.00007.parquet``: numbered to sort in partition order as text, as readers list
    the files of a dataset."""
    return f"part.{i:0{max(width, 5)}d}.parquet"


def _computed(work, path) -> None:
    """Compute ``work`` on the current scheduler; on a distributed client, cancel what is left
    of it when a task fails, so that no task writes on. A write that fails and workers that
    die beyond Dask's retries are an :class:`~a2b.io.atomic.OutputFileError` naming ``path``;
    a job's error is raised as it is."""
    from .io.atomic import OutputFileError

    lost: tuple = ()  # the errors of workers that died
    try:
        from distributed import KilledWorker, default_client

        lost = (KilledWorker,)
        current = default_client()
    except (ImportError, ValueError):
        current = None
    try:
        if current is None:
            work.compute()
            return
        future = current.compute(work)
        try:
            future.result()
        except BaseException:
            current.cancel(future, force=True)
            raise
    except (OSError, *lost) as e:
        reason = getattr(e, "strerror", None) or str(e)
        raise OutputFileError(f"cannot write the dataset {path}: {reason}") from e


def batch(
    jobs: str,
    output: str,
    *,
    layout: str = "csv",
    blocksize: int = BLOCKSIZE,
    mode: str = "darboux",
    samples: int = 101,
    duration: float | None = None,
    start_time: float = 0.0,
    block_jobs: int | None = None,
) -> list[str]:
    """``a2b batch JOBS --format parquet -o DIR/ --workers N`` on the current Dask scheduler:
    the samples of the JSON Lines file ``jobs`` (:func:`jsonl_samples`) as a dataset in
    ``output`` (:func:`write_dataset`). Returns the files written.

    Raises
    ------
    MissingDependencyError
        Without dask, distributed or pyarrow (the extra ``a2b-motions[dask]``).
    """
    _require()
    frame = jsonl_samples(
        jobs,
        blocksize=blocksize,
        mode=mode,
        samples=samples,
        layout=layout,
        duration=duration,
        start_time=start_time,
        block_jobs=block_jobs,
    )
    motion = {"mode": mode, "samples": samples, "jobs": os.path.basename(os.fspath(jobs))}
    if duration is not None:
        motion |= {"duration": duration, "start_time": start_time}
    return write_dataset(frame, output, layout=layout, motion=motion)


@contextmanager
def client(scheduler: str | None = None, workers: int | None = None) -> Iterator:
    """A ``distributed.Client``: of the scheduler at ``scheduler`` (``tcp://host:port``), or of
    a local cluster of ``workers`` processes, one thread each, closed at the end.

    Raises
    ------
    A2bError
        If both or neither are given, or the scheduler cannot be reached.
    MissingDependencyError
        Without dask, distributed or pyarrow (the extra ``a2b-motions[dask]``).
    """
    _require()
    from distributed import Client, LocalCluster

    if (scheduler is None) == (workers is None):
        raise A2bError("give a scheduler address or a number of workers, not both or neither")
    if scheduler is not None:
        try:
            connected = Client(scheduler, timeout="10s")
        except OSError as e:
            raise A2bError(f"cannot reach the Dask scheduler {scheduler}: {e}") from e
        with connected:
            yield connected
        return
    if workers < 1:
        raise A2bError(f"a local cluster needs at least one worker, got {workers}")
    with (
        LocalCluster(
            n_workers=workers,
            threads_per_worker=1,
            processes=True,
            host="127.0.0.1",
            dashboard_address="127.0.0.1:0",
        ) as cluster,
        Client(cluster) as connected,
    ):
        yield connected
