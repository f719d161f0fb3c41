"""``a2b batch``: many motions from a jobs file: one CSV with a ``job`` column, a directory of
tum or kitti files, or an MCAP file with one topic per job."""

from __future__ import annotations

import os
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
@click.argument("jobs", type=options.INPUT)
@click.option(
    "--mode",
    type=click.Choice(options.MODES),
    help="The mode of jobs that do not name one  [default: darboux]",
)
@click.option(
    "--samples",
    type=options.Count(min=options.MIN_SAMPLES, max=options.MAX_SAMPLES),
    help="Samples per motion for jobs that do not say  [default: 101]",
)
@click.option(
    "--format",
    "fmt",
    type=click.Choice(options.FORMATS),
    help="csv, matrix, study: one CSV, the job column first (layouts as for a2b interpolate); "
    "tum, kitti: a file per job, DIR/NAME.tum or DIR/NAME.kitti, in the directory -o DIR; "
    "mcap: one file, the poses of job NAME on topic /a2b/NAME/pose; ros2: the same as "
    "ROS 2 PoseStamped messages  [default: from the -o suffix .mcap, else csv]",
)
@options.profile_option
@click.option(
    "--chunk-size",
    type=options.Count(min=1),
    default=1024,
    show_default=True,
    help="Jobs read and built together, and the most in one chunk of output; memory is "
    "bounded by them.",
)
@options.timing_options
@click.option(
    "--frame-id",
    default="world",
    show_default=True,
    help="mcap, ros2: the fixed frame of the poses.",
)
@click.option(
    "-o",
    "--output",
    type=click.Path(allow_dash=True),
    default="-",
    show_default=True,
    help="Where to write; '-' is standard output. A file is written to a temporary file and "
    "renamed into place when complete; tum and kitti need a directory, made if missing.",
)
@options.verbose_option
@options.orthonormalize_option
def command(
    jobs, mode, samples, fmt, profile, chunk_size, duration, start_time, frame_id, output,
    verbose, orthonormalize,
):  # fmt: skip
    """Sample every job in JOBS: into one CSV whose first column, job, names the motion, into
    a file per job (tum, kitti), or into one MCAP file with a topic per job.

    JOBS is a YAML or JSON list of jobs, or JSON Lines (one job per line, read as it goes).
    A job has start and end poses and, optionally, name (default: its index), mode, samples
    and parameters, as in a poses file. Jobs are read, built and sampled in chunks, the jobs
    of one kind (mode and parameters given) all at once, with the results of building each
    alone; a progress bar shows on stderr when stderr is a terminal. A job that fails stops
    the run with a message that names it (by line and index for an error in the file, by
    name for one of the mathematics), and with -o no file is written. tum, kitti, mcap and
    ros2 keep each job under its name, so names must differ (and, for tum and kitti, be file
    names); the files of a directory are moved into it only when every job is written,
    replacing files of the same name and leaving others alone.
    -v states every choice a2b makes, job by job.

    \b
    Example:
      a2b batch samples/jobs.yaml -o motions.csv
      a2b batch samples/jobs.jsonl --samples 101 --format matrix -o motions.csv
      a2b batch samples/jobs.yaml --format tum --duration 2 -o motions/
      a2b batch samples/jobs.yaml -o motions.mcap
    """
    from ..errors import printable
    from ..io.atomic import atomic_directory, atomic_output
    from ..io.jobfiles import read_jobs
    from ..io.writers import (
        REPRESENTATION,
        Chunk,
        JobRuns,
        write_batch_csv,
        write_batch_files,
        write_batch_mcap,
    )
    from ..jobs import sample

    choices: list[str] = []
    if fmt is None and str(output).lower().endswith(".mcap"):
        fmt = "mcap"
        choices.append("format mcap: from the -o suffix .mcap (--format to change)")
    elif fmt is None:
        fmt = "csv"
        choices.append("format csv: the default (--format to change)")
    fmt = options.format_from(fmt, output, None, profile)
    if mode is None:
        choices.append("mode darboux for jobs that name none: the default (--mode to change)")
    if samples is None:
        choices.append("101 samples for jobs that give none: the default (--samples to change)")
    options.state_choices(choices, verbose)
    options.check_output(fmt, output, samples or 101, duration, start_time)

    def report(name, made):
        for choice in made:
            click.echo(f"  • {printable(f'job {name}: {choice}')}", err=True)

    if fmt in ("tum", "kitti") and output == "-":
        raise click.UsageError(f"{fmt} writes one file per job: give a directory with -o DIR")
    repaired: list[str] = []
    with options.repairing(orthonormalize, repaired):  # the jobs are read as they are sampled
        job_list = read_jobs(jobs)
        target = atomic_directory if fmt in ("tum", "kitti") else atomic_output
        if target is atomic_output and os.path.isdir(output):
            raise click.BadParameter(f"{output!r} is a directory", param_hint="'-o' / '--output'")
        with _progress(job_list.count) as progress, target(output) as out:
            task = progress.add_task("jobs", total=job_list.count) if progress else None

            def computed():  # in a process of its own: see a2b.io.parallel.produced_apart
                from ..io.poseschema import current_repairs

                repairs = current_repairs() or []
                before = len(repairs)  # those made here are sent at the end
                events: list = []  # reports and progress, sent before the piece they precede
                pieces = sample(
                    job_list.blocks(chunk_size),
                    mode=mode or "darboux",
                    samples=samples or 101,
                    representation=REPRESENTATION[fmt],
                    report=(lambda name, made: events.append((name, made))) if verbose else None,
                    advance=(lambda n: events.append(n)) if progress else None,
                    unique_names=fmt in ("tum", "kitti", *options.MCAP_FORMATS),
                )
                for piece in pieces:
                    yield from events
                    events.clear()
                    yield piece
                yield from events
                yield repairs[before:]  # the matrix poses repaired here

            def chunks():
                from ..io.parallel import produced_apart
                from ..io.poseschema import current_repairs

                for item in produced_apart(computed):
                    if isinstance(item, tuple):
                        report(*item)
                    elif isinstance(item, int):
                        progress.advance(task, item)
                    elif isinstance(item, list):
                        if current_repairs() is not None:
                            current_repairs().extend(item)
                    else:
                        yield Chunk(item.t, job=JobRuns(item.names, item.counts), **item.fields)

            chunks = chunks()
            try:
                if fmt in ("tum", "kitti"):
                    write_batch_files(out, chunks, fmt, duration=duration, start_time=start_time)
                elif fmt in options.MCAP_FORMATS:
                    write_batch_mcap(
                        out, chunks, duration=duration, start_time=start_time, frame_id=frame_id,
                        profile="ros2" if fmt == "ros2" else "foxglove",
                    )  # fmt: skip
                else:
                    write_batch_csv(out, chunks, fmt)
            finally:  # stops the computing process at once on an error
                chunks.close()
    if verbose and repaired:
        click.echo(f"Repairs a2b made:\n  • {repaired[0]}", err=True)
