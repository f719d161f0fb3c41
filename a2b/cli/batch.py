"""``a2b batch``: many motions from a jobs file into one CSV with a ``job`` column."""

from __future__ import annotations

import sys
from contextlib import nullcontext
from itertools import islice

import click

from . import CONTEXT_SETTINGS, options


def _progress(total: int | None):
    """A rich progress bar on stderr if stderr is a terminal, else nothing."""
    if not sys.stderr.isatty():
        return nullcontext(None)
    from rich.console import Console
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    return Progress(
        TextColumn("jobs"),
        BarColumn(),
        MofNCompleteColumn(),
        TimeElapsedColumn(),
        console=Console(stderr=True),
        transient=True,
    )


def batch_chunks(jobs, mode: str, samples: int, representation: str, chunk_size: int, advance=None):
    """Sample the jobs ``chunk_size`` at a time; yield one :class:`Chunk` per group of jobs.

    Memory stays bounded by the samples of ``chunk_size`` jobs. An :class:`A2bError` of a job
    is re-raised naming the job.
    """
    import numpy as np

    import a2b
    from a2b.errors import A2bError

    from ..io.writers import Chunk, sample_chunks

    iterator = enumerate(jobs)
    while True:
        group = list(islice(iterator, chunk_size))
        if not group:
            return
        parts = []
        for index, job in group:
            name = job.name if job.name is not None else str(index)
            try:
                motion = a2b.motion(job.start, job.end, job.mode or mode, **job.parameters)
                ts = np.linspace(0.0, 1.0, job.samples or samples)
                parts.extend((name, c) for c in sample_chunks(motion, ts, representation, size=len(ts)))
            except A2bError as e:
                raise type(e)(f"job {name}: {e}") from e
        fields = {}
        for key in ("t", "quat_wxyz", "trans", "matrices", "study"):
            values = [getattr(c, key) for _, c in parts]
            fields[key] = None if values[0] is None else np.concatenate(values)
        job_column = [name for name, c in parts for _ in range(len(c.t))]
        yield Chunk(job=job_column, **fields)
        if advance is not None:
            advance(len(group))


@click.command(context_settings=CONTEXT_SETTINGS)
@click.argument("jobs", type=click.File("rb"))
@click.option(
    "--mode",
    type=click.Choice(options.MODES),
    default="darboux",
    show_default=True,
    help="The mode of jobs that do not name one.",
)
@click.option(
    "--samples",
    type=click.IntRange(min=1),
    default=101,
    show_default=True,
    help="Samples per motion for jobs that do not say.",
)
@click.option(
    "--format",
    "fmt",
    type=click.Choice(["csv", "matrix", "study"]),
    default="csv",
    show_default=True,
    help="The CSV layout after the job column (as for a2b interpolate).",
)
@click.option(
    "--chunk-size",
    type=click.IntRange(min=1),
    default=256,
    show_default=True,
    help="Jobs sampled and written at a time; memory is bounded by one chunk.",
)
@options.output_option
def command(jobs, mode, samples, fmt, chunk_size, output):
    """Sample every job in JOBS into one CSV whose first column, job, names the motion.

    JOBS is a YAML or JSON list of jobs, or JSON Lines (one job per line, read as it goes).
    A job has start and end poses and, optionally, name (default: its index), mode, samples
    and parameters, as in a poses file. Jobs are processed in chunks; a progress bar shows
    on stderr when stderr is a terminal. A job that fails stops the run with its name, and
    with -o no file is written.

    \b
    Example:
      a2b batch samples/jobs.yaml -o motions.csv
      a2b batch jobs.jsonl --samples 1001 --format matrix > motions.csv
    """
    from ..io.atomic import atomic_output
    from ..io.readers import read_jobs
    from ..io.writers import REPRESENTATION, write_batch_csv

    job_list = read_jobs(jobs)
    with _progress(job_list.count) as progress, atomic_output(output) as stream:
        advance = None
        if progress is not None:
            task = progress.add_task("jobs", total=job_list.count)
            advance = lambda n: progress.advance(task, n)
        chunks = batch_chunks(job_list, mode, samples, REPRESENTATION[fmt], chunk_size, advance)
        write_batch_csv(stream, chunks, fmt)
