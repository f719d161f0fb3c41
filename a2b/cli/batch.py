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


#: The parameters each mode's vectorised path takes (:mod:`a2b.motions.batched`); a job with
#: others goes through :func:`a2b.motion` on its own.
_BATCHED_PARAMETERS = {
    "darboux": frozenset({"delta", "long_way"}),
    "cubic": frozenset({"m", "a", "b", "frame"}),
    "screw": frozenset(),
}


def _group_key(mode, parameters: dict):
    """The vectorised path's group of a job, or ``None`` for a job to build on its own.

    Jobs of one group share a mode and the shape of their parameters: darboux (``delta``,
    ``long_way`` false), cubic by frame and whether ``m`` is given (``m``, ``a``, ``b``), screw.
    """
    allowed = _BATCHED_PARAMETERS.get(mode) if isinstance(mode, str) else None
    if allowed is None or not allowed.issuperset(parameters):
        return None
    if not parameters:
        return _NO_PARAMETERS[mode]
    if mode == "darboux":
        if parameters.get("long_way") not in (None, False):
            return None
        return ("darboux",) if _is_number(parameters.get("delta", 0.0)) else None
    if mode == "cubic":
        frame = parameters.get("frame")
        if frame not in (None, "canonical", "given"):
            return None
        if not all(_is_number(parameters.get(key, 0.0)) for key in ("a", "b")):
            return None
        m = parameters.get("m")
        if m is not None and not (
            isinstance(m, (tuple, list)) and len(m) == 4 and all(map(_is_number, m))
        ):
            return None
        return ("cubic", frame or "canonical", m is None)
    return ("screw",) if all(value is None for value in parameters.values()) else None


_NO_PARAMETERS = {
    "darboux": ("darboux",),
    "cubic": ("cubic", "canonical", True),
    "screw": ("screw",),
}


def _is_number(value) -> bool:
    return type(value) is float or type(value) is int


def _bulk_motions(key, start, end, parameters: list, checked: bool):
    """The :class:`MotionBatch` of one group of jobs."""
    import numpy as np

    from ..motions.batched import motions

    def column(name):
        return np.array([0.0 if p.get(name) is None else p[name] for p in parameters], dtype=float)

    if key[0] == "darboux":
        return motions(start, end, "darboux", delta=column("delta"), checked=checked)
    if key[0] == "cubic":
        _, frame, default_m = key
        m = None if default_m else np.array([p["m"] for p in parameters], dtype=float)
        return motions(
            start, end, "cubic", m=m, a=column("a"), b=column("b"), frame=frame, checked=checked
        )
    return motions(start, end, "screw", checked=checked)


