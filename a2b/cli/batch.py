"""``a2b batch``: many motions from a jobs file: one CSV or Parquet file with a ``job`` column, a
directory of tum or kitti files, an MCAP file with one topic per job, or a Parquet dataset
written by a Dask cluster (:mod:`a2b.dask`)."""

from __future__ import annotations

import os
import sys
from contextlib import nullcontext

import click

from ..names import MAX_SAMPLES, MIN_SAMPLES
from . import CONTEXT_SETTINGS, options, writing

#: What a Parquet file of ``a2b batch`` says of its jobs in ``a2b.motion`` (per-job parameters
#: do not fit file metadata).
JOBS_NOTE = "mode and samples: those of jobs that name none; each job's own are in the jobs file"


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
@click.argument("jobs", type=options.INPUT)
@click.option(
    "--mode",
    type=click.Choice(options.MODES),
    help="The mode of jobs that do not name one  [default: darboux]",
)
@click.option(
    "--samples",
    type=options.Count(min=MIN_SAMPLES, max=MAX_SAMPLES),
    help="Samples per motion for jobs that do not say  [default: 101]",
)
@writing.format_option(batch=True)
@writing.storage_option
@click.option(
    "--chunk-size",
    type=options.Count(min=1),
    default=1024,
    show_default=True,
    help="Jobs read and built together, and the most in one chunk of output; memory is "
    "bounded by them.",
)
@writing.timing_options
@writing.frame_id_option
@writing.output_option(directory=True)
@click.option(
    "--scheduler",
    metavar="ADDRESS",
    help="parquet: sample on the Dask cluster whose scheduler is at ADDRESS (tcp://host:port) "
    "into a dataset, a new or empty directory -o DIR/ of Parquet files, one per partition of "
    "JOBS (JSON Lines, read in 2 MiB byte ranges on the workers; needs a2b-motions[dask]).",
)
@click.option(
    "--workers",
    type=options.Count(min=1),
    help="parquet: as --scheduler, on a local cluster of N worker processes.",
)
@options.verbose_option
@options.orthonormalize_option
def command(
    jobs, mode, samples, fmt, profile, storage, chunk_size, duration, start_time, frame_id,
    output, scheduler, workers, verbose, orthonormalize,
):  # fmt: skip
    """Sample every job in JOBS: into one CSV whose first column, job, names the motion, into
    a file per job (tum, kitti), into one MCAP file with a topic per job, or into one
    Parquet file; with --scheduler or --workers, into a Parquet dataset made on a Dask cluster.

    JOBS is a YAML or JSON list of jobs, or JSON Lines (one job per line, read as it goes).
    A job has start and end poses and, optionally, name (default: job0, job1, …), mode, samples
    and parameters, as in a poses file. Jobs are read, built and sampled in chunks, the jobs
    of one kind (mode and parameters given) all at once, with the results of building each
    alone; a progress bar shows on stderr when stderr is a terminal. A job that fails stops
    the run with a message that names it (by line and index for an error in the file, by
    name for one of the mathematics), and with -o no file is written. tum, kitti, mcap and
    ros2 keep each job under its name, so names must differ (and, for tum and kitti, be file
    names); the files of a directory are moved into it only when every job is written,
    replacing files of the same name and leaving others alone. A dataset appears in DIR
    only when every partition is written; its rows are those of one Parquet file
    (a2b batch jobs.jsonl --format parquet --workers 2 -o dataset/). A Parquet file's
    metadata states the mode and samples of jobs that name none; the jobs file holds the rest.
    -v states every choice a2b makes, job by job.

    \b
    Example:
      a2b batch samples/jobs.yaml -o motions.csv
      a2b batch samples/jobs.jsonl --samples 101 --format matrix -o motions.csv
      a2b batch samples/jobs.yaml --format tum --duration 2 -o motions/
      a2b batch samples/jobs.yaml -o motions.mcap
      a2b batch samples/jobs.jsonl -o motions.parquet
    """
    from ..errors import printable
    from ..formats import BY_NAME
    from ..io.jobfiles import read_jobs
    from ..jobs import sample
    from ..output import check_plan, stamped, write_samples

    choices: list[str] = []
    fmt = BY_NAME[writing.format_from(fmt, output, choices, profile, batch=True)]
    if mode is None:
        choices.append("mode darboux for jobs that name none: the default (--mode to change)")
    if samples is None:
        choices.append("101 samples for jobs that give none: the default (--samples to change)")
    options.state_choices(choices, verbose)
    frames = writing.refuse_defaults(fmt, {"duration": duration, "start_time": start_time,
                                           "frame_id": frame_id})  # fmt: skip
    check_plan(fmt, output, samples or 101, start_time, duration)
    if scheduler is not None or workers is not None:
        _on_cluster(jobs, output, fmt, scheduler, workers, orthonormalize, verbose,
                    mode=mode or "darboux", samples=samples or 101, duration=duration,
                    start_time=start_time, block_jobs=chunk_size)  # fmt: skip
        return
    if fmt.batch == "files" and output == "-":
        raise click.UsageError(f"{fmt.name} writes one file per job: give a directory with -o DIR")
    if fmt.batch != "files" and os.path.isdir(output):
        raise click.BadParameter(f"{output!r} is a directory", param_hint="'-o' / '--output'")

    def report(name, made):
        for choice in made:
            click.echo(f"  • {printable(f'job {name}: {choice}')}", err=True)

    repaired: list[str] = []
    with options.repairing(orthonormalize, repaired):  # the jobs are read as they are sampled
        job_list = read_jobs(*options.read_text_input(jobs))
        with _progress(job_list.count) as progress:
            task = progress.add_task("jobs", total=job_list.count) if progress else None
            pieces = sample(
                job_list.blocks(chunk_size),
                mode=mode or "darboux",
                samples=samples or 101,
                representation=fmt.representation,
                report=report if verbose else None,
                advance=(lambda n: progress.advance(task, n)) if progress else None,
                unique_names=fmt.batch != "rows",
            )
            timed = stamped(pieces, duration, start_time)
            defaults = {"mode": mode or "darboux", "samples": samples or 101, "jobs": JOBS_NOTE}
            write_samples(timed, output, fmt, batch=True, storage=storage, motion=defaults,
                          **frames)  # fmt: skip
    if verbose and repaired:
        click.echo(f"Repairs a2b made:\n  • {repaired[0]}", err=True)


