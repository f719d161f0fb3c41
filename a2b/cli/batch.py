"""``a2b batch``: many motions from a jobs file into one CSV with a ``job`` column."""

from __future__ import annotations

import sys
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
    default=1024,
    show_default=True,
    help="Jobs read and built together, and the most in one chunk of output; memory is "
    "bounded by them.",
)
@options.output_option
@options.verbose_option
def command(jobs, mode, samples, fmt, chunk_size, output, verbose):
    """Sample every job in JOBS into one CSV whose first column, job, names the motion.

    JOBS is a YAML or JSON list of jobs, or JSON Lines (one job per line, read as it goes).
    A job has start and end poses and, optionally, name (default: its index), mode, samples
    and parameters, as in a poses file. Jobs are read, built and sampled in chunks, the jobs
    of one kind (mode and parameters given) all at once, with the results of building each
    alone; a progress bar shows on stderr when stderr is a terminal. A job that fails stops the run
    with a message that names it (by line and index
    for an error in the file, by name for one of the mathematics), and with -o no file is
    written.
    -v states every choice a2b makes, job by job.

    \b
    Example:
      a2b batch samples/jobs.yaml -o motions.csv
      a2b batch samples/jobs.jsonl --samples 101 --format matrix -o motions.csv
    """
    from ..io.atomic import atomic_output
    from ..io.readers import read_jobs
    from ..io.writers import REPRESENTATION, Chunk, JobRuns, write_batch_csv
    from ..jobs import sample

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

            def advance(n):
                progress.advance(task, n)

        pieces = sample(
            job_list.blocks(chunk_size),
            mode=mode or "darboux",
            samples=samples or 101,
            representation=REPRESENTATION[fmt],
            report=report if verbose else None,
            advance=advance,
        )
        chunks = (
            Chunk(piece.t, job=JobRuns(piece.names, piece.counts), **piece.fields)
            for piece in pieces
        )
        write_batch_csv(stream, chunks, fmt)
