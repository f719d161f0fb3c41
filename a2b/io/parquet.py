"""Parquet: samples as columns, through pyarrow (the optional extra ``a2b-motions[parquet]``).

=========  ================================================================================
column     type and meaning
=========  ================================================================================
job        ``dictionary<values=string, indices=int32>``: the job's name (batches only)
t          ``double``: the first column of the CSV output (the motion parameter t in [0, 1],
           or the time in seconds where the output has no ``time`` column and is timed)
time       ``double``: seconds, ``t · duration + start_time`` (where the samples carry times)
pose       ``double`` each, named as a2b's CSV headers, from the representation the samples
           hold: ``tx,ty,tz,qw,qx,qy,qz`` (layout ``csv``, what ``--format parquet`` writes),
           ``r11,r12,r13,tx,…,tz`` (``matrix``), ``p0,…,p3,q0,…,q3`` (``study``)
twist      ``double`` each, ``vx,vy,vz,wx,wy,wz`` (when the samples carry velocities)
original   ``bool``: the row is a pose of a resampled trajectory (when the samples say)
=========  ================================================================================

The numbers are the doubles of the CSV output bit for bit (the CSV writes each as its
shortest round-trip text). The file's key-value metadata holds, as JSON: ``a2b.layout``,
``a2b.units`` (column -> unit: ``length`` is the unit of the input translations, ``s``,
``rad/s``, ``length/s``, ``""`` for none) and ``a2b.motion`` (what the caller states about the
motion: its mode, parameters, sample count, duration …; the commands state it through
:func:`a2b.output.motion_statement`); ``a2b.version`` names the writer.

:func:`write_parquet` and :func:`write_batch_parquet` are the writers of the ``parquet`` row of
:mod:`a2b.formats`: they take a binary stream and :class:`a2b.samples.Samples` as every writer
does, and stream: each row group holds at most :data:`ROW_GROUP_ROWS` rows, so memory stays
bounded for any count. :func:`a2b.output.write` gives them a file that appears whole or not at
all. :func:`read_parquet` reads a file back into the samples it was written from. The layouts
are those of the table's CSV formats (:data:`LAYOUTS`), so a CSV layout added there is one here.
"""

from __future__ import annotations

import json
from collections.abc import Iterable, Iterator, Mapping
from typing import IO

import numpy as np

from ..formats import TABLE
from ..samples import FIELDS, JobRuns, Samples

__all__ = [
    "LAYOUTS",
    "REPRESENTATIONS",
    "ROW_GROUP_ROWS",
    "TWIST_COLUMNS",
    "file_metadata",
    "layout_for",
    "layout_of",
    "read_parquet",
    "record_batch",
    "schema",
    "write_batch_parquet",
    "write_parquet",
]

#: The CSV formats of the table: layout name -> its header's pose columns, and the
#: representation of its samples.
_CSV_ROWS = [row for row in TABLE if row.batch == "rows" and (row.header or "").startswith("t,")]
LAYOUTS = {row.name: tuple(row.header.split(",")[1:]) for row in _CSV_ROWS}
REPRESENTATIONS = {row.name: row.representation for row in _CSV_ROWS}
#: The velocity columns, as in the CSV layouts.
TWIST_COLUMNS = ("vx", "vy", "vz", "wx", "wy", "wz")
#: The most rows in one row group: about 10 MB of numbers in the matrix layout.
ROW_GROUP_ROWS = 1 << 17

_UNITS = {
    "t": "",
    "time": "s",
    **dict.fromkeys(("tx", "ty", "tz"), "length"),
    **dict.fromkeys(("q0", "q1", "q2", "q3"), "length"),  # the dual part of a Study vector
    **dict.fromkeys(("vx", "vy", "vz"), "length/s"),
    **dict.fromkeys(("wx", "wy", "wz"), "rad/s"),
}


def _pyarrow():
    """pyarrow, or a one-line error that names the extra."""
    try:
        import pyarrow as pa
        import pyarrow.parquet  # noqa: F401
    except ImportError as e:
        from ..errors import MissingDependencyError

        raise MissingDependencyError(
            "Parquet needs pyarrow, which is not installed: pip install 'a2b-motions[parquet]'"
        ) from e
    return pa