class _Pending:
    """Rows sampled but not yet handed on, and the chunk they make.

    A chunk ends once it holds ``limit`` rows (``CHUNK_SAMPLES``) or ``jobs`` jobs
    (``--chunk-size``), and before a job that would take it past ``balance`` rows: one task of
    the writer's workers (``TASK`` numbers). Chunks of about one task keep the work of the main
    process (reading, building and sampling the next chunk) in small steps between those of
    the writer, so that its helper processes are never left waiting for long.
    """

    def __init__(self, limit: int, balance: int, jobs: int):
        self.limit = limit
        self.balance = balance
        self.max_jobs = jobs
        self.parts: list = []  # (JobRuns, t, fields)
        self.rows = 0
        self.jobs = 0

    def full_before(self, rows: int) -> bool:
        """Whether the chunk should end before ``rows`` more rows."""
        return self.rows > 0 and self.rows + rows > self.balance

    def fits(self, count: int) -> int:
        """How many more jobs of ``count`` rows the chunk takes (at least one)."""
        to_limit = -(-(self.limit - self.rows) // count)
        room = min(to_limit, (self.balance - self.rows) // count, self.max_jobs - self.jobs)
        return max(1, room)

    def add(self, job, t, fields: dict, jobs: int) -> bool:
        """Add the rows of ``jobs`` more jobs (0: more rows of the last one); True when the
        chunk is full and should be flushed."""
        self.parts.append((job, t, fields))
        self.rows += len(t)
        self.jobs += jobs
        return self.rows >= self.limit or self.jobs >= self.max_jobs

    def flush(self):
        import numpy as np

        from ..io.writers import Chunk, JobRuns

        parts, self.parts, self.rows, self.jobs = self.parts, [], 0, 0
        fields = {}
        for key in ("quat_wxyz", "trans", "matrices", "study"):
            values = [f.get(key) for _, _, f in parts]
            if values[0] is None:
                fields[key] = None
            else:
                fields[key] = values[0] if len(values) == 1 else np.concatenate(values)
        t = parts[0][1] if len(parts) == 1 else np.concatenate([p[1] for p in parts])
        job = parts[0][0] if len(parts) == 1 else JobRuns.join(p[0] for p in parts)
        return Chunk(t, job=job, **fields)


#: Columns of each representation's CSV layout (without the job column).
_COLUMNS = {"quat_trans": 8, "matrices": 13, "study": 9}
#: Jobs read at a time between chunks (see :class:`_Reader`).
READ_STEP = 512


class _Reader:
    """The jobs, read :data:`READ_STEP` at a time and handed out in blocks of ``size``.

    Between chunks the caller reads one step ahead (:meth:`ahead`), so that reading the next
    block is spread over the chunks of this one, unless a helper process scans the jobs ahead
    already (then reading ahead here would only wait for input, a pipe's that is still open,
    while the chunks of this block wait to be written). An error while reading is raised once
    the jobs before it have been handed out.
    """

    def __init__(self, jobs, size: int):
        from ..io.readers import Jobs, job_blocks

        step = min(READ_STEP, size)
        self._blocks = jobs.blocks(step) if isinstance(jobs, Jobs) else job_blocks(jobs, step)
        self.size = size
        self.buffer: list = []  # JobBlocks read ahead
        self.count = 0  # their jobs
        self.error = None
        self.done = False
        self.read_ahead = not getattr(jobs, "scanned_ahead", False)

    def ahead(self) -> None:
        """Read one step ahead between chunks, where that is this process's to do."""
        if self.read_ahead:
            self.step()

    def step(self) -> bool:
        """Read one step ahead, unless a block's worth is read; False if nothing was read."""
        if self.done or self.error is not None or self.count >= self.size:
            return False
        try:
            block = next(self._blocks)
        except StopIteration:
            self.done = True
            return False
        except Exception as e:  # noqa: BLE001 - raised in turn, after the jobs before it
            self.error = e
            return False
        self.buffer.append(block)
        self.count += len(block)
        return True

    def take(self):
        """The next block of at most ``size`` jobs, or ``None`` after the last."""
        from ..io.readers import JobBlock

        while self.step():
            pass
        if not self.buffer:
            if self.error is not None:
                error, self.error = self.error, None
                raise error
            return None
        blocks, taken = [], 0
        while self.buffer and taken < self.size:
            block = self.buffer.pop(0)
            if taken + len(block) > self.size:  # the rest goes back
                block, rest = block.split(self.size - taken)
                self.buffer.insert(0, rest)
            blocks.append(block)
            taken += len(block)
        self.count -= taken
        return JobBlock.concatenate(blocks)


def _sample(batch, ts, representation: str) -> tuple[dict, object]:
    """The samples of a :class:`MotionBatch` as rows ``(J·S, ...)`` of the chunk's fields, and
    which jobs' samples are all finite ``(J,)``.

    (A sum of numbers is finite only if every one of them is; it may overflow where they do
    not, which only sends a job to the per-job path, where it turns out fine.)
    """
    import numpy as np

    jobs = len(batch)
    rows = jobs * len(ts)
    if representation == "quat_trans":
        quat, trans = batch.quat_trans(ts)
        # quaternions are computed component by component, (4, J, S): handed on transposed
        columns = np.moveaxis(quat, -1, 0)
        fields = {"quat_wxyz": columns.reshape(4, rows).T, "trans": trans.reshape(rows, 3)}
        return fields, _finite(quat, trans)
    if representation == "matrices":
        values = batch.matrices(ts)
        return {"matrices": values.reshape(rows, 4, 4)}, _finite(values)
    values = batch.study(ts)
    return {"study": values.reshape(rows, 8)}, _finite(values)


def _finite(*arrays):
    """Which jobs have finite values in every array (each with the job axis first)."""
    import numpy as np

    jobs = len(arrays[0])
    ok = np.ones(jobs, dtype=bool)
    if all(np.isfinite(np.add.reduce(a, axis=None)) for a in arrays):
        return ok  # a sum is finite only if every term is (it may overflow where they do not)
    for a in arrays:
        ok &= np.isfinite(a).reshape(jobs, -1).all(axis=1)
    return ok


def batch_chunks(
    jobs, mode: str, samples: int, representation: str, chunk_size: int, advance=None, report=None
):
    """Sample the jobs and yield :class:`Chunk` s of at most ``chunk_size`` jobs.

    A chunk also ends when it holds ``CHUNK_SAMPLES`` rows, so a job of 10⁹ samples streams
    through in bounded memory like any other, and before a job that would take it past one
    task of the writer's workers (see :class:`_Pending`). Jobs are read and built
    ``chunk_size`` at a time. ``advance(n)`` is called after ``n`` jobs are done,
    ``report(name, choices)`` before each job is sampled. An :class:`A2bError` of a job
    (including a sample that overflows) is re-raised naming the job, and so is an
    :class:`A2bWarning`.

    ``jobs`` is a :class:`a2b.io.readers.Jobs` (read block by block) or any iterable of
    :class:`a2b.io.readers.Job`. The jobs of a block that :mod:`a2b.motions.batched` covers
    are built and sampled together; the others, and any job that path leaves to the per-job
    code, go through :func:`a2b.motion` one by one. The chunks, choices, warnings and errors
    are the same either way.
    """
    from ..io import writers

    balance = max(1, writers.TASK // _COLUMNS.get(representation, 8))
    pending = _Pending(writers.CHUNK_SAMPLES, balance, chunk_size)
    reader = _Reader(jobs, chunk_size)
    first = 0  # index of the block's first job
    done = 0  # jobs finished since the last advance
    while True:
        block = reader.take()
        if block is None:
            break
        for chunk in _block_chunks(block, first, mode, samples, representation, pending, report):
            yield chunk
            reader.ahead()
        first += len(block)
        done += len(block)
        if done >= chunk_size:
            if advance is not None:
                advance(done)
            done = 0
    if pending.parts:
        yield pending.flush()
    if done and advance is not None:
        advance(done)


def _block_chunks(block, first, mode, samples, representation, pending, report):
    """The chunks that the jobs of one :class:`JobBlock` complete, in job order."""
    import numpy as np

    n = len(block)
    names = [str(first + i) if name is None else name for i, name in enumerate(block.names)]
    counts = [s or samples for s in block.samples]
    modes = [m or mode for m in block.modes]
    groups: dict = {}
    if not any(block.parameters) and len(set(modes)) == 1 and max(counts) <= pending.limit:
        key = _group_key(modes[0], {})  # the common case: one group of every job
        if key is not None:
            groups[key] = range(n)
    else:
        for i in range(n):
            if counts[i] <= pending.limit:
                key = _group_key(modes[i], block.parameters[i])
                if key is not None:
                    groups.setdefault(key, []).append(i)
    group = np.full(n, -1)  # the batch of each job, or -1: on its own
    position = np.zeros(n, dtype=np.intp)  # its place in the batch
    batches = []
    for key, members in groups.items():
        index = np.asarray(members, dtype=np.intp)
        start, end = (
            (block.start, block.end) if len(index) == n else (block.start[index], block.end[index])
        )
        batch = _bulk_motions(
            key, start, end, [block.parameters[i] for i in members], block.checked
        )
        ok = batch.matrices_ok if representation == "matrices" else batch.ok
        group[index[ok]] = len(batches)
        position[index] = np.arange(len(index))
        batches.append(batch)
    count_of = np.array(counts)
    # runs of consecutive jobs of one batch and one sample count
    breaks = (
        np.flatnonzero(
            (group[1:] != group[:-1]) | (count_of[1:] != count_of[:-1]) | (group[1:] < 0)
        )
        + 1
    )
    for lo, hi in zip([0, *breaks.tolist()], [*breaks.tolist(), n]):
        if group[lo] < 0:
            for i in range(lo, hi):
                yield from _one_job(
                    block.job(i), names[i], mode, counts[i], representation, pending, report
                )
            continue
        yield from _run_chunks(
            batches[group[lo]], int(position[lo]), names[lo:hi], counts[lo],
            lambda i, lo=lo: block.job(lo + i), mode, representation, pending, report,
        )  # fmt: skip


def _run_chunks(batch, position, names, count, job, mode, representation, pending, report):
    """Sample consecutive jobs of one batch, ``batch[position:]``, at ``count`` samples each.

    Pieces end where the chunk is full, so that chunks are cut where the per-job loop cut
    them. A job whose samples are not all finite goes through :func:`_one_job` (``job(i)``
    gives it), which raises the error a single motion raises.
    """
    import numpy as np

    from ..io.writers import JobRuns

    ts = next(options.evenly_spaced(count, count))
    i, n = 0, len(names)
    while i < n:
        if pending.full_before(count):
            yield pending.flush()
        take = min(n - i, pending.fits(count))
        piece = batch.take(slice(position + i, position + i + take))
        fields, finite = _sample(piece, ts, representation)
        good = take if finite.all() else int(np.argmin(finite))
        if good:
            if report is not None:
                for k in range(good):
                    report(names[i + k], piece.choices[k])
            if good < take:
                fields = {key: v[: good * count] for key, v in fields.items()}
            column = JobRuns(names[i : i + good], [count] * good)
            if pending.add(column, np.tile(ts, good), fields, good):
                yield pending.flush()
        i += good
        if good < take:  # its samples overflow: on its own, which says so
            yield from _one_job(job(i), names[i], mode, count, representation, pending, report)
            i += 1


def _one_job(job, name, mode, samples, representation, pending, report):
    """Build, sample and add one job with :func:`a2b.motion`, as a single motion."""
    import a2b
    from a2b.errors import A2bError, A2bWarning

    from ..io.writers import JobRuns

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
        first = 1
        for chunk in options.motion_chunks(motion, samples, representation):
            if pending.full_before(len(chunk.t)):
                yield pending.flush()
            starts = first or not pending.parts  # (the rest of a job begins a chunk: a job too)
            column = JobRuns([name], [len(chunk.t)])
            if pending.add(column, chunk.t, _fields(chunk), int(starts)):
                yield pending.flush()
            first = 0
    except A2bError as e:
        raise type(e)(f"job {name}: {e}") from e


def _fields(chunk) -> dict:
    return {
        key: getattr(chunk, key)
        for key in ("quat_wxyz", "trans", "matrices", "study")
        if getattr(chunk, key) is not None
    }


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
    and parameters, as in a poses file. Jobs are read, built and sampled in chunks, the
    common kinds (darboux with delta, cubic with m, a, b, screw) all at once, with the
    results of building each alone; a progress bar shows on stderr when stderr is a
    terminal. A job that fails stops the run with a message that names it (by line and index
    for an error in the file, by name for one of the mathematics), and with -o no file is
    written.
    -v states every choice a2b makes, job by job.

    \b
    Example:
      a2b batch samples/jobs.yaml -o motions.csv
      a2b batch samples/jobs.jsonl --samples 101 --format matrix -o motions.csv
    """
    from ..io import jobscan

    # JSON Lines are scanned by a helper process from here on, while numpy and the core load
    sniffed = jobscan.sniff(jobs)
    scanned = None
    if sniffed.json_lines:
        scanned = jobscan.scan_ahead(jobs, sniffed, min(READ_STEP, chunk_size))
    try:
        _run(jobs, sniffed, scanned, mode, samples, fmt, chunk_size, output, verbose)
    finally:
        if scanned is not None:
            scanned.close()


def _run(jobs, sniffed, scanned, mode, samples, fmt, chunk_size, output, verbose) -> None:
    """The command's work, once the helper (if any) scans the jobs."""
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

    job_list = read_jobs(jobs, sniffed=sniffed, scanned=scanned)
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
