"""``a2b batch``: many motions from a jobs file into one CSV with a ``job`` column."""

from __future__ import annotations

import sys
import warnings
from contextlib import nullcontext

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


def batch_chunks(
    jobs, mode: str, samples: int, representation: str, chunk_size: int, advance=None, report=None
):
    """Sample the jobs and yield :class:`Chunk` s of at most ``chunk_size`` jobs.

    A chunk also ends when it holds ``CHUNK_SAMPLES`` rows, so a job of 10⁹ samples streams
    through in bounded memory like any other. ``advance(n)`` is called after ``n`` jobs are
    done, ``report(name, choices)`` before each job is sampled. An :class:`A2bError` of a job
    (including a sample that overflows) is re-raised naming the job, and so is an
    :class:`A2bWarning`.
    """
    import numpy as np

    import a2b
    from a2b.errors import A2bError, A2bWarning

    from ..io.writers import CHUNK_SAMPLES, Chunk

    parts: list = []  # (job name, chunk) not yet yielded
    rows = 0  # their samples
    done = 0  # jobs finished since the last advance

    def flush() -> Chunk:
        nonlocal rows
        rows = 0
        fields = {}
        for key in ("t", "quat_wxyz", "trans", "matrices", "study"):
            values = [getattr(c, key) for _, c in parts]
            fields[key] = None if values[0] is None else np.concatenate(values)
        job_column = [name for name, c in parts for _ in range(len(c.t))]
        parts.clear()
        return Chunk(job=job_column, **fields)

    for index, job in enumerate(jobs):
        name = job.name if job.name is not None else str(index)
        try:
            with warnings.catch_warnings(record=True) as caught:
                warnings.simplefilter("always", A2bWarning)
                motion = a2b.motion(job.start, job.end, job.mode or mode, **job.parameters)
            for warning in caught:  # say which job, then show as usual
                warnings.warn_explicit(
                    f"job {name}: {warning.message}",
                    warning.category,
                    warning.filename,
                    warning.lineno,
                )
            if report is not None:
                report(name, motion.choices)
            for chunk in options.motion_chunks(motion, job.samples or samples, representation):
                parts.append((name, chunk))
                rows += len(chunk.t)
                if rows >= CHUNK_SAMPLES:
                    yield flush()
        except A2bError as e:
            raise type(e)(f"job {name}: {e}") from e
        done += 1
        if done == chunk_size:
            if parts:
                yield flush()
            if advance is not None:
                advance(done)
            done = 0
    if parts:
        yield flush()
    if done and advance is not None:
        advance(done)


@click.command(context_settings=CONTEXT_SETTINGS)
@click.argument("jobs", type=click.File("rb"))
@click.option(
    "--mode",
    type=click.Choice(options.MODES),
    help="The mode of jobs that do not name one  [default: darboux]",
)
@click.option(
    "--samples",
    type=click.IntRange(min=options.MIN_SAMPLES, max=options.MAX_SAMPLES),
    help="Samples per motion for jobs that do not say  [default: 101]",
)
@click.option(
    "--format",
    "fmt",
    type=click.Choice(["csv", "matrix", "study"]),
    help="The CSV layout after the job column (as for a2b interpolate)  [default: csv]",
)
@click.option(
    "--chunk-size",
    type=click.IntRange(min=1),
    default=256,
    show_default=True,
    help="Jobs sampled and written at a time; memory is bounded by one chunk.",
)
@options.output_option
@options.verbose_option
def command(jobs, mode, samples, fmt, chunk_size, output, verbose):
    """Sample every job in JOBS into one CSV whose first column, job, names the motion.

    JOBS is a YAML or JSON list of jobs, or JSON Lines (one job per line, read as it goes).
    A job has start and end poses and, optionally, name (default: its index), mode, samples
    and parameters, as in a poses file. Jobs are processed in chunks; a progress bar shows
    on stderr when stderr is a terminal. A job that fails stops the run with its name, and
    with -o no file is written. -v states every choice a2b makes, job by job.

    \b
    Example:
      a2b batch samples/jobs.yaml -o motions.csv
      a2b batch jobs.jsonl --samples 1001 --format matrix > motions.csv
    """
    from ..io.atomic import atomic_output
    from ..io.readers import read_jobs
    from ..io.writers import REPRESENTATION, write_batch_csv

    choices: list[str] = []
    if fmt is None:
        fmt = "csv"
        choices.append("format csv: the default (--format to change)")
    if mode is None:
        choices.append("mode darboux for jobs that name none: the default (--mode to change)")
    if samples is None:
        choices.append("101 samples for jobs that give none: the default (--samples to change)")
    options.state_choices(choices, verbose)

    def report(name, made):
        for choice in made:
            click.echo(f"  • job {name}: {choice}", err=True)

    job_list = read_jobs(jobs)
    with _progress(job_list.count) as progress, atomic_output(output) as stream:
        advance = None
        if progress is not None:
            task = progress.add_task("jobs", total=job_list.count)
            advance = lambda n: progress.advance(task, n)
        chunks = batch_chunks(
            job_list,
            mode or "darboux",
            samples or 101,
            REPRESENTATION[fmt],
            chunk_size,
            advance,
            report if verbose else None,
        )
        write_batch_csv(stream, chunks, fmt)