def schema(
    layout: str = "csv",
    *,
    job: bool = True,
    time: bool = False,
    twist: bool = False,
    original: bool = False,
    motion: Mapping | None = None,
):
    """The Arrow schema of samples in ``layout`` (a key of :data:`LAYOUTS`), with the columns
    and the key-value metadata of the module's table; ``motion`` goes into ``a2b.motion``."""
    pa = _pyarrow()
    from .. import __version__

    if layout not in LAYOUTS:
        raise ValueError(f"unknown layout {layout!r}; expected one of {', '.join(LAYOUTS)}")
    names = ["job"] * job + ["t"] + ["time"] * time + list(LAYOUTS[layout])
    names += list(TWIST_COLUMNS) * twist
    fields = [
        pa.field(n, pa.dictionary(pa.int32(), pa.string()) if n == "job" else pa.float64())
        for n in names
    ]
    if original:
        fields.append(pa.field("original", pa.bool_()))
    metadata = {
        "a2b.version": json.dumps(__version__),
        "a2b.layout": json.dumps(layout),
        "a2b.units": json.dumps({n: _UNITS.get(n, "") for n in names if n != "job"}),
        "a2b.motion": json.dumps(dict(motion or {}), default=_plain),
    }
    return pa.schema(fields, metadata=metadata)


def _plain(value):
    """JSON for numpy values in the motion's parameters."""
    if isinstance(value, np.ndarray | np.generic):
        return value.tolist()
    raise TypeError(f"cannot write {type(value).__name__} into the metadata")


def file_metadata(schema) -> dict:
    """The a2b metadata of an Arrow schema (of a file): ``layout``, ``units``, ``motion``,
    ``version``, decoded from JSON; ``{}`` for a file that a2b did not write."""
    raw = schema.metadata or {}
    return {
        key.decode()[4:]: json.loads(value) for key, value in raw.items() if key.startswith(b"a2b.")
    }


def layout_of(samples: Samples) -> str:
    """The layout of the representation ``samples`` hold (its pose fields that are filled)."""
    for layout, representation in REPRESENTATIONS.items():
        if all(getattr(samples, name) is not None for name in FIELDS[representation]):
            return layout
    raise ValueError("samples without poses")


def layout_for(representation: str) -> str:
    """The layout (a key of :data:`LAYOUTS`) whose pose columns hold ``representation``."""
    return next(name for name, held in REPRESENTATIONS.items() if held == representation)


def _pose_columns(layout: str, samples: Samples) -> list[np.ndarray]:
    """The pose of ``samples`` as the columns of ``layout``, in the order of its header."""
    representation = REPRESENTATIONS[layout]
    if representation == "quat_trans":
        return [*samples.trans.T, *samples.quat_wxyz.T]
    if representation == "matrices":
        return list(samples.matrices[:, :3, :].reshape(len(samples.t), 12).T)
    return list(samples.study.T)


def _job_column(job, rows: int):
    """A job column (names, or :class:`JobRuns`) as a dictionary array of ``rows`` rows."""
    pa = _pyarrow()
    runs = JobRuns.of(job)
    if sum(runs.counts) != rows:
        raise ValueError(f"a job column of {sum(runs.counts)} rows for {rows} samples")
    encoded = pa.array(runs.names, pa.string()).dictionary_encode()
    indices = np.repeat(encoded.indices.to_numpy(), runs.counts).astype(np.int32)
    return pa.DictionaryArray.from_arrays(pa.array(indices), encoded.dictionary)