def _on_cluster(jobs, output, fmt, scheduler, workers, orthonormalize, verbose, **settings):
    """``a2b batch --scheduler/--workers``: the jobs as a Parquet dataset in ``output``,
    computed on a Dask cluster (:func:`a2b.dask.batch`)."""
    from .. import dask as a2b_dask
    from ..errors import printable
    from ..io.parquet import layout_for

    if fmt.batch_writer != "a2b.io.parquet:write_batch_parquet":
        raise click.UsageError(
            f"--scheduler and --workers write a Parquet dataset, not {fmt.name}: give --format "
            "parquet"
        )
    if scheduler is not None and workers is not None:
        raise click.UsageError("give --scheduler or --workers, not both")
    path = getattr(jobs, "name", None)
    if output == "-" or not isinstance(path, str) or path in ("-", "<stdin>"):
        raise click.UsageError(
            "a dataset is a directory of files read from a file: give JOBS as a file and -o DIR/"
        )
    if orthonormalize:
        raise click.UsageError("--orthonormalize: not on a cluster (repair the jobs file first)")
    layout = layout_for(fmt.representation)
    with a2b_dask.client(scheduler, workers):
        files = a2b_dask.batch(path, output, layout=layout, **settings)
    if verbose:
        click.echo(printable(f"  • a dataset of {len(files)} Parquet files in {output}"), err=True)