def record_batch(samples: Samples):
    """One block of :class:`a2b.samples.Samples` as an Arrow record batch of :func:`schema`'s
    columns: ``time`` (:meth:`~a2b.samples.Samples.seconds`) where the block has times, the
    pose in the layout of its representation (:func:`layout_of`)."""
    pa = _pyarrow()
    layout = layout_of(samples)
    time = None if samples.time is None else samples.seconds()
    job, twist, original = samples.job, samples.twist, samples.original
    columns = [samples.t] + [time] * (time is not None) + _pose_columns(layout, samples)
    columns += list(twist.T) if twist is not None else []
    arrays = [pa.array(np.ascontiguousarray(c, dtype=float)) for c in columns]
    if job is not None:
        arrays.insert(0, _job_column(job, len(samples.t)))
    if original is not None:
        arrays.append(pa.array(np.asarray(original, dtype=bool)))
    kinds = {"job": job, "time": time, "twist": twist, "original": original}
    shape = schema(layout, **{k: v is not None for k, v in kinds.items()})
    return pa.RecordBatch.from_arrays(arrays, schema=shape.remove_metadata())


def write_parquet(
    stream: IO[bytes],
    samples: Iterable[Samples],
    *,
    motion: Mapping | None = None,
    row_group_rows: int = ROW_GROUP_ROWS,
) -> int:
    """Write samples into ``stream`` as one Parquet file; return the number of rows.

    Parameters
    ----------
    stream : binary stream
        Written from start to end (no seek), not closed.
    samples : iterable of Samples
        The first decides the columns (the layout of its representation, ``job``, ``time``,
        ``twist``, ``original``), and every later one must carry the same. No samples: an
        empty file of the ``csv`` layout.
    motion : mapping, optional
        What to state about the motion in the metadata ``a2b.motion``: mode, parameters,
        samples, duration, … (numbers, strings, lists, numpy arrays).
    row_group_rows : int
        The most rows in one row group (and in memory at once, besides one block).

    Raises
    ------
    MissingDependencyError
        Without pyarrow.
    """
    pa = _pyarrow()
    import pyarrow.parquet as pq

    blocks = _coalesced(samples, min(row_group_rows, BATCH_ROWS))
    first = next(blocks, None)
    if first is None:
        pq.write_table(schema(job=False, motion=motion).empty_table(), stream)
        return 0
    batch = record_batch(first)
    names = batch.schema.names
    flags = {k: k in names for k in ("job", "time", "original")} | {"twist": "vx" in names}
    shape = schema(layout_of(first), **flags, motion=motion)
    pending: list = []  # batches of fewer than row_group_rows rows in all
    held = rows = 0
    with pq.ParquetWriter(stream, shape) as writer:
        while batch is not None:
            if batch.schema.names != names:
                raise ValueError(f"a block with columns {batch.schema.names}, expected {names}")
            pending.append(batch)
            held += batch.num_rows
            if held >= row_group_rows:  # whole row groups out, the rest kept for the next
                table = pa.Table.from_batches(pending, shape)
                whole = held - held % row_group_rows
                writer.write_table(table.slice(0, whole), row_group_size=row_group_rows)
                pending, held, rows = table.slice(whole).to_batches(), held - whole, rows + whole
            block = next(blocks, None)
            batch = None if block is None else record_batch(block)
        if held:
            writer.write_table(pa.Table.from_batches(pending, shape), row_group_size=held)
            rows += held
    return rows


#: Rows of samples joined into one record batch: a batch's jobs come in pieces of a few
#: hundred rows, and an Arrow batch costs about 0.4 ms whatever its size.
BATCH_ROWS = 1 << 16

_COLUMNS = ("t", "time", "quat_wxyz", "trans", "matrices", "study", "twist", "original")


def _coalesced(samples: Iterable[Samples], rows: int) -> Iterator[Samples]:
    """``samples`` joined into blocks of at least ``rows`` rows (the last may have fewer);
    blocks that carry different columns are not joined."""
    held: list[Samples] = []
    count = 0
    for block in samples:
        if held and _kinds(block) != _kinds(held[0]):
            yield _joined(held)
            held, count = [], 0
        held.append(block)
        count += len(block.t)
        if count >= rows:
            yield _joined(held)
            held, count = [], 0
    if held:
        yield _joined(held)


def _kinds(block: Samples) -> tuple:
    return (block.job is None, block.origin_ns, block.stamps_ns is None) + tuple(
        getattr(block, name) is None for name in _COLUMNS
    )


def _joined(blocks: list[Samples]) -> Samples:
    """Consecutive blocks of samples with the same columns as one."""
    if len(blocks) == 1:
        return blocks[0]
    first = blocks[0]
    fields = {
        name: np.concatenate([getattr(b, name) for b in blocks])
        for name in (*_COLUMNS, "stamps_ns")
        if getattr(first, name) is not None
    }
    job = None if first.job is None else JobRuns.join(JobRuns.of(b.job) for b in blocks)
    return Samples(**fields, job=job, origin_ns=first.origin_ns)


def write_batch_parquet(
    stream: IO[bytes], samples: Iterable[Samples], fmt: str = "", motion: Mapping | None = None
) -> int:
    """Many motions into one Parquet file, the ``job`` column first (``a2b batch``): as
    :func:`write_parquet`; every block names the job of each row. ``fmt``: the table's name
    of the format, which a batch writer is given (one layout here: that of the samples).
    ``motion``: what holds for the whole batch (``a2b batch``: the mode and the sample count
    of jobs that name none); each job's own mode and parameters are in the jobs file, not
    in the metadata."""

    def named():
        for block in samples:
            if block.job is None:
                raise ValueError("a batch block without a job column")
            yield block

    return write_parquet(stream, named(), motion=motion)


def read_parquet(source) -> tuple[Samples, np.ndarray | None, dict]:
    """Read a Parquet file of samples (a path or a binary stream) back.

    Returns
    -------
    samples : Samples
        ``t``, the pose in the file's layout (``quat_wxyz`` and ``trans``, ``matrices`` or
        ``study``), ``job`` as :class:`JobRuns` (if the file has the column), ``twist`` and
        ``original`` (if it has them).
    time : ndarray or None
        The ``time`` column in seconds, if the file has one.
    metadata : dict
        :func:`file_metadata` of the file.
    """
    _pyarrow()
    import pyarrow.parquet as pq

    from ..errors import InputFileError

    table = pq.read_table(source)
    metadata = file_metadata(table.schema)
    layout = metadata.get("layout")
    if layout not in LAYOUTS:
        raise InputFileError(f"{_name(source)}: not a Parquet file of a2b samples (no layout)")
    columns = {name: _numbers(table, name) for name in table.schema.names if name != "job"}
    pose = np.column_stack([columns[name] for name in LAYOUTS[layout]])
    samples = Samples(columns["t"])
    representation = REPRESENTATIONS[layout]
    if representation == "quat_trans":
        samples.trans, samples.quat_wxyz = pose[:, :3].copy(), pose[:, 3:].copy()
    elif representation == "matrices":
        samples.matrices = np.zeros((len(pose), 4, 4))
        samples.matrices[:, :3, :] = pose.reshape(-1, 3, 4)
        samples.matrices[:, 3, 3] = 1.0
    else:
        samples.study = pose
    if "job" in table.schema.names:
        samples.job = _runs(table)
    if "vx" in columns:
        samples.twist = np.column_stack([columns[name] for name in TWIST_COLUMNS])
    if "original" in columns:
        samples.original = columns["original"].astype(bool)
    return samples, columns.get("time"), metadata


def _name(source) -> str:
    return str(getattr(source, "name", source))


def _numbers(table, name: str) -> np.ndarray:
    return table.column(name).to_numpy()


def _runs(table) -> JobRuns:
    """The ``job`` column of a table as runs of equal names."""
    pa = _pyarrow()
    column = table.unify_dictionaries().column("job").combine_chunks()
    if not pa.types.is_dictionary(column.type):
        column = column.dictionary_encode()
    if column.null_count:
        raise ValueError("the job column has null names")
    codes = column.indices.to_numpy(zero_copy_only=False)
    if not len(codes):
        return JobRuns([], [])
    starts = np.flatnonzero(np.r_[True, codes[1:] != codes[:-1]])
    names = column.dictionary.to_pylist()
    return JobRuns([names[c] for c in codes[starts]], np.diff(np.r_[starts, len(codes)]).tolist())
